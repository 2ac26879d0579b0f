//! Vanishing-point detection measured on labelled photos (`vpmap eval-detect DIR`).
//!
//! The folder holds York Urban-style pairs `<name>.jpg` (or `.jpeg`, `.png`) + `<name>.json` with
//! `K` (3x3 intrinsics), `vp_dirs_camera_yup` (the three labelled vanishing directions in a
//! camera frame with y up: pixel = K diag(1, -1, 1) dir) and `most_vertical_vp_index`. Every
//! photo is detected twice, one at a time (one thread), timing [`vpmap_vision::detect`] only:
//! with the true intrinsics given, and with them estimated.
//!
//! The error of a vanishing point is the angle between the detected and the labelled
//! direction's lines (sign-free, 0 to 90 degrees). The detected direction is the detected point
//! through the intrinsics the detector used (given or estimated), or its `direction_camera`
//! when the point is at infinity. The vertical is matched to the labelled vertical, the two
//! horizontals to the labelled ones by the assignment with the smaller total error. A photo the
//! detector refuses, or a vanishing point it does not return, counts as a miss (error
//! infinite) in every figure.
//!
//! Each direction's own vanishing point ([`vpmap_vision::VanishingPoint::own_point`], the
//! least-squares point of its segments, not held orthogonal) is scored the same way, with the
//! same intrinsics; a direction without one is a miss. When the label file holds the
//! dataset's orthogonalised directions (`vp_orthogonal_dirs_camera_yup`), both are scored
//! against those too, and the orthogonalised directions themselves against the labels (the
//! best any exactly orthogonal frame can do against them).
//!
//! The horizon error ([`horizon`]) is that of the scene file `vpmap detect` would write for the
//! detection ([`vpmap_vision::scene::detected_scene`]): the line through its two horizontal
//! vanishing points, against the labelled camera's horizon `K^-T v` (`v` the labelled
//! vertical). A photo refused, or whose detection gives no scene, counts as a miss.

use std::path::{Path, PathBuf};

pub mod coverage;
pub mod geom;
pub mod horizon;
pub mod report;
pub mod results;

use std::time::Instant;

use image::DynamicImage;
use serde::Deserialize;
use vpmap_vision::photo::{Photo, PhotoLimits, decode_photo};
use vpmap_vision::scene::detected_scene;
use vpmap_vision::{DetectOptions, Detection, detect};

use crate::error::{Result, ResultExt as _, bail};
use crate::output::OutputSet;
use crate::progress::Progress;
use geom::{Vec3, direction_of_pixel, line_angle_deg, normalize};
use horizon::{Line, horizon_error, horizon_of_vertical, line_through};
pub use results::{ImageResult, Intrinsics, Run, RunOk};

/// How to run the detector on the photos.
#[derive(Clone, Debug, Default)]
pub struct DetectionOptions {
    /// The detector's options; its focal length and principal point are set per run (the
    /// label's, or `None` to estimate them).
    pub detect: DetectOptions,
    /// The photos accepted.
    pub photo_limits: PhotoLimits,
    /// Whether the run with the intrinsics estimated takes each photo's EXIF focal length as
    /// a prior, as `vpmap detect` does ([`vpmap_vision::photo::Photo::exif_focal_prior`]).
    pub exif: bool,
}

/// A labelled photo.
pub struct Pair {
    /// The file stem.
    pub name: String,
    /// The photo.
    pub image: PathBuf,
    /// Its labels.
    pub label: PathBuf,
}

/// What a label file says, in the camera frame of `vpmap_vision` (x right, y down).
#[derive(Clone, Debug, PartialEq)]
pub struct Label {
    /// Focal length, pixels.
    pub focal_px: f64,
    /// Principal point, pixels.
    pub principal_point_px: [f64; 2],
    /// The three labelled vanishing directions, unit, y down.
    pub directions: [Vec3; 3],
    /// Which of them is vertical.
    pub vertical: usize,
    /// The dataset's orthogonalised directions (`vp_orthogonal_dirs_camera_yup`, the labels
    /// made exactly orthogonal), unit, y down, in the same order; `None` when the file has
    /// none.
    pub orthogonal_directions: Option<[Vec3; 3]>,
}

impl Label {
    /// The true horizon, `K^-T v` for the labelled vertical `v` (see [`horizon`]).
    #[must_use]
    pub fn horizon(&self) -> Line {
        let v = self
            .directions
            .get(self.vertical)
            .copied()
            .unwrap_or_default();
        horizon_of_vertical(v, self.focal_px, self.principal_point_px)
    }

    /// The horizon through the two labelled horizontal vanishing points, `K^-T (a x b)` for
    /// the labelled horizontal directions `a`, `b`. The labels are not exactly orthogonal
    /// (`docs/detection.md`), so it differs from [`Label::horizon`].
    #[must_use]
    pub fn horizon_of_horizontals(&self) -> Line {
        let mut horizontals = (0..3)
            .filter(|&i| i != self.vertical)
            .filter_map(|i| self.directions.get(i).copied());
        let (a, b) = (horizontals.next(), horizontals.next());
        let normal = a.zip(b).map(|(a, b)| geom::cross(a, b)).unwrap_or_default();
        horizon_of_vertical(normal, self.focal_px, self.principal_point_px)
    }

    /// The same label with the orthogonalised directions in place of the labelled ones
    /// (`None` when the file has none).
    #[must_use]
    pub fn orthogonalised(&self) -> Option<Self> {
        self.orthogonal_directions.map(|directions| Self {
            directions,
            orthogonal_directions: None,
            ..self.clone()
        })
    }

    /// Each orthogonalised direction's angle from its labelled one, degrees (label order;
    /// `None` when the file has none): the error of the best exactly orthogonal frame the
    /// dataset gives, against its own labels.
    #[must_use]
    pub fn orthogonal_errors_deg(&self) -> Option<[f64; 3]> {
        let ortho = self.orthogonal_directions?;
        Some([0, 1, 2].map(|i| line_angle_deg(ortho[i], self.directions[i])))
    }
}

#[derive(Deserialize)]
struct LabelFile {
    #[serde(rename = "K")]
    k: [[f64; 3]; 3],
    vp_dirs_camera_yup: Vec<[f64; 3]>,
    #[serde(default)]
    vp_orthogonal_dirs_camera_yup: Option<Vec<[f64; 3]>>,
    most_vertical_vp_index: usize,
}

/// Parse and check a York Urban label file.
///
/// # Errors
/// Malformed JSON, missing fields, a `K` with skew or non-square pixels, degenerate
/// directions, a vertical index out of range.
pub fn parse_label(text: &str) -> Result<Label> {
    let file: LabelFile = serde_json::from_str(text).context("not a York Urban label file")?;
    let k = file.k;
    if !k.iter().flatten().all(|v| v.is_finite()) {
        bail!("`K` holds a non-finite number");
    }
    let (fx, fy) = (k[0][0], k[1][1]);
    if !(fx > 0.0 && fy > 0.0) || (fx - fy).abs() > 1e-3 * fx {
        bail!("`K` has focal lengths {fx} and {fy}; square pixels are needed");
    }
    let unit_row = k[2]
        .iter()
        .zip([0.0, 0.0, 1.0])
        .all(|(a, b)| (a - b).abs() <= 1e-9);
    if k[0][1].abs() > 1e-6 * fx || k[1][0].abs() > 1e-9 || !unit_row {
        bail!("`K` must be [[f, 0, cx], [0, f, cy], [0, 0, 1]], got {k:?}");
    }
    if file.vp_dirs_camera_yup.len() != 3 {
        bail!(
            "`vp_dirs_camera_yup` holds {} directions; expected 3",
            file.vp_dirs_camera_yup.len()
        );
    }
    if file.most_vertical_vp_index > 2 {
        bail!(
            "`most_vertical_vp_index` is {}; expected 0, 1 or 2",
            file.most_vertical_vp_index
        );
    }
    let directions = y_down_directions(&file.vp_dirs_camera_yup, "vp_dirs_camera_yup")?;
    let orthogonal_directions = file
        .vp_orthogonal_dirs_camera_yup
        .as_deref()
        .map(|dirs| {
            if dirs.len() != 3 {
                bail!(
                    "`vp_orthogonal_dirs_camera_yup` holds {} directions; expected 3",
                    dirs.len()
                );
            }
            y_down_directions(dirs, "vp_orthogonal_dirs_camera_yup")
        })
        .transpose()?;
    Ok(Label {
        focal_px: 0.5 * (fx + fy),
        principal_point_px: [k[0][2], k[1][2]],
        directions,
        vertical: file.most_vertical_vp_index,
        orthogonal_directions,
    })
}

/// Three directions of a label file (y up) as unit directions with y down.
fn y_down_directions(dirs: &[[f64; 3]], field: &str) -> Result<[Vec3; 3]> {
    let mut directions = [[0.0; 3]; 3];
    for (i, d) in dirs.iter().enumerate() {
        // y up to y down.
        let Some(direction) = normalize([d[0], -d[1], d[2]]) else {
            bail!("`{field}[{i}]` is degenerate: {d:?}");
        };
        if let Some(slot) = directions.get_mut(i) {
            *slot = direction;
        }
    }
    Ok(directions)
}

/// The labelled photos in `dir`, in name order.
///
/// # Errors
/// When `dir` cannot be listed or holds no pairs.
pub fn find_pairs(dir: &Path) -> Result<Vec<Pair>> {
    if !dir.exists() {
        bail!("folder {} does not exist", dir.display());
    }
    if !dir.is_dir() {
        bail!("{} is not a folder", dir.display());
    }
    let entries =
        std::fs::read_dir(dir).with_context(|| format!("cannot list {}", dir.display()))?;
    let mut pairs = Vec::new();
    for entry in entries {
        let path = entry
            .with_context(|| format!("cannot list {}", dir.display()))?
            .path();
        let is_photo = path.extension().is_some_and(|e| {
            ["jpg", "jpeg", "png"]
                .iter()
                .any(|x| e.eq_ignore_ascii_case(x))
        });
        let label = path.with_extension("json");
        if is_photo && path.is_file() && label.is_file() {
            let name = path
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default();
            pairs.push(Pair {
                name,
                image: path,
                label,
            });
        }
    }
    pairs.sort_by(|a, b| a.name.cmp(&b.name).then_with(|| a.image.cmp(&b.image)));
    if pairs.is_empty() {
        bail!(
            "no labelled photos in {}: expected <name>.jpg (or .png) with <name>.json beside it",
            dir.display()
        );
    }
    Ok(pairs)
}

/// Which of a detection's points is scored: the frame's, or each direction's own.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Points {
    /// The orthogonal frame's points ([`vpmap_vision::VanishingPoint::point_px`]), what
    /// `vpmap detect` writes.
    Frame,
    /// Each direction's own least-squares point ([`vpmap_vision::VanishingPoint::own_point`]).
    Own,
}

/// The detected direction of one vanishing point through the intrinsics the detector used:
/// its point through them, or its direction when the point is at infinity (`None` for a
/// missing point, or a missing own point).
fn detected_direction(det: &Detection, index: usize, points: Points) -> Option<Vec3> {
    let vp = det.vanishing_points.get(index)?;
    let (point_px, direction) = match points {
        Points::Frame => (vp.point_px, vp.direction_camera),
        Points::Own => {
            let own = vp.own_point?;
            (own.point_px, own.direction_camera)
        }
    };
    let intr = det.intrinsics;
    point_px
        .and_then(|p| direction_of_pixel(p, intr.focal_px, intr.principal_point_px))
        .or_else(|| normalize(direction))
}

/// Errors of the detected vanishing points (the frame's) against the labelled ones, in label
/// order: vertical to vertical, horizontals by the assignment with the smaller total error.
#[must_use]
pub fn match_errors(det: &Detection, label: &Label) -> [Option<f64>; 3] {
    match_points(det, label, Points::Frame)
}

/// Errors of the detection's `points` against the labelled directions, matched as
/// [`match_errors`] does.
#[must_use]
pub fn match_points(det: &Detection, label: &Label, points: Points) -> [Option<f64>; 3] {
    let mut errors = [None; 3];
    let vertical = (0..det.vanishing_points.len())
        .find(|&i| det.vanishing_points[i].vertical)
        .and_then(|i| detected_direction(det, i, points));
    if let Some(d) = vertical {
        errors[label.vertical] = Some(line_angle_deg(d, label.directions[label.vertical]));
    }
    let horizontals: Vec<Vec3> = (0..det.vanishing_points.len())
        .filter(|&i| !det.vanishing_points[i].vertical)
        .filter_map(|i| detected_direction(det, i, points))
        .take(2)
        .collect();
    let labelled: Vec<usize> = (0..3).filter(|&i| i != label.vertical).collect();
    let err = |d: Vec3, l: usize| line_angle_deg(d, label.directions[l]);
    match horizontals.as_slice() {
        [a, b] => {
            let straight = [err(*a, labelled[0]), err(*b, labelled[1])];
            let crossed = [err(*a, labelled[1]), err(*b, labelled[0])];
            let [e0, e1] = if straight[0] + straight[1] <= crossed[0] + crossed[1] {
                straight
            } else {
                [crossed[1], crossed[0]]
            };
            errors[labelled[0]] = Some(e0);
            errors[labelled[1]] = Some(e1);
        }
        [a] => {
            let (e0, e1) = (err(*a, labelled[0]), err(*a, labelled[1]));
            if e0 <= e1 {
                errors[labelled[0]] = Some(e0);
            } else {
                errors[labelled[1]] = Some(e1);
            }
        }
        _ => {}
    }
    errors
}

/// The horizon errors of the scene `vpmap detect` writes for `det`, image heights (`None` when
/// it writes none): the line through the scene's two horizontal vanishing points, as
/// `vpmap build` reads them, against [`Label::horizon`] and [`Label::horizon_of_horizontals`].
#[must_use]
pub fn scene_horizon_error(det: &Detection, label: &Label) -> Option<[f64; 2]> {
    let scene = detected_scene(det).ok()?;
    let vps = &scene.calibration.vanishing_points_px;
    let (a, b) = (vps.first()?, vps.get(1)?);
    let written = line_through([a.x, a.y], [b.x, b.y]);
    Some(
        [label.horizon(), label.horizon_of_horizontals()]
            .map(|truth| horizon_error(written, truth, det.image_size_px)),
    )
}

/// Read a JPEG or PNG photo as `vpmap detect` does: one line naming the file and the problem.
fn read_photo(path: &Path, limits: &PhotoLimits) -> std::result::Result<Photo, String> {
    let bytes =
        std::fs::read(path).map_err(|e| format!("cannot read photo {}: {e}", path.display()))?;
    decode_photo(&bytes, limits).map_err(|e| format!("{}: {e}", path.display()))
}

/// Detect one photo with given or estimated intrinsics.
fn run_one(
    image: &DynamicImage,
    label: &Label,
    which: Intrinsics,
    opts: &DetectOptions,
    focal_prior: Option<(f64, f64)>,
) -> Run {
    let opts = DetectOptions {
        focal_px: (which == Intrinsics::Given).then_some(label.focal_px),
        focal_prior: focal_prior.filter(|_| which == Intrinsics::Estimated),
        principal_point_px: (which == Intrinsics::Given).then_some(label.principal_point_px),
        ..*opts
    };
    let started = Instant::now();
    let result = detect(image, &opts);
    let elapsed = started.elapsed();
    let outcome = result.map(|det| {
        let scene = detected_scene(&det).ok();
        let orthogonal = label.orthogonalised();
        RunOk {
            errors_deg: match_errors(&det, label),
            own_errors_deg: match_points(&det, label, Points::Own),
            against_orthogonal_deg: orthogonal
                .map(|o| [Points::Frame, Points::Own].map(|points| match_points(&det, &o, points))),
            ellipse_d2: scene
                .as_ref()
                .map_or([None; 3], |s| coverage::direction_distances(s, label)),
            focal_z: scene
                .as_ref()
                .filter(|_| which == Intrinsics::Estimated)
                .and_then(|s| coverage::focal_z(s, label)),
            camera_z: scene.as_ref().and_then(|s| coverage::camera_z(s, label)),
            focal_px: det.intrinsics.focal_px,
            focal_error: (which == Intrinsics::Estimated)
                .then(|| (det.intrinsics.focal_px - label.focal_px).abs() / label.focal_px),
            principal_point_px: det.intrinsics.principal_point_px,
            perspective: det.perspective.name(),
            segments: det.segments.len(),
            horizon_error: scene_horizon_error(&det, label),
            lens: det.lens.map(|l| [l.estimated_k, l.k_sd]),
            lens_segments_sd: det.lens.and_then(|l| l.segments_k_sd),
        }
    });
    Run {
        time_ms: Some(elapsed.as_secs_f64() * 1e3),
        outcome: outcome.map_err(|e| e.to_string()),
    }
}

/// Evaluate every pair, one photo at a time.
///
/// # Errors
/// A label file that cannot be read or parsed (checked for every pair before any detection).
pub fn evaluate(
    pairs: &[Pair],
    opts: &DetectionOptions,
    progress: &dyn Progress,
) -> Result<Vec<ImageResult>> {
    let labels: Vec<Label> = pairs
        .iter()
        .map(|p| {
            let text = std::fs::read_to_string(&p.label)
                .with_context(|| format!("cannot read {}", p.label.display()))?;
            parse_label(&text).with_context(|| format!("{}", p.label.display()))
        })
        .collect::<Result<_>>()?;
    progress.start(pairs.len() as u64);
    let mut results = Vec::with_capacity(pairs.len());
    for (pair, label) in pairs.iter().zip(&labels) {
        progress.message(&pair.name);
        let result = match read_photo(&pair.image, &opts.photo_limits) {
            Ok(photo) => {
                let prior = if opts.exif {
                    photo.exif_focal_prior().ok().flatten()
                } else {
                    None
                };
                let image = &photo.image;
                ImageResult {
                    name: pair.name.clone(),
                    size_px: Some([image.width(), image.height()]),
                    vertical: label.vertical,
                    orthogonal_label_errors_deg: label.orthogonal_errors_deg(),
                    runs: Intrinsics::BOTH
                        .map(|which| run_one(image, label, which, &opts.detect, prior)),
                }
            }
            Err(e) => {
                let failed = Run {
                    time_ms: None,
                    outcome: Err(e),
                };
                ImageResult {
                    name: pair.name.clone(),
                    size_px: None,
                    vertical: label.vertical,
                    orthogonal_label_errors_deg: label.orthogonal_errors_deg(),
                    runs: [failed.clone(), failed],
                }
            }
        };
        results.push(result);
        progress.step();
    }
    progress.finish();
    Ok(results)
}

/// An evaluation's report: the summaries of both kinds of run and the files.
pub struct Report {
    /// What the run was over.
    pub context: report::Context,
    /// The summaries, in [`Intrinsics::BOTH`] order.
    pub summaries: [report::Summary; 2],
    /// `eval-detect.json` and `summary.md`.
    pub files: OutputSet,
}

/// Summarise an evaluation and make its files.
///
/// # Errors
/// When the JSON report cannot be serialised.
pub fn report(context: report::Context, results: &[ImageResult]) -> Result<Report> {
    let summaries = Intrinsics::BOTH.map(|which| report::summarise(results, which));
    let mut files = OutputSet::default();
    files.add(
        "eval-detect.json",
        report::json(&context, results, &summaries)?,
    );
    files.add(
        "summary.md",
        report::markdown(&context, results, &summaries),
    );
    Ok(Report {
        context,
        summaries,
        files,
    })
}

impl Report {
    /// The console table.
    #[must_use]
    pub fn table(&self) -> String {
        report::table(&self.context, &self.summaries)
    }

    /// The section to publish into a results file: where, when and how (`command`, the
    /// command line) it was measured, then the summary.
    #[must_use]
    pub fn published(&self, results: &[ImageResult], command: &str) -> String {
        let body = report::markdown(&self.context, results, &self.summaries);
        let body = body
            .split_once('\n')
            .map_or(body.as_str(), |(_, rest)| rest)
            .trim_start();
        format!(
            "## Vanishing-point detection on real photos (`vpmap eval-detect`)\n\n\
             Measured on {}, {}, with\n\n{}\n{body}",
            crate::publish::machine_description(),
            crate::publish::utc_now(),
            crate::publish::command_block(command)
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const LABEL: &str = r#"{"K": [[674.9, 0.0, 307.5], [0.0, 674.9, 251.4], [0.0, 0.0, 1.0]],
        "vp_dirs_camera_yup": [[-0.83, -0.10, 0.54], [0.02, 0.97, 0.22], [0.54, -0.20, 0.82]],
        "most_vertical_vp_index": 1, "extra": 1}"#;

    #[test]
    fn label_directions_turn_to_y_down() {
        let l = parse_label(LABEL).unwrap_or_else(|e| panic!("{e:#}"));
        assert_eq!(l.vertical, 1);
        assert!(l.directions[1][1] < -0.9, "{:?}", l.directions[1]);
        assert!((l.focal_px - 674.9).abs() < 1e-12);
        assert!(parse_label(&LABEL.replace("674.9, 0.0, 307.5", "600.0, 0.0, 307.5")).is_err());
        assert!(
            parse_label(&LABEL.replace(
                "\"most_vertical_vp_index\": 1",
                "\"most_vertical_vp_index\": 3"
            ))
            .is_err()
        );
        assert_eq!(l.orthogonal_directions, None);
        assert_eq!(l.orthogonal_errors_deg(), None);
    }

    #[test]
    fn orthogonalised_labels_are_read_and_scored_by_index() {
        // The first orthogonalised direction flipped (sign-free) and turned; the other two
        // as labelled; then only two of them, which is refused.
        let one = 1f64.to_radians();
        let text = LABEL.replace(
            "\"most_vertical_vp_index\"",
            &format!(
                "\"vp_orthogonal_dirs_camera_yup\": [[{}, 0.0, {}], [0.02, 0.97, 0.22], [0.54, -0.2, 0.82]], \"most_vertical_vp_index\"",
                -one.cos(),
                -one.sin()
            ),
        );
        let l = parse_label(&text).unwrap_or_else(|e| panic!("{e:#}"));
        let errors = l.orthogonal_errors_deg().unwrap_or_default();
        let expected = line_angle_deg([one.cos(), 0.0, one.sin()], l.directions[0]);
        assert!(
            (errors[0] - expected).abs() < 1e-9,
            "{errors:?} vs {expected}"
        );
        assert!(errors[0] > 1.0, "{errors:?}");
        assert!(errors[1] < 1e-9 && errors[2] < 1e-9, "{errors:?}");
        let o = l
            .orthogonalised()
            .unwrap_or_else(|| panic!("no orthogonalised label"));
        assert_eq!(o.vertical, l.vertical);
        assert!(line_angle_deg(o.directions[1], l.directions[1]) < 1e-9);
        // The y axis is turned down as the labels' are.
        assert!(o.directions[1][1] < -0.9);
        let two = text.replace(", [0.54, -0.2, 0.82]]", "]");
        assert!(parse_label(&two).is_err(), "two orthogonalised directions");
    }
}

//! Snapping on real photos: the labelled corners of York Urban (`vpmap eval-clicks --yud DIR`).
//!
//! The folder holds York Urban pairs `<name>.jpg` + `<name>.json` (`segments_xyxy`,
//! `segment_vp_index0`, `vp_px`; [`crate::detection`] reads the same files).
//!
//! * **Corners.** Where two labelled segments of different vanishing points meet: an end of one
//!   within [`YudConfig::max_gap_px`] (3 px) of an end of the other, both at least
//!   [`YudConfig::min_length_px`] (15 px) long; the corner is where their lines cross. Every
//!   such pair is one corner (three segments meeting at a Y give three).
//! * **Clicks.** Each corner is clicked once, `sigma` px off (Gaussian per coordinate, seeded by
//!   the photo's name and the corner), and snapped with
//!   [`vpmap_vision::snap::SnapOptions::for_click_sigma`] and the photo's detected vanishing
//!   points ([`vpmap_vision::detect`], as `vpmap detect` finds them; the labelled ones when
//!   detection finds fewer than two). A second click exactly on the labelled corner shows how
//!   far snapping moves a perfect click.
//! * **The labels' own error.** A labelled line is not exactly on the photo's edge. At each
//!   corner, along each of its two segments from 3 to 12 px from the corner, the edge is located
//!   across the labelled line (the largest gradient of the photo smoothed by 1 px, by a
//!   parabola through its neighbours; one polarity per segment); the median of these offsets is
//!   the labelled line's offset at the corner. Their robust spread (1.4826 x the median
//!   absolute deviation about their mean, over every corner's segments) is the labels' line
//!   error `sigma_l`, and a labelled corner, the crossing of two such lines with unit normals
//!   `n1`, `n2`, is off by `sigma_l^2 (N^T N)^-1` (`N` the matrix of rows `n1`, `n2`): that
//!   covariance is added to a snapped point's before its error is judged against its 95 %
//!   ellipse. Their mean, per image axis, shows whether the labels sit half a pixel off the
//!   photo's pixel grid (coordinates here: pixel centres at `k + 0.5`).
//!
//! Measured: the distance of the point after snapping (the click when it stays) from the
//! labelled corner, its median against the raw clicks'; the share of clicks made worse by more
//! than 1 px; the share snapped; the share of snapped points whose labelled corner lies in their
//! 95 % ellipse, with and without the labels' error; the reasons clicks stayed.

use std::fmt::Write as _;
use std::path::Path;

use rand::{RngExt as _, SeedableRng as _};
use rand_chacha::ChaCha8Rng;
use serde::Deserialize;
use vpmap_metrology::scene::DivisionModel;
use vpmap_vision::photo::{PhotoLimits, decode_photo};
use vpmap_vision::snap::scene::vanishing_points_at;
use vpmap_vision::snap::{
    Doubt, KeptReason, SnapEdge, SnapImage, SnapOptions, SnapOutcome, snap_click,
};
use vpmap_vision::{DetectOptions, detect};

use super::yud_labels::{Gradient, label_offset};
use crate::detection::find_pairs;
use crate::error::{EvalError, Result, ResultExt as _, bail};
use crate::progress::Progress;
use crate::stats::{median, quantile_of};

/// Options of [`run_yud`].
#[derive(Debug, Clone, PartialEq)]
pub struct YudConfig {
    /// Click noise, pixels (1 sigma per coordinate).
    pub sigma_px: f64,
    /// Seed of the clicks.
    pub seed: u64,
    /// Largest distance between the two segments' nearest ends, pixels.
    pub max_gap_px: f64,
    /// Shortest segment, pixels.
    pub min_length_px: f64,
    /// Subtracted from every labelled coordinate, pixels: 0.5, as the labels put pixel
    /// centres at whole numbers and snapping at `k + 0.5` (see the [module docs](self)).
    pub label_shift_px: f64,
    /// The snapping options (`None`: [`SnapOptions::for_click_sigma`] of the click noise).
    pub snap: Option<SnapOptions>,
}

impl Default for YudConfig {
    fn default() -> Self {
        Self {
            sigma_px: 2.0,
            seed: 1,
            max_gap_px: 3.0,
            min_length_px: 15.0,
            label_shift_px: 0.5,
            snap: None,
        }
    }
}

/// A labelled corner: the crossing of two labelled segments' lines.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LabelledCorner {
    /// The corner, pixels.
    pub point_px: [f64; 2],
    /// The two segments (indices into the label file's `segments_xyxy`).
    pub segments: [usize; 2],
    /// The two lines' unit normals.
    pub normals: [[f64; 2]; 2],
}

/// One click on one labelled corner.
#[derive(Debug, Clone, PartialEq)]
pub struct YudClick {
    /// The photo's file stem.
    pub photo: String,
    /// The corner.
    pub corner: LabelledCorner,
    /// Distance of the click from the corner, pixels.
    pub raw_error_px: f64,
    /// Distance of the point after snapping (the click when kept), pixels.
    pub error_px: f64,
    /// Whether it moved.
    pub snapped: bool,
    /// The larger standard deviation of a snapped point's covariance, pixels.
    pub sd_px: Option<f64>,
    /// A snapped point's covariance, pixels squared.
    pub covariance_px2: Option<[[f64; 2]; 2]>,
    /// Why it stayed (a short name), when it did.
    pub kept: Option<&'static str>,
    /// How far a click exactly on the corner moved, pixels.
    pub exact_moved_px: f64,
    /// The error of the point after snapping, pixels (signed, x and y).
    pub error_vec_px: [f64; 2],
    /// The labelled lines' offsets from the photo's edges at the corner, pixels, along their
    /// normals (`None` where no edge was found).
    pub label_offsets_px: [Option<f64>; 2],
    /// A snapped point's edges (empty when it stayed).
    pub edges: Vec<SnapEdge>,
}

/// Every click of a run, and what the run found of the photos.
#[derive(Debug, Clone, Default)]
pub struct YudResults {
    /// Every click, photo by photo.
    pub clicks: Vec<YudClick>,
    /// Photos read.
    pub photos: usize,
    /// Photos whose vanishing points were detected (the labelled ones otherwise).
    pub detected: usize,
}

#[derive(Deserialize)]
struct LabelFile {
    segments_xyxy: Vec<[f64; 4]>,
    segment_vp_index0: Vec<usize>,
    vp_px: Vec<[f64; 2]>,
}

/// The labelled corners of one photo (see the [module docs](self)).
#[must_use]
pub fn labelled_corners(
    segments: &[[f64; 4]],
    vp_index: &[usize],
    config: &YudConfig,
) -> Vec<LabelledCorner> {
    let length = |s: &[f64; 4]| (s[2] - s[0]).hypot(s[3] - s[1]);
    let ends = |s: &[f64; 4]| [[s[0], s[1]], [s[2], s[3]]];
    let mut out = Vec::new();
    for (i, (a, va)) in segments.iter().zip(vp_index).enumerate() {
        if length(a) < config.min_length_px {
            continue;
        }
        for (j, (b, vb)) in segments.iter().zip(vp_index).enumerate().skip(i + 1) {
            if va == vb || length(b) < config.min_length_px {
                continue;
            }
            let gap = ends(a)
                .iter()
                .flat_map(|p| ends(b).map(|q| dist(*p, q)))
                .fold(f64::INFINITY, f64::min);
            if gap > config.max_gap_px {
                continue;
            }
            let (da, db) = ([a[2] - a[0], a[3] - a[1]], [b[2] - b[0], b[3] - b[1]]);
            let den = da[0] * db[1] - da[1] * db[0];
            if den.abs() <= 1e-12 {
                continue;
            }
            let t = ((b[0] - a[0]) * db[1] - (b[1] - a[1]) * db[0]) / den;
            let point_px = [a[0] + t * da[0], a[1] + t * da[1]];
            let normal = |d: [f64; 2]| {
                let n = d[0].hypot(d[1]);
                [-d[1] / n, d[0] / n]
            };
            out.push(LabelledCorner {
                point_px,
                segments: [i, j],
                normals: [normal(da), normal(db)],
            });
        }
    }
    out
}

/// Snap every labelled corner of every photo in `dir`, one photo at a time; one
/// [`Progress::step`] per photo.
///
/// # Errors
/// When the folder holds no labelled photos, or a photo or label file cannot be read.
pub fn run_yud(dir: &Path, config: &YudConfig, progress: &dyn Progress) -> Result<YudResults> {
    if !(config.sigma_px.is_finite() && config.sigma_px >= 0.0 && config.sigma_px <= 10.0) {
        bail!("the click noise {} px must lie in [0, 10]", config.sigma_px);
    }
    let pairs = find_pairs(dir)?;
    progress.start(pairs.len() as u64);
    let mut out = YudResults::default();
    let opts = snap_options(config);
    for pair in &pairs {
        let text = std::fs::read_to_string(&pair.label)
            .with_context(|| format!("cannot read {}", pair.label.display()))?;
        let label: LabelFile = serde_json::from_str(&text)
            .with_context(|| format!("{} is not a York Urban label file", pair.label.display()))?;
        if label.segments_xyxy.len() != label.segment_vp_index0.len() {
            bail!(
                "{}: {} segments but {} vanishing-point indices",
                pair.label.display(),
                label.segments_xyxy.len(),
                label.segment_vp_index0.len()
            );
        }
        let bytes = std::fs::read(&pair.image)
            .with_context(|| format!("cannot read photo {}", pair.image.display()))?;
        let photo = decode_photo(&bytes, &PhotoLimits::default())
            .map_err(|e| EvalError::Invalid(format!("{}: {e}", pair.image.display())))?;
        let image = SnapImage::new(&photo.image);
        let grad = Gradient::new(&photo.image);
        // Detect's points are the pinhole camera's of the lens it applied (none unless the
        // edges show one at 99 %); snapping looks through that lens, as `vpmap snap` does with
        // the scene detect writes.
        let (detected, lens): (Vec<[f64; 3]>, Option<DivisionModel>) =
            detect(&photo.image, &DetectOptions::default())
                .map(|d| {
                    let (f, c) = (d.intrinsics.focal_px, d.intrinsics.principal_point_px);
                    let points = d
                        .vanishing_points
                        .iter()
                        .map(|v| {
                            let k = v.direction_camera;
                            [f * k[0] + c[0] * k[2], f * k[1] + c[1] * k[2], k[2]]
                        })
                        .collect();
                    (points, d.lens.map(|l| l.model))
                })
                .unwrap_or_default();
        let (vps, lens) = if detected.len() >= 2 {
            out.detected += 1;
            (detected, lens)
        } else {
            (
                label.vp_px.iter().map(|p| [p[0], p[1], 1.0]).collect(),
                None,
            )
        };
        out.photos += 1;
        // The labels put pixel centres at whole numbers (MATLAB's 1-based pixels); here they
        // sit at `k + 0.5`.
        let segments: Vec<[f64; 4]> = label
            .segments_xyxy
            .iter()
            .map(|s| s.map(|v| v - config.label_shift_px))
            .collect();
        let corners = labelled_corners(&segments, &label.segment_vp_index0, config);
        let mut rng = ChaCha8Rng::seed_from_u64(config.seed ^ name_hash(&pair.name));
        for corner in corners {
            let noise = [gaussian(&mut rng), gaussian(&mut rng)];
            let click = clamp_into(
                [
                    corner.point_px[0] + config.sigma_px * noise[0],
                    corner.point_px[1] + config.sigma_px * noise[1],
                ],
                &image,
            );
            let Some(truth_click) = inside(corner.point_px, &image) else {
                continue;
            };
            let snap = snap_click(
                &image,
                &vanishing_points_at(&vps, lens.as_ref(), click),
                click,
                &opts,
            )
            .map_err(|e| EvalError::Invalid(format!("{}: snapping a click: {e}", pair.name)))?;
            let exact = snap_click(
                &image,
                &vanishing_points_at(&vps, lens.as_ref(), truth_click),
                truth_click,
                &opts,
            )
            .map_err(|e| EvalError::Invalid(format!("{}: snapping a click: {e}", pair.name)))?;
            let label_offsets_px = [0, 1].map(|k| {
                let s = corner.segments[k];
                segments
                    .get(s)
                    .and_then(|seg| label_offset(&grad, corner.point_px, seg, corner.normals[k]))
            });
            out.clicks.push(YudClick {
                photo: pair.name.clone(),
                corner,
                raw_error_px: dist(click, corner.point_px),
                error_px: dist(snap.point_px, corner.point_px),
                snapped: snap.snapped(),
                sd_px: snap.covariance_px2.map(largest_sd),
                covariance_px2: snap.covariance_px2,
                kept: match snap.outcome {
                    SnapOutcome::Snapped => None,
                    SnapOutcome::Kept(r) => Some(kept_name(&r)),
                },
                exact_moved_px: exact.moved_px(),
                error_vec_px: [
                    snap.point_px[0] - corner.point_px[0],
                    snap.point_px[1] - corner.point_px[1],
                ],
                label_offsets_px,
                edges: snap.edges.clone(),
            });
        }
        progress.step();
    }
    progress.finish();
    Ok(out)
}

fn kept_name(r: &KeptReason) -> &'static str {
    match r {
        KeptReason::NoEdge => "no straight edge",
        KeptReason::OneDirection(_) => "edges of one direction",
        KeptReason::TooFar { .. } => "no meeting within the radius",
        KeptReason::Unsure { doubt, .. } => match doubt {
            Doubt::TJunction => "unsure: a T junction",
            Doubt::ShortEdge { .. } => "unsure: an edge too short",
            Doubt::RoughEdge { .. } => "unsure: an edge not straight",
            Doubt::OffVanishingPoint { .. } => "unsure: an edge off its vanishing point",
            Doubt::Rival { .. } => "unsure: a rival corner",
            #[allow(unreachable_patterns)]
            _ => "unsure",
        },
        #[allow(unreachable_patterns)]
        _ => "other",
    }
}

/// The labels' error measured at the corners: the mean offset per image axis (a bias, by
/// least squares over the offsets' normals) and the robust sd of the offsets about it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LabelError {
    /// The mean offset of the labelled lines from the photo's edges, x and y, pixels.
    pub bias_px: [f64; 2],
    /// 1.4826 x the median absolute deviation of the offsets about the bias, pixels.
    pub sd_px: f64,
    /// Segment ends measured.
    pub count: usize,
}

/// The labels' error from the clicks' measured offsets (each corner's two segments).
#[must_use]
pub fn label_error(clicks: &[YudClick]) -> Option<LabelError> {
    let obs: Vec<([f64; 2], f64)> = clicks
        .iter()
        .flat_map(|c| {
            (0..2).filter_map(move |k| c.label_offsets_px[k].map(|d| (c.corner.normals[k], d)))
        })
        .collect();
    // Least squares d = n . b.
    let (mut a, mut r) = ([[0.0; 2]; 2], [0.0; 2]);
    for (n, d) in &obs {
        for i in 0..2 {
            r[i] += n[i] * d;
            for j in 0..2 {
                a[i][j] += n[i] * n[j];
            }
        }
    }
    let det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
    if obs.len() < 10 || det.abs() < 1e-9 {
        return None;
    }
    let bias_px = [
        (a[1][1] * r[0] - a[0][1] * r[1]) / det,
        (a[0][0] * r[1] - a[1][0] * r[0]) / det,
    ];
    let dev: Vec<f64> = obs
        .iter()
        .map(|(n, d)| (d - n[0] * bias_px[0] - n[1] * bias_px[1]).abs())
        .collect();
    Some(LabelError {
        bias_px,
        sd_px: 1.4826 * median(&dev)?,
        count: obs.len(),
    })
}

/// The covariance of a labelled corner from its two lines' error `sd_px`:
/// `sd^2 (N^T N)^-1`, `N` the rows of the two normals.
#[must_use]
pub fn corner_label_covariance(corner: &LabelledCorner, sd_px: f64) -> [[f64; 2]; 2] {
    let [n1, n2] = corner.normals;
    let m = [
        [n1[0] * n1[0] + n2[0] * n2[0], n1[0] * n1[1] + n2[0] * n2[1]],
        [n1[0] * n1[1] + n2[0] * n2[1], n1[1] * n1[1] + n2[1] * n2[1]],
    ];
    let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    let s2 = sd_px * sd_px;
    if det.abs() < 1e-12 {
        return [[f64::INFINITY, 0.0], [0.0, f64::INFINITY]];
    }
    [
        [s2 * m[1][1] / det, -s2 * m[0][1] / det],
        [-s2 * m[1][0] / det, s2 * m[0][0] / det],
    ]
}

/// The squared Mahalanobis distance of `e` under `cov`.
pub(super) fn mahalanobis_sq(e: [f64; 2], cov: [[f64; 2]; 2]) -> f64 {
    let det = cov[0][0] * cov[1][1] - cov[0][1] * cov[1][0];
    if det.is_nan() || det <= 0.0 {
        return f64::INFINITY;
    }
    (e[0] * e[0] * cov[1][1] - 2.0 * e[0] * e[1] * cov[0][1] + e[1] * e[1] * cov[0][0]) / det
}

/// Whether a snapped click's labelled corner lies inside its 95 % ellipse: the snap's
/// covariance plus the labels' error at the corner (`label_sd_px`,
/// [`corner_label_covariance`]) plus `add_px2` on each axis (a floor changed, a term taken
/// out); `None` for a click without a covariance.
pub(super) fn inside_95(c: &YudClick, label_sd_px: f64, add_px2: f64) -> Option<bool> {
    let cov = c.covariance_px2?;
    let l = corner_label_covariance(&c.corner, label_sd_px);
    let total = [
        [cov[0][0] + l[0][0] + add_px2, cov[0][1] + l[0][1]],
        [cov[1][0] + l[1][0], cov[1][1] + l[1][1] + add_px2],
    ];
    Some(mahalanobis_sq(c.error_vec_px, total) <= CHI2_95)
}

/// The chi-square quantile with 2 degrees of freedom at 95 %.
pub(super) const CHI2_95: f64 = 5.991_464_547_107_979;

/// What the median distance after snapping is made of: the share of clicks within 1 px of
/// their labelled corner (the median is at most 1 px exactly when it reaches half), of the
/// snapped ones and of those that stayed, and what an all-precise snap would give at this
/// share snapped.
fn within_one_px(clicks: &[YudClick]) -> String {
    let share = |set: &[&YudClick]| {
        let near = set.iter().filter(|c| c.error_px <= 1.0).count();
        (
            near,
            set.len(),
            100.0 * near as f64 / set.len().max(1) as f64,
        )
    };
    let all: Vec<&YudClick> = clicks.iter().collect();
    let (snapped, stayed): (Vec<&YudClick>, Vec<&YudClick>) =
        clicks.iter().partition(|c| c.snapped);
    let (a, n, a_pct) = share(&all);
    let (b, m, b_pct) = share(&snapped);
    let (c, k, c_pct) = share(&stayed);
    // Were every snapped point within 1 px, the share within 1 px would be the snapped share
    // plus the clicks that stayed and lie within 1 px anyway.
    let best = 100.0 * (m + c) as f64 / n.max(1) as f64;
    format!(
        "Within 1 px of the labelled corner after snapping: {a} of {n} clicks ({a_pct:.1} %; the median distance is at most 1 px when this reaches 50 %): {b} of the {m} snapped ({b_pct:.1} %), {c} of the {k} that stayed ({c_pct:.1} %). Were every snapped point within 1 px, {best:.1} % would be."
    )
}

/// The name of the section `--yud DIR --publish` writes.
pub const YUD_SECTION: &str = "eval-clicks-yud";

/// The section of `docs/results.md`.
#[must_use]
pub fn yud_published_section(
    config: &YudConfig,
    results: &YudResults,
    elapsed: std::time::Duration,
    command: &str,
) -> String {
    crate::publish::published(
        "Snapping clicks on real photos (`vpmap eval-clicks --yud`)",
        &yud_markdown(config, results),
        elapsed,
        command,
    )
}

/// The report's Markdown (no title).
#[must_use]
pub fn yud_markdown(config: &YudConfig, results: &YudResults) -> String {
    let mut s = String::new();
    let clicks = &results.clicks;
    let n = clicks.len();
    let label = label_error(clicks);
    let _ = writeln!(
        s,
        "{} York Urban photos (640 x 480), {n} labelled corners (two labelled segments of different vanishing points, their nearest ends within {} px, both at least {} px long; the corner where their lines cross); vanishing points detected in {} photos (the labelled ones otherwise). Each corner clicked once, Gaussian noise of {} px per coordinate (seed {}); search radius {:.1} px.\n",
        results.photos,
        config.max_gap_px,
        config.min_length_px,
        results.detected,
        config.sigma_px,
        config.seed,
        snap_options(config).search_radius_px,
    );
    if let Some(l) = label {
        let _ = writeln!(
            s,
            "The labels' own error, measured at the corners ({} segment ends: the photo's edge located across the labelled line from 3 to 12 px from the corner): mean offset ({:+.2}, {:+.2}) px in x and y, spread about it {:.2} px (robust sd), so a labelled corner is off by `{:.2}^2 (N^T N)^-1` px² (`N` the two lines' unit normals), which is added to a snapped point's covariance below.\n",
            l.count, l.bias_px[0], l.bias_px[1], l.sd_px, l.sd_px
        );
    }
    let sd_l = label.map_or(0.0, |l| l.sd_px);
    let bias = label.map_or([0.0; 2], |l| l.bias_px);
    let checks: Vec<LabelCheck> = clicks.iter().map(|c| label_check(c, bias, sd_l)).collect();
    let subset = |keep: &dyn Fn(LabelCheck) -> bool| -> Vec<&YudClick> {
        clicks
            .iter()
            .zip(&checks)
            .filter(|(_, k)| keep(**k))
            .map(|(c, _)| c)
            .collect()
    };
    let not_outlier = subset(&|k| k != LabelCheck::Outlier);
    let confirmed = subset(&|k| k == LabelCheck::Confirmed);
    let _ = writeln!(
        s,
        "| corners | median distance to the corner after snapping | p90 | raw clicks' median | made worse by > 1 px | snapped | snapped points' median distance | corner in the 95 % ellipse (labels' error added) | without it | snapped points' median sd |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|---|");
    let all: Vec<&YudClick> = clicks.iter().collect();
    table_row(&mut s, &format!("every corner, {n}"), &all, sd_l);
    table_row(
        &mut s,
        &format!("labels the photo does not show off, {}", not_outlier.len()),
        &not_outlier,
        sd_l,
    );
    table_row(
        &mut s,
        &format!("labels the photo confirms, {}", confirmed.len()),
        &confirmed,
        sd_l,
    );
    let _ = writeln!(
        s,
        "\nThe labels' error is taken as a Gaussian of that sd with outliers: a labelled line farther than {LABEL_OUTLIER_SDS} robust sd ({:.2} px) from the photo's edge where it is measured (3-12 px from the corner) is an outlier, and a corner with one cannot say whether a snap is right ({} of {n} corners; where the labels drew an edge the photo does not show there). The second row leaves those out; the third also leaves out the {} corners where a line could not be measured (no edge found beside the label), which favours clear corners. Which corners are left out depends on the labels and the photo only, never on the snap.",
        LABEL_OUTLIER_SDS * sd_l,
        n - not_outlier.len(),
        not_outlier.len() - confirmed.len(),
    );
    let snapped: Vec<&YudClick> = clicks.iter().filter(|c| c.snapped).collect();
    // The floor the covariances would need on these photos: the smallest, in steps of 0.1 px,
    // that puts at least 90 % (92 %) of the labelled corners in the snapped points' 95 %
    // ellipses.
    let floor = opts_floor(config);
    let needed = |share: f64| {
        (0..=40).map(|k| 0.1 * f64::from(k)).find(|&f| {
            let inside = snapped
                .iter()
                .filter(|c| inside_95(c, sd_l, f * f - floor * floor) == Some(true))
                .count();
            !snapped.is_empty() && inside as f64 >= share * snapped.len() as f64
        })
    };
    let show =
        |f: Option<f64>| f.map_or_else(|| "more than 4 px".to_owned(), |f| format!("{f:.1} px"));
    let _ = writeln!(s, "\n{}", within_one_px(clicks));
    let _ = writeln!(
        s,
        "\nThe covariance floor (`SnapOptions::covariance_floor_px`, {floor} px in this run) these photos need for the snapped points' 95 % ellipses to hold their labelled corner (labels' error added) 90 % of the time: {}; 92 %: {}.",
        show(needed(0.90)),
        show(needed(0.92))
    );
    s.push_str(&super::yud_unseen::by_unseen_stretch(
        &snapped,
        sd_l,
        snap_options(config).unseen_sd_per_px,
    ));
    // Coverage by how clear the edges are.
    let quality: Vec<(super::EdgeQuality, bool)> = snapped
        .iter()
        .filter_map(|c| Some((super::EdgeQuality::of(&c.edges)?, inside_95(c, sd_l, 0.0)?)))
        .collect();
    let _ = writeln!(
        s,
        "\nThe snapped points (every corner) inside their 95 % ellipse (labels' error added), in four groups of about equal size by the weaker edge's mean gradient across (grey levels per pixel, weakest first): {}; by the rougher edge's residual RMS (pixels, smoothest first): {}.",
        super::inside_by_quarter(
            quality
                .iter()
                .map(|(q, i)| (q.weaker_gradient, *i))
                .collect()
        ),
        super::inside_by_quarter(
            quality
                .iter()
                .map(|(q, i)| (q.rougher_rms_px, *i))
                .collect()
        ),
    );
    let exact: Vec<f64> = clicks.iter().map(|c| c.exact_moved_px).collect();
    let _ = writeln!(
        s,
        "\nA click exactly on the labelled corner moves a median {} px (p90 {} px).\n",
        num(median(&exact), 2),
        num(quantile_of(&exact, 0.9), 2)
    );
    let mut reasons: Vec<(&str, usize)> = Vec::new();
    for c in clicks {
        if let Some(k) = c.kept {
            match reasons.iter_mut().find(|(r, _)| *r == k) {
                Some(e) => e.1 += 1,
                None => reasons.push((k, 1)),
            }
        }
    }
    if !reasons.is_empty() {
        let list: Vec<String> = reasons.iter().map(|(r, k)| format!("{r}: {k}")).collect();
        let _ = writeln!(s, "Clicks that stayed, by reason: {}.", list.join("; "));
    }
    s
}

/// A labelled line farther than this many robust sd from the photo's edge is an outlier.
pub const LABEL_OUTLIER_SDS: f64 = 3.0;

/// What the photo says of a corner's two labelled lines, each compared with the photo's edge
/// where it was measured (after the labels' mean offset `bias_px`): within
/// [`LABEL_OUTLIER_SDS`] robust sd (`sd_px`), farther, or not measured (no edge found).
#[must_use]
pub fn label_check(click: &YudClick, bias_px: [f64; 2], sd_px: f64) -> LabelCheck {
    let mut check = LabelCheck::Confirmed;
    for k in 0..2 {
        match click.label_offsets_px[k] {
            None => check = LabelCheck::Unmeasured,
            Some(d) => {
                let n = click.corner.normals[k];
                if (d - n[0] * bias_px[0] - n[1] * bias_px[1]).abs() > LABEL_OUTLIER_SDS * sd_px {
                    return LabelCheck::Outlier;
                }
            }
        }
    }
    check
}

/// What the photo says of a labelled corner ([`label_check`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LabelCheck {
    /// Both labelled lines lie within [`LABEL_OUTLIER_SDS`] sd of the photo's edges.
    Confirmed,
    /// Neither is off, but at least one could not be measured (no edge found there).
    Unmeasured,
    /// A labelled line lies farther than [`LABEL_OUTLIER_SDS`] sd from the photo's edge.
    Outlier,
}

/// One row of the table: the clicks `clicks`, named `name`.
fn table_row(s: &mut String, name: &str, clicks: &[&YudClick], sd_l: f64) {
    let n = clicks.len();
    let after: Vec<f64> = clicks.iter().map(|c| c.error_px).collect();
    let raw: Vec<f64> = clicks.iter().map(|c| c.raw_error_px).collect();
    let worse = clicks
        .iter()
        .filter(|c| c.error_px > c.raw_error_px + 1.0)
        .count();
    let snapped: Vec<&&YudClick> = clicks.iter().filter(|c| c.snapped).collect();
    let (mut inside, mut inside_plain) = (0, 0);
    for c in &snapped {
        let (Some(cov), Some(labelled)) = (c.covariance_px2, inside_95(c, sd_l, 0.0)) else {
            continue;
        };
        inside += usize::from(labelled);
        inside_plain += usize::from(mahalanobis_sq(c.error_vec_px, cov) <= CHI2_95);
    }
    let sds: Vec<f64> = snapped.iter().filter_map(|c| c.sd_px).collect();
    let snapped_err: Vec<f64> = snapped.iter().map(|c| c.error_px).collect();
    let _ = writeln!(
        s,
        "| {name} | {} px | {} px | {} px | {} ({}) | {} ({}) | {} px | {} | {} | {} px |",
        num(median(&after), 2),
        num(quantile_of(&after, 0.9), 2),
        num(median(&raw), 2),
        worse,
        pct(worse, n),
        snapped.len(),
        pct(snapped.len(), n),
        num(median(&snapped_err), 2),
        pct(inside, snapped.len()),
        pct(inside_plain, snapped.len()),
        num(median(&sds), 2),
    );
}

/// The snapping options of a run.
fn snap_options(config: &YudConfig) -> SnapOptions {
    config
        .snap
        .unwrap_or_else(|| SnapOptions::for_click_sigma(config.sigma_px.max(0.5)))
}

fn opts_floor(config: &YudConfig) -> f64 {
    snap_options(config).covariance_floor_px
}

fn pct(part: usize, whole: usize) -> String {
    if whole == 0 {
        "-".to_owned()
    } else {
        format!("{:.1} %", 100.0 * part as f64 / whole as f64)
    }
}

fn num(v: Option<f64>, digits: usize) -> String {
    v.map_or_else(|| "-".to_owned(), |v| format!("{v:.digits$}"))
}

fn largest_sd(c: [[f64; 2]; 2]) -> f64 {
    let (a, b, d) = (c[0][0], c[0][1], c[1][1]);
    let m = 0.5 * (a + d);
    let r = (0.25 * (a - d) * (a - d) + b * b).sqrt();
    (m + r).max(0.0).sqrt()
}

pub(super) fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// A standard normal draw (Box-Muller).
fn gaussian(rng: &mut ChaCha8Rng) -> f64 {
    let u1: f64 = rng.random::<f64>().max(1e-300);
    let u2: f64 = rng.random::<f64>();
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

/// FNV-1a of a name, for per-photo seeds.
fn name_hash(name: &str) -> u64 {
    name.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

/// The point if it lies inside the photo.
fn inside(p: [f64; 2], image: &SnapImage) -> Option<[f64; 2]> {
    let (w, h) = (f64::from(image.width()), f64::from(image.height()));
    (p[0] >= 0.0 && p[0] <= w && p[1] >= 0.0 && p[1] <= h).then_some(p)
}

/// The point moved into the photo.
fn clamp_into(p: [f64; 2], image: &SnapImage) -> [f64; 2] {
    [
        p[0].clamp(0.0, f64::from(image.width())),
        p[1].clamp(0.0, f64::from(image.height())),
    ]
}

/// A click for unit tests: a corner at (10, 10) on two axis-aligned lines, clicked 2 px off
/// and left there 1 px off, not snapped, no label offsets measured.
#[cfg(test)]
pub(super) fn test_click() -> YudClick {
    YudClick {
        photo: "p".to_owned(),
        corner: LabelledCorner {
            point_px: [10.0, 10.0],
            segments: [0, 1],
            normals: [[1.0, 0.0], [0.0, 1.0]],
        },
        raw_error_px: 2.0,
        error_px: 1.0,
        snapped: false,
        sd_px: None,
        covariance_px2: None,
        kept: None,
        exact_moved_px: 0.0,
        error_vec_px: [1.0, 0.0],
        label_offsets_px: [None, None],
        edges: Vec::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_share_within_1_px_counts_snapped_and_stayed_clicks_apart() {
        let click = |error_px: f64, snapped: bool| YudClick {
            error_px,
            snapped,
            error_vec_px: [error_px, 0.0],
            ..test_click()
        };
        // Snapped: 0.5 and 1.0 px within, 1.5 px not; stayed: 0.9 within, 2.5 and 3.0 not.
        let clicks = [
            click(0.5, true),
            click(1.0, true),
            click(1.5, true),
            click(0.9, false),
            click(2.5, false),
            click(3.0, false),
        ];
        let text = within_one_px(&clicks);
        assert!(text.contains("3 of 6 clicks (50.0 %"), "{text}");
        assert!(text.contains("2 of the 3 snapped (66.7 %)"), "{text}");
        assert!(text.contains("1 of the 3 that stayed (33.3 %)"), "{text}");
        // Every snapped point within 1 px: the three snapped and the one that stayed.
        assert!(text.contains("66.7 % would be"), "{text}");
    }

    #[test]
    fn a_label_is_an_outlier_only_where_the_photo_shows_its_line_off() {
        let click = |offsets: [Option<f64>; 2]| YudClick {
            label_offsets_px: offsets,
            ..test_click()
        };
        let sd = 0.5;
        // 3 sd = 1.5 px; a bias of 0.2 px along x moves the first line's allowance.
        let bias = [0.2, 0.0];
        assert_eq!(
            label_check(&click([Some(1.6), Some(-1.4)]), bias, sd),
            LabelCheck::Confirmed
        );
        assert_eq!(
            label_check(&click([Some(-1.4), Some(0.0)]), bias, sd),
            LabelCheck::Outlier
        );
        assert_eq!(
            label_check(&click([Some(0.1), Some(1.6)]), bias, sd),
            LabelCheck::Outlier
        );
        assert_eq!(
            label_check(&click([None, Some(0.3)]), bias, sd),
            LabelCheck::Unmeasured
        );
        assert_eq!(
            label_check(&click([None, Some(2.0)]), bias, sd),
            LabelCheck::Outlier
        );
    }

    #[test]
    fn two_segments_meeting_at_their_ends_make_one_corner_where_their_lines_cross() {
        // An L: a horizontal segment ending 2 px short of a vertical one's end.
        let segments = [
            [10.0, 50.0, 48.0, 50.0],
            [50.0, 49.0, 50.0, 10.0],
            [10.0, 10.0, 20.0, 10.0], // too short
            [12.0, 60.0, 48.0, 60.0], // same direction as the first
        ];
        let corners = labelled_corners(&segments, &[0, 1, 0, 0], &YudConfig::default());
        assert_eq!(corners.len(), 1);
        let c = corners[0];
        assert!(dist(c.point_px, [50.0, 50.0]) < 1e-9);
        assert_eq!(c.segments, [0, 1]);
        // Perpendicular lines of 0.5 px error: the corner is off by 0.5 px per axis.
        let cov = corner_label_covariance(&c, 0.5);
        assert!((cov[0][0] - 0.25).abs() < 1e-12 && (cov[1][1] - 0.25).abs() < 1e-12);
    }
}

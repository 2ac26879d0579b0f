//! `vpmap detect` and `vpmap eval-detect`.
//!
//! `vpmap detect PHOTO --out SCENE` finds line segments, the three Manhattan vanishing points
//! and the camera in one photo ([`vpmap_vision::detect`]) and writes a scene file
//! (`docs/scene-format.md`) whose vanishing points carry their supporting segments as
//! evidence, with empty `objects` and `floor` for the user to fill in; `--overlay` draws what
//! was found on the photo. `vpmap eval-detect DIR` measures the detector on York Urban-style
//! labelled photos ([`eval`]).

mod eval;
mod options;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::{Context, Result, anyhow, bail};
use vpmap_metrology::calibration::Perspective;
use vpmap_vision::{DetectOptions, Detection, detect};

pub use eval::{EvalDetectArgs, run_eval_detect};

use crate::output::write_file;
use options::{check_max_side, check_two_point_tolerance, default_options, parse_lens};
use vpmap_pipeline::num;
use vpmap_render::overlay::{VP_COLOUR_NAMES, detection_overlay_png};
use vpmap_vision::photo::{PhotoLimits, decode_photo};
use vpmap_vision::scene::{DetectedScene, VP_NAMES, detected_scene};

/// Accepted `--focal-px`, as multiples of the photo's longer side (fields of view from about
/// 157 degrees down to 0.6 degree).
const FOCAL_RANGE_SIDES: std::ops::RangeInclusive<f64> = 0.1..=100.0;

/// Arguments of `vpmap detect`.
#[derive(clap::Args)]
pub struct DetectArgs {
    /// The photo: JPEG or PNG, any size, grey or colour.
    pub photo: PathBuf,
    /// Scene file to write (JSON; see docs/scene-format.md).
    #[arg(long, short)]
    pub out: PathBuf,
    /// Known focal length, pixels (default: estimated from the vanishing points).
    #[arg(long, allow_negative_numbers = true)]
    pub focal_px: Option<f64>,
    /// Known principal point X,Y, pixels (default: estimated, or the image centre).
    #[arg(long, allow_hyphen_values = true)]
    pub principal_point: Option<String>,
    /// Also write the photo with the segments (coloured by vanishing point), the horizon and
    /// the principal point drawn on it (PNG).
    #[arg(long)]
    pub overlay: Option<PathBuf>,
    /// Vertical edges within this angle of the image plane make the scene two-point
    /// perspective: the vertical vanishing point is left out, and `vpmap build`'s side-view and
    /// projective methods take the camera as level. The horizon written is the measured one
    /// either way (the camera is never levelled). Default 0: the vertical point is written
    /// whenever it is finite, degrees.
    #[arg(long, default_value_t = default_options().two_point_tolerance_deg, allow_negative_numbers = true)]
    pub two_point_tolerance: f64,
    /// The photo is downscaled internally so that its longer side is at most this, pixels
    /// (results are in the photo's pixels).
    #[arg(long, default_value_t = default_options().max_side_px)]
    pub max_side: u32,
    /// Lens distortion: `estimate` the one-parameter division model's k from the straight
    /// edges (default), `none` (a pinhole photo, e.g. already undistorted), or a known k
    /// (barrel distortion is negative; docs/scene-format.md).
    #[arg(long, default_value = "estimate", allow_hyphen_values = true)]
    pub lens: String,
}

pub use vpmap_vision::photo::Photo;

/// Read a JPEG or PNG photo, refusing other files, truncated files and absurd sizes.
///
/// # Errors
/// One line naming the file and the problem.
pub fn read_photo(path: &Path) -> Result<Photo> {
    let bytes = vpmap_files::read_bytes(path, vpmap_files::Format::Photo)?;
    // The vision crate's limits: the detector's largest side, 150 megapixels, 2 GiB of
    // decoder memory.
    decode_photo(&bytes, &PhotoLimits::default()).map_err(|e| anyhow!("{}: {e}", path.display()))
}

/// `X,Y` as two finite numbers.
fn parse_point(what: &str, text: &str) -> Result<[f64; 2]> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    let parsed: Vec<f64> = parts.iter().filter_map(|s| s.parse().ok()).collect();
    match parsed.as_slice() {
        [x, y] if parts.len() == 2 && x.is_finite() && y.is_finite() => Ok([*x + 0.0, *y + 0.0]),
        _ => bail!("{what} {text:?} is not a point X,Y (two numbers separated by a comma)"),
    }
}

/// Check what can be checked before the photo is read.
fn check_args(args: &DetectArgs) -> Result<Option<[f64; 2]>> {
    if let Some(f) = args.focal_px
        && !(f.is_finite() && f > 0.0)
    {
        bail!(
            "--focal-px must be a positive number of pixels, got {}",
            num(f)
        );
    }
    let principal_point = args
        .principal_point
        .as_deref()
        .map(|t| parse_point("--principal-point", t))
        .transpose()?;
    check_two_point_tolerance(args.two_point_tolerance)?;
    check_max_side(args.max_side)?;
    if args.out.to_string_lossy().ends_with('/') || args.out.is_dir() {
        bail!(
            "--out {} is a folder; give a file name such as scene.json",
            args.out.display()
        );
    }
    if let Some(o) = &args.overlay {
        if o.to_string_lossy().ends_with('/') || o.is_dir() {
            bail!(
                "--overlay {} is a folder; give a file name such as overlay.png",
                o.display()
            );
        }
        if !o.extension().is_some_and(|e| e.eq_ignore_ascii_case("png")) {
            bail!("--overlay {} must be a .png file", o.display());
        }
        if same_file(o, &args.out) {
            bail!("--overlay and --out are the same file {}", o.display());
        }
    }
    for (flag, target) in [
        ("--out", Some(&args.out)),
        ("--overlay", args.overlay.as_ref()),
    ] {
        if let Some(t) = target
            && same_file(t, &args.photo)
        {
            bail!("{flag} {} would overwrite the photo", t.display());
        }
    }
    Ok(principal_point)
}

/// Whether two paths name the same file (after resolving the folders that exist).
fn same_file(a: &Path, b: &Path) -> bool {
    let resolve = |p: &Path| -> PathBuf {
        let parent = p
            .parent()
            .filter(|d| !d.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        let dir = parent
            .canonicalize()
            .unwrap_or_else(|_| parent.to_path_buf());
        p.file_name().map_or(dir.clone(), |n| dir.join(n))
    };
    resolve(a) == resolve(b)
}

/// Check the known intrinsics against the photo.
fn check_intrinsics(
    args: &DetectArgs,
    principal_point: Option<[f64; 2]>,
    width: u32,
    height: u32,
) -> Result<()> {
    let side = f64::from(width.max(height));
    if let Some(f) = args.focal_px
        && !FOCAL_RANGE_SIDES.contains(&(f / side))
    {
        bail!(
            "--focal-px {} is outside {} to {} px ({} to {} times the photo's longer side, {side} px)",
            num(f),
            num(FOCAL_RANGE_SIDES.start() * side),
            num(FOCAL_RANGE_SIDES.end() * side),
            FOCAL_RANGE_SIDES.start(),
            FOCAL_RANGE_SIDES.end()
        );
    }
    if let Some([x, y]) = principal_point
        && !(0.0..=f64::from(width)).contains(&x) | !(0.0..=f64::from(height)).contains(&y)
    {
        bail!(
            "--principal-point ({}, {}) lies outside the {width} x {height} photo",
            num(x),
            num(y)
        );
    }
    Ok(())
}

/// `vpmap detect`.
pub fn run_detect(args: &DetectArgs) -> Result<()> {
    let principal_point = check_args(args)?;
    let photo = read_photo(&args.photo)?;
    let (width, height) = (photo.image.width(), photo.image.height());
    check_intrinsics(args, principal_point, width, height)?;
    // The EXIF focal length is a prior when the focal length is not given; one present but
    // unusable (absurd, no 35 mm value, broken EXIF) is said, never silently used or dropped.
    let exif_prior = if args.focal_px.is_none() {
        match photo.exif_focal_prior() {
            Ok(prior) => prior,
            Err(why) => {
                eprintln!("warning: {}: {why}", args.photo.display());
                None
            }
        }
    } else {
        None
    };
    let opts = DetectOptions {
        focal_px: args.focal_px,
        focal_prior: exif_prior,
        principal_point_px: principal_point,
        max_side_px: args.max_side,
        two_point_tolerance_deg: args.two_point_tolerance,
        lens: parse_lens(&args.lens)?,
        ..default_options()
    };
    let started = Instant::now();
    let result = detect(&photo.image, &opts);
    let elapsed = started.elapsed();
    let det = result
        .map_err(|e| anyhow!("{e}"))
        .with_context(|| format!("no vanishing points found in {}", args.photo.display()))?;
    let scene = detected_scene(&det)
        .with_context(|| format!("no usable vanishing points in {}", args.photo.display()))?;
    let overlay = args
        .overlay
        .as_ref()
        .map(|_| detection_overlay_png(&photo.image, &det, &scene))
        .transpose()?;

    if let (Some(path), Some(bytes)) = (&args.overlay, overlay) {
        write_file(path, bytes)?;
    }
    if let Err(e) = write_file(&args.out, scene.json.clone()) {
        // Both files or neither.
        if let Some(path) = &args.overlay {
            let _ = std::fs::remove_file(path);
        }
        return Err(e);
    }
    println!(
        "{}",
        wrap(&summary(args, &photo, &det, &scene, elapsed), 100)
    );
    for (name, n) in scene.thinly_supported(&det) {
        let drawn = if args.overlay.is_some() {
            " in the overlay"
        } else {
            " (--overlay draws them)"
        };
        eprintln!("warning: {name} rests on only {n} segments; check it{drawn}");
    }
    for w in scene
        .off_centre_warning(&det)
        .iter()
        .chain(&scene.calibration.warnings)
    {
        eprintln!("warning: {w}");
    }
    Ok(())
}

fn point_text(p: Option<[f64; 2]>) -> String {
    match p {
        Some([x, y]) if x.abs().max(y.abs()) < 1e6 => format!("({x:.1}, {y:.1})"),
        Some([x, y]) => format!("({x:.3e}, {y:.3e})"),
        None => "at infinity".to_owned(),
    }
}

/// The one-paragraph summary `vpmap detect` prints.
fn summary(
    args: &DetectArgs,
    photo: &Photo,
    det: &Detection,
    scene: &DetectedScene,
    elapsed: Duration,
) -> String {
    let cal = &scene.calibration;
    let exif_source;
    let focal_source = match det.focal_prior {
        _ if !det.focal_estimated => "given",
        Some((f, sd)) => {
            exif_source = format!(
                "estimated with the EXIF's 35 mm equivalent as a prior, {f:.1} px +- {:.0} %, which the scene carries for vpmap build",
                100.0 * sd
            );
            exif_source.as_str()
        }
        None => "estimated",
    };
    let principal_point_source = if args.principal_point.is_some() {
        "given"
    } else if det.principal_point_estimated {
        "estimated"
    } else {
        "the image centre: the vanishing points do not fix it"
    };
    let mut text = format!(
        "{} ({} x {}{}): {} perspective, focal {:.1} px ({}), principal point ({:.1}, {:.1}) ({}), ",
        args.photo.display(),
        det.image_size_px[0],
        det.image_size_px[1],
        if photo.reoriented {
            ", turned upright as its EXIF orientation says"
        } else {
            ""
        },
        scene.perspective.words(),
        det.intrinsics.focal_px,
        focal_source,
        det.intrinsics.principal_point_px[0],
        det.intrinsics.principal_point_px[1],
        principal_point_source,
    );
    let _ = match scene.perspective {
        Perspective::TwoPoint => write!(
            text,
            "roll {:.2} deg; vertical edges {:.2} deg from the image plane, {}, so the vertical vanishing point is not written and vpmap build's side-view and projective methods take the camera as level. The horizon written is the measured one, {:.1} px {} the principal point.",
            cal.roll_rad.to_degrees(),
            det.vertical_tilt_deg,
            if det.perspective == Perspective::TwoPoint {
                format!("within the {} deg tolerance", args.two_point_tolerance)
            } else {
                "their vanishing point too far to write".to_owned()
            },
            scene.horizon_offset_px(det).abs(),
            if scene.horizon_offset_px(det) >= 0.0 {
                "above"
            } else {
                "below"
            },
        ),
        Perspective::ThreePoint => write!(
            text,
            "pitch {:.2} deg {}, roll {:.2} deg.",
            cal.pitch_rad.to_degrees().abs(),
            if cal.pitch_rad >= 0.0 { "down" } else { "up" },
            cal.roll_rad.to_degrees()
        ),
    };
    let mut assigned = 0;
    let mut parts = Vec::new();
    for (role, &vp) in scene.roles.iter().enumerate() {
        let n = det.vanishing_points[vp].segments.len();
        assigned += n;
        let written = if role == 2 && scene.perspective == Perspective::TwoPoint {
            "not written: two-point perspective".to_owned()
        } else {
            format!("{} written as lines", scene.lines_written[role])
        };
        let point = if role == 2 && scene.perspective == Perspective::TwoPoint {
            point_text(det.vanishing_points[vp].point_px)
        } else {
            point_text(scene.points_px[role])
        };
        let colour = if args.overlay.is_some() {
            format!("{} in the overlay, ", VP_COLOUR_NAMES[role])
        } else {
            String::new()
        };
        // The edges alone, not held orthogonal to the other directions: far from the frame's
        // point, the room is not quite Manhattan there, or the focal length is off.
        let alone = det.vanishing_points[vp]
            .own_point
            .map(|o| {
                format!(
                    "; alone they meet {:.2} deg from the frame's",
                    o.from_frame_deg
                )
            })
            .unwrap_or_default();
        let within = scene.covariances[role]
            .map(|c| {
                format!(
                    " +-{:.2} deg at 95 % ({} independent edges{alone})",
                    c.major_sd_deg() * CHI2_2DOF_95.sqrt(),
                    c.edges
                )
            })
            .unwrap_or_default();
        parts.push(format!(
            "{} {point}{within} from {n} segments ({colour}{written})",
            VP_NAMES[role]
        ));
    }
    let _ = write!(
        text,
        " Vanishing points: {}; {} segments in all, {} unassigned.",
        parts.join(", "),
        det.segments.len(),
        det.segments.len().saturating_sub(assigned)
    );
    if let Some(lens) = &det.lens {
        let _ = if lens.k_sd > 0.0 && lens.k() != 0.0 {
            write!(
                text,
                " Lens distortion (division model) k = {:.4} +- {:.4} (95 %), estimated from the edges' bowing; the clicks and segments are undistorted by it before the fit.",
                lens.k(),
                Z_95 * lens.k_sd,
            )
        } else if lens.k_sd > 0.0 {
            write!(
                text,
                " Lens distortion (division model): the edges give k = {:.4} +- {:.4} (95 %){}, not clearly a lens (99 %), so the photo is taken as a pinhole's (k = 0, its sd kept for the error bars).",
                lens.estimated_k,
                Z_95 * lens.k_sd,
                if lens.segments_k_sd.is_none() {
                    " (they do not fix it: the prior of real lenses alone)"
                } else {
                    ""
                }
            )
        } else {
            write!(
                text,
                " Lens distortion (division model) k = {} as given.",
                lens.k()
            )
        };
    }
    if let Some(c) = scene.camera_estimate() {
        let _ = write!(
            text,
            " Before any click the scene gives focal {:.1} +- {:.1} px, pitch {:.2} +- {:.2} deg, roll {:.2} +- {:.2} deg, the horizon within +-{:.1} px (95 %){}.",
            c.focal_px,
            Z_95 * c.focal_sd_px,
            c.pitch_deg,
            Z_95 * c.pitch_sd_deg,
            c.roll_deg,
            Z_95 * c.roll_sd_deg,
            Z_95 * c.horizon_sd_px,
            scene.principal_point_px.1.map_or_else(String::new, |sd| format!(
                "; the principal point is written as a prior, the image centre +- {sd:.1} px (1 sd), which vpmap build refines"
            ))
        );
    }
    if scene.adjusted_deg >= 0.01 {
        let _ = write!(
            text,
            " The directions were turned by up to {:.2} deg to make them exactly orthogonal for the scene file.",
            scene.adjusted_deg,
        );
    }
    let _ = write!(
        text,
        " Detection took {:.0} ms (longer side scaled to at most {} px). Wrote {}{}; add the objects and the floor (docs/scene-format.md), then run vpmap build {} --out out/ (vpmap is on the PATH after cargo install --path crates/vpmap-cli; from the repository, cargo run --release -- build works too).",
        elapsed.as_secs_f64() * 1e3,
        args.max_side,
        args.out.display(),
        args.overlay
            .as_ref()
            .map_or_else(String::new, |o| format!(" and {}", o.display())),
        args.out.display()
    );
    text
}

/// `text` broken into lines of at most `width` characters at spaces (longer words stay whole).
/// The chi-square quantile with 2 degrees of freedom at 95 %.
const CHI2_2DOF_95: f64 = 5.991_464_547_107_979;
/// The normal quantile at 97.5 % (a two-sided 95 % interval).
const Z_95: f64 = 1.959_963_984_540_054;

fn wrap(text: &str, width: usize) -> String {
    let mut out = String::new();
    let mut line_len = 0;
    for word in text.split_whitespace() {
        let len = word.chars().count();
        if line_len > 0 && line_len + 1 + len > width {
            out.push('\n');
            line_len = 0;
        } else if line_len > 0 {
            out.push(' ');
            line_len += 1;
        }
        out.push_str(word);
        line_len += len;
    }
    out
}

//! `vpmap synth`: a random synthetic scene and its truth; with `--photos N` (2 to 4) a room
//! photographed N times, written as a room file with its truth in the first photo's plan frame
//! ([`vpmap_metrology::synth::synthesize_room`]).

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use vpmap_metrology::synth::{
    Annotation, MAX_ROOM_PHOTOS, RoomSynthOptions, SynthOptions, VanishingPointForm, synthesize,
    synthesize_room,
};

use crate::output::write_file;
use vpmap_pipeline::num;

/// Largest `--noise`, pixels: beyond it the clicks say nothing of the scene, and far beyond
/// it (1e308) they overflow to infinities that JSON cannot hold.
const MAX_NOISE_PX: f64 = 100.0;

/// Arguments of `vpmap synth`.
#[derive(clap::Args)]
pub struct SynthArgs {
    /// Random seed.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Camera pitch, degrees down (0 gives two-point perspective).
    #[arg(long, default_value_t = 20.0, allow_hyphen_values = true)]
    pitch: f64,
    /// Camera roll, degrees.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    roll: f64,
    /// Camera height, metres.
    #[arg(long, default_value_t = 1.5, allow_negative_numbers = true)]
    height: f64,
    /// Focal length, pixels.
    #[arg(long, default_value_t = 1100.0, allow_negative_numbers = true)]
    focal_px: f64,
    /// Number of boxes (default 4; 6 in a room of several photos).
    #[arg(long)]
    boxes: Option<usize>,
    /// Number of pentagonal (chair-like) objects (default 1; a room of several photos holds
    /// boxes only).
    #[arg(long)]
    prisms: Option<usize>,
    /// Photos of the room, 1 to 8. One: the single-photo scene the other flags describe. More:
    /// a rectangular room (4-7 m a side) with --boxes boxes along its walls, photographed from
    /// near its corners looking in, each camera its own height (1.1-1.7 m), pitch (8-35 deg),
    /// roll (up to 4 deg) and focal length (700-1300 px), drawn from --seed (--pitch, --roll,
    /// --height, --focal-px and --annotation apply to one photo only); written as a room file,
    /// the truth in the first photo's plan frame. Only the first photo carries the scale.
    #[arg(long, default_value_t = 1)]
    photos: usize,
    /// With --photos 2 or more: give every photo its camera height as scale, not only the first.
    #[arg(long)]
    scale_every_photo: bool,
    /// Gaussian noise on every annotated point, pixels (0 to 100).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    noise: f64,
    /// Give vanishing points as the clicked box edges instead of points.
    #[arg(long)]
    lines: bool,
    /// Leave out the scale (lengths then come out in camera heights).
    #[arg(long)]
    no_scale: bool,
    /// How the boxes are annotated: `thesis` (base near/right/left, top near/left), `face-on`
    /// (boxes seen nearly face-on, named in the face view), `hidden-base` (base near and the
    /// four top corners) or `own-yaw` (every second box turned by its own angle).
    #[arg(long, default_value = "thesis", value_parser = parse_annotation)]
    annotation: Annotation,
    /// Scene file to write.
    #[arg(long, short)]
    out: PathBuf,
    /// Truth file to write (default: beside the scene, `.truth.json`).
    #[arg(long)]
    truth: Option<PathBuf>,
}

fn parse_annotation(s: &str) -> Result<Annotation, String> {
    match s {
        "thesis" => Ok(Annotation::Thesis),
        "face-on" => Ok(Annotation::FaceOn),
        "hidden-base" => Ok(Annotation::HiddenBase),
        "own-yaw" => Ok(Annotation::OwnYaw),
        other => Err(format!(
            "unknown annotation {other:?}; use thesis, face-on, hidden-base or own-yaw"
        )),
    }
}

pub fn run(args: &SynthArgs) -> Result<()> {
    for (name, v) in [
        ("--pitch", args.pitch),
        ("--roll", args.roll),
        ("--height", args.height),
        ("--focal-px", args.focal_px),
        ("--noise", args.noise),
    ] {
        if !v.is_finite() {
            bail!("{name} must be a finite number, got {v}");
        }
    }
    if !(-30.0..=60.0).contains(&args.pitch) {
        bail!(
            "--pitch {} is outside the supported range -30..=60 degrees",
            args.pitch
        );
    }
    if args.roll.abs() > 30.0 {
        bail!(
            "--roll {} is outside the supported range -30..=30 degrees",
            args.roll
        );
    }
    if args.height <= 0.0 || args.focal_px <= 0.0 || args.noise < 0.0 {
        bail!(
            "--height ({}) and --focal-px ({}) must be positive and --noise ({}) non-negative",
            num(args.height),
            num(args.focal_px),
            num(args.noise)
        );
    }
    if args.noise > MAX_NOISE_PX {
        bail!(
            "--noise {} is outside the supported range 0..={MAX_NOISE_PX} px (a click that far off is no annotation)",
            num(args.noise)
        );
    }
    if !(1..=MAX_ROOM_PHOTOS).contains(&args.photos) {
        bail!(
            "--photos {} must be from 1 to {MAX_ROOM_PHOTOS}",
            args.photos
        );
    }
    let (boxes, prisms) = (args.boxes.unwrap_or(4), args.prisms.unwrap_or(1));
    if boxes.saturating_add(prisms) > 100 {
        bail!(
            "--boxes ({boxes}) + --prisms ({prisms}) is more than 100 objects; at most 100 fit a synthetic room"
        );
    }
    if !(100.0..=20_000.0).contains(&args.focal_px) {
        bail!(
            "--focal-px {} is outside the supported range 100..=20000 px",
            num(args.focal_px)
        );
    }
    if !(0.05..=100.0).contains(&args.height) {
        bail!(
            "--height {} is outside the supported range 0.05..=100 m",
            num(args.height)
        );
    }
    if args.out.to_string_lossy().ends_with('/') || args.out.is_dir() {
        bail!(
            "--out {} is a folder; give a file name such as scene.json",
            args.out.display()
        );
    }
    if args.photos > 1 {
        return run_room(args);
    }
    if args.scale_every_photo {
        bail!("--scale-every-photo is for a room of several photos (--photos 2 or more)");
    }
    let (scene, truth) = synthesize(&SynthOptions {
        seed: args.seed,
        focal_px: args.focal_px,
        height_m: args.height,
        pitch_deg: args.pitch,
        roll_deg: args.roll,
        boxes,
        prisms,
        noise_px: args.noise,
        vanishing_points: if args.lines {
            VanishingPointForm::Lines
        } else {
            VanishingPointForm::Points
        },
        with_scale: !args.no_scale,
        annotation: args.annotation,
        ..SynthOptions::default()
    })?;
    write_pair(args, &scene.to_json_string(), &truth)
}

/// `vpmap synth --photos N` for N of 2 or more: a room file and its truth.
fn run_room(args: &SynthArgs) -> Result<()> {
    if args.prisms.is_some_and(|p| p > 0) {
        bail!("--prisms: a room of several photos holds boxes only");
    }
    if args.annotation != Annotation::Thesis {
        bail!("--annotation: a room of several photos is annotated in the thesis's corner view");
    }
    let (scene, truth) = synthesize_room(&RoomSynthOptions {
        seed: args.seed,
        photos: args.photos,
        boxes: args.boxes.unwrap_or(RoomSynthOptions::default().boxes),
        noise_px: args.noise,
        vanishing_points: if args.lines {
            VanishingPointForm::Lines
        } else {
            VanishingPointForm::Points
        },
        scale_every_photo: args.scale_every_photo,
        ..RoomSynthOptions::default()
    })?;
    write_pair(args, &scene.to_json_string(), &truth)
}

/// Write the scene (or room) file and its truth: both or neither.
fn write_pair(args: &SynthArgs, scene_json: &str, truth: &impl serde::Serialize) -> Result<()> {
    let truth_path = args.truth.clone().unwrap_or_else(|| {
        let stem = args.out.with_extension("");
        PathBuf::from(format!("{}.truth.json", stem.display()))
    });
    if same_file(&truth_path, &args.out) {
        bail!(
            "--truth {} is the scene file --out {}: the scene would overwrite its truth; give two paths",
            truth_path.display(),
            args.out.display()
        );
    }
    // Both paths checked before either is written (a FIFO, a device, a folder is refused).
    for path in [&truth_path, &args.out] {
        vpmap_files::check_output_path(path)?;
    }
    write_file(
        &truth_path,
        serde_json::to_string_pretty(truth).context("serialising the truth")?,
    )?;
    if let Err(e) = write_file(&args.out, scene_json.to_owned()) {
        // Both files or neither.
        let _ = std::fs::remove_file(&truth_path);
        return Err(e);
    }
    println!("wrote {} and {}", args.out.display(), truth_path.display());
    Ok(())
}

/// Whether two output paths name the same file: the same folder (after resolving links and
/// `..`) and the same name, or one existing file reached through symbolic links.
fn same_file(a: &Path, b: &Path) -> bool {
    let resolved = |p: &Path| {
        let dir = match p.parent() {
            Some(d) if !d.as_os_str().is_empty() => d,
            _ => Path::new("."),
        };
        std::fs::canonicalize(dir)
            .ok()
            .zip(p.file_name())
            .map(|(d, n)| d.join(n))
    };
    if let (Ok(a), Ok(b)) = (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        return a == b;
    }
    match (resolved(a), resolved(b)) {
        (Some(a), Some(b)) => a == b,
        _ => a == b,
    }
}

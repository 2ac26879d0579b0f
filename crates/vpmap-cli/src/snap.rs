//! `vpmap snap PHOTO SCENE -o SCENE2`: every click of a scene (objects and floor) snapped to
//! the photo's corner it means ([`vpmap_vision::snap`]), written with each snapped point's
//! covariance in `click_covariances_px2` (a click that stayed: `--click-sigma` squared), every
//! other field kept as it was; each move printed.
//!
//! A room file takes one photo per room photo, in the room's order (`vpmap snap P1 P2 P3
//! ROOM -o ROOM2`): each photo's clicks are snapped on its own photo and its covariances
//! written inside that photo (`photos[k].click_covariances_px2`). Every photo's size is read
//! from its header and compared with the scene's before any photo is decoded.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, anyhow, bail};
use vpmap_vision::VisionError;
use vpmap_vision::photo::{PhotoLimits, decode_photo, photo_dimensions};
use vpmap_vision::snap::scene::{SnappedClick, snap_scene, write_snapped};
use vpmap_vision::snap::{SnapImage, SnapOptions, SnapOutcome};

use crate::output::write_file;

/// Arguments of `vpmap snap`.
#[derive(clap::Args)]
pub struct SnapArgs {
    /// The photo the scene was clicked on (JPEG or PNG); for a room file, each of its photos
    /// in the room's order.
    #[arg(required = true, num_args = 1..)]
    pub photos: Vec<PathBuf>,
    /// The scene or room file (JSON; see docs/scene-format.md).
    #[arg(required = true)]
    pub scene: PathBuf,
    /// The scene file to write, with the snapped points and their covariances.
    #[arg(long, short)]
    pub out: PathBuf,
    /// How far off the clicks are, pixels (1 sigma): the search radius is 2.45 times it, 3 to
    /// 16 px, and a click that stays is written with this sigma's covariance.
    #[arg(long, default_value_t = 2.0)]
    pub click_sigma: f64,
    /// The search radius, pixels: the farthest a click moves (overrides --click-sigma's).
    #[arg(long)]
    pub radius: Option<f64>,
}

/// Run `vpmap snap`.
pub fn run(args: &SnapArgs) -> Result<()> {
    if !(args.click_sigma.is_finite() && args.click_sigma > 0.0 && args.click_sigma <= 10.0) {
        bail!(
            "--click-sigma is {}; it must lie in (0, 10] pixels",
            args.click_sigma
        );
    }
    let mut opts = SnapOptions::for_click_sigma(args.click_sigma);
    if let Some(r) = args.radius {
        if !(r.is_finite() && (0.5..=64.0).contains(&r)) {
            bail!("--radius is {r}; it must lie in 0.5..=64 pixels");
        }
        opts.search_radius_px = r;
    }
    vpmap_files::check_output_path(&args.out)?;
    let text = vpmap_files::read_text(&args.scene, vpmap_files::Format::Scene)?;
    let parsed = vpmap_pipeline::scene::parse_scene(&text)
        .map_err(|e| anyhow!("{}: {e}", args.scene.display()))?;
    let scene = &parsed.scene;
    let mut value: serde_json::Value =
        serde_json::from_str(&text).with_context(|| format!("reading {}", args.scene.display()))?;
    let room = value.get("photos").is_some();
    let count = scene.photo_count();
    if args.photos.len() != count {
        if room {
            bail!(
                "{} is a room of {count} photos but {} photo file{} given; give one photo per room photo, in the room's order, before the room file",
                args.scene.display(),
                args.photos.len(),
                if args.photos.len() == 1 {
                    " was"
                } else {
                    "s were"
                }
            );
        }
        bail!(
            "{} is the scene of one photo but {} photo files were given",
            args.scene.display(),
            args.photos.len()
        );
    }
    // Every photo's header size first: a mismatch is refused before any photo is decoded.
    // The bytes are read again for decoding, so that a room's photos are never all held at
    // once (16 photos of up to 64 MB).
    for (k, (path, photo_scene)) in args.photos.iter().zip(scene.photos()).enumerate() {
        let bytes = vpmap_files::read_bytes(path, vpmap_files::Format::Photo)?;
        let (width, height) =
            photo_dimensions(&bytes).map_err(|e| anyhow!("{}: {e}", path.display()))?;
        if (width, height) != (photo_scene.image.width, photo_scene.image.height) {
            let mismatch = VisionError::ImageSizeMismatch {
                scene_width: photo_scene.image.width,
                scene_height: photo_scene.image.height,
                photo_width: width,
                photo_height: height,
            };
            bail!(
                "snapping {}{} on {}: {mismatch}",
                args.scene.display(),
                photo_label(room, k),
                path.display()
            );
        }
    }
    let mut printed = String::new();
    let mut all: Vec<SnappedClick> = Vec::new();
    for (k, (path, photo_scene)) in args.photos.iter().zip(scene.photos()).enumerate() {
        let bytes = vpmap_files::read_bytes(path, vpmap_files::Format::Photo)?;
        let photo = decode_photo(&bytes, &PhotoLimits::default())
            .map_err(|e| anyhow!("{}: {e}", path.display()))?;
        drop(bytes);
        let image = SnapImage::new(&photo.image);
        drop(photo);
        let snapped = snap_scene(&image, photo_scene, &opts).map_err(|e| {
            anyhow!(
                "snapping {}{} on {}: {e}",
                args.scene.display(),
                photo_label(room, k),
                path.display()
            )
        })?;
        let target = if room {
            value
                .get_mut("photos")
                .and_then(|p| p.get_mut(k))
                .ok_or_else(|| anyhow!("{}: the room has no photos[{k}]", args.scene.display()))?
        } else {
            &mut value
        };
        write_snapped(target, &snapped, Some(args.click_sigma))
            .map_err(|e| anyhow!("{}{}: {e}", args.scene.display(), photo_label(room, k)))?;
        if room {
            let _ = writeln!(printed, "photo {} ({}):", k + 1, path.display());
        }
        printed.push_str(&clicks_summary(&snapped));
        all.extend(snapped);
    }
    let mut json = serde_json::to_string_pretty(&value)?;
    json.push('\n');
    write_file(&args.out, json).with_context(|| format!("writing {}", args.out.display()))?;
    print!(
        "{printed}{}",
        totals(&all, opts.search_radius_px, &args.out)
    );
    Ok(())
}

/// `" photos[k] (photo k+1)"` for a room's photo, empty for a single-photo scene.
fn photo_label(room: bool, k: usize) -> String {
    if room {
        format!(" photos[{k}] (photo {})", k + 1)
    } else {
        String::new()
    }
}

/// One line per click.
fn clicks_summary(snapped: &[SnappedClick]) -> String {
    let mut s = String::new();
    let width = snapped
        .iter()
        .map(|c| c.place.field().len())
        .max()
        .unwrap_or(0);
    for c in snapped {
        let p = &c.snap;
        let field = c.place.field();
        let _ = match p.outcome {
            SnapOutcome::Snapped => {
                let sd = p
                    .covariance_px2
                    .map_or(f64::NAN, |c| c[0][0].max(c[1][1]).sqrt());
                writeln!(
                    s,
                    "{field:<width$}  ({:8.2}, {:8.2}) -> ({:8.2}, {:8.2})  moved {:5.2} px  +-{sd:.2} px",
                    p.click_px[0],
                    p.click_px[1],
                    p.point_px[0],
                    p.point_px[1],
                    p.moved_px()
                )
            }
            SnapOutcome::Kept(why) => writeln!(
                s,
                "{field:<width$}  ({:8.2}, {:8.2})    kept: {why}",
                p.click_px[0], p.click_px[1]
            ),
        };
    }
    s
}

/// The totals over every photo's clicks.
fn totals(snapped: &[SnappedClick], radius_px: f64, out: &Path) -> String {
    let mut s = String::new();
    let moved: Vec<f64> = snapped
        .iter()
        .filter(|c| c.snap.snapped())
        .map(|c| c.snap.moved_px())
        .collect();
    let largest = moved.iter().copied().fold(0.0, f64::max);
    let _ = writeln!(
        s,
        "snapped {} of {} clicks (largest move {largest:.2} px, search radius {radius_px:.1} px); wrote {}",
        moved.len(),
        snapped.len(),
        out.display()
    );
    s
}

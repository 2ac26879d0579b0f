//! `vpmap snap PHOTO SCENE -o SCENE2`: every click of a scene (objects and floor) snapped to
//! the photo's corner it means ([`vpmap_vision::snap`]), written with each snapped point's
//! covariance in `click_covariances_px2`, every other field kept as it was; each move printed.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, anyhow, bail};
use vpmap_vision::snap::scene::{SnappedClick, snap_scene, write_snapped};
use vpmap_vision::snap::{SnapImage, SnapOptions, SnapOutcome};

use crate::detect::read_photo;
use crate::output::write_file;

/// Arguments of `vpmap snap`.
#[derive(clap::Args)]
pub struct SnapArgs {
    /// The photo the scene was clicked on (JPEG or PNG).
    pub photo: PathBuf,
    /// The scene file (JSON; see docs/scene-format.md).
    pub scene: PathBuf,
    /// The scene file to write, with the snapped points and their covariances.
    #[arg(long, short)]
    pub out: PathBuf,
    /// How far off the clicks may be, pixels (1 sigma): the search radius is 3.5 times it,
    /// 6 to 16 px.
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
    let photo = read_photo(&args.photo)?;
    let text = vpmap_files::read_text(&args.scene, vpmap_files::Format::Scene)?;
    let parsed = vpmap_pipeline::scene::parse_scene(&text)
        .map_err(|e| anyhow!("{}: {e}", args.scene.display()))?;
    let mut value: serde_json::Value =
        serde_json::from_str(&text).with_context(|| format!("reading {}", args.scene.display()))?;
    let image = SnapImage::new(&photo.image);
    let snapped = snap_scene(&image, &parsed.scene, &opts).map_err(|e| {
        anyhow!(
            "snapping {} on {}: {e}",
            args.scene.display(),
            args.photo.display()
        )
    })?;
    write_snapped(&mut value, &snapped).map_err(|e| anyhow!("{}: {e}", args.scene.display()))?;
    let mut json = serde_json::to_string_pretty(&value)?;
    json.push('\n');
    write_file(&args.out, json).with_context(|| format!("writing {}", args.out.display()))?;
    print!("{}", summary(&snapped, opts.search_radius_px, &args.out));
    Ok(())
}

/// One line per click, then the totals.
fn summary(snapped: &[SnappedClick], radius_px: f64, out: &Path) -> String {
    use std::fmt::Write as _;
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
    let moved: Vec<f64> = snapped
        .iter()
        .filter(|c| c.snap.snapped())
        .map(|c| c.snap.moved_px())
        .collect();
    let largest = moved.iter().copied().fold(0.0, f64::max);
    let _ = writeln!(
        s,
        "snapped {} of {} clicks (largest move {largest:.2} px, search radius {radius_px} px); wrote {}",
        moved.len(),
        snapped.len(),
        out.display()
    );
    s
}

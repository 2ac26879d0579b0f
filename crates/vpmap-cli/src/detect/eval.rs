//! `vpmap eval-detect DIR`: vanishing-point detection measured on labelled photos. The
//! measurement and its reports are [`vpmap_eval::detection`]; this is its flags, progress bar
//! and printing.

use std::path::PathBuf;

use anyhow::{Result, bail};
use vpmap_eval::detection::report::{Context, label_of};
use vpmap_eval::detection::{DetectionOptions, Intrinsics, evaluate, find_pairs};
use vpmap_vision::DetectOptions;
use vpmap_vision::photo::PhotoLimits;

use super::options::{check_max_side, check_two_point_tolerance, default_options};

/// Arguments of `vpmap eval-detect`.
#[derive(clap::Args)]
pub struct EvalDetectArgs {
    /// Folder of labelled photos: `<name>.jpg` + `<name>.json` pairs in the York Urban format
    /// (e.g. ../shared/data/yud-train).
    pub dir: PathBuf,
    /// Also write `eval-detect.json` (per photo and summary) and `summary.md` into this folder.
    #[arg(long, short)]
    pub out: Option<PathBuf>,
    /// Evaluate only the first N photos (in name order).
    #[arg(long)]
    pub limit: Option<usize>,
    /// The detector's internal downscale: longer side at most this, pixels.
    #[arg(long, default_value_t = default_options().max_side_px)]
    pub max_side: u32,
    /// The detector's `--two-point-tolerance`, degrees (as `vpmap detect`).
    #[arg(long, default_value_t = default_options().two_point_tolerance_deg, allow_negative_numbers = true)]
    pub two_point_tolerance: f64,
    /// Also write the summary into the `detect` section of this Markdown file (e.g.
    /// docs/results.md), with the command line, date and machine.
    #[arg(long)]
    pub publish: Option<PathBuf>,
    /// In the run with the intrinsics estimated, take each photo's EXIF focal length (its 35 mm
    /// equivalent) as a prior, as `vpmap detect` does.
    #[arg(long)]
    pub exif: bool,
    /// Lens distortion, as `vpmap detect --lens`: `estimate` (default), `none` or a known k.
    #[arg(long, default_value = "estimate", allow_hyphen_values = true)]
    pub lens: String,
}

/// `vpmap eval-detect` (photos read with the limits of `vpmap detect`, the vision crate's
/// defaults).
pub fn run_eval_detect(args: &EvalDetectArgs) -> Result<()> {
    // Time detection on one core: the segment detector would otherwise spread over every
    // core through rayon's global pool. (Fails only if the pool already exists.)
    let _ = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build_global();
    check_max_side(args.max_side)?;
    check_two_point_tolerance(args.two_point_tolerance)?;
    if args.limit == Some(0) {
        bail!("--limit must be at least 1");
    }
    if let Some(out) = &args.out
        && out.exists()
        && !out.is_dir()
    {
        bail!("--out {} is not a folder", out.display());
    }
    let mut pairs = find_pairs(&args.dir)?;
    let available = pairs.len();
    if let Some(n) = args.limit {
        pairs.truncate(n);
    }
    let opts = DetectionOptions {
        detect: DetectOptions {
            max_side_px: args.max_side,
            two_point_tolerance_deg: args.two_point_tolerance,
            lens: super::options::parse_lens(&args.lens)?,
            ..default_options()
        },
        photo_limits: PhotoLimits::default(),
        exif: args.exif,
    };
    let bar = crate::progress::Bar::new("{elapsed_precise} [{bar}] {pos}/{len} photos {msg}", "30");
    let results = evaluate(&pairs, &opts, &bar)?;
    let context = Context {
        dir: args.dir.display().to_string(),
        available,
        max_side: args.max_side,
        exif: args.exif,
    };
    let report = vpmap_eval::detection::report(context, &results)?;
    println!("{}", report.table());
    for r in &results {
        for (which, run) in Intrinsics::BOTH.iter().zip(&r.runs) {
            if let Err(e) = &run.outcome {
                eprintln!("note: {} ({}): {e}", r.name, label_of(*which));
            }
        }
    }
    if let Some(out) = &args.out {
        let written = report.files.write_all(out)?;
        let names: Vec<String> = written
            .iter()
            .filter_map(|p| p.file_name().map(|n| n.to_string_lossy().into_owned()))
            .collect();
        println!("wrote {} in {}", names.join(", "), out.display());
    }
    if let Some(path) = &args.publish {
        let section = report.published(&results, &crate::output::command_line());
        vpmap_eval::publish::replace_section(path, "detect", &section)?;
        println!("published the summary into {}", path.display());
    }
    Ok(())
}

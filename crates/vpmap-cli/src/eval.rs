//! `vpmap eval`: map accuracy under annotation noise on synthetic scenes, as in the thesis's
//! section 6.1 (figures 6.8-6.13 for 2PP, 6.18-6.23 for 3PP); the measurement is
//! [`vpmap_eval::accuracy`], this is its flags, progress bar and printing.
//!
//! Every chosen experiment set-up (`--experiments`: the seventeen of
//! [`vpmap_metrology::eval::SETUPS`] by default, or the six views real photos show,
//! [`vpmap_metrology::eval::VIEW_SETUPS`]) draws `--trials` scenes; each
//! scene is built with every method at every noise level and compared with its truth
//! ([`vpmap_metrology::eval::run_trial`]). Scenes run in parallel (rayon); each scene's seed
//! depends only on (`--seed`, set-up, trial), so the files are the same for the same
//! arguments whatever the thread count. Writes into `--out`:
//!
//! | file | what |
//! |---|---|
//! | `summary.json` | rows `{method, sigma, metric, median, p5, p95, min, max, q1, q3, mean, count, perspective, experiment, scenes, refused}`: per perspective (`experiment` null) and per set-up |
//! | `summary.md` | the headline numbers at the true scale, the set-ups, refusals, the error bars' coverage, one table per metric beside the thesis's reported ranges, the camera's errors |
//! | `box_<metric>.svg`, `.png` | the thesis's box plots: one box per set-up and method, 2PP and 3PP side by side, at `--plot-sigma` |
//! | `objects.csv` | one row per object, noise level and method: every metric, and for the fit's objects whether the truth lies within the error bars |
//! | `failures.csv` | one row per scene a builder refused: the reason's category and message |
//!
//! `--vp-edges` chooses the edges the vanishing points are fitted to: `objects` (the boxes' own
//! edges through their noisy corners, the default) or `long` (per vanishing point
//! `--vp-edge-count` straight room lines of `--vp-edge-px` pixels spread over the image, each
//! the image of a 3D line in the vanishing direction in front of the true camera, their end
//! points clicked with the same noise; [`vpmap_metrology::eval::VpEdges`]).

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result, bail};
use vpmap_eval::accuracy::{Config, DEFAULT_TRIALS, section_name, select_setups, sigmas_from_text};
use vpmap_eval::navigate::{EVAL_SECTION, eval_published_section};
use vpmap_eval::output::check_writable_folder;
use vpmap_metrology::eval::{Setup, VpEdges};
use vpmap_metrology::reconstruct::Method;
use vpmap_metrology::synth::LongEdgeOptions;

use vpmap_pipeline::num;

/// Most trials per set-up accepted (objects.csv grows by about 300 kB per trial with three
/// methods).
const MAX_TRIALS: u64 = 10_000;

/// Shortest long vanishing-point edge accepted, pixels.
const MIN_VP_EDGE_PX: f64 = 20.0;

/// Longest long vanishing-point edge accepted, as a fraction of the smallest image height among
/// the chosen set-ups (so that vertical edges fit with room to place them).
const MAX_VP_EDGE_OF_HEIGHT: f64 = 0.75;

/// Most long edges per vanishing point accepted.
const MAX_VP_EDGE_COUNT: usize = 20;

/// Arguments of `vpmap eval`.
#[derive(clap::Args)]
pub struct EvalArgs {
    /// Output folder (created if missing).
    #[arg(long, short, default_value = "out/eval")]
    pub out: PathBuf,
    /// Random scenes per experiment set-up.
    #[arg(long, default_value_t = DEFAULT_TRIALS)]
    pub trials: u64,
    /// Random seed; the same seed and arguments give the same files.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Annotation noise levels: standard deviations in pixels, comma separated.
    #[arg(long, default_value = "0,0.5,1,2,4", allow_hyphen_values = true)]
    pub sigma: String,
    /// Reconstruction methods, comma separated: sideview (the thesis's), projective (the
    /// camera-matrix form), fit (the joint maximum-likelihood fit, with error bars).
    #[arg(long, default_value = "sideview,projective,fit")]
    pub methods: String,
    /// Experiment set-ups, comma separated: names (2pp-1 ... 2pp-9, 3pp-1 ... 3pp-8), 2pp, 3pp
    /// or all (these seventeen, the thesis's comparison); or views, the six set-ups of the
    /// views real photos show, apart from them (2pp-face, 3pp-face: boxes seen nearly face-on;
    /// 2pp-hidden, 3pp-hidden: hidden base corners; 2pp-yaw, 3pp-yaw: boxes with their own
    /// yaw), which the side-view and projective methods can read only in part.
    #[arg(long, default_value = "all")]
    pub experiments: String,
    /// Noise level of the box plots, pixels; one of --sigma (default: their median, the
    /// upper one of the middle two for an even count).
    #[arg(long, allow_hyphen_values = true)]
    pub plot_sigma: Option<f64>,
    /// Also write the report into the `eval` section of this Markdown file (e.g.
    /// docs/results.md), or its `eval-long-edges` section with `--vp-edges long` (`eval-views`
    /// and `eval-views-long-edges` with the views' set-ups); its image links point into --out.
    #[arg(long)]
    pub publish: Option<PathBuf>,
    /// Edges the vanishing points are fitted to (least squares), as a user would click them:
    /// `objects`, the boxes' own base and top edges through their noisy corners (short: median
    /// 87 px in 2PP, 164 px in 3PP); or `long`, per vanishing point --vp-edge-count straight
    /// room lines (floor-wall junctions, wall corners) of --vp-edge-px pixels. A long edge
    /// lies on the line from the vanishing point through a pixel drawn uniformly over the
    /// image, at a uniform place on it inside the image (2 % margin) and on the far side of
    /// the vanishing point: the image of a 3D line in the vanishing direction in front of the
    /// true camera. Its end points get the same Gaussian noise as every clicked point, and the
    /// objects' points get the same noise in both models.
    #[arg(long, default_value = "objects")]
    pub vp_edges: String,
    /// Length of each long edge, pixels (with --vp-edges long; default 600; from 20 to three
    /// quarters of the smallest image height among the chosen set-ups, 720 for all).
    #[arg(long, allow_hyphen_values = true)]
    pub vp_edge_px: Option<String>,
    /// Long edges per vanishing point (with --vp-edges long; default 3).
    #[arg(long, allow_hyphen_values = true)]
    pub vp_edge_count: Option<String>,
    /// What a map's error costs a robot instead (see docs/navigation.md): --trials synthetic
    /// rooms annotated at each --sigma, their maps built with each of --methods (and the
    /// fitted map grown by its error bars, see --grow-confidence), a robot driven across each
    /// (D* Lite and online MBPP) against the true room; writes navigate.md (excess travel and
    /// re-plans per noise level, map and planner); --publish writes the `eval-navigate`
    /// section.
    #[arg(long)]
    pub navigate: bool,
    /// With --navigate: the confidence the fitted map's obstacles are grown at by their error
    /// bars for the extra "fit, grown" map (0.5 to 0.9999; default 0.95; 0: no grown map).
    #[arg(long, allow_negative_numbers = true)]
    pub grow_confidence: Option<f64>,
    /// Rooms of several photos instead (see docs/results.md, "Rooms of several photos"):
    /// numbers of photos, comma separated, each 1 to 8 (e.g. 1,2,3,4). --trials rooms per
    /// number, each at every --sigma, mapped jointly and from its first photo alone; writes
    /// rooms.md and rooms.csv; --publish writes the `eval-rooms` section.
    #[arg(long)]
    pub photos: Option<String>,
    /// With --photos: boxes drawn per room (default 6; those no photo shows are left out).
    #[arg(long)]
    pub boxes: Option<usize>,
}

/// `vpmap eval --photos N`.
fn run_rooms(args: &EvalArgs, photos: &str) -> Result<()> {
    use vpmap_eval::room::{ROOM_SECTION, RoomEvalOptions, room_csv, room_report, run_rooms};
    if !(1..=MAX_TRIALS).contains(&args.trials) {
        bail!(
            "--trials must be a whole number from 1 to {MAX_TRIALS}, got {}",
            args.trials
        );
    }
    let mut counts = Vec::new();
    for part in photos.split(',') {
        match part.trim().parse::<usize>() {
            Ok(n)
                if (1..=vpmap_metrology::synth::MAX_ROOM_PHOTOS).contains(&n)
                    && !counts.contains(&n) =>
            {
                counts.push(n);
            }
            _ => bail!(
                "--photos {part:?} must be whole numbers of photos from 1 to {}, each once (e.g. 1,2,3,4)",
                vpmap_metrology::synth::MAX_ROOM_PHOTOS
            ),
        }
    }
    let boxes = args.boxes.unwrap_or(RoomEvalOptions::default().boxes);
    if !(2..=30).contains(&boxes) {
        bail!("--boxes {boxes} must be from 2 to 30");
    }
    let options = RoomEvalOptions {
        trials: args.trials,
        seed: args.seed,
        photos: counts,
        sigmas_px: parse_sigmas(&args.sigma)?,
        boxes,
    };
    check_writable_folder(&args.out)?;
    if let Some(path) = &args.publish {
        check_publish_target(path, ROOM_SECTION)?;
    }
    let started = Instant::now();
    let bar = crate::progress::Bar::new(
        "{elapsed_precise} [{bar}] {pos}/{len} rooms ({eta} left)",
        "40",
    );
    let trials = run_rooms(&options, &bar);
    let elapsed = started.elapsed();
    let report = room_report(&options, &trials);
    let command = crate::output::command_line();
    let mut files = vpmap_eval::output::OutputSet::default();
    files.add(
        "rooms.md",
        format!("{report}\nMeasured with `{command}`.\n"),
    );
    files.add("rooms.csv", room_csv(&trials));
    files.write_all(&args.out)?;
    if let Some(path) = &args.publish {
        let section = vpmap_eval::publish::published(
            "Rooms of several photos (`vpmap eval --photos`)",
            &report,
            elapsed,
            &command,
        );
        vpmap_eval::publish::replace_section(path, ROOM_SECTION, &section)?;
    }
    print!("{report}");
    println!("wrote rooms.md and rooms.csv in {}", args.out.display());
    if let Some(path) = &args.publish {
        println!("published the {ROOM_SECTION} section of {}", path.display());
    }
    Ok(())
}

/// The default growth confidence of `vpmap eval --navigate` (the fitted map is driven as
/// built and grown by its error bars at this confidence).
const DEFAULT_NAVIGATE_GROW_CONFIDENCE: f64 = 0.95;

/// `vpmap eval --navigate`.
fn run_navigate(args: &EvalArgs) -> Result<()> {
    if !(1..=MAX_TRIALS).contains(&args.trials) {
        bail!(
            "--trials must be a whole number from 1 to {MAX_TRIALS}, got {}",
            args.trials
        );
    }
    let grow_confidence = match args.grow_confidence {
        None => Some(DEFAULT_NAVIGATE_GROW_CONFIDENCE),
        Some(0.0) => None,
        Some(p) if (0.5..=0.9999).contains(&p) => Some(p),
        Some(p) => bail!(
            "--grow-confidence {} must be from 0.5 to 0.9999 (or 0: do not drive a grown map)",
            num(p)
        ),
    };
    let opts = vpmap_eval::navigate::NavEvalOptions {
        scenes: args.trials,
        noise_px: parse_sigmas(&args.sigma)?,
        methods: parse_methods(&args.methods)?,
        seed: args.seed,
        grow_confidence,
        ..vpmap_eval::navigate::NavEvalOptions::default()
    };
    check_writable_folder(&args.out)?;
    if let Some(path) = &args.publish {
        check_publish_target(path, EVAL_SECTION)?;
    }
    let started = std::time::Instant::now();
    let bar = crate::progress::Bar::new("{elapsed_precise} [{bar}] {pos}/{len} {msg}", "40");
    let (trials, skipped) = vpmap_eval::navigate::run_eval(&opts, &bar)?;
    let elapsed = started.elapsed();
    let table = vpmap_eval::navigate::eval_table(&trials, &opts, skipped);
    let command = crate::output::command_line();
    let md = format!("{table}\nMeasured with `{command}`.\n");
    let mut files = vpmap_eval::output::OutputSet::default();
    files.add("navigate.md", md.clone());
    files.write_all(&args.out)?;
    if let Some(path) = &args.publish {
        let section = eval_published_section(&table, &opts, elapsed, &command);
        vpmap_eval::publish::replace_section(path, EVAL_SECTION, &section)?;
    }
    print!("{md}");
    println!("wrote navigate.md in {}", args.out.display());
    if let Some(path) = &args.publish {
        println!("published the {EVAL_SECTION} section of {}", path.display());
    }
    Ok(())
}

/// `--sigma`: the noise levels ([`vpmap_eval::accuracy::sigmas_from_text`]).
fn parse_sigmas(text: &str) -> Result<Vec<f64>> {
    sigmas_from_text(text).map_err(|e| anyhow::anyhow!("--sigma {e}"))
}

fn parse_methods(text: &str) -> Result<Vec<Method>> {
    let mut methods = Vec::new();
    for part in text.split(',') {
        let m: Method = part
            .trim()
            .parse()
            .map_err(|e: String| anyhow::anyhow!("--methods: {e}"))?;
        if methods.contains(&m) {
            bail!("--methods names {m} twice");
        }
        methods.push(m);
    }
    Ok(methods)
}

/// `--experiments`: the set-ups it names ([`vpmap_eval::accuracy::select_setups`]).
fn parse_experiments(text: &str) -> Result<Vec<&'static Setup>> {
    select_setups(text).map_err(|e| anyhow::anyhow!("--experiments {e}"))
}

/// `--vp-edges` with its `--vp-edge-px` and `--vp-edge-count`, for the chosen set-ups.
fn parse_vp_edges(
    model: &str,
    length_px: Option<&str>,
    count: Option<&str>,
    setups: &[&Setup],
) -> Result<VpEdges> {
    match model.trim().to_ascii_lowercase().as_str() {
        "objects" => {
            if length_px.is_some() || count.is_some() {
                bail!("--vp-edge-px and --vp-edge-count apply only to --vp-edges long");
            }
            Ok(VpEdges::Objects)
        }
        "long" => {
            let mut long = LongEdgeOptions::default();
            let smallest = setups
                .iter()
                .map(|s| s.image.height)
                .min()
                .unwrap_or(u32::MAX);
            let max_px = (MAX_VP_EDGE_OF_HEIGHT * f64::from(smallest)).floor();
            if let Some(text) = length_px {
                let v = text.trim().parse::<f64>().unwrap_or(f64::NAN);
                if !(v.is_finite() && (MIN_VP_EDGE_PX..=max_px).contains(&v)) {
                    bail!(
                        "--vp-edge-px {text:?} must be a length in pixels from {MIN_VP_EDGE_PX} to {max_px} (three quarters of the smallest image height, {smallest} px, among the chosen set-ups)"
                    );
                }
                long.length_px = v;
            } else if long.length_px > max_px {
                long.length_px = max_px;
            }
            if let Some(text) = count {
                match text.trim().parse::<usize>() {
                    Ok(n) if (2..=MAX_VP_EDGE_COUNT).contains(&n) => long.per_vanishing_point = n,
                    _ => bail!(
                        "--vp-edge-count {text:?} must be a whole number of edges per vanishing point from 2 to {MAX_VP_EDGE_COUNT}"
                    ),
                }
            }
            Ok(VpEdges::Long(long))
        }
        other => bail!("--vp-edges {other:?} is not an edge model; use objects or long"),
    }
}

/// Check the arguments before any work.
fn check_args(args: &EvalArgs) -> Result<Config> {
    if !(1..=MAX_TRIALS).contains(&args.trials) {
        bail!(
            "--trials must be a whole number from 1 to {MAX_TRIALS}, got {}",
            args.trials
        );
    }
    if let Some(p) = args.grow_confidence {
        bail!(
            "--grow-confidence {} is for --navigate (the accuracy evaluation measures the maps as built)",
            num(p)
        );
    }
    let sigmas = parse_sigmas(&args.sigma)?;
    let methods = parse_methods(&args.methods)?;
    let setups = parse_experiments(&args.experiments)?;
    let vp_edges = parse_vp_edges(
        &args.vp_edges,
        args.vp_edge_px.as_deref(),
        args.vp_edge_count.as_deref(),
        &setups,
    )?;
    let plot_sigma = match args.plot_sigma {
        Some(p) => {
            if !sigmas.iter().any(|s| (s - p).abs() <= 1e-12) {
                bail!(
                    "--plot-sigma {} is not one of the noise levels --sigma {}",
                    num(p),
                    args.sigma
                );
            }
            p
        }
        None => sigmas.get(sigmas.len() / 2).copied().unwrap_or(0.0),
    };
    check_writable_folder(&args.out)?;
    if let Some(path) = &args.publish {
        check_publish_target(path, section_name(&vp_edges, &setups))?;
    }
    Ok(Config {
        trials: args.trials,
        seed: args.seed,
        sigmas,
        methods,
        setups,
        plot_sigma,
        vp_edges,
    })
}

/// The publish target must be a Markdown file whose `name` section markers, if any, are in
/// order, in a folder that can be written.
fn check_publish_target(path: &Path, name: &str) -> Result<()> {
    if path.is_dir() {
        bail!(
            "--publish {} is a folder; give a Markdown file",
            path.display()
        );
    }
    vpmap_eval::publish::check_section(path, name).map_err(|e| match e {
        // "--publish docs/results.md has a broken `eval` section: ..."
        vpmap_eval::EvalError::Invalid(message) => anyhow::anyhow!("--publish {message}"),
        other => other.into(),
    })?;
    let parent = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    check_writable_folder(parent).with_context(|| format!("cannot publish into {}", path.display()))
}

/// `vpmap eval`.
pub fn run(args: &EvalArgs) -> Result<()> {
    if let Some(photos) = &args.photos {
        if args.navigate {
            bail!("--photos and --navigate are separate evaluations; give one");
        }
        return run_rooms(args, photos);
    }
    if args.boxes.is_some() {
        bail!("--boxes is for --photos (rooms of several photos)");
    }
    if args.navigate {
        return run_navigate(args);
    }
    let config = check_args(args)?;
    let started = Instant::now();
    let bar = crate::progress::Bar::new(
        "{elapsed_precise} [{bar}] {pos}/{len} scenes ({eta} left)",
        "40",
    );
    let results = vpmap_eval::accuracy::run_trials(&config, &bar);
    let report = vpmap_eval::accuracy::report(&config, &results)?;
    if report.svg_only {
        eprintln!(
            "warning: no system fonts, so the box plots are written as SVG only (install fonts, e.g. DejaVu Sans, for PNG)"
        );
    }
    let written = report.files.write_all(&args.out)?;
    let elapsed = started.elapsed();
    if let Some(path) = &args.publish {
        let section = report.published(
            &config,
            path,
            &args.out,
            &crate::output::command_line(),
            elapsed,
        );
        vpmap_eval::publish::replace_section(
            path,
            section_name(&config.vp_edges, &config.setups),
            &section,
        )?;
    }
    print!("{}", report.headline(&config));
    println!(
        "{} scenes x {} noise levels x {} methods in {:.1} s",
        config.setups.len() as u64 * config.trials,
        config.sigmas.len(),
        config.methods.len(),
        elapsed.as_secs_f64()
    );
    let names: Vec<String> = written
        .iter()
        .filter_map(|p| p.file_name().map(|n| n.to_string_lossy().into_owned()))
        .collect();
    println!("wrote {} in {}", names.join(", "), args.out.display());
    if let Some(path) = &args.publish {
        println!(
            "published the {} section of {}",
            section_name(&config.vp_edges, &config.setups),
            path.display()
        );
    }
    Ok(())
}
#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arguments_are_parsed_strictly() {
        assert_eq!(parse_sigmas(" 2, 0,1").unwrap(), vec![0.0, 1.0, 2.0]);
        assert!(parse_sigmas("1,1").is_err());
        assert!(parse_sigmas("-1").is_err());
        assert!(parse_sigmas("inf").is_err());
        assert!(parse_sigmas("").is_err());
        assert_eq!(
            parse_methods("projective").unwrap(),
            vec![Method::Projective]
        );
        assert!(parse_methods("sideview,bogus").is_err());
        assert!(parse_experiments("4pp").is_err_and(|e| {
            e.to_string()
                .starts_with("--experiments \"4pp\" is not a set-up")
        }));
        let all = parse_experiments("all").unwrap();
        assert_eq!(
            parse_vp_edges("objects", None, None, &all).unwrap(),
            VpEdges::Objects
        );
        let VpEdges::Long(long) = parse_vp_edges(" Long", Some("400"), Some("5"), &all).unwrap()
        else {
            panic!("long")
        };
        assert_eq!((long.length_px, long.per_vanishing_point), (400.0, 5));
        // 3/4 of the 960-px-high small images; 900 px fits the 1200-px-high ones only.
        assert!(parse_vp_edges("long", Some("721"), None, &all).is_err());
        let big: Vec<&Setup> = parse_experiments("2pp-1").unwrap();
        assert!(parse_vp_edges("long", Some("900"), None, &big).is_ok());
        assert!(parse_vp_edges("long", Some("19"), None, &all).is_err());
        assert!(parse_vp_edges("long", None, Some("1"), &all).is_err());
        assert!(parse_vp_edges("objects", Some("400"), None, &all).is_err());
        assert!(parse_vp_edges("edges", None, None, &all).is_err());
    }
}

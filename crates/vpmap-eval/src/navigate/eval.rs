//! What a map's error costs a robot (`vpmap eval --navigate`): synthetic rooms annotated
//! with noise, their maps built with each method, and a robot driven across each map
//! against the true room.
//!
//! Per scene: the truth is rasterised into the believed map's grid ([`truth_grid`](vpmap_raster::truth_grid)); start
//! and goal are two free cells of the true room at least 2 m apart (drawn once per scene on
//! the noise-free truth, as map points, so every method and noise level drives between the
//! same points); a trial whose start or goal falls on an obstacle of the true grid in a
//! method's frame is skipped (counted). Excess travel is the driven length over the true
//! map's optimum, minus 1: over the octile optimum (what an 8-connected planner can reach at
//! best) and over the any-angle optimum (the shortest path of all).
//!
//! The fitted map is driven twice when [`NavEvalOptions::grow_confidence`] is set: as built,
//! and with each object grown by its error bars at that confidence
//! ([`vpmap_pipeline::grown_by_uncertainty`], what `vpmap build --grow-confidence` draws), so
//! the table shows what the inflation costs or saves a robot.

use std::fmt::Write as _;

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use vpmap_metrology::map::{BuildOptions, build_map};
use vpmap_metrology::reconstruct::Method;
use vpmap_metrology::synth::{SynthOptions, Truth, add_noise, synthesize};
use vpmap_pipeline::grown_by_uncertainty;
use vpmap_plan::navigate::{NavigateOptions, OnlinePlanner, Outcome, navigate, truth_optimum};
use vpmap_plan::{Budget, Occupancy, OccupancyGrid};
use vpmap_raster::{RasterOptions, rasterize_map, truth_grid};

use crate::error::Result;
use crate::progress::Progress;

/// Options of [`run_eval`].
#[derive(Clone, Debug)]
pub struct NavEvalOptions {
    /// Scenes (seeds `seed..seed + scenes`).
    pub scenes: u64,
    /// Annotation noise levels, pixels (1 sigma per coordinate).
    pub noise_px: Vec<f64>,
    /// Reconstruction methods.
    pub methods: Vec<Method>,
    /// Online planners.
    pub planners: Vec<OnlinePlanner>,
    /// Grid resolution, metres.
    pub resolution_m: f64,
    /// Robot radius, metres.
    pub robot_radius_m: f64,
    /// Sensor range, metres.
    pub sensor_range_m: f64,
    /// First scene seed.
    pub seed: u64,
    /// Also drive the fitted map with its obstacles grown by their error bars at this
    /// confidence (0.5 to 0.9999); `None`: only the maps as built.
    pub grow_confidence: Option<f64>,
}

impl Default for NavEvalOptions {
    fn default() -> Self {
        Self {
            scenes: 10,
            noise_px: vec![0.0, 1.0, 2.0, 4.0],
            methods: vec![Method::Sideview, Method::Projective, Method::Fit],
            planners: vec![OnlinePlanner::DStarLite, OnlinePlanner::Mbpp],
            resolution_m: 0.05,
            robot_radius_m: 0.2,
            sensor_range_m: 1.5,
            seed: 1,
            grow_confidence: Some(0.95),
        }
    }
}

/// One drive.
#[derive(Clone, Debug)]
pub struct NavTrial {
    /// Scene seed.
    pub scene: u64,
    /// Annotation noise, pixels.
    pub noise_px: f64,
    /// Method.
    pub method: Method,
    /// The map's obstacles were grown by their error bars
    /// ([`NavEvalOptions::grow_confidence`]).
    pub grown: bool,
    /// Planner.
    pub planner: OnlinePlanner,
    /// How it ended.
    pub outcome: Outcome,
    /// Driven length, metres.
    pub length_m: f64,
    /// True octile optimum, metres.
    pub optimum_m: f64,
    /// True any-angle optimum, metres.
    pub optimum_any_angle_m: f64,
    /// Re-plans.
    pub replans: usize,
}

/// Two free map points of `truth` at least 2 m apart, or `None`.
fn endpoints(
    truth: &Truth,
    opts: &NavEvalOptions,
    rng: &mut ChaCha8Rng,
) -> Result<Option<([f64; 2], [f64; 2])>> {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in &truth.floor {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let r = opts.resolution_m;
    let cells = |k: usize| (((hi[k] - lo[k]) / r).ceil().max(1.0) as usize) + 2;
    let frame = OccupancyGrid::new(
        cells(0),
        cells(1),
        r,
        [lo[0] - r, lo[1] - r],
        Occupancy::Unknown,
    )?;
    let grid = truth_grid(truth, &frame, opts.robot_radius_m)?;
    let components = vpmap_plan::Components::label(&grid, false);
    let free: Vec<usize> = (0..grid.cells().len())
        .filter(|&i| components.labels().get(i).is_some_and(|&l| l > 0))
        .collect();
    for _ in 0..2000 {
        if free.is_empty() {
            break;
        }
        let a = components.cell_at(free[rng.random_range(0..free.len())]);
        let b = components.cell_at(free[rng.random_range(0..free.len())]);
        let (pa, pb) = (
            grid.world_from_cell(a.x, a.y),
            grid.world_from_cell(b.x, b.y),
        );
        if components.connected(a, b) && (pa[0] - pb[0]).hypot(pa[1] - pb[1]) >= 2.0 {
            return Ok(Some((pa, pb)));
        }
    }
    Ok(None)
}

/// The maps driven: each method's as built, and the fitted one grown by its error bars when
/// [`NavEvalOptions::grow_confidence`] is set.
fn map_variants(opts: &NavEvalOptions) -> Vec<(Method, bool)> {
    let mut variants: Vec<(Method, bool)> = opts.methods.iter().map(|&m| (m, false)).collect();
    if opts.grow_confidence.is_some() && opts.methods.contains(&Method::Fit) {
        variants.push((Method::Fit, true));
    }
    variants
}

/// The name of a map variant in the table: the method, and for a grown map the confidence.
fn variant_name(method: Method, grown: bool, opts: &NavEvalOptions) -> String {
    match (grown, opts.grow_confidence) {
        (true, Some(p)) => format!("{method}, grown ({} %)", p * 100.0),
        _ => method.to_string(),
    }
}

/// Drive every planner across every method's map at every noise level of every scene.
/// Returns the trials and the number skipped (start or goal blocked in a method's frame,
/// or a map that could not be built).
///
/// # Errors
/// A scene that cannot be synthesised, a planner error.
pub fn run_eval(opts: &NavEvalOptions, progress: &dyn Progress) -> Result<(Vec<NavTrial>, usize)> {
    let mut trials = Vec::new();
    let mut skipped = 0;
    if let Some(p) = opts.grow_confidence
        && !(0.5..=0.9999).contains(&p)
    {
        return Err(crate::error::EvalError::Invalid(format!(
            "the growth confidence is {p}; it must be from 0.5 to 0.9999"
        )));
    }
    let per_level = map_variants(opts).len() * opts.planners.len();
    progress.start(opts.scenes * opts.noise_px.len() as u64);
    for scene_seed in opts.seed..opts.seed + opts.scenes {
        let (scene, truth) = synthesize(&SynthOptions {
            seed: scene_seed,
            ..SynthOptions::default()
        })?;
        let mut rng = ChaCha8Rng::seed_from_u64(scene_seed ^ 0x6e61_7669);
        let Some((from, to)) = endpoints(&truth, opts, &mut rng)? else {
            skipped += opts.noise_px.len() * per_level;
            continue;
        };
        for (level, &sigma) in opts.noise_px.iter().enumerate() {
            progress.message(&format!("scene {scene_seed} noise {sigma} px"));
            let mut noisy = scene.clone();
            add_noise(
                &mut noisy,
                sigma,
                &mut ChaCha8Rng::seed_from_u64(scene_seed * 1000 + level as u64),
            );
            for (method, grown) in map_variants(opts) {
                let built = build_map(
                    &noisy,
                    &BuildOptions {
                        method,
                        ..BuildOptions::default()
                    },
                )
                .ok()
                .map(|map| match (grown, opts.grow_confidence) {
                    (true, Some(p)) => grown_by_uncertainty(&map, p),
                    _ => map,
                })
                .and_then(|map| {
                    rasterize_map(
                        &map,
                        &RasterOptions {
                            resolution_m: opts.resolution_m,
                            robot_radius_m: opts.robot_radius_m,
                            ..RasterOptions::default()
                        },
                    )
                    .ok()
                });
                let Some(belief) = built else {
                    skipped += opts.planners.len();
                    continue;
                };
                let true_grid = truth_grid(&truth, &belief, opts.robot_radius_m)?;
                let cell = |p: [f64; 2]| {
                    true_grid
                        .cell_from_world(p)
                        .filter(|c| true_grid.is_free(c.x, c.y))
                };
                let (Some(start), Some(goal)) = (cell(from), cell(to)) else {
                    skipped += opts.planners.len();
                    continue;
                };
                let optimum = truth_optimum(&true_grid, start, goal, &Budget::default())?;
                let (Some(optimum_cells), Some(any_angle_cells)) =
                    (optimum.octile_cells, optimum.any_angle_cells)
                else {
                    skipped += opts.planners.len();
                    continue;
                };
                for &planner in &opts.planners {
                    let nav = NavigateOptions {
                        planner,
                        sensor_range_cells: (opts.sensor_range_m / opts.resolution_m)
                            .clamp(1.0, 256.0),
                        ..NavigateOptions::default()
                    };
                    let run = navigate(&belief, &true_grid, start, goal, &nav)?;
                    trials.push(NavTrial {
                        scene: scene_seed,
                        noise_px: sigma,
                        method,
                        grown,
                        planner,
                        outcome: run.outcome,
                        length_m: run.length_cells * opts.resolution_m,
                        optimum_m: optimum_cells * opts.resolution_m,
                        optimum_any_angle_m: any_angle_cells * opts.resolution_m,
                        replans: run.events.len().saturating_sub(1),
                    });
                }
            }
            progress.step();
        }
    }
    progress.finish();
    Ok((trials, skipped))
}

/// The Markdown table: per noise level, map (method, grown or not) and planner, the trials,
/// how many reached the goal, the median excess travel over the true octile and any-angle
/// optima (reached trials) and the mean re-plans.
#[must_use]
pub fn eval_table(trials: &[NavTrial], opts: &NavEvalOptions, skipped: usize) -> String {
    let mut md = String::from(
        "| noise (px) | map | planner | trials | reached | median excess travel over the octile optimum | over the any-angle optimum | mean re-plans |\n|---|---|---|---|---|---|---|---|\n",
    );
    for &sigma in &opts.noise_px {
        for (method, grown) in map_variants(opts) {
            for &planner in &opts.planners {
                let v: Vec<&NavTrial> = trials
                    .iter()
                    .filter(|t| {
                        t.noise_px.to_bits() == sigma.to_bits()
                            && t.method == method
                            && t.grown == grown
                            && t.planner == planner
                    })
                    .collect();
                if v.is_empty() {
                    continue;
                }
                let reached: Vec<&&NavTrial> =
                    v.iter().filter(|t| t.outcome == Outcome::Reached).collect();
                let median = |optimum: fn(&NavTrial) -> f64| {
                    let mut excess: Vec<f64> = reached
                        .iter()
                        .map(|t| t.length_m / optimum(t) - 1.0)
                        .collect();
                    excess.sort_by(f64::total_cmp);
                    // `+ 0.0`: a median a rounding error below zero prints as 0.0, not -0.0.
                    excess.get(excess.len() / 2).map_or_else(
                        || "-".to_owned(),
                        |m| format!("{:.1} %", (m * 1000.0).round() / 10.0 + 0.0),
                    )
                };
                let octile = median(|t| t.optimum_m);
                let any_angle = median(|t| t.optimum_any_angle_m);
                let replans = v.iter().map(|t| t.replans as f64).sum::<f64>() / v.len() as f64;
                let _ = writeln!(
                    md,
                    "| {sigma} | {} | {} | {} | {} | {octile} | {any_angle} | {replans:.1} |",
                    variant_name(method, grown, opts),
                    planner.name(),
                    v.len(),
                    reached.len()
                );
            }
        }
    }
    let _ = writeln!(
        md,
        "\n{skipped} trials skipped (start or goal on an obstacle of the true grid in the method's frame, or no map)."
    );
    md
}

/// The section of a results file (`docs/results.md`) the evaluation publishes into.
pub const EVAL_SECTION: &str = "eval-navigate";

/// The evaluation's published section: where, when and how it was measured (`elapsed`,
/// `command`), what was driven (from `opts`), then its [`eval_table`].
#[must_use]
pub fn eval_published_section(
    table: &str,
    opts: &NavEvalOptions,
    elapsed: std::time::Duration,
    command: &str,
) -> String {
    crate::publish::published(
        "What a map's error costs a robot (`vpmap eval --navigate`)",
        &format!(
            "{} synthetic rooms, each annotated at every noise level; each method's map (and the fitted map grown by its error bars) driven from the same start to the same goal, sensing the true room within {} m; excess travel over the true room's optima (reached drives). How the drive works: [navigation.md](navigation.md).\n\n{table}",
            opts.scenes,
            vpmap_pipeline::num(opts.sensor_range_m)
        ),
        elapsed,
        command,
    )
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;

    /// These drives once stopped with "D* Lite could not follow its search": a cell on the
    /// path left inconsistent with a key tying the start's (the paper's loop stops at ties).
    #[test]
    fn regression_dstar_lite_stale_tie_cell_on_the_path() {
        let opts = NavEvalOptions {
            scenes: 2,
            noise_px: vec![0.0, 2.0],
            methods: vec![Method::Sideview, Method::Fit],
            planners: vec![OnlinePlanner::DStarLite],
            ..NavEvalOptions::default()
        };
        let (trials, skipped) = run_eval(&opts, &crate::Silent).unwrap();
        // Two scenes, two noise levels, three maps (sideview, fit, fit grown), one planner.
        assert_eq!(trials.len() + skipped, 12);
        assert!(trials.len() >= 6);
        assert!(trials.iter().all(|t| t.length_m > 0.0
            && t.optimum_m > 0.0
            && t.optimum_any_angle_m <= t.optimum_m + 1e-9));
        let table = eval_table(&trials, &opts, skipped);
        assert!(table.contains("| 0 | sideview | dstar-lite |"), "{table}");
        assert!(
            table.contains("| 2 | fit, grown (95 %) | dstar-lite |"),
            "{table}"
        );
    }

    /// The fitted map grown by its error bars is driven beside the built one, once per built
    /// drive; only when the fit is among the methods; a confidence out of range is refused.
    #[test]
    fn the_grown_fitted_map_is_driven_beside_the_built_one() {
        let opts = NavEvalOptions {
            scenes: 3,
            noise_px: vec![2.0],
            methods: vec![Method::Fit],
            planners: vec![OnlinePlanner::Astar],
            ..NavEvalOptions::default()
        };
        let (trials, _) = run_eval(&opts, &crate::Silent).unwrap();
        let grown: Vec<_> = trials.iter().filter(|t| t.grown).collect();
        let built: Vec<_> = trials.iter().filter(|t| !t.grown).collect();
        assert!(
            !grown.is_empty() && grown.len() == built.len(),
            "{trials:?}"
        );
        assert!(trials.iter().all(|t| t.method == Method::Fit));
        // Without the fit among the methods there is nothing to grow.
        let side = NavEvalOptions {
            methods: vec![Method::Sideview],
            ..opts.clone()
        };
        let (trials, _) = run_eval(&side, &crate::Silent).unwrap();
        assert!(trials.iter().all(|t| !t.grown));
        let bad = NavEvalOptions {
            grow_confidence: Some(1.0),
            ..opts
        };
        let e = run_eval(&bad, &crate::Silent).unwrap_err().to_string();
        assert!(e.contains("growth confidence is 1"), "{e}");
    }
}

//! Planner benchmark (`vpmap bench`): MBPP against A* PS and the other planners on benchmark maps, by runtime
//! and path length — the thesis's section 6.2 (figures 6.25 and 6.26), rerun.
//!
//! Maps: the Moving AI benchmark maps of the thesis's kinds of environment (free, home and
//! office, game, maze, random, city), with problems from their scenario files spread over
//! the buckets, and occupancy grids vpmap builds from room scenes, with random free-cell
//! pairs; or the `.map` and `.scen` files given in [`BenchOptions::inputs`]. Every map with more
//! than one connected component also gets unsolvable queries (the thesis's "blocked way").
//!
//! Measurement: queries run one after another on this thread, each planner fresh, one
//! warm-up run and then [`BenchOptions::repeat`] timed runs (median kept; a warm-up run over a second is
//! the query's only run); peak heap from a [`MemoryProbe`] (the binary's global allocator). Every path is checked by the
//! independent validator, every "found" against breadth-first connectivity, every length
//! against the exact optimum. The exact `optimal` planner (an interval search whose free
//! space is built once per map; each query here builds it afresh, like every planner's
//! fresh start, and [`MapResult::optimal_build_s`] reports the build alone) runs on every
//! map; it is only dropped from the first query slower than [`BenchOptions::optimal_limit_s`]
//! (its results on that map are then dropped: all or nothing per map).
//!
//! Outputs ([`Report::files`], written all or nothing): `results.csv` (one row per query and planner),
//! `summary.md` and `summary.json` (per category and per map), and the plots
//! `runtime.svg`/`.png` (figure 6.25), `length.svg`/`.png` (figure 6.26) and
//! `excess.svg`/`.png` (mean excess over the optimum).

pub mod maps;
pub mod measure;
pub mod plots;
pub mod report;
pub mod results;
pub mod summary;

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use vpmap_plan::planner::PlannerKind;
use vpmap_plan::{ExactPlanner, corner_cells};

use crate::error::{Result, ResultExt as _, bail};
use crate::output::OutputSet;
use crate::progress::Progress;
use crate::publish::{machine_description, relative_link};
use maps::BenchMap;
pub use measure::{Measured, MemoryProbe, NoMemoryProbe};
pub use results::{MapResult, Results};

/// What to run: the options of a benchmark.
#[derive(Clone, Debug)]
pub struct BenchOptions {
    /// Moving AI `.map` files (queries: random free-cell pairs in one component) or `.scen`
    /// files (queries from the file, across its buckets). Empty: the thesis's map categories
    /// from the Moving AI data ([`maps::movingai_dir`]) and maps built from synthetic rooms.
    pub inputs: Vec<PathBuf>,
    /// Planners to compare, in report order.
    pub planners: Vec<PlannerKind>,
    /// Solvable queries per map (spread over scenario buckets or path lengths).
    pub per_map: usize,
    /// Timed runs per query and planner, after one warm-up run; the median is reported.
    pub repeat: usize,
    /// Seed of the sampled queries.
    pub seed: u64,
    /// Drop the exact `optimal` planner on a map when one of its queries takes longer,
    /// seconds.
    pub optimal_limit_s: f64,
    /// The command line that asked for the run, for the report.
    pub command: String,
}

impl BenchOptions {
    /// Check the options before any work.
    ///
    /// # Errors
    /// No planners, no queries per map, no timed runs, or a time limit that is not a positive
    /// number of seconds.
    pub fn validate(&self) -> Result<()> {
        if self.planners.is_empty() {
            bail!("no planners to compare");
        }
        if self.per_map == 0 {
            bail!("--per-map must be at least 1, got 0");
        }
        if self.repeat == 0 {
            bail!("--repeat must be at least 1, got 0");
        }
        if !(self.optimal_limit_s.is_finite() && self.optimal_limit_s > 0.0) {
            bail!(
                "the optimal planner's time limit must be a positive number of seconds, got {}",
                self.optimal_limit_s
            );
        }
        Ok(())
    }
}

impl Default for BenchOptions {
    /// `vpmap bench`'s defaults: the default maps, MBPP, A* PS, Theta*, A* and `optimal`, 10
    /// queries per map, 3 timed runs, seed 1, 15 s for `optimal`.
    fn default() -> Self {
        Self {
            inputs: Vec::new(),
            planners: vec![
                PlannerKind::Mbpp,
                PlannerKind::AstarPs,
                PlannerKind::ThetaStar,
                PlannerKind::Astar,
                PlannerKind::Optimal,
            ],
            per_map: 10,
            repeat: 3,
            seed: 1,
            optimal_limit_s: 15.0,
            command: String::new(),
        }
    }
}

/// The maps to run: the inputs, or the default set.
fn collect_maps(
    opts: &BenchOptions,
    notes: &mut Vec<String>,
    progress: &dyn Progress,
) -> Result<Vec<BenchMap>> {
    let mut out = Vec::new();
    if opts.inputs.is_empty() {
        match maps::movingai_dir() {
            Ok(dir) => {
                out.extend(maps::default_movingai_maps(
                    &dir,
                    opts.per_map,
                    opts.seed,
                    progress,
                )?);
                notes.push(format!("Moving AI maps from {}", dir.display()));
            }
            Err(missing) => {
                let line = format!("{missing}; benchmarking generated maps only");
                progress.warn(&line);
                notes.push(line);
                out.extend(maps::generated_maps(opts.per_map, opts.seed)?);
            }
        }
        out.extend(maps::built_maps(opts.per_map, opts.seed)?);
    } else {
        for path in &opts.inputs {
            let ext = path
                .extension()
                .map(|e| e.to_string_lossy().to_ascii_lowercase())
                .unwrap_or_default();
            match ext.as_str() {
                "map" => out.push(maps::load_map_file(path, opts.per_map, opts.seed)?),
                "scen" => {
                    let extra: Vec<PathBuf> = maps::movingai_dir()
                        .ok()
                        .map(|d| {
                            let set = path.parent().and_then(Path::file_name);
                            set.map(|s| d.join("maps").join(s)).into_iter().collect()
                        })
                        .unwrap_or_default();
                    out.extend(maps::load_scen_file(path, opts.per_map, opts.seed, &extra)?);
                }
                _ => bail!(
                    "{}: unknown input type; give Moving AI .map or .scen files",
                    path.display()
                ),
            }
        }
    }
    // Unique names: a map given twice (as a .map and through a .scen) gets a suffix.
    let mut seen: Vec<String> = Vec::new();
    for m in &mut out {
        let base = m.name.clone();
        let mut k = 1;
        while seen.contains(&m.name) {
            k += 1;
            m.name = format!("{base}#{k}");
        }
        seen.push(m.name.clone());
    }
    Ok(out)
}

/// Measure every planner on every query of every map (one [`Progress::step`] per planner
/// run, one [`Progress::note`] per map).
///
/// # Errors
/// When a planner refuses a query (start or goal blocked or outside the grid).
pub fn measure_maps(
    maps: Vec<BenchMap>,
    planners: &[PlannerKind],
    repeat: usize,
    optimal_limit: Duration,
    probe: &dyn MemoryProbe,
    progress: &dyn Progress,
) -> Result<Vec<MapResult>> {
    let total: u64 = maps
        .iter()
        .map(|m| (m.queries.len() * planners.len()) as u64)
        .sum();
    progress.start(total);
    let optimal_at = planners.iter().position(|&k| k == PlannerKind::Optimal);
    let mut results = Vec::with_capacity(maps.len());
    for map in maps {
        let began = Instant::now();
        let corners = corner_cells(&map.grid, false).len();
        // Like the queries: one warm-up build, then the median of `repeat` timed ones.
        let optimal_build_s = optimal_at.map(|_| {
            std::hint::black_box(ExactPlanner::new(&map.grid, false));
            let times: Vec<f64> = (0..repeat.max(1))
                .map(|_| {
                    let built = Instant::now();
                    std::hint::black_box(ExactPlanner::new(&map.grid, false));
                    built.elapsed().as_secs_f64()
                })
                .collect();
            crate::stats::median(&times).unwrap_or(0.0)
        });
        let mut optimal_skipped: Option<String> = None;
        let mut records: Vec<Vec<Option<Measured>>> = Vec::with_capacity(map.queries.len());
        for (qi, q) in map.queries.iter().enumerate() {
            let mut row = Vec::with_capacity(planners.len());
            for &kind in planners {
                progress.message(&format!("{} query {} {kind}", map.name, qi + 1));
                let is_optimal = kind == PlannerKind::Optimal;
                if is_optimal && optimal_skipped.is_some() {
                    row.push(None);
                    progress.step();
                    continue;
                }
                let limit = is_optimal.then_some(optimal_limit);
                let measured =
                    measure::measure(kind, &map.grid, q.start, q.goal, repeat, limit, probe)
                        .with_context(|| format!("{}: query {}", map.name, qi + 1))?;
                if is_optimal && measured.is_none() {
                    optimal_skipped = Some(format!(
                        "query {} took more than {} s",
                        qi + 1,
                        optimal_limit.as_secs_f64()
                    ));
                    // All or nothing per map: forget the earlier optimal results.
                    if let Some(at) = optimal_at {
                        for r in &mut records {
                            if let Some(slot) = r.get_mut(at) {
                                *slot = None;
                            }
                        }
                    }
                }
                row.push(measured);
                progress.step();
            }
            records.push(row);
        }
        let wall_s = began.elapsed().as_secs_f64();
        progress.note(&format!(
            "{} ({}): {} queries, {:.1} s{}{}",
            map.name,
            map.category,
            map.queries.len(),
            wall_s,
            optimal_build_s.map_or_else(String::new, |b| format!(
                "; optimal's free space built in {:.2} ms",
                1e3 * b
            )),
            optimal_skipped
                .as_ref()
                .map_or_else(String::new, |r| format!("; optimal skipped: {r}"))
        ));
        results.push(MapResult {
            map,
            corner_cells: corners,
            optimal_build_s,
            optimal_skipped,
            records,
            wall_s,
        });
    }
    progress.finish();
    Ok(results)
}

/// Run a benchmark: load or build the maps, then measure every planner on every query.
///
/// # Errors
/// Options out of range, maps or scenario files that cannot be read, no queries at all, or a
/// planner refusing a query (start or goal blocked).
pub fn run(
    opts: &BenchOptions,
    probe: &dyn MemoryProbe,
    progress: &dyn Progress,
) -> Result<Results> {
    opts.validate()?;
    let started = Instant::now();
    let mut notes = Vec::new();
    let maps = collect_maps(opts, &mut notes, progress)?;
    if maps.iter().all(|m| m.queries.is_empty()) {
        bail!("no queries: the maps have no two connected free cells");
    }
    let optimal_limit = Duration::from_secs_f64(opts.optimal_limit_s.min(1e6));
    let measured = measure_maps(
        maps,
        &opts.planners,
        opts.repeat,
        optimal_limit,
        probe,
        progress,
    )?;
    Ok(Results {
        planners: opts.planners.clone(),
        maps: measured,
        command: opts.command.clone(),
        date: crate::publish::utc_now(),
        machine: machine_description(),
        repeat: opts.repeat,
        per_map: opts.per_map,
        seed: opts.seed,
        wall_s: started.elapsed().as_secs_f64(),
        optimal_limit_s: opts.optimal_limit_s,
        notes,
    })
}

/// A benchmark's report: its summary and its files.
pub struct Report {
    /// Per category and per map.
    pub summary: summary::Summary,
    /// `results.csv`, `summary.json`, the plots and `summary.md`.
    pub files: OutputSet,
    /// The plots are SVG only: the system has no fonts to render their PNGs.
    pub svg_only: bool,
}

/// Summarise a benchmark and make its files.
///
/// # Errors
/// When a plot cannot be drawn or rendered, or the summary cannot be serialised.
pub fn report(results: &Results) -> Result<Report> {
    let summary = summary::Summary::compute(results);
    let mut files = OutputSet::default();
    files.add("results.csv", report::csv(results));
    files.add(
        "summary.json",
        format!(
            "{}\n",
            serde_json::to_string_pretty(&report::json(results, &summary))?
        ),
    );
    let mut pngs = true;
    for plot in plots::plots(results, &summary)? {
        match vpmap_render::svg_to_png(&plot.svg) {
            Ok(png) => files.add(&format!("{}.png", plot.name), png),
            Err(vpmap_render::RenderError::NoFonts) => pngs = false,
            Err(e) => return Err(e).with_context(|| format!("rendering {}.png", plot.name)),
        }
        files.add(&format!("{}.svg", plot.name), plot.svg);
    }
    let image_ext = if pngs { "png" } else { "svg" };
    files.add(
        "summary.md",
        report::markdown(results, &summary, "", image_ext),
    );
    Ok(Report {
        summary,
        files,
        svg_only: !pngs,
    })
}

impl Report {
    /// The section to publish into the Markdown file `doc`, its image links pointing into the
    /// folder `out`.
    #[must_use]
    pub fn published(&self, results: &Results, doc: &Path, out: &Path) -> String {
        let folder = doc
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        let prefix = format!("{}/", relative_link(folder, out));
        let image_ext = if self.svg_only { "svg" } else { "png" };
        report::markdown(results, &self.summary, &prefix, image_ext)
    }

    /// The console summary.
    #[must_use]
    pub fn console(&self, results: &Results) -> String {
        report::console(results, &self.summary)
    }
}

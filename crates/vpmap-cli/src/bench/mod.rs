//! `vpmap bench`: MBPP against A* PS and the other planners on benchmark maps, by runtime
//! and path length — the thesis's section 6.2 (figures 6.25 and 6.26), rerun.
//!
//! Maps: the Moving AI benchmark maps of the thesis's kinds of environment (free, home and
//! office, game, maze, random, city), with problems from their scenario files spread over
//! the buckets, and occupancy grids vpmap builds from room scenes, with random free-cell
//! pairs; or the `.map` and `.scen` files given on the command line. Every map with more
//! than one connected component also gets unsolvable queries (the thesis's "blocked way").
//!
//! Measurement: queries run one after another on this thread, each planner fresh, one
//! warm-up run and then `--repeat` timed runs (median kept; a warm-up run over a second is
//! the query's only run); peak heap from the global allocator. Every path is checked by the
//! independent validator, every "found" against breadth-first connectivity, every length
//! against the exact optimum. The exact `optimal` planner is skipped on maps with more than
//! [`OPTIMAL_CORNER_LIMIT`] corner cells, or from the first query slower than
//! `--optimal-limit` (its results on that map are then dropped: all or nothing per map).
//!
//! Outputs (all or nothing, into `--out`): `results.csv` (one row per query and planner),
//! `summary.md` and `summary.json` (per category and per map), and the plots
//! `runtime.svg`/`.png` (figure 6.25), `length.svg`/`.png` (figure 6.26) and
//! `excess.svg`/`.png` (mean excess over the optimum).

mod maps;
mod measure;
mod plots;
mod report;

use std::io::IsTerminal as _;
use std::path::{Component, Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::{Context, Result, bail};
use indicatif::{ProgressBar, ProgressStyle};
use vpmap_plan::corner_cells;
use vpmap_plan::planner::PlannerKind;

use crate::output::OutputSet;
use crate::publish::{machine_description, replace_section};
use maps::BenchMap;
use measure::Measured;

/// The planners compared by default.
const DEFAULT_PLANNERS: &str = "mbpp,astar-ps,theta-star,astar,optimal";

/// Above this many corner cells (the nodes of its visibility graph) the exact `optimal`
/// planner is not run on a map at all: its cost grows with their square. Below it,
/// `--optimal-limit` decides. (On the default maps this skips only the two 512 x 512
/// random-obstacle maps, with 6.7 and 8.6 x 10^4 corners; maze512-2-5, with 2.2 x 10^4,
/// takes 1-11 s a query in release on the project's 2-core machine.)
pub const OPTIMAL_CORNER_LIMIT: usize = 25_000;

/// Default of `--optimal-limit`, seconds: when one `optimal` query's warm-up run takes
/// longer, `optimal` is dropped for the rest of the map (and its results on the map
/// discarded).
const DEFAULT_OPTIMAL_LIMIT_S: f64 = 15.0;

/// Arguments of `vpmap bench`.
#[derive(clap::Args)]
pub struct BenchArgs {
    /// Moving AI `.map` files (queries: random free-cell pairs in one component) or `.scen`
    /// files (queries from the file, across its buckets). Default: the thesis's map
    /// categories from ../shared/data/movingai (or $VPMAP_MOVINGAI) and maps vpmap builds
    /// from synthetic room scenes.
    inputs: Vec<PathBuf>,
    /// Planners to compare, comma-separated: mbpp, mbpp-closer, astar-ps, theta-star,
    /// astar, optimal.
    #[arg(long, value_delimiter = ',', default_value = DEFAULT_PLANNERS)]
    planners: Vec<String>,
    /// Solvable queries per map (spread over scenario buckets or path lengths).
    #[arg(long, default_value_t = 10)]
    per_map: usize,
    /// Timed runs per query and planner, after one warm-up run; the median is reported.
    #[arg(long, default_value_t = 3)]
    repeat: usize,
    /// Output folder.
    #[arg(long, short, default_value = "bench-out")]
    out: PathBuf,
    /// Seed of the sampled queries.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Drop the exact `optimal` planner on a map when one of its queries takes longer than
    /// this many seconds (it is also skipped on maps with more than 25,000 corner cells).
    #[arg(long, default_value_t = DEFAULT_OPTIMAL_LIMIT_S, allow_negative_numbers = true)]
    optimal_limit: f64,
    /// Also write the summary into the `bench` section of this Markdown file.
    #[arg(long)]
    publish: Option<PathBuf>,
}

/// Everything measured on one map.
pub struct MapResult {
    /// The map and its queries.
    pub map: BenchMap,
    /// Corner cells of the map (the optimal planner's graph nodes).
    pub corner_cells: usize,
    /// Why `optimal` was not run on this map, if it was asked for and not run.
    pub optimal_skipped: Option<String>,
    /// `records[query][planner]`: `None` where the planner was not run.
    pub records: Vec<Vec<Option<Measured>>>,
    /// Wall time spent on the map, seconds.
    pub wall_s: f64,
}

/// A whole run.
pub struct Results {
    /// The planners, in the order asked for.
    pub planners: Vec<PlannerKind>,
    /// Per map.
    pub maps: Vec<MapResult>,
    /// The command line, as typed.
    pub command: String,
    /// When it ran (UTC).
    pub date: String,
    /// The machine.
    pub machine: String,
    /// Timed runs per query.
    pub repeat: usize,
    /// Solvable queries asked per map.
    pub per_map: usize,
    /// Seed of the sampled queries.
    pub seed: u64,
    /// Wall time of the whole run, seconds.
    pub wall_s: f64,
    /// `--optimal-limit`, seconds.
    pub optimal_limit_s: f64,
    /// Notes about the maps (data not found, ...).
    pub notes: Vec<String>,
}

impl Results {
    /// Index of a planner in [`Self::planners`].
    pub fn index_of(&self, kind: PlannerKind) -> Option<usize> {
        self.planners.iter().position(|&k| k == kind)
    }
}

fn parse_planners(names: &[String]) -> Result<Vec<PlannerKind>> {
    let mut out = Vec::new();
    for name in names {
        let name = name.trim();
        if name.is_empty() {
            bail!(
                "--planners has an empty name; give a comma-separated list such as {DEFAULT_PLANNERS}"
            );
        }
        let kind: PlannerKind = name
            .parse()
            .map_err(|e| anyhow::anyhow!("--planners: {e}"))?;
        if !out.contains(&kind) {
            out.push(kind);
        }
    }
    if out.is_empty() {
        bail!("--planners is empty; give a comma-separated list such as {DEFAULT_PLANNERS}");
    }
    Ok(out)
}

/// Fail before measuring when `--publish` names a file whose `bench` section is broken.
fn check_publish_target(path: &Path) -> Result<()> {
    if path.is_dir() {
        bail!(
            "--publish {}: it is a folder, not a Markdown file",
            path.display()
        );
    }
    let text = match std::fs::read_to_string(path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(()),
        Err(e) => return Err(e).with_context(|| format!("cannot read {}", path.display())),
    };
    let (begin, end) = ("<!-- bench:begin -->", "<!-- bench:end -->");
    match (text.find(begin), text.find(end)) {
        (Some(b), Some(e)) if b < e => Ok(()),
        (None, None) => Ok(()),
        _ => bail!(
            "{} has a broken `bench` section: it needs `{begin}` before `{end}`",
            path.display()
        ),
    }
}

/// The maps to run: the inputs, or the default set.
fn collect_maps(args: &BenchArgs, notes: &mut Vec<String>) -> Result<Vec<BenchMap>> {
    let mut out = Vec::new();
    if args.inputs.is_empty() {
        match maps::movingai_dir() {
            Ok(dir) => {
                out.extend(maps::default_movingai_maps(&dir, args.per_map, args.seed)?);
                notes.push(format!("Moving AI maps from {}", dir.display()));
            }
            Err(missing) => {
                let line = format!("{missing}; benchmarking generated maps only");
                eprintln!("warning: {line}");
                notes.push(line);
                out.extend(maps::generated_maps(args.per_map, args.seed)?);
            }
        }
        out.extend(maps::built_maps(args.per_map, args.seed)?);
    } else {
        for path in &args.inputs {
            let ext = path
                .extension()
                .map(|e| e.to_string_lossy().to_ascii_lowercase())
                .unwrap_or_default();
            match ext.as_str() {
                "map" => out.push(maps::load_map_file(path, args.per_map, args.seed)?),
                "scen" => {
                    let extra: Vec<PathBuf> = maps::movingai_dir()
                        .ok()
                        .map(|d| {
                            let set = path.parent().and_then(Path::file_name);
                            set.map(|s| d.join("maps").join(s)).into_iter().collect()
                        })
                        .unwrap_or_default();
                    out.extend(maps::load_scen_file(path, args.per_map, args.seed, &extra)?);
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

/// Measure every planner on every query of every map.
fn run_all(
    maps: Vec<BenchMap>,
    planners: &[PlannerKind],
    repeat: usize,
    optimal_limit: Duration,
) -> Result<Vec<MapResult>> {
    let total: u64 = maps
        .iter()
        .map(|m| (m.queries.len() * planners.len()) as u64)
        .sum();
    let bar = if std::io::stderr().is_terminal() {
        let bar = ProgressBar::new(total);
        if let Ok(style) =
            ProgressStyle::with_template("{elapsed_precise} [{bar:30}] {pos}/{len} {msg}")
        {
            bar.set_style(style.progress_chars("=> "));
        }
        bar
    } else {
        ProgressBar::hidden()
    };
    let say = |line: String| {
        if bar.is_hidden() {
            eprintln!("{line}");
        } else {
            bar.println(line);
        }
    };
    let optimal_at = planners.iter().position(|&k| k == PlannerKind::Optimal);
    let mut results = Vec::with_capacity(maps.len());
    for map in maps {
        let began = Instant::now();
        let corners = corner_cells(&map.grid, false).len();
        let mut optimal_skipped = (optimal_at.is_some() && corners > OPTIMAL_CORNER_LIMIT)
            .then(|| format!("{corners} corner cells, more than {OPTIMAL_CORNER_LIMIT}"));
        let mut records: Vec<Vec<Option<Measured>>> = Vec::with_capacity(map.queries.len());
        for (qi, q) in map.queries.iter().enumerate() {
            let mut row = Vec::with_capacity(planners.len());
            for &kind in planners {
                bar.set_message(format!("{} query {} {kind}", map.name, qi + 1));
                let is_optimal = kind == PlannerKind::Optimal;
                if is_optimal && optimal_skipped.is_some() {
                    row.push(None);
                    bar.inc(1);
                    continue;
                }
                let limit = is_optimal.then_some(optimal_limit);
                let measured = measure::measure(kind, &map.grid, q.start, q.goal, repeat, limit)
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
                            r[at] = None;
                        }
                    }
                }
                row.push(measured);
                bar.inc(1);
            }
            records.push(row);
        }
        let wall_s = began.elapsed().as_secs_f64();
        say(format!(
            "{} ({}): {} queries, {:.1} s{}",
            map.name,
            map.category,
            map.queries.len(),
            wall_s,
            optimal_skipped
                .as_ref()
                .map_or_else(String::new, |r| format!("; optimal skipped: {r}"))
        ));
        results.push(MapResult {
            map,
            corner_cells: corners,
            optimal_skipped,
            records,
            wall_s,
        });
    }
    bar.finish_and_clear();
    Ok(results)
}

/// `path` made absolute and with `.` and `..` removed lexically.
fn normalized(path: &Path) -> PathBuf {
    let absolute = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
    let mut out = PathBuf::new();
    for c in absolute.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                out.pop();
            }
            other => out.push(other),
        }
    }
    out
}

/// The relative path from folder `from` to `to`, with `/` separators (for a Markdown link).
fn relative_link(from: &Path, to: &Path) -> String {
    let (from, to) = (normalized(from), normalized(to));
    let a: Vec<Component> = from.components().collect();
    let b: Vec<Component> = to.components().collect();
    let common = a.iter().zip(&b).take_while(|(x, y)| x == y).count();
    let mut parts: Vec<String> = vec!["..".to_owned(); a.len() - common];
    parts.extend(
        b[common..]
            .iter()
            .map(|c| c.as_os_str().to_string_lossy().into_owned()),
    );
    if parts.is_empty() {
        ".".to_owned()
    } else {
        parts.join("/")
    }
}

/// `vpmap bench`.
pub fn run(args: &BenchArgs) -> Result<()> {
    let planners = parse_planners(&args.planners)?;
    if args.per_map == 0 {
        bail!("--per-map must be at least 1, got 0");
    }
    if args.repeat == 0 {
        bail!("--repeat must be at least 1, got 0");
    }
    if !(args.optimal_limit.is_finite() && args.optimal_limit > 0.0) {
        bail!(
            "--optimal-limit must be a positive number of seconds, got {}",
            crate::num(args.optimal_limit)
        );
    }
    if let Some(p) = &args.publish {
        check_publish_target(p)?;
    }
    if args.out.is_file() {
        bail!("--out {}: it is a file, not a folder", args.out.display());
    }
    let started = Instant::now();
    let mut notes = Vec::new();
    let maps = collect_maps(args, &mut notes)?;
    if maps.iter().all(|m| m.queries.is_empty()) {
        bail!("no queries: the maps have no two connected free cells");
    }
    let optimal_limit = Duration::from_secs_f64(args.optimal_limit.min(1e6));
    let measured = run_all(maps, &planners, args.repeat, optimal_limit)?;
    let results = Results {
        planners,
        maps: measured,
        command: crate::publish::command_line(),
        date: crate::publish::utc_now(),
        machine: machine_description(),
        repeat: args.repeat,
        per_map: args.per_map,
        seed: args.seed,
        wall_s: started.elapsed().as_secs_f64(),
        optimal_limit_s: args.optimal_limit,
        notes,
    };
    let summary = report::Summary::compute(&results);
    let mut files = OutputSet::default();
    files.add("results.csv", report::csv(&results));
    files.add(
        "summary.json",
        format!(
            "{}\n",
            serde_json::to_string_pretty(&report::json(&results, &summary))?
        ),
    );
    let mut pngs = true;
    for plot in plots::plots(&results, &summary)? {
        match vpmap_render::svg_to_png(&plot.svg) {
            Ok(png) => files.add(&format!("{}.png", plot.name), png),
            Err(vpmap_render::RenderError::NoFonts) => {
                if pngs {
                    eprintln!(
                        "warning: no system fonts to render the plots' PNGs; writing their SVGs only"
                    );
                }
                pngs = false;
            }
            Err(e) => return Err(e).with_context(|| format!("rendering {}.png", plot.name)),
        }
        files.add(&format!("{}.svg", plot.name), plot.svg);
    }
    let image_ext = if pngs { "png" } else { "svg" };
    files.add(
        "summary.md",
        report::markdown(&results, &summary, "", image_ext),
    );
    let written = files.write_all(&args.out)?;
    if let Some(publish) = &args.publish {
        let folder = publish
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        let prefix = format!("{}/", relative_link(folder, &args.out));
        replace_section(
            publish,
            "bench",
            &report::markdown(&results, &summary, &prefix, image_ext),
        )?;
    }
    print!("{}", report::console(&results, &summary));
    let names: Vec<String> = written
        .iter()
        .filter_map(|p| p.file_name())
        .map(|n| n.to_string_lossy().into_owned())
        .collect();
    println!(
        "wrote {} in {} ({:.1} s)",
        names.join(", "),
        args.out.display(),
        results.wall_s
    );
    if let Some(publish) = &args.publish {
        println!("published the summary into {}", publish.display());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn planner_lists_are_parsed_and_checked() {
        let names = |s: &str| s.split(',').map(str::to_owned).collect::<Vec<_>>();
        let parsed = parse_planners(&names("mbpp, astar-ps,mbpp")).unwrap_or_default();
        assert_eq!(parsed, [PlannerKind::Mbpp, PlannerKind::AstarPs]);
        assert!(parse_planners(&names("mbpp,dijkstra")).is_err());
        assert!(parse_planners(&names("mbpp,")).is_err());
    }

    #[test]
    fn links() {
        assert_eq!(
            relative_link(Path::new("/a/docs"), Path::new("/a/bench-out")),
            "../bench-out"
        );
        assert_eq!(relative_link(Path::new("/a"), Path::new("/a/b/c")), "b/c");
        assert_eq!(relative_link(Path::new("/a/b"), Path::new("/a/b")), ".");
        assert_eq!(
            relative_link(Path::new("/a/./b/../c"), Path::new("/a/d")),
            "../d"
        );
    }
}

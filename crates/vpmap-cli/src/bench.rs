//! `vpmap bench`: MBPP against A* PS and the other planners on benchmark maps, by runtime
//! and path length — the thesis's section 6.2 (figures 6.25 and 6.26), rerun. The benchmark is
//! [`vpmap_eval::bench`] (maps, measurement, reports and plots); this is its flags, progress
//! bar and printing, and the memory probe over the program's global allocator.

use std::path::{Path, PathBuf};

use anyhow::{Result, bail};
use vpmap_eval::bench::BenchOptions;
use vpmap_eval::navigate::SECTION;
use vpmap_plan::planner::PlannerKind;

use crate::memory::PeakAllocProbe;
use crate::output::command_line;

/// The planners compared by default.
const DEFAULT_PLANNERS: &str = "mbpp,astar-ps,theta-star,astar,optimal";

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
    /// this many seconds.
    #[arg(long, default_value_t = DEFAULT_OPTIMAL_LIMIT_S, allow_negative_numbers = true)]
    optimal_limit: f64,
    /// Also write the summary into the `bench` section of this Markdown file (with
    /// `--navigate`: its `bench-navigate` section).
    #[arg(long)]
    publish: Option<PathBuf>,
    /// The unknown-terrain navigation benchmark instead (see docs/navigation.md): on the
    /// Moving AI maps given (default: a selection of the larger ones), a robot starting
    /// with an empty belief drives `--per-map` episodes with every online planner; writes
    /// navigate.csv and navigate.md.
    #[arg(long)]
    navigate: bool,
    /// Online planners of `--navigate`, comma-separated: astar, astar-ps, dstar-lite, mbpp,
    /// dstar-lite-ties (D* Lite under the common tie rule; the tuned repeated A* is timed on
    /// its track: the "same track" ratio) and astar-ties (a plain A* under that rule, slow;
    /// for the equal-lengths column).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "astar,astar-ps,dstar-lite,mbpp,dstar-lite-ties"
    )]
    online_planners: Vec<String>,
    /// Sensor range of `--navigate`, cells.
    #[arg(long, default_value_t = 10.0, allow_negative_numbers = true)]
    sensor_range: f64,
    /// The smooth planner against its Hybrid-A* reference instead (issue 41; see
    /// docs/planning.md): Nav2-kind maps, maps built from scenes and, when found, Moving AI
    /// rooms and cities; writes smooth.csv and smooth.md (`--publish`: the `bench-smooth`
    /// section).
    #[arg(long, conflicts_with = "navigate")]
    smooth: bool,
    /// `--smooth` with both planners allowed to drive in reverse (Reeds-Shepp curves, cusps);
    /// `--publish` writes the `bench-smooth-reverse` section.
    #[arg(long, requires = "smooth")]
    reverse: bool,
    /// Queries per map of `--smooth` (each at every radius, with both planners).
    #[arg(long, default_value_t = 6)]
    queries: usize,
}

/// `vpmap bench --smooth`.
fn run_smooth(args: &BenchArgs) -> Result<()> {
    use vpmap_eval::smooth::{
        SMOOTH_REVERSE_SECTION, SMOOTH_SECTION, SmoothBenchOptions, load_average,
    };
    let section_name = if args.reverse {
        SMOOTH_REVERSE_SECTION
    } else {
        SMOOTH_SECTION
    };
    if !args.inputs.is_empty() {
        bail!("--smooth runs on its own maps; give no map files");
    }
    if args.queries == 0 {
        bail!("--queries must be at least 1, got 0");
    }
    if args.out.is_file() {
        bail!("--out {}: it is a file, not a folder", args.out.display());
    }
    if let Some(p) = &args.publish {
        check_publish_target(p, section_name)?;
    }
    let opts = SmoothBenchOptions {
        queries: args.queries,
        movingai_dir: vpmap_eval::bench::maps::movingai_dir().ok(),
        seed: args.seed,
        reverse: args.reverse,
        command: command_line(),
        ..SmoothBenchOptions::default()
    };
    let load_before = load_average();
    let started = std::time::Instant::now();
    let bar = crate::progress::Bar::new("{elapsed_precise} [{bar}] {pos}/{len} {msg}", "30");
    let trials = vpmap_eval::smooth::run_smooth(&opts, &bar)?;
    let elapsed = started.elapsed();
    let loads = [load_before, load_average()];
    vpmap_eval::smooth::smooth_report(&trials).write_all(&args.out)?;
    let table = vpmap_eval::smooth::smooth_table(&trials);
    if let Some(path) = &args.publish {
        let section = vpmap_eval::smooth::smooth_published_section(
            &table,
            elapsed,
            &opts.command,
            loads,
            args.reverse,
        );
        vpmap_eval::publish::replace_section(path, section_name, &section)?;
    }
    print!("{table}");
    println!(
        "wrote smooth.csv and smooth.md in {} ({:.1} s; load average {} before, {} after)",
        args.out.display(),
        elapsed.as_secs_f64(),
        loads[0].map_or_else(|| "unknown".to_owned(), |v| format!("{v:.2}")),
        loads[1].map_or_else(|| "unknown".to_owned(), |v| format!("{v:.2}")),
    );
    if let Some(path) = &args.publish {
        println!("published the {section_name} section of {}", path.display());
    }
    Ok(())
}

/// `vpmap bench --navigate`.
fn run_navigate(args: &BenchArgs) -> Result<()> {
    use vpmap_plan::navigate::{MAX_SENSOR_RANGE_CELLS, OnlinePlanner};
    if !(args.sensor_range.is_finite()
        && (1.0..=MAX_SENSOR_RANGE_CELLS).contains(&args.sensor_range))
    {
        bail!(
            "--sensor-range {} is not a sensor range; give 1 to {} cells",
            vpmap_pipeline::num(args.sensor_range),
            vpmap_pipeline::num(MAX_SENSOR_RANGE_CELLS)
        );
    }
    let mut planners = Vec::new();
    for name in &args.online_planners {
        let p: OnlinePlanner = name
            .trim()
            .parse()
            .map_err(|e| anyhow::anyhow!("--online-planners: {e}"))?;
        if !planners.contains(&p) {
            planners.push(p);
        }
    }
    let maps = if args.inputs.is_empty() {
        vpmap_eval::navigate::default_maps().map_err(|e| anyhow::anyhow!(e))?
    } else {
        args.inputs.clone()
    };
    if args.out.is_file() {
        bail!("--out {}: it is a file, not a folder", args.out.display());
    }
    if let Some(p) = &args.publish {
        check_publish_target(p, SECTION)?;
    }
    let started = std::time::Instant::now();
    let opts = vpmap_eval::navigate::NavBenchOptions {
        maps,
        episodes: args.per_map,
        sensor_range_cells: args.sensor_range,
        planners,
        seed: args.seed,
        command: command_line(),
    };
    let bar = crate::progress::Bar::new("{elapsed_precise} [{bar}] {pos}/{len} {msg}", "30");
    let results = vpmap_eval::navigate::run(&opts, &bar)?;
    let elapsed = started.elapsed();
    let files = vpmap_eval::navigate::report(&results, &opts);
    files.write_all(&args.out)?;
    let table = vpmap_eval::navigate::table(&results, &opts);
    if let Some(path) = &args.publish {
        let section = vpmap_eval::navigate::published_section(&table, elapsed, &opts.command);
        vpmap_eval::publish::replace_section(path, SECTION, &section)?;
    }
    print!("{table}");
    if let Some(path) = &args.publish {
        println!("published the {SECTION} section of {}", path.display());
    }
    Ok(())
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

/// Fail before measuring when `--publish` names a file whose section `name` is broken.
fn check_publish_target(path: &Path, name: &str) -> Result<()> {
    if path.is_dir() {
        bail!(
            "--publish {}: it is a folder, not a Markdown file",
            path.display()
        );
    }
    Ok(vpmap_eval::publish::check_section(path, name)?)
}

/// `vpmap bench`.
pub fn run(args: &BenchArgs) -> Result<()> {
    if args.navigate {
        return run_navigate(args);
    }
    if args.smooth {
        return run_smooth(args);
    }
    let opts = BenchOptions {
        inputs: args.inputs.clone(),
        planners: parse_planners(&args.planners)?,
        per_map: args.per_map,
        repeat: args.repeat,
        seed: args.seed,
        optimal_limit_s: args.optimal_limit,
        command: command_line(),
    };
    if !(args.optimal_limit.is_finite() && args.optimal_limit > 0.0) {
        bail!(
            "--optimal-limit must be a positive number of seconds, got {}",
            vpmap_pipeline::num(args.optimal_limit)
        );
    }
    opts.validate()?;
    if let Some(p) = &args.publish {
        check_publish_target(p, "bench")?;
    }
    if args.out.is_file() {
        bail!("--out {}: it is a file, not a folder", args.out.display());
    }
    let bar = crate::progress::Bar::new("{elapsed_precise} [{bar}] {pos}/{len} {msg}", "30");
    let results = vpmap_eval::bench::run(&opts, &PeakAllocProbe, &bar)?;
    let report = vpmap_eval::bench::report(&results)?;
    if report.svg_only {
        eprintln!("warning: no system fonts to render the plots' PNGs; writing their SVGs only");
    }
    let written = report.files.write_all(&args.out)?;
    if let Some(publish) = &args.publish {
        vpmap_eval::publish::replace_section(
            publish,
            "bench",
            &report.published(&results, publish, &args.out),
        )?;
    }
    print!("{}", report.console(&results));
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
}

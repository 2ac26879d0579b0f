//! Print every built-in planner's path on a sample of the Moving AI scenarios, one line per
//! query, so that a refactoring can be checked to leave every path unchanged: run it before
//! and after and `diff` the two outputs.
//!
//! ```text
//! cargo run --release -p vpmap-plan --example dump_paths -- ../shared/data/movingai 10 > paths.txt
//! ```
//!
//! Arguments: the Moving AI folder (with `maps/` and `scen/`), a stride (every N-th
//! scenario of each `.scen` file; default 10), and optionally the planners to run, named as
//! `vpmap plan --planner` names them, comma-separated (default: all). The exact optimum is only run on maps with at
//! most 6,000 corner cells (its visibility graph is quadratic in them). Lengths are printed to
//! 1e-9 cells and the waypoints in full; MBPP's alternatives are printed as their count and
//! the sum of their lengths.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use vpmap_plan::{Planner, PlannerKind, corner_cells, read_movingai_map, read_scen};

/// Largest number of corner cells on which the exact optimum is run.
const OPTIMAL_MAX_CORNERS: usize = 6_000;

fn scen_files(dir: &Path, out: &mut Vec<PathBuf>) -> std::io::Result<()> {
    let mut entries: Vec<_> = std::fs::read_dir(dir)?.collect::<Result<_, _>>()?;
    entries.sort_by_key(std::fs::DirEntry::path);
    for entry in entries {
        let path = entry.path();
        if path.is_dir() {
            scen_files(&path, out)?;
        } else if path.extension().is_some_and(|e| e == "scen") {
            out.push(path);
        }
    }
    Ok(())
}

fn find_map(maps: &Path, name: &str) -> Option<PathBuf> {
    let mut stack = vec![maps.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).ok()?.flatten() {
            let path = entry.path();
            if path.is_dir() {
                stack.push(path);
            } else if path.file_name().is_some_and(|f| f == name) {
                return Some(path);
            }
        }
    }
    None
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().collect();
    let Some(root) = args.get(1).map(PathBuf::from) else {
        eprintln!("usage: dump_paths MOVINGAI_DIR [STRIDE] [PLANNER,...]");
        return ExitCode::from(2);
    };
    let stride: usize = match args.get(2).map(|s| s.parse()) {
        None => 10,
        Some(Ok(n)) if n > 0 => n,
        Some(_) => {
            eprintln!("error: STRIDE must be a positive integer");
            return ExitCode::from(2);
        }
    };
    let kinds: Vec<PlannerKind> = match args.get(3) {
        None => PlannerKind::ALL.to_vec(),
        Some(list) => match list.split(',').map(str::parse).collect() {
            Ok(kinds) => kinds,
            Err(e) => {
                eprintln!("error: {e}");
                return ExitCode::from(2);
            }
        },
    };
    let mut files = Vec::new();
    if let Err(e) = scen_files(&root.join("scen"), &mut files) {
        eprintln!("error: cannot list {}: {e}", root.join("scen").display());
        return ExitCode::FAILURE;
    }
    for scen_path in files {
        let scenarios = match read_scen(&scen_path) {
            Ok(s) => s,
            Err(e) => {
                eprintln!("error: {e}");
                return ExitCode::FAILURE;
            }
        };
        let Some(first) = scenarios.first() else {
            continue;
        };
        let Some(map_path) = find_map(&root.join("maps"), first.map_file_name()) else {
            eprintln!("error: no map {} for {}", first.map, scen_path.display());
            return ExitCode::FAILURE;
        };
        let grid = match read_movingai_map(&map_path) {
            Ok(g) => g,
            Err(e) => {
                eprintln!("error: {e}");
                return ExitCode::FAILURE;
            }
        };
        let with_optimal = corner_cells(&grid, false).len() <= OPTIMAL_MAX_CORNERS;
        let name = first.map_file_name().to_owned();
        for (i, sc) in scenarios.iter().enumerate().step_by(stride) {
            for &kind in &kinds {
                if kind == PlannerKind::Optimal && !with_optimal {
                    continue;
                }
                let mut planner = kind.planner(false);
                let mut line = format!("{name} {i} {kind} ");
                match planner.plan(&grid, sc.start, sc.goal) {
                    Err(e) => {
                        let _ = write!(line, "error {e}");
                    }
                    Ok(planned) => {
                        match &planned.best {
                            None => line.push_str("none"),
                            Some(plan) => {
                                let _ =
                                    write!(line, "{:.9} {:?}", plan.length_cells, plan.waypoints);
                            }
                        }
                        let alt_sum: f64 =
                            planned.alternatives.iter().map(|p| p.length_cells).sum();
                        let _ = write!(
                            line,
                            " alternatives {} {alt_sum:.9}",
                            planned.alternatives.len()
                        );
                    }
                }
                println!("{line}");
            }
        }
    }
    ExitCode::SUCCESS
}

//! Running one planner on one query: time, peak heap, the path and its independent check.
//!
//! Every run gets a fresh planner (so that A*, which can keep its arrays between queries,
//! allocates like the others), runs on this thread, and is timed alone: one warm-up run,
//! then `repeat` timed runs, of which the median is kept. A query whose warm-up run takes
//! longer than [`SINGLE_RUN_ABOVE`] is not repeated: at that scale a first run's cold
//! caches and page faults are negligible, and its time is the warm-up run's. Peak heap is
//! the most bytes in use above those in use before the run, over all the runs.

use std::time::{Duration, Instant};

use vpmap_plan::planner::{Planned, Planner, PlannerKind};
use vpmap_plan::{OccupancyGrid, path_length, validate_path};

use super::maps::CellXy;
use crate::error::{Result, ResultExt as _};
use crate::stats::median;

/// A warm-up run slower than this is the query's only run.
pub const SINGLE_RUN_ABOVE: Duration = Duration::from_secs(1);

/// What one planner did on one query.
#[derive(Clone, Debug, PartialEq)]
pub struct Measured {
    /// A path was found.
    pub found: bool,
    /// The independent validator's verdict on the path (`None` when none was found):
    /// `Err` holds the violation.
    pub valid: Option<Result<(), String>>,
    /// MBPP alternatives that fail the validator (their first violation).
    pub invalid_alternatives: Vec<String>,
    /// The plan's length disagrees with the length of its own waypoints.
    pub length_mismatch: bool,
    /// Path length, cells.
    pub length_cells: Option<f64>,
    /// Number of waypoints.
    pub waypoints: usize,
    /// Sum of the absolute heading changes at the waypoints, degrees.
    pub turning_deg: Option<f64>,
    /// MBPP's alternatives (`None` for the other planners).
    pub alternatives: Option<usize>,
    /// MBPP's bugs (`None` for the other planners).
    pub bugs: Option<usize>,
    /// Nodes expanded (bug steps for MBPP); `None` when the planner reports none.
    pub expanded: Option<usize>,
    /// Line-of-sight queries; `None` when the planner reports none.
    pub los_checks: Option<usize>,
    /// Peak heap in use during a run above what was in use before it, bytes.
    pub peak_bytes: usize,
    /// Median time of the timed runs, seconds.
    pub time_s: f64,
    /// Runs in that median (1 when the warm-up run was slower than [`SINGLE_RUN_ABOVE`] and
    /// is the time).
    pub runs: usize,
}

/// The heap in use, from the program's global allocator: the library does not own the
/// allocator, so the binary that does (with `peak_alloc`, say) lends it through this trait.
pub trait MemoryProbe {
    /// Bytes in use now.
    fn current_bytes(&self) -> usize;
    /// Start a new peak: from now on, [`Self::peak_bytes`] is the most in use since this call.
    fn reset_peak(&self);
    /// The most bytes in use since the last [`Self::reset_peak`].
    fn peak_bytes(&self) -> usize;
}

/// No allocator to ask: every peak is 0 bytes.
#[derive(Clone, Copy, Debug, Default)]
pub struct NoMemoryProbe;

impl MemoryProbe for NoMemoryProbe {
    fn current_bytes(&self) -> usize {
        0
    }
    fn reset_peak(&self) {}
    fn peak_bytes(&self) -> usize {
        0
    }
}

/// Whether a planner is one of the MBPP variants.
#[must_use]
pub fn is_mbpp(kind: PlannerKind) -> bool {
    matches!(kind, PlannerKind::Mbpp | PlannerKind::MbppCloser)
}

/// One run: the result, its time and its peak heap above the bytes in use before it.
fn run_once(
    kind: PlannerKind,
    grid: &OccupancyGrid,
    start: CellXy,
    goal: CellXy,
    probe: &dyn MemoryProbe,
) -> Result<(Planned, Duration, usize)> {
    let mut planner = kind.planner(false);
    let before = probe.current_bytes();
    probe.reset_peak();
    let began = Instant::now();
    let planned = planner.plan(grid, start, goal);
    let elapsed = began.elapsed();
    let peak = probe.peak_bytes().saturating_sub(before);
    let planned = planned.with_context(|| format!("{kind} from {start:?} to {goal:?}"))?;
    Ok((planned, elapsed, peak))
}

/// Run `kind` from `start` to `goal`: a warm-up run, then `repeat` timed runs. `None` when
/// the warm-up run took longer than `limit`, and the timed runs were not made.
///
/// # Errors
/// When the planner rejects the query (start or goal blocked or outside the grid).
/// `probe` gives the heap in use (see [`MemoryProbe`]).
pub fn measure(
    kind: PlannerKind,
    grid: &OccupancyGrid,
    start: CellXy,
    goal: CellXy,
    repeat: usize,
    limit: Option<Duration>,
    probe: &dyn MemoryProbe,
) -> Result<Option<Measured>> {
    let (planned, warm_up, mut peak_bytes) = run_once(kind, grid, start, goal, probe)?;
    if limit.is_some_and(|l| warm_up > l) {
        return Ok(None);
    }
    if warm_up > SINGLE_RUN_ABOVE {
        return Ok(Some(describe(
            kind,
            grid,
            &planned,
            peak_bytes,
            (warm_up.as_secs_f64(), 1),
        )));
    }
    let mut times = Vec::with_capacity(repeat);
    for _ in 0..repeat {
        let (again, elapsed, peak) = run_once(kind, grid, start, goal, probe)?;
        drop(again);
        times.push(elapsed.as_secs_f64());
        peak_bytes = peak_bytes.max(peak);
    }
    Ok(Some(describe(
        kind,
        grid,
        &planned,
        peak_bytes,
        (median(&times).unwrap_or(0.0), repeat),
    )))
}

/// Sum of the absolute heading changes along a polyline through cell centres, degrees.
#[must_use]
pub fn turning_deg(waypoints: &[CellXy]) -> f64 {
    let dirs: Vec<(f64, f64)> = waypoints
        .windows(2)
        .filter_map(|w| match w {
            [a, b] if a != b => Some((b.x as f64 - a.x as f64, b.y as f64 - a.y as f64)),
            _ => None,
        })
        .collect();
    dirs.windows(2)
        .map(|w| match w {
            [u, v] => (u.0 * v.1 - u.1 * v.0).atan2(u.0 * v.0 + u.1 * v.1).abs(),
            _ => 0.0,
        })
        .fold(0.0, |sum, turn| sum + turn)
        .to_degrees()
}

fn describe(
    kind: PlannerKind,
    grid: &OccupancyGrid,
    planned: &Planned,
    peak_bytes: usize,
    (time_s, runs): (f64, usize),
) -> Measured {
    let mbpp = is_mbpp(kind);
    let best = planned.best.as_ref();
    let valid = best.map(|p| validate_path(grid, &p.waypoints, false).map_err(|e| e.to_string()));
    let invalid_alternatives = planned
        .alternatives
        .iter()
        .filter_map(|p| validate_path(grid, &p.waypoints, false).err())
        .map(|e| e.to_string())
        .collect();
    let length_mismatch = best.is_some_and(|p| {
        let own = path_length(&p.waypoints);
        (own - p.length_cells).abs() > 1e-9 * own.max(1.0)
    });
    let (expanded, los_checks) = if mbpp {
        (
            Some(planned.mbpp_stats.bug_steps),
            Some(planned.mbpp_stats.los_checks),
        )
    } else {
        (
            best.map(|p| p.stats.expanded),
            best.map(|p| p.stats.los_checks),
        )
    };
    Measured {
        found: best.is_some(),
        valid,
        invalid_alternatives,
        length_mismatch,
        length_cells: best.map(|p| p.length_cells),
        waypoints: best.map_or(0, |p| p.waypoints.len()),
        turning_deg: best.map(|p| turning_deg(&p.waypoints)),
        alternatives: mbpp.then_some(planned.alternatives.len()),
        bugs: mbpp.then_some(planned.mbpp_stats.bugs),
        expanded,
        los_checks,
        peak_bytes,
        time_s,
        runs,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use vpmap_plan::Occupancy;

    fn cells(xy: &[(usize, usize)]) -> Vec<CellXy> {
        xy.iter().map(|&c| CellXy::from(c)).collect()
    }

    #[test]
    fn turning_sums_absolute_heading_changes() {
        assert!(turning_deg(&cells(&[(0, 0), (5, 0)])).abs() < 1e-12);
        assert!((turning_deg(&cells(&[(0, 0), (5, 0), (5, 5)])) - 90.0).abs() < 1e-9);
        // Left then right: both count.
        assert!((turning_deg(&cells(&[(0, 0), (2, 0), (2, 2), (4, 2)])) - 180.0).abs() < 1e-9);
        assert!((turning_deg(&cells(&[(0, 0), (1, 1), (2, 1)])) - 45.0).abs() < 1e-9);
        assert!(turning_deg(&cells(&[(3, 3)])).abs() < 1e-12);
    }

    #[test]
    fn measured_paths_are_checked_and_counted() -> Result<()> {
        let mut grid = OccupancyGrid::new(8, 5, 1.0, [0.0; 2], Occupancy::Free)?;
        for y in 0..4 {
            grid.set(4, y, Occupancy::Occupied)?;
        }
        for kind in PlannerKind::ALL {
            let m = measure(
                kind,
                &grid,
                (0, 0).into(),
                (7, 0).into(),
                2,
                None,
                &NoMemoryProbe,
            )?
            .unwrap_or_else(|| panic!("{kind}: no limit was given"));
            assert!(m.found && m.valid == Some(Ok(())), "{kind}: {m:?}");
            assert!(!m.length_mismatch && m.invalid_alternatives.is_empty());
            assert_eq!(m.alternatives.is_some(), is_mbpp(kind));
            assert!(m.time_s > 0.0, "{kind}: {m:?}");
        }
        // A zero limit skips the timed runs.
        let skipped = measure(
            PlannerKind::Optimal,
            &grid,
            (0, 0).into(),
            (7, 0).into(),
            3,
            Some(Duration::ZERO),
            &NoMemoryProbe,
        )?;
        assert!(skipped.is_none());
        Ok(())
    }
}

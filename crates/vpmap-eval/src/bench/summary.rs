//! The summary of a `vpmap bench` run, per category and per map ([`Summary`]), the checks that
//! turn into its "failures", and the planners' display names.
//!
//! Definitions (in every output):
//! - **time ratio to A* PS**: geometric mean over the queries both planners ran of
//!   `time / time of A* PS` (median times), unsolvable queries included;
//! - **shorter / equal / longer than A* PS**: over the solvable queries where both found a
//!   path, lengths equal within a relative 1e-9;
//! - **excess over optimal**: `length / optimal - 1` over the solvable queries where the exact
//!   planner ran (never on maps where it was skipped);
//! - **failures**: a path found where breadth-first search finds no connection or none found
//!   where it does, a path (or MBPP alternative) the independent validator rejects, a length
//!   that disagrees with the waypoints, a length below the exact optimum, and on `.scen`
//!   problems an A* length that differs from the file's octile optimum (tolerance
//!   `max(0.005, 5e-6 length)`, the files' printed rounding) or an optimum above it.

use vpmap_plan::planner::PlannerKind;

use super::maps::{CATEGORY_ORDER, CellXy, Origin};
use super::results::{MapResult, Results};
use crate::stats::mean;

/// Relative tolerance of "equal lengths" and of "not below the optimum".
pub const LENGTH_REL_TOL: f64 = 1e-9;

/// How one planner's lengths compare with A* PS's.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Versus {
    /// Queries where it is shorter.
    pub shorter: usize,
    /// Equal within [`LENGTH_REL_TOL`].
    pub equal: usize,
    /// Longer.
    pub longer: usize,
}

impl Versus {
    /// Queries compared.
    #[must_use]
    pub fn total(self) -> usize {
        self.shorter + self.equal + self.longer
    }

    /// Shares of shorter, equal and longer (0 each when nothing was compared).
    #[must_use]
    pub fn shares(self) -> [f64; 3] {
        let n = self.total().max(1) as f64;
        [
            self.shorter as f64 / n,
            self.equal as f64 / n,
            self.longer as f64 / n,
        ]
    }
}

/// One planner's numbers over a group of queries.
#[derive(Clone, Debug, Default)]
pub struct PlannerStats {
    /// Queries it ran on.
    pub runs: usize,
    /// Mean of its median times, seconds.
    pub mean_time_s: Option<f64>,
    /// Geometric mean of its time over A* PS's.
    pub time_ratio: Option<f64>,
    /// Queries in that mean.
    pub ratio_queries: usize,
    /// Mean of `length / optimal - 1`.
    pub mean_excess: Option<f64>,
    /// Largest `length / optimal - 1`.
    pub max_excess: Option<f64>,
    /// Queries in the excess means.
    pub excess_queries: usize,
    /// Mean length over the solvable queries it found a path for, cells.
    pub mean_length_cells: Option<f64>,
    /// Mean total turning, degrees.
    pub mean_turning_deg: Option<f64>,
    /// Largest peak heap, bytes.
    pub max_peak_bytes: usize,
    /// Lengths against A* PS's (`None` for A* PS itself or when it did not run).
    pub vs_astar_ps: Option<Versus>,
}

/// Numbers over a group of maps: a category, all maps, or one map.
#[derive(Clone, Debug, Default)]
pub struct Group {
    /// Category or map name.
    pub name: String,
    /// Maps in the group.
    pub maps: usize,
    /// Solvable queries.
    pub solvable: usize,
    /// Unsolvable queries.
    pub unsolvable: usize,
    /// Per planner, in [`Results::planners`] order.
    pub planners: Vec<PlannerStats>,
    /// Failures in the group.
    pub failures: usize,
    /// Maps of the group where `optimal` was skipped.
    pub optimal_skipped: Vec<String>,
}

/// The whole summary.
pub struct Summary {
    /// Per category, in [`CATEGORY_ORDER`] then alphabetical order.
    pub categories: Vec<Group>,
    /// Every map together.
    pub all: Group,
    /// Per map, in run order.
    pub maps: Vec<Group>,
    /// Every failure, one line each.
    pub failures: Vec<String>,
}

fn equal_lengths(a: f64, b: f64) -> bool {
    (a - b).abs() <= LENGTH_REL_TOL * a.abs().max(b.abs())
}

/// The length of the optimal planner on query `q` of `m`, when it ran and found one.
pub(super) fn optimal_length(results: &Results, m: &MapResult, q: usize) -> Option<f64> {
    let at = results.index_of(PlannerKind::Optimal)?;
    m.records[q][at].as_ref()?.length_cells
}

pub(super) fn astar_ps_length(results: &Results, m: &MapResult, q: usize) -> Option<f64> {
    let at = results.index_of(PlannerKind::AstarPs)?;
    m.records[q][at].as_ref()?.length_cells
}

fn excess(length: f64, optimal: f64) -> Option<f64> {
    (optimal > 0.0).then(|| length / optimal - 1.0)
}

/// The failures of query `q` of map `m`.
fn query_failures(results: &Results, m: &MapResult, q: usize) -> Vec<String> {
    let query = &m.map.queries[q];
    let reachable = m.map.components.connected(query.start, query.goal);
    let optimal = optimal_length(results, m, q);
    let mut out = Vec::new();
    let at = |kind: PlannerKind| {
        format!(
            "{} query {} ({} -> {}, {}) {kind}",
            m.map.name,
            q + 1,
            cell_text(query.start),
            cell_text(query.goal),
            query.origin.name()
        )
    };
    for (&kind, record) in results.planners.iter().zip(&m.records[q]) {
        let Some(r) = record else { continue };
        if r.found != reachable {
            out.push(if r.found {
                format!(
                    "{}: found a path, but start and goal are not connected",
                    at(kind)
                )
            } else {
                format!(
                    "{}: found no path, but start and goal are connected",
                    at(kind)
                )
            });
        }
        if let Some(Err(e)) = &r.valid {
            out.push(format!("{}: invalid path: {e}", at(kind)));
        }
        for e in &r.invalid_alternatives {
            out.push(format!("{}: invalid alternative: {e}", at(kind)));
        }
        if r.length_mismatch {
            out.push(format!(
                "{}: length differs from its waypoints' length",
                at(kind)
            ));
        }
        if let (Some(len), Some(opt)) = (r.length_cells, optimal)
            && len < opt - LENGTH_REL_TOL * opt.max(1.0)
        {
            out.push(format!(
                "{}: length {len} is below the optimum {opt}",
                at(kind)
            ));
        }
        if let (
            Origin::Scen {
                octile_optimum_cells: octile_optimum,
                ..
            },
            Some(len),
        ) = (query.origin, r.length_cells)
        {
            let tol = (5e-6 * octile_optimum).max(0.005);
            if kind == PlannerKind::Astar && (len - octile_optimum).abs() > tol {
                out.push(format!(
                    "{}: length {len} differs from the scenario's octile optimum {octile_optimum}",
                    at(kind)
                ));
            }
            if kind == PlannerKind::Optimal && len > octile_optimum + tol {
                out.push(format!(
                    "{}: length {len} is above the scenario's octile optimum {octile_optimum}",
                    at(kind)
                ));
            }
        }
    }
    out
}

fn cell_text(c: CellXy) -> String {
    format!("({}, {})", c.x, c.y)
}

impl Group {
    fn compute(name: &str, results: &Results, maps: &[&MapResult]) -> Self {
        let np = results.planners.len();
        let astar_ps_at = results.index_of(PlannerKind::AstarPs);
        let mut times: Vec<Vec<f64>> = vec![Vec::new(); np];
        let mut log_ratios: Vec<Vec<f64>> = vec![Vec::new(); np];
        let mut excesses: Vec<Vec<f64>> = vec![Vec::new(); np];
        let mut lengths: Vec<Vec<f64>> = vec![Vec::new(); np];
        let mut turning: Vec<Vec<f64>> = vec![Vec::new(); np];
        let mut peaks = vec![0usize; np];
        let mut versus = vec![Versus::default(); np];
        let mut group = Group {
            name: name.to_owned(),
            maps: maps.len(),
            ..Group::default()
        };
        for m in maps {
            if m.optimal_skipped.is_some() {
                group.optimal_skipped.push(m.map.name.clone());
            }
            for (q, query) in m.map.queries.iter().enumerate() {
                if m.map.components.connected(query.start, query.goal) {
                    group.solvable += 1;
                } else {
                    group.unsolvable += 1;
                }
                group.failures += query_failures(results, m, q).len();
                let optimal = optimal_length(results, m, q);
                let reference = astar_ps_at.and_then(|at| m.records[q][at].as_ref());
                for (p, record) in m.records[q].iter().enumerate() {
                    let Some(r) = record else { continue };
                    times[p].push(r.time_s);
                    peaks[p] = peaks[p].max(r.peak_bytes);
                    if let Some(reference) = reference
                        && r.time_s > 0.0
                        && reference.time_s > 0.0
                    {
                        log_ratios[p].push((r.time_s / reference.time_s).ln());
                    }
                    let Some(len) = r.length_cells else { continue };
                    lengths[p].push(len);
                    turning[p].extend(r.turning_deg);
                    if let Some(e) = optimal.and_then(|opt| excess(len, opt)) {
                        excesses[p].push(e);
                    }
                    if let Some(ref_len) = reference.and_then(|x| x.length_cells) {
                        let v = &mut versus[p];
                        if equal_lengths(len, ref_len) {
                            v.equal += 1;
                        } else if len < ref_len {
                            v.shorter += 1;
                        } else {
                            v.longer += 1;
                        }
                    }
                }
            }
        }
        group.planners = (0..np)
            .map(|p| PlannerStats {
                runs: times[p].len(),
                mean_time_s: mean(&times[p]),
                time_ratio: mean(&log_ratios[p]).map(f64::exp),
                ratio_queries: log_ratios[p].len(),
                mean_excess: mean(&excesses[p]),
                max_excess: excesses[p].iter().copied().reduce(f64::max),
                excess_queries: excesses[p].len(),
                mean_length_cells: mean(&lengths[p]),
                mean_turning_deg: mean(&turning[p]),
                max_peak_bytes: peaks[p],
                vs_astar_ps: (Some(p) != astar_ps_at && astar_ps_at.is_some()).then_some(versus[p]),
            })
            .collect();
        group
    }
}

impl Summary {
    /// Every number of the summary.
    #[must_use]
    pub fn compute(results: &Results) -> Self {
        let mut categories: Vec<String> = Vec::new();
        for m in &results.maps {
            if !categories.contains(&m.map.category) {
                categories.push(m.map.category.clone());
            }
        }
        categories.sort_by_key(|c| {
            (
                CATEGORY_ORDER
                    .iter()
                    .position(|k| k == c)
                    .unwrap_or(CATEGORY_ORDER.len()),
                c.clone(),
            )
        });
        let groups = categories
            .iter()
            .map(|c| {
                let maps: Vec<&MapResult> = results
                    .maps
                    .iter()
                    .filter(|m| &m.map.category == c)
                    .collect();
                Group::compute(c, results, &maps)
            })
            .collect();
        let all_maps: Vec<&MapResult> = results.maps.iter().collect();
        let maps = results
            .maps
            .iter()
            .map(|m| Group::compute(&m.map.name, results, &[m]))
            .collect();
        let failures = results
            .maps
            .iter()
            .flat_map(|m| (0..m.map.queries.len()).flat_map(move |q| query_failures(results, m, q)))
            .collect();
        Self {
            categories: groups,
            all: Group::compute("all", results, &all_maps),
            maps,
            failures,
        }
    }
}

/// The planner's display name in tables.
pub(super) fn label(kind: PlannerKind) -> &'static str {
    match kind {
        PlannerKind::Mbpp => "MBPP",
        PlannerKind::MbppCloser => "MBPP (closer)",
        PlannerKind::AstarPs => "A* PS",
        PlannerKind::ThetaStar => "Theta*",
        PlannerKind::Astar => "A*",
        PlannerKind::Optimal => "optimal",
    }
}

/// A planner's display name (for plots).
#[must_use]
pub fn planner_label(kind: PlannerKind) -> &'static str {
    label(kind)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lengths_compare_within_a_relative_tolerance() {
        assert!(equal_lengths(100.0, 100.0 + 1e-8));
        assert!(!equal_lengths(100.0, 100.0 + 1e-6));
        assert!(equal_lengths(0.0, 0.0));
        let v = Versus {
            shorter: 1,
            equal: 2,
            longer: 1,
        };
        let shares = v.shares();
        assert!(
            shares
                .iter()
                .zip([0.25, 0.5, 0.25])
                .all(|(a, b)| (a - b).abs() < 1e-12)
        );
    }
}

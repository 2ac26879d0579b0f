//! The feasible paths besides the selected one (MBPP's alternatives): each goal-reaching
//! bug's `v_list`, and each waiting bug's completed by the shortest clear continuation.

use super::cells::to_u;
use super::graph::Graph;
use super::options::{MbppOptions, halted};
use super::walk::{Join, NONE};
use crate::grid::CellXy;
use crate::los::{LosCounter, PassableGrid};
use crate::plan::path_length;
use crate::planned::MbppStats;

/// The feasible paths besides the selected one: each goal-reaching bug's `v_list`, and each
/// waiting bug's `v_list` completed by the shortest clear continuation from its join.
pub(super) fn alternatives(
    mut graph_clear: Graph,
    (goals, joins): (&[u32], &[Join]),
    grid: &PassableGrid,
    (opts, stats, counter): (&MbppOptions, &mut MbppStats, &mut LosCounter),
    selected: Option<&[CellXy]>,
) -> Vec<Vec<CellXy>> {
    // Decide the join segments not yet known.
    for join in joins {
        if halted(opts, stats, counter) {
            return Vec::new();
        }
        let from = join.vertex;
        let a = graph_clear.cell(from);
        let unknown: Vec<u32> = graph_clear
            .out(from)
            .filter(|e| !e.clear)
            .map(|e| e.to)
            .collect();
        for to in unknown {
            let b = graph_clear.cell(to);
            if grid.sight(a, b, counter) {
                if let Some(e) = graph_clear.edge_mut(from, to) {
                    e.clear = true;
                }
            } else {
                graph_clear.remove_edge(from, to);
            }
        }
    }
    let goal = goals.first().map(|&g| graph_clear.cell(g));
    let Some(goal) = goal else {
        return Vec::new();
    };
    let (to_goal, next) = graph_clear.to_goal(goal);
    let mut paths: Vec<Vec<CellXy>> = Vec::new();
    for &g in goals {
        paths.push(
            graph_clear
                .tree_path(g)
                .iter()
                .map(|&v| to_u(graph_clear.cell(v)))
                .collect(),
        );
    }
    for join in joins {
        if !to_goal
            .get(join.vertex as usize)
            .is_some_and(|d| d.is_finite())
        {
            continue;
        }
        let mut ids = graph_clear.tree_path(join.vertex);
        let mut at = join.vertex;
        while let Some(&n) = next.get(at as usize) {
            if n == NONE || ids.len() > graph_clear.cells.len() {
                break;
            }
            ids.push(n);
            at = n;
        }
        paths.push(ids.iter().map(|&v| to_u(graph_clear.cell(v))).collect());
    }
    let mut keyed: Vec<(f64, Vec<CellXy>)> =
        paths.into_iter().map(|p| (path_length(&p), p)).collect();
    keyed.sort_by(|a, b| a.0.total_cmp(&b.0).then_with(|| a.1.cmp(&b.1)));
    keyed.dedup_by(|a, b| a.1 == b.1);
    keyed
        .into_iter()
        .map(|(_, p)| p)
        .filter(|p| Some(p.as_slice()) != selected)
        .collect()
}

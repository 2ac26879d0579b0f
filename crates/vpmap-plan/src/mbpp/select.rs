//! The thesis's `select_list`: the shortest `v_list` path, its line-of-sight check and the
//! re-planning of blocked segments, and the other feasible paths (the alternatives).

use super::graph::Graph;
use super::result::MbppOptions;
use super::walk::Join;
use super::{MbppStats, NONE, Xy, halted, run, to_i, to_u};
use crate::grid::CellXy;
use crate::los::{LosCounter, PassableGrid};
use crate::plan::path_length;

/// The shortest `v_list` path whose segments are all clear: select, check, re-plan the
/// first blocked segment, repeat.
pub(super) fn select(
    graph: &mut Graph,
    grid: &PassableGrid,
    goal: Xy,
    opts: &MbppOptions,
    depth: usize,
    stats: &mut MbppStats,
    counter: &mut LosCounter,
) -> Option<Vec<CellXy>> {
    loop {
        if halted(opts, stats, counter) {
            return None;
        }
        let path = graph.shortest(goal, false)?;
        let mut blocked = None;
        for pair in path.windows(2) {
            let &[u, v] = pair else { continue };
            let (a, b) = (graph.cell(u), graph.cell(v));
            let Some(edge) = graph.edge_mut(u, v) else {
                continue;
            };
            if edge.clear {
                continue;
            }
            if grid.sight(a, b, counter) {
                edge.clear = true;
            } else {
                blocked = Some((u, v));
                break;
            }
        }
        let Some((u, v)) = blocked else {
            return Some(path.iter().map(|&v| to_u(graph.cell(v))).collect());
        };
        graph.remove_edge(u, v);
        stats.replans += 1;
        if depth < opts.max_replan_depth {
            let (a, b) = (graph.cell(u), graph.cell(v));
            let sub = run(grid, a, b, opts, depth + 1, stats, counter);
            if let Some(way) = sub.best {
                let mut from = u;
                let inner = way.get(1..way.len().saturating_sub(1)).unwrap_or(&[]);
                for &c in inner {
                    let w = graph.add_vertex(to_i(c));
                    graph.add_edge(from, w);
                    from = w;
                }
                graph.add_edge(from, v);
            }
        }
    }
}

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

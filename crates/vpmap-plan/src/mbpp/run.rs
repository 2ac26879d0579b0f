//! One MBPP run, possibly nested: the bugs' walk, then the thesis's `select_list` (the
//! shortest `v_list` path), its line-of-sight check and the re-planning of blocked segments
//! by nested runs, the alternatives, and the smoothing of the chosen path.

use super::alternatives::alternatives;
use super::cells::{Xy, to_i, to_u};
use super::graph::Graph;
use super::options::{MbppOptions, halted};
use super::walk::{Walk, WalkEnd};
use crate::grid::CellXy;
use crate::los::{LosCounter, PassableGrid};
use crate::planned::{BugFate, BugTrack, MbppStats};
use crate::smoothing::smooth_path;

/// What one (possibly nested) run produces.
pub(super) struct Outcome {
    pub(super) best: Option<Vec<CellXy>>,
    pub(super) alternatives: Vec<Vec<CellXy>>,
    pub(super) bugs: Vec<BugTrack>,
}

/// The bugs' walk, then selection, check and re-planning.
pub(super) fn run(
    grid: &PassableGrid,
    start: Xy,
    goal: Xy,
    opts: &MbppOptions,
    depth: usize,
    stats: &mut MbppStats,
    counter: &mut LosCounter,
) -> Outcome {
    if start == goal {
        stats.bugs += 1;
        return Outcome {
            best: Some(vec![to_u(start)]),
            alternatives: Vec::new(),
            bugs: vec![BugTrack::born(
                None,
                start,
                opts.record_tracks,
                BugFate::ReachedGoal,
            )],
        };
    }
    let mut walk = Walk::new(
        grid,
        start,
        goal,
        opts.record_tracks && depth == 0,
        opts.leave,
    );
    let budget = opts.max_bug_steps.saturating_sub(stats.bug_steps);
    match walk.run(counter, (budget, opts.max_sight_cells), &opts.stop) {
        WalkEnd::Done => {}
        WalkEnd::Budget => stats.budget_exhausted = true,
        WalkEnd::SightBudget => stats.sight_budget_exhausted = true,
        WalkEnd::Stopped(reason) => stats.stopped = Some(reason),
    }
    stats.bugs += walk.bugs.len();
    stats.bug_steps += walk.steps;
    stats.hits += walk.hits;
    stats.waits += walk.joins.len();
    let Walk {
        vertices,
        joins,
        goals,
        bugs,
        ..
    } = walk;
    let bugs: Vec<BugTrack> = bugs.into_iter().map(|b| b.track).collect();
    if goals.is_empty() || halted(opts, stats, counter) {
        return Outcome {
            best: None,
            alternatives: Vec::new(),
            bugs,
        };
    }
    let mut graph = Graph::new(&vertices, &joins);
    let selected = select(&mut graph, grid, goal, opts, depth, stats, counter);
    let alternatives = alternatives(
        graph,
        (&goals, &joins),
        grid,
        (opts, &mut *stats, &mut *counter),
        selected.as_deref(),
    );
    let best = selected.map(|path| smooth_path(grid, &path, counter));
    Outcome {
        best,
        alternatives,
        bugs,
    }
}

/// The shortest `v_list` path whose segments are all clear: select, check, re-plan the
/// first blocked segment, repeat.
fn select(
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

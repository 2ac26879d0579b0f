//! Multi-Bug Path Planning (MBPP, the thesis's chapter 5 and Algorithm 2): virtual bugs go
//! greedily toward the goal along the m-line, split at every obstacle they hit so that one
//! follows its wall each way, note the corner states they pass (`v_list`), leave the wall
//! where it meets the m-line again, wait where another bug has gone before, and finally
//! the shortest `v_list` — completed, line-of-sight checked and re-planned where blocked —
//! is smoothed into the path. Every other feasible `v_list` is returned as an alternative.
//!
//! `docs/mbpp.md` walks through the rules with the thesis's names; this page states them
//! exactly as implemented.
//!
//! # States and moves
//! A bug stands on a traversable cell. `rr(s) = rr_g - |s - goal|` (errata: no stored
//! matrix), so the greedy action `argmax rr` over the 8 neighbours is the neighbour
//! nearest to the goal. From the start, greedy moves in an empty grid go diagonally until
//! the bug is level with the goal, then straight (the nearest neighbour is unique for
//! integer offsets): that walk is the **m-line**, and every cell on it has a position
//! `0..=n` along it with the distance to the goal strictly falling. A bug in **greedy
//! mode** always stands on the m-line and steps to the next m-line cell when that step is
//! legal (8-connected, a diagonal step needs both orthogonal neighbours traversable — the
//! collision rule of [`crate::los`] for single steps).
//!
//! # Hit, birth and wall following (C4)
//! When the greedy step is illegal the bug **hits** the obstacle at its cell `H` (added to
//! its `hit_list`). It gives birth to a second bug with a copy of its `v_list`; the parent
//! follows the wall keeping it on its right hand, the newborn keeps it on its left, so the
//! two go round the obstacle in opposite directions (the thesis's "state on the other side
//! of its parent"). Both put their hand on the blocked cell of the greedy step (or, for a
//! diagonal step squeezed between blocked cells, on the first blocked orthogonal
//! neighbour). Wall following uses the four straight moves and the classic hand rule:
//! turn towards the hand if that cell is traversable, else go straight, else turn away,
//! else go back. (The thesis lets the bug choose among its 8 neighbours by `rr` without
//! revisiting its last two states; that rule is not well defined at concave corners and
//! can cycle in a dead end, while the hand rule traces the whole boundary of the
//! obstacle's 8-connected component, and the path's shape comes from the `v_list`, not
//! from the track.)
//!
//! # Leaving (C2) and termination (C1)
//! - **C2(a)**: a following bug that steps onto an m-line cell *further along than its
//!   hit* (closer to the goal) leaves the wall, notes the cell in its `leave_list`, and goes
//!   greedy. The thesis leaves at any m-line cell; that is Bug2 without its "closer than the
//!   hit point" test, which can circle forever between two m-line crossings, and the
//!   printed C1(b) does not always catch it. With the test, the hit positions along one
//!   bug's life strictly increase, so a bug hits at most `n` times.
//! - **C1(a)**, **C1(b)**: a following bug that cannot move, or whose (cell, heading) state
//!   repeats (it went round its obstacle without meeting the m-line beyond its hit), is
//!   terminated. The wall walk is deterministic, so a repeat means a loop; repeats are
//!   found in `O(1)` memory by Brent's cycle detection, plus a direct test for the state it
//!   started in.
//! - **C1(c)** as printed (end a following bug on *any* bug's hit state) is not applied: a
//!   bug crossing another's hit cell walks a different wall state with a different hit
//!   distance, and ending it can lose the only path (found by the random-grid tests). The
//!   waiting condition below already stops duplicate work where it is exact.
//! - A bug that reaches the goal is done; the goal ends its `v_list`.
//!
//! # Waiting (C3) and idle bugs
//! Greedy behaviour has no memory: two greedy bugs on the same m-line cell walk the same
//! states from then on. So the first bug to stand greedily on an m-line cell **owns** it;
//! a bug that would go greedy on an owned cell (by leaving there, or by a greedy step) waits
//! there instead (the thesis waits only on other bugs' leave states; a greedy step onto an
//! owned cell can only reach a leave state, and leaving onto a cell another bug walked
//! greedily would otherwise walk its path again, against Lemma 3). When all bugs are done,
//! a waiting bug is completed with the corner states the owner (and its descendants) noted
//! after that cell: its `v_list` joins every continuation of the owner's `v_list` at that
//! point.
//!
//! # `v_list` by line of sight
//! Each bug keeps the last state of its `v_list` as its anchor. After every step it checks
//! line of sight from the anchor to its new cell; when it is blocked, the previous cell —
//! visible from the anchor and one legal step from the new cell — is appended and becomes
//! the anchor (the thesis's "common neighbour of the previous and current states visible
//! from the latest state in `v_list`"). A bug leaving the wall also appends its leave cell,
//! so that bugs waiting there later join clear segments. Hence consecutive states of a
//! bug's own `v_list` are always in line of sight.
//!
//! # Selection, line-of-sight check and re-planning
//! All `v_list`s form one graph (a tree of shared prefixes plus the joins of waiting bugs).
//! Its shortest start-goal path (Dijkstra over Euclidean segment lengths) is the thesis's
//! `select_list`. Its segments are checked for line of sight; a join segment can be
//! blocked (the owner's next corner need not be visible from where the waiting bug joined).
//! A blocked segment `(u, v)` is re-planned by running MBPP from `u` to `v` and splicing the
//! result in (the thesis restarts "with the state just before the first identified
//! occupied state"; starting at `u` keeps the segment's ends on known states), and the
//! selection is repeated until the shortest path is clear. A re-planning that fails
//! (nesting deeper than [`MbppOptions::max_replan_depth`]) drops the segment; bugs' own
//! `v_list`s are clear, so a path is always left when one was found. The chosen path is
//! then smoothed by [`smooth_path`](crate::smoothing::smooth_path) (the thesis's
//! `Path_smooth`: farthest visible state first).
//!
//! # Completeness and bounds
//! If the goal is reachable, the m-line beyond a hit runs from the obstacle to the goal, and
//! the wall walk round the obstacle's component crosses it (an 8-connected path from inside
//! to outside meets a 4-connected closed boundary), so one of the two wall followers
//! leaves beyond its hit; hits move strictly along the m-line, so some bug reaches the goal.
//! Every m-line cell is hit at most once (it must be owned first), so there are at most
//! `2 n + 1` bugs for an m-line of `n + 1` cells, and each walks at most about three times
//! the boundary of one obstacle component plus the m-line: an unsolvable query ends with
//! `found = false` after `O(n x free cells)` steps in the worst case, and usually after one
//! walk round the enclosing wall.
//!
//! # References
//! - The thesis, chapter 5 and Appendix A.2 (Algorithm 2), read with its errata.
//! - V. J. Lumelsky, A. A. Stepanov, "Path-Planning Strategies for a Point Mobile Automaton
//!   Moving Amidst Unknown Obstacles of Arbitrary Shape", Algorithmica 2, 1987 (Bug2 and its
//!   leave rule).
//! - R. P. Brent, "An Improved Monte Carlo Factorization Algorithm", BIT 20, 1980 (cycle
//!   detection).
//!
//! # Files
//! - `cells.rs`: the cells as signed integer pairs and their arithmetic;
//! - `options.rs`: the options and limits (the result and its records, shared with
//!   [`crate::planner`], are in `planned.rs` beside this folder);
//! - `walk.rs`: the m-line and the bugs' walk (greedy moves, hits, wall following,
//!   leaving, waiting), which builds the `v_list` tree;
//! - `graph.rs`: every `v_list` as one graph, with its shortest-path searches;
//! - `alternatives.rs`: the other feasible paths;
//! - `run.rs`: one run: the walk, then selection, line-of-sight check and re-planning (by
//!   nested runs), the alternatives and the smoothing;
//! - this file: [`mbpp`], which runs it and turns its outcome into a [`Planned`].

mod alternatives;
mod cells;
mod graph;
mod options;
mod run;
mod walk;

pub use crate::planned::{BugFate, BugTrack, MbppStats};
pub use options::{DEFAULT_MAX_ALTERNATIVES, DEFAULT_MAX_BUG_STEPS, LeaveRule, MbppOptions};
pub use walk::m_line;

use crate::error::Result;
use crate::grid::{CellXy, OccupancyGrid};
use crate::los::{LosCounter, PassableGrid};
use crate::plan::{Plan, PlanStats, check_endpoint, path_length};
use crate::planned::Planned;

use cells::to_i;
use run::run;

/// Multi-Bug Path Planning from `start` to `goal` (see the [module docs](self)).
///
/// # Errors
/// [`PlanError::EndpointOutsideGrid`](crate::PlanError::EndpointOutsideGrid) when `start`
/// or `goal` is outside the grid,
/// [`PlanError::EndpointBlocked`](crate::PlanError::EndpointBlocked) when it is not
/// traversable.
///
/// # Complexity
/// At most `2 n + 1` bugs for an m-line of `n + 1` cells; each step costs one line-of-sight
/// query. See the module docs for the bound on unsolvable queries.
///
/// # Example
/// ```
/// use vpmap_plan::{Occupancy, OccupancyGrid, mbpp::{mbpp, MbppOptions}};
/// // ......
/// // ..#...
/// // ..#...
/// // ..#...
/// // ......
/// let mut grid = OccupancyGrid::new(6, 5, 1.0, [0.0; 2], Occupancy::Free).unwrap();
/// for y in 1..4 {
///     grid.set(2, y, Occupancy::Occupied).unwrap();
/// }
/// let result = mbpp(&grid, (0, 2), (5, 2), &MbppOptions::default()).unwrap();
/// let best = result.best.unwrap();
/// // Round the wall's top end, past the corner cells (1, 0) and (3, 0): the shortest way.
/// assert_eq!(best.waypoints, [(0, 2), (1, 0), (3, 0), (5, 2)]);
/// assert!((best.length_cells - (5f64.sqrt() + 2.0 + 8f64.sqrt())).abs() < 1e-12);
/// // The first bug split once, at the wall; the newborn went round the bottom end and
/// // waited where the first bug had left the wall; its completed path is the alternative.
/// assert_eq!(result.bugs.len(), 2);
/// assert_eq!(result.alternatives.len(), 1);
/// assert!(result.alternatives[0].length_cells > best.length_cells);
/// ```
pub fn mbpp(
    grid: &OccupancyGrid,
    start: impl Into<CellXy>,
    goal: impl Into<CellXy>,
    opts: &MbppOptions,
) -> Result<Planned> {
    let (start, goal) = (start.into(), goal.into());
    check_endpoint(grid, "start", start, opts.unknown_passable)?;
    check_endpoint(grid, "goal", goal, opts.unknown_passable)?;
    opts.stop.check("MBPP")?;
    let mut padded = PassableGrid::new(grid, opts.unknown_passable);
    // Bugs check sight from their anchor at every step: along a corridor that is a walk
    // of the whole corridor per step, unless free boxes are proved in a few look-ups. The
    // index costs a pass over the grid, so it is built once the walks have cost as much.
    padded.index_boxes_when_worth_it();
    let mut stats = MbppStats::default();
    let mut counter = LosCounter::default();
    let outcome = run(
        &padded,
        to_i(start),
        to_i(goal),
        opts,
        0,
        &mut stats,
        &mut counter,
    );
    stats.los_checks = counter.checks;
    stats.los_cells = counter.cells;
    // The last checks (the smoothing) run after the last look at the budget.
    if counter.cells > opts.max_sight_cells {
        stats.sight_budget_exhausted = true;
    }
    if stats.budget_exhausted {
        return Err(crate::PlanError::BudgetExhausted {
            planner: "MBPP",
            what: "bug steps",
            limit: opts.max_bug_steps,
            option: "max_bug_steps",
        });
    }
    if stats.sight_budget_exhausted {
        return Err(crate::PlanError::BudgetExhausted {
            planner: "MBPP",
            what: "cells looked up by line-of-sight checks",
            limit: opts.max_sight_cells,
            option: "max_sight_cells",
        });
    }
    if let Some(reason) = stats.stopped {
        return Err(crate::PlanError::Stopped {
            planner: "MBPP",
            reason,
            allowed_s: opts.stop.allowed_s(),
        });
    }
    let plan_stats = PlanStats {
        expanded: stats.bug_steps,
        generated: stats.bugs,
        los_checks: counter.checks,
        los_cells: counter.cells,
    };
    let best = outcome.best.map(|waypoints| Plan {
        length_cells: path_length(&waypoints),
        waypoints,
        stats: plan_stats,
    });
    let mut alternatives: Vec<Plan> = outcome
        .alternatives
        .into_iter()
        .map(|waypoints| Plan {
            length_cells: path_length(&waypoints),
            waypoints,
            stats: plan_stats,
        })
        .collect();
    // Keep the shortest `max_alternatives` (a stable sort keeps equal lengths in bug order).
    if alternatives.len() > opts.max_alternatives {
        alternatives.sort_by(|a, b| a.length_cells.total_cmp(&b.length_cells));
        alternatives.truncate(opts.max_alternatives);
    }
    Ok(Planned {
        best,
        alternatives,
        bugs: outcome.bugs,
        mbpp_stats: stats,
    })
}

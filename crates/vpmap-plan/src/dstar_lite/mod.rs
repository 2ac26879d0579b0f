//! D* Lite: incremental re-planning on the 8-connected grid, for a robot that learns the
//! map as it moves (Koenig and Likhachev 2002, the optimized version of their Figure 4).
//!
//! Semantics: exactly the grid model of [`crate::astar`](mod@crate::astar). The robot moves
//! between the centres of 8-neighbouring passable cells; a straight step costs 1 and needs
//! both its cells passable, a diagonal step costs `sqrt 2` and needs both its cells **and
//! both orthogonal neighbours** passable (no corner cutting). Passable is
//! [`cell_passable`](crate::los::cell_passable): [`Occupancy::Free`](crate::Occupancy::Free),
//! and [`Occupancy::Unknown`](crate::Occupancy::Unknown) with
//! [`DStarLiteOptions::unknown_passable`]. Step costs are symmetric, so every cell's
//! predecessors are its successors (its 8 neighbours). A cell
//! changing passability changes the costs of the 8 steps into and out of it, and of the 4
//! diagonal steps between its orthogonal neighbours that cut past it.
//!
//! The search runs backwards from the goal: `g(s)` and `rhs(s)` are costs from `s` to the
//! goal, the heuristic is the octile distance from the robot's cell (consistent), and the
//! priority queue holds the locally inconsistent cells (`g != rhs`) keyed by
//! `[min(g, rhs) + h(start, s) + k_m; min(g, rhs)]`, compared lexicographically. When the
//! robot moves and cells change, `k_m` grows by the heuristic distance moved since the last
//! change, so queued keys stay lower bounds and need no re-sorting. [`DStarLite::path`]
//! follows `argmin c(s, s') + g(s')` from the robot's cell: a shortest path on the current
//! map, of the same cost as a fresh A* on it.
//!
//! Costs are exact: a path's cost is its counts of straight and diagonal steps (compared
//! as `s + d sqrt 2` exactly, in integers), so equal lengths are equal and no rounding
//! decides a tie, as in [`crate::astar`](mod@crate::astar). The queue is an indexed 4-ary
//! heap (each cell knows its position: re-keying and removing are in place, no stale
//! entries) of exact integer keys: lengths in fixed point with `2^-42` cells, exact up to a
//! million steps of each kind, in 16 bytes (24 with the common tie rule's weight); once a
//! key outgrows that (a search over a million steps long, checked at every key), the search
//! widens to 48-byte keys of lengths with `2^-64` cells and tie weights, exact below `2^27`
//! steps (`k_m` is folded into the keys before either limit). The smaller keys make a
//! drive's planning about a quarter faster, a tenth under the common tie rule
//! (docs/navigation.md).
//!
//! **The common tie rule** ([`DStarLiteOptions::common_ties`]): a cost is compared by
//! length first and then by the sum of the [`tie_weight`]s of the cells the path enters
//! (fixed pseudo-random 32-bit numbers per cell). The length stays exactly optimal; among
//! equally short paths the one of the smallest weight sum is returned, which is unique
//! unless two of them have equal sums (for two given paths that differ in some cell, a chance
//! of at most `2^-32`). The heuristic (octile length, weight 0) stays consistent. A forward
//! A* under the same rule returns the same path from the same belief, so the two drive the
//! same track (the `astar-ties` planner of [`crate::navigate`](mod@crate::navigate)). Off (the default), ties fall
//! as the search meets them: smaller cost-to-goal first, then the first move in the order
//! E, S, W, N, SE, SW, NW, NE when following the path.
//!
//! Why not a crate: no Rust crate on docs.rs implements D* Lite on this grid model (no
//! corner cutting, unknown cells as an option) with the project's [`Budget`](crate::Budget) and error
//! style; the generic graph implementations (e.g. gonum's in Go) would need the grid as an
//! explicit graph with per-edge updates. The algorithm is short enough to write to the
//! paper and test against repeated A* (`tests/it/dstar_lite.rs`).
//!
//! # Example
//! ```
//! use vpmap_plan::{CellXy, Occupancy, OccupancyGrid};
//! use vpmap_plan::dstar_lite::{DStarLite, DStarLiteOptions};
//! let grid = OccupancyGrid::new(5, 3, 1.0, [0.0; 2], Occupancy::Free).unwrap();
//! let mut planner = DStarLite::new(&grid, (0, 1), (4, 1), &DStarLiteOptions::default()).unwrap();
//! assert_eq!(planner.path().unwrap().unwrap().length_cells, 4.0);
//! // The robot learns that (2, 1) is blocked: the path bends around it.
//! planner.update_cells(&[(CellXy::new(2, 1), Occupancy::Occupied)]).unwrap();
//! let plan = planner.path().unwrap().unwrap();
//! assert!((plan.length_cells - 2.0 - 2.0 * std::f64::consts::SQRT_2).abs() < 1e-12);
//! // It moves one step and plans on from there, reusing the search.
//! planner.move_start((1, 0)).unwrap();
//! assert!((planner.path().unwrap().unwrap().length_cells - 2.0 - std::f64::consts::SQRT_2).abs() < 1e-12);
//! ```
//!
//! # References
//! S. Koenig, M. Likhachev, "D* Lite", AAAI 2002 (Figure 4, the optimized version); also
//! "Fast Replanning for Navigation in Unknown Terrain", IEEE Transactions on Robotics
//! 21(3), 2005.
//!
//! # Files
//! - `cost.rs`: path costs as exact step counts and tie weights, and the cells' tie weights;
//! - `keys.rs`: the queue keys (narrow, tie and wide) and their exact integer lengths;
//! - `queue.rs`: the indexed 4-ary heap;
//! - `search.rs`: the search itself (Figure 4), its options, cell changes and robot moves;
//! - `drive.rs`: [`DStarLite`], the handle a robot drives with (and its widening), and
//!   [`dstar_lite`].

mod cost;
mod drive;
mod keys;
mod queue;
mod search;

pub(crate) use cost::StepCost;
pub use cost::tie_weight;
pub use drive::{DStarLite, dstar_lite};
pub use search::DStarLiteOptions;

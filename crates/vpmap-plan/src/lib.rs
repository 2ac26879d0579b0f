//! Occupancy grids, their ROS `map_server` and Moving AI files, line of sight and path
//! planning on them. (A vpmap floor map becomes a grid in the `vpmap-raster` crate, so this
//! one stands alone: its only vpmap dependency is `vpmap-files`, the bounded file reader.)
//!
//! | step | module | method |
//! |---|---|---|
//! | grid model | [`grid`] | row-major [`Occupancy`]s, `(x, y)` = (column, row from the top), ROS origin at the lower-left corner |
//! | obstacle inflation | [`grid`] | exact Euclidean distance transform to the obstacles' squares (Felzenszwalb and Huttenlocher 2012), thresholded at the robot radius |
//! | map files | [`ros`] | `map_server` YAML + PGM writer; reader for PGM (P2, P5) and PNG with `negate`, thresholds and the `trinary`, `scale` and `raw` modes |
//! | benchmark files | [`movingai`] | Moving AI `.map` grids and `.scen` problem lists (Sturtevant 2012) |
//! | collision rule | [`los`] | a cell-sized square swept between cell centres may touch but not overlap blocked cells; exact integer walk over the swept cells, built once per grid as [`PassableGrid`] for every planner |
//! | reachability | [`reach`] | connected components of the passable cells by breadth-first search, the reference for "is there a path" |
//! | path check | [`validate`] | the same rule decided independently, by the separating axis theorem per cell |
//! | grid path | [`astar`](mod@astar) | A*, 8-connected, octile costs, no corner cutting, octile heuristic (Hart, Nilsson and Raphael 1968) |
//! | incremental grid path | [`dstar_lite`](mod@dstar_lite) | D* Lite: the same grid paths, repaired after cell changes and robot moves (Koenig and Likhachev 2002) |
//! | smoothed grid path | [`smoothing`] | A* PS: A*, then greedy farthest-visible line-of-sight shortcuts (Botea, Müller and Schaeffer 2004) |
//! | any-angle path | [`theta_star`](mod@theta_star) | Basic Theta*: A* whose nodes take a parent in line of sight (Nash, Daniel, Koenig and Felner 2007) |
//! | multi-bug path | [`mbpp`](mod@mbpp) | the thesis's Multi-Bug Path Planning: greedy bugs on the m-line split at obstacles, follow walls both ways, note corners by line of sight; shortest `v_list`, checked, re-planned and smoothed |
//! | navigation | [`navigate`](mod@navigate) | a robot driving a believed map, sensing the true one within a range by line of sight and re-planning (repeated A*, A* PS, D* Lite, online MBPP) |
//! | shortest any-angle path | [`anya`] | exact: Anya-style interval search over the free space cut into row-line intervals and strip rectangles, built once per grid (Harabor et al. 2016, Cui et al. 2017) |
//! | curvature-bounded path | [`smooth`] | lines and arcs of radius at least `R`: Dubins paths (Dubins 1957) through the exact any-angle path's corners with lazy feasibility repair, Hybrid-A* with analytic Dubins expansion as the complete fallback (Dolgov et al. 2008); an analytic validator of every point of the curve |
//! | shortest any-angle path (reference) | [`optimal`] | exact: A* on the visibility graph of start, goal and convex corner cells (Lozano-Pérez and Wesley 1979) |
//!
//! # Module order
//! Imports go one way: each module uses only modules listed before it (types two modules
//! share live in a third, lower one). Bottom-up, with what each uses (from step 6 on,
//! besides `budget`, `error`, `grid`, `los` and `plan`):
//! 1. `cell` (private: [`CellXy`], [`Occupancy`], [`BYTES_PER_CELL`](grid::BYTES_PER_CELL))
//!    and `stop_reason` (private: [`StopReason`]) use nothing;
//! 2. [`error`] uses `cell`, `stop_reason`;
//! 3. [`budget`] uses `error`, `stop_reason`; [`grid`] uses `cell`, `error`;
//! 4. [`los`] uses `grid`;
//! 5. [`plan`] uses `error`, `grid`, `los`; `corners` (private: the corner cells) uses `grid`,
//!    `los`; [`validate`] and [`reach`] use `grid` (and `los`); the files, [`ros`] and
//!    [`movingai`], use `error`, `grid`;
//! 6. the searches, [`astar`](mod@astar), [`theta_star`](mod@theta_star),
//!    [`dstar_lite`](mod@dstar_lite) and [`anya`] (also `corners`), use `budget`, `error`,
//!    `grid`, `los`, `plan`;
//! 7. [`smoothing`] uses `astar`; [`optimal`] uses `anya`, `corners`, `theta_star`;
//! 8. `planned` (private: [`Planned`] and MBPP's records) uses `budget`, `grid`, `plan`;
//! 9. [`mbpp`](mod@mbpp) uses `planned`, `smoothing`;
//! 10. [`planner`] uses `planned`, `astar`, `smoothing`, `theta_star`, `anya`, `mbpp`;
//! 11. [`navigate`](mod@navigate) uses `planner`, `dstar_lite`, `mbpp`;
//! 12. [`smooth`] uses `anya` (and `budget`, `error`, `grid`, `plan`).
//!
//! Inside the folders, bottom-up: `anya/`: `dead_ends`, `space`, `search`, `mod.rs`;
//! `dstar_lite/`: `cost`, `keys`, `queue`, `search`, `drive`, `mod.rs`; `mbpp/`: `cells` and
//! `options`, `walk`, `graph`, `alternatives`, `run`, `mod.rs`; `navigate/`: `options`,
//! `sensor`, `ties`, `shadow`, `outcome`, `replan`, `mod.rs`; `smooth/`: `curve`, `dubins`,
//! `check`, `clearance`, `fillet`, `hybrid`, `mod.rs`.
//!
//! # Example
//! ```
//! use vpmap_plan::{astar, read_ros_map, write_ros_map, AstarOptions, Occupancy, OccupancyGrid};
//! // A 20 x 10 room of 0.1 m cells with a wall across it, open at the bottom.
//! let mut grid = OccupancyGrid::new(20, 10, 0.1, [0.0, 0.0], Occupancy::Free).unwrap();
//! for y in 0..8 {
//!     grid.set(10, y, Occupancy::Occupied).unwrap();
//! }
//! let grid = grid.inflate(0.1).unwrap();
//! let plan = astar(&grid, (2, 2), (17, 2), &AstarOptions::default()).unwrap().unwrap();
//! assert!(plan.length_cells > 15.0);
//! let dir = tempfile::tempdir().unwrap();
//! write_ros_map(&grid, &dir.path().join("room.yaml")).unwrap();
//! assert_eq!(read_ros_map(&dir.path().join("room.yaml")).unwrap(), grid);
//! ```
//!
//! # References
//! - P. F. Felzenszwalb, D. P. Huttenlocher, "Distance Transforms of Sampled Functions",
//!   Theory of Computing 8 (2012).
//! - ROS `map_server` / `nav2_map_server` map format (YAML fields, pixel thresholds).
//! - N. Sturtevant, "Benchmarks for Grid-Based Pathfinding", IEEE Transactions on
//!   Computational Intelligence and AI in Games 4(2), 2012.
//! - P. E. Hart, N. J. Nilsson, B. Raphael, "A Formal Basis for the Heuristic Determination
//!   of Minimum Cost Paths", IEEE Transactions on Systems Science and Cybernetics 4(2), 1968.
//! - A. Botea, M. Müller, J. Schaeffer, "Near Optimal Hierarchical Path-Finding", Journal
//!   of Game Development 1(1), 2004.
//! - A. Nash, K. Daniel, S. Koenig, A. Felner, "Theta*: Any-Angle Path Planning on Grids",
//!   AAAI 2007.
//! - L. E. Dubins, "On Curves of Minimal Length with a Constraint on Average Curvature...",
//!   American Journal of Mathematics 79(3), 1957.
//! - D. Dolgov, S. Thrun, M. Montemerlo, J. Diebel, "Practical Search Techniques in Path
//!   Planning for Autonomous Driving", STAIR 2008.
//! - T. Lozano-Pérez, M. A. Wesley, "An Algorithm for Planning Collision-Free Paths Among
//!   Polyhedral Obstacles", Communications of the ACM 22(10), 1979.
#![deny(missing_docs)]

pub mod anya;
pub mod astar;
pub mod budget;
mod cell;
mod corners;
pub mod dstar_lite;
pub mod error;
pub mod grid;
pub mod los;
pub mod mbpp;
pub mod movingai;
pub mod navigate;
pub mod optimal;
pub mod plan;
mod planned;
pub mod planner;
pub mod reach;
pub mod ros;
pub mod smooth;
pub mod smoothing;
mod stop_reason;
pub mod theta_star;
pub mod validate;

pub use anya::ExactPlanner;
pub use astar::{AstarOptions, AstarSearch, astar};
pub use budget::{Budget, Stop, StopReason};
pub use dstar_lite::{DStarLite, DStarLiteOptions, dstar_lite};
pub use error::{PlanError, Result};
pub use grid::{CellXy, MAX_CELLS, Occupancy, OccupancyGrid};
pub use los::{
    LosCounter, Passable, PassableGrid, Traversable, cell_passable, line_of_sight,
    line_of_sight_counted,
};
pub use mbpp::{MbppOptions, mbpp};
pub use movingai::{Scenario, parse_movingai_map, parse_scen, read_movingai_map, read_scen};
pub use navigate::{NavigateOptions, Navigation, OnlinePlanner, Outcome, navigate};
pub use optimal::{OptimalAnyAngleOptions, corner_cells, optimal_any_angle};
pub use plan::{Plan, PlanStats, path_length};
pub use planner::{Planned, Planner, PlannerKind};
pub use reach::{Components, reachable};
pub use ros::{encode_ros_map, read_ros_map, write_ros_map};
pub use smooth::{
    Pose, SmoothCurve, SmoothOptions, SmoothOutcome, SmoothPlanner, plan_smooth, validate_smooth,
};
pub use smoothing::{AstarPsOptions, astar_ps, smooth_path};
pub use theta_star::{ThetaStarOptions, theta_star};
pub use validate::{PathViolation, validate_path};

/// The README's example, compiled and run as a doc test.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;

//! What a `vpmap bench` run measured: per map ([`MapResult`]) and in all ([`Results`]).

use vpmap_plan::planner::PlannerKind;

use super::maps::BenchMap;
use super::measure::Measured;

/// Everything measured on one map.
pub struct MapResult {
    /// The map and its queries.
    pub map: BenchMap,
    /// Corner cells of the map (the nodes of the reference visibility graph).
    pub corner_cells: usize,
    /// Time to build the exact planner's free space for the map once
    /// ([`vpmap_plan::ExactPlanner::new`]; one warm-up build, then the median of the
    /// query's number of timed runs), seconds; `None` when `optimal` was not
    /// asked for. Included in each `optimal` query's time.
    pub optimal_build_s: Option<f64>,
    /// Why `optimal` was not run on this map, if it was asked for and not run.
    pub optimal_skipped: Option<String>,
    /// `records[query][planner]`: `None` where the planner was not run.
    pub records: Vec<Vec<Option<Measured>>>,
    /// Wall time spent on the map, seconds.
    pub wall_s: f64,
}

/// A whole run.
pub struct Results {
    /// The planners, in the order asked for.
    pub planners: Vec<PlannerKind>,
    /// Per map.
    pub maps: Vec<MapResult>,
    /// The command line, as typed.
    pub command: String,
    /// When it ran (UTC).
    pub date: String,
    /// The machine.
    pub machine: String,
    /// Timed runs per query.
    pub repeat: usize,
    /// Solvable queries asked per map.
    pub per_map: usize,
    /// Seed of the sampled queries.
    pub seed: u64,
    /// Wall time of the whole run, seconds.
    pub wall_s: f64,
    /// `--optimal-limit`, seconds.
    pub optimal_limit_s: f64,
    /// Notes about the maps (data not found, ...).
    pub notes: Vec<String>,
}

impl Results {
    /// Index of a planner in [`Self::planners`].
    #[must_use]
    pub fn index_of(&self, kind: PlannerKind) -> Option<usize> {
        self.planners.iter().position(|&k| k == kind)
    }
}

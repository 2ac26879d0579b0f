//! What a drive takes: the online planner ([`OnlinePlanner`]) and the options of
//! [`navigate`](super::navigate) ([`NavigateOptions`]).

use std::str::FromStr;

use crate::budget::Budget;
use crate::error::{PlanError, Result};

/// The planners a robot can re-plan with.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum OnlinePlanner {
    /// A* from scratch at every re-plan ([`crate::astar`](mod@crate::astar)).
    Astar,
    /// A* PS from scratch at every re-plan ([`crate::smoothing`]).
    AstarPs,
    /// D* Lite, incremental ([`crate::dstar_lite`](mod@crate::dstar_lite)).
    DStarLite,
    /// MBPP re-run from the robot's cell, keeping its alternatives (see the
    /// [module docs](super)).
    Mbpp,
    /// A* from scratch at every re-plan under the common tie rule (a plain A*, not the
    /// tuned one): drives the same track as [`OnlinePlanner::DStarLiteTies`].
    AstarTies,
    /// D* Lite under the common tie rule
    /// ([`DStarLiteOptions::common_ties`](crate::DStarLiteOptions::common_ties)): drives the
    /// same track as [`OnlinePlanner::AstarTies`].
    DStarLiteTies,
}

impl OnlinePlanner {
    /// Every online planner.
    pub const ALL: [Self; 6] = [
        Self::Astar,
        Self::AstarPs,
        Self::DStarLite,
        Self::Mbpp,
        Self::AstarTies,
        Self::DStarLiteTies,
    ];

    /// The planner's name (also what [`FromStr`] reads).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Astar => "astar",
            Self::AstarPs => "astar-ps",
            Self::DStarLite => "dstar-lite",
            Self::Mbpp => "mbpp",
            Self::AstarTies => "astar-ties",
            Self::DStarLiteTies => "dstar-lite-ties",
        }
    }
}

impl FromStr for OnlinePlanner {
    type Err = PlanError;

    fn from_str(s: &str) -> Result<Self> {
        Self::ALL
            .into_iter()
            .find(|k| k.name() == s)
            .ok_or_else(|| PlanError::UnknownPlanner {
                name: s.to_owned(),
                choices: Self::ALL.map(Self::name).join(", "),
            })
    }
}

/// Options of [`navigate`](super::navigate).
#[derive(Clone, Debug, PartialEq)]
pub struct NavigateOptions {
    /// The planner (default D* Lite).
    pub planner: OnlinePlanner,
    /// Sensor range, cells (centre to centre); at least 1, at most
    /// [`MAX_SENSOR_RANGE_CELLS`](super::MAX_SENSOR_RANGE_CELLS) (default 10).
    pub sensor_range_cells: f64,
    /// Whether believed-unknown cells are passable to the planners (default `true`, the
    /// free-space assumption).
    pub unknown_passable: bool,
    /// Most moves (cells) before the run stops with
    /// [`Outcome::MoveLimit`](super::Outcome::MoveLimit) (default 10 million).
    pub max_moves: usize,
    /// Most re-plans before the run stops with
    /// [`Outcome::ReplanLimit`](super::Outcome::ReplanLimit) (default 1 million).
    pub max_replans: usize,
    /// The budget of each planner run (default [`Budget::default`]).
    pub budget: Budget,
}

impl Default for NavigateOptions {
    fn default() -> Self {
        Self {
            planner: OnlinePlanner::DStarLite,
            sensor_range_cells: 10.0,
            unknown_passable: true,
            max_moves: 10_000_000,
            max_replans: 1_000_000,
            budget: Budget::default(),
        }
    }
}

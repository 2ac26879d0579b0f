//! Why a planner was stopped ([`StopReason`]): what [`Stop`](crate::budget::Stop) decides
//! and [`PlanError::Stopped`](crate::PlanError::Stopped) carries, so it lives below both.
//! Re-exported by [`crate::budget`].

use std::fmt;

/// Why a [`Stop`](crate::budget::Stop) stopped a planner.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StopReason {
    /// Its deadline passed.
    Deadline,
    /// Its cancellation flag was set.
    Cancelled,
}

impl fmt::Display for StopReason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::Deadline => "its time ran out",
            Self::Cancelled => "it was cancelled",
        })
    }
}

//! Curvature-bounded smooth paths a robot can drive: lines and circular arcs of radius at
//! least `R`, tangent-continuous, clear of the blocked cells under the collision rule of
//! [`crate::los`] at every point.
//!
//! - [`curve`]: poses, segments (lines and arcs, forward or reverse) and curves;
//! - [`dubins`]: the shortest forward paths between poses without obstacles (Dubins 1957);
//! - [`check`]: the independent validator of a curve on a grid, analytic per segment.

pub mod check;
pub mod curve;
pub mod dubins;

pub use check::{SmoothRules, SmoothViolation, validate_smooth};
pub use curve::{Gear, Pose, Segment, SmoothCurve};
pub use dubins::{DubinsPath, dubins_distance, dubins_shortest, dubins_words};

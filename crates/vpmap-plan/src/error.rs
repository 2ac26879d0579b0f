//! The one error type of this crate.

use std::path::{Path, PathBuf};

use thiserror::Error;

use crate::cell::{BYTES_PER_CELL, Occupancy};
use crate::stop_reason::StopReason;

/// Everything that can go wrong when building, reading or writing an occupancy grid.
///
/// Every variant carries the offending values (field, value, file path) so that a user can
/// fix the input without reading the code.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum PlanError {
    /// A planner name that is not one of [`crate::PlannerKind::ALL`].
    #[error("unknown planner `{name}`; choose one of {choices}")]
    UnknownPlanner {
        /// The name given.
        name: String,
        /// The valid names, comma-separated.
        choices: String,
    },
    /// A numeric parameter (an option field or a grid property) is outside its valid range.
    #[error("`{field}` is {value}; it {requirement}")]
    InvalidParameter {
        /// Name of the parameter, e.g. `resolution_m`.
        field: &'static str,
        /// The value given.
        value: f64,
        /// What the value must satisfy, e.g. "must be finite and positive".
        requirement: &'static str,
    },
    /// A grid would have more cells than [`crate::grid::MAX_CELLS`].
    #[error(
        "a grid of {} x {} cells is too large: it would need about {} of memory to plan on ({} bytes a cell), more than the limit of {max} cells ({}); use a coarser resolution or a smaller map",
        count(*width),
        count(*height),
        megabytes(width.saturating_mul(*height)),
        BYTES_PER_CELL,
        megabytes(*max)
    )]
    GridTooLarge {
        /// Requested width, cells (saturated at `usize::MAX`).
        width: usize,
        /// Requested height, cells (saturated at `usize::MAX`).
        height: usize,
        /// The limit, cells.
        max: usize,
    },
    /// A grid needs at least one row and one column.
    #[error("a grid of {width} x {height} cells is empty; it needs at least one row and column")]
    EmptyGrid {
        /// Requested width, cells.
        width: usize,
        /// Requested height, cells.
        height: usize,
    },
    /// A cell vector does not have `width * height` entries.
    #[error("a {width} x {height} grid needs {expected} cells, but {found} were given")]
    CellCount {
        /// Grid width, cells.
        width: usize,
        /// Grid height, cells.
        height: usize,
        /// `width * height`.
        expected: usize,
        /// Length of the vector given.
        found: usize,
    },
    /// A cell index outside the grid.
    #[error("cell ({x}, {y}) is outside the {width} x {height} grid")]
    CellOutOfBounds {
        /// Column of the cell.
        x: usize,
        /// Row of the cell, from the top.
        y: usize,
        /// Grid width, cells.
        width: usize,
        /// Grid height, cells.
        height: usize,
    },
    /// A planner reached its work budget before finishing.
    #[error(
        "{planner} stopped after {limit} {what} without finishing (the `{option}` budget); the map makes its search explode: plan on a coarser grid, or raise the budget"
    )]
    BudgetExhausted {
        /// The planner.
        planner: &'static str,
        /// What was counted.
        what: &'static str,
        /// The budget.
        limit: usize,
        /// The option that sets it.
        option: &'static str,
    },
    /// A planner was stopped by its [`Stop`](crate::budget::Stop): its deadline passed or
    /// its cancellation flag was set.
    #[error("{planner} stopped: {}", stopped_message(*reason, *allowed_s))]
    Stopped {
        /// The planner.
        planner: &'static str,
        /// Deadline or cancellation.
        reason: StopReason,
        /// The time it was allowed, seconds (0 without a deadline).
        allowed_s: f64,
    },
    /// An input file was refused before or while reading it: not a regular file, over its
    /// format's size limit, or not readable ([`vpmap_files`]).
    #[error(transparent)]
    File(#[from] vpmap_files::FileError),
    /// A file could not be read or written.
    #[error("cannot {action} `{}`", path.display())]
    Io {
        /// "read", "write" or "rename to".
        action: &'static str,
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// A map YAML file is not valid YAML or a field has the wrong type.
    #[error("map file `{}` is malformed: {message}", path.display())]
    Yaml {
        /// The YAML file.
        path: PathBuf,
        /// The parser's message, with line and column.
        message: String,
    },
    /// A required field of a map YAML file is missing.
    #[error("map file `{}` has no `{field}` field", path.display())]
    MissingField {
        /// The YAML file.
        path: PathBuf,
        /// The missing field.
        field: &'static str,
    },
    /// A field of a map YAML file has an invalid value.
    #[error("map file `{}`: `{field}` is {value}; {reason}", path.display())]
    InvalidField {
        /// The YAML file.
        path: PathBuf,
        /// The field.
        field: &'static str,
        /// The value found, as text.
        value: String,
        /// What is wrong with it.
        reason: String,
    },
    /// A map image is malformed (truncated, bad header, value above the maximum).
    #[error("map image `{}` is malformed: {reason}", path.display())]
    MalformedImage {
        /// The image file.
        path: PathBuf,
        /// What is wrong, with the values.
        reason: String,
    },
    /// A map image is in a format or variant this crate does not read.
    #[error("map image `{}` is not supported: {reason}", path.display())]
    UnsupportedImage {
        /// The image file.
        path: PathBuf,
        /// Which format or variant it is.
        reason: String,
    },
    /// A Moving AI `.map` or `.scen` text is malformed.
    #[error("Moving AI {kind} {}line {line}: {reason}", file_prefix(file.as_deref()))]
    MovingAi {
        /// `"map"` or `"scenario"`.
        kind: &'static str,
        /// The file, when the text was read from one.
        file: Option<PathBuf>,
        /// 1-based line number of the offending line (one past the last line when the text
        /// ends too early).
        line: usize,
        /// What is wrong, with the values found.
        reason: String,
    },
    /// A planner's start or goal cell is outside the grid.
    #[error("{endpoint} ({x}, {y}) is outside the {width} x {height} grid")]
    EndpointOutsideGrid {
        /// `"start"` or `"goal"`.
        endpoint: &'static str,
        /// Column of the cell.
        x: usize,
        /// Row of the cell, from the top.
        y: usize,
        /// Grid width, cells.
        width: usize,
        /// Grid height, cells.
        height: usize,
    },
    /// A planner's start or goal cell is not traversable.
    #[error("{endpoint} ({x}, {y}) is an {} cell, which is not traversable", cell_name(*cell))]
    EndpointBlocked {
        /// `"start"` or `"goal"`.
        endpoint: &'static str,
        /// Column of the cell.
        x: usize,
        /// Row of the cell, from the top.
        y: usize,
        /// What the cell holds.
        cell: Occupancy,
    },
    /// An incremental planner's search state could not be followed to the goal (a bug).
    #[error(
        "{planner} could not follow its search from cell ({x}, {y}) to the goal; please report this"
    )]
    InconsistentSearch {
        /// The planner.
        planner: &'static str,
        /// Column of the cell.
        x: usize,
        /// Row of the cell, from the top.
        y: usize,
    },
    /// The believed and true maps of a navigation differ in size or resolution.
    #[error(
        "the believed map and the true map differ in {what}: believed {believed}, true {truth}; give maps of one grid"
    )]
    MapMismatch {
        /// What differs.
        what: &'static str,
        /// The believed map's value.
        believed: String,
        /// The true map's value.
        truth: String,
    },
}

fn file_prefix(file: Option<&Path>) -> String {
    file.map(|p| format!("`{}` ", p.display()))
        .unwrap_or_default()
}

fn cell_name(cell: Occupancy) -> &'static str {
    match cell {
        Occupancy::Free => "free",
        Occupancy::Occupied => "occupied",
        Occupancy::Unknown => "unknown",
    }
}

/// Result alias of this crate.
pub type Result<T, E = PlanError> = std::result::Result<T, E>;

/// The explanation of [`PlanError::Stopped`].
fn stopped_message(reason: StopReason, allowed_s: f64) -> String {
    match reason {
        StopReason::Deadline => format!(
            "it did not finish within its time limit of {} s; plan on a coarser grid, or allow more time",
            vpmap_files::num((allowed_s * 1e3).round() / 1e3)
        ),
        StopReason::Cancelled => "the request was cancelled".to_owned(),
    }
}

/// The work memory of `cells` grid cells, in readable units ("540 MB", "3.5 GB").
fn megabytes(cells: usize) -> String {
    let bytes = cells as f64 * BYTES_PER_CELL as f64;
    if bytes >= 1e15 {
        format!("{bytes:.1e} bytes")
    } else if bytes >= 1e9 {
        format!("{:.1} GB", bytes / 1e9)
    } else {
        format!("{:.0} MB", bytes / 1e6)
    }
}

/// A cell count that may have saturated at `usize::MAX`.
fn count(n: usize) -> String {
    if n == usize::MAX {
        format!("more than {}", vpmap_files::num(usize::MAX as f64))
    } else {
        n.to_string()
    }
}

//! Progress reporting: the measurements say what they are doing through [`Progress`]; the
//! command line draws it as a progress bar, a test ignores it.

/// Receives a long run's progress. Every method has an empty default.
///
/// Implementations must be `Sync`: the map-accuracy trials run in parallel and report from
/// several threads.
pub trait Progress: Sync {
    /// The run starts `total` steps (scenes, planner runs or photos).
    fn start(&self, total: u64) {
        let _ = total;
    }
    /// What the next step is ("maze512-1-0 query 3 mbpp").
    fn message(&self, text: &str) {
        let _ = text;
    }
    /// One step is done.
    fn step(&self) {}
    /// A line worth showing above the bar (a map finished, ...).
    fn note(&self, line: &str) {
        let _ = line;
    }
    /// Where a long run is, once per stage (a map begins), for a log with no progress bar
    /// to show it (the command line prints it only when stderr is not a terminal).
    fn milestone(&self, line: &str) {
        let _ = line;
    }
    /// A warning: the run goes on with less than asked ("no Moving AI data; generated maps
    /// only").
    fn warn(&self, line: &str) {
        let _ = line;
    }
    /// The run is over.
    fn finish(&self) {}
}

/// Reports nothing.
#[derive(Clone, Copy, Debug, Default)]
pub struct Silent;

impl Progress for Silent {}

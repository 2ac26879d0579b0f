//! `vpmap.plan`, `vpmap.Planner` and `vpmap.Path`: a path across a grid by any planner of
//! `vpmap plan`, endpoints checked and planners run by the pipeline as `vpmap plan` does.

use std::sync::Mutex;
use std::time::{Duration, Instant};

use numpy::PyArray2;
use numpy::ndarray::Array2;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use vpmap_pipeline::{Limits, OptionNames, PlanningMap, mbpp_stats};
use vpmap_plan::budget::{Budget, Stop, StopReason};
use vpmap_plan::planner::{BuiltIn, PlannerKind};
use vpmap_plan::{CellXy, PlanError, Planned, Planner as _};

use crate::convert::{error, point};
use crate::grid::{Grid, cells_from_array};
use crate::smooth::{SmoothArgs, plan_smooth_path};

/// A planner's error in the command line's words, ending with the keyword that raises the
/// budget (as `vpmap plan` ends it with the flag).
pub(crate) fn plan_error(e: &PlanError) -> PyErr {
    match e {
        PlanError::BudgetExhausted { option, .. } => error(format!("{e} with {option}")),
        PlanError::Stopped {
            reason: StopReason::Deadline,
            ..
        } => error(format!("{e} with timeout")),
        _ => error(e),
    }
}

/// The planner kind by its name, as `vpmap plan --planner` reads it.
fn planner_kind(name: &str) -> PyResult<PlannerKind> {
    if name == "smooth" {
        return Err(error(
            "planner \"smooth\" is for vpmap.plan (with turning_radius); a Planner keeps a grid planner's arrays",
        ));
    }
    name.parse::<PlannerKind>().map_err(|e| error(&e))
}

/// The work limits of a query from the keywords.
pub(crate) fn limits(
    max_expansions: Option<usize>,
    max_bug_steps: Option<usize>,
    timeout: Option<f64>,
) -> PyResult<Limits> {
    let stop = match timeout {
        None => Stop::new(),
        Some(t) if t.is_finite() && t > 0.0 && t <= 86_400.0 => {
            Stop::new().with_timeout(Duration::from_secs_f64(t))
        }
        Some(t) => {
            return Err(error(format!(
                "timeout {} is not a time limit; give a number of seconds above 0 and at most 86400",
                vpmap_pipeline::num(t)
            )));
        }
    };
    Ok(Limits {
        mbpp: Some((
            max_bug_steps.unwrap_or(vpmap_plan::mbpp::DEFAULT_MAX_BUG_STEPS),
            vpmap_plan::mbpp::DEFAULT_MAX_ALTERNATIVES,
        )),
        budget: Budget {
            max_expansions: max_expansions.unwrap_or(vpmap_plan::budget::DEFAULT_MAX_EXPANSIONS),
            stop,
            ..Budget::default()
        },
    })
}

/// Call `with` on the grid to plan on: a `Grid`'s, or an array's (a grid in cells, converted
/// at each call: pass a `Grid` to plan many times), inflated by `robot_radius` unless it is 0.
fn with_planning_map<T>(
    py: Python<'_>,
    grid: &Bound<'_, PyAny>,
    robot_radius: f64,
    with: impl FnOnce(&PlanningMap) -> PyResult<T>,
) -> PyResult<T> {
    let owned;
    let base: &PlanningMap = if let Ok(g) = grid.cast::<Grid>() {
        &g.get().map
    } else {
        let (width, height, cells) = cells_from_array(grid)?;
        let made = vpmap_plan::OccupancyGrid::from_cells(width, height, 1.0, [0.0; 2], cells)
            .map_err(error)?;
        owned = PlanningMap {
            grid: made,
            in_cells: true,
            robot_radius: 0.0,
        };
        &owned
    };
    if robot_radius == 0.0 {
        return with(base);
    }
    let radius = robot_radius * base.scale();
    let inflated = py.detach(|| base.grid.inflate(radius)).map_err(|e| {
        error(format!(
            "robot_radius {}: {e}",
            vpmap_pipeline::num(robot_radius)
        ))
    })?;
    with(&PlanningMap {
        grid: inflated,
        in_cells: base.in_cells,
        robot_radius,
    })
}

/// The cells of `start` and `goal` on `map`, checked as `vpmap plan` checks `--from`/`--to`.
fn endpoints(
    map: &PlanningMap,
    start: [f64; 2],
    goal: [f64; 2],
    unknown_passable: bool,
) -> PyResult<(CellXy, CellXy)> {
    let s = map
        .endpoint("start", start, unknown_passable, OptionNames::WebApi)
        .map_err(error)?;
    let g = map
        .endpoint("goal", goal, unknown_passable, OptionNames::WebApi)
        .map_err(error)?;
    Ok((s, g))
}

/// Find a path from ``start`` to ``goal`` across ``grid``, as ``vpmap plan`` does.
///
/// ``grid`` is a ``Grid`` (or a 2-D array, taken as a grid in cells and converted at each
/// call). ``start`` and ``goal`` are ``(x, y)``: cells ``(column, row)`` on a grid in cells,
/// metres in the map frame on a grid with a resolution. ``planner`` is one of ``"astar"``,
/// ``"astar-ps"``, ``"theta-star"``, ``"mbpp"``, ``"mbpp-closer"`` or ``"optimal"`` (the exact
/// shortest any-angle path). ``robot_radius`` inflates the obstacles first (the grid's
/// units). ``unknown_passable`` lets the path cross unknown cells; ``tracks`` records MBPP's
/// bugs' cells (for drawing). ``max_expansions``, ``max_bug_steps`` and ``timeout`` (seconds)
/// bound the work (defaults as ``vpmap plan``'s).
///
/// ``planner="smooth"`` plans a path a car-like robot can drive (lines and arcs of radius at
/// least ``turning_radius``, the grid's units), with optional ``start_heading`` and
/// ``goal_heading`` (degrees, ``atan2(dy, dx)`` in the grid's coordinates; free when left
/// out) and ``reverse`` (cusps allowed), as ``vpmap plan --planner smooth``; it returns a
/// ``SmoothPath`` whose ``poses`` are an N x 3 array of ``(x, y, heading_deg)``.
///
/// Returns a ``Path`` (``found`` False when start and goal are not connected). The GIL is
/// released while it plans. Raises ``VpmapError`` for bad input or a budget run out.
#[pyfunction]
#[pyo3(signature = (grid, start, goal, planner="mbpp", robot_radius=0.0, *, unknown_passable=false, tracks=false, max_expansions=None, max_bug_steps=None, timeout=None, turning_radius=None, start_heading=None, goal_heading=None, reverse=false))]
#[allow(clippy::too_many_arguments)]
pub fn plan(
    py: Python<'_>,
    grid: &Bound<'_, PyAny>,
    start: &Bound<'_, PyAny>,
    goal: &Bound<'_, PyAny>,
    planner: &str,
    robot_radius: f64,
    unknown_passable: bool,
    tracks: bool,
    max_expansions: Option<usize>,
    max_bug_steps: Option<usize>,
    timeout: Option<f64>,
    turning_radius: Option<f64>,
    start_heading: Option<f64>,
    goal_heading: Option<f64>,
    reverse: bool,
) -> PyResult<Py<PyAny>> {
    let start = point("start", start)?;
    let goal = point("goal", goal)?;
    if planner == "smooth" {
        let args = SmoothArgs {
            turning_radius,
            headings_deg: [start_heading, goal_heading],
            reverse,
            unknown_passable,
            max_expansions,
            timeout,
        };
        return with_planning_map(py, grid, robot_radius, |map| {
            let path = plan_smooth_path(py, map, start, goal, &args)?;
            Ok(Py::new(py, path)?.into_any())
        });
    }
    if turning_radius.is_some() || start_heading.is_some() || goal_heading.is_some() || reverse {
        return Err(error(format!(
            "turning_radius, start_heading, goal_heading and reverse are for planner=\"smooth\", not \"{planner}\""
        )));
    }
    let kind = planner_kind(planner)?;
    let limits = limits(max_expansions, max_bug_steps, timeout)?;
    with_planning_map(py, grid, robot_radius, |map| {
        let ends = endpoints(map, start, goal, unknown_passable)?;
        let began = Instant::now();
        let outcome = py
            .detach(|| {
                vpmap_pipeline::run_planner(
                    kind,
                    &map.grid,
                    ends,
                    unknown_passable,
                    tracks,
                    &limits,
                )
            })
            .map_err(|e| plan_error(&e))?;
        let seconds = began.elapsed().as_secs_f64();
        Ok(Py::new(py, Path::of(py, map, kind, &outcome, seconds)?)?.into_any())
    })
}

/// A planner bound to one grid, keeping its precomputation across queries: A*'s search
/// arrays, and the exact planner's (``"optimal"``) free space, built at the first query.
///
/// ``Planner(grid, planner="optimal", robot_radius=0.0, *, unknown_passable=False, ...)``;
/// ``.plan(start, goal)`` -> ``Path``, as ``vpmap.plan``. One ``Planner`` answers one query at
/// a time (a lock); give each thread its own to plan in parallel.
#[pyclass(frozen, name = "Planner", module = "vpmap")]
pub struct PyPlanner {
    map: PlanningMap,
    kind: PlannerKind,
    unknown_passable: bool,
    max_expansions: Option<usize>,
    max_bug_steps: Option<usize>,
    timeout: Option<f64>,
    inner: Mutex<BuiltIn>,
}

#[pymethods]
impl PyPlanner {
    #[new]
    #[pyo3(signature = (grid, planner="optimal", robot_radius=0.0, *, unknown_passable=false, max_expansions=None, max_bug_steps=None, timeout=None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        grid: &Bound<'_, PyAny>,
        planner: &str,
        robot_radius: f64,
        unknown_passable: bool,
        max_expansions: Option<usize>,
        max_bug_steps: Option<usize>,
        timeout: Option<f64>,
    ) -> PyResult<Self> {
        let kind = planner_kind(planner)?;
        limits(max_expansions, max_bug_steps, timeout)?;
        let map = with_planning_map(py, grid, robot_radius, |map| Ok(map.clone()))?;
        Ok(Self {
            map,
            kind,
            unknown_passable,
            max_expansions,
            max_bug_steps,
            timeout,
            inner: Mutex::new(kind.planner(unknown_passable)),
        })
    }

    /// Plan from ``start`` to ``goal`` (as ``vpmap.plan``), reusing what earlier queries on
    /// this grid computed. The GIL is released while it plans.
    fn plan(
        &self,
        py: Python<'_>,
        start: &Bound<'_, PyAny>,
        goal: &Bound<'_, PyAny>,
    ) -> PyResult<Path> {
        let start = point("start", start)?;
        let goal = point("goal", goal)?;
        let (s, g) = endpoints(&self.map, start, goal, self.unknown_passable)?;
        let limits = limits(self.max_expansions, self.max_bug_steps, self.timeout)?;
        let began = Instant::now();
        let outcome = py.detach(|| {
            let mut inner = self
                .inner
                .lock()
                .map_err(|_| error("a planner thread failed; make a new Planner"))?;
            // The budget (and its deadline) is per query; the planner keeps its arrays.
            let fresh = self.kind.planner(self.unknown_passable);
            let mut built = std::mem::replace(&mut *inner, fresh).with_budget(limits.budget);
            if let Some((steps, alternatives)) = limits.mbpp {
                built = built.with_mbpp_budget(steps, alternatives);
            }
            let result = built.plan(&self.map.grid, s, g);
            *inner = built;
            result.map_err(|e| plan_error(&e))
        })?;
        let seconds = began.elapsed().as_secs_f64();
        Path::of(py, &self.map, self.kind, &outcome, seconds)
    }

    /// The grid it plans on (inflated by its robot radius).
    #[getter]
    fn grid(&self) -> Grid {
        Grid::of(self.map.clone())
    }

    /// The planner's name.
    #[getter]
    fn planner(&self) -> &'static str {
        self.kind.name()
    }

    fn __repr__(&self) -> String {
        format!(
            "Planner({}, {} x {} grid)",
            self.kind.name(),
            self.map.grid.width(),
            self.map.grid.height()
        )
    }
}

/// A planned path (``vpmap.plan``, ``Planner.plan``).
#[pyclass(frozen, module = "vpmap")]
pub struct Path {
    /// Whether a path was found.
    #[pyo3(get)]
    found: bool,
    /// Its length in the grid's units (``None`` when none was found).
    #[pyo3(get)]
    length: Option<f64>,
    /// Nodes expanded (MBPP: bug steps).
    #[pyo3(get)]
    expanded: usize,
    /// The planner's name.
    #[pyo3(get)]
    planner: &'static str,
    /// The grid's units: ``"m"`` or ``"cells"``.
    #[pyo3(get)]
    units: &'static str,
    /// Seconds the planner took (the GIL released).
    #[pyo3(get)]
    time_s: f64,
    /// Waypoints.
    len: usize,
    waypoints: Py<PyArray2<f64>>,
    cells: Py<PyArray2<i64>>,
    stats: Py<PyDict>,
    alternatives: Py<PyList>,
    bugs: Py<PyList>,
}

/// A path's coordinates (N x 2, the map's units) and cells (N x 2, column and row).
type PathArrays<'py> = (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<i64>>);

/// The cells of a path as an N x 2 array (column, row), and their coordinates.
fn path_arrays<'py>(
    py: Python<'py>,
    map: &PlanningMap,
    cells: &[CellXy],
) -> PyResult<PathArrays<'py>> {
    let coords: Vec<f64> = cells.iter().flat_map(|&c| map.coords(c)).collect();
    let xy: Vec<i64> = cells
        .iter()
        .flat_map(|c| [c.x as i64, c.y as i64])
        .collect();
    let coords = Array2::from_shape_vec((cells.len(), 2), coords).map_err(error)?;
    let xy = Array2::from_shape_vec((cells.len(), 2), xy).map_err(error)?;
    Ok((
        PyArray2::from_owned_array(py, coords),
        PyArray2::from_owned_array(py, xy),
    ))
}

impl Path {
    /// The path object of a planner's answer, in `map`'s units (as `vpmap plan --json`).
    fn of(
        py: Python<'_>,
        map: &PlanningMap,
        kind: PlannerKind,
        outcome: &Planned,
        seconds: f64,
    ) -> PyResult<Self> {
        let scale = map.scale();
        let best = outcome.best.as_ref();
        let (waypoints, cells) = path_arrays(py, map, best.map_or(&[], |p| &p.waypoints))?;
        let stats = PyDict::new(py);
        let expanded = if let Some(s) = mbpp_stats(kind, outcome) {
            for (key, value) in vpmap_pipeline::planning::mbpp_counters(&s) {
                stats.set_item(key, value)?;
            }
            s.bug_steps
        } else {
            let s = best.map(|p| p.stats).unwrap_or_default();
            for (key, value) in [
                ("expanded", s.expanded),
                ("generated", s.generated),
                ("los_checks", s.los_checks),
                ("los_cells", s.los_cells),
            ] {
                stats.set_item(key, value)?;
            }
            s.expanded
        };
        stats.set_item("time_s", seconds)?;
        let alternatives = PyList::empty(py);
        for p in &outcome.alternatives {
            let (w, c) = path_arrays(py, map, &p.waypoints)?;
            let alt = Self {
                found: true,
                length: Some(p.length_cells * scale),
                expanded: 0,
                planner: kind.name(),
                units: map.unit(),
                time_s: 0.0,
                len: p.waypoints.len(),
                waypoints: w.unbind(),
                cells: c.unbind(),
                stats: PyDict::new(py).unbind(),
                alternatives: PyList::empty(py).unbind(),
                bugs: PyList::empty(py).unbind(),
            };
            alternatives.append(Py::new(py, alt)?)?;
        }
        let bugs = PyList::empty(py);
        for b in &outcome.bugs {
            let bug = PyDict::new(py);
            bug.set_item("parent", b.parent)?;
            bug.set_item("cells", path_arrays(py, map, &b.cells)?.1)?;
            bug.set_item("hits", path_arrays(py, map, &b.hits)?.1)?;
            bug.set_item("leaves", path_arrays(py, map, &b.leaves)?.1)?;
            bug.set_item("steps", b.steps)?;
            bug.set_item("fate", format!("{:?}", b.fate))?;
            bugs.append(bug)?;
        }
        Ok(Self {
            found: best.is_some(),
            length: best.map(|p| p.length_cells * scale),
            expanded,
            planner: kind.name(),
            units: map.unit(),
            time_s: seconds,
            len: best.map_or(0, |p| p.waypoints.len()),
            waypoints: waypoints.unbind(),
            cells: cells.unbind(),
            stats: stats.unbind(),
            alternatives: alternatives.unbind(),
            bugs: bugs.unbind(),
        })
    }
}

#[pymethods]
impl Path {
    /// The path's corners as an N x 2 float64 array of ``(x, y)`` in the grid's units (cell
    /// centres in metres, or ``(column, row)`` on a grid in cells), start first; empty when
    /// none was found.
    #[getter]
    fn waypoints<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        self.waypoints.bind(py).clone()
    }

    /// The path's corners as an N x 2 int64 array of cells ``(column, row)``.
    #[getter]
    fn cells<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<i64>> {
        self.cells.bind(py).clone()
    }

    /// The planner's counters, as ``vpmap plan --json`` prints them (``expanded``,
    /// ``generated``, ``los_checks``, ``los_cells``, MBPP's ``bugs``, ``hits``, ...).
    #[getter]
    fn stats<'py>(&self, py: Python<'py>) -> Bound<'py, PyDict> {
        self.stats.bind(py).clone()
    }

    /// MBPP's other feasible paths, shortest first, each a ``Path`` (empty for the others).
    #[getter]
    fn alternatives<'py>(&self, py: Python<'py>) -> Bound<'py, PyList> {
        self.alternatives.bind(py).clone()
    }

    /// MBPP's bugs, in order of birth: dicts with ``parent``, ``cells`` (walked, with
    /// ``tracks=True``), ``hits``, ``leaves`` (N x 2 cell arrays), ``steps`` and ``fate``.
    #[getter]
    fn bugs<'py>(&self, py: Python<'py>) -> Bound<'py, PyList> {
        self.bugs.bind(py).clone()
    }

    fn __len__(&self) -> usize {
        self.len
    }

    fn __repr__(&self) -> String {
        match self.length {
            Some(l) => format!(
                "Path({}: length {l:.3} {} through {} waypoints)",
                self.planner,
                self.units,
                self.__len__()
            ),
            None => format!("Path({}: no path)", self.planner),
        }
    }
}

//! `vpmap.plan(..., planner="smooth")` and `vpmap.SmoothPath`: a curvature-bounded path (lines
//! and arcs of radius at least the turning radius) as `vpmap plan --planner smooth` plans it,
//! in the grid's units and coordinates.

use std::time::Instant;

use numpy::PyArray2;
use numpy::ndarray::Array2;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use vpmap_pipeline::{OptionNames, PlanningMap, smooth_json, smooth_options};
use vpmap_plan::smooth::{Pose, SmoothOutcome, plan_smooth};

use crate::convert::{error, json_to_py};
use crate::plan::{limits, plan_error};

/// What `vpmap.plan` reads for the smooth planner, beyond the grid and the endpoints.
pub(crate) struct SmoothArgs {
    /// The smallest turning radius, the grid's units.
    pub turning_radius: Option<f64>,
    /// The start and goal headings, degrees, `atan2(dy, dx)` in the grid's coordinates.
    pub headings_deg: [Option<f64>; 2],
    /// Whether the robot may drive in reverse.
    pub reverse: bool,
    /// Whether unknown cells may be entered.
    pub unknown_passable: bool,
    /// The any-angle search's and the Hybrid-A*'s expansions and states together.
    pub max_expansions: Option<usize>,
    /// Seconds.
    pub timeout: Option<f64>,
}

/// Plan a smooth path on `map` from `start` to `goal` (the map's units), as
/// `vpmap plan --planner smooth` does; the GIL is released while it plans.
pub(crate) fn plan_smooth_path(
    py: Python<'_>,
    map: &PlanningMap,
    start: [f64; 2],
    goal: [f64; 2],
    args: &SmoothArgs,
) -> PyResult<SmoothPath> {
    let Some(radius) = args.turning_radius else {
        return Err(error(
            "planner \"smooth\" needs turning_radius (the grid's units: metres, or cells)",
        ));
    };
    let mut opts = smooth_options(
        map,
        radius,
        "turning_radius",
        args.headings_deg,
        args.reverse,
    )
    .map_err(error)?;
    let names = OptionNames::WebApi;
    let s = map
        .endpoint("start", start, args.unknown_passable, names)
        .map_err(error)?;
    let g = map
        .endpoint("goal", goal, args.unknown_passable, names)
        .map_err(error)?;
    opts.unknown_passable = args.unknown_passable;
    opts.budget = limits(args.max_expansions, None, args.timeout)?.budget;
    let began = Instant::now();
    let outcome = py
        .detach(|| plan_smooth(&map.grid, s, g, &opts))
        .map_err(|e| plan_error(&e))?;
    let seconds = began.elapsed().as_secs_f64();
    let asked = [(s, opts.start_heading_rad), (g, opts.goal_heading_rad)]
        .map(|(c, h)| Pose::new(c.x as f64, c.y as f64, h.unwrap_or(0.0)));
    let json = smooth_json(map, &outcome, asked, seconds);
    SmoothPath::of(py, map, &outcome, &json, seconds)
}

/// A curvature-bounded path (``vpmap.plan(..., planner="smooth")``).
///
/// ``poses`` is an N x 3 array of ``(x, y, heading_deg)`` at most a quarter cell apart, the
/// first and last the asked start and goal (a free heading is the path's there);
/// ``segments`` the lines and arcs exactly (as ``vpmap plan --planner smooth --json``).
/// Without a path, ``found`` is False and ``reason`` says why (which pose has no room to
/// turn, and how much room a turn needs).
#[pyclass(frozen, module = "vpmap")]
pub struct SmoothPath {
    /// Whether a drivable path was found.
    #[pyo3(get)]
    found: bool,
    /// Its length in the grid's units (``None`` when none was found).
    #[pyo3(get)]
    length: Option<f64>,
    /// The grid's units: ``"m"`` or ``"cells"``.
    #[pyo3(get)]
    units: &'static str,
    /// Seconds the planner took (the GIL released).
    #[pyo3(get)]
    time_s: f64,
    /// Why there is no path (``None`` when there is one).
    #[pyo3(get)]
    reason: Option<String>,
    /// Its largest curvature, 1 / the grid's unit (``None`` without a path).
    #[pyo3(get)]
    max_curvature: Option<f64>,
    /// Its smallest clearance over every point of the curve, the grid's units (``None``
    /// without a path).
    #[pyo3(get)]
    min_clearance: Option<f64>,
    /// Changes between driving forward and in reverse.
    #[pyo3(get)]
    cusps: usize,
    len: usize,
    poses: Py<PyArray2<f64>>,
    answer: Py<PyDict>,
}

impl SmoothPath {
    /// The path object of the planner's answer and its JSON (`smooth_json`).
    fn of(
        py: Python<'_>,
        map: &PlanningMap,
        outcome: &SmoothOutcome,
        json: &serde_json::Value,
        seconds: f64,
    ) -> PyResult<Self> {
        let scale = map.scale();
        let poses: Vec<f64> = match outcome {
            SmoothOutcome::Path(p) => p
                .poses
                .iter()
                .flat_map(|&q| vpmap_pipeline::smooth::pose_in_map(map, q))
                .collect(),
            SmoothOutcome::NoPath(_) => Vec::new(),
        };
        let len = poses.len() / 3;
        let poses = Array2::from_shape_vec((len, 3), poses).map_err(error)?;
        let answer = json_to_py(py, json)?.cast_into::<PyDict>()?;
        let (found, length, reason, max_curvature, min_clearance, cusps) = match outcome {
            SmoothOutcome::Path(p) => (
                true,
                Some(p.length_cells * scale),
                None,
                Some(p.max_curvature / scale),
                Some(p.min_clearance_cells * scale),
                p.cusps,
            ),
            SmoothOutcome::NoPath(_) => (
                false,
                None,
                json.get("reason")
                    .and_then(serde_json::Value::as_str)
                    .map(str::to_owned),
                None,
                None,
                0,
            ),
        };
        Ok(Self {
            found,
            length,
            units: map.unit(),
            time_s: seconds,
            reason,
            max_curvature,
            min_clearance,
            cusps,
            len,
            poses: PyArray2::from_owned_array(py, poses).unbind(),
            answer: answer.unbind(),
        })
    }
}

#[pymethods]
impl SmoothPath {
    /// The poses along the path as an N x 3 float64 array of ``(x, y, heading_deg)`` in the
    /// grid's units and coordinates, at most a quarter cell apart; empty when none was found.
    #[getter]
    fn poses<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        self.poses.bind(py).clone()
    }

    /// The lines and arcs, each a dict: ``type`` (``"line"`` or ``"arc"``), ``start`` and
    /// ``end`` poses, ``length``, ``direction`` (``"forward"`` or ``"reverse"``) and, for an
    /// arc, ``centre``, ``radius`` and ``turn`` (``"left"`` or ``"right"``).
    #[getter]
    fn segments<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        match self.answer.bind(py).get_item("segments")? {
            Some(s) => Ok(s),
            None => Ok(pyo3::types::PyList::empty(py).into_any()),
        }
    }

    /// The whole answer as ``vpmap plan --planner smooth --json`` prints it (a dict).
    #[getter]
    fn answer<'py>(&self, py: Python<'py>) -> Bound<'py, PyDict> {
        self.answer.bind(py).clone()
    }

    fn __len__(&self) -> usize {
        self.len
    }

    fn __repr__(&self) -> String {
        match self.length {
            Some(l) => format!(
                "SmoothPath(found, length {} {})",
                vpmap_pipeline::num(l),
                self.units
            ),
            None => format!(
                "SmoothPath(not found: {})",
                self.reason.as_deref().unwrap_or("")
            ),
        }
    }
}

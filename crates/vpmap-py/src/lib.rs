//! The `vpmap` Python module: numpy in and out over the library crates, conversion only.
//!
//! Every function here converts Python values into the library crates' types, calls the same
//! library function the `vpmap` command calls (so results and messages match), and converts
//! the answer back. Nothing is computed here that the libraries do not compute.
//!
//! | Python | calls | module |
//! |---|---|---|
//! | `vpmap.build` | `vpmap_pipeline::parse_scene`, `vpmap_pipeline::map_and_grid` (as `vpmap build`) | `map` |
//! | `Map.occupancy` | `vpmap_pipeline::occupancy_grid` | `map` |
//! | `vpmap.Grid` | `vpmap_plan::OccupancyGrid::from_cells`, `vpmap_pipeline::read_planning_map`, `vpmap_plan::write_ros_map` | `grid` |
//! | `vpmap.plan`, `vpmap.Planner` | `vpmap_pipeline::PlanningMap::endpoint`, `vpmap_pipeline::run_planner` and the plan crate's `Planner` (as `vpmap plan`) | `plan` |
//! | `vpmap.plan(..., planner="smooth")`, `vpmap.SmoothPath` | `vpmap_pipeline::smooth_options`, `vpmap_plan::smooth::plan_smooth`, `vpmap_pipeline::smooth_json` (as `vpmap plan --planner smooth`) | `smooth` |
//! | `vpmap.detect` | `vpmap_vision::detect`, `vpmap_vision::scene::detected_scene` (as `vpmap detect`) | `detect` |
//! | `vpmap.navigate` | `vpmap_plan::navigate`, `vpmap_pipeline::navigate_json` (as `vpmap navigate`) | `navigate` |
//! | `vpmap.navigate(..., planner="smooth")` | `vpmap_pipeline::smooth_options`, `vpmap_plan::navigate::navigate_smooth`, `vpmap_pipeline::navigate_smooth_json` (as `vpmap navigate --planner smooth`) | `navigate` |
//!
//! Errors: every library error becomes `vpmap.VpmapError` (a `ValueError`) with the message
//! the command line prints, option names written as the Python keywords. No panic crosses into
//! Python: pyo3 turns one into `pyo3_runtime.PanicException`, and the library crates do not
//! panic on bad input. Long work runs with the GIL released (`Python::detach`).
//!
//! Modules, bottom-up: `convert` (values both ways, `VpmapError`), `grid`, `map`, `plan`,
//! `smooth`, `detect`, `navigate`.

mod convert;
mod detect;
mod grid;
mod map;
mod navigate;
mod plan;
mod smooth;

use pyo3::prelude::*;

/// vpmap: single-view metrology from vanishing points -> metric floor map -> occupancy grid
/// -> path planners.
///
/// photo -> ``detect`` -> scene dict -> ``build`` -> ``Map`` -> ``Map.occupancy`` -> ``Grid``
/// -> ``plan`` / ``Planner`` -> ``Path``. Errors raise ``VpmapError`` (a ``ValueError``)
/// with the message the ``vpmap`` command prints. See docs/python.md.
#[pymodule]
fn _vpmap(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("VpmapError", py.get_type::<convert::VpmapError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<grid::Grid>()?;
    m.add_class::<map::Map>()?;
    m.add_class::<plan::Path>()?;
    m.add_class::<plan::PyPlanner>()?;
    m.add_class::<smooth::SmoothPath>()?;
    m.add_class::<detect::PyDetection>()?;
    m.add_function(wrap_pyfunction!(map::build, m)?)?;
    m.add_function(wrap_pyfunction!(plan::plan, m)?)?;
    m.add_function(wrap_pyfunction!(detect::detect, m)?)?;
    m.add_function(wrap_pyfunction!(navigate::navigate, m)?)?;
    Ok(())
}

//! `vpmap.build` and `vpmap.Map`: a scene (dict, JSON text or file) to its floor map, read
//! by the pipeline's one scene reader and built by the pipeline as `vpmap build` builds it.

use std::path::{Path, PathBuf};

use numpy::PyArray2;
use numpy::ndarray::Array2;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyString};
use vpmap_metrology::map::FloorMap;
use vpmap_metrology::reconstruct::Method;
use vpmap_pipeline::{MapOptions, ParsedScene, PipelineError, PlanningMap};
use vpmap_plan::OccupancyGrid;

use crate::convert::{as_path, error, json_text_to_py, shown};
use crate::grid::Grid;

/// A pipeline error in the command line's words, option names as the Python keywords
/// (`resolution must be ..., got 0`), as `vpmap build`'s `pipeline_error` words them with
/// flags.
pub(crate) fn pipeline_error(e: PipelineError) -> PyErr {
    match e {
        PipelineError::OptionOutOfRange { option, value } => error(format!(
            "{} must be {}, got {}",
            option.key(),
            option.requirement(),
            vpmap_pipeline::num(value)
        )),
        PipelineError::Model(e) => error(format!("building model.glb: {e}")),
        PipelineError::Grid(e) => error(format!("rasterising the occupancy grid: {e}")),
        e => error(crate::convert::with_causes(&e)),
    }
}

/// Where a scene came from: its file, or `None` for a dict or JSON text.
type Source = Option<PathBuf>;

/// The scene's JSON text and where it came from.
fn scene_text(scene: &Bound<'_, PyAny>) -> PyResult<(String, Source)> {
    let py = scene.py();
    if scene.is_instance_of::<PyDict>() {
        let dumps = py.import("json")?.getattr("dumps")?;
        let text: String = dumps
            .call1((scene,))
            .map_err(|e| error(format!("the scene dict cannot be written as JSON: {e}")))?
            .extract()?;
        return Ok((text, None));
    }
    if scene.is_instance_of::<PyString>() {
        let text: String = scene.extract()?;
        if text.trim_start().starts_with('{') {
            return Ok((text, None));
        }
    }
    let Some(path) = as_path(scene) else {
        return Err(error(format!(
            "scene {} is neither a dict, JSON text nor a file path",
            shown(scene)
        )));
    };
    let text = vpmap_files::read_text(&path, vpmap_files::Format::Scene).map_err(error)?;
    // Editors on Windows may start the file with a byte-order mark; it is not JSON.
    let text = text.strip_prefix('\u{feff}').unwrap_or(&text).to_owned();
    Ok((text, Some(path)))
}

/// The scene read by the pipeline's one scene reader, with the command line's messages for a
/// file (`FILE: scene file is malformed: ...`, `FILE: <why it is invalid>`).
fn parse(text: &str, source: Option<&Path>) -> PyResult<ParsedScene> {
    let prefix = source.map_or_else(String::new, |p| format!("{}: ", p.display()));
    vpmap_pipeline::parse_scene(text).map_err(|e| match (e, source) {
        (PipelineError::SceneNotAnObject, Some(_)) => error(format!(
            "{prefix}scene file is malformed: it must be a JSON object ({{ ... }})"
        )),
        (PipelineError::SceneJson(e), Some(_)) => {
            error(format!("{prefix}scene file is malformed: {e}"))
        }
        (PipelineError::InvalidScene { error: e, .. }, _) => error(format!("{prefix}{e}")),
        (other, _) => error(other),
    })
}

/// Build a scene into a metric floor map, as ``vpmap build`` does.
///
/// ``scene`` is a dict, JSON text, or the path of a scene file (a single photo's scene, or a
/// room of several photos where the library reads them; see docs/scene-format.md).
/// ``method`` is ``"fit"`` (the joint fit with error bars), ``"sideview"`` (the thesis's
/// method) or ``"projective"``; ``click_sigma`` the click noise in pixels the error bars are
/// for (default: estimated from the clicks). Returns a ``Map``.
///
/// Raises ``VpmapError`` with the message ``vpmap build`` prints.
#[pyfunction]
#[pyo3(signature = (scene, *, method="fit", click_sigma=None))]
pub fn build(
    py: Python<'_>,
    scene: &Bound<'_, PyAny>,
    method: &str,
    click_sigma: Option<f64>,
) -> PyResult<Map> {
    let method: Method = method.parse().map_err(error)?;
    let (text, source) = scene_text(scene)?;
    let parsed = py.detach(|| parse(&text, source.as_deref()))?;
    let options = MapOptions {
        method,
        click_sigma_px: click_sigma,
        max_grid_cells: Some(vpmap_plan::MAX_CELLS as f64),
        ..MapOptions::default()
    };
    let scene = &parsed.scene;
    let built = py
        .detach(|| vpmap_pipeline::map_and_grid(scene, &options))
        .map_err(|e| match &source {
            Some(path) => error(format!(
                "building {}: {}",
                path.display(),
                pipeline_error(e).value(py)
            )),
            None => pipeline_error(e),
        })?;
    let json = built.map.to_json_string();
    let mut warnings = parsed.warnings;
    warnings.extend(built.map.warnings.iter().cloned());
    Ok(Map {
        built: built.map,
        default_grid: built.grid,
        options,
        json,
        warnings,
    })
}

/// A metric floor map built from a scene (``vpmap.build``): the camera, the objects with
/// their sizes and error bars, the floor outline and free space, as in ``map.json``
/// (docs/map-format.md).
#[pyclass(frozen, module = "vpmap")]
pub struct Map {
    built: FloorMap,
    /// The occupancy grid at the default options, made by the build.
    default_grid: OccupancyGrid,
    /// The options it was built with (method, click sigma; the grid's defaults).
    options: MapOptions,
    /// `map.json`'s text.
    json: String,
    /// The scene's unknown fields, then the map's warnings.
    warnings: Vec<String>,
}

impl Map {
    /// One top-level field of `map.json` as a Python object.
    fn field<'py>(&self, py: Python<'py>, key: &str) -> PyResult<Bound<'py, PyAny>> {
        let dict = self.to_dict(py)?;
        let found = dict.cast::<PyDict>()?.get_item(key)?;
        Ok(found.unwrap_or_else(|| py.None().into_bound(py)))
    }
}

#[pymethods]
impl Map {
    /// The camera: ``focal_px``, ``principal_point``, ``pitch_deg``, ``roll_deg``, ``height``,
    /// ``position``, the vanishing points, and with the fit its ``uncertainty`` (1 sigma).
    #[getter]
    fn camera<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.field(py, "camera")
    }

    /// The objects, one dict each: ``name``, ``footprint``, ``height``, ``size`` (``length``,
    /// ``breadth``), ``centroid``, ``area`` and with the fit ``uncertainty`` (standard
    /// deviations and the centroid's 95 % ellipse).
    #[getter]
    fn objects<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.field(py, "objects")
    }

    /// The floor outline as an N x 2 float64 array of map coordinates (``x`` right, ``y``
    /// away from the camera).
    #[getter]
    fn floor<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let flat: Vec<f64> = self.built.floor.iter().flatten().copied().collect();
        let array = Array2::from_shape_vec((self.built.floor.len(), 2), flat).map_err(error)?;
        Ok(PyArray2::from_owned_array(py, array))
    }

    /// The free floor: a list of polygons, each ``{"exterior": [...], "holes": [...]}``.
    #[getter]
    fn free_space<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.field(py, "free_space")
    }

    /// The fit's report (click sigma, RMS residual, ...), or ``None`` for other methods.
    #[getter]
    fn fit<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.field(py, "fit")
    }

    /// ``"m"``, or ``"camera_heights"`` for a scene without a scale.
    #[getter]
    fn units(&self) -> &'static str {
        vpmap_pipeline::units_name(self.built.units)
    }

    /// The reconstruction method: ``"fit"``, ``"sideview"`` or ``"projective"``.
    #[getter]
    fn method(&self) -> String {
        self.built.method.to_string()
    }

    /// Warnings: the scene's unknown fields, sizes the clicks leave uncertain, clicks that
    /// disagree with the fitted model (what ``vpmap build`` prints as ``warning:``).
    #[getter]
    fn warnings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        PyList::new(py, &self.warnings)
    }

    /// The map as the JSON text ``vpmap build`` writes to ``map.json``.
    fn to_json(&self) -> &str {
        &self.json
    }

    /// The map as a dict (``json.loads(map.to_json())``).
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json_text_to_py(py, &self.json)
    }

    /// The occupancy grid ``vpmap build`` writes (``occupancy.yaml``): cells of
    /// ``resolution`` metres, obstacles inflated by ``robot_radius`` metres, each grown by
    /// its uncertainty at ``grow_confidence`` (e.g. 0.95; method fit only) when given; floor
    /// hidden behind objects unknown unless ``hidden_free``. Returns a ``Grid`` in metres.
    #[pyo3(signature = (resolution=0.05, robot_radius=0.2, grow_confidence=None, hidden_free=false))]
    fn occupancy(
        &self,
        py: Python<'_>,
        resolution: f64,
        robot_radius: f64,
        grow_confidence: Option<f64>,
        hidden_free: bool,
    ) -> PyResult<Grid> {
        let options = MapOptions {
            resolution_m: resolution,
            robot_radius_m: robot_radius,
            grow_confidence,
            hidden_free,
            ..self.options
        };
        let grid = if options == self.options {
            self.default_grid.clone()
        } else {
            options.validate().map_err(pipeline_error)?;
            let map = &self.built;
            py.detach(|| vpmap_pipeline::occupancy_grid(map, &options))
                .map_err(pipeline_error)?
        };
        Ok(Grid::of(PlanningMap {
            grid,
            in_cells: false,
            robot_radius,
        }))
    }

    fn __repr__(&self) -> String {
        format!(
            "Map({} objects, {} floor corners, method {}, units {})",
            self.built.objects.len(),
            self.built.floor.len(),
            self.built.method,
            vpmap_pipeline::units_name(self.built.units)
        )
    }
}

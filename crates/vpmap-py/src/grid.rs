//! `vpmap.Grid`: an occupancy grid from a numpy array or a map file, and back.
//!
//! The array form: a 2-D array, row 0 at the top (as an image, and as the plan crate's
//! `(x, y)` = (column, row)), `0` free, `1` occupied, `-1` or `255` unknown; a `bool` array
//! means occupied where `True`. `Grid.array` gives `int8` back (`-1` unknown).

use std::path::PathBuf;

use numpy::ndarray::{Array2, ArrayView2};
use numpy::{Element, PyArray2, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use vpmap_pipeline::PlanningMap;
use vpmap_plan::{Occupancy, OccupancyGrid};

use crate::convert::{as_path, error, shown};

/// The array form's values, named in messages.
const VALUES: &str = "0 free, 1 occupied, -1 or 255 unknown; or bools, True occupied";

/// An occupancy grid: cells free, occupied or unknown, with an optional metric frame.
///
/// ``Grid(array, resolution=None, origin=(0.0, 0.0))`` makes one from a 2-D numpy array (or
/// anything ``numpy.asarray`` takes), row 0 at the top: 0 free, 1 occupied, -1 or 255
/// unknown; a bool array is occupied where True. Any integer dtype and memory order is
/// converted; floats and other shapes are refused with ``VpmapError``.
///
/// Without ``resolution`` the grid's coordinates are cells ``(column, row)``, as a Moving AI
/// map's; with it they are metres in the map frame (``+y`` up), ``origin`` being the
/// lower-left corner of the lower-left cell (the ROS ``map_server`` convention).
///
/// ``Grid.load(path)`` reads a ROS map ``.yaml``, a Moving AI ``.map`` or a vpmap
/// ``map.json``, as ``vpmap plan`` does.
#[pyclass(frozen, module = "vpmap")]
pub struct Grid {
    /// The grid and how its coordinates read.
    pub(crate) map: PlanningMap,
    /// `.array`, made once on first use.
    array: PyOnceLock<Py<PyArray2<i8>>>,
}

impl Grid {
    /// A grid object of a planning map.
    pub(crate) fn of(map: PlanningMap) -> Self {
        Self {
            map,
            array: PyOnceLock::new(),
        }
    }
}

/// An integer element type of an input array.
trait CellValue: Element + Copy {
    /// The value as a wide integer.
    fn wide(self) -> i128;
}

macro_rules! cell_value {
    ($($t:ty),*) => {$(
        impl CellValue for $t {
            fn wide(self) -> i128 {
                i128::from(self)
            }
        }
    )*};
}
cell_value!(i8, u8, i16, u16, i32, u32, i64, u64);

/// The cells of an integer array, row-major, or the first value that is not a cell.
fn integer_cells<T: CellValue>(view: &ArrayView2<'_, T>) -> PyResult<Vec<Occupancy>> {
    let mut cells = Vec::with_capacity(view.len());
    for ((row, column), &v) in view.indexed_iter() {
        cells.push(match v.wide() {
            0 => Occupancy::Free,
            1 => Occupancy::Occupied,
            -1 | 255 => Occupancy::Unknown,
            other => {
                return Err(error(format!(
                    "grid array holds {other} at row {row}, column {column}; the values are {VALUES}"
                )));
            }
        });
    }
    Ok(cells)
}

/// Try one integer dtype: `Some(cells)` when the array has it.
fn try_integer<T: CellValue>(array: &Bound<'_, PyAny>) -> Option<PyResult<Vec<Occupancy>>> {
    let typed = array.cast::<PyArray2<T>>().ok()?;
    let readonly = typed.readonly();
    Some(integer_cells(&readonly.as_array()))
}

/// Width, height and row-major cells of a 2-D array (anything `numpy.asarray` takes).
pub(crate) fn cells_from_array(obj: &Bound<'_, PyAny>) -> PyResult<(usize, usize, Vec<Occupancy>)> {
    let py = obj.py();
    let numpy = py.import("numpy")?;
    let array = numpy.getattr("asarray")?.call1((obj,)).map_err(|e| {
        error(format!(
            "{} is not an array: {e}; give a 2-D numpy array ({VALUES})",
            shown(obj)
        ))
    })?;
    let shape: Vec<usize> = array.getattr("shape")?.extract()?;
    let dtype = array.getattr("dtype")?.str()?.to_string();
    let [height, width] = shape[..] else {
        return Err(error(format!(
            "a grid array must be 2-D (rows, columns); got shape {} ({dtype})",
            shown(&array.getattr("shape")?)
        )));
    };
    let cells = if let Ok(typed) = array.cast::<PyArray2<bool>>() {
        let readonly = typed.readonly();
        Ok(readonly
            .as_array()
            .iter()
            .map(|&b| {
                if b {
                    Occupancy::Occupied
                } else {
                    Occupancy::Free
                }
            })
            .collect())
    } else {
        try_integer::<i8>(&array)
            .or_else(|| try_integer::<u8>(&array))
            .or_else(|| try_integer::<i16>(&array))
            .or_else(|| try_integer::<u16>(&array))
            .or_else(|| try_integer::<i32>(&array))
            .or_else(|| try_integer::<u32>(&array))
            .or_else(|| try_integer::<i64>(&array))
            .or_else(|| try_integer::<u64>(&array))
            .unwrap_or_else(|| {
                Err(error(format!(
                    "a grid array of dtype {dtype} is not a grid; give integers or bools ({VALUES})"
                )))
            })
    }?;
    Ok((width, height, cells))
}

/// The cells as `int8`: 0 free, 1 occupied, -1 unknown.
fn int8_cells(grid: &OccupancyGrid) -> Vec<i8> {
    grid.cells()
        .iter()
        .map(|c| match c {
            Occupancy::Free => 0,
            Occupancy::Occupied => 1,
            Occupancy::Unknown => -1,
        })
        .collect()
}

#[pymethods]
impl Grid {
    #[new]
    #[pyo3(signature = (array, resolution=None, origin=(0.0, 0.0)), text_signature = "(array, resolution=None, origin=(0.0, 0.0))")]
    fn new(
        py: Python<'_>,
        array: &Bound<'_, PyAny>,
        resolution: Option<f64>,
        origin: (f64, f64),
    ) -> PyResult<Self> {
        let (width, height, cells) = cells_from_array(array)?;
        let grid = py
            .detach(|| {
                OccupancyGrid::from_cells(
                    width,
                    height,
                    resolution.unwrap_or(1.0),
                    [origin.0, origin.1],
                    cells,
                )
            })
            .map_err(error)?;
        Ok(Self::of(PlanningMap {
            grid,
            in_cells: resolution.is_none(),
            robot_radius: 0.0,
        }))
    }

    /// Read a map file as ``vpmap plan`` does: a ROS map ``.yaml`` (metres), a Moving AI
    /// ``.map`` (cells) or a vpmap ``map.json`` (rasterised at ``resolution`` metres, obstacles
    /// inflated by ``robot_radius``, by default 0.2 m for a map.json and 0 for the others;
    /// metres, cells for a ``.map``).
    #[staticmethod]
    #[pyo3(signature = (path, robot_radius=None, resolution=0.05))]
    fn load(
        py: Python<'_>,
        path: &Bound<'_, PyAny>,
        robot_radius: Option<f64>,
        resolution: f64,
    ) -> PyResult<Self> {
        let path =
            as_path(path).ok_or_else(|| error(format!("{} is not a file path", shown(path))))?;
        let map = py
            .detach(|| vpmap_pipeline::read_planning_map(&path, robot_radius, resolution))
            .map_err(error)?;
        Ok(Self::of(map))
    }

    /// Write the grid as a ROS ``map_server`` map: ``path`` (the ``.yaml``) and its ``.pgm``
    /// image beside it; returns the image's path. A grid in cells is written at 1 m a cell.
    fn save_ros(&self, py: Python<'_>, path: &Bound<'_, PyAny>) -> PyResult<String> {
        let path: PathBuf =
            as_path(path).ok_or_else(|| error(format!("{} is not a file path", shown(path))))?;
        let grid = &self.map.grid;
        let image = py
            .detach(|| vpmap_plan::write_ros_map(grid, &path))
            .map_err(error)?;
        Ok(image.display().to_string())
    }

    /// A copy with its obstacles inflated by ``robot_radius`` (metres; cells for a grid in
    /// cells): cells whose centre is closer than that to an occupied cell become occupied.
    fn inflate(&self, py: Python<'_>, robot_radius: f64) -> PyResult<Self> {
        let map = &self.map;
        let radius = robot_radius * map.scale();
        let grid = py.detach(|| map.grid.inflate(radius)).map_err(error)?;
        Ok(Self::of(PlanningMap {
            grid,
            in_cells: map.in_cells,
            robot_radius: map.robot_radius + robot_radius,
        }))
    }

    /// The cells as a read-only ``int8`` array of shape ``(height, width)``, row 0 at the top:
    /// 0 free, 1 occupied, -1 unknown. Made once and kept: reading it again returns the same
    /// array without copying (``.array.copy()`` to edit, ``Grid(edited)`` for a new grid).
    #[getter]
    fn array<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<i8>>> {
        let array = self.array.get_or_try_init(py, || -> PyResult<_> {
            let grid = &self.map.grid;
            let shape = (grid.height(), grid.width());
            let cells = int8_cells(grid);
            let owned = Array2::from_shape_vec(shape, cells).map_err(error)?;
            let array = PyArray2::from_owned_array(py, owned);
            Ok(array
                .readwrite()
                .make_nonwriteable()
                .as_unbound()
                .clone_ref(py))
        })?;
        Ok(array.bind(py).clone())
    }

    /// Metres a cell, or ``None`` for a grid in cells.
    #[getter]
    fn resolution(&self) -> Option<f64> {
        (!self.map.in_cells).then(|| self.map.grid.resolution_m())
    }

    /// The map-frame position ``(x, y)`` of the lower-left corner of the lower-left cell,
    /// metres, or ``None`` for a grid in cells.
    #[getter]
    fn origin(&self) -> Option<(f64, f64)> {
        let [x, y] = self.map.grid.origin_m();
        (!self.map.in_cells).then_some((x, y))
    }

    /// ``(height, width)``, as the array's shape.
    #[getter]
    fn shape(&self) -> (usize, usize) {
        (self.map.grid.height(), self.map.grid.width())
    }

    /// Columns.
    #[getter]
    fn width(&self) -> usize {
        self.map.grid.width()
    }

    /// Rows.
    #[getter]
    fn height(&self) -> usize {
        self.map.grid.height()
    }

    /// The unit of points on this grid: ``"m"`` or ``"cells"``.
    #[getter]
    fn units(&self) -> &'static str {
        self.map.unit()
    }

    /// The radius the obstacles were inflated by when the grid was made (``Grid.load``,
    /// ``Map.occupancy``, ``inflate``), in the grid's units.
    #[getter]
    fn robot_radius(&self) -> f64 {
        self.map.robot_radius
    }

    /// Cells ``(free, occupied, unknown)``.
    #[getter]
    fn counts(&self) -> (usize, usize, usize) {
        self.map.grid.counts()
    }

    /// The map-frame coordinates of a cell's centre (column, row) in the grid's units.
    fn world_from_cell(&self, column: usize, row: usize) -> (f64, f64) {
        let [x, y] = self.map.coords(vpmap_plan::CellXy::new(column, row));
        (x, y)
    }

    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other.cast::<Grid>().is_ok_and(|o| {
            o.get().map.grid == self.map.grid && o.get().map.in_cells == self.map.in_cells
        })
    }

    fn __repr__(&self) -> String {
        let g = &self.map.grid;
        let (free, occupied, unknown) = g.counts();
        let frame = if self.map.in_cells {
            "in cells".to_owned()
        } else {
            let [x, y] = g.origin_m();
            format!("{} m a cell from ({x}, {y})", g.resolution_m())
        };
        format!(
            "Grid({} x {} cells, {frame}: {free} free, {occupied} occupied, {unknown} unknown)",
            g.width(),
            g.height()
        )
    }
}

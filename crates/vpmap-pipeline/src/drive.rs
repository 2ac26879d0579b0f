//! What `vpmap navigate` needs besides the drive itself: the believed and true maps
//! ([`drive_maps`], from files or maps in hand), a synthetic scene's truth read from its file
//! ([`is_truth_file`], [`read_truth`]), an empty grid framing it ([`truth_frame`], for a drive
//! that starts knowing nothing), and the drive's report file, `navigate.json`
//! ([`navigate_json`]; format in docs/navigation.md).

use std::path::{Path, PathBuf};

use vpmap_metrology::synth::Truth;
use vpmap_plan::grid::{CellXy, Occupancy, OccupancyGrid};
use vpmap_plan::navigate::{Navigation, OnlinePlanner, Outcome, TruthOptimum};
use vpmap_raster::truth_grid;

use crate::error::PipelineError;
use crate::options::DEFAULT_ROBOT_RADIUS_M;
use crate::planning::{PlanningMap, read_planning_map};
use crate::ranges::BuildOption;

/// One map of a drive: a file (a `map.json`, ROS `.yaml` or Moving AI `.map`, read by
/// [`read_planning_map`]; for the true map also a synthetic scene's `*.truth.json`) or a map
/// in hand.
#[derive(Debug, Clone)]
pub enum DriveMap {
    /// A map file.
    File(PathBuf),
    /// A map already read.
    Given(PlanningMap),
}

impl DriveMap {
    fn read(
        self,
        robot_radius: Option<f64>,
        resolution_m: f64,
    ) -> Result<PlanningMap, PipelineError> {
        match self {
            DriveMap::File(path) => read_planning_map(&path, robot_radius, resolution_m),
            DriveMap::Given(map) => Ok(map),
        }
    }
}

/// The believed map of a drive and the true grid on the same cells, as `vpmap navigate` reads
/// them. A synthetic truth is rasterised on the believed map's grid (or, with no believed map,
/// on an all-unknown grid of `resolution_m` framing it); any other true map is read as a map,
/// and no believed map means an all-unknown grid of its size. `robot_radius` as
/// [`read_planning_map`] (a truth's obstacles are grown by the believed map's radius).
///
/// # Errors
/// What reading either map gives ([`read_planning_map`], [`read_truth`], [`truth_frame`]); the
/// true map's wrapped in [`PipelineError::TrueMap`]; [`PipelineError::TruthWithCells`] for a
/// synthetic truth with a believed map in cells; [`PipelineError::Grid`] when the truth
/// cannot be rasterised.
pub fn drive_maps(
    believed: Option<DriveMap>,
    truth: DriveMap,
    robot_radius: Option<f64>,
    resolution_m: f64,
) -> Result<(PlanningMap, OccupancyGrid), PipelineError> {
    if let DriveMap::File(path) = &truth
        && is_truth_file(path)
    {
        let truth = read_truth(path)?;
        let believed = match believed {
            Some(b) => b.read(robot_radius, resolution_m)?,
            None => PlanningMap {
                grid: truth_frame(&truth, resolution_m)?,
                in_cells: false,
                robot_radius: robot_radius.unwrap_or(DEFAULT_ROBOT_RADIUS_M),
            },
        };
        if believed.in_cells {
            return Err(PipelineError::TruthWithCells);
        }
        let grid = truth_grid(&truth, &believed.grid, believed.robot_radius)
            .map_err(PipelineError::Grid)?;
        return Ok((believed, grid));
    }
    let path = match &truth {
        DriveMap::File(path) => Some(path.clone()),
        DriveMap::Given(_) => None,
    };
    let truth = truth
        .read(robot_radius, resolution_m)
        .map_err(|error| match path {
            Some(path) => PipelineError::TrueMap {
                path,
                error: Box::new(error),
            },
            None => error,
        })?;
    let believed = match believed {
        Some(b) => b.read(robot_radius, resolution_m)?,
        None => PlanningMap {
            grid: OccupancyGrid::new(
                truth.grid.width(),
                truth.grid.height(),
                truth.grid.resolution_m(),
                truth.grid.origin_m(),
                Occupancy::Unknown,
            )
            .map_err(|e| PipelineError::Grid(e.into()))?,
            in_cells: truth.in_cells,
            robot_radius: truth.robot_radius,
        },
    };
    Ok((believed, truth.grid))
}

/// Whether `path` names a synthetic scene's truth: its file name ends in `.truth.json` (any
/// case), as `vpmap synth` writes it.
#[must_use]
pub fn is_truth_file(path: &Path) -> bool {
    path.file_name().is_some_and(|n| {
        n.to_string_lossy()
            .to_ascii_lowercase()
            .ends_with(".truth.json")
    })
}

/// A synthetic scene's truth (`*.truth.json`, as `vpmap synth` writes it).
///
/// # Errors
/// [`PipelineError::File`] when the file cannot be read, [`PipelineError::NotATruth`] when it
/// is not a truth.
pub fn read_truth(path: &Path) -> Result<Truth, PipelineError> {
    let text =
        vpmap_files::read_text(path, vpmap_files::Format::Map).map_err(PipelineError::File)?;
    serde_json::from_str(&text).map_err(|source| PipelineError::NotATruth {
        path: path.to_path_buf(),
        source,
    })
}

/// An all-unknown grid of cells of `resolution_m` around a truth's floor outline, one cell of
/// border on every side.
///
/// # Errors
/// [`PipelineError::NoTruthFloor`] when the truth has no finite floor outline,
/// [`PipelineError::OptionOutOfRange`] for [`BuildOption::Resolution`] when `resolution_m`
/// is not a positive number, and [`PipelineError::Grid`] for a grid too large to make.
pub fn truth_frame(truth: &Truth, resolution_m: f64) -> Result<OccupancyGrid, PipelineError> {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in &truth.floor {
        for ((l, h), v) in lo.iter_mut().zip(hi.iter_mut()).zip(p) {
            *l = l.min(*v);
            *h = h.max(*v);
        }
    }
    if !(lo.iter().chain(&hi).all(|v| v.is_finite())) {
        return Err(PipelineError::NoTruthFloor);
    }
    if !(resolution_m.is_finite() && resolution_m > 0.0) {
        return Err(PipelineError::OptionOutOfRange {
            option: BuildOption::Resolution,
            value: resolution_m,
        });
    }
    let cells = |l: f64, h: f64| ((h - l) / resolution_m).ceil().max(1.0) as usize + 2;
    OccupancyGrid::new(
        cells(lo[0], hi[0]),
        cells(lo[1], hi[1]),
        resolution_m,
        [lo[0] - resolution_m, lo[1] - resolution_m],
        Occupancy::Unknown,
    )
    .map_err(|e| PipelineError::Grid(e.into()))
}

/// What a drive's report says besides the drive: who drove, how, in which units.
#[derive(Debug, Clone, Copy)]
pub struct DriveReport<'a> {
    /// The drive.
    pub run: &'a Navigation,
    /// The true map's optima between the same start and goal.
    pub optimum: &'a TruthOptimum,
    /// The online planner.
    pub planner: OnlinePlanner,
    /// Unknown cells were believed free.
    pub unknown_passable: bool,
    /// The sensor's range, cells.
    pub sensor_range_cells: f64,
    /// Map units per cell.
    pub scale: f64,
    /// The map's unit: `m` or `cells`.
    pub unit: &'a str,
}

/// `navigate.json` (format in docs/navigation.md); `coords` gives a cell's place in the map's
/// coordinates.
#[must_use]
pub fn navigate_json(
    report: &DriveReport<'_>,
    coords: &dyn Fn(CellXy) -> [f64; 2],
) -> serde_json::Value {
    let DriveReport {
        run,
        optimum,
        planner,
        unknown_passable,
        sensor_range_cells,
        scale,
        unit,
    } = *report;
    let events: Vec<serde_json::Value> = run
        .events
        .iter()
        .map(|e| {
            serde_json::json!({
                "moves": e.moves,
                "cell": [e.cell.x, e.cell.y],
                "at": coords(e.cell),
                "reason": e.reason.as_str(),
                "time_s": e.time_s,
                "expanded": e.expanded,
                "planned_length": e.planned_length_cells.map(|l| l * scale),
                "used_alternative": e.used_alternative,
                "doubted_cells": e.doubted_cells,
            })
        })
        .collect();
    let excess = |opt: Option<f64>| opt.filter(|&o| o > 0.0).map(|o| run.length_cells / o - 1.0);
    serde_json::json!({
        "version": 1,
        "planner": planner.name(),
        "units": unit,
        "sensor_range_cells": sensor_range_cells,
        "unknown_passable": unknown_passable,
        "outcome": run.outcome.as_str(),
        "reached": run.outcome == Outcome::Reached,
        "moves": run.moves,
        "length": run.length_cells * scale,
        "length_cells": run.length_cells,
        "length_m": if unit == "m" { Some(run.length_cells * scale) } else { None },
        "optimum_octile": optimum.octile_cells.map(|l| l * scale),
        "optimum_any_angle": optimum.any_angle_cells.map(|l| l * scale),
        "excess_over_octile": excess(optimum.octile_cells),
        "excess_over_any_angle": excess(optimum.any_angle_cells),
        "replans": run.events.len().saturating_sub(1),
        "planning_time_s": run.planning_time_s,
        "expanded": run.expanded,
        "waypoints": run.waypoints.iter().map(|&c| coords(c)).collect::<Vec<_>>(),
        "cells": run.cells.iter().map(|c| [c.x, c.y]).collect::<Vec<_>>(),
        "events": events,
        "seen_cells": run.belief.seen.iter().filter(|&&s| s).count(),
    })
}

/// A sensor range in the map's units (`unit`, `scale` of them per cell) as cells: 10 cells
/// when none is given; refused, naming `option` and the value, below one cell or beyond
/// [`vpmap_plan::navigate::MAX_SENSOR_RANGE_CELLS`] (the command line's and the Python
/// module's check).
///
/// # Errors
/// The message for the user.
pub fn sensor_range_cells(
    range: Option<f64>,
    scale: f64,
    unit: &str,
    option: &str,
) -> Result<f64, String> {
    use vpmap_plan::navigate::MAX_SENSOR_RANGE_CELLS;
    let Some(r) = range else {
        return Ok(10.0);
    };
    let cells = r / scale;
    if !(r.is_finite() && (1.0..=MAX_SENSOR_RANGE_CELLS).contains(&cells)) {
        let num = crate::num;
        return Err(format!(
            "{option} {} {unit} is not a sensor range; give at least one cell ({} {unit}) and at most {} cells ({} {unit})",
            num(r),
            num(scale),
            num(MAX_SENSOR_RANGE_CELLS),
            num(MAX_SENSOR_RANGE_CELLS * scale)
        ));
    }
    Ok(cells)
}

#[cfg(test)]
mod tests {
    use super::*;
    use vpmap_metrology::synth::{SynthOptions, synthesize};

    #[test]
    fn a_truth_frame_holds_the_floor_with_a_cell_to_spare() {
        let (_, truth) = synthesize(&SynthOptions::default()).unwrap();
        let grid = truth_frame(&truth, 0.1).unwrap();
        let o = grid.origin_m();
        for p in &truth.floor {
            assert!(
                p[0] > o[0] + 0.1 - 1e-9 && p[1] > o[1] + 0.1 - 1e-9,
                "{p:?}"
            );
            assert!(p[0] < o[0] + 0.1 * (grid.width() - 1) as f64 + 1e-9);
            assert!(p[1] < o[1] + 0.1 * (grid.height() - 1) as f64 + 1e-9);
        }
        assert_eq!(grid.counts().2, grid.width() * grid.height());
        assert!(truth_frame(&truth, 0.0).is_err());
        let empty = Truth {
            floor: Vec::new(),
            ..truth
        };
        assert!(matches!(
            truth_frame(&empty, 0.1),
            Err(PipelineError::NoTruthFloor)
        ));
        assert!(is_truth_file(Path::new("out/Office.Truth.JSON")));
        assert!(!is_truth_file(Path::new("out/map.json")));
    }
}

//! A map file ready for planning ([`read_planning_map`]: a Moving AI `.map`, a ROS map `.yaml`
//! or a vpmap `map.json`, its obstacles inflated by the robot's radius), how its coordinates
//! read ([`PlanningMap`]), one planner run within counted limits ([`run_planner`]) and its
//! answer as JSON ([`plan_json`]), for `vpmap plan` and `vpmap navigate`.
//!
//! A `map.json` is rasterised by [`occupancy_grid`], the rasterisation `vpmap build` and the
//! page's `/api/plan` use: with the same resolution and radius (and hidden floor unknown), a
//! map.json gives the grid its scene gives on the page.

use std::path::Path;

use vpmap_metrology::map::FloorMap;
use vpmap_plan::PlanError;
use vpmap_plan::budget::Budget;
use vpmap_plan::grid::{CellXy, OccupancyGrid};
use vpmap_plan::mbpp::MbppStats;
use vpmap_plan::plan::Plan;
use vpmap_plan::planner::{Planned, Planner, PlannerKind};

use crate::endpoint::{Coordinates, Endpoint, EndpointRules, OptionNames, endpoint_cell};
use crate::error::PipelineError;
use crate::grid::occupancy_grid;
use crate::options::{DEFAULT_ROBOT_RADIUS_M, MapOptions};

/// A map ready for planning, and how its coordinates read.
#[derive(Debug, Clone)]
pub struct PlanningMap {
    /// The grid (inflated).
    pub grid: OccupancyGrid,
    /// Coordinates are cells (Moving AI) rather than metres.
    pub in_cells: bool,
    /// The radius the obstacles were inflated by, in the map's coordinates.
    pub robot_radius: f64,
}

impl PlanningMap {
    /// How points on this map read: cells for a Moving AI map, metres otherwise.
    #[must_use]
    pub fn coordinates(&self) -> Coordinates {
        if self.in_cells {
            Coordinates::Cells
        } else {
            Coordinates::Map { units: "m" }
        }
    }

    /// The cell of a path's start or goal `name` at `point`, which a path must be able to
    /// enter ([`endpoint_cell`]).
    ///
    /// # Errors
    /// [`PipelineError::Endpoint`] as [`endpoint_cell`].
    pub fn endpoint(
        &self,
        name: &str,
        point: [f64; 2],
        unknown_passable: bool,
        names: OptionNames,
    ) -> Result<CellXy, PipelineError> {
        let rules = EndpointRules {
            unknown_passable,
            robot_radius: self.robot_radius,
            names,
        };
        endpoint_cell(
            &self.grid,
            self.coordinates(),
            &Endpoint { name, point },
            &rules,
        )
    }

    /// A cell in the map's coordinates (its centre, for a map in metres).
    #[must_use]
    pub fn coords(&self, cell: CellXy) -> [f64; 2] {
        if self.in_cells {
            [cell.x as f64, cell.y as f64]
        } else {
            self.grid.world_from_cell(cell.x, cell.y)
        }
    }

    /// The coordinates' unit: `cells` or `m`.
    #[must_use]
    pub fn unit(&self) -> &'static str {
        if self.in_cells { "cells" } else { "m" }
    }

    /// Map units per cell: lengths in cells times this are in [`Self::unit`].
    #[must_use]
    pub fn scale(&self) -> f64 {
        if self.in_cells {
            1.0
        } else {
            self.grid.resolution_m()
        }
    }
}

/// Read any supported map, by its extension, and inflate its obstacles by `robot_radius`
/// (metres, cells for a Moving AI map; by default [`DEFAULT_ROBOT_RADIUS_M`] for a
/// `map.json`, the radius `vpmap build` uses, and 0 for the others, whose grids are inflated
/// already or are benchmark grids). A `map.json` is rasterised at `resolution_m` by
/// [`occupancy_grid`]. The radius is not range-checked here: the caller checks it against
/// [`crate::ROBOT_RADIUS_RANGE_M`] and words the message its own way.
///
/// # Errors
/// [`PipelineError::UnknownMapType`], [`PipelineError::File`] and [`PipelineError::NotAMap`]
/// for a file that cannot be read as a map, [`PipelineError::Rasterise`] for a `map.json`
/// that cannot be rasterised at `resolution_m`, and [`PipelineError::Grid`] for a grid file
/// the plan crate refuses or a radius it cannot inflate by.
pub fn read_planning_map(
    path: &Path,
    robot_radius: Option<f64>,
    resolution_m: f64,
) -> Result<PlanningMap, PipelineError> {
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    let is_map_json = ext == "json";
    let robot_radius = robot_radius.unwrap_or(if is_map_json {
        DEFAULT_ROBOT_RADIUS_M
    } else {
        0.0
    });
    let (grid, in_cells) = match ext.as_str() {
        "map" => (
            vpmap_plan::movingai::read_movingai_map(path)
                .map_err(|e| PipelineError::Grid(e.into()))?,
            true,
        ),
        "yaml" | "yml" => (
            vpmap_plan::ros::read_ros_map(path).map_err(|e| PipelineError::Grid(e.into()))?,
            false,
        ),
        "json" => {
            let text = vpmap_files::read_text(path, vpmap_files::Format::Map)
                .map_err(PipelineError::File)?;
            let map = FloorMap::from_json_str(&text).map_err(|source| PipelineError::NotAMap {
                path: path.to_path_buf(),
                source,
            })?;
            let options = MapOptions {
                resolution_m,
                robot_radius_m: robot_radius,
                ..MapOptions::default()
            };
            let grid = occupancy_grid(&map, &options).map_err(|e| match e {
                PipelineError::Grid(source) => PipelineError::Rasterise {
                    path: path.to_path_buf(),
                    resolution: resolution_m,
                    source,
                },
                other => other,
            })?;
            return Ok(PlanningMap {
                grid,
                in_cells: false,
                robot_radius,
            });
        }
        _ => {
            return Err(PipelineError::UnknownMapType {
                path: path.to_path_buf(),
            });
        }
    };
    let radius = if in_cells {
        robot_radius * grid.resolution_m()
    } else {
        robot_radius
    };
    let grid = grid
        .inflate(radius)
        .map_err(|e| PipelineError::Grid(e.into()))?;
    Ok(PlanningMap {
        grid,
        in_cells,
        robot_radius,
    })
}

/// The work limits of one planning query: MBPP's budget and every planner's [`Budget`].
#[derive(Clone, Debug, Default)]
pub struct Limits {
    /// MBPP's most bug steps and most alternatives kept (`None`: the plan crate's defaults).
    pub mbpp: Option<(usize, usize)>,
    /// The budget of A*, A* PS, Theta* and the exact planner, and every planner's stop.
    pub budget: Budget,
}

/// Run one planner (through the plan crate's [`Planner`] interface) and keep everything it
/// found: the path, MBPP's alternatives and bugs (with their walked cells when
/// `record_tracks`; that costs memory in proportion to the bugs' steps, so ask only when
/// drawing them), within `limits`.
///
/// # Errors
/// The planner's: bad input, a budget exhausted (naming the option that raises it), or a
/// stop.
pub fn run_planner(
    kind: PlannerKind,
    grid: &OccupancyGrid,
    (start, goal): (CellXy, CellXy),
    unknown_passable: bool,
    record_tracks: bool,
    limits: &Limits,
) -> Result<Planned, PlanError> {
    let mut planner = kind
        .planner(unknown_passable)
        .with_tracks(record_tracks)
        .with_budget(limits.budget.clone());
    if let Some((max_bug_steps, max_alternatives)) = limits.mbpp {
        planner = planner.with_mbpp_budget(max_bug_steps, max_alternatives);
    }
    planner.plan(grid, start, goal)
}

/// MBPP's counters, for the MBPP planners only (`None` for the others).
#[must_use]
pub fn mbpp_stats(kind: PlannerKind, planned: &Planned) -> Option<MbppStats> {
    matches!(kind, PlannerKind::Mbpp | PlannerKind::MbppCloser).then_some(planned.mbpp_stats)
}

/// MBPP's counters by the names `vpmap plan --json` and the Python module report them
/// (`expanded` is its bug steps, `generated` its bugs).
#[must_use]
pub fn mbpp_counters(s: &MbppStats) -> [(&'static str, usize); 9] {
    [
        ("expanded", s.bug_steps),
        ("generated", s.bugs),
        ("los_checks", s.los_checks),
        ("los_cells", s.los_cells),
        ("bugs", s.bugs),
        ("bug_steps", s.bug_steps),
        ("hits", s.hits),
        ("waits", s.waits),
        ("replans", s.replans),
    ]
}

/// The answer of `vpmap plan --json`, one object: `found`, `length` and `waypoints` in the
/// map's units, `planner`, MBPP's `alternatives`, and `stats` (the planner's counters, MBPP's
/// own when it is MBPP, and `time_s`, the `seconds` the planner took).
#[must_use]
pub fn plan_json(
    map: &PlanningMap,
    planner: PlannerKind,
    outcome: &Planned,
    seconds: f64,
) -> serde_json::Value {
    let scale = map.scale();
    let plan = outcome.best.as_ref();
    let waypoints =
        |p: &Plan| -> Vec<[f64; 2]> { p.waypoints.iter().map(|c| map.coords(*c)).collect() };
    let alternatives: Vec<serde_json::Value> = outcome
        .alternatives
        .iter()
        .map(|p| serde_json::json!({ "length": p.length_cells * scale, "waypoints": waypoints(p) }))
        .collect();
    let mut stats = serde_json::Map::new();
    if let Some(s) = mbpp_stats(planner, outcome) {
        // MBPP's own counters are there even when no path was found.
        for (key, value) in mbpp_counters(&s) {
            stats.insert(key.to_owned(), value.into());
        }
    } else {
        let s = plan.map(|p| p.stats).unwrap_or_default();
        for (key, value) in [
            ("expanded", s.expanded),
            ("generated", s.generated),
            ("los_checks", s.los_checks),
            ("los_cells", s.los_cells),
        ] {
            stats.insert(key.to_owned(), value.into());
        }
    }
    stats.insert("time_s".to_owned(), seconds.into());
    serde_json::json!({
        "found": plan.is_some(),
        "length": plan.map(|p| p.length_cells * scale),
        "units": map.unit(),
        "waypoints": plan.map(waypoints).unwrap_or_default(),
        "planner": planner.name(),
        "alternatives": alternatives,
        "stats": stats,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::build::map_and_grid;
    use vpmap_metrology::synth::{SynthOptions, synthesize};
    use vpmap_plan::budget::Stop;
    use vpmap_plan::grid::Occupancy;

    const BUDGET: &Limits = &Limits {
        mbpp: None,
        budget: Budget {
            max_expansions: vpmap_plan::budget::DEFAULT_MAX_EXPANSIONS,
            max_sight_cells: vpmap_plan::budget::DEFAULT_MAX_SIGHT_CELLS,
            stop: Stop::new(),
        },
    };

    #[test]
    fn a_map_json_gives_the_grid_its_scene_gives() {
        // `vpmap plan map.json` and the page's `/api/plan` on the scene: one rasterisation.
        let (scene, _) = synthesize(&SynthOptions {
            seed: 7,
            ..SynthOptions::default()
        })
        .unwrap();
        let options = MapOptions {
            resolution_m: 0.1,
            robot_radius_m: 0.3,
            ..MapOptions::default()
        };
        let page = map_and_grid(&scene, &options).unwrap();
        let dir = tempfile_dir();
        let path = dir.join("map.json");
        std::fs::write(&path, page.map.to_json_string()).unwrap();
        let cli = read_planning_map(&path, Some(0.3), 0.1).unwrap();
        let _ = std::fs::remove_dir_all(&dir);
        assert_eq!(cli.grid, page.grid);
        assert!(!cli.in_cells && cli.robot_radius.to_bits() == 0.3f64.to_bits());
    }

    /// A fresh folder under the system's temporary folder.
    fn tempfile_dir() -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!(
            "vpmap-pipeline-test-{}-{:?}",
            std::process::id(),
            std::thread::current().id()
        ));
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn map_files_of_unknown_types_are_named() {
        let e = read_planning_map(Path::new("floor.png"), None, 0.05).unwrap_err();
        assert_eq!(
            e.to_string(),
            "floor.png: unknown map type; give a Moving AI .map, a ROS map .yaml or a vpmap map.json"
        );
    }

    #[test]
    fn mbpp_tracks_are_recorded_only_when_asked() {
        // A wall across the straight line, open at both ends.
        let mut grid = OccupancyGrid::new(6, 5, 1.0, [0.0; 2], Occupancy::Free).unwrap();
        for y in 1..4 {
            grid.set(2, y, Occupancy::Occupied).unwrap();
        }
        let ends = (CellXy::new(0, 2), CellXy::new(5, 2));
        let quiet = run_planner(PlannerKind::Mbpp, &grid, ends, false, false, BUDGET).unwrap();
        let drawn = run_planner(PlannerKind::Mbpp, &grid, ends, false, true, BUDGET).unwrap();
        assert!(quiet.bugs.len() >= 2 && quiet.bugs.iter().all(|b| b.cells.is_empty()));
        assert_eq!(drawn.bugs.len(), quiet.bugs.len());
        assert_eq!(
            drawn.bugs.first().and_then(|b| b.cells.first()),
            Some(&ends.0)
        );
        assert!(drawn.bugs.iter().all(|b| !b.cells.is_empty()));
        assert_eq!(drawn.best, quiet.best);
        assert!(quiet.best.is_some());
        let other = run_planner(PlannerKind::ThetaStar, &grid, ends, false, true, BUDGET).unwrap();
        assert!(other.bugs.is_empty() && other.alternatives.is_empty());
        assert!(mbpp_stats(PlannerKind::Mbpp, &quiet).is_some());
        assert!(mbpp_stats(PlannerKind::ThetaStar, &other).is_none());
        let map = PlanningMap {
            grid,
            in_cells: true,
            robot_radius: 0.0,
        };
        let json = plan_json(&map, PlannerKind::Mbpp, &quiet, 0.5);
        assert_eq!(json["found"], true);
        assert_eq!(json["units"], "cells");
        assert_eq!(json["stats"]["bugs"], quiet.mbpp_stats.bugs);
        assert_eq!(json["waypoints"][0], serde_json::json!([0.0, 2.0]));
    }
}

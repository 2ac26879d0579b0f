//! The pipeline: a scene to its floor map and occupancy grid ([`map_and_grid`]), and to
//! everything `vpmap build` writes ([`build`]).

use vpmap_metrology::interrupt::Interrupt;
use vpmap_metrology::map::{BuildOptions, FloorMap, build_map_until};
use vpmap_metrology::scene::Scene;
use vpmap_plan::OccupancyGrid;
use vpmap_plan::ros::encode_ros_map;
use vpmap_render::{FloorPlanStyle, floor_plan_svg, model_glb};

use crate::error::PipelineError;
use crate::grid::occupancy_grid;
use crate::options::MapOptions;

/// A floor map and its occupancy grid.
#[derive(Debug, Clone)]
pub struct MapAndGrid {
    /// The floor map.
    pub map: FloorMap,
    /// Its occupancy grid, obstacles inflated by the robot radius.
    pub grid: OccupancyGrid,
}

/// Everything a build makes, in memory.
#[derive(Debug, Clone)]
pub struct Built {
    /// The floor map (`map.json`).
    pub map: FloorMap,
    /// Its occupancy grid, obstacles inflated by the robot radius.
    pub grid: OccupancyGrid,
    /// The glTF binary model (`model.glb`).
    pub model_glb: Vec<u8>,
    /// The ROS `map_server` YAML (`occupancy.yaml`), naming `occupancy.pgm` as its image.
    pub occupancy_yaml: String,
    /// The ROS map image (`occupancy.pgm`).
    pub occupancy_pgm: Vec<u8>,
    /// The floor plan (`map.svg`) in the default style.
    pub svg: String,
}

/// The floor map of a scene and its occupancy grid.
///
/// # Errors
/// An option out of range, a scene that cannot be built (calibration, reconstruction,
/// scale), a grid larger than [`MapOptions::max_grid_cells`], or a map that cannot be
/// rasterised.
pub fn map_and_grid(scene: &Scene, options: &MapOptions) -> Result<MapAndGrid, PipelineError> {
    map_and_grid_until(scene, options, &Interrupt::default())
}

/// [`map_and_grid`], stopping early when `interrupt` fires while a room is fitted
/// (`vpmap_metrology::map::build_map_until`): the page's time limit and its clients that go
/// away.
///
/// # Errors
/// As [`map_and_grid`], and `PipelineError::Map(MetrologyError::Interrupted)` when
/// `interrupt` fires.
pub fn map_and_grid_until(
    scene: &Scene,
    options: &MapOptions,
    interrupt: &Interrupt,
) -> Result<MapAndGrid, PipelineError> {
    options.validate()?;
    let map = floor_map(scene, options, interrupt)?;
    let grid = occupancy_grid(&map, options)?;
    Ok(MapAndGrid { map, grid })
}

/// Build everything `vpmap build` writes and `/api/build` returns: map, 3D model, occupancy
/// grid and its ROS files, and the floor plan in the default style.
///
/// # Errors
/// As [`map_and_grid`], and a map the 3D model cannot be made of.
pub fn build(scene: &Scene, options: &MapOptions) -> Result<Built, PipelineError> {
    build_until(scene, options, &Interrupt::default())
}

/// [`build`], stopping early when `interrupt` fires while a room is fitted (as
/// [`map_and_grid_until`]).
///
/// # Errors
/// As [`build`], and `PipelineError::Map(MetrologyError::Interrupted)` when `interrupt`
/// fires.
pub fn build_until(
    scene: &Scene,
    options: &MapOptions,
    interrupt: &Interrupt,
) -> Result<Built, PipelineError> {
    options.validate()?;
    let map = floor_map(scene, options, interrupt)?;
    let model_glb = model_glb(&map).map_err(PipelineError::Model)?;
    let grid = occupancy_grid(&map, options)?;
    let (occupancy_yaml, occupancy_pgm) = encode_ros_map(&grid, "occupancy.pgm");
    let svg = floor_plan_svg(&map, &FloorPlanStyle::default());
    Ok(Built {
        map,
        grid,
        model_glb,
        occupancy_yaml,
        occupancy_pgm,
        svg,
    })
}

fn floor_map(
    scene: &Scene,
    options: &MapOptions,
    interrupt: &Interrupt,
) -> Result<FloorMap, PipelineError> {
    build_map_until(
        scene,
        &BuildOptions {
            method: options.method,
            click_sigma_px: options.click_sigma_px,
        },
        interrupt,
    )
    .map_err(PipelineError::Map)
}

#[cfg(test)]
mod tests {
    use super::*;
    use vpmap_metrology::reconstruct::Method;
    use vpmap_metrology::synth::{SynthOptions, synthesize};
    use vpmap_plan::Occupancy;

    fn occupied(grid: &OccupancyGrid) -> usize {
        grid.cells()
            .iter()
            .filter(|c| **c == Occupancy::Occupied)
            .count()
    }

    #[test]
    fn growing_by_uncertainty_keeps_every_obstacle_cell_and_adds_some() {
        let (scene, _) = synthesize(&SynthOptions {
            seed: 4,
            noise_px: 2.0,
            ..SynthOptions::default()
        })
        .map_err(|e| e.to_string())
        .unwrap_or_else(|e| panic!("{e}"));
        let plain = MapOptions {
            click_sigma_px: Some(2.0),
            ..MapOptions::default()
        };
        let grown = MapOptions {
            grow_confidence: Some(0.95),
            ..plain
        };
        let a = map_and_grid(&scene, &plain).unwrap_or_else(|e| panic!("{e}"));
        let b = map_and_grid(&scene, &grown).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(a.map, b.map, "map.json keeps the fitted footprints");
        assert_eq!(
            (a.grid.width(), a.grid.height()),
            (b.grid.width(), b.grid.height())
        );
        let kept = a
            .grid
            .cells()
            .iter()
            .zip(b.grid.cells())
            .all(|(x, y)| *x != Occupancy::Occupied || *y == Occupancy::Occupied);
        assert!(kept, "every occupied cell stays occupied");
        assert!(occupied(&b.grid) > occupied(&a.grid));
        // Methods without error bars cannot grow.
        let e = MapOptions {
            method: Method::Sideview,
            ..grown
        }
        .validate()
        .unwrap_err()
        .to_string();
        assert!(e.contains("only the fit method"), "{e}");
    }

    #[test]
    fn a_room_builds_one_map_with_every_camera_in_every_output() {
        let text = include_str!("../../vpmap-metrology/tests/fixtures/room-mv00.json");
        let parsed = crate::scene::parse_scene(text).unwrap_or_else(|e| panic!("{e}"));
        assert!(parsed.warnings.is_empty(), "{:?}", parsed.warnings);
        let built = build(&parsed.scene, &MapOptions::default()).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(built.map.cameras.len(), 2);
        // The floor plan draws photo 2's camera; the model has a pyramid per camera.
        assert!(built.svg.contains(r#"<g id="cameras">"#) && built.svg.contains("photo 2"));
        let glb = String::from_utf8_lossy(&built.model_glb);
        assert!(glb.contains("\"camera 2\"") && glb.contains("\"heading_deg\""));
        // The grid covers both cameras' floor: more free cells than photo 1 alone.
        let photo1 = crate::scene::parse_scene(
            &serde_json::from_str::<serde_json::Value>(text).unwrap()["photos"][0].to_string(),
        )
        .unwrap_or_else(|e| panic!("{e}"));
        let alone =
            map_and_grid(&photo1.scene, &MapOptions::default()).unwrap_or_else(|e| panic!("{e}"));
        let free = |g: &OccupancyGrid| g.cells().iter().filter(|c| **c == Occupancy::Free).count();
        assert!(
            free(&built.grid) > free(&alone.grid),
            "{} vs {}",
            free(&built.grid),
            free(&alone.grid)
        );
    }
}

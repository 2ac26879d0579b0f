//! One build pipeline: a scene to its floor map, occupancy grid, 3D model and floor plan.
//!
//! `vpmap build`, `vpmap demo` and the page's `/api/build` and `/api/plan` all build here,
//! with one options type whose [`MapOptions::validate`] holds every range and whose default
//! robot radius ([`DEFAULT_ROBOT_RADIUS_M`], 0.2 m) is the same everywhere. The crate sits
//! above `vpmap-metrology` (the map), `vpmap-plan` (the grid) and `vpmap-render` (model and
//! picture), which it is the first crate to need all together.
//!
//! | function | what |
//! |---|---|
//! | [`map_and_grid`] | scene -> floor map and its occupancy grid (what `/api/plan` plans on) |
//! | [`build`] | scene -> map, grid, glTF model, ROS map files and floor-plan SVG (what `vpmap build` writes and `/api/build` returns) |
//! | [`endpoint_cell`] | a start or goal in map coordinates -> its grid cell, checked (`vpmap plan`, `/api/plan`) |
//!
//! # Example
//! ```
//! use vpmap_metrology::synth::{synthesize, SynthOptions};
//! use vpmap_pipeline::{build, MapOptions};
//! let (scene, _) = synthesize(&SynthOptions::default()).unwrap();
//! let built = build(&scene, &MapOptions::default()).unwrap();
//! assert!(built.model_glb.starts_with(b"glTF") && built.svg.contains("data-svg-from-map"));
//! assert_eq!(built.grid.resolution_m(), 0.05);
//! ```
#![deny(missing_docs)]
#![cfg_attr(test, allow(clippy::unwrap_used, clippy::expect_used))]

pub mod endpoint;
mod error;
pub mod options;

use nalgebra::Vector2;
use vpmap_metrology::map::{BuildOptions, FloorMap, ObjectUncertainty, Units, build_map};
use vpmap_metrology::scene::Scene;
use vpmap_plan::ros::encode_ros_map;
use vpmap_plan::{OccupancyGrid, RasterOptions, rasterize_map};
use vpmap_render::{FloorPlanStyle, floor_plan_svg, model_glb};

pub use endpoint::{Coordinates, Endpoint, EndpointRules, OptionNames, endpoint_cell};
pub use error::PipelineError;
pub use options::{
    BuildOption, DEFAULT_RESOLUTION_M, DEFAULT_ROBOT_RADIUS_M, GRID_MARGIN_M, MapOptions,
    RESOLUTION_RANGE_M, ROBOT_RADIUS_RANGE_M,
};

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

/// The name of a map's unit in messages and the web API: `m` or `camera_heights`.
#[must_use]
pub fn units_name(units: Units) -> &'static str {
    match units {
        Units::Meters => "m",
        Units::CameraHeights => "camera_heights",
    }
}

/// The floor map of a scene and its occupancy grid.
///
/// # Errors
/// An option out of range, a scene that cannot be built (calibration, reconstruction,
/// scale), a grid larger than [`MapOptions::max_grid_cells`], or a map that cannot be
/// rasterised.
pub fn map_and_grid(scene: &Scene, options: &MapOptions) -> Result<MapAndGrid, PipelineError> {
    options.validate()?;
    let map = floor_map(scene, options)?;
    let grid = occupancy_grid(&map, options)?;
    Ok(MapAndGrid { map, grid })
}

/// Build everything `vpmap build` writes and `/api/build` returns: map, 3D model, occupancy
/// grid and its ROS files, and the floor plan in the default style.
///
/// # Errors
/// As [`map_and_grid`], and a map the 3D model cannot be made of.
pub fn build(scene: &Scene, options: &MapOptions) -> Result<Built, PipelineError> {
    options.validate()?;
    let map = floor_map(scene, options)?;
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

fn floor_map(scene: &Scene, options: &MapOptions) -> Result<FloorMap, PipelineError> {
    build_map(
        scene,
        &BuildOptions {
            method: options.method,
            click_sigma_px: options.click_sigma_px,
        },
    )
    .map_err(PipelineError::Map)
}

/// Radius by which an obstacle is grown at confidence `p`: the radius of the centroid's
/// confidence circle of its larger standard deviation, `sqrt(-2 ln(1 - p))` sigmas (the
/// chi-square quantile with 2 degrees of freedom), plus half its larger side's standard
/// deviation at the same multiple. Conservative: the circle contains the ellipse.
#[must_use]
pub fn uncertainty_margin(u: &ObjectUncertainty, p: f64) -> f64 {
    let k = (-2.0 * (1.0 - p).ln()).sqrt();
    let c = u.centroid_covariance;
    let mean = 0.5 * (c[0][0] + c[1][1]);
    let det = c[0][0] * c[1][1] - c[0][1] * c[1][0];
    let largest = mean + (mean * mean - det).max(0.0).sqrt();
    let side = u.length_sd.unwrap_or(0.0).max(u.breadth_sd.unwrap_or(0.0));
    k * (largest.max(0.0).sqrt() + 0.5 * side)
}

/// The map with each obstacle grown by [`uncertainty_margin`] at confidence `p` and the free
/// space recomputed; objects without error bars stay as they are.
#[must_use]
pub fn grown_by_uncertainty(map: &FloorMap, p: f64) -> FloorMap {
    use geo::{Buffer, LineString, Polygon};
    let mut out = map.clone();
    for o in &mut out.objects {
        let Some(u) = &o.uncertainty else { continue };
        let r = uncertainty_margin(u, p);
        if !(r.is_finite() && r > 0.0) || o.footprint.len() < 3 {
            continue;
        }
        let poly = Polygon::new(
            LineString::from(o.footprint.iter().map(|q| (q[0], q[1])).collect::<Vec<_>>()),
            vec![],
        );
        let grown = poly.buffer(r);
        if let Some(largest) = grown
            .0
            .iter()
            .max_by(|a, b| geo::Area::unsigned_area(*a).total_cmp(&geo::Area::unsigned_area(*b)))
        {
            let mut ring: Vec<[f64; 2]> = largest.exterior().coords().map(|c| [c.x, c.y]).collect();
            if ring.len() > 1 && ring.first() == ring.last() {
                ring.pop();
            }
            o.footprint = ring;
        }
    }
    let floor: Vec<Vector2<f64>> = out.floor.iter().map(|p| Vector2::new(p[0], p[1])).collect();
    let footprints: Vec<Vec<Vector2<f64>>> = out
        .objects
        .iter()
        .map(|o| {
            o.footprint
                .iter()
                .map(|p| Vector2::new(p[0], p[1]))
                .collect()
        })
        .collect();
    out.free_space =
        vpmap_metrology::map::to_polygons(&vpmap_metrology::map::free_space(&floor, &footprints));
    out
}

/// The occupancy grid of a map; refused beyond [`MapOptions::max_grid_cells`] before any
/// cell is made.
fn occupancy_grid(map: &FloorMap, options: &MapOptions) -> Result<OccupancyGrid, PipelineError> {
    let grown;
    let map = match options.grow_confidence {
        Some(p) => {
            grown = grown_by_uncertainty(map, p);
            &grown
        }
        None => map,
    };
    if let Some(limit) = options.max_grid_cells {
        let (mut lo, mut hi) = map.bounds();
        for p in map.free_space.iter().flat_map(|p| &p.exterior) {
            for axis in 0..2 {
                lo[axis] = lo[axis].min(p[axis]);
                hi[axis] = hi[axis].max(p[axis]);
            }
        }
        let cells_along = |axis: usize| {
            ((hi[axis] - lo[axis] + 2.0 * GRID_MARGIN_M) / options.resolution_m).ceil() + 1.0
        };
        let (width, height) = (cells_along(0), cells_along(1));
        let cells = width * height;
        if cells.is_nan() || cells > limit {
            return Err(PipelineError::GridTooLarge {
                resolution: options.resolution_m,
                width,
                height,
                span_x: hi[0] - lo[0],
                span_y: hi[1] - lo[1],
                units: units_name(map.units),
                limit,
            });
        }
    }
    rasterize_map(
        map,
        &RasterOptions {
            resolution_m: options.resolution_m,
            robot_radius_m: options.robot_radius_m,
            hidden_free: options.hidden_free,
            margin_m: GRID_MARGIN_M,
        },
    )
    .map_err(PipelineError::Grid)
}

/// A number for a message: plain when readable, scientific when huge or tiny (the one
/// formatter of numbers in the command line's and the page's error messages).
///
/// # Example
/// ```
/// assert_eq!(vpmap_pipeline::num(0.05), "0.05");
/// assert_eq!(vpmap_pipeline::num(1e300), "1e300");
/// ```
#[must_use]
pub fn num(v: f64) -> String {
    vpmap_files::num(v)
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
}

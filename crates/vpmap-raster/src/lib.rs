//! A vpmap floor map (and a synthetic scene's truth) rasterised into a
//! [`vpmap_plan::OccupancyGrid`]: the one step between the photo geometry of
//! [`vpmap_metrology`] and the planners of [`vpmap_plan`].
//!
//! | function | method |
//! |---|---|
//! | [`rasterize_map`] | a [`FloorMap`](vpmap_metrology::map::FloorMap) to a grid: scanline fill of the free-space polygons by cell centre, conservative obstacles (every cell a footprint touches), floor hidden behind objects unknown, obstacles inflated by the robot radius |
//! | [`truth_grid`] | a synthetic scene's [`Truth`](vpmap_metrology::synth::Truth) into the frame of a believed map's grid: free where a cell centre is on the floor and in no footprint (even-odd rule) |
//!
//! A crate of its own so that [`vpmap_plan`] stands alone (grids, their files and the
//! planners, without nalgebra and the photo geometry), while the pipeline, the evaluation,
//! the web API and the fuzz targets share this one rasterisation without pulling in the
//! pipeline's rendering stack.
//!
//! # Rules
//! In the order they are applied to a grid that starts all
//! [`Occupancy::Unknown`](vpmap_plan::Occupancy::Unknown):
//! 1. **Free**: a cell whose centre lies inside a free-space polygon (the floor minus the
//!    footprints): inside its exterior ring and outside every hole, each ring read with the
//!    even-odd rule. A centre exactly on a boundary is decided by the half-open scanline
//!    convention (the obstacle rule below blocks such cells along footprints anyway).
//! 2. **Occupied**: a cell whose closed square intersects an object's closed footprint:
//!    its centre is inside the footprint, or a footprint edge touches the square. This is
//!    conservative: an obstacle that grazes a cell, even along its border, blocks it.
//!    Footprints with one or two points block the cells their point or segment touches.
//! 3. **Inflation** by [`RasterOptions::robot_radius_m`] (see
//!    [`OccupancyGrid::inflate`](vpmap_plan::OccupancyGrid::inflate)).
//!
//! Everything else (outside the floor the photo shows) stays unknown.
//!
//! The grid covers [`FloorMap::bounds`](vpmap_metrology::map::FloorMap::bounds) (floor,
//! objects and the station point at the origin) plus [`RasterOptions::margin_m`] on every side, with its origin snapped down to a multiple
//! of the resolution so that grids of one resolution share cell boundaries.
//!
//! Polygons are filled by scanlines: for each row, the crossings of every edge with the
//! row's centre line, sorted, give the runs of inside cells, so the cost is
//! `O(rows x edges + cells)`, not a point-in-polygon test per cell.
//!
//! # Example
//! ```
//! use vpmap_metrology::{map::{build_map, BuildOptions}, synth::{synthesize, SynthOptions}};
//! use vpmap_raster::{rasterize_map, RasterOptions};
//! let (scene, _) = synthesize(&SynthOptions::default()).unwrap();
//! let map = build_map(&scene, &BuildOptions::default()).unwrap();
//! let opts = RasterOptions { resolution_m: 0.1, robot_radius_m: 0.2, ..RasterOptions::default() };
//! let grid = rasterize_map(&map, &opts).unwrap();
//! let (free, occupied, unknown) = grid.counts();
//! assert!(free > 0 && occupied > 0 && unknown > 0);
//! ```
#![deny(missing_docs)]

mod error;
mod raster;

pub use error::{RasterError, Result};
pub use raster::{MAX_MAP_COORDINATE, RasterOptions, rasterize_map, truth_grid};

/// The README's example, compiled and run as a doc test.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;

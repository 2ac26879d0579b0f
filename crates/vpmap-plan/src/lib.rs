//! Occupancy grids from vpmap floor maps, and their ROS `map_server` files.
//!
//! | step | module | method |
//! |---|---|---|
//! | grid model | [`grid`] | row-major [`Cell`]s, `(x, y)` = (column, row from the top), ROS origin at the lower-left corner |
//! | obstacle inflation | [`grid`] | exact Euclidean distance transform to the obstacles' squares (Felzenszwalb and Huttenlocher 2012), thresholded at the robot radius |
//! | floor map to grid | [`raster`] | scanline fill of free-space polygons by cell centre; conservative obstacles (every cell a footprint touches) |
//! | map files | [`ros`] | `map_server` YAML + PGM writer; reader for PGM (P2, P5) and PNG with `negate`, thresholds and the `trinary`, `scale` and `raw` modes |
//!
//! # Example
//! ```
//! use vpmap_metrology::{map::{build_map, BuildOptions}, synth::{synthesize, SynthOptions}};
//! use vpmap_plan::{rasterize_map, read_ros_map, write_ros_map, RasterOptions};
//! let (scene, _) = synthesize(&SynthOptions::default()).unwrap();
//! let map = build_map(&scene, &BuildOptions::default()).unwrap();
//! let opts = RasterOptions { resolution_m: 0.1, robot_radius_m: 0.2, ..RasterOptions::default() };
//! let grid = rasterize_map(&map, &opts).unwrap();
//! let dir = tempfile::tempdir().unwrap();
//! write_ros_map(&grid, &dir.path().join("room.yaml")).unwrap();
//! assert_eq!(read_ros_map(&dir.path().join("room.yaml")).unwrap(), grid);
//! ```
//!
//! # References
//! - P. F. Felzenszwalb, D. P. Huttenlocher, "Distance Transforms of Sampled Functions",
//!   Theory of Computing 8 (2012).
//! - ROS `map_server` / `nav2_map_server` map format (YAML fields, pixel thresholds).
#![deny(missing_docs)]

pub mod error;
pub mod grid;
pub mod raster;
pub mod ros;

pub use error::{PlanError, Result};
pub use grid::{Cell, MAX_CELLS, OccupancyGrid};
pub use raster::{RasterOptions, rasterize_map};
pub use ros::{encode_ros_map, read_ros_map, write_ros_map};

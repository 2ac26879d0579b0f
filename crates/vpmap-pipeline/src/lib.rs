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
//! | [`parse_scene`] | scene JSON text -> a validated scene and its unknown fields' warnings (`vpmap build`, `/api/build`) |
//! | [`map_and_grid`] | scene -> floor map and its occupancy grid (what `/api/plan` plans on) |
//! | [`build`] | scene -> map, grid, glTF model, ROS map files and floor-plan SVG (what `vpmap build` writes and `/api/build` returns) |
//! | [`occupancy_grid`] | floor map -> occupancy grid: the one rasterisation behind all of these and `vpmap plan` on a `map.json` |
//! | [`read_planning_map`] | a `.map`, ROS `.yaml` or `map.json` file -> an inflated grid to plan on (`vpmap plan`, `vpmap navigate`) |
//! | [`endpoint_cell`] | a start or goal in map coordinates -> its grid cell, checked (`vpmap plan`, `/api/plan`) |
//! | [`run_planner`] | one planner on a grid within counted limits (`vpmap plan`) |
//! | [`truth_frame`], [`navigate_json`] | an empty grid around a synthetic truth, and a drive's report file (`vpmap navigate`) |
//! | [`demo_path`], [`demo_path_text`] | the path `vpmap demo` draws across the bundled example, and what it says of it |
//! | [`map_summary`] | what `vpmap build` prints of a map: cameras, objects, floor, grid |
//!
//! Modules, bottom-up (each uses only those before it): `text` (numbers and units in
//! messages), `ranges` (each option's range and names), `error`, [`options`], [`scene`],
//! `grid` ([`occupancy_grid`]), `build` ([`map_and_grid`], [`build`]), [`endpoint`],
//! [`planning`], [`drive`], [`demo`], `summary` ([`map_summary`]). This file only declares and
//! re-exports them.
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

mod build;
pub mod demo;
pub mod drive;
pub mod endpoint;
mod error;
mod grid;
pub mod options;
pub mod planning;
mod ranges;
pub mod scene;
pub mod smooth;
mod summary;
mod text;

pub use build::{Built, MapAndGrid, build, build_until, map_and_grid, map_and_grid_until};
pub use demo::{DemoPath, DemoRoute, TruthErrors, demo_path, demo_path_text, errors_against_truth};
pub use drive::{
    DriveMap, DriveReport, drive_maps, is_truth_file, navigate_json, read_truth, truth_frame,
};
pub use endpoint::{Coordinates, Endpoint, EndpointRules, OptionNames, endpoint_cell};
pub use error::PipelineError;
pub use grid::{grown_by_uncertainty, occupancy_grid, uncertainty_margin};
pub use options::{
    BuildOption, DEFAULT_RESOLUTION_M, DEFAULT_ROBOT_RADIUS_M, GRID_MARGIN_M, MapOptions,
    RESOLUTION_RANGE_M, ROBOT_RADIUS_RANGE_M,
};
pub use planning::{Limits, PlanningMap, mbpp_stats, plan_json, read_planning_map, run_planner};
pub use scene::{ParsedScene, parse_scene};
pub use smooth::{
    SmoothDriveReport, navigate_smooth_json, navigate_smooth_svg, no_path_reason, smooth_json,
    smooth_options, smooth_text,
};
pub use summary::{GROUPED_PLACE_WARNINGS, map_summary, printed_warnings};
pub use text::{num, units_name};

/// The README's example, compiled and run as a doc test.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;

//! Pictures and models of vpmap floor maps.
//!
//! Input is a [`FloorMap`](vpmap_metrology::map::FloorMap) (map frame: origin at the station
//! point, `+x` right, `+y` forward, `+z` up; metres or camera heights).
//!
//! | function | output | how |
//! |---|---|---|
//! | [`floor_plan_svg`] | an SVG floor plan, `+y` up the page: free space, hidden floor (hatched), floor outline, labelled objects, station point, field of view, grid, axes, scale bar, legend, title | hand-written SVG, greedy label placement |
//! | [`plan_svg()`] | an SVG of a plan on its occupancy grid: cells, path, start and goal; MBPP's bug tracks, hits, leave points and alternatives; a title, axes in metres or cells and a legend | hand-written SVG, one unit per cell, straight runs of a track merged |
//! | [`smooth_svg()`] | the same picture of a smooth (curvature-bounded) path: the curve through its poses, its tightest turn's circle and its cusps | [`plan_svg()`] plus a polyline at most a quarter cell between points |
//! | [`detection_overlay_png`] | PNG bytes of a photo with what `vpmap_vision::detect` found drawn on it: segments coloured by vanishing point, horizon, vanishing points, principal point, and a legend strip under the photo | `imageproc` antialiased lines and circles on the half-desaturated photo; the legend an SVG rendered by [`svg_to_png`] |
//! | [`svg_to_png`] | PNG bytes of any SVG | resvg / tiny-skia, system fonts with `sans-serif` mapped to DejaVu Sans |
//! | [`model_glb`] | a glTF 2.0 binary model: floor mesh, one prism per object, camera pyramid | ear-cut triangulation (`earcutr`), `gltf-json`, GLB chunks written here; glTF `(X, Y, Z)` = map `(x, z, -y)` |
//!
//! # Example
//! ```
//! use vpmap_metrology::map::{build_map, BuildOptions};
//! use vpmap_metrology::synth::{synthesize, SynthOptions};
//! use vpmap_render::{floor_plan_svg, model_glb, svg_to_png, FloorPlanStyle};
//! let (scene, _) = synthesize(&SynthOptions::default()).unwrap();
//! let map = build_map(&scene, &BuildOptions::default()).unwrap();
//! let svg = floor_plan_svg(&map, &FloorPlanStyle::default());
//! let png = svg_to_png(&svg).unwrap();
//! let glb = model_glb(&map).unwrap();
//! assert!(png.starts_with(b"\x89PNG") && glb.starts_with(b"glTF"));
//! ```
//!
//! # References
//! - glTF 2.0 specification, Khronos Group: <https://registry.khronos.org/glTF/specs/2.0/glTF-2.0.html>
//!   (GLB layout, accessor bounds, Y-up right-handed frame).
//! - SVG 1.1, W3C: `fill-rule="evenodd"` for free space with holes.
//! - M. Held, *FIST: Fast industrial-strength triangulation of polygons*, 2001 (ear cutting).
#![deny(missing_docs)]
#![cfg_attr(test, allow(clippy::unwrap_used, clippy::expect_used))]

pub mod error;
mod geometry;
mod metrics;
pub mod model;
pub mod navigation_svg;
pub mod overlay;
pub mod plan_svg;
pub mod raster;
pub mod smooth_svg;
pub mod svg;

pub use error::RenderError;
pub use model::model_glb;
pub use navigation_svg::navigation_svg;
pub use overlay::detection_overlay_png;
pub use plan_svg::{GridCoordinates, plan_svg, plan_title, planner_title};
pub use raster::svg_to_png;
pub use smooth_svg::smooth_svg;
pub use svg::{FloorPlanStyle, SVG_FROM_MAP_ATTRIBUTE, escape_xml, floor_plan_svg, matrix_text};

/// The README's example, compiled and run as a doc test.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;

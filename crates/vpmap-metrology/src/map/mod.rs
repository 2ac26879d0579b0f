//! The floor map: the result of `vpmap build`, as written to `map.json`.
//!
//! Frame: origin at the station point, `+x` right, `+y` forward along the camera's horizontal
//! viewing direction, `+z` up. Units: metres when the scene gives a scale, else camera heights.
//! The format is documented for users in `docs/map-format.md`.
//!
//! The types are in `map/types.rs`, the options in `map/options.rs`; `map/build.rs` builds a
//! map from the reconstruction and its scale (`map/reconstruction.rs`), the regions on the
//! floor (`map/regions.rs`), the warnings (`map/warnings.rs`), the camera's report
//! (`map/cameras.rs`) and what the lens distortion's uncertainty adds (`map/lens.rs`); a room
//! of several photos is built by `map/room.rs` in the first photo's frame. After the fit,
//! `map/priors.rs` tests the intrinsics' priors (a cropped photo) and `map/lens_refine.rs` the
//! lens against the clicks, and `build` fits again with what they reject widened or refined.
//! Files in that order, each importing only files before it: `types` and `options`, then
//! `reconstruction`, `regions`, `warnings`, `cameras`, `lens`, `lens_refine`, `priors`, then
//! `room`, then `build`.

mod build;
mod cameras;
mod lens;
mod lens_refine;
mod options;
mod priors;
mod reconstruction;
mod regions;
mod room;
mod types;
mod warnings;

pub use crate::camera::{MapPoint, calibrate, room_yaw_rad, rotation_map_from_camera};
pub use crate::uncertainty::{CameraUncertainty, Ellipse, ObjectUncertainty};
pub use build::{build_map, build_map_until};
pub use options::BuildOptions;
pub use priors::CROPPED_PRINCIPAL_POINT_SD_DIAGONALS;
pub use reconstruction::{MAX_RANGE_CAMERA_HEIGHTS, meters_per_camera_height, reconstruct_scene};
pub use regions::{free_space, occlusion_shadow, to_polygons};
pub use types::{
    BoxSize, CameraReport, FitReport, FloorMap, MapAlternative, MapObject, PolygonWithHoles, Units,
};
pub use warnings::{
    WARN_FOCAL_SD_FRACTION, WARN_POSITION_M, WARN_POSITION_PROBABILITY,
    WARN_PRINCIPAL_POINT_SD_DIAGONALS, WARN_RELATIVE_SD, WARN_RESIDUAL_SIGMAS, self_crossing,
    warn_position_sigmas,
};

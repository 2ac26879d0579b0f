//! The scene file: what a user annotates on one photo, or on each photo of a room (format
//! version 1).
//!
//! Pixel coordinates, origin at the image's top-left corner, x right, y down.
//! The format is documented for users in `docs/scene-format.md`; this module is its
//! reference implementation. [`Scene::from_json_str`] parses and validates in one step,
//! so every later stage can rely on finite numbers and well-formed objects.
//!
//! The types are in `scene/types.rs`, reading and validation in `scene/validate.rs`, the
//! vanishing points' resolution in `scene/vanishing.rs`, the room file of several photos in
//! `scene/room.rs`, lens distortion in `scene/lens.rs`.

mod lens;
mod room;
mod types;
mod unknown;
mod validate;
mod vanishing;

pub use lens::{DivisionModel, LensDistortion, MAX_DIVISION_K, MAX_DIVISION_STRETCH};
pub use room::{MAX_PHOTOS, PLACEMENT_TURNS_DEG};
pub use types::{
    BoxBase, BoxCorner, BoxCorners, BoxPoint, BoxView, Dimension, FloorDistance, ImageSize,
    ObjectShape, ObjectSpec, Perspective, PixelPoint, Scale, ScaleSpec, Scene, ThesisBox, TopSpec,
    VanishingPointSpec,
};
pub use unknown::unknown_fields;
pub use validate::{
    MAX_CLICK_COVARIANCE_CONDITION, MAX_CLICK_VARIANCE_PX2, MAX_OBJECTS, MAX_POINT_PX, MAX_POINTS,
    MAX_SCALE_M, MAX_VANISHING_POINT_PX, MAX_VP_SD_DEG, MIN_CLICK_VARIANCE_PX2, MIN_IMAGE_SIDE_PX,
    MIN_VP_SD_DEG,
};
pub use vanishing::{SegmentFit, VpChart, intersect_segments};

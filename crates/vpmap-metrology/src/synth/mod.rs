//! A synthetic pinhole camera: Manhattan scenes with known truth.
//!
//! This is the test oracle of the reconstruction (and the evaluation's data source). It shares
//! nothing with the reconstruction code but the scene and map types: it projects known 3D
//! points through a textbook pinhole camera (`u = o + f [x/z, y/z]` in a camera frame with `x`
//! right, `y` down, `z` forward), so an error in the reconstruction's geometry shows up as a
//! mismatch against [`Truth`].
//!
//! World frame = map frame: origin at the station point, `x` right, `y` forward (the camera's
//! horizontal viewing direction), `z` up; lengths in metres. The camera stands at
//! `(0, 0, height_m)`, pitched down by `pitch` about `x`, then rolled by `roll` about its
//! viewing direction (positive roll makes the horizon fall to the right in the image, as in
//! `../shared/data/synthetic-scenes`).
//!
//! The module's parts: [`PinholeCamera`] (the camera and its projections), the true objects
//! and [`Truth`], [`render_annotated`] (what a synthetic user clicks), the vanishing points
//! given as edges ([`vanishing_points_as_lines`], [`long_edges`]), [`add_noise`] and the
//! random room ([`synthesize`]), and a room photographed several times ([`synthesize_room`]).

mod annotate;
mod camera;
mod noise;
mod random_scene;
mod room;
mod truth;
mod vp_edges;

pub use annotate::{BoxAnnotation, BoxClicks, render_annotated, render_scene};
pub use camera::PinholeCamera;
pub use noise::add_noise;
pub use random_scene::{Annotation, SynthOptions, VanishingPointForm, synthesize};
pub use room::{
    FLOOR_OUTLINE_INSET, MAX_ROOM_PHOTOS, RoomSynthOptions, RoomTruth, RoomTruthCamera,
    RoomTruthObject, synthesize_room,
};
pub use truth::{SynthBox, SynthPrism, Truth, TruthCamera, TruthObject};
pub use vp_edges::{LongEdgeOptions, long_edges, vanishing_points_as_lines};

//! What a synthetic scene really holds: the boxes and prisms placed in the world, and the
//! [`Truth`] written beside the scene (camera and objects in the map frame, metres).

use nalgebra::Vector2;
use serde::{Deserialize, Serialize};

use super::camera::PinholeCamera;
use crate::scene::ImageSize;

/// A box standing on the floor.
#[derive(Debug, Clone, PartialEq)]
pub struct SynthBox {
    /// Name.
    pub name: String,
    /// One base corner, metres.
    pub corner: Vector2<f64>,
    /// First edge from `corner` (along one room axis), metres.
    pub edge_a: Vector2<f64>,
    /// Second edge from `corner` (along the other room axis), metres.
    pub edge_b: Vector2<f64>,
    /// Height, metres.
    pub height_m: f64,
}

impl SynthBox {
    /// The four base corners in order around the box.
    #[must_use]
    pub fn corners(&self) -> [Vector2<f64>; 4] {
        [
            self.corner,
            self.corner + self.edge_a,
            self.corner + self.edge_a + self.edge_b,
            self.corner + self.edge_b,
        ]
    }
}

/// A prism with a polygonal footprint standing on the floor (the thesis's chair).
#[derive(Debug, Clone, PartialEq)]
pub struct SynthPrism {
    /// Name.
    pub name: String,
    /// Footprint vertices in order, metres.
    pub footprint: Vec<Vector2<f64>>,
    /// Height, metres.
    pub height_m: f64,
}

/// The truth of a synthetic scene, in the map frame (metres).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Truth {
    /// The camera.
    pub camera: TruthCamera,
    /// Objects in scene order: a box's footprint is near, right, far, left.
    pub objects: Vec<TruthObject>,
    /// Floor outline in scene order.
    pub floor: Vec<[f64; 2]>,
}

/// The true camera.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TruthCamera {
    /// Focal length, pixels.
    pub focal_px: f64,
    /// Principal point, pixels (absent: the image centre).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub principal_point: Option<[f64; 2]>,
    /// Pitch, degrees, positive looking down.
    pub pitch_deg: f64,
    /// Roll, degrees.
    pub roll_deg: f64,
    /// Height, metres.
    pub height: f64,
}

impl TruthCamera {
    /// The pinhole camera this truth describes, for an image of the given size (principal
    /// point: the image centre when absent).
    #[must_use]
    pub fn pinhole(&self, image: ImageSize) -> PinholeCamera {
        PinholeCamera {
            image,
            focal_px: self.focal_px,
            principal_point_px: self
                .principal_point
                .map_or_else(|| image.centre(), |p| Vector2::new(p[0], p[1])),
            height_m: self.height,
            pitch_rad: self.pitch_deg.to_radians(),
            roll_rad: self.roll_deg.to_radians(),
        }
    }
}

/// One true object.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TruthObject {
    /// Name.
    pub name: String,
    /// Footprint corners, metres.
    pub footprint: Vec<[f64; 2]>,
    /// Height, metres.
    pub height: f64,
}

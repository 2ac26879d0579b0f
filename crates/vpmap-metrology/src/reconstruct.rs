//! What a reconstruction method produces, in camera heights, and the choice of method.
//!
//! Frame: origin at the station point (the floor point under the camera), `+x` right, `+y`
//! forward along the camera's horizontal viewing direction, `+z` up. Unit: the camera height
//! (the camera stands at `(0, 0, 1)`).

use nalgebra::Vector2;
use serde::{Deserialize, Serialize};

use crate::calibration::Calibration;
use crate::error::{MetrologyError, Result};
use crate::scene::{ObjectShape, PixelPoint, Scene};

/// Which reconstruction to run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Method {
    /// The thesis's side-view method (chapters 3-4 with the errata's sign rules).
    Sideview,
    /// The camera-matrix form: each pixel's ray meets the floor plane.
    Projective,
    /// The joint maximum-likelihood fit of the camera and every object to all clicked points
    /// and vanishing-point segments ([`crate::fit`]): the default.
    #[default]
    Fit,
}

impl std::fmt::Display for Method {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Sideview => "sideview",
            Self::Projective => "projective",
            Self::Fit => "fit",
        })
    }
}

impl std::str::FromStr for Method {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        match s {
            "sideview" => Ok(Self::Sideview),
            "projective" => Ok(Self::Projective),
            "fit" => Ok(Self::Fit),
            other => Err(format!(
                "unknown method \"{other}\"; use fit, sideview or projective"
            )),
        }
    }
}

/// Whether an object was annotated as a box or as a footprint polygon.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ObjectKind {
    /// A rectangular box: footprint is near, right, far, left.
    Box,
    /// A general footprint polygon, in the annotated order.
    Footprint,
}

/// One reconstructed object, in camera heights.
#[derive(Debug, Clone, PartialEq)]
pub struct ReconstructedObject {
    /// The scene's name for it.
    pub name: String,
    /// Box or footprint.
    pub kind: ObjectKind,
    /// Floor corners `(x, y)`: a box's near, right, far, left; a footprint's vertices.
    pub footprint: Vec<Vector2<f64>>,
    /// Height above the floor, or `None` when no top was annotated.
    pub height: Option<f64>,
}

/// A reconstruction in camera heights.
#[derive(Debug, Clone, PartialEq)]
pub struct Reconstruction {
    /// The method that produced it.
    pub method: Method,
    /// The objects, in scene order.
    pub objects: Vec<ReconstructedObject>,
    /// The floor outline, in scene order.
    pub floor: Vec<Vector2<f64>>,
}

/// A method's map from image points to the floor and from vertical edges to heights.
///
/// Implemented by the side-view method and the projective form; [`reconstruct`] walks a
/// scene with either.
pub trait FloorProjection {
    /// The floor point `(x, y)` (camera heights) seen at an image point.
    ///
    /// # Errors
    /// [`MetrologyError::NotBelowHorizon`] when the point is on or above the horizon.
    fn floor_point(&self, field: &str, image_px: PixelPoint) -> Result<Vector2<f64>>;

    /// The height (camera heights) of a vertical edge whose base is at `base_px` and top at
    /// `top_px`.
    ///
    /// # Errors
    /// As [`FloorProjection::floor_point`] for the base.
    fn edge_height(&self, field: &str, base_px: PixelPoint, top_px: PixelPoint) -> Result<f64>;

    /// The box's far corners from its three visible base corners: returns near, right, far,
    /// left on the floor.
    ///
    /// # Errors
    /// When a corner is not below the horizon or the construction degenerates.
    fn box_footprint(
        &self,
        field: &str,
        near_px: PixelPoint,
        right_px: PixelPoint,
        left_px: PixelPoint,
    ) -> Result<[Vector2<f64>; 4]>;
}

/// Check that an image point lies strictly below the horizon.
///
/// # Errors
/// [`MetrologyError::NotBelowHorizon`].
pub fn require_below_horizon(cal: &Calibration, field: &str, p: PixelPoint) -> Result<f64> {
    let below = cal.frame.below_horizon_px(Vector2::new(p[0], p[1]));
    if below <= 1e-9 * cal.focal_px {
        return Err(MetrologyError::NotBelowHorizon {
            field: field.to_owned(),
            x: p[0],
            y: p[1],
            distance_px: below.abs(),
            side: if below.abs() <= 1e-9 * cal.focal_px {
                "on"
            } else {
                "above"
            },
        });
    }
    Ok(below)
}

fn negative_height(field: &str, name: &str, h: f64) -> MetrologyError {
    MetrologyError::Degenerate {
        field: field.to_owned(),
        reason: format!(
            "object {name:?} comes out with a negative height ({h:.6} camera heights): the top point lies below its base in the image"
        ),
    }
}

/// Reconstruct every object and the floor of a scene with one method.
///
/// Heights: a box's height is the mean of the estimates from its near vertical edge and, when
/// annotated, its left one; a footprint object's from its one top point.
///
/// # Errors
/// The first annotated point that cannot be placed on the floor, or a negative height.
pub fn reconstruct(
    scene: &Scene,
    method: Method,
    projection: &dyn FloorProjection,
) -> Result<Reconstruction> {
    let mut objects = Vec::with_capacity(scene.objects.len());
    for (i, obj) in scene.objects.iter().enumerate() {
        let field = format!("objects[{i}]");
        let shape = obj.shape(i)?;
        let (kind, footprint, height) = match shape {
            ObjectShape::Box { .. } => {
                let Some(b) = shape.thesis_box(i, &obj.name, &method.to_string())? else {
                    continue;
                };
                let corners = projection.box_footprint(&field, b.near, b.right, b.left)?;
                let mut estimates = Vec::new();
                for (name, base_px, top) in
                    [("near", b.near, b.top_near), ("left", b.left, b.top_left)]
                {
                    let Some(t) = top else { continue };
                    let top_field = format!("{field}.top.{name}");
                    let h = projection.edge_height(&top_field, base_px, t)?;
                    if h < 0.0 {
                        return Err(negative_height(&top_field, &obj.name, h));
                    }
                    estimates.push(h);
                }
                let height = if estimates.is_empty() {
                    None
                } else {
                    Some(estimates.iter().sum::<f64>() / estimates.len() as f64)
                };
                (ObjectKind::Box, corners.to_vec(), height)
            }
            ObjectShape::Footprint { polygon, top } => {
                let footprint = polygon
                    .iter()
                    .enumerate()
                    .map(|(j, p)| projection.floor_point(&format!("{field}.footprint[{j}]"), *p))
                    .collect::<Result<Vec<_>>>()?;
                let height = match top {
                    Some((k, t)) => Some(projection.edge_height(
                        &format!("{field}.top.point"),
                        polygon[k],
                        t,
                    )?),
                    None => None,
                };
                (ObjectKind::Footprint, footprint, height)
            }
        };
        if let Some(h) = height
            && h < 0.0
        {
            return Err(negative_height(&format!("{field}.top.point"), &obj.name, h));
        }
        objects.push(ReconstructedObject {
            name: obj.name.clone(),
            kind,
            footprint,
            height,
        });
    }
    let floor = scene
        .floor
        .iter()
        .enumerate()
        .map(|(i, p)| projection.floor_point(&format!("floor[{i}]"), *p))
        .collect::<Result<Vec<_>>>()?;
    Ok(Reconstruction {
        method,
        objects,
        floor,
    })
}

//! The error bars a map reports: an object's and the camera's standard deviations and the
//! centroid's confidence ellipse. The fit computes them; the map carries them.

use serde::{Deserialize, Serialize};

use crate::camera::MapPoint;

/// A 2-D confidence ellipse on the floor.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Ellipse {
    /// Centre `[x, y]`, map units.
    pub centre: MapPoint,
    /// Semi-major and semi-minor axis lengths, map units.
    pub semi_axes: [f64; 2],
    /// Direction of the major axis, degrees counter-clockwise from `+x`.
    pub angle_deg: f64,
}

/// One object's error bars: standard deviations (1 sigma) and the centroid's covariance, for
/// the click noise in [`FitReport::click_sigma_px`](crate::map::FitReport::click_sigma_px),
/// first-order propagated through the fit and the scale.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ObjectUncertainty {
    /// Covariance of the centroid `[[xx, xy], [xy, yy]]`, map units squared.
    pub centroid_covariance: [[f64; 2]; 2],
    /// The centroid's 95 % confidence ellipse.
    pub centroid_ellipse_95: Ellipse,
    /// The standard deviation of the least certain floor corner (of the footprint's), along
    /// that corner's least certain direction, map units: how far the outline may be off where
    /// it is least known (a box's size and yaw move its corners more than its centroid).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub corner_sd: Option<f64>,
    /// Standard deviation of a box's longer side, map units.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub length_sd: Option<f64>,
    /// Standard deviation of a box's shorter side, map units.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub breadth_sd: Option<f64>,
    /// Standard deviation of the height, map units.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub height_sd: Option<f64>,
    /// A box's yaw: the direction of its longer side, degrees counter-clockwise from `+x`,
    /// in `[0, 180)`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub yaw_deg: Option<f64>,
    /// Standard deviation of the yaw, degrees.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub yaw_sd_deg: Option<f64>,
}

/// The camera's error bars (1 sigma), as [`ObjectUncertainty`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CameraUncertainty {
    /// Focal length, pixels.
    pub focal_px_sd: f64,
    /// Pitch, degrees.
    pub pitch_deg_sd: f64,
    /// Roll, degrees.
    pub roll_deg_sd: f64,
    /// Camera height, map units (0 when the scale is the camera height, or without a scale:
    /// then the camera height is the unit, which nothing in a photo can fix).
    pub height_sd: f64,
    /// Principal point `[x, y]`, pixels, when the fit placed it (three finite vanishing
    /// points); absent when it was held at the given value or the image centre.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub principal_point_px_sd: Option<[f64; 2]>,
    /// The room's yaw ([`CameraReport::room_yaw_deg`](crate::map::CameraReport::room_yaw_deg)),
    /// degrees.
    #[serde(default)]
    pub room_yaw_deg_sd: f64,
    /// A room's photos after the first: the station point `[x, y]`, map units.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub position_sd: Option<[f64; 2]>,
    /// A room's photos after the first: the heading, degrees.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub heading_deg_sd: Option<f64>,
}

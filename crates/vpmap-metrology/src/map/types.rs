//! The map's types: what `map.json` holds (the camera as reported, the objects, the floor and
//! its regions, the fit's report), and reading and writing it.

use geo::{Area, LineString, Polygon};
use serde::{Deserialize, Serialize};

use crate::calibration::Perspective;
use crate::camera::MapPoint;
use crate::error::{MetrologyError, Result};
use crate::reconstruct::{Method, ObjectKind};
use crate::scene::ImageSize;
use crate::uncertainty::{CameraUncertainty, ObjectUncertainty};

/// Length unit of a map.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Units {
    /// Metres (the scene gave a scale).
    #[serde(rename = "m")]
    Meters,
    /// Camera heights (no scale given; the camera height is 1).
    #[serde(rename = "camera_heights")]
    CameraHeights,
}

/// The camera as reported in a map.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CameraReport {
    /// "2pp" or "3pp".
    pub perspective: Perspective,
    /// Focal length, pixels.
    pub focal_px: f64,
    /// Principal point used, pixels.
    pub principal_point: [f64; 2],
    /// Pitch, degrees, positive when the camera looks down.
    pub pitch_deg: f64,
    /// Roll, degrees: the horizon's angle in the image, positive when it falls to the right.
    pub roll_deg: f64,
    /// The room's yaw: the direction on the floor of the first horizontal vanishing point's
    /// edges, degrees counter-clockwise from `+x` (the second runs 90 degrees from it).
    #[serde(default)]
    pub room_yaw_deg: f64,
    /// Camera height above the floor, in the map's units.
    pub height: f64,
    /// The intrinsic matrix `K = [[f, 0, cx], [0, f, cy], [0, 0, 1]]` (pixels; square pixels,
    /// no skew), row by row.
    #[serde(default)]
    pub k_matrix: [[f64; 3]; 3],
    /// Rotation from the camera frame (x right, y down, z along the optical axis, as in
    /// OpenCV) to the map frame, row by row: a ray `K^-1 (u, v, 1)` in camera coordinates
    /// points along `R` times it in the map frame.
    #[serde(default)]
    pub rotation_map_from_camera: [[f64; 3]; 3],
    /// Position of the camera `[x, y, z]` in the map frame (always `[0, 0, height]`).
    pub position: [f64; 3],
    /// The photo's size.
    pub image: ImageSize,
    /// Vanishing points used, pixels.
    pub vanishing_points: Vec<[f64; 2]>,
    /// The fit's error bars (method `fit` only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub uncertainty: Option<CameraUncertainty>,
    /// Horizontal field of view: angles of the image's left and right extent, degrees from
    /// `+y`, negative to the left.
    pub horizontal_fov_deg: [f64; 2],
    /// The floor the photo shows: the image rectangle projected onto the floor, cut where it
    /// reaches 1.5 times the farthest mapped point (the part near the horizon runs to
    /// infinity). A convex polygon, counter-clockwise.
    #[serde(default)]
    pub view_on_floor: Vec<MapPoint>,
    /// A room's cameras: the horizontal viewing direction, degrees counter-clockwise from the
    /// map's `+y` (0 for the first photo's). Absent for a single photo, whose camera looks
    /// along `+y`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub heading_deg: Option<f64>,
    /// The lens distortion the photo's clicks were undistorted by (the scene's
    /// `lens_distortion`: the division model's `k` and its sd, whose spread the error bars
    /// include). Absent for a photo taken as a pinhole camera's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lens_distortion: Option<crate::scene::LensDistortion>,
}

/// Footprint side lengths of a box.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BoxSize {
    /// Longer side.
    pub length: f64,
    /// Shorter side.
    pub breadth: f64,
}

/// One object of the map.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MapObject {
    /// Name from the scene.
    pub name: String,
    /// "box" or "footprint".
    pub kind: ObjectKind,
    /// Floor corners: a box's near, right, far, left; a footprint's vertices in scene order.
    pub footprint: Vec<MapPoint>,
    /// Height above the floor (`null` when the scene gives no top point).
    pub height: Option<f64>,
    /// A box's side lengths.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub size: Option<BoxSize>,
    /// Footprint centroid.
    pub centroid: MapPoint,
    /// Footprint area.
    pub area: f64,
    /// The fit's error bars for this object (method `fit` only; absent otherwise).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub uncertainty: Option<ObjectUncertainty>,
}

/// How the joint fit went (method `fit` only).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FitReport {
    /// The click noise the error bars are computed for, pixels (1 sigma per coordinate).
    pub click_sigma_px: f64,
    /// Where it comes from: `"given"` (set by the user), `"residuals"` (estimated from the
    /// fit's residuals, the data over-determining the model) or `"default"` (1 px).
    pub click_sigma_source: String,
    /// Root-mean-square reprojection error of the clicked points, pixels.
    pub rms_residual_px: f64,
    /// With clicks of their own covariance: the root-mean-square of the normalised
    /// residuals, in standard deviations (each click's residual whitened by its covariance,
    /// or divided by `click_sigma_px` without one); about 1 when the covariances are right.
    /// Absent when no click has a covariance.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rms_normalised: Option<f64>,
    /// Residuals minus parameters.
    pub degrees_of_freedom: usize,
    /// Levenberg-Marquardt iterations.
    pub iterations: usize,
    /// Whether the principal point was fitted (else held at the given or central value).
    pub principal_point_fitted: bool,
    /// How many clicks the fit weighted by their own covariance (the scene's
    /// `click_covariances_px2`); absent when none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub clicks_with_covariance: Option<usize>,
}

/// A polygon with holes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PolygonWithHoles {
    /// Outer ring (not repeated at the end).
    pub exterior: Vec<MapPoint>,
    /// Inner rings.
    pub holes: Vec<Vec<MapPoint>>,
}

/// A floor map (`map.json`, version 1).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FloorMap {
    /// Format version: 1.
    pub version: u32,
    /// Length unit of every coordinate and length.
    pub units: Units,
    /// Reconstruction method used.
    pub method: Method,
    /// The camera (a room's first photo's, whose station point is the origin).
    pub camera: CameraReport,
    /// A room's cameras, one per photo in order (the first is `camera`); absent for a
    /// single photo.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub cameras: Vec<CameraReport>,
    /// The objects, in scene order.
    pub objects: Vec<MapObject>,
    /// The floor outline (may be empty).
    pub floor: Vec<MapPoint>,
    /// The floor minus every footprint.
    pub free_space: Vec<PolygonWithHoles>,
    /// The parts of the free space the camera cannot see because objects stand in the way
    /// (each object's occlusion shadow as seen from the camera, clipped to the free space;
    /// for a room, what no photo sees). The occupancy grid marks them unknown.
    #[serde(default)]
    pub hidden: Vec<PolygonWithHoles>,
    /// Notes for the user.
    pub warnings: Vec<String>,
    /// A room's placements that fit about as well as the map's and that no physical check
    /// rules out (a tie the clicks leave open), one per photo placed otherwise; absent when
    /// there is none.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub alternatives: Vec<MapAlternative>,
    /// How the joint fit went (method `fit` only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fit: Option<FitReport>,
}

/// A room photo's other placement (`map.json`'s `alternatives`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MapAlternative {
    /// The photo, from 1 (as the warnings name it).
    pub photo: usize,
    /// Its turn from the map's placement, degrees counter-clockwise: 90, 180 or 270.
    pub turn_deg: i32,
    /// Its quarter turn against photo 1's room directions in this placement, degrees: 0, 90,
    /// 180 or 270. Written as the photo's `placement_turn_deg` in the room file, it asks the
    /// build for this placement.
    pub placement_turn_deg: i32,
    /// The joint fit's cost with the photo so turned, squared pixels.
    pub cost_px2: f64,
    /// The map's own cost, squared pixels.
    pub chosen_cost_px2: f64,
}

impl FloorMap {
    /// Parse a map from JSON text.
    ///
    /// # Errors
    /// [`MetrologyError::Json`] when the text is not a version-1 map.
    pub fn from_json_str(text: &str) -> Result<Self> {
        let map: FloorMap =
            serde_json::from_str(text).map_err(|e| MetrologyError::Json(e.to_string()))?;
        if map.version != 1 {
            return Err(MetrologyError::UnsupportedVersion {
                file: "map.json",
                version: u64::from(map.version),
            });
        }
        Ok(map)
    }

    /// Whether a warning says that object `name`'s place or one of its sizes is uncertain
    /// (beyond [`WARN_POSITION_M`](super::WARN_POSITION_M) or
    /// [`WARN_RELATIVE_SD`](super::WARN_RELATIVE_SD)): the map then says the object may be
    /// off.
    #[must_use]
    pub fn warns_uncertain(&self, name: &str) -> bool {
        let prefix = format!("object {name:?}: its ");
        self.warnings
            .iter()
            .any(|w| w.starts_with(&prefix) && w.contains(" is uncertain by +-"))
    }

    /// The map as pretty-printed JSON.
    #[must_use]
    pub fn to_json_string(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_default()
    }

    /// Area of the free space (exteriors minus holes), in the map's units squared.
    #[must_use]
    pub fn free_area(&self) -> f64 {
        self.free_space
            .iter()
            .map(|p| {
                let ring = |pts: &[MapPoint]| {
                    LineString::from(pts.iter().map(|q| (q[0], q[1])).collect::<Vec<_>>())
                };
                Polygon::new(ring(&p.exterior), p.holes.iter().map(|h| ring(h)).collect())
                    .unsigned_area()
            })
            .sum::<f64>()
            // An empty sum of floats is -0.0.
            + 0.0
    }

    /// Axis-aligned bounds `(min, max)` of the floor, the objects and the station point.
    #[must_use]
    pub fn bounds(&self) -> (MapPoint, MapPoint) {
        let mut lo = [0.0f64, 0.0];
        let mut hi = [0.0f64, 0.0];
        let all = self
            .floor
            .iter()
            .chain(self.objects.iter().flat_map(|o| o.footprint.iter()));
        for p in all {
            for i in 0..2 {
                lo[i] = lo[i].min(p[i]);
                hi[i] = hi[i].max(p[i]);
            }
        }
        (lo, hi)
    }
}

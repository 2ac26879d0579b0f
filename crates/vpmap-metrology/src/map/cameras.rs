//! The cameras as a map reports them: one photo's in its own map frame, and a room's photos
//! placed in the room frame.

use nalgebra::Vector2;

use super::regions::view_on_floor;
use super::types::CameraReport;
use crate::calibration::Calibration;
use crate::camera::rotation_map_from_camera;
use crate::scene::ImageSize;
use crate::uncertainty::CameraUncertainty;

/// The camera as a map reports it, in its own map frame (station point at the origin,
/// looking along `+y`): `height` above the floor in map units, its view on the floor cut at
/// `view_reach`.
pub(super) fn camera_report(
    cal: &Calibration,
    image: ImageSize,
    room_yaw_rad: f64,
    height: f64,
    view_reach: f64,
    uncertainty: Option<CameraUncertainty>,
) -> CameraReport {
    let corners = [
        Vector2::new(0.0, 0.0),
        Vector2::new(f64::from(image.width), 0.0),
        Vector2::new(0.0, f64::from(image.height)),
        Vector2::new(f64::from(image.width), f64::from(image.height)),
    ];
    let xs = corners.map(|c| cal.frame.coords(c).x);
    let d0 = cal.top_view_distance_px();
    let fov = [
        xs.iter().copied().fold(f64::INFINITY, f64::min),
        xs.iter().copied().fold(f64::NEG_INFINITY, f64::max),
    ]
    .map(|x| x.atan2(d0).to_degrees());
    let o = cal.principal_point_px();
    CameraReport {
        perspective: cal.perspective,
        focal_px: cal.focal_px,
        principal_point: [o.x, o.y],
        pitch_deg: cal.pitch_rad.to_degrees(),
        roll_deg: cal.roll_rad.to_degrees(),
        room_yaw_deg: room_yaw_rad.to_degrees(),
        height,
        k_matrix: [
            [cal.focal_px, 0.0, o.x],
            [0.0, cal.focal_px, o.y],
            [0.0, 0.0, 1.0],
        ],
        rotation_map_from_camera: rotation_map_from_camera(cal.pitch_rad, cal.roll_rad),
        position: [0.0, 0.0, height],
        image,
        vanishing_points: cal.vanishing_points_px.iter().map(|v| [v.x, v.y]).collect(),
        uncertainty,
        horizontal_fov_deg: fov,
        view_on_floor: view_on_floor(cal, image, height, view_reach),
        heading_deg: None,
        lens_distortion: None,
    }
}

/// A camera report moved from its own map frame into a room's: standing at `position` (map
/// units) and turned by `heading_rad` counter-clockwise.
pub(super) fn placed(
    mut report: CameraReport,
    position: Vector2<f64>,
    heading_rad: f64,
) -> CameraReport {
    let (s, c) = heading_rad.sin_cos();
    let turn = |p: [f64; 2]| {
        [
            position.x + c * p[0] - s * p[1],
            position.y + s * p[0] + c * p[1],
        ]
    };
    report.view_on_floor = report.view_on_floor.iter().map(|p| turn(*p)).collect();
    report.position = [position.x, position.y, report.position[2]];
    let r = report.rotation_map_from_camera;
    let mut turned = r;
    for j in 0..3 {
        turned[0][j] = c * r[0][j] - s * r[1][j];
        turned[1][j] = s * r[0][j] + c * r[1][j];
    }
    report.rotation_map_from_camera = turned;
    report.heading_deg = Some(heading_rad.to_degrees());
    report
}

//! The camera in the map frame, which the fit and the map both use: a floor position in the
//! frame, the rotation from camera coordinates into it, the camera of a scene calibrated from
//! its vanishing points, and the room's yaw.
//!
//! The map frame (as `map.json` writes it): origin at the station point, `+x` right, `+y`
//! forward along the camera's horizontal viewing direction, `+z` up.

use nalgebra::Vector2;

use crate::calibration::Calibration;
use crate::error::Result;
use crate::scene::Scene;

/// A floor position `[x, y]` in the map frame.
pub type MapPoint = [f64; 2];

/// Calibrate the camera of a validated scene.
///
/// # Errors
/// As [`Scene::resolve_vanishing_points`] and [`Calibration::from_vanishing_points`].
pub fn calibrate(scene: &Scene) -> Result<Calibration> {
    let vps = scene.resolve_vanishing_points()?;
    // A principal point with a standard deviation is a prior, which the closed forms (they
    // have no priors) use only where they need a principal point: three finite vanishing
    // points fix it themselves (their orthocentre).
    let prior_only = scene.principal_point_sd_px.is_some()
        && vps.len() == 3
        && vps.iter().all(|v| v.z.abs() > 1e-12 * v.x.hypot(v.y));
    let pp = scene
        .principal_point
        .filter(|_| !prior_only)
        .map(|p| Vector2::new(p[0], p[1]));
    let mut cal =
        Calibration::from_listed(&vps, pp, scene.image, scene.vanishing_points_labelled())?;
    if let Some(f) = scene.focal_px
        && (f - cal.focal_px).abs() > 0.02 * cal.focal_px
    {
        cal.warnings.push(format!(
            "the scene's focal_px {f:.1} disagrees with the {:.1} px the vanishing points give; the vanishing points were used",
            cal.focal_px
        ));
    }
    Ok(cal)
}

/// The room's yaw from a calibration: the floor direction, from `+x`, of the edges that run to
/// the first vanishing point, radians.
#[must_use]
pub fn room_yaw_rad(cal: &Calibration) -> f64 {
    let Some(v) = cal.vanishing_points_px.first() else {
        return 0.0;
    };
    let q = (v - cal.principal_point_px()) / cal.focal_px;
    let r = rotation_map_from_camera(cal.pitch_rad, cal.roll_rad);
    let x = r[0][0] * q.x + r[0][1] * q.y + r[0][2];
    let y = r[1][0] * q.x + r[1][1] * q.y + r[1][2];
    y.atan2(x)
}

/// The rotation from camera coordinates (x right, y down, z forward) to the map frame for a
/// camera pitched down by `pitch` and rolled by `roll` (positive: the horizon falls to the
/// right in the image). Its columns are the camera's right, down and forward axes in the map.
#[must_use]
pub fn rotation_map_from_camera(pitch_rad: f64, roll_rad: f64) -> [[f64; 3]; 3] {
    let (sp, cp) = pitch_rad.sin_cos();
    let (sr, cr) = roll_rad.sin_cos();
    // Unrolled axes: right (1, 0, 0), down (0, -sin p, -cos p), forward (0, cos p, -sin p);
    // roll turns right and down about forward.
    let right = [cr, sr * sp, sr * cp];
    let down = [sr, -cr * sp, -cr * cp];
    let forward = [0.0, cp, -sp];
    [
        [right[0], down[0], forward[0]],
        [right[1], down[1], forward[1]],
        [right[2], down[2], forward[2]],
    ]
}

//! Snapping every click of a scene: box corners, footprint vertices and tops, floor corners.
//!
//! [`snap_scene`] checks the whole scene against the photo first (its image size, every
//! click inside the photo, its vanishing points), then snaps each click with the scene's
//! vanishing points. [`write_snapped`] puts the snapped points into the scene's JSON value,
//! leaving every other field as it was, and records each snapped point's covariance in the
//! scene's top-level `click_covariances_px2` table, keyed by the click's field path
//! (`docs/scene-format.md`). A click that stays keeps its entry if it had one, else gets the
//! click noise's (`sigma^2 I`, when given). Floor corners get no entry: the fit does not weigh
//! them.
//!
//! A scene with a lens (`lens_distortion`) gives its vanishing points as the pinhole camera's
//! while its clicks and the photo are the lens's: [`vanishing_points_at`] turns them into the
//! points the photo's edges run to near one click (each edge is straight in the pinhole image
//! and bowed in the photo), so the edges are searched along, and checked against, the
//! directions the photo shows there.

use nalgebra::Vector2;
use serde_json::{Map, Value, json};
use vpmap_metrology::scene::{DivisionModel, Scene};

use super::{Snap, SnapImage, SnapOptions, snap_click};
use crate::clicks::{ClickPlace, scene_clicks};
use crate::error::{Result, VisionError};

/// The scene field holding each snapped click's covariance, pixels squared.
pub const COVARIANCES_FIELD: &str = "click_covariances_px2";

/// One click of a scene, snapped.
#[derive(Clone, Debug, PartialEq)]
pub struct SnappedClick {
    /// Where it sits in the scene.
    pub place: ClickPlace,
    /// The result.
    pub snap: Snap,
}

/// The scene's vanishing points in homogeneous pixel coordinates.
///
/// # Errors
/// [`VisionError::InvalidScene`] when they cannot be resolved (parallel segments, ...).
pub fn scene_vanishing_points(scene: &Scene) -> Result<Vec<[f64; 3]>> {
    scene
        .resolve_vanishing_points()
        .map(|v| v.iter().map(|p| [p.x, p.y, p.z]).collect())
        .map_err(|e| VisionError::InvalidScene {
            message: e.to_string(),
        })
}

/// The vanishing points the photo's edges run to near photo pixel `click_px`, for `vanishing_points`
/// of the pinhole camera (homogeneous, as [`scene_vanishing_points`] gives them) seen through
/// the lens `lens`. An edge towards a vanishing point is a straight line in the pinhole image,
/// bowed by the lens in the photo; near the click it runs along the line's image under the
/// lens, whose direction there is the pinhole direction mapped by the inverse of the
/// undistortion's Jacobian at the click. Each point is returned where that direction, scaled
/// the same way, puts it: a finite point at `click + J^-1 (v - p)` (`p` the click's pinhole
/// pixel, `v` the point), a point at infinity as the direction `J^-1 d`. A two-point scene gets
/// its vertical here too (perpendicular to the pinhole horizon, then mapped), so
/// [`super::snap_click`] takes the three as the photo shows them. Without a lens, or where
/// the Jacobian is singular (beyond the lens's reach), the points are returned as given.
#[must_use]
pub fn vanishing_points_at(
    vanishing_points: &[[f64; 3]],
    lens: Option<&DivisionModel>,
    click_px: [f64; 2],
) -> Vec<[f64; 3]> {
    let Some(lens) = lens.filter(|l| l.k != 0.0) else {
        return vanishing_points.to_vec();
    };
    let Some(to_photo) = lens.undistort_jacobian(click_px).try_inverse() else {
        return vanishing_points.to_vec();
    };
    let p = lens.undistort(click_px);
    let mut out: Vec<[f64; 3]> = vanishing_points
        .iter()
        .map(|v| {
            if v[2].abs() > f64::EPSILON * v[0].hypot(v[1]) {
                let d = to_photo * Vector2::new(v[0] / v[2] - p[0], v[1] / v[2] - p[1]);
                [click_px[0] + d.x, click_px[1] + d.y, 1.0]
            } else {
                let d = to_photo * Vector2::new(v[0], v[1]);
                [d.x, d.y, 0.0]
            }
        })
        .collect();
    // The pinhole camera's vertical, perpendicular to its horizon, mapped the same way.
    if let [a, b] = vanishing_points
        && let Some(v) = super::two_point_vertical(*a, *b)
    {
        let d = to_photo * Vector2::new(v[0], v[1]);
        out.push([d.x, d.y, 0.0]);
    }
    out
}

/// Snap every click of `scene` on its photo, with the scene's vanishing points (seen through
/// its lens near each click, [`vanishing_points_at`], when it gives one).
///
/// # Errors
/// [`VisionError::ImageSizeMismatch`] when the scene's image size is not the photo's,
/// [`VisionError::ClickOutsidePhoto`] naming the first click outside the photo,
/// [`VisionError::InvalidScene`] when the vanishing points cannot be resolved,
/// [`VisionError::InvalidParameter`] for options out of range. All are checked before any
/// click is snapped.
pub fn snap_scene(
    image: &SnapImage,
    scene: &Scene,
    opts: &SnapOptions,
) -> Result<Vec<SnappedClick>> {
    if scene.image.width != image.width() || scene.image.height != image.height() {
        return Err(VisionError::ImageSizeMismatch {
            scene_width: scene.image.width,
            scene_height: scene.image.height,
            photo_width: image.width(),
            photo_height: image.height(),
        });
    }
    let clicks = scene_clicks(scene);
    let (w, h) = (f64::from(image.width()), f64::from(image.height()));
    if let Some(c) = clicks.iter().find(|c| {
        !(c.point_px.iter().all(|v| v.is_finite())
            && (0.0..=w).contains(&c.point_px[0])
            && (0.0..=h).contains(&c.point_px[1]))
    }) {
        return Err(VisionError::ClickOutsidePhoto {
            field: c.field(),
            x: c.point_px[0],
            y: c.point_px[1],
            width: image.width(),
            height: image.height(),
        });
    }
    let vps = scene_vanishing_points(scene)?;
    // A scene that states its vanishing points' uncertainty (`vpmap detect` writes it): the
    // edges may run off them by as much (the largest sd of any, if larger than the options').
    let opts = SnapOptions {
        vp_direction_sd_deg: opts.vp_direction_sd_deg.max(largest_vp_sd_deg(scene)),
        ..*opts
    };
    let lens = scene.division_model();
    clicks
        .into_iter()
        .map(|c| {
            let here = vanishing_points_at(&vps, lens.as_ref(), c.point_px);
            Ok(SnappedClick {
                place: c.place,
                snap: snap_click(image, &here, c.point_px, &opts)?,
            })
        })
        .collect()
}

/// The largest standard deviation of any of the scene's vanishing points, degrees (the major
/// axis of its `covariance_deg2`; 0 when none states one). The chart's angle stands in for
/// the angle of the image line through a click, which it matches for points off the image.
fn largest_vp_sd_deg(scene: &Scene) -> f64 {
    scene
        .vanishing_points
        .iter()
        .filter_map(|v| v.covariance_deg2)
        .map(|c| {
            let (a, b, d) = (c[0][0], c[0][1], c[1][1]);
            let major = 0.5 * (a + d) + (0.25 * (a - d) * (a - d) + b * b).sqrt();
            if major.is_finite() {
                major.max(0.0).sqrt()
            } else {
                0.0
            }
        })
        .fold(0.0, f64::max)
}

/// A number rounded to 1e-4 (pixels) or 1e-6 (pixels squared), for a readable file.
fn rounded(v: f64, digits: i32) -> f64 {
    let k = 10f64.powi(digits);
    (v * k).round() / k
}

/// Write snapped clicks into a scene's JSON value: each snapped point replaces its click and
/// its covariance goes into `click_covariances_px2`; with `kept_sigma_px`, each click that
/// stayed gets `kept_sigma_px^2 I` there unless it has an entry already (the fit takes a
/// click without an entry for a 1 px click once the scene has any); every other field stays
/// as it was (serde_json orders an object's keys alphabetically).
///
/// # Errors
/// [`VisionError::InvalidScene`] when the value is not a JSON object or lacks a click's
/// field.
pub fn write_snapped(
    scene: &mut Value,
    snapped: &[SnappedClick],
    kept_sigma_px: Option<f64>,
) -> Result<()> {
    if !scene.is_object() {
        return Err(VisionError::InvalidScene {
            message: "the scene is not a JSON object".to_owned(),
        });
    }
    let mut table = match scene.get(COVARIANCES_FIELD) {
        Some(Value::Object(m)) => m.clone(),
        _ => Map::new(),
    };
    for s in snapped {
        let field = s.place.field();
        let Some(cov) = s.snap.covariance_px2 else {
            if let Some(sigma) = kept_sigma_px
                && !table.contains_key(&field)
                && !matches!(s.place, ClickPlace::Floor { .. })
            {
                let v = rounded(sigma * sigma, 6);
                table.insert(field, json!([[v, 0.0], [0.0, v]]));
            }
            continue;
        };
        let Some(slot) = s.place.point_in_json(scene) else {
            return Err(VisionError::InvalidScene {
                message: format!("the scene has no `{field}`"),
            });
        };
        *slot = json!([
            rounded(s.snap.point_px[0], 4),
            rounded(s.snap.point_px[1], 4)
        ]);
        table.insert(
            field,
            json!([
                [rounded(cov[0][0], 6), rounded(cov[0][1], 6)],
                [rounded(cov[1][0], 6), rounded(cov[1][1], 6)]
            ]),
        );
    }
    if let Some(obj) = scene.as_object_mut()
        && !table.is_empty()
    {
        obj.insert(COVARIANCES_FIELD.to_owned(), Value::Object(table));
    }
    Ok(())
}

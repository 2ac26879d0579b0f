//! What the lens distortion's uncertainty adds to a map's error bars.
//!
//! A scene's `lens_distortion` gives the division model's `k` with a standard deviation
//! `k_sd`. The fit undistorts the clicks with `k` and treats them as exact there, so the
//! error bars it computes leave out what `k` itself may be off by. `k` is a *consider*
//! parameter here: the map is rebuilt with `k + k_sd` and `k - k_sd`, and half the change of
//! every reported value (an object's centroid, sides, height and yaw; the camera's focal
//! length, principal point when fitted, pitch, roll, height and the room's yaw; a room's
//! station points and headings) is added in quadrature to its error bar, the centroid's as a
//! rank-one covariance. Central differences of a refit: exact for a value linear in `k` over
//! one sd, and they carry every correlation the refit sees. A photo's refit starts from its
//! fit's answer with everything the fit chose held (the vanishing-point reading, the click
//! noise it estimated, the evidence it widened; [`crate::fit::Fitted`]'s `refit_with_lens`):
//! only the clicks move with `k`. In a room each photo's `k` is its own consider parameter:
//! the joint fit again at that photo's `k +- k_sd` with the chosen placement held, the photos'
//! spreads added (their lenses are independent).

use super::types::{CameraReport, FloorMap};
use crate::error::{MetrologyError, Result};
use crate::fit::ellipse_95;
use crate::interrupt::Interrupt;
use crate::room::RoomFitted;
use crate::scene::{DivisionModel, LensDistortion, MAX_DIVISION_STRETCH, Scene};

/// The yaw of a box footprint's longer side, degrees in `[0, 180)`.
fn longer_side_yaw_deg(footprint: &[[f64; 2]]) -> Option<f64> {
    let [a, b, c, ..] = footprint else {
        return None;
    };
    let side = |p: &[f64; 2], q: &[f64; 2]| [q[0] - p[0], q[1] - p[1]];
    let (u, v) = (side(a, b), side(b, c));
    let longer = if u[0].hypot(u[1]) >= v[0].hypot(v[1]) {
        u
    } else {
        v
    };
    Some(longer[1].atan2(longer[0]).to_degrees().rem_euclid(180.0))
}

/// The difference of two angles in degrees modulo `period`, in `(-period/2, period/2]`.
fn angle_difference_deg(a: f64, b: f64, period: f64) -> f64 {
    let d = (a - b).rem_euclid(period);
    if d > 0.5 * period { d - period } else { d }
}

/// `sd` and `extra` added in quadrature.
fn quadrature(sd: f64, extra: f64) -> f64 {
    sd.hypot(extra)
}

/// Adds half the change from `lo` to `hi` (times `scale`: 0.5 for a central difference, 1 for
/// a one-sided one) of every reported value to `map`'s error bars in quadrature: every
/// object's centroid (as a rank-one covariance), sides, height and yaw, and every camera's
/// (`camera`, and a room's `cameras`) focal length, principal point (when fitted), pitch,
/// roll, height, room yaw, and a room's station points and headings.
fn add_spread(map: &mut FloorMap, hi: &FloorMap, lo: &FloorMap, scale: f64) {
    for (i, o) in map.objects.iter_mut().enumerate() {
        let (Some(a), Some(b)) = (hi.objects.get(i), lo.objects.get(i)) else {
            continue;
        };
        let Some(u) = o.uncertainty.as_mut() else {
            continue;
        };
        let dc = [
            scale * (a.centroid[0] - b.centroid[0]),
            scale * (a.centroid[1] - b.centroid[1]),
        ];
        let c = &mut u.centroid_covariance;
        c[0][0] += dc[0] * dc[0];
        c[0][1] += dc[0] * dc[1];
        c[1][0] += dc[1] * dc[0];
        c[1][1] += dc[1] * dc[1];
        u.centroid_ellipse_95 = ellipse_95(o.centroid, *c);
        if let Some(sd) = u.corner_sd.as_mut() {
            // The corner that moves most, with the least certain corner's sd: at least as
            // large as any one corner's.
            let moved = a
                .footprint
                .iter()
                .zip(&b.footprint)
                .map(|(p, q)| scale * (p[0] - q[0]).hypot(p[1] - q[1]))
                .fold(0.0, f64::max);
            *sd = quadrature(*sd, moved);
        }
        if let (Some(sd), Some(sa), Some(sb)) = (u.length_sd.as_mut(), a.size, b.size) {
            *sd = quadrature(*sd, scale * (sa.length - sb.length));
        }
        if let (Some(sd), Some(sa), Some(sb)) = (u.breadth_sd.as_mut(), a.size, b.size) {
            *sd = quadrature(*sd, scale * (sa.breadth - sb.breadth));
        }
        if let (Some(sd), Some(ha), Some(hb)) = (u.height_sd.as_mut(), a.height, b.height) {
            *sd = quadrature(*sd, scale * (ha - hb));
        }
        if let (Some(sd), Some(ya), Some(yb)) = (
            u.yaw_sd_deg.as_mut(),
            longer_side_yaw_deg(&a.footprint),
            longer_side_yaw_deg(&b.footprint),
        ) {
            *sd = quadrature(*sd, scale * angle_difference_deg(ya, yb, 180.0));
        }
    }
    add_camera_spread(&mut map.camera, &hi.camera, &lo.camera, scale);
    for (i, c) in map.cameras.iter_mut().enumerate() {
        if let (Some(a), Some(b)) = (hi.cameras.get(i), lo.cameras.get(i)) {
            add_camera_spread(c, a, b, scale);
        }
    }
}

/// [`add_spread`] for one camera.
fn add_camera_spread(camera: &mut CameraReport, a: &CameraReport, b: &CameraReport, scale: f64) {
    let Some(u) = camera.uncertainty.as_mut() else {
        return;
    };
    u.focal_px_sd = quadrature(u.focal_px_sd, scale * (a.focal_px - b.focal_px));
    u.pitch_deg_sd = quadrature(u.pitch_deg_sd, scale * (a.pitch_deg - b.pitch_deg));
    u.roll_deg_sd = quadrature(u.roll_deg_sd, scale * (a.roll_deg - b.roll_deg));
    u.room_yaw_deg_sd = quadrature(
        u.room_yaw_deg_sd,
        scale * angle_difference_deg(a.room_yaw_deg, b.room_yaw_deg, 90.0),
    );
    if u.height_sd > 0.0 {
        u.height_sd = quadrature(u.height_sd, scale * (a.height - b.height));
    }
    if let Some(sd) = u.principal_point_px_sd.as_mut() {
        for (axis, s) in sd.iter_mut().enumerate() {
            *s = quadrature(
                *s,
                scale * (a.principal_point[axis] - b.principal_point[axis]),
            );
        }
    }
    if let Some(sd) = u.position_sd.as_mut() {
        for (axis, s) in sd.iter_mut().enumerate() {
            *s = quadrature(*s, scale * (a.position[axis] - b.position[axis]));
        }
    }
    if let (Some(sd), Some(ha), Some(hb)) =
        (u.heading_deg_sd.as_mut(), a.heading_deg, b.heading_deg)
    {
        *sd = quadrature(*sd, scale * angle_difference_deg(ha, hb, 360.0));
    }
}

/// The maps at `k + sd` and `k - sd` as `add_spread` takes them: both and 0.5, or the one
/// that exists with `map` itself and 1 (a one-sided difference); `None` without either.
fn sides<'a>(
    map: &'a FloorMap,
    plus: Option<&'a FloorMap>,
    minus: Option<&'a FloorMap>,
) -> Option<(&'a FloorMap, &'a FloorMap, f64)> {
    match (plus, minus) {
        (Some(p), Some(m)) => Some((p, m, 0.5)),
        (Some(p), None) => Some((p, map, 1.0)),
        (None, Some(m)) => Some((map, m, 1.0)),
        (None, None) => None,
    }
}

/// Whether a rebuilt map reports the same things as `map` (objects, cameras, units).
fn comparable(map: &FloorMap, other: &FloorMap) -> bool {
    other.objects.len() == map.objects.len()
        && other.cameras.len() == map.cameras.len()
        && other.units == map.units
}

/// Adds the spread of `scene`'s `k_sd` to `map`'s error bars, with `build` the map of the
/// photo refitted at `k +- k_sd`: given the scene undistorted by the shifted lens, the lens
/// the fit's clicks were undistorted by and the shifted one (a side whose model would fold the
/// image is left out; with neither, the error bars stay and a warning says so). Nothing to do
/// without a `k_sd` or without error bars.
///
/// # Errors
/// None of its own; a rebuild's error is not one (the side is left out).
pub(super) fn add_lens_spread(
    scene: &Scene,
    map: &mut FloorMap,
    build: impl Fn(&Scene, &DivisionModel, &DivisionModel) -> Result<FloorMap>,
) {
    let Some(LensDistortion { k, k_sd: Some(sd) }) = scene.lens_distortion else {
        return;
    };
    if sd <= 0.0 || map.objects.iter().all(|o| o.uncertainty.is_none()) {
        return;
    }
    let Some(from) = scene.division_model() else {
        return;
    };
    let shifted = |dk: f64| -> Option<FloorMap> {
        let mut s = scene.clone();
        s.lens_distortion = Some(LensDistortion {
            k: k + dk,
            k_sd: None,
        });
        let to = s.division_model()?;
        if to.stretch(s.image) > MAX_DIVISION_STRETCH {
            return None;
        }
        let pinhole = s.undistorted();
        build(&pinhole, &from, &to)
            .ok()
            .filter(|m| comparable(map, m))
    };
    // Half the central difference, or the whole one-sided one when a side is out of reach.
    let (plus, minus) = (shifted(sd), shifted(-sd));
    let Some((hi, lo, scale)) = sides(map, plus.as_ref(), minus.as_ref()) else {
        map.warnings.push(format!(
            "the lens distortion's sd ({sd}) is not in the error bars: the map could not be rebuilt with k = {} or {}",
            k + sd,
            k - sd
        ));
        return;
    };
    let (hi, lo) = (hi.clone(), lo.clone());
    add_spread(map, &hi, &lo, scale);
}

/// Adds the spread of every `k_sd` of a room's photos to its map's error bars: for each photo
/// with a `k_sd`, the joint fit `fitted` again with that photo's clicks undistorted by
/// `k + k_sd` and by `k - k_sd`, every photo's placement as chosen
/// ([`RoomFitted::refit_with_lens`]: two joint fits, no placement search), and `map_of` its
/// map; each photo's spread added in quadrature (the photos' lenses are independent). A side
/// whose model would fold the image, whose refit fails or whose map differs in what it
/// reports is left out; with neither side, the error bars stay and a warning names the photo.
///
/// Returns, per photo, the refits' `(k, cost)` (for the lens's profile,
/// [`super::lens_refine`]).
///
/// # Errors
/// [`MetrologyError::Interrupted`] when `interrupt` fires during a refit; no other (a refit's
/// error leaves its side out).
pub(super) fn add_room_lens_spread(
    scene: &Scene,
    fitted: &RoomFitted,
    map: &mut FloorMap,
    map_of: impl Fn(&Scene, &RoomFitted) -> Result<FloorMap>,
    interrupt: &Interrupt,
) -> Result<Vec<Vec<(f64, f64)>>> {
    let mut costs = vec![Vec::new(); scene.photo_count()];
    if map.objects.iter().all(|o| o.uncertainty.is_none()) {
        return Ok(costs);
    }
    for (n, photo) in scene.photos().enumerate() {
        let Some(LensDistortion { k, k_sd: Some(sd) }) = photo.lens_distortion else {
            continue;
        };
        let Some(from) = photo.division_model().filter(|_| sd > 0.0) else {
            continue;
        };
        // The refits' costs, for the lens's profile.
        let found = std::cell::RefCell::new(Vec::new());
        let shifted = |dk: f64| -> Result<Option<FloorMap>> {
            let lens = LensDistortion {
                k: k + dk,
                k_sd: None,
            };
            let to = DivisionModel::new(lens.k, photo.image, photo.principal_point);
            if to.stretch(photo.image) > MAX_DIVISION_STRETCH {
                return Ok(None);
            }
            let mut s = scene.clone();
            if let Some(p) = s.photo_mut(n) {
                p.lens_distortion = Some(lens);
            }
            let pinhole = s.undistorted();
            match fitted.refit_with_lens(&pinhole, n, &from, &to, interrupt) {
                Ok(refitted) => {
                    found.borrow_mut().push((lens.k, refitted.cost()));
                    Ok(map_of(&pinhole, &refitted)
                        .ok()
                        .filter(|m| comparable(map, m)))
                }
                Err(e @ MetrologyError::Interrupted { .. }) => Err(e),
                Err(_) => Ok(None),
            }
        };
        let (plus, minus) = (shifted(sd)?, shifted(-sd)?);
        costs[n] = found.into_inner();
        let Some((hi, lo, scale)) = sides(map, plus.as_ref(), minus.as_ref()) else {
            map.warnings.push(format!(
                "photo {}'s lens distortion sd ({sd}) is not in the error bars: the room could not be refitted with its k = {} or {}",
                n + 1,
                k + sd,
                k - sd
            ));
            continue;
        };
        let (hi, lo) = (hi.clone(), lo.clone());
        add_spread(map, &hi, &lo, scale);
    }
    Ok(costs)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn yaw_of_the_longer_side_folds_into_half_a_turn() {
        let fp = [[0.0, 0.0], [-2.0, 0.0], [-2.0, 1.0], [0.0, 1.0]];
        assert!((longer_side_yaw_deg(&fp).unwrap() - 0.0).abs() < 1e-12);
        let fp = [[0.0, 0.0], [0.0, 1.0], [-3.0, 1.0], [-3.0, 0.0]];
        assert!((longer_side_yaw_deg(&fp).unwrap() - 0.0).abs() < 1e-12);
        assert!((angle_difference_deg(179.5, 0.5, 180.0) + 1.0).abs() < 1e-12);
    }
}

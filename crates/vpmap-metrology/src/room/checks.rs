//! Physical consistency of a room hypothesis: what a real room cannot be. Used to break ties
//! between placements the clicks fit about equally well (a photo tied by one box fits as well
//! turned by half a turn).
//!
//! Counted, each one a violation:
//! * a camera, a floor corner of another photo or a corner of a box outside a photo's walls:
//!   the lines through two consecutive floor-outline corners both inside its image (a wall
//!   meets the floor there; an edge to a corner on the image's border is where the photo
//!   ends), by more than [`WALL_MARGIN`] of the outline's size; the room is taken as convex
//!   (Manhattan rooms mostly are);
//! * two boxes whose footprints overlap by more than [`OVERLAP_SHARE`] of the smaller one
//!   (more than their error bars allow for the clicks that place them), unless their sides
//!   agree within their error bars (then they may be one box named differently in two
//!   photos): the differences of their shorter and of their longer sides lie inside the
//!   95 % ellipse of the differences' covariance in this hypothesis ([`CHI2_2DOF_95`], the
//!   fit's click variance times `(J^T J)^-1`, propagated by central differences as the
//!   map's error bars are). Without a covariance (a singular fit, or no variance given)
//!   the sides must agree within [`OVERLAP_SHARE`] of the longer one instead;
//! * a camera standing inside a box (deeper than [`OVERLAP_SHARE`] of its smaller side).
//!
//! Every clicked point lies in front of its camera in any hypothesis the joint fit accepts
//! (its residuals are not defined otherwise), so that check is the fit's own.

use geo::{Area, BooleanOps, Contains, Coord, LineString, Point, Polygon};
use nalgebra::Vector2;

use super::model::{Place, RoomProblem, Shape};
use crate::fit::CHI2_2DOF_95;
use crate::fit::model::px;
use crate::fit::solve::{Factored, Model};
use crate::fit::uncertainty::{gradients, quad};
use crate::scene::Scene;

/// Share of a floor outline's size a point may lie outside its walls (the clicks' noise).
pub(crate) const WALL_MARGIN: f64 = 0.05;

/// Share of the smaller box two footprints may overlap by, and of its smaller side a camera
/// may stand inside a box by.
pub(crate) const OVERLAP_SHARE: f64 = 0.1;

/// The violations of one hypothesis.
#[derive(Debug, Clone, Default)]
pub(crate) struct Physical {
    /// Cameras, floor corners and box corners outside another photo's walls.
    pub outside_walls: usize,
    /// Pairs of boxes that overlap.
    pub overlaps: Vec<(String, String)>,
    /// Cameras (photo, from 0) inside a box.
    pub cameras_inside: Vec<(usize, String)>,
}

impl Physical {
    /// Every violation.
    pub fn total(&self) -> usize {
        self.outside_walls + self.overlaps.len() + self.cameras_inside.len()
    }
}

fn polygon(points: &[Vector2<f64>]) -> Polygon<f64> {
    let mut ring: Vec<Coord<f64>> = points.iter().map(|p| Coord { x: p.x, y: p.y }).collect();
    if let Some(first) = ring.first().copied() {
        ring.push(first);
    }
    Polygon::new(LineString::new(ring), Vec::new())
}

/// The sorted sides (shorter, longer) of the footprint of box part `part` for cameras and
/// objects `x`, room frame.
fn box_sides(problem: &RoomProblem, x: &[f64], part: usize) -> Option<(f64, f64)> {
    let views = problem.views(x.get(..problem.camera_len)?);
    let room_cam = views.first()?.cam;
    let shape = problem.parts.get(part)?;
    let p = problem.part_params(x, part);
    let corner = |a, b| {
        let v = shape.point(&room_cam, p, Place::Corner(a, b, 0));
        Vector2::new(v.x, v.y)
    };
    let origin = corner(0, 0);
    let (u, v) = (
        (corner(1, 0) - origin).norm(),
        (corner(0, 1) - origin).norm(),
    );
    Some((u.min(v), u.max(v)))
}

/// Whether box parts `a` and `b` may be one box: the differences of their shorter and longer
/// sides inside the 95 % ellipse of their covariance ([`CHI2_2DOF_95`]), `variance` times
/// `(J^T J)^-1` at `x`; `None` when there is no such covariance (a singular fit).
fn sides_agree_within_error_bars(
    problem: &RoomProblem,
    x: &[f64],
    factored: &Factored,
    variance: f64,
    (a, b): (usize, usize),
) -> Option<bool> {
    let difference = |xs: &[f64]| match (box_sides(problem, xs, a), box_sides(problem, xs, b)) {
        (Some(sa), Some(sb)) => [sa.0 - sb.0, sa.1 - sb.1],
        _ => [f64::NAN; 2],
    };
    let d = difference(x);
    let g = gradients(problem, x, &[a, b], difference, [false, false]);
    let (g0, g1) = (g.first()?, g.get(1)?);
    let (c00, c01, c11) = (
        variance * quad(factored, g0, g0),
        variance * quad(factored, g0, g1),
        variance * quad(factored, g1, g1),
    );
    let det = c00 * c11 - c01 * c01;
    if !(det.is_finite() && det > 0.0 && c00 > 0.0 && d.iter().all(|v| v.is_finite())) {
        return None;
    }
    let chi2 = (c11 * d[0] * d[0] - 2.0 * c01 * d[0] * d[1] + c00 * d[1] * d[1]) / det;
    Some(chi2 <= CHI2_2DOF_95)
}

/// The physical checks of the room for cameras and objects `x` of `problem`; `names` are its
/// parts' names. `variance` is the fit's click variance, for the boxes' error bars (see the
/// [module docs](self)); `None` compares their sides by [`OVERLAP_SHARE`].
pub(crate) fn physical(
    scene: &Scene,
    problem: &RoomProblem,
    x: &[f64],
    names: &[String],
    variance: Option<f64>,
) -> Physical {
    let views = problem.views(&x[..problem.camera_len]);
    let Some(room_cam) = views.first().map(|v| v.cam) else {
        return Physical::default();
    };
    // Box footprints, room frame.
    let mut boxes: Vec<(String, Vec<Vector2<f64>>)> = Vec::new();
    let mut box_parts: Vec<usize> = Vec::new();
    for (i, part) in problem.parts.iter().enumerate() {
        if let Shape::Box { .. } = part.shape {
            let p = problem.part_params(x, i);
            let fp = [(0, 0), (1, 0), (1, 1), (0, 1)]
                .iter()
                .map(|&(a, b)| {
                    let v = part.point(&room_cam, p, Place::Corner(a, b, 0));
                    Vector2::new(v.x, v.y)
                })
                .collect();
            boxes.push((names.get(i).cloned().unwrap_or_default(), fp));
            box_parts.push(i);
        }
    }
    let mut out = Physical {
        outside_walls: outside_walls(scene, &views, &boxes),
        ..Physical::default()
    };
    let polys: Vec<Polygon<f64>> = boxes.iter().map(|(_, fp)| polygon(fp)).collect();
    let areas: Vec<f64> = polys.iter().map(Area::unsigned_area).collect();
    // Sorted sides: two overlapping boxes of one size may be one box named differently in
    // two photos (the map warns about them elsewhere), not a misplaced photo.
    let sides: Vec<(f64, f64)> = boxes
        .iter()
        .map(|(_, fp)| {
            let (u, v) = ((fp[1] - fp[0]).norm(), (fp[3] - fp[0]).norm());
            (u.min(v), u.max(v))
        })
        .collect();
    let share_alike = |a: usize, b: usize| {
        let close = |x: f64, y: f64| (x - y).abs() <= OVERLAP_SHARE * x.max(y);
        close(sides[a].0, sides[b].0) && close(sides[a].1, sides[b].1)
    };
    // The covariance, factored once and only when two boxes overlap.
    let mut factored: Option<Option<Factored>> = None;
    for a in 0..boxes.len() {
        for b in a + 1..boxes.len() {
            let shared = polys[a].intersection(&polys[b]).unsigned_area();
            if shared <= OVERLAP_SHARE * areas[a].min(areas[b]) {
                continue;
            }
            let by_error_bars = variance.and_then(|variance| {
                let f = factored
                    .get_or_insert_with(|| problem.normal(x)?.factor(0.0).ok())
                    .as_ref()?;
                let parts = (*box_parts.get(a)?, *box_parts.get(b)?);
                sides_agree_within_error_bars(problem, x, f, variance, parts)
            });
            if by_error_bars.unwrap_or_else(|| share_alike(a, b)) {
                continue;
            }
            out.overlaps.push((boxes[a].0.clone(), boxes[b].0.clone()));
        }
    }
    for (k, v) in views.iter().enumerate() {
        for (name, fp) in &boxes {
            // The box shrunk about its centre by the margin.
            let centre = fp.iter().sum::<Vector2<f64>>() / 4.0;
            let inner: Vec<Vector2<f64>> = fp
                .iter()
                .map(|c| centre + (c - centre) * (1.0 - 2.0 * OVERLAP_SHARE))
                .collect();
            if polygon(&inner).contains(&Point::new(v.position.x, v.position.y)) {
                out.cameras_inside.push((k, name.clone()));
            }
        }
    }
    out
}

/// Cameras, floor corners and box corners outside another photo's walls.
fn outside_walls(
    scene: &Scene,
    views: &[super::model::View],
    boxes: &[(String, Vec<Vector2<f64>>)],
) -> usize {
    let mut floors: Vec<Vec<(Vector2<f64>, bool)>> = Vec::new();
    for (k, p) in scene.photos().enumerate() {
        let Some(view) = views.get(k) else { continue };
        let (w, h) = (f64::from(p.image.width), f64::from(p.image.height));
        let inside = |q: [f64; 2]| q[0] > 1.0 && q[0] < w - 1.0 && q[1] > 1.0 && q[1] < h - 1.0;
        floors.push(
            p.floor
                .iter()
                .filter_map(|q| {
                    let own = view.cam.floor_point(px(*q))?;
                    Some((view.room_from_own(own), inside(*q)))
                })
                .collect(),
        );
    }
    let corners: Vec<Vector2<f64>> = boxes
        .iter()
        .flat_map(|(_, fp)| fp.iter().copied())
        .collect();
    let mut count = 0;
    for (q, floor) in floors.iter().enumerate() {
        let m = floor.len();
        if m < 3 {
            continue;
        }
        // The outline's orientation: the floor is on the left of a counter-clockwise ring.
        let area: f64 = (0..m).map(|i| floor[i].0.perp(&floor[(i + 1) % m].0)).sum();
        let sign = area.signum();
        let size = floor
            .iter()
            .map(|(a, _)| a.norm())
            .fold(0.0f64, f64::max)
            .max(1.0);
        let margin = WALL_MARGIN * size;
        for i in 0..m {
            let ((a, wa), (b, wb)) = (floor[i], floor[(i + 1) % m]);
            if !(wa && wb) || (b - a).norm() <= 1e-9 * size {
                continue;
            }
            let side = |p: Vector2<f64>| sign * (b - a).perp(&(p - a)) / (b - a).norm();
            for (k, other) in floors.iter().enumerate() {
                if k == q {
                    continue;
                }
                if views.get(k).is_some_and(|v| side(v.position) < -margin) {
                    count += 1;
                }
                count += other.iter().filter(|(p, _)| side(*p) < -margin).count();
            }
            count += corners.iter().filter(|p| side(**p) < -margin).count();
        }
    }
    count
}

#[cfg(test)]
#[allow(clippy::unwrap_used, clippy::expect_used, clippy::indexing_slicing)]
mod tests {
    use super::*;
    use crate::fit::MIN_CLICK_SIGMA_PX;
    use crate::room::fit_room;
    use crate::synth::{RoomSynthOptions, synthesize_room};

    /// A synthetic two-photo room (exact clicks) in which one box both photos show is named
    /// apart in the second photo: the fit has it twice, as parts `a` and `b`, in one place.
    fn one_box_named_twice() -> (Scene, RoomProblem, Vec<f64>, Vec<String>, usize, usize) {
        for seed in 0..40 {
            let options = RoomSynthOptions {
                seed,
                photos: 2,
                boxes: 6,
                ..RoomSynthOptions::default()
            };
            let Ok((mut scene, _truth)) = synthesize_room(&options) else {
                continue;
            };
            let first: Vec<String> = scene.objects.iter().map(|o| o.name.clone()).collect();
            let second = &mut scene.other_photos[0].objects;
            let shared: Vec<usize> = (0..second.len())
                .filter(|&i| first.contains(&second[i].name))
                .collect();
            if shared.len() < 3 {
                continue;
            }
            let renamed = second[shared[0]].name.clone();
            second[shared[0]].name = format!("{renamed} (photo 2)");
            let Ok(fitted) = fit_room(&scene) else {
                continue;
            };
            let names: Vec<String> = fitted.objects.iter().map(|o| o.name.clone()).collect();
            let a = names.iter().position(|n| *n == renamed).unwrap();
            let b = names
                .iter()
                .position(|n| *n == format!("{renamed} (photo 2)"))
                .unwrap();
            return (scene, fitted.problem, fitted.x, names, a, b);
        }
        panic!("no synthetic room with three shared boxes fitted");
    }

    #[test]
    fn one_box_named_twice_is_told_from_two_boxes_by_the_error_bars_of_their_sides() {
        let (scene, problem, x, names, a, b) = one_box_named_twice();
        let overlapping = |x: &[f64], variance: Option<f64>| {
            physical(&scene, &problem, x, &names, variance)
                .overlaps
                .iter()
                .any(|(p, q)| (p, q) == (&names[a], &names[b]) || (p, q) == (&names[b], &names[a]))
        };
        let exact = Some(MIN_CLICK_SIGMA_PX.powi(2));
        // One box twice, exact clicks: one place, one size, no violation either way.
        assert!(!overlapping(&x, exact));
        assert!(!overlapping(&x, None));
        // Scale the second box's sides about its first corner: one place, another size.
        let grown = |share: f64| {
            let mut x = x.clone();
            let at = problem.offsets[b];
            x[at + 2] *= 1.0 + share;
            x[at + 3] *= 1.0 + share;
            x
        };
        // Two boxes 6 % apart in size in one place, fitted from exact clicks (sides known to
        // a few thousandths of a camera height): two boxes overlapping, which no room
        // allows. The fixed 10 % share took them for one box.
        assert!(overlapping(&grown(0.06), exact));
        assert!(!overlapping(&grown(0.06), None));
        // 12 % apart with the error bars of clicks 8 px off: one box named twice whose
        // sizes the clicks cannot tell apart. The fixed share counted it an overlap.
        let noisy = Some(8.0f64.powi(2));
        assert!(!overlapping(&grown(0.12), noisy));
        assert!(overlapping(&grown(0.12), None));
    }
}

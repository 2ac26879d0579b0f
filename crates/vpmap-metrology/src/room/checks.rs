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
//!   agree within that share (then they may be one box named differently in two photos);
//! * a camera standing inside a box (deeper than [`OVERLAP_SHARE`] of its smaller side).
//!
//! Every clicked point lies in front of its camera in any hypothesis the joint fit accepts
//! (its residuals are not defined otherwise), so that check is the fit's own.

use geo::{Area, BooleanOps, Contains, Coord, LineString, Point, Polygon};
use nalgebra::Vector2;

use super::model::{Place, RoomProblem, Shape};
use crate::fit::model::px;
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

/// The physical checks of the room for cameras and objects `x` of `problem`; `names` are its
/// parts' names.
pub(crate) fn physical(
    scene: &Scene,
    problem: &RoomProblem,
    x: &[f64],
    names: &[String],
) -> Physical {
    let views = problem.views(&x[..problem.camera_len]);
    let Some(room_cam) = views.first().map(|v| v.cam) else {
        return Physical::default();
    };
    // Box footprints, room frame.
    let mut boxes: Vec<(String, Vec<Vector2<f64>>)> = Vec::new();
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
    let alike = |a: usize, b: usize| {
        let close = |x: f64, y: f64| (x - y).abs() <= OVERLAP_SHARE * x.max(y);
        close(sides[a].0, sides[b].0) && close(sides[a].1, sides[b].1)
    };
    for a in 0..boxes.len() {
        for b in a + 1..boxes.len() {
            if alike(a, b) {
                continue;
            }
            let shared = polys[a].intersection(&polys[b]).unsigned_area();
            if shared > OVERLAP_SHARE * areas[a].min(areas[b]) {
                out.overlaps.push((boxes[a].0.clone(), boxes[b].0.clone()));
            }
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

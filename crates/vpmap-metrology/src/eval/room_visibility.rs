//! The floor a room's true cameras see: the most of the floor any map of those photos can know.
//!
//! A map knows the floor some photo shows and no object hides, and the floor under the objects
//! (occupied). With exact clicks that is, at best, what the true cameras see past the true
//! boxes. [`visible_floor_share`] measures it from the truth alone, by ray casting on a grid of
//! floor points, independently of the map's polygon code: a floor point counts when it lies
//! under a box, or when some camera's [`PinholeCamera`] projects it inside the image (the part
//! a floor outline covers, [`FLOOR_OUTLINE_INSET`] inside its borders) and the line of sight
//! from the camera centre to it meets no box (each box a prism on its footprint, up to its
//! height).

use nalgebra::{Vector2, Vector3};

use crate::scene::ImageSize;
use crate::synth::{FLOOR_OUTLINE_INSET, PinholeCamera, RoomTruth, RoomTruthObject};

/// Spacing of the floor points, metres.
pub const VISIBILITY_STEP_M: f64 = 0.025;

/// The share (0 to 1) of the true room's floor that lies under a box or that one of the
/// cameras `photos` (0-based; `images` their photos' sizes) sees past every box, on a grid of
/// [`VISIBILITY_STEP_M`] (cell centres).
#[must_use]
pub fn visible_floor_share(truth: &RoomTruth, images: &[ImageSize], photos: &[usize]) -> f64 {
    let Some((lo, hi)) = bounds(&truth.room) else {
        return 0.0;
    };
    let cameras: Vec<(Vector2<f64>, f64, PinholeCamera)> = photos
        .iter()
        .filter_map(|&k| {
            let c = truth.cameras.get(k)?;
            let image = *images.get(k)?;
            Some((
                Vector2::new(c.position[0], c.position[1]),
                c.heading_deg.to_radians(),
                PinholeCamera {
                    image,
                    focal_px: c.focal_px,
                    principal_point_px: image.centre(),
                    height_m: c.height,
                    pitch_rad: c.pitch_deg.to_radians(),
                    roll_rad: c.roll_deg.to_radians(),
                },
            ))
        })
        .collect();
    let room: Vec<Vector2<f64>> = truth
        .room
        .iter()
        .map(|p| Vector2::new(p[0], p[1]))
        .collect();
    let boxes: Vec<(Vec<Vector2<f64>>, f64)> = truth.objects.iter().map(prism).collect();
    let (mut inside, mut known) = (0usize, 0usize);
    let columns = ((hi.x - lo.x) / VISIBILITY_STEP_M).ceil() as usize;
    let rows = ((hi.y - lo.y) / VISIBILITY_STEP_M).ceil() as usize;
    for j in 0..rows {
        for i in 0..columns {
            let q = lo + Vector2::new(i as f64 + 0.5, j as f64 + 0.5) * VISIBILITY_STEP_M;
            if !in_convex(&room, q) {
                continue;
            }
            inside += 1;
            let under_a_box = boxes.iter().any(|(fp, _)| in_convex(fp, q));
            if under_a_box
                || cameras
                    .iter()
                    .any(|(at, heading, cam)| sees(*at, *heading, cam, q, &boxes))
            {
                known += 1;
            }
        }
    }
    if inside == 0 {
        0.0
    } else {
        known as f64 / inside as f64
    }
}

/// A box's footprint (counter-clockwise) and height.
fn prism(o: &RoomTruthObject) -> (Vec<Vector2<f64>>, f64) {
    let mut fp: Vec<Vector2<f64>> = o
        .footprint
        .iter()
        .map(|p| Vector2::new(p[0], p[1]))
        .collect();
    if signed_area(&fp) < 0.0 {
        fp.reverse();
    }
    (fp, o.height)
}

fn bounds(points: &[[f64; 2]]) -> Option<(Vector2<f64>, Vector2<f64>)> {
    let first = points.first()?;
    let mut lo = Vector2::new(first[0], first[1]);
    let mut hi = lo;
    for p in points {
        lo = lo.inf(&Vector2::new(p[0], p[1]));
        hi = hi.sup(&Vector2::new(p[0], p[1]));
    }
    Some((lo, hi))
}

fn signed_area(p: &[Vector2<f64>]) -> f64 {
    (0..p.len())
        .map(|i| {
            let (a, b) = (p[i], p[(i + 1) % p.len()]);
            a.x * b.y - b.x * a.y
        })
        .sum::<f64>()
        / 2.0
}

/// Whether `q` lies inside a convex polygon of either orientation.
fn in_convex(poly: &[Vector2<f64>], q: Vector2<f64>) -> bool {
    let side = |i: usize| {
        let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
        (b - a).perp(&(q - a))
    };
    let sides: Vec<f64> = (0..poly.len()).map(side).collect();
    sides.iter().all(|s| *s >= 0.0) || sides.iter().all(|s| *s <= 0.0)
}

/// Whether the camera standing at `at` with `heading` (radians counter-clockwise from `+y`)
/// sees the floor point `q`: in front, inside its image, no box on the line of sight.
fn sees(
    at: Vector2<f64>,
    heading: f64,
    cam: &PinholeCamera,
    q: Vector2<f64>,
    boxes: &[(Vec<Vector2<f64>>, f64)],
) -> bool {
    let (s, c) = heading.sin_cos();
    let d = q - at;
    // The camera's plan frame: x right (c, s), y forward (-s, c).
    let local = Vector3::new(c * d.x + s * d.y, -s * d.x + c * d.y, 0.0);
    let (w, h) = (f64::from(cam.image.width), f64::from(cam.image.height));
    let (mx, my) = (FLOOR_OUTLINE_INSET * w, FLOOR_OUTLINE_INSET * h);
    let in_view = cam
        .project(local)
        .is_some_and(|p| p.x >= mx && p.x <= w - mx && p.y >= my && p.y <= h - my);
    if !in_view {
        return false;
    }
    boxes
        .iter()
        .all(|(fp, h)| !blocks(at, cam.height_m, q, fp, *h))
}

/// Whether the segment from the camera centre (`at`, height `camera_h`) to the floor point `q`
/// passes through the prism of convex footprint `fp` (counter-clockwise) and height `h`
/// before reaching `q`.
fn blocks(at: Vector2<f64>, camera_h: f64, q: Vector2<f64>, fp: &[Vector2<f64>], h: f64) -> bool {
    // Along the sight line t in [0, 1] from the camera to q, the height is camera_h (1 - t):
    // at or below the box's top for t >= 1 - h / camera_h.
    let t_low = if h >= camera_h {
        0.0
    } else {
        1.0 - h / camera_h
    };
    // Stop short of q itself: a point on a box's edge is seen past its own box.
    let (mut t0, mut t1): (f64, f64) = (t_low, 1.0 - 1e-9);
    let dir = q - at;
    // Cyrus-Beck: clip the segment to the inside of every edge.
    for i in 0..fp.len() {
        let (a, b) = (fp[i], fp[(i + 1) % fp.len()]);
        let edge = b - a;
        // Inside when edge.perp(p - a) >= 0 (counter-clockwise polygon).
        let f0 = edge.perp(&(at - a));
        let df = edge.perp(&dir);
        if df.abs() < 1e-15 {
            if f0 < 0.0 {
                return false;
            }
            continue;
        }
        let t = -f0 / df;
        if df > 0.0 {
            t0 = t0.max(t);
        } else {
            t1 = t1.min(t);
        }
        if t0 > t1 {
            return false;
        }
    }
    t0 < t1
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;

    #[test]
    fn a_box_hides_the_floor_behind_it_up_to_where_its_top_edge_points() {
        // Camera 2 m up at the origin; a box 1 m high from y = 2 to y = 3 across the view.
        let fp = vec![
            Vector2::new(-1.0, 2.0),
            Vector2::new(1.0, 2.0),
            Vector2::new(1.0, 3.0),
            Vector2::new(-1.0, 3.0),
        ];
        let at = Vector2::zeros();
        // The top's far edge (y = 3, 1 m up) points at y = 6 on the floor.
        assert!(blocks(at, 2.0, Vector2::new(0.0, 3.5), &fp, 1.0));
        assert!(blocks(at, 2.0, Vector2::new(0.0, 5.9), &fp, 1.0));
        assert!(!blocks(at, 2.0, Vector2::new(0.0, 6.1), &fp, 1.0));
        assert!(!blocks(at, 2.0, Vector2::new(0.0, 1.9), &fp, 1.0));
        // Beside the box.
        assert!(!blocks(at, 2.0, Vector2::new(2.5, 4.0), &fp, 1.0));
        // A box as tall as the camera hides everything behind it.
        assert!(blocks(at, 2.0, Vector2::new(0.0, 40.0), &fp, 2.0));
    }

    #[test]
    fn exact_clicks_know_no_more_than_the_true_cameras_see() {
        use crate::eval::{RoomTrialOptions, run_room_trial};
        for trial in 0..3 {
            let t = run_room_trial(
                5,
                trial,
                &RoomTrialOptions {
                    photos: 3,
                    boxes: 6,
                    sigmas_px: vec![0.0],
                },
            );
            let ev = t.outcomes[0].result.as_ref().unwrap();
            // The map's floor known, from exact clicks, is the ceiling up to the grid's
            // resolution (half a percent).
            assert!(
                (ev.joint.floor_known - ev.floor_visible).abs() < 0.005,
                "trial {trial}: map {} against the true cameras {}",
                ev.joint.floor_known,
                ev.floor_visible
            );
            assert!(ev.floor_visible < 1.0 && ev.floor_visible > 0.3);
        }
    }
}

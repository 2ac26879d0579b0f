//! Vanishing points from the clicked boxes alone: a second family of starting cameras for the
//! fit, for when the given or detected vanishing points are wrong (an occluding bar or a
//! clutter edge taken for a room direction) and every camera started from them runs into a
//! local minimum far from the clicks.
//!
//! Every box lined up with the room (not `own_yaw`) has its edges along the room's three
//! directions: two clicked corners that differ in one place of the box's grid
//! ([`crate::scene::BoxPoint::grid_index`]) span an edge along that direction. Which of the
//! box's two horizontal sides runs towards which horizontal vanishing point is read from the
//! given points (the side whose edges point closer to it); each direction's point is then the
//! least-squares intersection of its edges' lines, and the sides are read again against those
//! points until the reading settles. A direction with fewer than two edges, or with edges
//! whose lines are nearly one, keeps the given point.

use nalgebra::{Vector2, Vector3};

use crate::scene::{BoxPoint, ObjectShape, Scene};

/// A clicked box edge: its two end points, pixels `[x1, y1, x2, y2]`.
type Edge = [f64; 4];

/// The vanishing points the clicked boxes' edges give, in the order of `points` (two
/// horizontal ones, then the vertical one when there are three), each falling back to the
/// given point where the boxes have too few edges along it; `None` when no direction changed.
pub(super) fn box_edge_points(
    scene: &Scene,
    points: &[Vector3<f64>],
    image: crate::scene::ImageSize,
) -> Option<Vec<Vector3<f64>>> {
    if points.len() < 2 {
        return None;
    }
    let boxes: Vec<BoxEdges> = scene
        .objects
        .iter()
        .enumerate()
        .filter(|(index, object)| {
            matches!(
                object.shape(*index),
                Ok(ObjectShape::Box { own_yaw: false, .. })
            )
        })
        .filter_map(|(_, object)| box_edges(object))
        .collect();
    // Each box's sides read against the given points, then again against the points they
    // gave, until the reading settles (a given point far off can read a box near the other
    // point the wrong way round).
    let mut reference = points.to_vec();
    let mut found = None;
    for _ in 0..MAX_ROUNDS {
        let groups = assign(&boxes, &reference);
        let mut out = points.to_vec();
        let mut changed = false;
        for (g, edges) in groups.iter().enumerate().take(points.len()) {
            if edges.len() < 2 || !spread(edges) {
                continue;
            }
            if let Some(v) = super::init::homogeneous_vp(edges, image) {
                out[g] = v;
                changed = true;
            }
        }
        if !changed {
            return None;
        }
        let settled = found.as_ref() == Some(&out);
        reference.clone_from(&out);
        found = Some(out);
        if settled {
            break;
        }
    }
    found
}

/// Most rounds of reading the boxes' sides against the points they gave.
const MAX_ROUNDS: usize = 4;

/// A box's clicked edges: along its grid's `i` place, along `j`, and vertical.
type BoxEdges = (Vec<Edge>, Vec<Edge>, Vec<Edge>);

/// The edges towards each of `points` (two horizontal ones, then the vertical one): each box's
/// `i` side towards the horizontal point its edges point closer to.
fn assign(boxes: &[BoxEdges], points: &[Vector3<f64>]) -> [Vec<Edge>; 3] {
    let mut groups: [Vec<Edge>; 3] = [Vec::new(), Vec::new(), Vec::new()];
    let miss = |edges: &[Edge], g: usize| {
        edges
            .iter()
            .map(|e| points.get(g).map_or(0.0, |p| angle_off(e, *p)))
            .sum::<f64>()
    };
    for (along_i, along_j, vertical) in boxes {
        let straight = miss(along_i, 0) + miss(along_j, 1);
        let crossed = miss(along_i, 1) + miss(along_j, 0);
        let (to0, to1) = if straight <= crossed {
            (along_i, along_j)
        } else {
            (along_j, along_i)
        };
        groups[0].extend_from_slice(to0);
        groups[1].extend_from_slice(to1);
        groups[2].extend_from_slice(vertical);
    }
    groups
}

/// A box object's clicked edges: along its grid's `i` place, along `j`, and vertical.
fn box_edges(object: &crate::scene::ObjectSpec) -> Option<BoxEdges> {
    let base = object.base.as_ref()?;
    let mut corners: Vec<((u8, u8, u8), [f64; 2])> = base
        .given()
        .map(|(c, p)| {
            (
                BoxPoint {
                    corner: c,
                    top: false,
                }
                .grid_index(),
                p,
            )
        })
        .collect();
    if let Some(top) = &object.top {
        corners.extend(top.corners.given().map(|(c, p)| {
            (
                BoxPoint {
                    corner: c,
                    top: true,
                }
                .grid_index(),
                p,
            )
        }));
    }
    let (mut along_i, mut along_j, mut vertical) = (Vec::new(), Vec::new(), Vec::new());
    for (k, (a, pa)) in corners.iter().enumerate() {
        for (b, pb) in corners.iter().skip(k + 1) {
            let differ = [a.0 != b.0, a.1 != b.1, a.2 != b.2];
            let edge = [pa[0], pa[1], pb[0], pb[1]];
            match differ {
                [true, false, false] => along_i.push(edge),
                [false, true, false] => along_j.push(edge),
                [false, false, true] => vertical.push(edge),
                _ => {}
            }
        }
    }
    Some((along_i, along_j, vertical))
}

/// The angle (radians, 0 to pi/2) between an edge and the line from its midpoint to the
/// homogeneous point `v`.
fn angle_off(edge: &Edge, v: Vector3<f64>) -> f64 {
    let m = Vector2::new(0.5 * (edge[0] + edge[2]), 0.5 * (edge[1] + edge[3]));
    let d = Vector2::new(edge[2] - edge[0], edge[3] - edge[1]);
    let to = Vector2::new(v.x - m.x * v.z, v.y - m.y * v.z);
    let (dn, tn) = (d.norm(), to.norm());
    if dn == 0.0 || tn == 0.0 {
        return std::f64::consts::FRAC_PI_2;
    }
    (d.dot(&to) / (dn * tn)).abs().min(1.0).acos()
}

/// Whether the edges' lines are spread enough to meet at a point: some two of them at least
/// [`MIN_SPREAD_RAD`] apart in direction or [`MIN_SPREAD_PX`] apart across.
fn spread(edges: &[Edge]) -> bool {
    let line = |e: &Edge| {
        let d = Vector2::new(e[2] - e[0], e[3] - e[1]);
        let n = d.norm();
        (n > 0.0).then(|| (d / n, Vector2::new(e[0], e[1])))
    };
    let lines: Vec<(Vector2<f64>, Vector2<f64>)> = edges.iter().filter_map(line).collect();
    lines.iter().enumerate().any(|(k, (da, pa))| {
        lines.iter().skip(k + 1).any(|(db, pb)| {
            let cross = da.x * db.y - da.y * db.x;
            let apart = pb - pa;
            cross.abs() >= MIN_SPREAD_RAD
                || (da.x * apart.y - da.y * apart.x).abs() >= MIN_SPREAD_PX
        })
    })
}

/// Least angle (radians, as a sine) between two edges' lines that lets them fix a point.
const MIN_SPREAD_RAD: f64 = 0.01;

/// Least distance (pixels) between two parallel edges' lines that lets them fix a direction.
const MIN_SPREAD_PX: f64 = 20.0;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::synth::{SynthOptions, synthesize};

    /// A homogeneous point's direction from the principal point, as a unit vector.
    fn direction(v: Vector3<f64>, pp: [f64; 2], f: f64) -> Vector3<f64> {
        Vector3::new(v.x - pp[0] * v.z, v.y - pp[1] * v.z, f * v.z).normalize()
    }

    #[test]
    fn exact_clicks_give_the_true_vanishing_points_whatever_the_given_ones() {
        // The synthetic camera's own vanishing points (computed from its rotation, not from
        // any click) against the boxes' edges' intersection, with the given points a fifth of
        // the image diagonal off (enough to read some boxes the wrong way round at first).
        for seed in 0..24 {
            let (scene, truth) = synthesize(&SynthOptions {
                seed,
                ..SynthOptions::default()
            })
            .unwrap();
            let truth_points: Vec<Vector3<f64>> = scene
                .vanishing_points
                .iter()
                .map(|v| {
                    let p = v.point.unwrap();
                    Vector3::new(p[0], p[1], 1.0)
                })
                .collect();
            let f = truth.camera.focal_px;
            let pp = [
                f64::from(scene.image.width) / 2.0,
                f64::from(scene.image.height) / 2.0,
            ];
            let pp = truth.camera.principal_point.unwrap_or(pp);
            // Each given point moved by a fifth of the image.
            let shift = 0.2 * scene.image.diagonal();
            let given: Vec<Vector3<f64>> = truth_points
                .iter()
                .map(|p| Vector3::new(p.x + shift, p.y - shift, 1.0))
                .collect();
            let found = box_edge_points(&scene, &given, scene.image).unwrap();
            for (g, (a, b)) in found.iter().zip(&truth_points).enumerate() {
                let cos = direction(*a, pp, f).dot(&direction(*b, pp, f)).abs();
                let deg = cos.min(1.0).acos().to_degrees();
                assert!(deg < 1e-4, "seed {seed}, direction {g}: {deg} degrees off");
            }
        }
    }
}

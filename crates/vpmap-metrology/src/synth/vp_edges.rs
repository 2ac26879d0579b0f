//! Vanishing points given as the edges a user clicks instead of as points: the boxes' own
//! edges through their annotated corners, or long straight room lines drawn through the camera.

use nalgebra::{Vector2, Vector3};
use rand::{Rng, RngExt};

use super::camera::PinholeCamera;
use crate::error::{MetrologyError, Result};
use crate::scene::{BoxCorner, PixelPoint, Scene};

/// Rewrite the vanishing points of a scene as the box edges that meet there (two or more per
/// vanishing point), as a user clicking edges would give them. Uses the scene's (possibly
/// noisy) annotated corners, so noise reaches the vanishing points the way it would in use.
/// Only the vertical edges of a box marked `own_yaw` are used (its horizontal edges run to
/// its own vanishing points, not the room's). A vanishing point with fewer than two edges is
/// left as it was.
pub fn vanishing_points_as_lines(scene: &mut Scene) {
    let mut lines: Vec<Vec<[f64; 4]>> = vec![Vec::new(); scene.vanishing_points.len()];
    let points: Vec<Vector2<f64>> = scene
        .vanishing_points
        .iter()
        .map(|v| {
            v.point
                .map_or(Vector2::zeros(), |p| Vector2::new(p[0], p[1]))
        })
        .collect();
    let seg = |a: PixelPoint, b: PixelPoint| [a[0], a[1], b[0], b[1]];
    // How far a segment's line misses a vanishing point: the sine of the angle between the
    // segment and the direction from its first end to the point.
    let miss = |l: &[f64; 4], v: Vector2<f64>| {
        let a = Vector2::new(l[2] - l[0], l[3] - l[1]);
        let b = v - Vector2::new(l[0], l[1]);
        (a.x * b.y - a.y * b.x).abs() / (a.norm() * b.norm()).max(1e-300)
    };
    for obj in &scene.objects {
        let Some(base) = obj.base else { continue };
        let top = obj.top.map(|t| t.corners).unwrap_or_default();
        // The box's edges between given corners, by the axis they run along.
        let mut along: [Vec<[f64; 4]>; 3] = [Vec::new(), Vec::new(), Vec::new()];
        let levels = [base, top];
        // A box with its own yaw: its horizontal edges do not run to the room's vanishing
        // points (its vertical edges do).
        let horizontal_axes = if obj.own_yaw { 0 } else { 2 };
        for (axis, edges) in along.iter_mut().enumerate().take(horizontal_axes) {
            for corners in &levels {
                for (c, p) in corners.given() {
                    let (i, j) = c.grid_index();
                    if (if axis == 0 { i } else { j }) != 0 {
                        continue;
                    }
                    let other = if axis == 0 {
                        BoxCorner::at(c.view(), 1, j)
                    } else {
                        BoxCorner::at(c.view(), i, 1)
                    };
                    if let Some(q) = corners.get(other) {
                        edges.push(seg(p, q));
                    }
                }
            }
        }
        for (c, p) in base.given() {
            if let Some(q) = top.get(c) {
                along[2].push(seg(p, q));
            }
        }
        // Which horizontal vanishing point each floor axis runs to: the assignment whose
        // edges point at them best.
        let cost =
            |axis: usize, k: usize| along[axis].iter().map(|l| miss(l, points[k])).sum::<f64>();
        let (k0, k1) = if cost(0, 0) + cost(1, 1) <= cost(0, 1) + cost(1, 0) {
            (0, 1)
        } else {
            (1, 0)
        };
        let [a0, a1, vertical] = along;
        lines[k0].extend(a0);
        lines[k1].extend(a1);
        if lines.len() > 2 {
            lines[2].extend(vertical);
        }
    }
    for (vp, l) in scene.vanishing_points.iter_mut().zip(lines) {
        if l.len() >= 2 {
            vp.point = None;
            vp.lines = l;
        }
    }
}

/// How [`long_edges`] draws the edges a user would click to locate the vanishing points on a
/// real photo: the room's long straight lines (floor-wall and wall-ceiling junctions, wall
/// corners, door and window frames) rather than the objects' own short edges.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LongEdgeOptions {
    /// Length of every edge in the image, pixels.
    pub length_px: f64,
    /// Edges per vanishing point (at least 2).
    pub per_vanishing_point: usize,
    /// Margin kept from the image borders, as a fraction of the image's width and height.
    pub inset: f64,
}

impl Default for LongEdgeOptions {
    /// Three edges of 600 px per vanishing point, 2 % inside the image.
    fn default() -> Self {
        Self {
            length_px: 600.0,
            per_vanishing_point: 3,
            inset: 0.02,
        }
    }
}

/// Attempts per edge before [`long_edges`] gives up.
const LONG_EDGE_ATTEMPTS: usize = 2000;

/// Long straight edges running to each of the given world directions' vanishing points, as
/// segments `[x1, y1, x2, y2]` (one list per direction, in order), each the exact image of a
/// segment of a 3D line in that direction lying in front of the camera.
///
/// Per edge: a pixel `c` is drawn uniformly from the image less `inset`; the 3D line in
/// `direction` through the point one camera height along `c`'s viewing ray is the line a user
/// would click there (where along the ray does not change the line's image). The
/// part of that line in front of the camera images onto the ray from the vanishing point
/// through `c` (the whole line when the direction is parallel to the image plane). A
/// `length_px` stretch of that ray inside the inset image, at a uniform position, is taken;
/// its end points are pulled back onto the 3D line and projected through the camera, so they
/// are projections of 3D points (equal to the drawn pixels to rounding). A `c` whose ray has
/// too short a stretch inside the image is drawn again.
///
/// # Errors
/// [`MetrologyError::InvalidField`] for a non-positive or non-finite length, fewer than 2
/// edges, an inset outside `[0, 0.25]` or a zero direction; [`MetrologyError::Degenerate`]
/// when no edge of that length fits in the image for a direction (ask for shorter edges).
///
/// # Example
/// ```
/// use nalgebra::{Vector2, Vector3};
/// use rand::SeedableRng;
/// use vpmap_metrology::scene::{intersect_segments, ImageSize};
/// use vpmap_metrology::synth::{LongEdgeOptions, PinholeCamera, long_edges};
/// let image = ImageSize { width: 1600, height: 1200 };
/// let camera = PinholeCamera {
///     image, focal_px: 1000.0, principal_point_px: image.centre(), height_m: 1.5,
///     pitch_rad: 0.3, roll_rad: 0.05,
/// };
/// let direction = Vector3::new(0.6, 0.8, 0.0);
/// let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
/// let edges = long_edges(&camera, &[direction], &LongEdgeOptions::default(), &mut rng).unwrap();
/// assert_eq!(edges[0].len(), 3);
/// let vp = camera.vanishing_point(direction).unwrap();
/// let fitted = intersect_segments(&edges[0], image).unwrap();
/// assert!((fitted - vp).norm() < 1e-6 * vp.norm());
/// ```
pub fn long_edges(
    camera: &PinholeCamera,
    directions: &[Vector3<f64>],
    options: &LongEdgeOptions,
    rng: &mut impl Rng,
) -> Result<Vec<Vec<[f64; 4]>>> {
    let invalid = |field: &str, reason: String| MetrologyError::InvalidField {
        field: format!("long_edges.{field}"),
        reason,
    };
    let length = options.length_px;
    if !(length.is_finite() && length > 0.0) {
        return Err(invalid(
            "length_px",
            format!("must be a positive number of pixels, got {length}"),
        ));
    }
    if options.per_vanishing_point < 2 {
        return Err(invalid(
            "per_vanishing_point",
            format!(
                "at least 2 edges fix a vanishing point, got {}",
                options.per_vanishing_point
            ),
        ));
    }
    if !(0.0..=0.25).contains(&options.inset) {
        return Err(invalid(
            "inset",
            format!("must lie in [0, 0.25], got {}", options.inset),
        ));
    }
    let w = f64::from(camera.image.width);
    let h = f64::from(camera.image.height);
    let (x0, x1) = (options.inset * w, (1.0 - options.inset) * w);
    let (y0, y1) = (options.inset * h, (1.0 - options.inset) * h);
    let (right, down, forward) = camera.axes();
    let f = camera.focal_px;
    let pp = camera.principal_point_px;
    let ray = |pixel: Vector2<f64>| {
        let q = (pixel - pp) / f;
        right * q.x + down * q.y + forward
    };
    let mut out = Vec::with_capacity(directions.len());
    for (k, &dir) in directions.iter().enumerate() {
        let norm = dir.norm();
        if !(norm.is_finite() && norm > 0.0) {
            return Err(invalid(
                "directions",
                format!("direction {} is not a non-zero vector", k + 1),
            ));
        }
        let u = dir / norm;
        // The vanishing point in homogeneous pixels: (vxy, w), at infinity when w = 0.
        let w_h = u.dot(&forward);
        let v_xy = Vector2::new(u.dot(&right), u.dot(&down)) * f + pp * w_h;
        let mut edges = Vec::with_capacity(options.per_vanishing_point);
        let mut attempts = 0;
        while edges.len() < options.per_vanishing_point {
            attempts += 1;
            if attempts > LONG_EDGE_ATTEMPTS * options.per_vanishing_point {
                return Err(MetrologyError::Degenerate {
                    field: "long_edges.length_px".to_owned(),
                    reason: format!(
                        "no line through vanishing point {} has {length} px inside the image ({} x {} less {} %) in {} attempts; ask for shorter edges",
                        k + 1,
                        camera.image.width,
                        camera.image.height,
                        options.inset * 100.0,
                        LONG_EDGE_ATTEMPTS * options.per_vanishing_point
                    ),
                });
            }
            let c = Vector2::new(rng.random_range(x0..=x1), rng.random_range(y0..=y1));
            // Direction along the image line, pointing away from the vanishing point.
            let away = c * w_h - v_xy;
            let away = if w_h < 0.0 { -away } else { away };
            let e_norm = away.norm();
            if !(e_norm.is_finite() && e_norm > 1e-9 * f) {
                continue; // c is the vanishing point itself
            }
            let e = away / e_norm;
            // The stretch c + s e inside the inset image ...
            let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
            for (from, to, at, step) in [(x0, x1, c.x, e.x), (y0, y1, c.y, e.y)] {
                if step.abs() <= f64::EPSILON {
                    continue;
                }
                let (a, b) = ((from - at) / step, (to - at) / step);
                lo = lo.max(a.min(b));
                hi = hi.min(a.max(b));
            }
            // ... and on the vanishing point's far side (in front of the camera), a pixel
            // clear of it.
            if w_h != 0.0 {
                let v = v_xy / w_h;
                lo = lo.max((v - c).dot(&e) + 1.0);
            }
            // (`hi - length < lo` also when `hi - lo` rounds to `length`: an empty range.)
            let last_start = hi - length;
            if hi - lo < length || last_start < lo {
                continue;
            }
            let start = rng.random_range(lo..=last_start);
            // The 3D line through the point one camera height along c's ray.
            let eye = camera.centre();
            let through = eye + ray(c) * camera.height_m;
            let on_line = |pixel: Vector2<f64>| {
                let r = ray(pixel);
                let ur = u.cross(&r);
                let t = -(through - eye).cross(&r).dot(&ur) / ur.norm_squared();
                camera.project(through + u * t)
            };
            let (Some(a), Some(b)) = (on_line(c + e * start), on_line(c + e * (start + length)))
            else {
                continue;
            };
            edges.push([a.x, a.y, b.x, b.y]);
        }
        out.push(edges);
    }
    Ok(out)
}

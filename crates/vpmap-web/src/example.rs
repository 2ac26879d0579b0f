//! The bundled example: `examples/office.json` and a photo of the office it annotates.
//!
//! The photo is rendered here, from the example's known truth (`examples/office.truth.json`:
//! the camera, every object's footprint and height, the floor outline), so that the
//! annotations of `office.json` sit exactly on the corners they name:
//!
//! * the floor is a checkerboard of 0.5 m tiles running along the objects' sides (the room's
//!   axes), its contrast fading with distance as in
//!   [`vpmap_vision::synthetic`], over the floor outline and a metre
//!   around it;
//! * the walls stand on the floor outline's edges that run along the room's axes (the other
//!   edges are where the photo's frame cuts the floor), 2.7 m high, each wall without a
//!   neighbour at one end prolonged past the picture;
//! * the objects are prisms of their truth footprints and heights, far ones first (painter's
//!   algorithm), faces turned away from the camera left out (they are convex), each face
//!   shaded by how it faces the light.
//!
//! Projection is [`vpmap_metrology::synth::PinholeCamera`], the camera `office.json` was made
//! with; faces are cut at a plane just in front of the camera before they are projected, and
//! filled by scanlines: pixels wholly inside a face are set, pixels on its edges get the
//! colour in proportion to 4 x 4 sub-samples (anti-aliasing).

use std::io::Cursor;

use image::{ImageFormat, Rgb, RgbImage};
use nalgebra::{Vector2, Vector3};
use vpmap_metrology::scene::Scene;
use vpmap_metrology::synth::{PinholeCamera, Truth};

/// `examples/office.json`: the scene the page starts with.
pub const OFFICE_SCENE: &str = vpmap_pipeline::demo::EXAMPLE_SCENE;
/// `examples/office.truth.json`: what the office really is.
pub const OFFICE_TRUTH: &str = vpmap_pipeline::demo::EXAMPLE_TRUTH;

/// Height of the rendered walls, metres.
const WALL_HEIGHT_M: f64 = 2.7;
/// How far a wall with no neighbouring wall at one end is prolonged, metres.
const WALL_PROLONGATION_M: f64 = 40.0;
/// Faces are cut at this depth in front of the camera, metres.
const NEAR_PLANE_M: f64 = 0.05;
/// Floor tile side, metres.
const TILE_M: f64 = 0.5;
/// Distance over which the tiles' contrast falls by `e`, metres.
const FLOOR_FADE_M: f64 = 12.0;
/// The two tile colours, linear 0-1.
const TILE_ALBEDOS: [[f64; 3]; 2] = [[0.78, 0.70, 0.55], [0.42, 0.33, 0.25]];
/// A floor edge within this sine of a room axis is a wall's foot.
const AXIS_TOLERANCE: f64 = 1e-3;
/// Sub-samples per pixel side on face edges.
const SUB: u32 = 4;
/// Wall colour, linear 0-1.
const WALL_ALBEDO: [f64; 3] = [0.86, 0.84, 0.79];
/// Object colours, linear 0-1, by object index (cycled).
const OBJECT_ALBEDOS: [[f64; 3]; 5] = [
    [0.58, 0.40, 0.26],
    [0.74, 0.58, 0.33],
    [0.36, 0.47, 0.62],
    [0.62, 0.63, 0.66],
    [0.78, 0.28, 0.24],
];

/// The example photo as PNG bytes, its width and height.
///
/// # Errors
/// A message when the bundled files do not parse (a bug: they are compiled in) or the PNG
/// cannot be encoded.
pub fn office_photo_png() -> Result<(Vec<u8>, u32, u32), String> {
    let image = render_office_photo()?;
    let (w, h) = image.dimensions();
    let mut png = Vec::new();
    image
        .write_to(&mut Cursor::new(&mut png), ImageFormat::Png)
        .map_err(|e| format!("cannot encode the example photo as PNG: {e}"))?;
    Ok((png, w, h))
}

/// Render the office (see the module documentation).
///
/// # Errors
/// A message when the bundled files do not parse, or the truth has no box to take the room's
/// axes from.
pub fn render_office_photo() -> Result<RgbImage, String> {
    let scene = Scene::from_json_str(OFFICE_SCENE)
        .map_err(|e| format!("the bundled examples/office.json: {e}"))?;
    let truth: Truth = serde_json::from_str(OFFICE_TRUTH)
        .map_err(|e| format!("the bundled examples/office.truth.json: {e}"))?;
    let camera = truth.camera.pinhole(scene.image);
    let yaw_rad = truth
        .objects
        .iter()
        .find(|o| o.footprint.len() == 4)
        .and_then(|o| {
            let (a, b) = (o.footprint.first()?, o.footprint.get(1)?);
            Some((b[1] - a[1]).atan2(b[0] - a[0]))
        })
        .ok_or("the example's truth has no box to take the room's axes from")?;
    let mut image = RgbImage::from_pixel(
        scene.image.width,
        scene.image.height,
        Rgb(encode(mean_tile_albedo(), 1.0)),
    );
    let axis = Vector2::new(yaw_rad.cos(), yaw_rad.sin());
    paint_floor(&mut image, &camera, &truth.floor, axis);
    for wall in walls(&truth.floor, axis) {
        paint_face(&mut image, &camera, &wall.corners, wall.inward, WALL_ALBEDO);
    }
    let mut order: Vec<usize> = (0..truth.objects.len()).collect();
    let distance = |i: usize| {
        let fp = &truth.objects[i].footprint;
        let n = fp.len().max(1) as f64;
        let (x, y) = fp
            .iter()
            .fold((0.0, 0.0), |(x, y), p| (x + p[0] / n, y + p[1] / n));
        x.hypot(y)
    };
    order.sort_by(|&a, &b| distance(b).total_cmp(&distance(a)));
    for i in order {
        let o = &truth.objects[i];
        let albedo = OBJECT_ALBEDOS[i % OBJECT_ALBEDOS.len()];
        for (corners, outward) in prism_faces(&o.footprint, o.height) {
            let p = corners[0];
            if outward.dot(&(camera.centre() - p)) > 0.0 {
                paint_face(&mut image, &camera, &corners, outward, albedo);
            }
        }
    }
    Ok(image)
}

/// A wall: its four corners (foot, foot, top, top) and the normal facing into the room.
struct Wall {
    corners: Vec<Vector3<f64>>,
    inward: Vector3<f64>,
}

/// Twice the signed area of a polygon (positive counter-clockwise, x right, y forward).
fn signed_area2(points: &[[f64; 2]]) -> f64 {
    let n = points.len();
    (0..n)
        .map(|i| {
            let (p, q) = (points[i], points[(i + 1) % n]);
            p[0] * q[1] - q[0] * p[1]
        })
        .sum()
}

/// The walls standing on the floor outline's edges that run along a room axis.
fn walls(floor: &[[f64; 2]], axis: Vector2<f64>) -> Vec<Wall> {
    let n = floor.len();
    if n < 3 {
        return Vec::new();
    }
    let orientation = signed_area2(floor).signum();
    let edge = |i: usize| {
        let (p, q) = (floor[i % n], floor[(i + 1) % n]);
        (
            Vector2::new(p[0], p[1]),
            Vector2::new(q[0] - p[0], q[1] - p[1]),
        )
    };
    let along_axis = |i: usize| {
        let (_, d) = edge(i);
        let len = d.norm();
        len > 0.0 && {
            let sine = (d.x * axis.y - d.y * axis.x).abs() / len;
            let cosine = d.dot(&axis).abs() / len;
            sine < AXIS_TOLERANCE || cosine < AXIS_TOLERANCE
        }
    };
    let mut out = Vec::new();
    for i in 0..n {
        if !along_axis(i) {
            continue;
        }
        let (p, d) = edge(i);
        let unit = d / d.norm();
        let start = if along_axis(i + n - 1) {
            p
        } else {
            p - unit * WALL_PROLONGATION_M
        };
        let end = if along_axis(i + 1) {
            p + d
        } else {
            p + d + unit * WALL_PROLONGATION_M
        };
        let inward = Vector3::new(-unit.y, unit.x, 0.0) * orientation;
        let at = |v: Vector2<f64>, z: f64| Vector3::new(v.x, v.y, z);
        out.push(Wall {
            corners: vec![
                at(start, 0.0),
                at(end, 0.0),
                at(end, WALL_HEIGHT_M),
                at(start, WALL_HEIGHT_M),
            ],
            inward,
        });
    }
    out
}

/// The faces of a prism standing on `footprint` with height `height_m`: the top, then one
/// side per footprint edge, each with its outward normal.
fn prism_faces(footprint: &[[f64; 2]], height_m: f64) -> Vec<(Vec<Vector3<f64>>, Vector3<f64>)> {
    let n = footprint.len();
    let orientation = signed_area2(footprint).signum();
    let at = |p: [f64; 2], z: f64| Vector3::new(p[0], p[1], z);
    let mut faces = vec![(
        footprint.iter().map(|&p| at(p, height_m)).collect(),
        Vector3::new(0.0, 0.0, 1.0),
    )];
    for i in 0..n {
        let (p, q) = (footprint[i], footprint[(i + 1) % n]);
        let d = Vector2::new(q[0] - p[0], q[1] - p[1]);
        let len = d.norm();
        if len == 0.0 {
            continue;
        }
        let outward = Vector3::new(d.y / len, -d.x / len, 0.0) * orientation;
        faces.push((
            vec![at(p, 0.0), at(q, 0.0), at(q, height_m), at(p, height_m)],
            outward,
        ));
    }
    faces
}

/// Linear 0-1 colour times `k` as 8-bit sRGB-like values (gamma 2.2).
fn encode(albedo: [f64; 3], k: f64) -> [u8; 3] {
    albedo.map(|a| (255.0 * (a * k).clamp(0.0, 1.0).powf(1.0 / 2.2)).round() as u8)
}

/// Colour of a face with normal `n`: tops brightest, sides by how they face a horizontal
/// light, so that every visible face orientation gets its own shade.
fn shade(n: &Vector3<f64>, albedo: [f64; 3]) -> [u8; 3] {
    let light = Vector3::new(0.6, -0.8, 0.0);
    let k = if n.z > 0.5 {
        0.95
    } else {
        (0.58 + 0.3 * n.dot(&light)).clamp(0.3, 0.9)
    };
    encode(albedo, k)
}

fn mean_tile_albedo() -> [f64; 3] {
    let [l, d] = TILE_ALBEDOS;
    [
        0.5 * (l[0] + d[0]),
        0.5 * (l[1] + d[1]),
        0.5 * (l[2] + d[2]),
    ]
}

/// The checkerboard floor: tiles along the room's axes over the floor outline's extent and a
/// metre around it (walls cover what lies beyond them). The background is the tiles' mean
/// colour, so the thin seams between anti-aliased tiles do not show.
fn paint_floor(image: &mut RgbImage, camera: &PinholeCamera, floor: &[[f64; 2]], a: Vector2<f64>) {
    let b = Vector2::new(-a.y, a.x);
    let room = |p: &[f64; 2]| {
        let p = Vector2::new(p[0], p[1]);
        (p.dot(&a), p.dot(&b))
    };
    let (mut lo, mut hi) = (
        (f64::INFINITY, f64::INFINITY),
        (f64::NEG_INFINITY, f64::NEG_INFINITY),
    );
    for (u, v) in floor.iter().map(room) {
        lo = (lo.0.min(u), lo.1.min(v));
        hi = (hi.0.max(u), hi.1.max(v));
    }
    if !(lo.0.is_finite() && lo.1.is_finite() && hi.0.is_finite() && hi.1.is_finite()) {
        return;
    }
    let first = |v: f64| ((v - 1.0) / TILE_M).floor() as i64;
    let last = |v: f64| ((v + 1.0) / TILE_M).ceil() as i64;
    let mean = mean_tile_albedo();
    for i in first(lo.0)..last(hi.0) {
        for j in first(lo.1)..last(hi.1) {
            let (u, v) = (i as f64 * TILE_M, j as f64 * TILE_M);
            let at = |du: f64, dv: f64| {
                let p = a * (u + du) + b * (v + dv);
                Vector3::new(p.x, p.y, 0.0)
            };
            let corners = [
                at(0.0, 0.0),
                at(TILE_M, 0.0),
                at(TILE_M, TILE_M),
                at(0.0, TILE_M),
            ];
            let centre = at(0.5 * TILE_M, 0.5 * TILE_M);
            let keep = (-(centre - camera.centre()).norm() / FLOOR_FADE_M).exp();
            let albedo = TILE_ALBEDOS[usize::from((i + j).rem_euclid(2) == 1)];
            let faded: [f64; 3] = std::array::from_fn(|k| mean[k] + (albedo[k] - mean[k]) * keep);
            paint_polygon(image, camera, &corners, encode(faded, 1.0));
        }
    }
}

/// Cut a world polygon at the near plane, keeping the part in front of the camera
/// (Sutherland-Hodgman against one plane).
fn clip_near(camera: &PinholeCamera, polygon: &[Vector3<f64>]) -> Vec<Vector3<f64>> {
    let n = polygon.len();
    let mut out = Vec::with_capacity(n + 1);
    for i in 0..n {
        let (p, q) = (polygon[i], polygon[(i + 1) % n]);
        let (dp, dq) = (
            camera.depth(p) - NEAR_PLANE_M,
            camera.depth(q) - NEAR_PLANE_M,
        );
        if dp >= 0.0 {
            out.push(p);
        }
        if (dp >= 0.0) != (dq >= 0.0) {
            out.push(p + (q - p) * (dp / (dp - dq)));
        }
    }
    out
}

/// Paint one planar convex face, anti-aliased, shaded by its normal.
fn paint_face(
    image: &mut RgbImage,
    camera: &PinholeCamera,
    corners: &[Vector3<f64>],
    normal: Vector3<f64>,
    albedo: [f64; 3],
) {
    paint_polygon(image, camera, corners, shade(&normal, albedo));
}

/// Paint one planar convex world polygon in one colour, anti-aliased.
fn paint_polygon(
    image: &mut RgbImage,
    camera: &PinholeCamera,
    corners: &[Vector3<f64>],
    colour: [u8; 3],
) {
    let projected: Vec<[f64; 2]> = clip_near(camera, corners)
        .into_iter()
        .filter_map(|p| camera.project(p).map(|v| [v.x, v.y]))
        .collect();
    fill_convex(image, &projected, colour);
}

/// The x-interval where a convex polygon meets the horizontal line at `y`.
fn span_at(polygon: &[[f64; 2]], y: f64) -> Option<(f64, f64)> {
    let n = polygon.len();
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for i in 0..n {
        let (p, q) = (polygon[i], polygon[(i + 1) % n]);
        if (p[1] <= y && y <= q[1]) || (q[1] <= y && y <= p[1]) {
            let dy = q[1] - p[1];
            let xs = if dy.abs() < 1e-12 {
                [p[0], q[0]]
            } else {
                let x = p[0] + (y - p[1]) / dy * (q[0] - p[0]);
                [x, x]
            };
            lo = lo.min(xs[0]).min(xs[1]);
            hi = hi.max(xs[0]).max(xs[1]);
        }
    }
    (lo <= hi).then_some((lo, hi))
}

/// Fill a convex image polygon with `colour`, by scanlines: in each pixel row, the pixels
/// whose square lies inside the polygon (inside on both of the row's edges, which for a
/// convex polygon means inside everywhere) are set; the others the polygon reaches get the
/// colour in proportion to the 4 x 4 sub-samples it covers.
fn fill_convex(image: &mut RgbImage, polygon: &[[f64; 2]], colour: [u8; 3]) {
    let n = polygon.len();
    if n < 3 || polygon.iter().flatten().any(|c| !c.is_finite()) {
        return;
    }
    let orientation = signed_area2(polygon).signum();
    if orientation == 0.0 {
        return;
    }
    // Each edge as (point, unit direction): inside is where every cross product has the sign
    // of the polygon's orientation.
    let edges: Vec<([f64; 2], [f64; 2])> = (0..n)
        .filter_map(|i| {
            let (p, q) = (polygon[i], polygon[(i + 1) % n]);
            let (dx, dy) = (q[0] - p[0], q[1] - p[1]);
            let len = dx.hypot(dy);
            (len > 1e-12).then(|| (p, [dx / len, dy / len]))
        })
        .collect();
    let inside = |x: f64, y: f64| {
        edges
            .iter()
            .all(|(p, d)| orientation * (d[0] * (y - p[1]) - d[1] * (x - p[0])) >= 0.0)
    };
    let (w, h) = image.dimensions();
    let (w_f, h_f) = (f64::from(w), f64::from(h));
    let y_lo = polygon.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min);
    let y_hi = polygon
        .iter()
        .map(|p| p[1])
        .fold(f64::NEG_INFINITY, f64::max);
    let (y0, y1) = (
        y_lo.floor().clamp(0.0, h_f) as u32,
        y_hi.ceil().clamp(0.0, h_f) as u32,
    );
    for y in y0..y1 {
        let (top, bottom) = (f64::from(y), f64::from(y) + 1.0);
        // The polygon's x-extent within the row: its spans on the row's edges and the
        // vertices between them.
        let mut reach: Option<(f64, f64)> = None;
        let mut widen = |lo: f64, hi: f64| {
            reach = Some(reach.map_or((lo, hi), |(a, b)| (a.min(lo), b.max(hi))));
        };
        let (span_top, span_bottom) = (span_at(polygon, top), span_at(polygon, bottom));
        for (lo, hi) in [span_top, span_bottom].into_iter().flatten() {
            widen(lo, hi);
        }
        for p in polygon.iter().filter(|p| top <= p[1] && p[1] <= bottom) {
            widen(p[0], p[0]);
        }
        let Some((lo, hi)) = reach else {
            continue;
        };
        let (x0, x1) = (
            lo.floor().clamp(0.0, w_f) as u32,
            hi.ceil().clamp(0.0, w_f) as u32,
        );
        // Whole pixels inside: within both edge spans.
        let full = match (span_top, span_bottom) {
            (Some(a), Some(b)) => (a.0.max(b.0).ceil(), a.1.min(b.1).floor()),
            _ => (f64::INFINITY, f64::NEG_INFINITY),
        };
        for x in x0..x1 {
            let xf = f64::from(x);
            if xf >= full.0 && xf + 1.0 <= full.1 {
                image.put_pixel(x, y, Rgb(colour));
                continue;
            }
            let mut hits = 0u32;
            for sy in 0..SUB {
                for sx in 0..SUB {
                    let px = xf + (f64::from(sx) + 0.5) / f64::from(SUB);
                    let py = top + (f64::from(sy) + 0.5) / f64::from(SUB);
                    if inside(px, py) {
                        hits += 1;
                    }
                }
            }
            if hits > 0 {
                let coverage = f64::from(hits) / f64::from(SUB * SUB);
                let Rgb(old) = *image.get_pixel(x, y);
                let mixed: [u8; 3] = std::array::from_fn(|k| {
                    (f64::from(old[k]) * (1.0 - coverage) + f64::from(colour[k]) * coverage)
                        .round()
                        .clamp(0.0, 255.0) as u8
                });
                image.put_pixel(x, y, Rgb(mixed));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn annotations_of_office_json_sit_on_the_rendered_corners() {
        // The camera rebuilt from the truth projects each truth corner onto the pixel
        // office.json annotates, so the painted boxes are where the annotations are.
        let scene = Scene::from_json_str(OFFICE_SCENE).unwrap_or_else(|e| panic!("{e}"));
        let truth: Truth = serde_json::from_str(OFFICE_TRUTH).unwrap_or_else(|e| panic!("{e}"));
        let camera = truth.camera.pinhole(scene.image);
        let base = scene.objects[0].base.as_ref().and_then(|b| b.near);
        let fp = truth.objects[0].footprint[0];
        let p = camera
            .project(Vector3::new(fp[0], fp[1], 0.0))
            .unwrap_or_default();
        let a = base.unwrap_or_default();
        assert!((p.x - a[0]).hypot(p.y - a[1]) < 1e-6, "{p:?} vs {a:?}");
    }

    #[test]
    fn walls_stand_on_the_three_room_edges_of_the_office_floor() {
        let truth: Truth = serde_json::from_str(OFFICE_TRUTH).unwrap_or_else(|e| panic!("{e}"));
        let fp = &truth.objects[0].footprint;
        let axis = Vector2::new(fp[1][0] - fp[0][0], fp[1][1] - fp[0][1]).normalize();
        let walls = walls(&truth.floor, axis);
        assert_eq!(walls.len(), 3);
        // Every inward normal points towards the camera's side of the wall.
        for w in &walls {
            let foot = w.corners[0];
            assert!(w.inward.dot(&(Vector3::new(0.0, 0.0, 0.0) - foot)) > 0.0);
        }
    }

    #[test]
    fn convex_fill_covers_a_square_exactly() {
        let mut image = RgbImage::new(10, 10);
        fill_convex(
            &mut image,
            &[[2.0, 2.0], [6.0, 2.0], [6.0, 6.0], [2.0, 6.0]],
            [255; 3],
        );
        let lit = image.pixels().filter(|p| p.0[0] == 255).count();
        let partial = image
            .pixels()
            .filter(|p| p.0[0] != 0 && p.0[0] != 255)
            .count();
        assert_eq!((lit, partial), (16, 0));
        // Half-covered pixels get half the colour.
        let mut image = RgbImage::new(4, 4);
        fill_convex(
            &mut image,
            &[[0.0, 0.0], [2.5, 0.0], [2.5, 4.0], [0.0, 4.0]],
            [200; 3],
        );
        assert_eq!(image.get_pixel(2, 1).0[0], 100);
    }
}

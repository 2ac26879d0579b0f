//! The map's regions on the floor, as `geo` polygons and as `map.json` writes them: the free
//! space (the floor minus the footprints), the occlusion shadows behind objects, and the floor
//! the photo shows.

use geo::{BooleanOps, ConvexHull, Coord, LineString, MultiPoint, MultiPolygon, Point, Polygon};
use nalgebra::Vector2;

use super::types::PolygonWithHoles;
use crate::calibration::Calibration;
use crate::camera::MapPoint;
use crate::scene::ImageSize;

pub(super) fn ring(points: &[Vector2<f64>]) -> LineString<f64> {
    LineString::from(
        points
            .iter()
            .map(|p| Coord { x: p.x, y: p.y })
            .collect::<Vec<_>>(),
    )
}

fn unclosed(ls: &LineString<f64>) -> Vec<MapPoint> {
    let mut pts: Vec<MapPoint> = ls.coords().map(|c| [c.x, c.y]).collect();
    if pts.len() > 1 && pts.first() == pts.last() {
        pts.pop();
    }
    pts
}

/// The floor outline minus the object footprints, as polygons with holes.
#[must_use]
pub fn free_space(floor: &[Vector2<f64>], footprints: &[Vec<Vector2<f64>>]) -> MultiPolygon<f64> {
    if floor.len() < 3 {
        return MultiPolygon::new(Vec::new());
    }
    let floor_poly = MultiPolygon::new(vec![Polygon::new(ring(floor), vec![])]);
    let obstacles: Vec<Polygon<f64>> = footprints
        .iter()
        .filter(|f| f.len() >= 3)
        .map(|f| Polygon::new(ring(f), vec![]))
        .collect();
    if obstacles.is_empty() {
        return floor_poly;
    }
    let union = geo::unary_union(&obstacles);
    floor_poly.difference(&union)
}

/// The floor hidden behind one object, seen from a camera at `camera_height` above the
/// station point (the origin): the convex hull of the footprint and of the top outline
/// projected from the camera onto the floor (`v -> v H / (H - h)`). An object as tall as the
/// camera or taller hides everything behind it; its shadow is cut at `reach` from the station
/// point. Objects without a height hide nothing (their height is unknown).
#[must_use]
pub fn occlusion_shadow(
    footprint: &[Vector2<f64>],
    height: Option<f64>,
    camera_height: f64,
    reach: f64,
) -> Option<Polygon<f64>> {
    let h = height?;
    if footprint.len() < 3 || h <= 0.0 {
        return None;
    }
    let mut points: Vec<Point<f64>> = footprint.iter().map(|p| Point::new(p.x, p.y)).collect();
    for p in footprint {
        let r = p.norm();
        if r == 0.0 {
            continue;
        }
        let stretch = if h < camera_height {
            (camera_height / (camera_height - h)).min(reach / r)
        } else {
            reach / r
        };
        let q = p * stretch.max(1.0);
        points.push(Point::new(q.x, q.y));
    }
    Some(MultiPoint::new(points).convex_hull())
}

/// The image rectangle's floor footprint, cut at forward distance `reach` (in units where the
/// camera height is `camera_height`), by the closed form of the errata: a point at
/// horizon-frame offset `(x, y)` from `O` lies on the floor at
/// `X = H x / (d sin(theta) - y cos(theta))`, `Y = H (d cos(theta) + y sin(theta)) / (d sin(theta) - y cos(theta))`.
pub(super) fn view_on_floor(
    cal: &Calibration,
    image: ImageSize,
    camera_height: f64,
    reach: f64,
) -> Vec<MapPoint> {
    let (d, th) = (cal.focal_px, cal.pitch_rad);
    let (s, c) = th.sin_cos();
    // The image row (horizon frame) whose floor points lie `reach` ahead on the centre line.
    let y_far = d * (reach * s - camera_height * c) / (reach * c + camera_height * s);
    let (w, h) = (f64::from(image.width), f64::from(image.height));
    let corners = [
        Vector2::new(0.0, 0.0),
        Vector2::new(w, 0.0),
        Vector2::new(w, h),
        Vector2::new(0.0, h),
    ]
    .map(|p| cal.frame.coords(p));
    // Clip the rectangle (horizon frame) to y <= y_far.
    let mut clipped: Vec<Vector2<f64>> = Vec::new();
    for i in 0..4 {
        let (p, q) = (corners[i], corners[(i + 1) % 4]);
        if p.y <= y_far {
            clipped.push(p);
        }
        if (p.y <= y_far) != (q.y <= y_far) {
            clipped.push(p + (q - p) * ((y_far - p.y) / (q.y - p.y)));
        }
    }
    let mut out: Vec<MapPoint> = clipped
        .iter()
        .filter_map(|v| {
            let den = d * s - v.y * c;
            (den > 0.0).then(|| {
                [
                    camera_height * v.x / den,
                    camera_height * (d * c + v.y * s) / den,
                ]
            })
        })
        .collect();
    // Counter-clockwise in the map frame.
    let twice_area: f64 = (0..out.len())
        .map(|i| {
            let (a, b) = (out[i], out[(i + 1) % out.len()]);
            a[0] * b[1] - a[1] * b[0]
        })
        .sum();
    if twice_area < 0.0 {
        out.reverse();
    }
    out
}

/// Polygons with holes as `map.json` writes them (rings not closed).
#[must_use]
pub fn to_polygons(mp: &MultiPolygon<f64>) -> Vec<PolygonWithHoles> {
    mp.0.iter()
        .map(|p| PolygonWithHoles {
            exterior: unclosed(p.exterior()),
            holes: p.interiors().iter().map(unclosed).collect(),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use geo::Contains;
    use rand::{RngExt, SeedableRng};

    /// Does the segment from the camera to a floor point pass through the axis-aligned box?
    /// (Slab test: independent of the convex-hull construction.)
    fn ray_hits_box(camera_h: f64, p: Vector2<f64>, lo: [f64; 3], hi: [f64; 3]) -> bool {
        let origin = [0.0, 0.0, camera_h];
        let dir = [p.x, p.y, -camera_h];
        let (mut t0, mut t1) = (0.0f64, 1.0f64);
        for k in 0..3 {
            if dir[k].abs() < 1e-15 {
                if origin[k] < lo[k] || origin[k] > hi[k] {
                    return false;
                }
                continue;
            }
            let (a, b) = ((lo[k] - origin[k]) / dir[k], (hi[k] - origin[k]) / dir[k]);
            t0 = t0.max(a.min(b));
            t1 = t1.min(a.max(b));
        }
        t0 <= t1
    }

    #[test]
    fn occlusion_shadow_matches_ray_casting() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        for &(h, camera_h) in &[(0.8, 1.5), (2.0, 1.5), (0.3, 1.0)] {
            let (lo, hi) = ([0.5, 2.0, 0.0], [1.3, 2.6, h]);
            let fp = [
                Vector2::new(lo[0], lo[1]),
                Vector2::new(hi[0], lo[1]),
                Vector2::new(hi[0], hi[1]),
                Vector2::new(lo[0], hi[1]),
            ];
            let shadow = occlusion_shadow(&fp, Some(h), camera_h, 100.0).unwrap();
            let footprint = Polygon::new(ring(&fp), vec![]);
            let mut hidden_seen = 0;
            for _ in 0..4000 {
                let p = Vector2::new(rng.random_range(-3.0..5.0), rng.random_range(0.1..12.0));
                let pt = Point::new(p.x, p.y);
                if footprint.contains(&pt) {
                    continue;
                }
                let expected = ray_hits_box(camera_h, p, lo, hi);
                hidden_seen += usize::from(expected);
                assert_eq!(
                    shadow.contains(&pt),
                    expected,
                    "h {h}, camera {camera_h}: point {p:?}"
                );
            }
            assert!(hidden_seen > 20, "the test must see hidden points");
        }
    }
}

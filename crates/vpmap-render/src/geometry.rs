//! Plane geometry shared by the SVG and glTF writers: finite bounds, ring cleaning, shoelace
//! areas and ear-cut triangulation. Points are `[x, y]` in the map frame.

use vpmap_metrology::map::{FloorMap, MapPoint};

/// Axis-aligned box of the finite points of a map, never empty.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Bounds {
    /// Smallest `[x, y]`.
    pub min: MapPoint,
    /// Largest `[x, y]`.
    pub max: MapPoint,
}

impl Bounds {
    /// The station point alone.
    fn origin() -> Self {
        Self {
            min: [0.0, 0.0],
            max: [0.0, 0.0],
        }
    }

    /// Grow to contain `p` (ignored unless finite).
    pub fn include(&mut self, p: MapPoint) {
        if is_finite(p) {
            self.min = [self.min[0].min(p[0]), self.min[1].min(p[1])];
            self.max = [self.max[0].max(p[0]), self.max[1].max(p[1])];
        }
    }

    /// Bounds of the floor, the objects, the free space and the station point of a map (and
    /// a room's other cameras), skipping non-finite points. Like [`FloorMap::bounds`], but
    /// safe on broken maps.
    pub fn of_map(map: &FloorMap) -> Self {
        let mut b = Self::origin();
        for c in &map.cameras {
            b.include([c.position[0], c.position[1]]);
        }
        let free = map
            .free_space
            .iter()
            .flat_map(|p| p.exterior.iter().chain(p.holes.iter().flatten()));
        for p in map
            .floor
            .iter()
            .chain(map.objects.iter().flat_map(|o| o.footprint.iter()))
            .chain(free)
        {
            b.include(*p);
        }
        b
    }

    /// Width and depth `[dx, dy]`.
    pub fn span(&self) -> [f64; 2] {
        [self.max[0] - self.min[0], self.max[1] - self.min[1]]
    }

    /// The larger of the two spans, or `fallback` when the box is a point (or not finite).
    pub fn size_or(&self, fallback: f64) -> f64 {
        let [dx, dy] = self.span();
        let s = dx.max(dy);
        if s.is_finite() && s > 0.0 {
            s
        } else {
            fallback
        }
    }

    /// The box grown by `margin` on every side.
    pub fn padded(&self, margin: f64) -> Self {
        Self {
            min: [self.min[0] - margin, self.min[1] - margin],
            max: [self.max[0] + margin, self.max[1] + margin],
        }
    }
}

/// Both coordinates finite.
pub(crate) fn is_finite(p: MapPoint) -> bool {
    p[0].is_finite() && p[1].is_finite()
}

/// Signed area by the shoelace formula: positive for counter-clockwise rings (x right, y up).
pub(crate) fn signed_area(ring: &[MapPoint]) -> f64 {
    let next = ring.iter().cycle().skip(1);
    let twice: f64 = ring
        .iter()
        .zip(next)
        .map(|(a, b)| a[0] * b[1] - b[0] * a[1])
        .sum();
    twice / 2.0
}

/// A ring without consecutive repeats and without a closing copy of its first point.
pub(crate) fn clean_ring(ring: &[MapPoint]) -> Vec<MapPoint> {
    let mut out: Vec<MapPoint> = Vec::with_capacity(ring.len());
    for p in ring {
        if out.last() != Some(p) {
            out.push(*p);
        }
    }
    while out.len() > 1 && out.first() == out.last() {
        out.pop();
    }
    out
}

/// Ear-cut triangulation of a simple polygon (any orientation, may be non-convex).
/// Every returned triangle indexes `ring` and is counter-clockwise.
///
/// # Errors
/// The reason, when earcut fails or covers none of the polygon.
pub(crate) fn triangulate(ring: &[MapPoint]) -> Result<Vec<[usize; 3]>, String> {
    let flat: Vec<f64> = ring.iter().flat_map(|p| [p[0], p[1]]).collect();
    let indices = earcutr::earcut(&flat, &[], 2).map_err(|e| e.to_string())?;
    let mut tris = Vec::with_capacity(indices.len() / 3);
    for t in indices.chunks_exact(3) {
        let &[a, b, c] = t else { continue };
        let (Some(pa), Some(pb), Some(pc)) = (ring.get(a), ring.get(b), ring.get(c)) else {
            return Err(format!(
                "earcut returned an index outside 0..{}",
                ring.len()
            ));
        };
        let area = signed_area(&[*pa, *pb, *pc]);
        if area > 0.0 {
            tris.push([a, b, c]);
        } else if area < 0.0 {
            tris.push([a, c, b]);
        }
    }
    if tris.is_empty() {
        return Err("no triangle of positive area".to_owned());
    }
    Ok(tris)
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn shoelace_of_unit_square_is_one_and_signed() {
        let ccw = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        assert_relative_eq!(signed_area(&ccw), 1.0);
        let cw: Vec<_> = ccw.iter().rev().copied().collect();
        assert_relative_eq!(signed_area(&cw), -1.0);
    }

    #[test]
    fn clean_ring_drops_repeats_and_closing_point() {
        let ring = [[0.0, 0.0], [0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 0.0]];
        assert_eq!(clean_ring(&ring), vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]]);
    }

    #[test]
    fn triangulation_of_clockwise_l_shape_covers_its_area_ccw() {
        // An L-shaped (non-convex) ring, clockwise.
        let ring = [
            [0.0, 0.0],
            [0.0, 2.0],
            [1.0, 2.0],
            [1.0, 1.0],
            [2.0, 1.0],
            [2.0, 0.0],
        ];
        let tris = triangulate(&ring).unwrap();
        let mut total = 0.0;
        for t in &tris {
            let a = signed_area(&[ring[t[0]], ring[t[1]], ring[t[2]]]);
            assert!(a > 0.0);
            total += a;
        }
        assert_relative_eq!(total, 3.0, max_relative = 1e-12);
    }

    #[test]
    fn triangulation_of_collinear_points_fails() {
        assert!(triangulate(&[[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]).is_err());
    }

    #[test]
    fn bounds_skip_non_finite_points() {
        let mut b = Bounds::origin();
        b.include([f64::NAN, 3.0]);
        b.include([f64::INFINITY, 1.0]);
        b.include([2.0, -1.0]);
        assert_eq!(b.min.map(f64::to_bits), [0.0, -1.0f64].map(f64::to_bits));
        assert_eq!(b.max.map(f64::to_bits), [2.0, 0.0f64].map(f64::to_bits));
        assert_relative_eq!(b.size_or(9.0), 2.0);
        assert_relative_eq!(Bounds::origin().size_or(9.0), 9.0);
    }
}

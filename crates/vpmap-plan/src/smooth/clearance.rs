//! The planner's collision test of segments ([`Field`]): a chessboard distance field over
//! the cell centres lets it skip along a segment in steps as long as the clearance
//! certifies, and near blocked cells it falls back to the exact piece test of
//! [`super::check`]. Exact under the same rule as the validator, much faster in open space.
//!
//! `D(c)` is the Chebyshev distance, in cells, from the centre of cell `c` to the nearest
//! blocked cell's centre (cells outside the grid count as blocked). A point `p` whose
//! nearest cell centre is `c` is then at Chebyshev distance at least
//! `D(c) - |p - c|_inf >= D(c) - 1/2` from every blocked centre, and it is clear (outside
//! every open square of side 2) when that is at least 1. Moving a length `l` along a curve
//! moves the point by at most `l`, so a point with margin `m = D(c) - 3/2 >= 0` certifies
//! the next `m` cells of the curve.

use super::check::{PIECE_CELLS, piece_enters_square};
use super::curve::{Pose, Segment, SmoothCurve};
use crate::grid::{Occupancy, OccupancyGrid};

/// Below this certified margin (cells) the test switches to exact pieces.
const EXACT_BELOW: f64 = 0.25;

/// Blocked cells and their chessboard distance field, built once per grid.
#[derive(Clone, Debug)]
pub struct Field {
    width: usize,
    height: usize,
    blocked: Vec<bool>,
    distance: Vec<u32>,
}

impl Field {
    /// Build the field of `grid` (unknown cells blocked unless `unknown_passable`).
    ///
    /// # Complexity
    /// Two passes over the grid.
    #[must_use]
    pub fn new(grid: &OccupancyGrid, unknown_passable: bool) -> Self {
        let (w, h) = (grid.width(), grid.height());
        let blocked: Vec<bool> = grid
            .cells()
            .iter()
            .map(|&c| match c {
                Occupancy::Free => false,
                Occupancy::Unknown => !unknown_passable,
                Occupancy::Occupied => true,
            })
            .collect();
        let mut distance = vec![u32::MAX; w * h];
        for y in 0..h {
            for x in 0..w {
                let border = (x + 1).min(w - x).min(y + 1).min(h - y) as u32;
                let i = y * w + x;
                if let (Some(d), Some(&b)) = (distance.get_mut(i), blocked.get(i)) {
                    *d = if b { 0 } else { border };
                }
            }
        }
        // Chamfer passes with unit weights: exact for the chessboard metric.
        let relax = |distance: &mut Vec<u32>, x: usize, y: usize, nbrs: &[(isize, isize)]| {
            let i = y * w + x;
            let mut best = distance.get(i).copied().unwrap_or(0);
            for &(dx, dy) in nbrs {
                let (nx, ny) = (x as isize + dx, y as isize + dy);
                if nx >= 0 && ny >= 0 && (nx as usize) < w && (ny as usize) < h {
                    let j = ny as usize * w + nx as usize;
                    if let Some(&d) = distance.get(j) {
                        best = best.min(d.saturating_add(1));
                    }
                }
            }
            if let Some(d) = distance.get_mut(i) {
                *d = best;
            }
        };
        for y in 0..h {
            for x in 0..w {
                relax(&mut distance, x, y, &[(-1, 0), (-1, -1), (0, -1), (1, -1)]);
            }
        }
        for y in (0..h).rev() {
            for x in (0..w).rev() {
                relax(&mut distance, x, y, &[(1, 0), (1, 1), (0, 1), (-1, 1)]);
            }
        }
        Self {
            width: w,
            height: h,
            blocked,
            distance,
        }
    }

    /// Whether cell `(x, y)` is blocked (outside the grid: yes).
    #[must_use]
    pub fn blocked(&self, x: i64, y: i64) -> bool {
        if x < 0 || y < 0 || x >= self.width as i64 || y >= self.height as i64 {
            return true;
        }
        self.blocked
            .get(y as usize * self.width + x as usize)
            .copied()
            .unwrap_or(true)
    }

    /// `D` of the cell nearest to `(x, y)` (0 outside the grid).
    fn distance_near(&self, x: f64, y: f64) -> f64 {
        let (cx, cy) = (x.round(), y.round());
        if !(cx >= 0.0 && cy >= 0.0 && cx < self.width as f64 && cy < self.height as f64) {
            return 0.0;
        }
        self.distance
            .get(cy as usize * self.width + cx as usize)
            .map_or(0.0, |&d| f64::from(d))
    }

    /// Grid size `(width, height)`, cells.
    #[must_use]
    pub fn size(&self) -> (usize, usize) {
        (self.width, self.height)
    }

    /// A lower bound on the clearance at `(x, y)`: how far (Chebyshev, cells) the robot's
    /// square is from every blocked cell; negative values say nothing.
    #[must_use]
    pub fn margin(&self, x: f64, y: f64) -> f64 {
        self.distance_near(x, y) - 1.5
    }

    /// Whether the piece `lo..=hi` of `seg` is clear, exactly.
    fn piece_clear(&self, seg: &Segment, lo: f64, hi: f64) -> bool {
        let (a, b) = (seg.pose_at(lo), seg.pose_at(hi));
        let reach = 1.0 + 0.5 * (hi - lo);
        let x0 = (a.x.min(b.x) - reach).floor() as i64;
        let x1 = (a.x.max(b.x) + reach).ceil() as i64;
        let y0 = (a.y.min(b.y) - reach).floor() as i64;
        let y1 = (a.y.max(b.y) + reach).ceil() as i64;
        for y in y0..=y1 {
            for x in x0..=x1 {
                if self.blocked(x, y) && piece_enters_square(seg, lo, hi, (x, y)).is_some() {
                    return false;
                }
            }
        }
        true
    }

    /// How far along `seg` (cells) the robot drives before its square first enters a
    /// blocked cell's square, to within [`PIECE_CELLS`] (the start of the first piece that
    /// is not clear); `seg.length` when all of it is clear.
    #[must_use]
    pub fn clear_length(&self, seg: &Segment) -> f64 {
        let mut s = 0.0;
        while s < seg.length {
            let p = seg.pose_at(s);
            let m = self.margin(p.x, p.y);
            if m >= EXACT_BELOW {
                s += m;
                continue;
            }
            let hi = (s + PIECE_CELLS).min(seg.length);
            if !self.piece_clear(seg, s, hi) {
                return s;
            }
            s = hi;
        }
        seg.length
    }

    /// Whether all of `seg` is clear.
    #[must_use]
    pub fn segment_clear(&self, seg: &Segment) -> bool {
        if seg.length == 0.0 {
            return self.piece_clear(seg, 0.0, 0.0);
        }
        self.clear_length(seg) >= seg.length
    }

    /// Whether every segment of `curve` is clear.
    #[must_use]
    pub fn curve_clear(&self, curve: &SmoothCurve) -> bool {
        curve.segments.iter().all(|s| self.segment_clear(s))
    }

    /// The clearance at `p`, exactly: the Chebyshev distance from `p` to the nearest
    /// blocked cell's centre, minus 1 (0: the robot's square touches a blocked cell).
    #[must_use]
    pub fn clearance_at(&self, p: Pose) -> f64 {
        let (cx, cy) = (p.x.round() as i64, p.y.round() as i64);
        let d = self.distance_near(p.x, p.y) as i64;
        // The nearest blocked centre is at chessboard distance d or d + 1 from c.
        let mut best = f64::INFINITY;
        for ring in d.max(0)..=d + 1 {
            for (x, y) in ring_cells(cx, cy, ring) {
                if self.blocked(x, y) {
                    let dist = (p.x - x as f64).abs().max((p.y - y as f64).abs());
                    best = best.min(dist);
                }
            }
        }
        best - 1.0
    }

    /// The smallest clearance over `poses` (see [`Self::clearance_at`]), skipping poses
    /// whose bound cannot beat the current minimum.
    #[must_use]
    pub fn min_clearance(&self, poses: &[Pose]) -> f64 {
        let mut best = f64::INFINITY;
        for p in poses {
            if self.distance_near(p.x, p.y) - 1.5 < best {
                best = best.min(self.clearance_at(*p));
            }
        }
        best
    }
}

impl Field {
    /// The smallest clearance over every point of `curve` (not only sampled poses), cells:
    /// the least Chebyshev distance from a point of the curve to a blocked cell's centre,
    /// minus 1 (see [`Self::clearance_at`]); for an empty curve, the clearance at `start`.
    ///
    /// The curve is cut into pieces of at most a quarter cell. The clearance moves by at most
    /// the length moved along the curve, so a piece whose start's clearance minus its length
    /// cannot beat the smallest value found is skipped; every other piece is solved exactly
    /// against each blocked cell within reach ([`piece_chebyshev`]).
    ///
    /// # Complexity
    /// `O(length)` clearance look-ups, plus `O(r^2)` cells for each piece near the minimum,
    /// `r` the clearance there.
    #[must_use]
    pub fn curve_min_clearance(&self, curve: &SmoothCurve, start: Pose) -> f64 {
        const PIECE: f64 = 0.25;
        let mut pieces = Vec::new();
        for seg in &curve.segments {
            let n = (seg.length / PIECE).ceil().max(1.0) as usize;
            for k in 0..n {
                let (lo, hi) = (
                    seg.length * k as f64 / n as f64,
                    seg.length * (k + 1) as f64 / n as f64,
                );
                pieces.push((seg, lo, hi));
            }
        }
        if pieces.is_empty() {
            return self.clearance_at(start);
        }
        // The pieces' ends first (cheaply, skipping by the distance field), then the pieces
        // that could still come closer.
        let ends: Vec<Pose> = pieces
            .iter()
            .flat_map(|&(seg, lo, hi)| [seg.pose_at(lo), seg.pose_at(hi)])
            .collect();
        let mut best = self.min_clearance(&ends);
        for &(seg, lo, hi) in &pieces {
            let len = hi - lo;
            let p = seg.pose_at(lo);
            if self.margin(p.x, p.y) - len >= best {
                continue;
            }
            let ca = self.clearance_at(p);
            if ca - len >= best {
                continue;
            }
            // Every point of the piece is within `len` of `p`, and its nearest blocked centre
            // within `ca + 1 + len` of it.
            let reach = (ca + 1.0 + 2.0 * len).ceil() as i64 + 1;
            let (cx, cy) = (p.x.round() as i64, p.y.round() as i64);
            for y in cy - reach..=cy + reach {
                for x in cx - reach..=cx + reach {
                    if self.blocked(x, y) {
                        let d = piece_chebyshev(seg, lo, hi, (x as f64, y as f64));
                        best = best.min(d - 1.0);
                    }
                }
            }
        }
        best
    }
}

/// The least Chebyshev distance from the piece `lo..=hi` of `seg` to the point `q`, exactly:
/// along the piece the distance is `max(|X|, |Y|)` of the offsets `X`, `Y` from `q`, linear
/// in the length on a line and sinusoids of the heading on an arc, so its minimum is at an
/// end of the piece, where `X` or `Y` is 0, where `|X| = |Y|`, or (arcs) at an extreme of
/// `X` or `Y`: every such place is solved in closed form and evaluated.
#[must_use]
pub fn piece_chebyshev(seg: &Segment, lo: f64, hi: f64, q: (f64, f64)) -> f64 {
    let cheb = |p: Pose| (p.x - q.0).abs().max((p.y - q.1).abs());
    let mut best = cheb(seg.pose_at(lo)).min(cheb(seg.pose_at(hi)));
    let (p0, g, k) = (seg.start, seg.gear.sign(), seg.curvature);
    if k == 0.0 {
        // X = a + b s, Y = c + d s.
        let (sin, cos) = p0.heading_rad.sin_cos();
        let (a, b, c, d) = (p0.x - q.0, g * cos, p0.y - q.1, g * sin);
        for (num, den) in [(a, b), (c, d), (a - c, b - d), (a + c, b + d)] {
            if den.abs() > 1e-300 {
                let s = -num / den;
                if s > lo && s < hi {
                    best = best.min(cheb(seg.pose_at(s)));
                }
            }
        }
        return best;
    }
    // X(t) = a + sin(t) / k, Y(t) = b - cos(t) / k for the heading t along the arc.
    let (sin0, cos0) = p0.heading_rad.sin_cos();
    let (a, b) = (p0.x - q.0 - sin0 / k, p0.y - q.1 + cos0 / k);
    let (t_lo, t_hi) = (p0.heading_rad + g * k * lo, p0.heading_rad + g * k * hi);
    let (t_min, t_max) = (t_lo.min(t_hi), t_lo.max(t_hi));
    let mut angles = vec![
        0.0,
        std::f64::consts::FRAC_PI_2,
        std::f64::consts::PI,
        -std::f64::consts::FRAC_PI_2,
    ];
    let mut both = |v: f64, shift: f64| {
        if v.abs() <= 1.0 {
            let r = v.asin();
            angles.push(r + shift);
            angles.push(std::f64::consts::PI - r + shift);
        }
    };
    // X = 0: sin t = -a k.  Y = 0: cos t = b k, i.e. sin(t + pi/2) = b k.
    both(-a * k, 0.0);
    both(b * k, -std::f64::consts::FRAC_PI_2);
    // X = Y: sin t + cos t = k (b - a), i.e. sqrt 2 sin(t + pi/4) = k (b - a).
    both(k * (b - a) / 2f64.sqrt(), -std::f64::consts::FRAC_PI_4);
    // X = -Y: sin t - cos t = -k (a + b), i.e. sqrt 2 sin(t - pi/4) = -k (a + b).
    both(-k * (a + b) / 2f64.sqrt(), std::f64::consts::FRAC_PI_4);
    let tau = std::f64::consts::TAU;
    for t in angles {
        // Every turn of `t` inside the arc's range of headings.
        let mut u = t + ((t_min - t) / tau).ceil() * tau;
        while u <= t_max {
            let x = a + u.sin() / k;
            let y = b - u.cos() / k;
            best = best.min(x.abs().max(y.abs()));
            u += tau;
        }
    }
    best
}

/// The cells at chessboard distance exactly `ring` from `(cx, cy)`.
fn ring_cells(cx: i64, cy: i64, ring: i64) -> Vec<(i64, i64)> {
    if ring == 0 {
        return vec![(cx, cy)];
    }
    let mut out = Vec::with_capacity(8 * ring as usize);
    for k in -ring..=ring {
        out.push((cx + k, cy - ring));
        out.push((cx + k, cy + ring));
    }
    for k in -ring + 1..ring {
        out.push((cx - ring, cy + k));
        out.push((cx + ring, cy + k));
    }
    out
}

#[cfg(test)]
#[allow(clippy::unwrap_used, clippy::float_cmp)]
mod tests {
    use super::*;
    use crate::smooth::curve::Gear;

    #[test]
    fn distance_field_and_clearance_by_brute_force() {
        let mut grid = OccupancyGrid::new(9, 7, 1.0, [0.0; 2], Occupancy::Free).unwrap();
        for (x, y) in [(3, 2), (4, 2), (6, 5)] {
            grid.set(x, y, Occupancy::Occupied).unwrap();
        }
        let field = Field::new(&grid, false);
        for y in 0..7i64 {
            for x in 0..9i64 {
                let mut best = i64::MAX;
                for by in -1..=7i64 {
                    for bx in -1..=9i64 {
                        if field.blocked(bx, by) {
                            best = best.min((bx - x).abs().max((by - y).abs()));
                        }
                    }
                }
                assert_eq!(field.distance_near(x as f64, y as f64), best as f64);
            }
        }
        let p = Pose::new(1.3, 3.6, 0.0);
        // Nearest blocked centres: (3, 2) at max(1.7, 1.6) = 1.7, the border x = -1 at 2.3.
        assert!((field.clearance_at(p) - 0.7).abs() < 1e-12);
        let seg = Segment {
            start: Pose::new(1.0, 4.0, 0.0),
            curvature: 0.0,
            length: 6.0,
            gear: Gear::Forward,
        };
        // Along row 4 the square slides 2 rows below row 2: clear; along y = 2.5 it
        // enters (3, 2)'s square at x = 2, one cell along.
        assert!(field.segment_clear(&seg));
        let low = Segment {
            start: Pose::new(1.0, 2.5, 0.0),
            ..seg
        };
        assert!((field.clear_length(&low) - 1.0).abs() <= PIECE_CELLS);
    }

    #[test]
    fn curve_clearance_matches_dense_sampling_by_brute_force() {
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(41);
        let mut grid = OccupancyGrid::new(24, 20, 1.0, [0.0; 2], Occupancy::Free).unwrap();
        for _ in 0..30 {
            let (x, y) = (rng.random_range(0..24), rng.random_range(0..20));
            grid.set(x, y, Occupancy::Occupied).unwrap();
        }
        let field = Field::new(&grid, false);
        let blocked: Vec<(f64, f64)> = (-1..=24i64)
            .flat_map(|y| (-1..=25i64).map(move |x| (x, y)))
            .filter(|&(x, y)| field.blocked(x, y))
            .map(|(x, y)| (x as f64, y as f64))
            .collect();
        let brute = |p: Pose| {
            blocked
                .iter()
                .map(|&(x, y)| (p.x - x).abs().max((p.y - y).abs()))
                .fold(f64::INFINITY, f64::min)
                - 1.0
        };
        let (mut below_poses, mut tested) = (0, 0);
        for _ in 0..600 {
            let seg = Segment {
                start: Pose::new(
                    rng.random_range(2.0..22.0),
                    rng.random_range(2.0..18.0),
                    rng.random_range(-3.2..3.2),
                ),
                curvature: [0.0, 0.3, -0.7, 1.0][rng.random_range(0..4)],
                length: rng.random_range(0.1..9.0),
                gear: if rng.random_bool(0.3) {
                    Gear::Reverse
                } else {
                    Gear::Forward
                },
            };
            let curve = SmoothCurve {
                segments: vec![seg],
            };
            // On the grid (the brute force knows the border's blocked cells, not beyond).
            let inside = curve
                .sample(0.05)
                .iter()
                .all(|p| (0.0..=23.0).contains(&p.x) && (0.0..=19.0).contains(&p.y));
            if !inside {
                continue;
            }
            tested += 1;
            let exact = field.curve_min_clearance(&curve, seg.start);
            let h = 1e-3;
            let n = (seg.length / h).ceil() as usize;
            let sampled = (0..=n)
                .map(|i| brute(seg.pose_at(seg.length * i as f64 / n as f64)))
                .fold(f64::INFINITY, f64::min);
            // Never above any point's clearance; below the samples' by at most half a step
            // (the clearance moves by at most the length moved).
            assert!(exact <= sampled + 1e-9, "{seg:?}: {exact} > {sampled}");
            assert!(
                exact >= sampled - h / 2.0 - 1e-9,
                "{seg:?}: {exact} < {sampled}"
            );
            let poses = curve.sample(0.25);
            if exact < field.min_clearance(&poses) - 1e-6 {
                below_poses += 1;
            }
        }
        assert!(tested > 150, "{tested}");
        // Between poses a quarter cell apart the curve comes closer on some of them.
        assert!(below_poses > 0);
    }
}

//! The rasterisation: rules in the [crate docs](crate).

use vpmap_metrology::map::{FloorMap, MapPoint};
use vpmap_metrology::synth::Truth;

use vpmap_plan::{MAX_CELLS, Occupancy, OccupancyGrid, PlanError};

use crate::error::{RasterError, Result};

/// Options of [`rasterize_map`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RasterOptions {
    /// Side length of a cell, metres (map units). Default 0.05.
    pub resolution_m: f64,
    /// Obstacles are grown by this radius, metres. Default 0 (no inflation).
    pub robot_radius_m: f64,
    /// Unknown border added around the map's bounds, metres. Default 0.5.
    pub margin_m: f64,
    /// Treat floor hidden behind objects as free instead of unknown. Default false.
    pub hidden_free: bool,
}

impl Default for RasterOptions {
    fn default() -> Self {
        Self {
            resolution_m: 0.05,
            robot_radius_m: 0.0,
            margin_m: 0.5,
            hidden_free: false,
        }
    }
}

impl RasterOptions {
    /// Check every field.
    ///
    /// # Errors
    /// [`PlanError::InvalidParameter`] (in [`RasterError::Plan`]) naming the first invalid field and
    /// its value.
    pub fn validate(&self) -> Result<()> {
        if !(self.resolution_m.is_finite() && self.resolution_m > 0.0) {
            return Err(PlanError::InvalidParameter {
                field: "RasterOptions.resolution_m",
                value: self.resolution_m,
                requirement: "must be finite and positive",
            }
            .into());
        }
        for (field, value) in [
            ("RasterOptions.robot_radius_m", self.robot_radius_m),
            ("RasterOptions.margin_m", self.margin_m),
        ] {
            if !(value.is_finite() && value >= 0.0) {
                return Err(PlanError::InvalidParameter {
                    field,
                    value,
                    requirement: "must be finite and non-negative",
                }
                .into());
            }
        }
        Ok(())
    }
}

/// A point in continuous grid coordinates: `u` along columns, `v` along rows from the top;
/// cell `(x, y)` covers `[x, x + 1] x [y, y + 1]`.
#[derive(Debug, Clone, Copy)]
struct GridPoint {
    u: f64,
    v: f64,
}

/// The frame of the grid being filled.
struct Frame {
    origin_m: [f64; 2],
    resolution_m: f64,
    height: usize,
}

impl Frame {
    fn grid_from_world(&self, p: MapPoint) -> GridPoint {
        GridPoint {
            u: (p[0] - self.origin_m[0]) / self.resolution_m,
            v: self.height as f64 - (p[1] - self.origin_m[1]) / self.resolution_m,
        }
    }

    fn ring(&self, points: &[MapPoint]) -> Vec<GridPoint> {
        points.iter().map(|p| self.grid_from_world(*p)).collect()
    }
}

/// The edges of a ring, closed implicitly (a repeated last point adds a zero-length edge).
fn edges(ring: &[GridPoint]) -> impl Iterator<Item = (GridPoint, GridPoint)> + '_ {
    ring.iter()
        .zip(ring.iter().cycle().skip(1))
        .map(|(p, q)| (*p, *q))
}

/// Index range `[lo, hi]` (inclusive) of integers `i` with `lo_f <= i <= hi_f`, clamped
/// into `[0, len - 1]`; `None` when empty.
fn clamped_range(lo_f: f64, hi_f: f64, len: usize) -> Option<(usize, usize)> {
    let lo = lo_f.max(0.0);
    let hi = hi_f.min(len as f64 - 1.0);
    (lo <= hi).then_some((lo as usize, hi as usize))
}

/// Append to `runs` the half-open cell ranges `[x0, x1)` of the row whose centre line is
/// `v = vc` with centres inside `ring` (even-odd rule, half-open crossings).
fn centre_runs(
    ring: &[GridPoint],
    vc: f64,
    width: usize,
    crossings: &mut Vec<f64>,
    runs: &mut Vec<(usize, usize)>,
) {
    crossings.clear();
    for (p, q) in edges(ring) {
        if (p.v <= vc) != (q.v <= vc) {
            crossings.push(p.u + (vc - p.v) * (q.u - p.u) / (q.v - p.v));
        }
    }
    crossings.sort_by(f64::total_cmp);
    let w = width as f64;
    for pair in crossings.chunks_exact(2) {
        // Cells with u_in <= x + 1/2 < u_out.
        let x0 = (pair[0] - 0.5).ceil().clamp(0.0, w) as usize;
        let x1 = (pair[1] - 0.5).ceil().clamp(0.0, w) as usize;
        if x0 < x1 {
            runs.push((x0, x1));
        }
    }
}

/// Set every cell whose centre is inside `exterior` and outside every hole to `value`.
/// Each ring is read with the even-odd rule; holes are subtracted, so a hole that leaves
/// the exterior (an invalid polygon) removes nothing outside it.
fn fill_centres(
    grid: &mut OccupancyGrid,
    exterior: &[GridPoint],
    holes: &[Vec<GridPoint>],
    value: Occupancy,
) {
    let (w, h) = (grid.width(), grid.height());
    let (mut v_min, mut v_max) = (f64::INFINITY, f64::NEG_INFINITY);
    for p in exterior {
        v_min = v_min.min(p.v);
        v_max = v_max.max(p.v);
    }
    // Rows whose centre line `y + 1/2` lies in [v_min, v_max].
    let Some((y0, y1)) = clamped_range((v_min - 0.5).ceil(), (v_max - 0.5).floor(), h) else {
        return;
    };
    let mut crossings = Vec::new();
    let (mut inside, mut removed) = (Vec::new(), Vec::new());
    for y in y0..=y1 {
        let vc = y as f64 + 0.5;
        inside.clear();
        removed.clear();
        centre_runs(exterior, vc, w, &mut crossings, &mut inside);
        if inside.is_empty() {
            continue;
        }
        for hole in holes {
            centre_runs(hole, vc, w, &mut crossings, &mut removed);
        }
        removed.sort_unstable();
        let row_start = y * w;
        let Some(row) = grid.cells_mut().get_mut(row_start..row_start + w) else {
            continue;
        };
        let mut fill = |a: usize, b: usize| {
            if let Some(run) = row.get_mut(a..b) {
                run.fill(value);
            }
        };
        for &(a, b) in &inside {
            let mut cursor = a;
            for &(c, d) in &removed {
                if c >= b {
                    break;
                }
                if c > cursor {
                    fill(cursor, c);
                }
                cursor = cursor.max(d);
            }
            if cursor < b {
                fill(cursor, b);
            }
        }
    }
}

/// Set every cell whose closed square the segment `p`-`q` touches to `value`.
fn mark_segment(grid: &mut OccupancyGrid, p: GridPoint, q: GridPoint, value: Occupancy) {
    let (w, h) = (grid.width(), grid.height());
    let (v_lo, v_hi) = (p.v.min(q.v), p.v.max(q.v));
    let Some((y0, y1)) = clamped_range(v_lo.ceil() - 1.0, v_hi.floor(), h) else {
        return;
    };
    for y in y0..=y1 {
        let (u_lo, u_hi) = if v_hi > v_lo {
            let u_at = |v: f64| p.u + (v - p.v) * (q.u - p.u) / (q.v - p.v);
            let a = u_at((y as f64).max(v_lo));
            let b = u_at((y as f64 + 1.0).min(v_hi));
            (a.min(b), a.max(b))
        } else {
            (p.u.min(q.u), p.u.max(q.u))
        };
        if let Some((x0, x1)) = clamped_range(u_lo.ceil() - 1.0, u_hi.floor(), w)
            && let Some(run) = grid.cells_mut().get_mut(y * w + x0..=y * w + x1)
        {
            run.fill(value);
        }
    }
}

/// Largest distance of a floor map coordinate from the origin, map units (1,000 km for a
/// metric map): beyond it a map is refused before its extent is computed.
pub const MAX_MAP_COORDINATE: f64 = 1e6;

fn check_points<'a>(
    field: impl Fn(usize, usize) -> String,
    points: impl IntoIterator<Item = &'a MapPoint>,
) -> Result<()> {
    for (i, p) in points.into_iter().enumerate() {
        for (axis, value) in p.iter().enumerate() {
            if !value.is_finite() {
                return Err(RasterError::NonFiniteMap {
                    field: field(i, axis),
                    value: *value,
                });
            }
            if value.abs() > MAX_MAP_COORDINATE {
                return Err(RasterError::MapCoordinateOutOfRange {
                    field: field(i, axis),
                    value: *value,
                    limit: MAX_MAP_COORDINATE,
                });
            }
        }
    }
    Ok(())
}

fn check_map(map: &FloorMap) -> Result<()> {
    check_points(|i, a| format!("floor[{i}][{a}]"), &map.floor)?;
    for (k, poly) in map.free_space.iter().enumerate() {
        check_points(
            |i, a| format!("free_space[{k}].exterior[{i}][{a}]"),
            &poly.exterior,
        )?;
        for (h, hole) in poly.holes.iter().enumerate() {
            check_points(|i, a| format!("free_space[{k}].holes[{h}][{i}][{a}]"), hole)?;
        }
    }
    for (k, poly) in map.hidden.iter().enumerate() {
        check_points(
            |i, a| format!("hidden[{k}].exterior[{i}][{a}]"),
            &poly.exterior,
        )?;
        for (h, hole) in poly.holes.iter().enumerate() {
            check_points(|i, a| format!("hidden[{k}].holes[{h}][{i}][{a}]"), hole)?;
        }
    }
    for (k, object) in map.objects.iter().enumerate() {
        check_points(
            |i, a| format!("objects[{k}].footprint[{i}][{a}]"),
            &object.footprint,
        )?;
    }
    Ok(())
}

/// The occupancy grid of a floor map (rules in the [crate docs](crate)).
///
/// # Errors
/// [`RasterError::NonFiniteMap`] for a NaN or infinite map coordinate,
/// [`RasterError::MapCoordinateOutOfRange`] for one beyond [`MAX_MAP_COORDINATE`], and in
/// [`RasterError::Plan`]: [`PlanError::InvalidParameter`] for an invalid option,
/// [`PlanError::GridTooLarge`] when the map at this resolution needs more than [`MAX_CELLS`]
/// cells.
///
/// # Complexity
/// `O(rows x polygon edges + cells)`.
///
/// # Example
/// ```
/// use vpmap_metrology::map::{build_map, BuildOptions};
/// use vpmap_metrology::synth::{synthesize, SynthOptions};
/// use vpmap_plan::{CellXy, Occupancy};
/// use vpmap_raster::{rasterize_map, RasterOptions};
/// let (scene, _) = synthesize(&SynthOptions::default()).unwrap();
/// let map = build_map(&scene, &BuildOptions::default()).unwrap();
/// let grid = rasterize_map(&map, &RasterOptions::default()).unwrap();
/// let CellXy { x, y } = grid.cell_from_world(map.objects[0].centroid).unwrap();
/// assert_eq!(grid.get(x, y), Some(Occupancy::Occupied));
/// ```
pub fn rasterize_map(map: &FloorMap, opts: &RasterOptions) -> Result<OccupancyGrid> {
    opts.validate()?;
    check_map(map)?;
    let res = opts.resolution_m;
    let (mut lo, mut hi) = map.bounds();
    for p in map.free_space.iter().flat_map(|p| &p.exterior) {
        for axis in 0..2 {
            lo[axis] = lo[axis].min(p[axis]);
            hi[axis] = hi[axis].max(p[axis]);
        }
    }
    let origin_m = [
        ((lo[0] - opts.margin_m) / res).floor() * res,
        ((lo[1] - opts.margin_m) / res).floor() * res,
    ];
    let width_f = ((hi[0] + opts.margin_m - origin_m[0]) / res)
        .ceil()
        .max(1.0);
    let height_f = ((hi[1] + opts.margin_m - origin_m[1]) / res)
        .ceil()
        .max(1.0);
    let cells_f = width_f * height_f;
    if cells_f.is_nan() || cells_f > MAX_CELLS as f64 {
        return Err(PlanError::GridTooLarge {
            width: width_f as usize,
            height: height_f as usize,
            max: MAX_CELLS,
        }
        .into());
    }
    let (width, height) = (width_f as usize, height_f as usize);
    let mut grid = OccupancyGrid::new(width, height, res, origin_m, Occupancy::Unknown)?;
    let frame = Frame {
        origin_m,
        resolution_m: res,
        height,
    };
    for poly in &map.free_space {
        let holes: Vec<Vec<GridPoint>> = poly.holes.iter().map(|r| frame.ring(r)).collect();
        fill_centres(
            &mut grid,
            &frame.ring(&poly.exterior),
            &holes,
            Occupancy::Free,
        );
    }
    if !opts.hidden_free {
        for poly in &map.hidden {
            let holes: Vec<Vec<GridPoint>> = poly.holes.iter().map(|r| frame.ring(r)).collect();
            fill_centres(
                &mut grid,
                &frame.ring(&poly.exterior),
                &holes,
                Occupancy::Unknown,
            );
        }
    }
    for object in &map.objects {
        let ring = frame.ring(&object.footprint);
        for (p, q) in edges(&ring) {
            mark_segment(&mut grid, p, q, Occupancy::Occupied);
        }
        fill_centres(&mut grid, &ring, &[], Occupancy::Occupied);
    }
    Ok(grid.inflate(opts.robot_radius_m)?)
}

/// `truth` rasterised into `frame`'s grid (its size, resolution and origin; the truth's
/// coordinates are map metres, the frame of a map built from the truth's scene): a cell is
/// free when its centre lies on the floor outline and in no object's footprint (even-odd
/// rule), occupied otherwise; then inflated by `radius_m` like every planning grid.
///
/// # Errors
/// [`PlanError::InvalidParameter`] (in [`RasterError::Plan`]) when `radius_m` is negative or
/// not finite.
///
/// # Example
/// ```
/// use vpmap_metrology::{map::{build_map, BuildOptions}, synth::{synthesize, SynthOptions}};
/// use vpmap_raster::{rasterize_map, truth_grid, RasterOptions};
/// let (scene, truth) = synthesize(&SynthOptions::default()).unwrap();
/// let map = build_map(&scene, &BuildOptions::default()).unwrap();
/// let belief = rasterize_map(&map, &RasterOptions::default()).unwrap();
/// let true_grid = truth_grid(&truth, &belief, 0.2).unwrap();
/// assert_eq!((true_grid.width(), true_grid.height()), (belief.width(), belief.height()));
/// ```
pub fn truth_grid(truth: &Truth, frame: &OccupancyGrid, radius_m: f64) -> Result<OccupancyGrid> {
    let mut grid = OccupancyGrid::new(
        frame.width(),
        frame.height(),
        frame.resolution_m(),
        frame.origin_m(),
        Occupancy::Occupied,
    )?;
    for y in 0..grid.height() {
        for x in 0..grid.width() {
            let p = grid.world_from_cell(x, y);
            let on_floor = inside_even_odd(&truth.floor, p);
            let in_object = truth
                .objects
                .iter()
                .any(|o| inside_even_odd(&o.footprint, p));
            if on_floor && !in_object {
                grid.set(x, y, Occupancy::Free)?;
            }
        }
    }
    Ok(grid.inflate(radius_m)?)
}

/// Even-odd point-in-polygon test.
fn inside_even_odd(polygon: &[[f64; 2]], p: [f64; 2]) -> bool {
    let mut odd = false;
    let n = polygon.len();
    for i in 0..n {
        let (a, b) = (polygon[i], polygon[(i + 1) % n]);
        if (a[1] > p[1]) != (b[1] > p[1]) {
            let x = a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
            if p[0] < x {
                odd = !odd;
            }
        }
    }
    odd
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;
    use vpmap_metrology::synth::{TruthCamera, TruthObject};

    fn grid(w: usize, h: usize) -> OccupancyGrid {
        OccupancyGrid::new(w, h, 1.0, [0.0; 2], Occupancy::Free).unwrap()
    }

    fn occupied(g: &OccupancyGrid) -> Vec<(usize, usize)> {
        let mut out = Vec::new();
        for y in 0..g.height() {
            for x in 0..g.width() {
                if g.get(x, y) == Some(Occupancy::Occupied) {
                    out.push((x, y));
                }
            }
        }
        out
    }

    fn gp(u: f64, v: f64) -> GridPoint {
        GridPoint { u, v }
    }

    #[test]
    fn segment_marks_touched_squares_only() {
        let mut g = grid(5, 5);
        mark_segment(&mut g, gp(0.5, 0.5), gp(2.5, 0.5), Occupancy::Occupied);
        assert_eq!(occupied(&g), vec![(0, 0), (1, 0), (2, 0)]);
        let mut g = grid(5, 5);
        // A diagonal through cell corners touches the corner-adjacent cells too (closed squares).
        mark_segment(&mut g, gp(0.5, 0.5), gp(2.5, 2.5), Occupancy::Occupied);
        assert_eq!(
            occupied(&g),
            vec![(0, 0), (1, 0), (0, 1), (1, 1), (2, 1), (1, 2), (2, 2)]
        );
        let mut g = grid(5, 5);
        mark_segment(&mut g, gp(1.2, 3.7), gp(1.2, 3.7), Occupancy::Occupied);
        assert_eq!(occupied(&g), vec![(1, 3)]);
        let mut g = grid(3, 3);
        mark_segment(&mut g, gp(-5.0, 1.5), gp(10.0, 1.5), Occupancy::Occupied);
        assert_eq!(occupied(&g), vec![(0, 1), (1, 1), (2, 1)]);
    }

    #[test]
    fn scanline_fills_centres_and_skips_holes() {
        let mut g = grid(6, 6);
        let outer = vec![gp(0.0, 0.0), gp(6.0, 0.0), gp(6.0, 6.0), gp(0.0, 6.0)];
        let hole = vec![gp(2.0, 2.0), gp(4.0, 2.0), gp(4.0, 4.0), gp(2.0, 4.0)];
        fill_centres(&mut g, &outer, &[hole], Occupancy::Occupied);
        assert_eq!(g.counts(), (4, 32, 0));
        assert_eq!(g.get(2, 2), Some(Occupancy::Free));
        assert_eq!(g.get(3, 3), Some(Occupancy::Free));
        assert_eq!(g.get(1, 2), Some(Occupancy::Occupied));
        // Overlapping holes, and a hole reaching outside the exterior.
        let mut g = grid(8, 1);
        let outer = vec![gp(1.0, 0.0), gp(7.0, 0.0), gp(7.0, 1.0), gp(1.0, 1.0)];
        let holes = [
            vec![gp(2.0, 0.0), gp(4.0, 0.0), gp(4.0, 1.0), gp(2.0, 1.0)],
            vec![gp(3.0, 0.0), gp(5.0, 0.0), gp(5.0, 1.0), gp(3.0, 1.0)],
            vec![gp(6.0, 0.0), gp(9.0, 0.0), gp(9.0, 1.0), gp(6.0, 1.0)],
        ];
        fill_centres(&mut g, &outer, &holes, Occupancy::Occupied);
        let o = Occupancy::Occupied;
        let f = Occupancy::Free;
        assert_eq!(g.cells(), &[f, o, f, f, f, o, f, f]);
    }

    #[test]
    fn invalid_options_name_the_field() {
        let e = RasterOptions {
            resolution_m: -0.1,
            ..RasterOptions::default()
        }
        .validate()
        .unwrap_err();
        assert!(e.to_string().contains("RasterOptions.resolution_m"), "{e}");
        assert!(e.to_string().contains("-0.1"), "{e}");
        let e = RasterOptions {
            robot_radius_m: f64::NAN,
            ..RasterOptions::default()
        }
        .validate()
        .unwrap_err();
        assert!(e.to_string().contains("robot_radius_m"), "{e}");
        let e = RasterOptions {
            margin_m: -1.0,
            ..RasterOptions::default()
        }
        .validate()
        .unwrap_err();
        assert!(e.to_string().contains("margin_m"), "{e}");
    }

    #[test]
    fn truth_grid_of_a_square_room_with_a_box_in_it() {
        // An independent count: a 4 x 4 m floor and a 1 x 1 m box, 0.5 m cells centred on
        // the quarter metres, no inflation.
        let truth = Truth {
            camera: TruthCamera {
                focal_px: 1000.0,
                principal_point: None,
                pitch_deg: 20.0,
                roll_deg: 0.0,
                height: 1.5,
            },
            objects: vec![TruthObject {
                name: "box".to_owned(),
                footprint: vec![[1.0, 1.0], [2.0, 1.0], [2.0, 2.0], [1.0, 2.0]],
                height: 1.0,
            }],
            floor: vec![[0.0, 0.0], [4.0, 0.0], [4.0, 4.0], [0.0, 4.0]],
        };
        let frame = OccupancyGrid::new(10, 10, 0.5, [-0.5, -0.5], Occupancy::Unknown).unwrap();
        let grid = truth_grid(&truth, &frame, 0.0).unwrap();
        let free = grid
            .cells()
            .iter()
            .filter(|&&c| c == Occupancy::Free)
            .count();
        // 8 x 8 cells on the floor, 2 x 2 of them in the box.
        assert_eq!(free, 64 - 4);
    }
}

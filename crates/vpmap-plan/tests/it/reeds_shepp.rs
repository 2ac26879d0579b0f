//! Reeds-Shepp paths against independent references: the forward and the backward Dubins
//! distances of the tangent construction in `smooth.rs` (a path with cusps allowed is never
//! longer than either), paths with one cusp composed of two such Dubins paths through a
//! dense set of cusp poses (each a valid path from start to goal, so an upper bound), the
//! lower bounds (straight-line distance, `R` times the heading change), cases where a
//! forward path meets the lower bound (so the shortest path is that one), symmetries of
//! the problem, and every returned curve checked by the validator on an empty grid.

use std::f64::consts::{PI, TAU};

use approx::assert_relative_eq;
use rand::RngExt;
use vpmap_plan::smooth::reeds_shepp::{rs_distance, rs_paths, rs_shortest};
use vpmap_plan::smooth::{Gear, Pose, SmoothRules, dubins_distance};
use vpmap_plan::{Occupancy, OccupancyGrid, validate_smooth};

use crate::rng;
use crate::smooth::reference_dubins;

fn heading_gap(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(TAU);
    d.min(TAU - d)
}

/// The Dubins distance driving only in reverse: the forward one with both headings turned.
fn backward_dubins(p: Pose, q: Pose, r: f64) -> f64 {
    reference_dubins(
        Pose::new(p.x, p.y, p.heading_rad + PI),
        Pose::new(q.x, q.y, q.heading_rad + PI),
        r,
    )
}

fn one_gear(p: Pose, q: Pose, r: f64) -> f64 {
    reference_dubins(p, q, r).min(backward_dubins(p, q, r))
}

/// The shortest path with exactly one cusp at one of a grid of cusp poses (positions
/// `step_r` radii apart around both ends, `headings` headings): one Dubins path in one gear
/// to the cusp, one in the other gear from it. Each is a valid path, so the minimum is an
/// upper bound of the shortest path.
fn one_cusp_bound(p: Pose, q: Pose, r: f64, step_r: f64, headings: usize) -> f64 {
    let pad = 2.5 * r;
    let (x0, x1) = (p.x.min(q.x) - pad, p.x.max(q.x) + pad);
    let (y0, y1) = (p.y.min(q.y) - pad, p.y.max(q.y) + pad);
    let step = step_r * r;
    let mut best = f64::INFINITY;
    let nx = ((x1 - x0) / step).ceil() as usize;
    let ny = ((y1 - y0) / step).ceil() as usize;
    for i in 0..=nx {
        for j in 0..=ny {
            for k in 0..headings {
                let c = Pose::new(
                    x0 + i as f64 * step,
                    y0 + j as f64 * step,
                    TAU * k as f64 / headings as f64,
                );
                let fwd_then_back = reference_dubins(p, c, r) + backward_dubins(c, q, r);
                let back_then_fwd = backward_dubins(p, c, r) + reference_dubins(c, q, r);
                best = best.min(fwd_then_back).min(back_then_fwd);
            }
        }
    }
    best
}

fn rules(p: Pose, q: Pose, r: f64) -> SmoothRules {
    SmoothRules {
        radius_cells: r,
        start: p,
        start_heading: true,
        goal: q,
        goal_heading: true,
        reverse: true,
        unknown_passable: false,
    }
}

/// Every candidate `rs_paths` returns is drivable (validator on a free grid large enough to
/// hold it) and measured right; the first is the shortest.
fn check_all(p: Pose, q: Pose, r: f64) -> f64 {
    let paths = rs_paths(p, q, r);
    assert!(
        !paths.is_empty(),
        "no Reeds-Shepp path {p:?} -> {q:?} R {r}"
    );
    let grid = OccupancyGrid::new(400, 400, 1.0, [0.0; 2], Occupancy::Free).unwrap();
    for w in paths.windows(2) {
        assert!(w[0].length <= w[1].length);
    }
    for path in &paths {
        // The grid's frame: shift everything to its middle.
        let shift = |s: Pose| Pose::new(s.x + 200.0, s.y + 200.0, s.heading_rad);
        let mut curve = path.curve.clone();
        for s in &mut curve.segments {
            s.start = shift(s.start);
        }
        if let Err(e) = validate_smooth(&grid, &curve, &rules(shift(p), shift(q), r)) {
            panic!("{:?} from {p:?} to {q:?} R {r}: {e}", path.pieces);
        }
        assert_relative_eq!(path.length, curve.length(), epsilon = 1e-9);
        assert_eq!(path.cusps, curve.cusps());
        assert!(path.cusps <= 2, "{:?}", path.pieces);
    }
    assert_relative_eq!(paths[0].length, rs_distance(p, q, r), epsilon = 1e-9);
    paths[0].length
}

fn random_pose(rng: &mut impl RngExt, half: f64) -> Pose {
    Pose::new(
        rng.random_range(-half..half),
        rng.random_range(-half..half),
        rng.random_range(-PI..PI),
    )
}

#[test]
fn reeds_shepp_is_never_longer_than_either_gear_of_dubins_and_never_below_the_bounds() {
    let mut rng = rng(41);
    let mut shorter = 0;
    let n = 400;
    for _ in 0..n {
        let r = rng.random_range(0.5..3.0);
        let (p, q) = (random_pose(&mut rng, 8.0), random_pose(&mut rng, 8.0));
        let rs = check_all(p, q, r);
        let (fwd, bwd) = (reference_dubins(p, q, r), backward_dubins(p, q, r));
        assert!(
            rs <= fwd.min(bwd) + 1e-9,
            "{p:?} {q:?} R {r}: {rs} > {fwd} / {bwd}"
        );
        let bound = p
            .distance(&q)
            .max(r * heading_gap(p.heading_rad, q.heading_rad));
        assert!(rs >= bound - 1e-9, "{p:?} {q:?} R {r}: {rs} < {bound}");
        if rs < fwd.min(bwd) - 1e-6 {
            shorter += 1;
        }
    }
    // Cusps pay off often between random poses a few radii apart.
    println!("Reeds-Shepp shorter than both Dubins gears on {shorter} of {n}");
    assert!(shorter > n / 4, "{shorter} of {n}");
}

#[test]
fn reeds_shepp_is_never_longer_than_a_dense_set_of_one_cusp_paths() {
    let mut rng = rng(7);
    let mut gaps = Vec::new();
    for _ in 0..12 {
        let r = 1.0;
        let (p, q) = (random_pose(&mut rng, 2.5), random_pose(&mut rng, 2.5));
        let rs = check_all(p, q, r);
        let bound = one_cusp_bound(p, q, r, 0.2, 36).min(one_gear(p, q, r));
        assert!(rs <= bound + 1e-9, "{p:?} {q:?}: {rs} > {bound}");
        gaps.push((bound - rs) / rs);
    }
    gaps.sort_by(f64::total_cmp);
    println!("one-cusp bound over Reeds-Shepp, relative: {gaps:.4?}");
}

#[test]
fn reeds_shepp_equals_a_forward_path_that_meets_the_lower_bound() {
    let mut rng = rng(3);
    for _ in 0..200 {
        let r = rng.random_range(0.5..4.0);
        let p = random_pose(&mut rng, 5.0);
        // Straight ahead: the length is the distance.
        let d = rng.random_range(0.1..20.0);
        let (s, c) = p.heading_rad.sin_cos();
        let ahead = Pose::new(p.x + d * c, p.y + d * s, p.heading_rad);
        assert_relative_eq!(check_all(p, ahead, r), d, epsilon = 1e-8);
        // One arc of at most pi: the length is R times the heading change.
        let turn =
            rng.random_range(0.05..PI - 1e-3) * if rng.random_bool(0.5) { 1.0 } else { -1.0 };
        let k = turn.signum() / r;
        let end = vpmap_plan::smooth::curve::pose_along(p, k, turn.abs() * r);
        let rs = check_all(p, end, r);
        assert_relative_eq!(rs, r * turn.abs(), epsilon = 1e-8);
        // (The tangent construction degenerates when both turning circles coincide; the
        // library's Dubins is checked against it elsewhere. Its line's length is the root of
        // a squared length that is zero up to round-off, 1e-16, so 1e-8 radii long.)
        assert_relative_eq!(rs, dubins_distance(p, end, r), epsilon = 1e-6);
        assert_eq!(rs_shortest(p, end, r).unwrap().cusps, 0);
    }
}

#[test]
fn reeds_shepp_lengths_keep_the_symmetries_of_the_problem() {
    let mut rng = rng(11);
    for _ in 0..300 {
        let r = rng.random_range(0.5..3.0);
        let (p, q) = (random_pose(&mut rng, 6.0), random_pose(&mut rng, 6.0));
        let l = rs_distance(p, q, r);
        // Time reversal: the same curve driven from the goal, gears swapped.
        assert_relative_eq!(rs_distance(q, p, r), l, epsilon = 1e-8);
        // Facing the other way: the same curve with every gear swapped.
        let turned = |s: Pose| Pose::new(s.x, s.y, s.heading_rad + PI);
        assert_relative_eq!(rs_distance(turned(p), turned(q), r), l, epsilon = 1e-8);
        // Reflection in the x axis.
        let mirror = |s: Pose| Pose::new(s.x, -s.y, -s.heading_rad);
        assert_relative_eq!(rs_distance(mirror(p), mirror(q), r), l, epsilon = 1e-8);
        // Rigid motion and scale: lengths scale with R.
        let moved = |s: Pose| {
            let (sn, cs) = 0.7f64.sin_cos();
            Pose::new(
                2.0 * (cs * s.x - sn * s.y) + 3.0,
                2.0 * (sn * s.x + cs * s.y) - 1.0,
                s.heading_rad + 0.7,
            )
        };
        assert_relative_eq!(
            rs_distance(moved(p), moved(q), 2.0 * r),
            2.0 * l,
            epsilon = 1e-8
        );
    }
}

#[test]
fn backing_into_a_pose_beside_the_start_uses_cusps() {
    // Parallel parking: one radius to the side, same heading. Forward needs a loop.
    let (p, q) = (Pose::new(0.0, 0.0, 0.0), Pose::new(0.0, 1.0, 0.0));
    let path = rs_shortest(p, q, 1.0).unwrap();
    check_all(p, q, 1.0);
    assert!(path.cusps >= 1, "{:?}", path.pieces);
    assert!(path.curve.segments.iter().any(|s| s.gear == Gear::Reverse));
    assert!(path.length < reference_dubins(p, q, 1.0) - 1.0);
}

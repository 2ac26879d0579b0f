//! Smooth paths: Dubins lengths against an independent tangent construction and textbook
//! values, curve invariants by property tests, the validator on hand-made grids.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use approx::assert_relative_eq;
use proptest::prelude::*;
use vpmap_plan::smooth::dubins::{Steer, dubins_from_point, dubins_to_point, dubins_words};
use vpmap_plan::smooth::{Gear, Pose, Segment, SmoothCurve, SmoothRules, SmoothViolation};
use vpmap_plan::{Occupancy, OccupancyGrid, validate_smooth};

// ---------------------------------------------------------------------------------------
// An independent Dubins: tangent lines between turning circles, and a third circle
// touching two, enumerated by elementary geometry (no closed-form word lengths).

fn left(u: [f64; 2]) -> [f64; 2] {
    [-u[1], u[0]]
}

/// Turning-circle centre for side `s` (+1 left, -1 right) at pose `p`, radius `r`.
fn circle(p: Pose, s: f64, r: f64) -> [f64; 2] {
    let n = left([p.heading_rad.cos(), p.heading_rad.sin()]);
    [p.x + s * r * n[0], p.y + s * r * n[1]]
}

/// Arc angle turning from heading `a` to heading `b` on side `s`.
fn turn(a: f64, b: f64, s: f64) -> f64 {
    (s * (b - a)).rem_euclid(TAU)
}

/// Shortest CSC path with sides `s1`, `s2` by enumerating the common tangents.
fn csc_by_tangents(p: Pose, q: Pose, s1: f64, s2: f64, r: f64) -> Option<f64> {
    let (c1, c2) = (circle(p, s1, r), circle(q, s2, r));
    let w = [c2[0] - c1[0], c2[1] - c1[1]];
    let dist = w[0].hypot(w[1]);
    // left(u) . w = r (s2 - s1)  <=>  dist sin(omega - theta) = r (s2 - s1).
    let k = r * (s2 - s1) / dist.max(1e-300);
    if k.abs() > 1.0 {
        return None;
    }
    let omega = w[1].atan2(w[0]);
    let mut best: Option<f64> = None;
    for theta in [omega - k.asin(), omega - (PI - k.asin())] {
        let u = [theta.cos(), theta.sin()];
        let n = left(u);
        let t1 = [c1[0] - s1 * r * n[0], c1[1] - s1 * r * n[1]];
        let t2 = [c2[0] - s2 * r * n[0], c2[1] - s2 * r * n[1]];
        let line = (t2[0] - t1[0]) * u[0] + (t2[1] - t1[1]) * u[1];
        if line < -1e-9 {
            continue;
        }
        let len = r * (turn(p.heading_rad, theta, s1) + turn(theta, q.heading_rad, s2)) + line;
        best = Some(best.map_or(len, |b: f64| b.min(len)));
    }
    best
}

/// Shortest CCC path with outer side `s` through a middle circle touching both.
fn ccc_by_circles(p: Pose, q: Pose, s: f64, r: f64) -> Option<f64> {
    let (c1, c3) = (circle(p, s, r), circle(q, s, r));
    let w = [c3[0] - c1[0], c3[1] - c1[1]];
    let dist = w[0].hypot(w[1]);
    if dist > 4.0 * r || dist < 1e-12 {
        return None;
    }
    let half = dist / 2.0;
    let h = ((2.0 * r).powi(2) - half * half).max(0.0).sqrt();
    let mid = [c1[0] + w[0] / 2.0, c1[1] + w[1] / 2.0];
    let n = [-w[1] / dist, w[0] / dist];
    let mut best: Option<f64> = None;
    for sign in [1.0, -1.0] {
        let m = [mid[0] + sign * h * n[0], mid[1] + sign * h * n[1]];
        // Headings at the two tangency points (midpoints between centres).
        let heading_on = |c: [f64; 2], point: [f64; 2], side: f64| {
            (point[1] - c[1]).atan2(point[0] - c[0]) + side * FRAC_PI_2
        };
        let q1 = [f64::midpoint(c1[0], m[0]), f64::midpoint(c1[1], m[1])];
        let q2 = [f64::midpoint(m[0], c3[0]), f64::midpoint(m[1], c3[1])];
        let h1 = heading_on(c1, q1, s);
        let h2 = heading_on(m, q2, -s);
        let len = r * (turn(p.heading_rad, h1, s) + turn(h1, h2, -s) + turn(h2, q.heading_rad, s));
        best = Some(best.map_or(len, |b: f64| b.min(len)));
    }
    best
}

pub(crate) fn reference_dubins(p: Pose, q: Pose, r: f64) -> f64 {
    let mut best = f64::INFINITY;
    for (s1, s2) in [(1.0, 1.0), (-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0)] {
        if let Some(l) = csc_by_tangents(p, q, s1, s2, r) {
            best = best.min(l);
        }
    }
    for s in [1.0, -1.0] {
        if let Some(l) = ccc_by_circles(p, q, s, r) {
            best = best.min(l);
        }
    }
    best
}

fn end_of(curve: &SmoothCurve, start: Pose) -> Pose {
    curve.segments.last().map_or(start, Segment::end)
}

fn heading_gap(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(TAU);
    d.min(TAU - d)
}

#[test]
fn dubins_textbook_values() {
    let o = Pose::new(0.0, 0.0, 0.0);
    let r = 2.0;
    let len = |q: Pose| dubins_words(o, q, r)[0].length;
    // Straight ahead.
    assert_relative_eq!(len(Pose::new(7.0, 0.0, 0.0)), 7.0, epsilon = 1e-9);
    // Half circles to either side, quarter circles.
    assert_relative_eq!(len(Pose::new(0.0, 2.0 * r, PI)), PI * r, epsilon = 1e-9);
    assert_relative_eq!(len(Pose::new(0.0, -2.0 * r, PI)), PI * r, epsilon = 1e-9);
    assert_relative_eq!(
        len(Pose::new(r, r, FRAC_PI_2)),
        FRAC_PI_2 * r,
        epsilon = 1e-9
    );
    // Straight behind, farther than 4r: half a circle, the line back, half a circle.
    let d = 10.0;
    assert_relative_eq!(len(Pose::new(-d, 0.0, 0.0)), TAU * r + d, epsilon = 1e-9);
    // The same pose: zero.
    assert_relative_eq!(len(o), 0.0, epsilon = 1e-9);
    // A sideways shift by 2r far ahead, same heading: an S-bend of two equal opposite
    // turns, minimised here by brute force over the turn angle.
    let x = 20.0;
    let lateral = 2.0 * r;
    // S-bend: turn a, straight l, turn back a with 2 r (1 - cos a) + l sin a = lateral,
    // 2 r sin a + l cos a = x; minimise 2 r a + l: brute force over a.
    let mut best = f64::INFINITY;
    for k in 1..200_000 {
        let a = FRAC_PI_2 * f64::from(k) / 200_000.0;
        let l = (lateral - 2.0 * r * (1.0 - a.cos())) / a.sin();
        if l >= 0.0 && ((2.0 * r * a.sin() + l * a.cos()) - x).abs() < 1e-3 {
            best = best.min(2.0 * r * a + l);
        }
    }
    assert!(best.is_finite());
    assert_relative_eq!(len(Pose::new(x, lateral, 0.0)), best, epsilon = 2e-3);
}

#[test]
fn dubins_matches_tangent_construction_on_a_grid_of_poses() {
    let r = 1.5;
    let o = Pose::new(0.0, 0.0, 0.4);
    let mut checked = 0;
    for ix in -6..=6 {
        for iy in -6..=6 {
            for ih in 0..12 {
                let q = Pose::new(
                    f64::from(ix) * 0.9,
                    f64::from(iy) * 0.9,
                    TAU * f64::from(ih) / 12.0,
                );
                let words = dubins_words(o, q, r);
                let mine = words[0].length;
                let reference = reference_dubins(o, q, r);
                assert!(
                    (mine - reference).abs() < 1e-7 * (1.0 + reference),
                    "to {q:?}: {mine} vs reference {reference}"
                );
                // Every CSC word alone agrees with its tangent construction.
                for w in &words {
                    let sides = w.word.map(|s| match s {
                        Steer::Left => 1.0,
                        Steer::Right => -1.0,
                        Steer::Straight => 0.0,
                    });
                    if sides[1] == 0.0 {
                        let t = csc_by_tangents(o, q, sides[0], sides[2], r).unwrap();
                        assert!((t - w.length).abs() < 1e-7 * (1.0 + t), "{:?}", w.word);
                    }
                }
                checked += 1;
            }
        }
    }
    assert_eq!(checked, 13 * 13 * 12);
}

proptest! {
    #[test]
    fn dubins_paths_join_the_poses_and_respect_the_radius(
        x in -30.0..30.0f64, y in -30.0..30.0f64,
        h0 in -PI..PI, h1 in -PI..PI, r in 0.2..8.0f64,
    ) {
        let p = Pose::new(1.0, -2.0, h0);
        let q = Pose::new(x, y, h1);
        let words = dubins_words(p, q, r);
        prop_assert!(!words.is_empty());
        for w in &words {
            let end = end_of(&w.curve, p);
            prop_assert!(end.distance(&q) < 1e-6 * (1.0 + r), "{:?} ends at {:?}", w.word, end);
            prop_assert!(heading_gap(end.heading_rad, q.heading_rad) < 1e-6);
            prop_assert!(w.curve.max_curvature() <= 1.0 / r * (1.0 + 1e-12));
            prop_assert!((w.curve.length() - w.length).abs() < 1e-9 * (1.0 + w.length));
            for pair in w.curve.segments.windows(2) {
                let (a, b) = (pair[0].end(), pair[1].start);
                prop_assert!(a.distance(&b) < 1e-9 * (1.0 + r));
                prop_assert!(heading_gap(a.heading_rad, b.heading_rad) < 1e-9);
            }
        }
        // Shortest: no longer than the independent construction, and the bound by
        // straight-line distance holds.
        let reference = reference_dubins(p, q, r);
        prop_assert!((words[0].length - reference).abs() < 1e-7 * (1.0 + reference));
        prop_assert!(words[0].length >= p.distance(&q) - 1e-9);
    }

    #[test]
    fn free_heading_paths_reach_the_point(
        x in -30.0..30.0f64, y in -30.0..30.0f64, h in -PI..PI, r in 0.2..8.0f64,
    ) {
        let p = Pose::new(0.0, 0.0, h);
        let to = dubins_to_point(p, x, y, r).unwrap();
        let end = end_of(&to.curve, p);
        prop_assert!((end.x - x).hypot(end.y - y) < 1e-6 * (1.0 + r));
        // Never longer than the Dubins path with the straight-on heading.
        let straight_on = dubins_words(p, Pose::new(x, y, (y - p.y).atan2(x - p.x)), r)[0].length;
        prop_assert!(to.length <= straight_on + 1e-9);
        let from = dubins_from_point(x, y, p, r).unwrap();
        let first = from.curve.segments.first().map_or(p, |s| s.start);
        prop_assert!((first.x - x).hypot(first.y - y) < 1e-6 * (1.0 + r));
        let end = end_of(&from.curve, p);
        prop_assert!(end.distance(&p) < 1e-6 * (1.0 + r));
        prop_assert!(heading_gap(end.heading_rad, p.heading_rad) < 1e-6);
    }
}

// ---------------------------------------------------------------------------------------
// The validator on hand-made grids.

fn line(x: f64, y: f64, h: f64, length: f64) -> Segment {
    Segment {
        start: Pose::new(x, y, h),
        curvature: 0.0,
        length,
        gear: Gear::Forward,
    }
}

fn rules(start: Pose, goal: Pose, radius: f64) -> SmoothRules {
    SmoothRules {
        radius_cells: radius,
        start,
        start_heading: true,
        goal,
        goal_heading: true,
        reverse: false,
        unknown_passable: false,
    }
}

fn curve_of(segments: &[Segment]) -> SmoothCurve {
    let mut c = SmoothCurve::default();
    for &s in segments {
        c.push(s);
    }
    c
}

#[test]
fn validator_accepts_a_path_sliding_along_a_wall_and_rejects_one_a_hair_closer() {
    // Row 0 blocked: a path along row 1 touches its squares' edge (allowed).
    let mut grid = OccupancyGrid::new(10, 4, 1.0, [0.0; 2], Occupancy::Free).unwrap();
    for x in 0..10 {
        grid.set(x, 0, Occupancy::Occupied).unwrap();
    }
    let ok = curve_of(&[line(1.0, 1.0, 0.0, 7.0)]);
    let r = rules(Pose::new(1.0, 1.0, 0.0), Pose::new(8.0, 1.0, 0.0), 1.0);
    assert_eq!(validate_smooth(&grid, &ok, &r), Ok(()));
    // Tilted by a little: it dips into row 0's squares on the way.
    let h = -0.01_f64;
    let bad = curve_of(&[line(1.0, 1.0, h, 7.0)]);
    let end = bad.segments[0].end();
    let r = rules(Pose::new(1.0, 1.0, h), end, 1.0);
    assert!(matches!(
        validate_smooth(&grid, &bad, &r),
        Err(SmoothViolation::Collision {
            segment: 0,
            cell: (_, 0),
            ..
        })
    ));
}

#[test]
fn validator_catches_an_arc_bulging_into_a_cell_between_samples() {
    // A quarter circle of radius 3 around (0, 3): from (0, 0) heading 0 to (3, 3) heading
    // pi/2. Its farthest point from the chord bulges into cell (3, 1)'s square only
    // between the ends: the cell (3, 0) is far from both ends' squares.
    let r = 3.0;
    let arc = Segment {
        start: Pose::new(0.0, 0.0, 0.0),
        curvature: 1.0 / r,
        length: FRAC_PI_2 * r,
        gear: Gear::Forward,
    };
    let curve = curve_of(&[arc]);
    let end = arc.end();
    let mut grid = OccupancyGrid::new(8, 8, 1.0, [0.0; 2], Occupancy::Free).unwrap();
    let rr = SmoothRules {
        start_heading: true,
        ..rules(arc.start, end, r)
    };
    // On the free grid the arc only touches the border's squares.
    assert_eq!(validate_smooth(&grid, &curve, &rr), Ok(()));
    // At 45 degrees it passes (2.12, 0.88), inside cell (3, 0)'s square, which neither
    // end's square reaches.
    grid.set(3, 0, Occupancy::Occupied).unwrap();
    assert!(matches!(
        validate_smooth(&grid, &curve, &rr),
        Err(SmoothViolation::Collision { cell: (3, 0), .. })
    ));
}

// ---------------------------------------------------------------------------------------
// The planner: every path validated again here, never shorter than the any-angle bound or
// the Dubins distance, the fallback reference found whenever it finds one.

use rand::RngExt;
use vpmap_plan::smooth::{
    SmoothMethod, SmoothOptions, SmoothOutcome, SmoothPlan, dubins_distance, plan_smooth,
    rs_distance,
};
use vpmap_plan::{PlanError, reachable};

fn random_grid(seed: u64, w: usize, h: usize, density: f64) -> OccupancyGrid {
    let mut rng = crate::rng(seed);
    let mut grid = OccupancyGrid::new(w, h, 1.0, [0.0; 2], Occupancy::Free).unwrap();
    // Rectangular obstacles, as Nav2's benchmark maps.
    let count = ((w * h) as f64 * density / 12.0) as usize;
    for _ in 0..count {
        let (x, y) = (rng.random_range(0..w), rng.random_range(0..h));
        let (bw, bh) = (rng.random_range(1..5), rng.random_range(1..5));
        for yy in y..(y + bh).min(h) {
            for xx in x..(x + bw).min(w) {
                grid.set(xx, yy, Occupancy::Occupied).unwrap();
            }
        }
    }
    grid
}

fn free_cell(grid: &OccupancyGrid, rng: &mut impl RngExt) -> (usize, usize) {
    loop {
        let c = (
            rng.random_range(0..grid.width()),
            rng.random_range(0..grid.height()),
        );
        if grid.is_free(c.0, c.1) {
            return c;
        }
    }
}

fn check_plan(
    grid: &OccupancyGrid,
    plan: &SmoothPlan,
    opts: &SmoothOptions,
    s: (usize, usize),
    g: (usize, usize),
) {
    let rules = SmoothRules {
        radius_cells: opts.turning_radius_cells,
        start: Pose::new(
            s.0 as f64,
            s.1 as f64,
            opts.start_heading_rad.unwrap_or(0.0),
        ),
        start_heading: opts.start_heading_rad.is_some(),
        goal: Pose::new(g.0 as f64, g.1 as f64, opts.goal_heading_rad.unwrap_or(0.0)),
        goal_heading: opts.goal_heading_rad.is_some(),
        reverse: opts.reverse,
        unknown_passable: opts.unknown_passable,
    };
    assert_eq!(validate_smooth(grid, &plan.curve, &rules), Ok(()));
    assert!(plan.length_cells >= plan.any_angle_length_cells - 1e-6);
    if let (Some(a), Some(b)) = (opts.start_heading_rad, opts.goal_heading_rad) {
        let (from, to) = (
            Pose::new(s.0 as f64, s.1 as f64, a),
            Pose::new(g.0 as f64, g.1 as f64, b),
        );
        // With reverse the Reeds-Shepp distance is the bound (the Dubins one is not).
        let d = if opts.reverse {
            rs_distance(from, to, opts.turning_radius_cells)
        } else {
            dubins_distance(from, to, opts.turning_radius_cells)
        };
        assert!(plan.length_cells >= d - 1e-6);
    }
    assert!(plan.max_curvature <= 1.0 / opts.turning_radius_cells * (1.0 + 1e-12));
    assert!(plan.min_clearance_cells >= -1e-9);
    // Poses: at most a quarter cell apart, the ends exact.
    for w in plan.poses.windows(2) {
        assert!(w[0].distance(&w[1]) <= 0.25 + 1e-9);
    }
    let (first, last) = (plan.poses[0], *plan.poses.last().unwrap());
    assert_eq!((first.x, first.y), (s.0 as f64, s.1 as f64));
    assert_eq!((last.x, last.y), (g.0 as f64, g.1 as f64));
}

/// Query `k` of the random-map tests: the turning radius 1, 2.5 or 4 cells, and free headings,
/// the start's only, or both, drawn from `rng`.
fn random_query_options(rng: &mut impl RngExt, k: usize) -> SmoothOptions {
    let headings = match k % 3 {
        0 => (None, None),
        1 => (Some(rng.random_range(-PI..PI)), None),
        _ => (
            Some(rng.random_range(-PI..PI)),
            Some(rng.random_range(-PI..PI)),
        ),
    };
    SmoothOptions {
        turning_radius_cells: [1.0, 2.5, 4.0][k % 3],
        start_heading_rad: headings.0,
        goal_heading_rad: headings.1,
        ..SmoothOptions::default()
    }
}

#[test]
fn smooth_paths_on_random_maps_are_drivable_and_no_shorter_than_the_bounds() {
    let mut found = 0;
    let mut rng = crate::rng(41);
    for seed in 0..12u64 {
        let grid = random_grid(seed, 60, 45, 0.12);
        for k in 0..4 {
            let (s, g) = (free_cell(&grid, &mut rng), free_cell(&grid, &mut rng));
            let opts = random_query_options(&mut rng, k);
            let out = plan_smooth(&grid, s, g, &opts).unwrap();
            let reference = plan_smooth(
                &grid,
                s,
                g,
                &SmoothOptions {
                    method: SmoothMethod::HybridAstar,
                    ..opts.clone()
                },
            )
            .unwrap();
            match (&out, &reference) {
                (SmoothOutcome::Path(p), _) => {
                    assert!(reachable(&grid, s, g, false));
                    check_plan(&grid, p, &opts, s, g);
                    found += 1;
                }
                (SmoothOutcome::NoPath(_), SmoothOutcome::Path(_)) => {
                    panic!(
                        "seed {seed}: the reference found a path from {s:?} to {g:?}, the planner none"
                    );
                }
                (SmoothOutcome::NoPath(n), SmoothOutcome::NoPath(_)) => {
                    assert!(!n.reason.is_empty());
                }
            }
            if let SmoothOutcome::Path(p) = &reference {
                check_plan(&grid, p, &opts, s, g);
            }
        }
    }
    assert!(found >= 30, "only {found} of 48 queries found a path");
}

#[test]
fn reverse_paths_on_random_maps_are_drivable_never_longer_than_forward_and_found_when_the_reference_finds_one()
 {
    let mut rng = crate::rng(43);
    let (mut found, mut with_cusps, mut shorter, mut fillet) = (0, 0, 0, 0);
    for seed in 0..12u64 {
        let grid = random_grid(100 + seed, 60, 45, 0.12);
        for k in 0..4 {
            let (s, g) = (free_cell(&grid, &mut rng), free_cell(&grid, &mut rng));
            let forward = random_query_options(&mut rng, k);
            let headings = (forward.start_heading_rad, forward.goal_heading_rad);
            let opts = SmoothOptions {
                reverse: true,
                ..forward.clone()
            };
            let out = plan_smooth(&grid, s, g, &opts).unwrap();
            let fwd = plan_smooth(&grid, s, g, &forward).unwrap();
            let reference = plan_smooth(
                &grid,
                s,
                g,
                &SmoothOptions {
                    method: SmoothMethod::HybridAstar,
                    ..opts.clone()
                },
            )
            .unwrap();
            let what = format!(
                "seed {seed} {s:?} -> {g:?} {headings:?} R {}",
                opts.turning_radius_cells
            );
            if let SmoothOutcome::Path(p) = &reference {
                check_plan(&grid, p, &opts, s, g);
            }
            match (&out, &reference, &fwd) {
                (SmoothOutcome::Path(p), _, _) => {
                    check_plan(&grid, p, &opts, s, g);
                    if let (Some(a), Some(b)) = headings {
                        let d = rs_distance(
                            Pose::new(s.0 as f64, s.1 as f64, a),
                            Pose::new(g.0 as f64, g.1 as f64, b),
                            opts.turning_radius_cells,
                        );
                        assert!(p.length_cells >= d - 1e-6, "{what}");
                    }
                    found += 1;
                    with_cusps += usize::from(p.cusps > 0);
                    fillet += usize::from(p.method == "fillet");
                    if let SmoothOutcome::Path(f) = &fwd {
                        // Every forward word is among the reverse words, so the fillet
                        // search's reverse path is no longer than its forward one; both are
                        // then polished, which never lengthens but is greedy, so the
                        // comparison is made before polishing.
                        if p.method == "fillet" && f.method == "fillet" {
                            let unpolished = |reverse: bool| {
                                let taut = vpmap_plan::ExactPlanner::new(&grid, false)
                                    .plan(s, g, &vpmap_plan::Budget::default())
                                    .unwrap()
                                    .unwrap();
                                let ends = (
                                    Pose::new(s.0 as f64, s.1 as f64, headings.0.unwrap_or(0.0)),
                                    headings.0.is_none(),
                                    Pose::new(g.0 as f64, g.1 as f64, headings.1.unwrap_or(0.0)),
                                    headings.1.is_none(),
                                );
                                vpmap_plan::smooth::fillet::fillet(
                                    &vpmap_plan::smooth::clearance::Field::new(&grid, false),
                                    &taut.waypoints,
                                    ends,
                                    opts.turning_radius_cells,
                                    reverse,
                                    &mut vpmap_plan::smooth::fillet::FilletStats::default(),
                                )
                                .unwrap()
                            };
                            let (rev, fwd) = (unpolished(true), unpolished(false));
                            assert!(rev.length() <= fwd.length() + 1e-6, "{what}");
                            assert!(p.length_cells <= rev.length() + 1e-6, "{what}");
                            assert!(f.length_cells <= fwd.length() + 1e-6, "{what}");
                            // The polish never adds a cusp.
                            assert!(p.cusps <= rev.cusps(), "{what}");
                        }
                        shorter += usize::from(p.length_cells < f.length_cells - 1e-6);
                    }
                }
                (SmoothOutcome::NoPath(n), SmoothOutcome::Path(_), _) => {
                    panic!(
                        "{what}: the reference found a path, the planner none: {}",
                        n.reason
                    );
                }
                (SmoothOutcome::NoPath(n), _, SmoothOutcome::Path(_)) => {
                    panic!(
                        "{what}: a forward path exists, the reverse planner found none: {}",
                        n.reason
                    );
                }
                (SmoothOutcome::NoPath(n), _, _) => assert!(!n.reason.is_empty()),
            }
        }
    }
    println!(
        "reverse: {found} of 48 found ({fillet} by fillet), {with_cusps} with cusps, {shorter} shorter than forward"
    );
    assert!(found >= 30, "only {found} of 48 queries found a path");
    assert!(with_cusps > 0 && shorter > 0);
}

#[test]
fn a_robot_facing_a_dead_end_backs_out_when_reverse_is_allowed() {
    // A dead-end corridor one cell wide, the robot in it facing the closed end.
    let mut grid = OccupancyGrid::new(30, 15, 1.0, [0.0; 2], Occupancy::Free).unwrap();
    for x in 0..10 {
        for y in [6, 8] {
            grid.set(x, y, Occupancy::Occupied).unwrap();
        }
    }
    grid.set(0, 7, Occupancy::Occupied).unwrap();
    let opts = SmoothOptions {
        turning_radius_cells: 3.0,
        start_heading_rad: Some(PI),
        goal_heading_rad: Some(PI / 2.0),
        reverse: true,
        ..SmoothOptions::default()
    };
    let (s, g) = ((3, 7), (22, 12));
    let SmoothOutcome::Path(p) = plan_smooth(&grid, s, g, &opts).unwrap() else {
        panic!("no path backing out of the dead end");
    };
    check_plan(&grid, &p, &opts, s, g);
    assert_eq!(p.curve.segments[0].gear, Gear::Reverse);
    assert!(p.cusps >= 1, "{:?}", p.curve);
    let forward = SmoothOptions {
        reverse: false,
        ..opts.clone()
    };
    assert!(matches!(
        plan_smooth(&grid, s, g, &forward).unwrap(),
        SmoothOutcome::NoPath(_)
    ));
}

#[test]
fn a_start_facing_a_wall_has_no_room_and_bad_input_is_refused() {
    // A dead-end corridor one cell wide, the start in it facing the wall.
    let mut grid = OccupancyGrid::new(20, 9, 1.0, [0.0; 2], Occupancy::Free).unwrap();
    for x in 0..20 {
        for y in [3, 5] {
            if x < 8 {
                grid.set(x, y, Occupancy::Occupied).unwrap();
            }
        }
    }
    grid.set(0, 4, Occupancy::Occupied).unwrap();
    let opts = SmoothOptions {
        turning_radius_cells: 3.0,
        start_heading_rad: Some(PI),
        ..SmoothOptions::default()
    };
    let SmoothOutcome::NoPath(n) = plan_smooth(&grid, (2, 4), (15, 4), &opts).unwrap() else {
        panic!("a robot facing a dead end one cell wide found a forward path");
    };
    assert_eq!(n.pose, Some("start"), "{}", n.reason);
    assert!(n.reason.contains("no room"), "{}", n.reason);
    // Facing the open end it drives out.
    let out = SmoothOptions {
        start_heading_rad: Some(0.0),
        ..opts.clone()
    };
    assert!(matches!(
        plan_smooth(&grid, (2, 4), (15, 4), &out).unwrap(),
        SmoothOutcome::Path(_)
    ));
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY, 21.0] {
        let o = SmoothOptions {
            turning_radius_cells: bad,
            ..opts.clone()
        };
        assert!(
            matches!(
                plan_smooth(&grid, (2, 4), (15, 4), &o),
                Err(PlanError::InvalidParameter { .. })
            ),
            "{bad}"
        );
    }
    let o = SmoothOptions {
        goal_heading_rad: Some(f64::NAN),
        ..opts.clone()
    };
    assert!(matches!(
        plan_smooth(&grid, (2, 4), (15, 4), &o),
        Err(PlanError::InvalidParameter { .. })
    ));
    assert!(matches!(
        plan_smooth(&grid, (0, 4), (15, 4), &opts),
        Err(PlanError::EndpointBlocked { .. })
    ));
}

#[test]
fn a_door_one_cell_wide_is_passed_exactly_along_its_line() {
    // A wall across row 10 with a one-cell door at column 12: the robot's square passes
    // only moving straight down column 12.
    let mut grid = OccupancyGrid::new(25, 21, 1.0, [0.0; 2], Occupancy::Free).unwrap();
    for x in 0..25 {
        if x != 12 {
            grid.set(x, 10, Occupancy::Occupied).unwrap();
        }
    }
    for (s, g) in [((4, 3), (20, 17)), ((12, 2), (12, 18)), ((20, 4), (3, 16))] {
        let opts = SmoothOptions {
            turning_radius_cells: 2.0,
            ..SmoothOptions::default()
        };
        let SmoothOutcome::Path(p) = plan_smooth(&grid, s, g, &opts).unwrap() else {
            panic!("no path through the door from {s:?} to {g:?}");
        };
        check_plan(&grid, &p, &opts, s, g);
    }
}

proptest! {
    #[test]
    fn the_exact_piece_test_agrees_with_dense_sampling(
        x in -2.0..2.0f64, y in -2.0..2.0f64, h in -PI..PI,
        kind in 0..3usize, r in 0.3..6.0f64, length in 0.01..6.0f64,
        bx in -4i64..=4, by in -4i64..=4, reverse in proptest::bool::ANY,
    ) {
        use vpmap_plan::smooth::check::piece_enters_square;
        let curvature = [0.0, 1.0 / r, -1.0 / r][kind];
        let seg = Segment {
            start: Pose::new(x, y, h),
            curvature,
            length,
            gear: if reverse { Gear::Reverse } else { Gear::Forward },
        };
        let exact = piece_enters_square(&seg, 0.0, length, (bx, by));
        // Dense samples by the curve's own closed form, 20000 along the piece.
        let depth = (0..=20_000)
            .map(|k| seg.pose_at(length * f64::from(k) / 20_000.0))
            .map(|p| 1.0 - (p.x - bx as f64).abs().max((p.y - by as f64).abs()))
            .fold(f64::NEG_INFINITY, f64::max);
        if depth > 1e-3 {
            prop_assert!(exact.is_some(), "samples reach {depth} inside, the exact test says clear");
        }
        if let Some(p) = exact {
            prop_assert!((p[0] - bx as f64).abs() < 1.0 && (p[1] - by as f64).abs() < 1.0);
            // A point inside means the samples come close to inside too.
            prop_assert!(depth > -1e-3, "exact inside at {p:?}, samples at best {depth}");
        }
    }
}

#[test]
fn the_hybrid_astar_looks_at_its_stop_on_every_expansion() {
    // A passed deadline stops the search at its first expansion. (It was looked at every 4,096
    // expansions, and one expansion takes milliseconds at a large radius: the page's 3 s
    // planner limit overran by seconds. This search finishes within 4,096 expansions, so the
    // old check never looked.)
    use vpmap_plan::smooth::clearance::Field;
    use vpmap_plan::smooth::hybrid::{HybridOptions, HybridQuery, HybridStats, hybrid_astar};
    let grid = OccupancyGrid::new(60, 60, 1.0, [0.0, 0.0], Occupancy::Free).unwrap();
    let field = Field::new(&grid, false);
    let query = HybridQuery {
        start: Pose::new(5.0, 5.0, 0.0),
        start_free: false,
        goal: Pose::new(50.0, 40.0, 0.0),
        goal_free: true,
        radius: 4.0,
        reverse: false,
    };
    let mut budget = vpmap_plan::budget::Budget::default();
    let mut stats = HybridStats::default();
    let found = hybrid_astar(
        &field,
        &query,
        &HybridOptions::default(),
        &budget,
        &mut stats,
    );
    assert!(matches!(found, Ok(Some(_))), "{found:?}");
    assert!(stats.expanded < 4096, "{}", stats.expanded);
    budget.stop = vpmap_plan::budget::Stop::new().with_timeout(std::time::Duration::ZERO);
    let mut stats = HybridStats::default();
    let stopped = hybrid_astar(
        &field,
        &query,
        &HybridOptions::default(),
        &budget,
        &mut stats,
    )
    .map(|_| ());
    assert!(
        matches!(stopped, Err(PlanError::Stopped { .. })),
        "{stopped:?}"
    );
    assert!(stats.expanded <= 1, "{}", stats.expanded);
}

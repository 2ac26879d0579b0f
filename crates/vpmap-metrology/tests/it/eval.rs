//! The map-accuracy metrics of the thesis's section 6.1 on hand-made cases whose answers are
//! worked out by hand (not by the code under test), and the experiment pipeline's guarantees:
//! exact at zero noise, deterministic, honest about refusals.

use vpmap_metrology::eval::{
    MapEvaluation, OBJECT_METRICS, SCENE_METRICS, SETUPS, Trial, TrialOptions, VpEdges,
    evaluate_map, failure_category, long_edge_seed, noise_seed, noisy_scene, object_errors,
    rectangle_size, run_trial, run_trial_with, scale_factor, scene_seed, with_long_edges,
};
use vpmap_metrology::map::{BoxSize, BuildOptions, MapPoint, build_map};
use vpmap_metrology::reconstruct::Method;
use vpmap_metrology::scene::intersect_segments;
use vpmap_metrology::synth::{LongEdgeOptions, SynthOptions, synthesize};

/// The unit square centred on `(cx, cy)`, counter-clockwise.
fn unit_square(cx: f64, cy: f64) -> Vec<MapPoint> {
    vec![
        [cx - 0.5, cy - 0.5],
        [cx + 0.5, cy - 0.5],
        [cx + 0.5, cy + 0.5],
        [cx - 0.5, cy + 0.5],
    ]
}

fn close(a: f64, b: f64, what: &str) {
    assert!((a - b).abs() < 1e-9, "{what}: {a} vs {b}");
}

/// The overlap comes from geo's boolean operations, which snap to a grid of 2^-29 of the
/// shapes' extent: about 1e-8 relative.
fn close_overlap(a: f64, b: f64) {
    assert!((a - b).abs() < 1e-5, "overlap: {a} vs {b}");
}

#[test]
fn a_square_shifted_by_a_known_vector() {
    // Actual centroid (0, 10): d_a = 10. Shift (0.3, 0.4): d_cm = 0.5, so 5 %.
    // d_m = sqrt(0.3^2 + 10.4^2) = sqrt(108.25). The overlap is (1 - 0.3) x (1 - 0.4) = 0.42.
    // Bearings: 90 deg and atan2(10.4, 0.3), i.e. 90 - atan(0.3 / 10.4).
    let actual = unit_square(0.0, 10.0);
    let modelled: Vec<MapPoint> = actual.iter().map(|p| [p[0] + 0.3, p[1] + 0.4]).collect();
    let e = object_errors(&modelled, None, &actual, None).unwrap();
    close(e.centroid_shift_pct, 5.0, "centroid shift");
    close(
        e.centroid_distance_pct,
        (108.25f64.sqrt() - 10.0) / 10.0 * 100.0,
        "centroid distance",
    );
    close_overlap(e.area_overlap_pct, 42.0);
    close(e.area_error_pct, 0.0, "area");
    close(
        e.pose_error_deg,
        -(0.3f64 / 10.4).atan().to_degrees(),
        "pose",
    );
    close(e.skew_error_deg, 0.0, "skew");
    assert_eq!(e.height_error_pct, None);
}

#[test]
fn a_square_rotated_about_its_centroid() {
    // Two concentric unit squares turned by t meet in an octagon whose eight sides all lie
    // r = 1/2 from the centre, with normals turning alternately by t and 90 - t. A polygon
    // circumscribed about a circle has area r^2 * sum(tan(turn / 2)) over its vertices:
    // 4 r^2 (tan(t / 2) + tan(45 - t / 2)) = tan(15) + tan(30) for t = 30 deg.
    let actual = unit_square(2.0, 6.0);
    let t = 30f64.to_radians();
    let modelled: Vec<MapPoint> = actual
        .iter()
        .map(|p| {
            let (x, y) = (p[0] - 2.0, p[1] - 6.0);
            [
                2.0 + x * t.cos() - y * t.sin(),
                6.0 + x * t.sin() + y * t.cos(),
            ]
        })
        .collect();
    let e = object_errors(&modelled, Some(0.5), &actual, Some(0.5)).unwrap();
    close(e.centroid_shift_pct, 0.0, "centroid shift");
    close(e.centroid_distance_pct, 0.0, "centroid distance");
    let expected = (15f64.to_radians().tan() + 30f64.to_radians().tan()) * 100.0;
    close_overlap(e.area_overlap_pct, expected);
    close(e.area_error_pct, 0.0, "area");
    close(e.pose_error_deg, 0.0, "pose");
    close(e.skew_error_deg, 30.0, "skew");
    close(e.height_error_pct.unwrap(), 0.0, "height");
}

#[test]
fn a_square_scaled_about_the_station_point() {
    // Everything 10 % farther out: the centroid (0, 5) moves to (0, 5.5), a shift of 10 % of
    // d_a and a distance error of +10 %; the area grows by 1.1^2 = 1.21; the bearing and the
    // sides' directions stay. The scaled square spans x -1.1..1.1, y 4.4..6.6, so it covers
    // x -1..1, y 4.4..6 of the actual one: 3.2 of 4.
    let actual = vec![[-1.0, 4.0], [1.0, 4.0], [1.0, 6.0], [-1.0, 6.0]];
    let modelled: Vec<MapPoint> = actual.iter().map(|p| [p[0] * 1.1, p[1] * 1.1]).collect();
    let e = object_errors(&modelled, Some(0.77), &actual, Some(0.7)).unwrap();
    close(e.centroid_shift_pct, 10.0, "centroid shift");
    close(e.centroid_distance_pct, 10.0, "centroid distance");
    close_overlap(e.area_overlap_pct, 80.0);
    close(e.area_error_pct, 21.0, "area");
    close(e.pose_error_deg, 0.0, "pose");
    close(e.skew_error_deg, 0.0, "skew");
    close(e.height_error_pct.unwrap(), 10.0, "height");
}

#[test]
fn angles_are_signed_counter_clockwise_and_wrapped() {
    // A centroid at bearing 45 deg modelled at 90 deg: +45. A side at 0 deg modelled at
    // 100 deg: the same line as -80 deg, so -80 in (-90, 90].
    let actual = unit_square(3.0, 3.0);
    let modelled = unit_square(0.0, 3.0 * 2f64.sqrt());
    let e = object_errors(&modelled, None, &actual, None).unwrap();
    close(e.pose_error_deg, 45.0, "pose");
    close(e.centroid_distance_pct, 0.0, "same distance");
    let t = 100f64.to_radians();
    let turned: Vec<MapPoint> = actual
        .iter()
        .map(|p| {
            let (x, y) = (p[0] - 3.0, p[1] - 3.0);
            [
                3.0 + x * t.cos() - y * t.sin(),
                3.0 + x * t.sin() + y * t.cos(),
            ]
        })
        .collect();
    let e = object_errors(&turned, None, &actual, None).unwrap();
    close(e.skew_error_deg, -80.0, "skew");
    // Exactly a quarter turn the other way is +90, the closed end of the range.
    let t = -90f64.to_radians();
    let quarter: Vec<MapPoint> = actual
        .iter()
        .map(|p| {
            let (x, y) = (p[0] - 3.0, p[1] - 3.0);
            [
                3.0 + x * t.cos() - y * t.sin(),
                3.0 + x * t.sin() + y * t.cos(),
            ]
        })
        .collect();
    let e = object_errors(&quarter, None, &actual, None).unwrap();
    assert!(
        (e.skew_error_deg.abs() - 90.0).abs() < 1e-9,
        "{}",
        e.skew_error_deg
    );
}

#[test]
fn degenerate_footprints_are_errors_not_nan() {
    let good = unit_square(0.0, 4.0);
    assert!(object_errors(&good[..2], None, &good, None).is_err());
    let flat = vec![[0.0, 1.0], [1.0, 1.0], [2.0, 1.0]];
    assert!(object_errors(&good, None, &flat, None).is_err());
    let around_origin = unit_square(0.0, 0.0);
    assert!(object_errors(&good, None, &around_origin, None).is_err());
    let bad = vec![[f64::NAN, 1.0], [1.0, 1.0], [1.0, 2.0]];
    assert!(object_errors(&bad, None, &good, None).is_err());
}

#[test]
fn scale_factor_of_a_known_pair() {
    // Eq. 6.1 with L2 = 1.2, B2 = 0.6 actual and L1 = 0.6, B1 = 0.4 modelled: (2 + 1.5) / 2.
    let actual = BoxSize {
        length: 1.2,
        breadth: 0.6,
    };
    let modelled = BoxSize {
        length: 0.6,
        breadth: 0.4,
    };
    close(scale_factor(actual, modelled).unwrap(), 1.75, "S_k");
    let zero = BoxSize {
        length: 0.0,
        breadth: 0.4,
    };
    assert!(scale_factor(actual, zero).is_err());
    // Length is the longer side whatever the corner order.
    let size = rectangle_size(&[[0.0, 0.0], [0.0, 0.5], [2.0, 0.5], [2.0, 0.0]]).unwrap();
    close(size.length, 2.0, "length");
    close(size.breadth, 0.5, "breadth");
}

#[test]
fn a_map_twice_too_large_is_exact_under_s_k_and_100_pct_off_at_true_scale() {
    let (scene, truth) = synthesize(&SynthOptions {
        seed: 11,
        ..SynthOptions::default()
    })
    .unwrap();
    let mut map = build_map(&scene, &BuildOptions::default()).unwrap();
    let exact = evaluate_map(&map, &truth).unwrap();
    close(exact.scale_factor, 1.0, "exact S_k");
    // Double every length of the model: S_k = 1/2 brings the truth to the model's scale.
    for o in &mut map.objects {
        for p in &mut o.footprint {
            *p = [p[0] * 2.0, p[1] * 2.0];
        }
        o.height = o.height.map(|h| h * 2.0);
        o.size = o.size.map(|s| BoxSize {
            length: s.length * 2.0,
            breadth: s.breadth * 2.0,
        });
    }
    map.camera.height *= 2.0;
    let e = evaluate_map(&map, &truth).unwrap();
    assert!((e.scale_factor - 0.5).abs() < 1e-9, "{}", e.scale_factor);
    assert!(e.camera_height_error_pct.abs() < 1e-6);
    assert_eq!(e.objects.len(), truth.objects.len());
    assert!(e.objects[0].reference && !e.objects[1].reference);
    for o in &e.objects {
        let sk = o.sk.values();
        for (name, v) in OBJECT_METRICS.iter().zip(sk) {
            let expected = if *name == "area_overlap_pct" {
                100.0
            } else {
                0.0
            };
            assert!((v - expected).abs() < 1e-6, "{} S_k {name}: {v}", o.name);
        }
        // At the true scale every point is twice as far out: the centroid moves by d_a.
        let t = &o.true_scale;
        assert!((t.centroid_shift_pct - 100.0).abs() < 1e-6, "{t:?}");
        assert!((t.centroid_distance_pct - 100.0).abs() < 1e-6, "{t:?}");
        assert!((t.area_error_pct - 300.0).abs() < 1e-6, "{t:?}");
        assert!((t.height_error_pct.unwrap() - 100.0).abs() < 1e-6, "{t:?}");
        assert!(t.pose_error_deg.abs() < 1e-6 && t.skew_error_deg.abs() < 1e-6);
    }
}

/// Every outcome of a zero-noise trial built, with every metric exact (rounding and geo's
/// 2^-29 snapping in the overlap).
fn assert_exact(setup_name: &str, objects: usize, t: &Trial) {
    for o in &t.outcomes {
        let ev: &MapEvaluation = o
            .result
            .as_ref()
            .unwrap_or_else(|f| panic!("{setup_name} trial {} {}: {f:?}", t.trial, o.method));
        assert_eq!(ev.objects.len(), objects);
        assert!((ev.scale_factor - 1.0).abs() < 1e-9);
        for (name, v) in SCENE_METRICS.iter().zip(ev.scene_values()) {
            assert!(v.abs() < 1e-6, "{setup_name} {name}: {v}");
        }
        for ob in &ev.objects {
            for (variant, values) in [("S_k", ob.sk.values()), ("true", ob.true_scale.values())] {
                for (name, v) in OBJECT_METRICS.iter().zip(values) {
                    let target = if *name == "area_overlap_pct" {
                        100.0
                    } else {
                        0.0
                    };
                    assert!(
                        (v - target).abs() < 1e-6,
                        "{setup_name} trial {} {} {} {variant} {name}: {v}",
                        t.trial,
                        o.method,
                        ob.name
                    );
                }
            }
        }
    }
}

#[test]
fn every_setup_is_exact_without_noise() {
    // At zero noise the only errors are rounding (the vanishing points are still fitted to
    // the exact edges by least squares) and geo's 2^-29 snapping in the overlap.
    for setup in &SETUPS {
        for trial in 0..3 {
            let t = run_trial(
                setup,
                7,
                trial,
                &[0.0],
                &[Method::Sideview, Method::Projective],
            );
            assert_exact(setup.name, setup.objects(), &t);
        }
    }
}

fn long(length_px: f64, per_vanishing_point: usize) -> LongEdgeOptions {
    LongEdgeOptions {
        length_px,
        per_vanishing_point,
        ..LongEdgeOptions::default()
    }
}

#[test]
fn every_setup_is_exact_without_noise_with_long_edges() {
    let options = TrialOptions {
        vp_edges: VpEdges::Long(LongEdgeOptions::default()),
    };
    for setup in &SETUPS {
        for trial in 0..3 {
            let t = run_trial_with(
                setup,
                7,
                trial,
                &[0.0],
                &[Method::Sideview, Method::Projective],
                &options,
            );
            assert_exact(setup.name, setup.objects(), &t);
        }
    }
}

#[test]
fn long_edges_run_through_the_true_vanishing_points_inside_the_image() {
    // Checked against the scene's exact vanishing points, which the synthetic camera
    // computed from the room's directions (not from the edges).
    for setup in &SETUPS {
        for (trial, options) in [
            (0, long(600.0, 3)),
            (1, long(200.0, 5)),
            (2, long(700.0, 2)),
        ] {
            let seed = scene_seed(3, setup, trial);
            let (scene, truth) = synthesize(&setup.synth_options(seed)).unwrap();
            let lined = with_long_edges(&scene, &truth, &options, long_edge_seed(seed)).unwrap();
            assert_eq!(lined.objects, scene.objects);
            assert_eq!(lined.floor, scene.floor);
            let (w, h) = (f64::from(scene.image.width), f64::from(scene.image.height));
            for (exact, fitted) in scene.vanishing_points.iter().zip(&lined.vanishing_points) {
                let v = exact.point.unwrap();
                assert!(fitted.point.is_none());
                assert_eq!(fitted.lines.len(), options.per_vanishing_point);
                for l in &fitted.lines {
                    let (a, b) = ([l[0], l[1]], [l[2], l[3]]);
                    for p in [a, b] {
                        assert!(
                            (0.02 * w - 1e-6..=0.98 * w + 1e-6).contains(&p[0])
                                && (0.02 * h - 1e-6..=0.98 * h + 1e-6).contains(&p[1]),
                            "{} end point {p:?} outside the image less 2 %",
                            setup.name
                        );
                    }
                    let len = (b[0] - a[0]).hypot(b[1] - a[1]);
                    assert!((len - options.length_px).abs() < 1e-6, "length {len}");
                    // The vanishing point lies on the edge's line: the angle at an end point
                    // between the edge and the direction to the vanishing point is rounding.
                    let (ab, av) = ([b[0] - a[0], b[1] - a[1]], [v[0] - a[0], v[1] - a[1]]);
                    let sin = (ab[0] * av[1] - ab[1] * av[0]) / (len * av[0].hypot(av[1]));
                    assert!(sin.abs() < 1e-9, "{} off by sin {sin}", setup.name);
                    // ... and outside the segment, on the line's far side from both end
                    // points (the segment images 3D points in front of the camera).
                    let bv = [v[0] - b[0], v[1] - b[1]];
                    assert!(
                        av[0] * bv[0] + av[1] * bv[1] > 0.0,
                        "{} {l:?} spans {v:?}",
                        setup.name
                    );
                }
                // Spread over the image: no two edges share a middle.
                let mids: Vec<[f64; 2]> = fitted
                    .lines
                    .iter()
                    .map(|l| [f64::midpoint(l[0], l[2]), f64::midpoint(l[1], l[3])])
                    .collect();
                for (i, p) in mids.iter().enumerate() {
                    for q in &mids[i + 1..] {
                        assert!((p[0] - q[0]).hypot(p[1] - q[1]) > 1.0, "{mids:?}");
                    }
                }
                // Least squares gives the vanishing point back.
                let fit = intersect_segments(&fitted.lines, scene.image).unwrap();
                let gap = (fit.x - v[0]).hypot(fit.y - v[1]);
                assert!(
                    gap < 1e-7 * (1.0 + v[0].hypot(v[1])),
                    "{} {gap}",
                    setup.name
                );
            }
        }
    }
}

#[test]
fn long_edges_that_cannot_fit_or_fix_a_point_are_refused() {
    let setup = &SETUPS[6]; // 1280 x 960
    let seed = scene_seed(0, setup, 0);
    let (scene, truth) = synthesize(&setup.synth_options(seed)).unwrap();
    let err = with_long_edges(&scene, &truth, &long(5000.0, 3), 1).unwrap_err();
    assert!(err.to_string().contains("shorter edges"), "{err}");
    assert!(with_long_edges(&scene, &truth, &long(300.0, 1), 1).is_err());
    assert!(with_long_edges(&scene, &truth, &long(f64::NAN, 3), 1).is_err());
    // In a trial, a scene the edges do not fit in is a named failure at every level.
    let t = run_trial_with(
        setup,
        0,
        0,
        &[0.0, 1.0],
        &[Method::Sideview],
        &TrialOptions {
            vp_edges: VpEdges::Long(long(5000.0, 3)),
        },
    );
    assert_eq!(t.outcomes.len(), 2);
    for o in &t.outcomes {
        assert_eq!(o.result.as_ref().unwrap_err().category, "vp_edges");
    }
}

#[test]
fn long_edges_are_placed_once_per_scene_and_objects_get_the_same_noise() {
    let setup = &SETUPS[2];
    let methods = [Method::Sideview, Method::Projective];
    let options = TrialOptions {
        vp_edges: VpEdges::Long(LongEdgeOptions::default()),
    };
    let a = run_trial_with(setup, 3, 5, &[0.0, 1.0, 2.0], &methods, &options);
    assert_eq!(
        a,
        run_trial_with(setup, 3, 5, &[0.0, 1.0, 2.0], &methods, &options)
    );
    // The edges do not depend on the other noise levels.
    let only = run_trial_with(setup, 3, 5, &[1.0], &methods, &options);
    assert_eq!(only.outcomes, a.outcomes[2..4]);
    // Different edges from the objects' own: a different answer under noise.
    let objects = run_trial(setup, 3, 5, &[1.0], &methods);
    assert_ne!(objects.outcomes, only.outcomes);
    // add_noise jitters the objects and floor before any edge, so with the trial's noise seed
    // they move exactly as with the objects' edges; every long-edge end point moves too.
    let seed = scene_seed(3, setup, 5);
    let (scene, truth) = synthesize(&setup.synth_options(seed)).unwrap();
    let lined = with_long_edges(
        &scene,
        &truth,
        &LongEdgeOptions::default(),
        long_edge_seed(seed),
    )
    .unwrap();
    let mut noisy = lined.clone();
    let mut rng =
        <rand_chacha::ChaCha8Rng as rand::SeedableRng>::seed_from_u64(noise_seed(seed, 1.0));
    vpmap_metrology::synth::add_noise(&mut noisy, 1.0, &mut rng);
    let reference = noisy_scene(&scene, 1.0, noise_seed(seed, 1.0));
    assert_eq!(noisy.objects, reference.objects);
    assert_eq!(noisy.floor, reference.floor);
    for (a, b) in lined.vanishing_points.iter().zip(&noisy.vanishing_points) {
        for (l, m) in a.lines.iter().zip(&b.lines) {
            assert!(
                l.iter().zip(m).all(|(x, y)| (x - y).abs() > 0.0),
                "{l:?} -> {m:?}"
            );
        }
    }
}

#[test]
fn long_edges_fix_the_vanishing_points_better_than_the_objects_edges() {
    // The cause of the 2PP gap: at 1 px the focal length from the objects' short edges is
    // off by several times more than from three 600 px room lines. Seeded, so exact.
    let mut focal = [Vec::new(), Vec::new()];
    for setup in SETUPS.iter().filter(|s| s.name.starts_with("2pp")) {
        for trial in 0..10 {
            for (k, vp_edges) in [VpEdges::Objects, VpEdges::Long(LongEdgeOptions::default())]
                .into_iter()
                .enumerate()
            {
                let t = run_trial_with(
                    setup,
                    0,
                    trial,
                    &[1.0],
                    &[Method::Projective],
                    &TrialOptions { vp_edges },
                );
                if let Ok(ev) = &t.outcomes[0].result {
                    focal[k].push(ev.camera.focal_error_pct.abs());
                }
            }
        }
    }
    // Median and 95th percentile by nearest rank (the reports' statistics are vpmap-eval's).
    let [objects, long] = focal.map(|mut v| {
        v.retain(|x| x.is_finite());
        v.sort_by(f64::total_cmp);
        let at = |q: f64| v[((v.len() - 1) as f64 * q).round() as usize];
        (v.len(), at(0.5), at(0.95))
    });
    assert!(objects.0 >= 80 && long.0 >= 80);
    assert!(
        long.1 * 3.0 < objects.1 && long.2 * 3.0 < objects.2,
        "focal error (count, median, p95): objects' edges {objects:?}, long edges {long:?}"
    );
}

#[test]
fn trials_are_deterministic_and_independent_of_the_other_noise_levels() {
    let setup = &SETUPS[10];
    let methods = [Method::Sideview, Method::Projective];
    let a = run_trial(setup, 3, 5, &[0.0, 1.0, 2.0], &methods);
    let b = run_trial(setup, 3, 5, &[0.0, 1.0, 2.0], &methods);
    assert_eq!(a, b);
    let only = run_trial(setup, 3, 5, &[2.0], &methods[1..]);
    assert_eq!(only.outcomes[0], a.outcomes[5]);
    assert_eq!(a.scene_seed, scene_seed(3, setup, 5));
    // Noise changes the answer; another seed changes the scene.
    assert_ne!(a.outcomes[0].result, a.outcomes[2].result);
    assert_ne!(
        run_trial(setup, 4, 5, &[0.0], &methods[..1]).outcomes[0],
        a.outcomes[0]
    );
}

#[test]
fn noise_reaches_every_clicked_point_with_the_requested_spread() {
    let (scene, _) = synthesize(&SETUPS[9].synth_options(1)).unwrap();
    let noisy = noisy_scene(&scene, 2.0, noise_seed(1, 2.0));
    // Every vanishing point is re-fitted from edges.
    for vp in &noisy.vanishing_points {
        assert!(vp.point.is_none() && vp.lines.len() >= 2, "{vp:?}");
    }
    let mut offsets = Vec::new();
    let mut push = |a: [f64; 2], b: [f64; 2]| offsets.extend([b[0] - a[0], b[1] - a[1]]);
    for (o, n) in scene.objects.iter().zip(&noisy.objects) {
        if let (Some(a), Some(b)) = (o.base, n.base) {
            for (p, q) in a.given().zip(b.given()) {
                push(p.1, q.1);
            }
        }
        if let (Some(a), Some(b)) = (&o.footprint, &n.footprint) {
            a.iter().zip(b).for_each(|(p, q)| push(*p, *q));
        }
        let (a, b) = (o.top.unwrap(), n.top.unwrap());
        for (p, q) in [
            (a.corners.near, b.corners.near),
            (a.corners.left, b.corners.left),
            (a.point, b.point),
        ] {
            if let (Some(p), Some(q)) = (p, q) {
                push(p, q);
            }
        }
    }
    scene
        .floor
        .iter()
        .zip(&noisy.floor)
        .for_each(|(p, q)| push(*p, *q));
    assert!(offsets.iter().all(|d| *d != 0.0), "every coordinate moves");
    let n = offsets.len() as f64;
    let rms = (offsets.iter().map(|d| d * d).sum::<f64>() / n).sqrt();
    // About 60 coordinates: the sample deviation is within 30 % of 2 px.
    assert!((rms - 2.0).abs() < 0.6, "rms {rms} over {n} coordinates");
    // Without noise only the vanishing points change form.
    let exact = noisy_scene(&scene, 0.0, 9);
    assert_eq!(exact.objects, scene.objects);
    assert_eq!(exact.floor, scene.floor);
}

#[test]
fn noise_moves_vanishing_point_lines_but_not_computed_points() {
    use rand::SeedableRng;
    use vpmap_metrology::synth::{add_noise, vanishing_points_as_lines};
    let (points, _) = synthesize(&SETUPS[9].synth_options(1)).unwrap();
    let mut lines = points.clone();
    vanishing_points_as_lines(&mut lines);
    let (mut a, mut b) = (points.clone(), lines.clone());
    add_noise(&mut a, 1.5, &mut rand_chacha::ChaCha8Rng::seed_from_u64(4));
    add_noise(&mut b, 1.5, &mut rand_chacha::ChaCha8Rng::seed_from_u64(4));
    // A vanishing point given as a point is computed, not clicked: it stays.
    for (p, q) in points.vanishing_points.iter().zip(&a.vanishing_points) {
        assert!(p.point.is_some());
        assert_eq!(p.point, q.point);
    }
    // Every end point of every line moves.
    let mut moved = 0;
    for (p, q) in lines.vanishing_points.iter().zip(&b.vanishing_points) {
        assert_eq!(p.lines.len(), q.lines.len());
        for (l, m) in p.lines.iter().zip(&q.lines) {
            assert!(
                l.iter().zip(m).all(|(x, y)| (x - y).abs() > 0.0),
                "{l:?} -> {m:?}"
            );
            moved += 1;
        }
    }
    assert!(moved >= 6, "{moved} lines");
    // The clicked corners get the same noise whichever form the vanishing points take.
    assert_eq!(a.objects, b.objects);
    assert_eq!(a.floor, b.floor);
    assert_ne!(a.objects, points.objects);
}

#[test]
fn refusals_are_reported_by_category() {
    // Heavy noise makes the builder refuse some scenes; each refusal carries a category and
    // the builder's message, and every scene is accounted for.
    let setup = &SETUPS[6];
    let mut categories = std::collections::BTreeMap::new();
    let mut total = 0;
    for trial in 0..40 {
        let t = run_trial(setup, 0, trial, &[8.0], &[Method::Sideview]);
        for o in &t.outcomes {
            total += 1;
            if let Err(f) = &o.result {
                assert!(!f.message.is_empty());
                *categories.entry(f.category).or_insert(0) += 1;
            }
        }
    }
    assert_eq!(total, 40);
    assert!(
        !categories.is_empty(),
        "8 px noise on a table-top scene must fail sometimes"
    );
    assert!(!categories.contains_key("scene_draw"), "{categories:?}");
    // A floor corner moved above the horizon is named as such.
    let (mut scene, _) = synthesize(&SETUPS[0].synth_options(2)).unwrap();
    scene.floor[0] = [800.0, 10.0];
    let err = build_map(&scene, &BuildOptions::default()).unwrap_err();
    assert_eq!(failure_category(&err), "point_not_below_horizon");
}

#[test]
fn coverage_is_reported_for_the_fits_objects_under_noise_only() {
    let setup = &SETUPS[9];
    let methods = [Method::Sideview, Method::Projective, Method::Fit];
    let t = run_trial(setup, 1, 0, &[0.0, 1.0], &methods);
    for o in &t.outcomes {
        let ev = o.result.as_ref().unwrap();
        for ob in &ev.objects {
            let Some(c) = ob.coverage else {
                assert!(o.method != Method::Fit || o.sigma_px == 0.0, "{}", ob.name);
                continue;
            };
            assert_eq!((o.method, o.sigma_px), (Method::Fit, 1.0));
            assert!(c.centroid_mahalanobis_sq.is_finite() && c.centroid_mahalanobis_sq >= 0.0);
            let is_box = ob.kind == vpmap_metrology::reconstruct::ObjectKind::Box;
            assert_eq!(c.length_z.is_some(), is_box, "{}", ob.name);
            assert_eq!(c.breadth_z.is_some(), is_box, "{}", ob.name);
            assert!(c.height_z.is_some_and(f64::is_finite), "{}", ob.name);
            assert_eq!(
                c.within()[0],
                Some(c.centroid_mahalanobis_sq <= vpmap_metrology::eval::CHI2_2DOF_95)
            );
        }
    }
    assert!(
        t.outcomes
            .iter()
            .filter_map(|o| o.result.as_ref().ok())
            .flat_map(|ev| &ev.objects)
            .any(|ob| ob.coverage.is_some())
    );
}

#[test]
fn the_fits_95_pct_ellipses_hold_the_truth_about_95_pct_of_the_time_with_long_edges() {
    // Independent vanishing-point clicks (long edges), 1 px: the fit's model holds, so its
    // first-order error bars should be calibrated. 20 scenes of 5 objects per perspective;
    // at a true 95 % the share of 100 objects falls below 85 % with probability under 1e-4.
    let options = TrialOptions {
        vp_edges: VpEdges::Long(LongEdgeOptions::default()),
    };
    for setup in [&SETUPS[3], &SETUPS[9]] {
        let (mut inside, mut total) = (0, 0);
        for trial in 0..20 {
            let t = run_trial_with(setup, 4, trial, &[1.0], &[Method::Fit], &options);
            for ev in t.outcomes.iter().filter_map(|o| o.result.as_ref().ok()) {
                for c in ev.objects.iter().filter_map(|o| o.coverage) {
                    total += 1;
                    inside += usize::from(c.centroid_in_ellipse_95());
                }
            }
        }
        assert!(total >= 95, "{}: {total} objects", setup.name);
        let share = inside as f64 / total as f64;
        assert!(
            (0.85..=1.0).contains(&share) && inside < total,
            "{}: {inside} of {total} inside",
            setup.name
        );
    }
}

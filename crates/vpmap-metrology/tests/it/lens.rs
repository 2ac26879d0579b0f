//! Lens distortion (`lens_distortion`, the division model): clicks taken through a distorting
//! lens and undistorted by the right `k` give the exact map; a wrong `k` moves the boxes; the
//! error bars carry what `k_sd` may move, as often as they say; bad values are refused by
//! name. Checked against the independent synthetic pinhole camera (`vpmap_metrology::synth`).

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use vpmap_metrology::map::{BuildOptions, build_map};
use vpmap_metrology::scene::{DivisionModel, LensDistortion, Scene};
use vpmap_metrology::synth::{SynthOptions, Truth, synthesize};

use crate::max_relative_error;

/// The synthetic scene with every click moved through a lens of division model `k` (the
/// pinhole clicks are where the synthetic camera projects the truth).
fn through_lens(seed: u64, k: f64) -> (Scene, Truth) {
    let (mut scene, truth) = synthesize(&SynthOptions {
        seed,
        ..SynthOptions::default()
    })
    .unwrap();
    let model = DivisionModel::new(k, scene.image, scene.principal_point);
    let distort = |p: &mut [f64; 2]| *p = model.distort(*p).unwrap();
    for o in &mut scene.objects {
        if let Some(b) = &mut o.base {
            b.points_mut().for_each(distort);
        }
        if let Some(t) = &mut o.top {
            t.corners.points_mut().for_each(distort);
            t.point.iter_mut().for_each(distort);
        }
        if let Some(f) = &mut o.footprint {
            f.iter_mut().for_each(distort);
        }
    }
    scene.floor.iter_mut().for_each(distort);
    (scene, truth)
}

#[test]
fn clicks_undistorted_by_the_right_k_give_the_exact_map() {
    for seed in [1, 5, 9] {
        let (mut scene, truth) = through_lens(seed, -0.1);
        scene.lens_distortion = Some(LensDistortion {
            k: -0.1,
            k_sd: None,
        });
        let map = build_map(&scene, &BuildOptions::default()).unwrap();
        let error = max_relative_error(&map, &truth);
        assert!(error < 1e-9, "seed {seed}: relative error {error:e}");
        assert_eq!(map.camera.lens_distortion, scene.lens_distortion);
        // The same clicks taken as a pinhole camera's are measurably off.
        scene.lens_distortion = None;
        let map = build_map(&scene, &BuildOptions::default()).unwrap();
        let error = max_relative_error(&map, &truth);
        assert!(
            error > 1e-3,
            "seed {seed}: ignoring the lens gave only {error:e}"
        );
    }
}

/// The centroid's squared Mahalanobis distance from the truth's, in the map's covariance.
fn centroid_d2(
    o: &vpmap_metrology::map::MapObject,
    t: &vpmap_metrology::synth::TruthObject,
) -> f64 {
    let u = o.uncertainty.as_ref().unwrap();
    let n = t.footprint.len() as f64;
    let c = [
        t.footprint.iter().map(|p| p[0]).sum::<f64>() / n,
        t.footprint.iter().map(|p| p[1]).sum::<f64>() / n,
    ];
    let d = [o.centroid[0] - c[0], o.centroid[1] - c[1]];
    let m = u.centroid_covariance;
    let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    (m[1][1] * d[0] * d[0] - 2.0 * m[0][1] * d[0] * d[1] + m[0][0] * d[1] * d[1]) / det
}

#[test]
fn error_bars_carry_what_k_sd_may_move() {
    // k is off by a normal draw of its stated sd, and every click has Gaussian noise of 1 px
    // (given as the click sigma): the ellipses must hold both, the lens's spread and the
    // clicks', as often as they say (a 95 % ellipse in two dimensions: chi-square 5.991, mean
    // 2), whether the clicks keep the given k or reject it for the one they fit
    // (map/lens_refine.rs).
    const K: f64 = -0.08;
    const K_SD: f64 = 0.02;
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let normal = Normal::new(0.0, 1.0).unwrap();
    let (mut inside, mut total, mut sum_d2, mut refined) = (0usize, 0usize, 0.0, 0usize);
    for trial in 0..60u64 {
        let z: f64 = normal.sample(&mut rng);
        let (mut scene, truth) = through_lens(100 + trial, K + K_SD * z);
        vpmap_metrology::synth::add_noise(&mut scene, 1.0, &mut rng);
        scene.lens_distortion = Some(LensDistortion {
            k: K,
            k_sd: Some(K_SD),
        });
        let map = build_map(
            &scene,
            &BuildOptions {
                click_sigma_px: Some(1.0),
                ..BuildOptions::default()
            },
        )
        .unwrap();
        refined += usize::from(
            map.warnings
                .iter()
                .any(|w| w.starts_with("the clicks disagree with the lens")),
        );
        for (o, t) in map.objects.iter().zip(&truth.objects) {
            let d2 = centroid_d2(o, t);
            sum_d2 += d2;
            total += 1;
            if d2 <= 5.991 {
                inside += 1;
            }
        }
    }
    let share = inside as f64 / total as f64;
    let mean = sum_d2 / total as f64;
    eprintln!(
        "lens coverage: {inside} of {total}, mean d^2 {mean:.3}; {refined} of 60 lenses refined by the clicks"
    );
    assert!(
        (0.90..=0.99).contains(&share),
        "{inside} of {total} centroids inside (mean d^2 {mean:.2})"
    );
    assert!(
        (1.2..=3.2).contains(&mean),
        "mean d^2 {mean:.2} (2 expected)"
    );
}

#[test]
fn clicks_that_see_the_lens_refine_it() {
    // Exact clicks through a lens 2.5 sd from the given one: the clicks reject the given k,
    // the map takes the one they fit, and lands on the truth. Through the given lens itself
    // they leave it as it is, and the map is exact.
    const K: f64 = -0.08;
    const K_SD: f64 = 0.02;
    for seed in [3, 8] {
        let k_true = K + 2.5 * K_SD;
        let (mut scene, truth) = through_lens(seed, k_true);
        scene.lens_distortion = Some(LensDistortion {
            k: K,
            k_sd: Some(K_SD),
        });
        let map = build_map(&scene, &BuildOptions::default()).unwrap();
        assert!(
            map.warnings[0].starts_with(
                "the clicks disagree with the lens distortion the scene gives, k = -0.08 +- 0.02"
            ),
            "seed {seed}: {:?}",
            map.warnings
        );
        // The true k inside the refined lens's 95 % interval, narrower than the given one.
        let used = map.camera.lens_distortion.unwrap();
        let sd = used.k_sd.unwrap();
        assert!(
            sd < K_SD && (used.k - k_true).abs() <= 1.96 * sd,
            "seed {seed}: k {} +- {sd} against {k_true}",
            used.k
        );
        // Far nearer the truth than the given lens put it.
        let error = max_relative_error(&map, &truth);
        let mut kept = scene.clone();
        kept.lens_distortion = Some(LensDistortion { k: K, k_sd: None });
        let before =
            max_relative_error(&build_map(&kept, &BuildOptions::default()).unwrap(), &truth);
        assert!(
            error < 0.2 * before,
            "seed {seed}: relative error {error:e}, {before:e} with the given k"
        );
        for (o, t) in map.objects.iter().zip(&truth.objects) {
            assert!(centroid_d2(o, t) <= 5.991, "seed {seed}: {}", o.name);
        }
        // The given lens right: kept, the map exact.
        let (mut scene, truth) = through_lens(seed, K);
        scene.lens_distortion = Some(LensDistortion {
            k: K,
            k_sd: Some(K_SD),
        });
        let map = build_map(&scene, &BuildOptions::default()).unwrap();
        assert_eq!(map.camera.lens_distortion, scene.lens_distortion);
        let error = max_relative_error(&map, &truth);
        assert!(error < 1e-9, "seed {seed}: relative error {error:e}");
    }
}

#[test]
fn a_lens_that_folds_the_image_or_an_absurd_k_is_refused_by_name() {
    let (scene, _) = through_lens(2, 0.0);
    for (k, k_sd, needle) in [
        (0.95, None, "folds the image"),
        (-0.97, None, "towards infinity"),
        (f64::NAN, None, "lens_distortion.k"),
        (3.0, None, "lens_distortion.k"),
        (-0.05, Some(-0.01), "lens_distortion.k_sd"),
    ] {
        let mut s = scene.clone();
        s.lens_distortion = Some(LensDistortion { k, k_sd });
        let err = build_map(&s, &BuildOptions::default())
            .unwrap_err()
            .to_string();
        assert!(err.contains(needle), "k {k}: {err}");
    }
    let text = scene.to_json_string().replace(
        "\"version\": 1,",
        "\"version\": 1, \"lens_distortion\": {\"k\": -0.1, \"ksd\": 0.01},",
    );
    let err = Scene::from_json_str(&text).unwrap_err().to_string();
    assert!(err.contains("ksd"), "{err}");
}

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

#[test]
fn error_bars_carry_what_k_sd_may_move() {
    // k is off by a normal draw of its stated sd; the clicks are otherwise exact and the click
    // noise is given as the smallest there is, so k's spread is what the ellipses must hold.
    // That spread is rank one (one parameter moves every centroid along a line), so a
    // centroid's squared Mahalanobis distance is z^2 of the draw: chi-square with one degree
    // of freedom, inside 3.84 for 95 % of draws.
    const K: f64 = -0.08;
    const K_SD: f64 = 0.02;
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let normal = Normal::new(0.0, 1.0).unwrap();
    let (mut inside, mut total, mut sum_d2) = (0usize, 0usize, 0.0);
    for trial in 0..60u64 {
        let z: f64 = normal.sample(&mut rng);
        let (mut scene, truth) = through_lens(100 + trial, K + K_SD * z);
        scene.lens_distortion = Some(LensDistortion {
            k: K,
            k_sd: Some(K_SD),
        });
        let map = build_map(
            &scene,
            &BuildOptions {
                click_sigma_px: Some(vpmap_metrology::fit::MIN_CLICK_SIGMA_PX),
                ..BuildOptions::default()
            },
        )
        .unwrap();
        for (o, t) in map.objects.iter().zip(&truth.objects) {
            let u = o.uncertainty.as_ref().unwrap();
            let n = t.footprint.len() as f64;
            let c = [
                t.footprint.iter().map(|p| p[0]).sum::<f64>() / n,
                t.footprint.iter().map(|p| p[1]).sum::<f64>() / n,
            ];
            let d = [o.centroid[0] - c[0], o.centroid[1] - c[1]];
            let m = u.centroid_covariance;
            let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
            let d2 =
                (m[1][1] * d[0] * d[0] - 2.0 * m[0][1] * d[0] * d[1] + m[0][0] * d[1] * d[1]) / det;
            sum_d2 += d2;
            total += 1;
            if d2 <= 3.841 {
                inside += 1;
            }
        }
    }
    let share = inside as f64 / total as f64;
    eprintln!(
        "lens coverage: {inside} of {total}, mean d^2 {:.3}",
        sum_d2 / total as f64
    );
    let mean = sum_d2 / total as f64;
    assert!(
        (0.90..=0.99).contains(&share),
        "{inside} of {total} centroids inside (mean d^2 {mean:.2})"
    );
    assert!(
        (0.6..=1.6).contains(&mean),
        "mean d^2 {mean:.2} (1 expected)"
    );
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

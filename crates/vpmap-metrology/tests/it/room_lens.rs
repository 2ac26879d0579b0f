//! A room's error bars carry each photo's lens `k_sd`: rooms drawn by the synthetic room
//! (`vpmap_metrology::synth::synthesize_room`, independent pinhole cameras), every photo's
//! clicks and vanishing-point segments moved through a division-model lens whose `k` is drawn
//! from the stated `N(k, k_sd^2)` and then given click noise, the room built with the stated
//! `k` and `k_sd`: the true centres fall inside the map's 95 % ellipses as often as they say.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use vpmap_metrology::map::{BuildOptions, FloorMap, build_map};
use vpmap_metrology::scene::{DivisionModel, LensDistortion, Scene};
use vpmap_metrology::synth::{RoomSynthOptions, RoomTruth, VanishingPointForm, synthesize_room};

/// The 95 % point of the chi-square distribution with two degrees of freedom: the map's
/// ellipse.
const CHI2_2DOF_95: f64 = 5.991;

/// Photo `p`'s clicks, taken by a pinhole camera, each moved by Gaussian noise of `noise_px`
/// and then as a lens of division model `k` shows them. The noise is drawn in the pinhole
/// camera's pixels because a build's `click_sigma_px` is in those (the clicks undistorted).
fn through_lens(p: &mut Scene, k: f64, noise_px: f64, rng: &mut ChaCha8Rng) {
    let model = DivisionModel::new(k, p.image, p.principal_point);
    let normal = Normal::new(0.0, noise_px).unwrap();
    let mut moved = |q: &mut [f64; 2]| {
        let noisy = [q[0] + normal.sample(rng), q[1] + normal.sample(rng)];
        *q = model.distort(noisy).unwrap();
    };
    for o in &mut p.objects {
        if let Some(b) = &mut o.base {
            b.points_mut().for_each(&mut moved);
        }
        if let Some(t) = &mut o.top {
            t.corners.points_mut().for_each(&mut moved);
            t.point.iter_mut().for_each(&mut moved);
        }
        if let Some(f) = &mut o.footprint {
            f.iter_mut().for_each(&mut moved);
        }
    }
    p.floor.iter_mut().for_each(&mut moved);
    for vp in &mut p.vanishing_points {
        for l in &mut vp.lines {
            let (mut a, mut b) = ([l[0], l[1]], [l[2], l[3]]);
            moved(&mut a);
            moved(&mut b);
            *l = [a[0], a[1], b[0], b[1]];
        }
    }
}

/// Each object's centroid's squared Mahalanobis distance from the truth's under the map's
/// covariance.
fn distances(map: &FloorMap, truth: &RoomTruth) -> Vec<f64> {
    truth
        .objects
        .iter()
        .map(|t| {
            let o = map.objects.iter().find(|o| o.name == t.name).unwrap();
            let n = t.footprint.len() as f64;
            let c = [
                t.footprint.iter().map(|p| p[0]).sum::<f64>() / n,
                t.footprint.iter().map(|p| p[1]).sum::<f64>() / n,
            ];
            let d = [o.centroid[0] - c[0], o.centroid[1] - c[1]];
            let m = o.uncertainty.as_ref().unwrap().centroid_covariance;
            let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
            (m[1][1] * d[0] * d[0] - 2.0 * m[0][1] * d[0] * d[1] + m[0][0] * d[1] * d[1]) / det
        })
        .collect()
}

/// How many of `d2` lie inside the 95 % ellipse, and their mean.
fn inside(d2: &[f64]) -> (usize, f64) {
    (
        d2.iter().filter(|d| **d <= CHI2_2DOF_95).count(),
        d2.iter().sum::<f64>() / d2.len() as f64,
    )
}

#[test]
fn a_room_s_error_bars_carry_what_each_photo_s_k_sd_may_move() {
    // A phone's barrel lens, known to +-0.02 (as `vpmap detect` estimates it), and 0.5 px
    // clicks (the noise given to the build as it is). Each photo's k is its own draw. The
    // lens's part is most of the error: with k taken as exact the ellipses hold about half.
    // 100 rooms (600 centroids, correlated within a room): the share is known to about 1 %.
    const K: f64 = -0.08;
    const K_SD: f64 = 0.02;
    const NOISE_PX: f64 = 0.5;
    const TRIALS: u64 = 100;
    let mut rng = ChaCha8Rng::seed_from_u64(39);
    let normal = Normal::new(0.0, 1.0).unwrap();
    let options = BuildOptions {
        click_sigma_px: Some(NOISE_PX),
        ..BuildOptions::default()
    };
    let (mut with, mut without, mut refined) = (Vec::new(), Vec::new(), 0usize);
    for trial in 0..TRIALS {
        let (mut scene, truth) = synthesize_room(&RoomSynthOptions {
            seed: 500 + trial,
            photos: 3,
            boxes: 6,
            vanishing_points: VanishingPointForm::Lines,
            ..RoomSynthOptions::default()
        })
        .unwrap();
        for n in 0..scene.photo_count() {
            let z: f64 = normal.sample(&mut rng);
            let p = if n == 0 {
                &mut scene
            } else {
                &mut scene.other_photos[n - 1]
            };
            through_lens(p, K + K_SD * z, NOISE_PX, &mut rng);
            p.lens_distortion = Some(LensDistortion {
                k: K,
                k_sd: Some(K_SD),
            });
        }
        let map = build_map(&scene, &options).unwrap();
        assert!(
            !map.warnings
                .iter()
                .any(|w| w.contains("not in the error bars")),
            "trial {trial}: {:?}",
            map.warnings
        );
        with.extend(distances(&map, &truth));
        // Photos whose clicks rejected the given lens for the one they fit.
        refined += map
            .warnings
            .iter()
            .filter(|w| w.starts_with("the clicks disagree with photo"))
            .count();
        // The same clicks with k taken as exact: the error bars of the fit alone.
        let exact = Some(LensDistortion { k: K, k_sd: None });
        scene.lens_distortion = exact;
        for p in &mut scene.other_photos {
            p.lens_distortion = exact;
        }
        let map = build_map(&scene, &options).unwrap();
        without.extend(distances(&map, &truth));
    }
    let (hit, mean) = inside(&with);
    let (hit_before, mean_before) = inside(&without);
    let share = hit as f64 / with.len() as f64;
    let share_before = hit_before as f64 / without.len() as f64;
    eprintln!(
        "room lens coverage: with k_sd {hit} of {} inside the 95 % ellipses (mean d^2 {mean:.2}; {refined} of {} photos' lenses refined by their clicks); k taken as exact {hit_before} of {} (mean d^2 {mean_before:.2})",
        with.len(),
        3 * TRIALS,
        without.len()
    );
    assert!(
        (0.92..=0.98).contains(&share),
        "{hit} of {} inside with k_sd (mean d^2 {mean:.2})",
        with.len()
    );
    assert!(
        share_before < 0.92,
        "without k_sd {hit_before} of {} were inside already: the test cannot tell",
        without.len()
    );
}

#[test]
fn a_room_photo_whose_clicks_see_another_lens_refines_it() {
    // Exact clicks; photo 2 taken through a lens 3 sd from the one the room file gives it:
    // its clicks reject the given k, the room is fitted again with the one they fit, and its
    // boxes land nearer the truth (inside their ellipses). The other photos' lenses are right
    // and stay as given.
    const K: f64 = -0.08;
    const K_SD: f64 = 0.02;
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let (mut scene, truth) = synthesize_room(&RoomSynthOptions {
        seed: 77,
        photos: 3,
        boxes: 6,
        vanishing_points: VanishingPointForm::Lines,
        ..RoomSynthOptions::default()
    })
    .unwrap();
    for n in 0..scene.photo_count() {
        let p = if n == 0 {
            &mut scene
        } else {
            &mut scene.other_photos[n - 1]
        };
        let k = if n == 1 { K + 3.0 * K_SD } else { K };
        through_lens(p, k, 0.0, &mut rng);
        p.lens_distortion = Some(LensDistortion {
            k: K,
            k_sd: Some(K_SD),
        });
    }
    let map = build_map(&scene, &BuildOptions::default()).unwrap();
    assert!(
        map.warnings[0]
            .starts_with("the clicks disagree with photo 2's lens distortion the scene gives"),
        "{:?}",
        map.warnings
    );
    let used = map.cameras[1].lens_distortion.unwrap();
    let sd = used.k_sd.unwrap();
    assert!(
        sd < K_SD && (used.k - (K + 3.0 * K_SD)).abs() <= 1.96 * sd,
        "photo 2's lens {used:?}"
    );
    for c in [&map.cameras[0], &map.cameras[2]] {
        assert_eq!(
            c.lens_distortion,
            Some(LensDistortion {
                k: K,
                k_sd: Some(K_SD)
            })
        );
    }
    let d2 = distances(&map, &truth);
    assert!(d2.iter().all(|d| *d <= 5.991), "{d2:?}");
}

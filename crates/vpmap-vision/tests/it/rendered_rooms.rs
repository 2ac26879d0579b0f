//! Issue 37's rendered rooms: photos with what real ones have (clutter near the corners,
//! occluding bars, blur growing off-centre, JPEG at 85 and a phone's barrel distortion,
//! `PhotoOptions::cluttered`), the vanishing points and the lens from `detect`, the clicks 1 px
//! off the true corners and snapped. The map's 95 % ellipses must hold the true centres for
//! 92-98 % of the objects, and the median position error be at most 1.5 times the error of the
//! same snapped clicks with the true vanishing points and lens. The truth is the independent
//! pinhole camera of `vpmap_metrology::synth`, moved through the renderer's lens.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use vpmap_metrology::map::{BuildOptions, FloorMap, build_map};
use vpmap_metrology::scene::{ImageSize, LensDistortion, Scene};
use vpmap_metrology::synth::{SynthOptions, synthesize};
use vpmap_vision::clicks::{scene_clicks, set_scene_click};
use vpmap_vision::scene::detected_scene;
use vpmap_vision::snap::scene::{snap_scene, write_snapped};
use vpmap_vision::snap::{SnapImage, SnapOptions};
use vpmap_vision::synthetic::photo::{PhotoOptions, render_photo};
use vpmap_vision::{DetectOptions, detect};

/// The chi-square quantile with 2 degrees of freedom at 95 %.
const CHI2_2DOF_95: f64 = 5.991_464_547_107_979;

/// The click noise before snapping, pixels.
const CLICK_SIGMA_PX: f64 = 1.0;

/// Per object: error with the detected vanishing points and lens (m), its Mahalanobis
/// distance squared, error with the true ones (m). `None` when detection fails.
fn room(seed: u64) -> Option<Vec<(f64, f64, f64)>> {
    let (scene, truth) = synthesize(&SynthOptions {
        seed,
        image: ImageSize {
            width: 800,
            height: 600,
        },
        focal_px: 620.0,
        pitch_deg: 12.0 + 4.0 * (seed % 4) as f64,
        ..SynthOptions::default()
    })
    .ok()?;
    let rendered = render_photo(&scene, &truth, &PhotoOptions::cluttered(seed)).unwrap();
    // The clicks: the true corners in the photo (through its lens), 1 px off.
    let mut rng = ChaCha8Rng::seed_from_u64(seed + 500);
    let noise = Normal::new(0.0, CLICK_SIGMA_PX).unwrap();
    let mut clicked = scene.clone();
    for (click, corner) in scene_clicks(&scene).iter().zip(&rendered.corners) {
        let p = [
            (corner.point_px[0] + noise.sample(&mut rng)).clamp(0.0, 800.0),
            (corner.point_px[1] + noise.sample(&mut rng)).clamp(0.0, 600.0),
        ];
        assert!(set_scene_click(&mut clicked, click.place, p));
    }
    let image = SnapImage::new(&rendered.image);
    // Detected: the scene detect writes, with the clicks added and snapped.
    let det = detect(&rendered.image, &DetectOptions::default()).ok()?;
    let written = detected_scene(&det).ok()?;
    if let Some(l) = &det.lens {
        eprintln!(
            "room {seed}: lens k {:.4} +- {:.4} (1 sd), applied {:.4}; true {}",
            l.estimated_k,
            l.k_sd,
            l.k(),
            rendered.distortion_k
        );
    }
    let mut detected = Scene::from_json_str(&written.json).unwrap();
    detected.objects.clone_from(&clicked.objects);
    detected.floor.clone_from(&clicked.floor);
    detected.scale.clone_from(&clicked.scale);
    let with_detected = snapped(&image, &detected);
    // The reference: the true vanishing points and lens, the same clicks snapped.
    let mut reference = clicked.clone();
    reference.lens_distortion = Some(LensDistortion {
        k: rendered.distortion_k,
        k_sd: None,
    });
    let with_truth = snapped(&image, &reference);
    let a = build_map(&with_detected, &BuildOptions::default()).ok()?;
    let b = build_map(&with_truth, &BuildOptions::default()).ok()?;
    Some(
        truth
            .objects
            .iter()
            .filter_map(|t| {
                let (ea, d2) = error(&a, t)?;
                let (eb, _) = error(&b, t)?;
                Some((ea, d2, eb))
            })
            .collect(),
    )
}

/// `scene` with its clicks snapped on `image` (a click that stays keeps the click noise).
fn snapped(image: &SnapImage, scene: &Scene) -> Scene {
    let snaps = snap_scene(image, scene, &SnapOptions::for_click_sigma(CLICK_SIGMA_PX)).unwrap();
    let mut value = serde_json::to_value(scene).unwrap();
    write_snapped(&mut value, &snaps, Some(CLICK_SIGMA_PX)).unwrap();
    Scene::from_json_str(&value.to_string()).unwrap()
}

/// The centroid's error (m) and Mahalanobis distance squared of object `t` in `map`.
fn error(map: &FloorMap, t: &vpmap_metrology::synth::TruthObject) -> Option<(f64, f64)> {
    let o = map.objects.iter().find(|o| o.name == t.name)?;
    let n = t.footprint.len() as f64;
    let c = [
        t.footprint.iter().map(|p| p[0]).sum::<f64>() / n,
        t.footprint.iter().map(|p| p[1]).sum::<f64>() / n,
    ];
    let d = [o.centroid[0] - c[0], o.centroid[1] - c[1]];
    let m = o.uncertainty.as_ref()?.centroid_covariance;
    let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    let d2 = (m[1][1] * d[0] * d[0] - 2.0 * m[0][1] * d[0] * d[1] + m[0][0] * d[1] * d[1]) / det;
    Some((d[0].hypot(d[1]), d2))
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

#[test]
#[ignore = "issue 37's rendered-room target, not met yet (docs/detection.md): run with -- --ignored rendered_rooms"]
fn rendered_rooms_with_clutter_and_a_lens_keep_their_error_bars_honest() {
    let mut rows = Vec::new();
    let mut refused = 0;
    for seed in 0..16 {
        match room(seed) {
            Some(r) => rows.extend(r),
            None => refused += 1,
        }
    }
    let n = rows.len();
    let inside = rows.iter().filter(|r| r.1 <= CHI2_2DOF_95).count();
    let detected = median(rows.iter().map(|r| r.0).collect());
    let true_vps = median(rows.iter().map(|r| r.2).collect());
    eprintln!(
        "rendered rooms: {n} objects, {refused} rooms refused; inside the 95 % ellipse {inside} of {n}; median error {:.1} cm detected, {:.1} cm with the true vanishing points and lens (ratio {:.2})",
        100.0 * detected,
        100.0 * true_vps,
        detected / true_vps
    );
    assert!(refused <= 1, "{refused} rooms refused");
    assert!(n >= 40, "{n} objects");
    let share = inside as f64 / n as f64;
    assert!((0.92..=0.98).contains(&share), "{inside} of {n} inside");
    assert!(
        detected <= 1.5 * true_vps,
        "median {detected} against {true_vps}"
    );
}

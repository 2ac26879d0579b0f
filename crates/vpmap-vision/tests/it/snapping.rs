//! Snapping clicks on rendered photos with known corners.
//!
//! The photos come from `vpmap_vision::synthetic::photo` over scenes of
//! `vpmap_metrology::synth` (an independent pinhole camera), whose exact clicks are the truth.

use image::{DynamicImage, GrayImage, Luma};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use vpmap_metrology::scene::{ImageSize, Scene};
use vpmap_metrology::synth::{SynthOptions, Truth, synthesize};
use vpmap_vision::VisionError;
use vpmap_vision::snap::scene::{scene_vanishing_points, snap_scene, write_snapped};
use vpmap_vision::snap::{KeptReason, SnapImage, SnapOptions, SnapOutcome, snap_click};
use vpmap_vision::synthetic::photo::{CornerKind, PhotoOptions, RenderedPhoto, render_photo};

fn scene(seed: u64, pitch_deg: f64) -> (Scene, Truth) {
    synthesize(&SynthOptions {
        seed,
        image: ImageSize {
            width: 800,
            height: 600,
        },
        focal_px: 560.0,
        pitch_deg,
        ..SynthOptions::default()
    })
    .unwrap()
}

fn photo(scene: &Scene, truth: &Truth, seed: u64) -> RenderedPhoto {
    render_photo(
        scene,
        truth,
        &PhotoOptions {
            seed,
            ..PhotoOptions::default()
        },
    )
    .unwrap()
}

/// Per visible box corner: the error of the snapped point (None when kept) and the squared
/// Mahalanobis distance of that error under the reported covariance.
fn box_corner_errors(seeds: std::ops::Range<u64>, sigma_px: f64) -> Vec<Option<(f64, f64)>> {
    let mut out = Vec::new();
    let normal = Normal::new(0.0, sigma_px).unwrap();
    for seed in seeds {
        let (scene, truth) = scene(seed, 10.0 + 5.0 * (seed % 4) as f64);
        let rendered = photo(&scene, &truth, seed);
        let image = SnapImage::new(&rendered.image);
        let vps = scene_vanishing_points(&scene).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(seed + 1000);
        let opts = SnapOptions::for_click_sigma(sigma_px);
        for c in rendered
            .corners
            .iter()
            .filter(|c| c.visible && c.kind == CornerKind::BoxCorner)
        {
            let click = [
                c.point_px[0] + normal.sample(&mut rng),
                c.point_px[1] + normal.sample(&mut rng),
            ];
            if !(0.0..800.0).contains(&click[0]) || !(0.0..600.0).contains(&click[1]) {
                continue;
            }
            // A corner beyond the search radius (2.45 sigma: 5 % of clicks) is out of reach
            // by design: the share snapped counts the corners within it.
            if (click[0] - c.point_px[0]).hypot(click[1] - c.point_px[1]) > opts.search_radius_px {
                continue;
            }
            let snap = snap_click(&image, &vps, click, &opts).unwrap();
            assert!(snap.moved_px() <= opts.search_radius_px + 1e-9);
            out.push(snap.covariance_px2.map(|cov| {
                let e = [
                    snap.point_px[0] - c.point_px[0],
                    snap.point_px[1] - c.point_px[1],
                ];
                let det = cov[0][0] * cov[1][1] - cov[0][1] * cov[1][0];
                let m = (e[0] * e[0] * cov[1][1] - 2.0 * e[0] * e[1] * cov[0][1]
                    + e[1] * e[1] * cov[0][0])
                    / det;
                (e[0].hypot(e[1]), m)
            }));
        }
    }
    out
}

fn quantile(values: &mut [f64], q: f64) -> f64 {
    values.sort_by(f64::total_cmp);
    let k = ((values.len() - 1) as f64 * q).round() as usize;
    values[k]
}

#[test]
fn visible_box_corners_snap_to_a_fraction_of_a_pixel() {
    let results = box_corner_errors(0..3, 2.0);
    let snapped: Vec<(f64, f64)> = results.iter().flatten().copied().collect();
    let share = snapped.len() as f64 / results.len() as f64;
    let mut errors: Vec<f64> = snapped.iter().map(|s| s.0).collect();
    let median = quantile(&mut errors, 0.5);
    let p95 = quantile(&mut errors, 0.95);
    assert!(results.len() >= 20, "{} corners", results.len());
    assert!(share >= 0.8, "snapped {share}");
    assert!(median <= 0.3, "median error {median} px");
    assert!(p95 <= 1.0, "p95 error {p95} px");
}

#[test]
fn the_covariance_is_roughly_calibrated() {
    // Squared Mahalanobis distances of the snapped errors: chi-squared with 2 degrees of
    // freedom when calibrated (median 1.39, 95 % below 5.99). The covariance floor (0.4 px)
    // is set for the tail (a corner taken a pixel off on a neighbouring edge), so the core
    // is wide: the median lies well below 1.39, the share inside the 95 % ellipse at or above
    // 95 % (on these 800 x 600 photos, all of them).
    let results = box_corner_errors(10..14, 2.0);
    let mut m: Vec<f64> = results.iter().flatten().map(|s| s.1).collect();
    assert!(m.len() >= 30, "{} snapped", m.len());
    let median = quantile(&mut m, 0.5);
    let inside = m.iter().filter(|&&v| v <= 5.991).count() as f64 / m.len() as f64;
    assert!((0.1..=2.0).contains(&median), "median chi2 {median}");
    // Too narrow: fewer than 90 % inside; too wide: the median below 0.1 (it bounds the
    // width).
    assert!(inside >= 0.9, "inside 95 % ellipse: {inside}");
}

#[test]
fn points_that_are_no_corner_stay() {
    let mut kept = 0;
    let mut total = 0;
    for seed in 0..3 {
        let (scene, truth) = scene(seed, 15.0);
        let rendered = photo(&scene, &truth, seed);
        let image = SnapImage::new(&rendered.image);
        let vps = scene_vanishing_points(&scene).unwrap();
        for c in rendered
            .corners
            .iter()
            .filter(|c| c.kind == CornerKind::NoCorner)
        {
            total += 1;
            let s = snap_click(&image, &vps, c.point_px, &SnapOptions::default()).unwrap();
            if !s.snapped() {
                kept += 1;
                assert_eq!(s.point_px, c.point_px);
            }
        }
    }
    assert!(total >= 3);
    assert!(
        f64::from(kept) >= 0.8 * f64::from(total),
        "{kept} of {total} stayed"
    );
}

/// A textured flat wall with a dark box whose corner is 30 px from the click.
fn wall_with_box() -> SnapImage {
    let img = GrayImage::from_fn(200, 160, |x, y| {
        let (fx, fy) = (f64::from(x), f64::from(y));
        let texture =
            6.0 * ((fx * 0.31).sin() * (fy * 0.23).cos()) + 1.5 * (fx * 0.9 + fy * 0.4).sin();
        let base = if x >= 130 && y >= 100 { 60.0 } else { 180.0 };
        Luma([(base + texture).round() as u8])
    });
    SnapImage::new(&DynamicImage::ImageLuma8(img))
}

#[test]
fn a_click_on_a_flat_wall_stays_and_says_so() {
    let image = wall_with_box();
    let vps = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    let click = [100.0, 75.0];
    let s = snap_click(&image, &vps, click, &SnapOptions::default()).unwrap();
    assert_eq!(s.point_px, click);
    assert_eq!(s.outcome, SnapOutcome::Kept(KeptReason::NoEdge));
    assert!(s.covariance_px2.is_none());
    // Even a wide search radius does not jump 40 px to the box corner.
    let wide = SnapOptions {
        search_radius_px: 12.0,
        ..SnapOptions::default()
    };
    let s = snap_click(&image, &vps, click, &wide).unwrap();
    assert_eq!(s.point_px, click);
    // Near the corner it snaps.
    let s = snap_click(&image, &vps, [127.0, 103.0], &SnapOptions::default()).unwrap();
    assert!(s.snapped(), "{:?}", s.outcome);
    assert!(
        (s.point_px[0] - 130.0).abs() < 0.4 && (s.point_px[1] - 100.0).abs() < 0.4,
        "{s:?}"
    );
    // On the edge but far from the corner: one direction only.
    let s = snap_click(&image, &vps, [160.0, 101.0], &SnapOptions::default()).unwrap();
    assert!(
        matches!(s.outcome, SnapOutcome::Kept(KeptReason::OneDirection(_))),
        "{:?}",
        s.outcome
    );
    assert!(s.to_string_note().contains("one way"));
}

trait Note {
    fn to_string_note(&self) -> String;
}

impl Note for vpmap_vision::snap::Snap {
    fn to_string_note(&self) -> String {
        match self.outcome {
            SnapOutcome::Kept(r) => r.to_string(),
            SnapOutcome::Snapped => String::new(),
        }
    }
}

#[test]
fn a_click_outside_the_photo_is_refused_naming_it() {
    let image = wall_with_box();
    let vps = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    let e = snap_click(&image, &vps, [250.5, 10.0], &SnapOptions::default()).unwrap_err();
    assert!(matches!(e, VisionError::ClickOutsidePhoto { .. }));
    let text = e.to_string();
    assert!(
        text.contains("250.5") && text.contains("200 x 160"),
        "{text}"
    );
    assert!(snap_click(&image, &vps, [f64::NAN, 1.0], &SnapOptions::default()).is_err());
}

#[test]
fn a_scene_for_another_photo_or_with_a_click_outside_is_refused() {
    let (mut scene, truth) = scene(1, 15.0);
    let rendered = photo(&scene, &truth, 1);
    let image = SnapImage::new(&rendered.image);
    let mut other = scene.clone();
    other.image.width = 1024;
    let e = snap_scene(&image, &other, &SnapOptions::default()).unwrap_err();
    assert!(e.to_string().contains("1024 x 600"), "{e}");
    if let Some(b) = scene.objects[0].base.as_mut() {
        b.near = Some([-3.0, 200.0]);
    }
    let e = snap_scene(&image, &scene, &SnapOptions::default()).unwrap_err();
    assert!(e.to_string().contains("objects[0].base.near"), "{e}");
    assert!(e.to_string().contains("-3"), "{e}");
}

#[test]
fn a_snapped_scene_keeps_its_other_fields_and_records_covariances() {
    let (scene, truth) = scene(2, 20.0);
    let rendered = photo(&scene, &truth, 2);
    let image = SnapImage::new(&rendered.image);
    let mut noisy = scene.clone();
    vpmap_metrology::synth::add_noise(&mut noisy, 1.5, &mut ChaCha8Rng::seed_from_u64(5));
    let snapped = snap_scene(&image, &noisy, &SnapOptions::default()).unwrap();
    let mut value = serde_json::to_value(&noisy).unwrap();
    value["my_note"] = serde_json::json!("kept");
    write_snapped(&mut value, &snapped, None).unwrap();
    assert_eq!(value["my_note"], "kept");
    let table = value["click_covariances_px2"].as_object().unwrap();
    let moved = snapped.iter().filter(|s| s.snap.snapped()).count();
    assert_eq!(table.len(), moved);
    assert!(moved >= 10, "{moved} snapped");
    for s in snapped.iter().filter(|s| s.snap.snapped()) {
        let cov = &table[&s.place.field()];
        assert!(cov[0][0].as_f64().unwrap() > 0.0 && cov[0][1] == cov[1][0]);
    }
    // The scene still reads, with the snapped points and their covariances.
    let back: Scene = serde_json::from_value(value).unwrap();
    assert_eq!(back.objects.len(), scene.objects.len());
    assert_eq!(back.click_covariances_px2.len(), moved);
    back.validate().unwrap();
    // With the click noise, every object click that stayed gets its covariance too.
    let mut value = serde_json::to_value(&noisy).unwrap();
    write_snapped(&mut value, &snapped, Some(1.5)).unwrap();
    let table = value["click_covariances_px2"].as_object().unwrap();
    let objects = snapped
        .iter()
        .filter(|s| !s.place.field().starts_with("floor"))
        .count();
    let floor_snapped = snapped
        .iter()
        .filter(|s| s.place.field().starts_with("floor") && s.snap.snapped())
        .count();
    assert_eq!(table.len(), objects + floor_snapped);
    let kept = snapped
        .iter()
        .find(|s| !s.snap.snapped() && !s.place.field().starts_with("floor"));
    if let Some(k) = kept {
        assert_eq!(table[&k.place.field()][0][0].as_f64(), Some(2.25));
    }
}

/// The lens distortion of the renderer follows the division model's convention: for a photo
/// pixel `p_d`, `r = |p_d - c| / h` (`c` the principal point, `h` half the diagonal), the
/// pinhole pixel is `p_u = c + (p_d - c) / (1 + k r^2)`. The returned (distorted) corners,
/// undistorted here by that formula, are the scene's exact clicks (the independent pinhole
/// camera's projections), and the photo shows them there: clicks near them snap to within a
/// pixel of them, while they lie several pixels from the pinhole points near the photo's edge.
#[test]
fn a_distorted_render_shows_its_corners_where_its_truth_says() {
    let (scene, truth) = scene(3, 15.0);
    let k = -0.1;
    let rendered = render_photo(
        &scene,
        &truth,
        &PhotoOptions {
            seed: 3,
            distortion_k: k,
            ..PhotoOptions::default()
        },
    )
    .unwrap();
    assert_eq!(rendered.distortion_k, k);
    let c = [
        truth.camera.pinhole(scene.image).principal_point_px.x,
        truth.camera.pinhole(scene.image).principal_point_px.y,
    ];
    let h = 0.5 * 800f64.hypot(600.0);
    let exact = vpmap_vision::clicks::scene_clicks(&scene);
    let image = SnapImage::new(&rendered.image);
    let vps = scene_vanishing_points(&scene).unwrap();
    let (mut near, mut far_from_pinhole) = (0, 0);
    for (t, e) in rendered.corners.iter().zip(&exact) {
        let d = [t.point_px[0] - c[0], t.point_px[1] - c[1]];
        let r2 = (d[0] * d[0] + d[1] * d[1]) / (h * h);
        let u = [c[0] + d[0] / (1.0 + k * r2), c[1] + d[1] / (1.0 + k * r2)];
        assert!(
            (u[0] - e.point_px[0]).abs() < 1e-6 && (u[1] - e.point_px[1]).abs() < 1e-6,
            "{:?} undistorts to {u:?}, not {:?}",
            t.point_px,
            e.point_px
        );
        if !(t.visible && t.kind == CornerKind::BoxCorner) {
            continue;
        }
        let click = [t.point_px[0] + 1.2, t.point_px[1] - 0.9];
        let snap = snap_click(&image, &vps, click, &SnapOptions::for_click_sigma(2.0)).unwrap();
        if snap.snapped() {
            let err = (snap.point_px[0] - t.point_px[0]).hypot(snap.point_px[1] - t.point_px[1]);
            near += usize::from(err < 1.0);
            let moved = (t.point_px[0] - e.point_px[0]).hypot(t.point_px[1] - e.point_px[1]);
            far_from_pinhole += usize::from(moved > 3.0 && err < 1.0);
        }
    }
    assert!(
        near >= 5,
        "{near} snapped within a pixel of the distorted truth"
    );
    assert!(
        far_from_pinhole >= 1,
        "no corner snapped where the distorted truth is far from the pinhole point"
    );
}

/// A dark rectangle whose corner at (60, 50) is rounded off by a quarter disc of `cut_px`
/// (zero: a sharp corner), on a light background.
fn rounded_corner(cut_px: f64) -> SnapImage {
    let img = GrayImage::from_fn(200, 160, |x, y| {
        let (px, py) = (f64::from(x) + 0.5, f64::from(y) + 0.5);
        let inside = px >= 60.0 && py >= 50.0;
        let (dx, dy) = (px - 60.0, py - 50.0);
        let cut = dx < cut_px && dy < cut_px && (cut_px - dx).hypot(cut_px - dy) > cut_px;
        Luma([if inside && !cut { 40 } else { 200 }])
    });
    SnapImage::new(&DynamicImage::ImageLuma8(img))
}

#[test]
fn a_corner_the_photo_does_not_show_is_held_less_sure_by_what_is_unseen() {
    // Both edges run straight to the rounded part: their lines still cross at (60, 50), but
    // the last `cut_px` of each is not seen, and the corner is only extrapolated there.
    let vps = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    let opts = SnapOptions {
        edge_length_px: 24.0,
        ..SnapOptions::default()
    };
    let click = [62.0, 52.5];
    let sharp = snap_click(&rounded_corner(0.0), &vps, click, &opts).unwrap();
    let cut_px = 5.0;
    let rounded = snap_click(&rounded_corner(cut_px), &vps, click, &opts).unwrap();
    assert!(sharp.snapped(), "{:?}", sharp.outcome);
    assert!(rounded.snapped(), "{:?}", rounded.outcome);
    for s in [&sharp, &rounded] {
        assert!(
            (s.point_px[0] - 60.0).abs() < 0.3 && (s.point_px[1] - 50.0).abs() < 0.3,
            "{:?}",
            s.point_px
        );
    }
    // The sharp corner's edges are seen to within the blur; the rounded one's stop near
    // where the rounding begins (the arc's first pixels still vote for the lines).
    assert!(
        sharp.edges.iter().all(|e| e.gap_px <= 3.5),
        "{:?}",
        sharp.edges
    );
    assert!(
        rounded.edges.iter().all(|e| e.gap_px >= cut_px - 3.0),
        "{:?}",
        rounded.edges
    );
    // The unseen stretch beyond the blur (two edge widths, at most 1.5 px each on this
    // sharp step smoothed by 1 px, plus the points' 1 px spacing) adds
    // `unseen_sd_per_px^2` per pixel squared on each axis.
    let added: f64 = rounded
        .edges
        .iter()
        .map(|e| (e.gap_px - 2.0 * 1.5 - 1.0).max(0.0).powi(2))
        .sum::<f64>()
        * opts.unseen_sd_per_px.powi(2);
    assert!(added > 0.1, "{added}");
    let (cs, cr) = (
        sharp.covariance_px2.unwrap(),
        rounded.covariance_px2.unwrap(),
    );
    for k in 0..2 {
        assert!(cr[k][k] >= cs[k][k] + added, "{cr:?} vs {cs:?} + {added}");
    }
    // Without the term the two corners would be held almost equally sure.
    let plain = SnapOptions {
        unseen_sd_per_px: 0.0,
        ..opts
    };
    let c0 = snap_click(&rounded_corner(cut_px), &vps, click, &plain)
        .unwrap()
        .covariance_px2
        .unwrap();
    assert!(c0[0][0] < cs[0][0] + 0.5 * added, "{c0:?}");
}

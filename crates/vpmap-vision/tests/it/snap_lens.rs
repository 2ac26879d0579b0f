//! Snapping on a photo taken through a lens: the scene's vanishing points are the pinhole
//! camera's, the photo's edges are bowed, and `vanishing_points_at` gives the points the
//! photo's edges run to near a click.
//!
//! Checked against the lens model written out here (the division model of
//! `docs/scene-format.md`, its inverse solved in closed form) and against renders of
//! `vpmap_vision::synthetic::photo`, whose truth is an independent pinhole camera.

use vpmap_metrology::scene::{DivisionModel, ImageSize, LensDistortion, Scene};
use vpmap_metrology::synth::{SynthOptions, Truth, synthesize};
use vpmap_vision::proposals::{ProposalOptions, propose_boxes};
use vpmap_vision::snap::scene::{scene_vanishing_points, snap_scene, vanishing_points_at};
use vpmap_vision::snap::{SnapImage, SnapOptions, snap_click};
use vpmap_vision::synthetic::photo::{CornerKind, PhotoOptions, RenderedPhoto, render_photo};

const W: f64 = 800.0;
const H: f64 = 600.0;

/// The photo pixel of pinhole pixel `p` under `c + (q - c) / (1 + k r^2)` (`r` in half
/// diagonals), written out: `r_u = r_d / (1 + k r_d^2)` solved for `r_d`.
fn distort(k: f64, p: [f64; 2]) -> [f64; 2] {
    let c = [W / 2.0, H / 2.0];
    let h = 0.5 * W.hypot(H);
    let d = [p[0] - c[0], p[1] - c[1]];
    let ru = d[0].hypot(d[1]) / h;
    if ru == 0.0 {
        return p;
    }
    let rd = (1.0 - (1.0 - 4.0 * k * ru * ru).sqrt()) / (2.0 * k * ru);
    [c[0] + d[0] * rd / ru, c[1] + d[1] * rd / ru]
}

/// The angle between the image directions `a` and `b`, sign-free, degrees.
fn angle_deg(a: [f64; 2], b: [f64; 2]) -> f64 {
    let cos = (a[0] * b[0] + a[1] * b[1]).abs() / (a[0].hypot(a[1]) * b[0].hypot(b[1]));
    cos.min(1.0).acos().to_degrees()
}

/// The image direction at photo pixel `at` towards homogeneous point `v`.
fn towards(at: [f64; 2], v: [f64; 3]) -> [f64; 2] {
    if v[2] == 0.0 {
        [v[0], v[1]]
    } else {
        [v[0] / v[2] - at[0], v[1] / v[2] - at[1]]
    }
}

#[test]
fn the_points_near_a_click_give_the_bowed_edges_directions_there() {
    let k = -0.15;
    let lens = DivisionModel::new(
        k,
        ImageSize {
            width: 800,
            height: 600,
        },
        None,
    );
    // Pinhole vanishing points: two finite ones and one at infinity.
    let vps = [[2400.0, 250.0, 1.0], [-900.0, 280.0, 1.0], [0.05, 1.0, 0.0]];
    let mut worst_deg: f64 = 0.0;
    let mut largest_bow_deg: f64 = 0.0;
    for pinhole in [[60.0, 50.0], [700.0, 540.0], [400.0, 300.0], [120.0, 520.0]] {
        let click = distort(k, pinhole);
        let here = vanishing_points_at(&vps, Some(&lens), click);
        assert_eq!(here.len(), 3);
        for (v, h) in vps.iter().zip(&here) {
            // The photo's edge through the click: the pinhole line towards `v`, through the
            // lens; its tangent at the click by central differences of 1e-4 px.
            let d = towards(pinhole, *v);
            let n = d[0].hypot(d[1]);
            let step = [1e-4 * d[0] / n, 1e-4 * d[1] / n];
            let a = distort(k, [pinhole[0] - step[0], pinhole[1] - step[1]]);
            let b = distort(k, [pinhole[0] + step[0], pinhole[1] + step[1]]);
            let tangent = [b[0] - a[0], b[1] - a[1]];
            worst_deg = worst_deg.max(angle_deg(tangent, towards(click, *h)));
            largest_bow_deg = largest_bow_deg.max(angle_deg(tangent, towards(click, *v)));
        }
    }
    assert!(worst_deg < 1e-4, "{worst_deg} degrees off the bowed edge");
    // The pinhole points themselves would be this far off at the photo's corners.
    assert!(largest_bow_deg > 3.0, "{largest_bow_deg}");
    // Without a lens the points are the scene's.
    assert_eq!(vanishing_points_at(&vps, None, [10.0, 10.0]), vps.to_vec());
}

#[test]
fn a_two_point_scene_gets_its_vertical_through_the_lens() {
    let k = -0.12;
    let lens = DivisionModel::new(
        k,
        ImageSize {
            width: 800,
            height: 600,
        },
        None,
    );
    // A level camera: the horizon is the row y = 300, the vertical edges are columns in the
    // pinhole image.
    let vps = [[2400.0, 300.0, 1.0], [-1500.0, 300.0, 1.0]];
    let pinhole = [90.0, 80.0];
    let click = distort(k, pinhole);
    let here = vanishing_points_at(&vps, Some(&lens), click);
    assert_eq!(here.len(), 3);
    let a = distort(k, [pinhole[0], pinhole[1] - 1e-4]);
    let b = distort(k, [pinhole[0], pinhole[1] + 1e-4]);
    let tangent = [b[0] - a[0], b[1] - a[1]];
    assert!(angle_deg(tangent, towards(click, here[2])) < 1e-4);
    // The column is bowed there: no longer vertical in the photo.
    assert!(angle_deg(tangent, [0.0, 1.0]) > 2.0);
}

fn scene(seed: u64) -> (Scene, Truth) {
    synthesize(&SynthOptions {
        seed,
        image: ImageSize {
            width: 800,
            height: 600,
        },
        focal_px: 480.0,
        pitch_deg: 20.0,
        ..SynthOptions::default()
    })
    .unwrap()
}

/// Synthetic scene `seed` rendered through the lens `k`; the scene says its lens.
fn through_lens(seed: u64, k: f64) -> (Scene, RenderedPhoto) {
    let (mut scene, truth) = scene(seed);
    let rendered = render_photo(
        &scene,
        &truth,
        &PhotoOptions {
            seed,
            distortion_k: k,
            ..PhotoOptions::default()
        },
    )
    .unwrap();
    scene.lens_distortion = Some(LensDistortion { k, k_sd: None });
    (scene, rendered)
}

#[test]
fn box_corners_of_a_wide_lens_snap_with_the_lens_where_the_pinhole_points_miss_them() {
    // Renders through a wide lens (k = -0.15); each visible box corner clicked 1.2 px off,
    // snapped with the scene's pinhole vanishing points as they are and seen through the lens.
    let k = -0.15;
    let (mut near_without, mut near_with, mut bowed, mut checked_scenes) = (0, 0, 0, 0);
    for seed in 0..6 {
        let (scene, rendered) = through_lens(seed, k);
        let lens = scene.division_model().unwrap();
        let image = SnapImage::new(&rendered.image);
        let vps = scene_vanishing_points(&scene).unwrap();
        let opts = SnapOptions::for_click_sigma(2.0);
        for t in rendered
            .corners
            .iter()
            .filter(|c| c.visible && c.kind == CornerKind::BoxCorner)
        {
            let click = [t.point_px[0] + 1.2, t.point_px[1] - 0.9];
            let err = |vps: &[[f64; 3]]| {
                let s = snap_click(&image, vps, click, &opts).unwrap();
                s.snapped()
                    .then(|| (s.point_px[0] - t.point_px[0]).hypot(s.point_px[1] - t.point_px[1]))
            };
            let here = vanishing_points_at(&vps, Some(&lens), click);
            let bow = vps
                .iter()
                .zip(&here)
                .map(|(v, h)| angle_deg(towards(click, *v), towards(click, *h)))
                .fold(0.0, f64::max);
            bowed += usize::from(bow > 3.0);
            near_without += usize::from(err(&vps).is_some_and(|e| e < 1.0));
            near_with += usize::from(err(&here).is_some_and(|e| e < 1.0));
        }
        // `snap_scene` snaps each of the scene's clicks with the points seen through its
        // lens there (the scene's clicks are the pinhole's, so only the wiring is checked;
        // a click the lens puts outside the photo is refused as such).
        if let Ok(snapped) = snap_scene(&image, &scene, &opts) {
            for (s, c) in snapped
                .iter()
                .zip(vpmap_vision::clicks::scene_clicks(&scene))
            {
                let here = vanishing_points_at(&vps, Some(&lens), c.point_px);
                assert_eq!(
                    s.snap,
                    snap_click(&image, &here, c.point_px, &opts).unwrap()
                );
            }
            checked_scenes += 1;
        }
    }
    println!(
        "box corners snapped within 1 px: {near_without} with the pinhole points, {near_with} through the lens; {bowed} where an edge bows more than 3 degrees"
    );
    assert!(bowed >= 5, "{bowed}");
    assert!(
        checked_scenes >= 1,
        "no scene had every click inside its photo"
    );
    assert!(
        near_with > near_without,
        "{near_with} through the lens, {near_without} without"
    );
}

#[test]
fn box_proposals_on_a_wide_lens_find_more_true_boxes_with_the_lens() {
    // The same renders; a proposal is true when every corner it names lies within 5 px of a
    // visible true box corner (the evaluations' match, `vpmap_eval::clicks`).
    let k = -0.15;
    let (mut true_without, mut true_with) = (0, 0);
    for seed in 0..16 {
        let (scene, rendered) = through_lens(seed, k);
        let image = SnapImage::new(&rendered.image);
        let vps = scene_vanishing_points(&scene).unwrap();
        let segments = vpmap_vision::detect_segments(
            &rendered.image,
            &vpmap_vision::DetectOptions {
                max_side_px: 800,
                ..vpmap_vision::DetectOptions::default()
            },
        )
        .unwrap();
        let truths: Vec<[f64; 2]> = rendered
            .corners
            .iter()
            .filter(|c| c.visible && c.kind == CornerKind::BoxCorner)
            .map(|c| c.point_px)
            .collect();
        let tol = 5.0;
        let count_true = |opts: &ProposalOptions| {
            propose_boxes(&image, &segments, &vps, opts)
                .unwrap()
                .iter()
                .filter(|p| {
                    let named: Vec<[f64; 2]> = [&p.base, &p.top]
                        .iter()
                        .flat_map(|c| [c.near, c.right, c.left])
                        .flatten()
                        .collect();
                    named.iter().all(|q| {
                        truths
                            .iter()
                            .any(|t| (t[0] - q[0]).hypot(t[1] - q[1]) < tol)
                    })
                })
                .count()
        };
        true_without += count_true(&ProposalOptions::default());
        true_with += count_true(&ProposalOptions {
            lens: scene.division_model(),
            ..ProposalOptions::default()
        });
    }
    println!(
        "true box proposals: {true_without} with the pinhole points, {true_with} through the lens"
    );
    assert!(
        true_with > true_without,
        "{true_with} through the lens, {true_without} without"
    );
}

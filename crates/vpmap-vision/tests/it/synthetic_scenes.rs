//! Detection on synthetic photos from known cameras.
//!
//! The renderer's camera is checked against `vpmap_metrology::synth::PinholeCamera` (an
//! independent pinhole model) first, so the truth the detector is compared with is right.

use image::ImageEncoder;
use nalgebra::{Vector2, Vector3};
use vpmap_metrology::scene::ImageSize;
use vpmap_metrology::synth::PinholeCamera;
use vpmap_vision::metrics::manhattan_errors_deg;
use vpmap_vision::scene::detected_scene;
use vpmap_vision::synthetic::{RenderedScene, SceneRenderOptions, render_manhattan_scene};
use vpmap_vision::{DetectOptions, Detection, Perspective, detect};

fn found_directions(d: &Detection) -> [[f64; 3]; 3] {
    let v = &d.vanishing_points;
    assert_eq!(v.len(), 3);
    assert!(v[2].vertical && !v[0].vertical && !v[1].vertical);
    [
        v[0].direction_camera,
        v[1].direction_camera,
        v[2].direction_camera,
    ]
}

/// Render, detect (intrinsics unknown), and check directions, focal length and perspective.
fn check(opts: &SceneRenderOptions, max_error_deg: f64, max_focal_error: f64) -> Detection {
    let scene = render_manhattan_scene(opts);
    let found = detect(&scene.image, &DetectOptions::default()).expect("detect");
    check_against(&scene, &found, max_error_deg);
    let focal_error = found.intrinsics.focal_px / opts.focal_px - 1.0;
    assert!(
        focal_error.abs() < max_focal_error,
        "focal {} vs {} ({:+.1} %)",
        found.intrinsics.focal_px,
        opts.focal_px,
        100.0 * focal_error
    );
    assert!(found.focal_estimated);
    found
}

fn check_against(scene: &RenderedScene, found: &Detection, max_error_deg: f64) {
    let errors = manhattan_errors_deg(&found_directions(found), 2, &scene.directions_camera, 2);
    assert!(
        errors.iter().all(|&e| e < max_error_deg),
        "direction errors {errors:?} deg (limit {max_error_deg})"
    );
    // The tilt is measured, never rounded to level (a level camera is reported three-point
    // with a small measured tilt unless a two-point tolerance is given).
    assert!(
        (found.vertical_tilt_deg - scene.vertical_tilt_deg).abs() < max_error_deg,
        "tilt {} vs {}",
        found.vertical_tilt_deg,
        scene.vertical_tilt_deg
    );
    assert_eq!(
        found.image_size_px,
        [scene.image.width(), scene.image.height()]
    );
    // Every vanishing point has support, and the support indices are valid.
    for vp in &found.vanishing_points {
        assert!(vp.segments.len() >= 3, "{vp:?}");
        assert!(vp.segments.iter().all(|&i| i < found.segments.len()));
    }
}

#[test]
fn renderer_truth_matches_an_independent_pinhole_camera() {
    let opts = SceneRenderOptions {
        pitch_rad: 0.4,
        roll_rad: -0.1,
        yaw_rad: 0.6,
        principal_point_px: Some([300.0, 250.0]),
        ..SceneRenderOptions::default()
    };
    let scene = render_manhattan_scene(&opts);
    let camera = PinholeCamera {
        image: ImageSize {
            width: opts.width_px,
            height: opts.height_px,
        },
        focal_px: opts.focal_px,
        principal_point_px: Vector2::new(300.0, 250.0),
        height_m: opts.camera_height_m,
        pitch_rad: opts.pitch_rad,
        roll_rad: opts.roll_rad,
    };
    let (s, c) = opts.yaw_rad.sin_cos();
    let axes = [
        Vector3::new(c, s, 0.0),
        Vector3::new(-s, c, 0.0),
        Vector3::z(),
    ];
    for (axis, vp) in axes.iter().zip(scene.vanishing_points_px) {
        let expected = camera.vanishing_point(*axis).expect("finite");
        let vp = vp.expect("finite");
        assert!(
            (expected.x - vp[0]).abs() < 1e-6 && (expected.y - vp[1]).abs() < 1e-6,
            "{expected:?} vs {vp:?}"
        );
    }
    assert_eq!(scene.image.width(), 640);
    assert_eq!(scene.boxes, 5);
}

#[test]
fn three_point_colour_640x480() {
    check(&SceneRenderOptions::default(), 1.0, 0.03);
}

#[test]
fn two_point_grey_with_roll() {
    let found = check(
        &SceneRenderOptions {
            focal_px: 500.0,
            pitch_rad: 0.0,
            roll_rad: 5f64.to_radians(),
            yaw_rad: 40f64.to_radians(),
            colour: false,
            seed: 1,
            ..SceneRenderOptions::default()
        },
        1.0,
        0.03,
    );
    // Two-point perspective: the principal point is not estimated.
    assert!(!found.principal_point_estimated);
    assert_eq!(found.intrinsics.principal_point_px, [320.0, 240.0]);
}

#[test]
fn three_point_long_focal_with_negative_roll() {
    check(
        &SceneRenderOptions {
            focal_px: 800.0,
            pitch_rad: 15f64.to_radians(),
            roll_rad: -8f64.to_radians(),
            yaw_rad: 55f64.to_radians(),
            seed: 2,
            ..SceneRenderOptions::default()
        },
        1.0,
        0.03,
    );
}

#[test]
fn three_point_wide_angle_steep_pitch() {
    check(
        &SceneRenderOptions {
            focal_px: 380.0,
            pitch_rad: 40f64.to_radians(),
            roll_rad: 3f64.to_radians(),
            yaw_rad: 25f64.to_radians(),
            seed: 3,
            ..SceneRenderOptions::default()
        },
        1.0,
        0.03,
    );
}

#[test]
fn large_2000x1500_is_downscaled_and_reported_in_input_pixels() {
    let opts = SceneRenderOptions {
        width_px: 2000,
        height_px: 1500,
        focal_px: 1800.0,
        pitch_rad: 35f64.to_radians(),
        roll_rad: -4f64.to_radians(),
        yaw_rad: 20f64.to_radians(),
        seed: 0,
        ..SceneRenderOptions::default()
    };
    let found = check(&opts, 1.0, 0.03);
    // Segments are in input pixels: they reach beyond the 640-pixel working image.
    let reach = found
        .segments
        .iter()
        .flat_map(|s| [s.start_px[0], s.end_px[0]])
        .fold(0.0f64, f64::max);
    assert!(reach > 1500.0, "rightmost segment end at x = {reach}");
    assert!(found.segments.iter().any(|s| s.length_px() > 300.0));
    // The vanishing points are consistent with the reported intrinsics.
    let k = found.intrinsics;
    for vp in &found.vanishing_points {
        let d = vp.direction_camera;
        let p = vp.point_px.expect("finite");
        let expected = [
            k.focal_px * d[0] / d[2] + k.principal_point_px[0],
            k.focal_px * d[1] / d[2] + k.principal_point_px[1],
        ];
        assert!((p[0] - expected[0]).abs() < 1e-6 * p[0].abs().max(1.0));
        assert!((p[1] - expected[1]).abs() < 1e-6 * p[1].abs().max(1.0));
    }
}

#[test]
fn known_intrinsics_are_kept_and_give_tighter_directions() {
    let opts = SceneRenderOptions {
        focal_px: 650.0,
        principal_point_px: Some([300.0, 255.0]),
        pitch_rad: 20f64.to_radians(),
        roll_rad: 2f64.to_radians(),
        yaw_rad: 35f64.to_radians(),
        seed: 5,
        ..SceneRenderOptions::default()
    };
    let scene = render_manhattan_scene(&opts);
    let found = detect(
        &scene.image,
        &DetectOptions {
            focal_px: Some(650.0),
            principal_point_px: Some([300.0, 255.0]),
            ..DetectOptions::default()
        },
    )
    .expect("detect");
    assert_eq!(found.intrinsics, scene.intrinsics);
    assert!(!found.focal_estimated && !found.principal_point_estimated);
    check_against(&scene, &found, 0.5);
}

#[test]
fn a_jpeg_round_trip_still_gives_the_camera() {
    let opts = SceneRenderOptions {
        pitch_rad: 10f64.to_radians(),
        yaw_rad: 50f64.to_radians(),
        seed: 6,
        ..SceneRenderOptions::default()
    };
    let scene = render_manhattan_scene(&opts);
    let rgb = scene.image.to_rgb8();
    let mut bytes = Vec::new();
    image::codecs::jpeg::JpegEncoder::new_with_quality(&mut bytes, 80)
        .write_image(
            rgb.as_raw(),
            rgb.width(),
            rgb.height(),
            image::ExtendedColorType::Rgb8,
        )
        .expect("encode");
    let decoded = image::load_from_memory(&bytes).expect("decode");
    let found = detect(&decoded, &DetectOptions::default()).expect("detect");
    check_against(&scene, &found, 1.0);
    assert!((found.intrinsics.focal_px / opts.focal_px - 1.0).abs() < 0.03);
}

#[test]
fn the_two_point_tolerance_decides_the_perspective() {
    // 2 degrees of pitch: three-point at a 1-degree tolerance and by default (0), two-point at
    // 3 degrees.
    let scene = render_manhattan_scene(&SceneRenderOptions {
        pitch_rad: 2f64.to_radians(),
        yaw_rad: 35f64.to_radians(),
        seed: 7,
        ..SceneRenderOptions::default()
    });
    let strict = DetectOptions {
        two_point_tolerance_deg: 1.0,
        ..DetectOptions::default()
    };
    let found = detect(&scene.image, &strict).expect("detect");
    assert!(
        (found.vertical_tilt_deg - 2.0).abs() < 0.7,
        "tilt {}",
        found.vertical_tilt_deg
    );
    assert_eq!(found.perspective, Perspective::ThreePoint);
    let found = detect(&scene.image, &DetectOptions::default()).expect("detect");
    assert_eq!(found.perspective, Perspective::ThreePoint);
    let lenient = DetectOptions {
        two_point_tolerance_deg: 3.0,
        ..DetectOptions::default()
    };
    let found = detect(&scene.image, &lenient).expect("detect");
    assert_eq!(found.perspective, Perspective::TwoPoint);
}

#[test]
fn the_same_seed_gives_the_same_result() {
    let scene = render_manhattan_scene(&SceneRenderOptions {
        seed: 8,
        ..SceneRenderOptions::default()
    });
    let a = detect(&scene.image, &DetectOptions::default()).expect("detect");
    let b = detect(&scene.image, &DetectOptions::default()).expect("detect");
    assert_eq!(a, b);
}

#[test]
fn a_sixteen_bit_grey_image_works_like_the_eight_bit_one() {
    let scene = render_manhattan_scene(&SceneRenderOptions {
        seed: 9,
        ..SceneRenderOptions::default()
    });
    let grey16 = image::DynamicImage::ImageLuma16(scene.image.to_luma16());
    let found = detect(&grey16, &DetectOptions::default()).expect("detect");
    check_against(&scene, &found, 1.0);
}

/// Detection on a rendered scene twice: with the true intrinsics given, and without them.
fn detect_given_and_estimated(
    scene: &RenderedScene,
    focal_px: f64,
    principal_point_px: [f64; 2],
) -> (Detection, Detection) {
    let given = detect(
        &scene.image,
        &DetectOptions {
            focal_px: Some(focal_px),
            principal_point_px: Some(principal_point_px),
            ..DetectOptions::default()
        },
    )
    .expect("detect with the intrinsics");
    let estimated = detect(&scene.image, &DetectOptions::default()).expect("detect");
    (given, estimated)
}

/// The York Urban photos give a *worse* vertical with the true intrinsics than without (1.07
/// against 0.60 degrees median), because their labelled vertical is not orthogonal to their
/// labelled horizontals (see `docs/results.md`). Here the truth is exactly orthogonal: on
/// York Urban-like cameras (f = 675 px, principal point 17 px off centre, looking down 1.5 to
/// 8 degrees) knowing the camera must not make the vertical worse.
#[test]
fn the_true_intrinsics_do_not_make_the_vertical_worse() {
    let (focal_px, principal_point_px) = (675.0, [307.5, 251.5]);
    // (scene number, pitch in degrees, looking down).
    for (k, pitch_deg) in [(0u32, 1.5f64), (2, 4.5), (4, 8.0), (9, 6.0)] {
        let k_f64 = f64::from(k);
        let scene = render_manhattan_scene(&SceneRenderOptions {
            focal_px,
            principal_point_px: Some(principal_point_px),
            pitch_rad: pitch_deg.to_radians(),
            roll_rad: (0.5 * (k_f64 - 6.0)).to_radians(),
            yaw_rad: (20.0 + 5.0 * k_f64).to_radians(),
            noise_sigma: 2.0,
            seed: 100 + u64::from(k),
            ..SceneRenderOptions::default()
        });
        let (given, estimated) = detect_given_and_estimated(&scene, focal_px, principal_point_px);
        let truth = &scene.directions_camera;
        let vertical_given = manhattan_errors_deg(&found_directions(&given), 2, truth, 2)[2];
        let vertical_estimated =
            manhattan_errors_deg(&found_directions(&estimated), 2, truth, 2)[2];
        // Measured: 0.12, 0.55, 0.62, 0.69 degrees given; 0.96, 1.47, 1.90, 1.65 estimated.
        assert!(
            vertical_given <= vertical_estimated && vertical_given < 1.0,
            "scene {k}, pitch {pitch_deg} deg: vertical off by {vertical_given:.2} deg with the \
             true intrinsics, {vertical_estimated:.2} deg without"
        );
    }
}

/// Looking up (negative pitch: the vertical vanishing point is above the image) works like
/// looking down when the camera sees near floor and boxes.
///
/// With the renderer's default camera height (1.6 m) a camera looking up sees no floor nearer
/// than 7 m (6 degrees up) to 14 m (12 degrees up): from 8 degrees up no box is placed at
/// all, and the 0.5 m floor tiles are 1-3 pixels tall and alias into moire bands below the
/// horizon. That scene has no vertical edge and no reliable horizontal one: at 8 degrees up
/// the directions come out 4-9 degrees off, and still 4-5 degrees off from only the segments
/// that point at a true vanishing point (within 1.5 degrees). A lower camera (0.5 m, 1 m
/// tiles) shows the same view with boxes and a resolvable floor; there the directions are as
/// good as looking down.
fn check_looking_up(pitch_up_deg: f64) {
    let (focal_px, principal_point_px) = (675.0, [307.5, 251.5]);
    for seed in 0..3u64 {
        let seed_f64 = seed as f64;
        let scene = render_manhattan_scene(&SceneRenderOptions {
            focal_px,
            principal_point_px: Some(principal_point_px),
            pitch_rad: -pitch_up_deg.to_radians(),
            roll_rad: (1.0 - seed_f64).to_radians(),
            yaw_rad: (25.0 + 10.0 * seed_f64).to_radians(),
            camera_height_m: 0.5,
            tile_size_m: 1.0,
            noise_sigma: 2.0,
            seed: 300 + seed,
            ..SceneRenderOptions::default()
        });
        assert!(scene.boxes >= 3, "only {} boxes", scene.boxes);
        let (given, estimated) = detect_given_and_estimated(&scene, focal_px, principal_point_px);
        // Measured: at most 0.50 degrees given, 1.02 degrees estimated, with the focal
        // length 1.0-5.5 % high (as on near-level photos, see docs/detection.md).
        check_against(&scene, &given, 1.0);
        check_against(&scene, &estimated, 2.0);
        let focal_error = estimated.intrinsics.focal_px / focal_px - 1.0;
        assert!(
            focal_error.abs() < 0.1,
            "{pitch_up_deg} deg up, seed {seed}: focal {:+.1} %",
            100.0 * focal_error
        );
    }
}

#[test]
fn looking_up_4_degrees_with_near_floor_and_boxes() {
    check_looking_up(4.0);
}

#[test]
fn looking_up_8_degrees_with_near_floor_and_boxes() {
    check_looking_up(8.0);
}

#[test]
fn looking_up_12_degrees_with_near_floor_and_boxes() {
    check_looking_up(12.0);
}

/// Where the line through `a` and `b` crosses `x`, pixels.
fn y_on_line(a: [f64; 2], b: [f64; 2], x: f64) -> f64 {
    a[1] + (b[1] - a[1]) * (x - a[0]) / (b[0] - a[0])
}

#[test]
fn a_nearly_level_photo_keeps_its_measured_horizon_in_the_scene() {
    // 1.5 degrees down, under the 3-degree tolerance that used to level the camera (turning
    // the directions until the horizon passed through the principal point).
    let scene = render_manhattan_scene(&SceneRenderOptions {
        pitch_rad: 1.5f64.to_radians(),
        yaw_rad: 35f64.to_radians(),
        seed: 11,
        ..SceneRenderOptions::default()
    });
    let k = scene.intrinsics;
    let (f, [cx, cy]) = (k.focal_px, k.principal_point_px);
    let width = f64::from(scene.image.width());
    // The true horizon, from the renderer's camera: the points whose ray is orthogonal to the
    // vertical `u`, u . ((x - cx) / f, (y - cy) / f, 1) = 0.
    let u = scene.directions_camera[2];
    let true_y = |x: f64| cy - (u[0] * (x - cx) / f + u[2]) * f / u[1];
    for (tolerance_deg, perspective) in
        [(0.0, Perspective::ThreePoint), (3.0, Perspective::TwoPoint)]
    {
        let found = detect(
            &scene.image,
            &DetectOptions {
                focal_px: Some(f),
                principal_point_px: Some(k.principal_point_px),
                two_point_tolerance_deg: tolerance_deg,
                ..DetectOptions::default()
            },
        )
        .expect("detect");
        let written = detected_scene(&found).expect("scene");
        assert_eq!(written.perspective, perspective, "{}", written.json);
        let [Some(a), Some(b), vertical] = written.points_px else {
            panic!("{}", written.json);
        };
        assert_eq!(vertical.is_some(), perspective == Perspective::ThreePoint);
        // What levelling wrote: the same horizon moved, parallel to itself, through the
        // principal point.
        let shift = y_on_line(a, b, cx) - cy;
        let error = |x: f64| (y_on_line(a, b, x) - true_y(x)).abs();
        let levelled_error = |x: f64| (y_on_line(a, b, x) - shift - true_y(x)).abs();
        let kept = error(0.0).max(error(width));
        let levelled = levelled_error(0.0).max(levelled_error(width));
        // The true horizon is f tan(1.5 deg) above the principal point.
        let offset = f * 1.5f64.to_radians().tan();
        assert!((cy - true_y(cx) - offset).abs() < 1e-6 * f);
        // Measured: 4.8 px as written, 15.9 px levelled, both tolerances (640 x 480).
        let height = f64::from(scene.image.height());
        assert!(
            kept < 0.5 * levelled && kept < 0.02 * height && levelled > 0.75 * offset,
            "tolerance {tolerance_deg}: horizon off by {kept:.2} px as written, {levelled:.2} px levelled ({offset:.2} px tilt)"
        );
        if perspective == Perspective::ThreePoint {
            let pitch_deg = written.calibration.pitch_rad.to_degrees();
            // Measured: 1.06 deg (the directions are within a degree on these renders); the
            // levelled scene had 0.
            assert!((pitch_deg - 1.5).abs() < 0.6, "pitch {pitch_deg} deg");
        }
    }
}

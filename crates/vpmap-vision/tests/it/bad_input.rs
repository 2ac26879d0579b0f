//! Inputs that cannot give vanishing points: errors, never panics.

use image::{DynamicImage, GrayImage, Luma, RgbImage};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use vpmap_vision::{DetectOptions, Segment, VisionError, detect, detect_from_segments};

#[test]
fn a_blank_image_has_not_enough_lines() {
    let img = DynamicImage::ImageLuma8(GrayImage::from_pixel(640, 480, Luma([128])));
    let err = detect(&img, &DetectOptions::default()).unwrap_err();
    assert!(matches!(err, VisionError::NotEnoughLines { .. }), "{err}");
}

#[test]
fn a_noise_image_has_not_enough_lines() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let img = RgbImage::from_fn(640, 480, |_, _| {
        image::Rgb([rng.random::<u8>(), rng.random::<u8>(), rng.random::<u8>()])
    });
    let err = detect(&DynamicImage::ImageRgb8(img), &DetectOptions::default()).unwrap_err();
    assert!(matches!(err, VisionError::NotEnoughLines { .. }), "{err}");
}

#[test]
fn lines_of_a_single_direction_fix_no_frame() {
    // Vertical stripes: many edges, all towards one vanishing point. The error says so,
    // rather than asking for more segments than were found.
    let img = GrayImage::from_fn(640, 480, |x, _| {
        Luma([if (x / 40) % 2 == 0 { 40 } else { 210 }])
    });
    let err = detect(&DynamicImage::ImageLuma8(img), &DetectOptions::default()).unwrap_err();
    assert!(
        matches!(err, VisionError::NoOrthogonalDirections { segments } if segments >= 8),
        "{err}"
    );
    assert!(
        err.to_string()
            .contains("two or more orthogonal directions"),
        "{err}"
    );
}

#[test]
fn tiny_and_huge_images_are_refused() {
    for (w, h) in [
        (0, 0),
        (8, 8),
        (15, 100),
        (100, 15),
        (40_000, 16),
        (16, 40_000),
    ] {
        let img = DynamicImage::ImageLuma8(GrayImage::new(w, h));
        let err = detect(&img, &DetectOptions::default()).unwrap_err();
        assert!(
            matches!(err, VisionError::BadImageSize { width, height, .. } if width == w && height == h),
            "{w} x {h}: {err}"
        );
    }
}

#[test]
fn invalid_options_are_refused() {
    let img = DynamicImage::ImageLuma8(GrayImage::new(64, 64));
    let cases = [
        DetectOptions {
            focal_px: Some(0.0),
            ..DetectOptions::default()
        },
        DetectOptions {
            focal_px: Some(f64::INFINITY),
            ..DetectOptions::default()
        },
        DetectOptions {
            principal_point_px: Some([f64::NAN, 1.0]),
            ..DetectOptions::default()
        },
        DetectOptions {
            max_side_px: 0,
            ..DetectOptions::default()
        },
        DetectOptions {
            two_point_tolerance_deg: f64::NAN,
            ..DetectOptions::default()
        },
        DetectOptions {
            two_point_tolerance_deg: 60.0,
            ..DetectOptions::default()
        },
    ];
    for opts in cases {
        let err = detect(&img, &opts).unwrap_err();
        assert!(
            matches!(err, VisionError::InvalidParameter { .. }),
            "{opts:?}: {err}"
        );
    }
}

#[test]
fn degenerate_segments_do_not_panic() {
    let mut segments = vec![
        Segment {
            start_px: [10.0, 10.0],
            end_px: [10.0, 10.0],
            strength: 1.0,
        },
        Segment {
            start_px: [f64::NAN, 1.0],
            end_px: [3.0, 4.0],
            strength: 1.0,
        },
        Segment {
            start_px: [1e300, 1.0],
            end_px: [-1e300, 4.0],
            strength: 1.0,
        },
    ];
    // The same line many times over.
    for _ in 0..20 {
        segments.push(Segment {
            start_px: [0.0, 100.0],
            end_px: [600.0, 100.0],
            strength: 1.0,
        });
    }
    let result = detect_from_segments(segments, [640, 480], &DetectOptions::default());
    assert!(
        matches!(
            result,
            // The 20 copies, and the huge segment along the same line.
            Err(VisionError::NoOrthogonalDirections { segments: 21 })
        ),
        "{result:?}"
    );
    let result = detect_from_segments(Vec::new(), [640, 480], &DetectOptions::default());
    assert!(matches!(result, Err(VisionError::NotEnoughLines { .. })));
}

#[test]
fn random_segment_soups_never_panic() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for round in 0..30 {
        let count = rng.random_range(0..60);
        let spread = [1.0, 1e3, 1e6, 1e150][round % 4];
        let segments: Vec<Segment> = (0..count)
            .map(|_| {
                let mut p = || rng.random_range(-spread..spread);
                Segment {
                    start_px: [p(), p()],
                    end_px: [p(), p()],
                    strength: 1.0,
                }
            })
            .collect();
        let opts = DetectOptions {
            focal_px: (round % 3 == 0).then_some(500.0),
            principal_point_px: (round % 5 == 0).then_some([1e4, -3e3]),
            seed: round as u64,
            ..DetectOptions::default()
        };
        // Any answer is fine; a panic is not. A result, when there is one, is finite.
        if let Ok(found) = detect_from_segments(segments, [640, 480], &opts) {
            assert!(found.intrinsics.focal_px.is_finite() && found.intrinsics.focal_px > 0.0);
            for vp in &found.vanishing_points {
                assert!(vp.direction_camera.iter().all(|v| v.is_finite()));
            }
        }
    }
}

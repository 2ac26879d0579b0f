//! Thousands of random scenes from the synthetic pinhole camera: both methods must reproduce
//! the true footprints, floor corners and heights to 1e-9 relative.

use vpmap_metrology::map::{BuildOptions, build_map};
use vpmap_metrology::reconstruct::Method;
use vpmap_metrology::synth::{SynthOptions, VanishingPointForm, synthesize};

use crate::max_relative_error;

const SCENES: u64 = 1000;

fn check(pitch_deg: f64, roll_deg: f64, seed_base: u64) {
    let mut worst = [0.0f64; 2];
    for i in 0..SCENES {
        let seed = seed_base + i;
        let options = SynthOptions {
            seed,
            pitch_deg,
            // Vary the roll's sign and size around the configuration's value.
            roll_deg: if i % 2 == 0 {
                roll_deg
            } else {
                -roll_deg * 0.7
            },
            boxes: 3 + (i % 3) as usize,
            prisms: 1,
            vanishing_points: if i % 4 == 1 {
                VanishingPointForm::Lines
            } else {
                VanishingPointForm::Points
            },
            with_principal_point: i % 5 == 2,
            height_m: 0.2 + (i % 10) as f64 * 0.2,
            ..SynthOptions::default()
        };
        let (scene, truth) = synthesize(&options);
        let mut maps = Vec::new();
        for (k, method) in [Method::Sideview, Method::Projective]
            .into_iter()
            .enumerate()
        {
            let map = build_map(&scene, &BuildOptions { method })
                .unwrap_or_else(|e| panic!("seed {seed} {method}: {e}"));
            let err = max_relative_error(&map, &truth);
            assert!(
                err < 1e-9,
                "seed {seed}, pitch {pitch_deg}, {method}: relative error {err:e}"
            );
            assert!(
                (map.camera.pitch_deg - truth.camera.pitch_deg).abs() < 1e-9,
                "seed {seed}: pitch {} vs {}",
                map.camera.pitch_deg,
                truth.camera.pitch_deg
            );
            assert!(
                (map.camera.roll_deg - truth.camera.roll_deg).abs() < 1e-9,
                "seed {seed}: roll {} vs {}",
                map.camera.roll_deg,
                truth.camera.roll_deg
            );
            assert!(
                (map.camera.focal_px - truth.camera.focal_px).abs() < 1e-9 * truth.camera.focal_px,
                "seed {seed}: focal {} vs {}",
                map.camera.focal_px,
                truth.camera.focal_px
            );
            worst[k] = worst[k].max(err);
            maps.push(map);
        }
        // The two methods agree with each other, corner by corner.
        let extent = truth
            .floor
            .iter()
            .map(|p| p[0].hypot(p[1]))
            .fold(1.0, f64::max);
        for (a, b) in maps[0].objects.iter().zip(&maps[1].objects) {
            for (p, q) in a.footprint.iter().zip(&b.footprint) {
                let gap = (p[0] - q[0]).hypot(p[1] - q[1]) / extent;
                assert!(
                    gap < 1e-9,
                    "seed {seed}: methods disagree by {gap:e} on {}",
                    a.name
                );
            }
        }
    }
    eprintln!(
        "pitch {pitch_deg} roll {roll_deg}: worst relative error sideview {:.1e}, projective {:.1e} over {SCENES} scenes",
        worst[0], worst[1]
    );
}

#[test]
fn two_point_perspective_1000_scenes() {
    check(0.0, 0.0, 10_000);
}

#[test]
fn two_point_perspective_with_roll_1000_scenes() {
    check(0.0, 10.0, 20_000);
}

#[test]
fn three_point_perspective_10_deg_1000_scenes() {
    check(10.0, 0.0, 30_000);
}

#[test]
fn three_point_perspective_30_deg_1000_scenes() {
    check(30.0, 0.0, 40_000);
}

#[test]
fn three_point_perspective_45_deg_1000_scenes() {
    check(45.0, 0.0, 50_000);
}

#[test]
fn three_point_perspective_with_roll_1000_scenes() {
    check(30.0, 8.0, 60_000);
}

#[test]
fn camera_looking_up_is_exact() {
    // A camera tilted up (negative pitch) sees the floor only near the bottom of the image.
    check_few(-8.0, 2.0);
}

fn check_few(pitch_deg: f64, roll_deg: f64) {
    for seed in 0..50 {
        let (scene, truth) = synthesize(&SynthOptions {
            seed,
            pitch_deg,
            roll_deg,
            boxes: 2,
            prisms: 0,
            ..SynthOptions::default()
        });
        for method in [Method::Sideview, Method::Projective] {
            let map = build_map(&scene, &BuildOptions { method }).unwrap();
            let err = max_relative_error(&map, &truth);
            assert!(err < 1e-9, "seed {seed} {method}: {err:e}");
        }
    }
}

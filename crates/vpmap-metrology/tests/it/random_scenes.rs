//! Thousands of random scenes from the synthetic pinhole camera: every method must reproduce
//! the true footprints, floor corners and heights to 1e-9 relative.

use vpmap_metrology::map::{BuildOptions, build_map};
use vpmap_metrology::reconstruct::Method;
use vpmap_metrology::synth::{SynthOptions, VanishingPointForm, synthesize};

use crate::{assert_camera_matches, max_relative_error};

const SCENES: u64 = 1000;

fn check(pitch_deg: f64, roll_deg: f64, seed_base: u64) {
    let mut worst = [0.0f64; 3];
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
        let (scene, truth) = synthesize(&options).unwrap();
        let mut maps = Vec::new();
        for (k, method) in [Method::Sideview, Method::Projective, Method::Fit]
            .into_iter()
            .enumerate()
        {
            let map = build_map(
                &scene,
                &BuildOptions {
                    method,
                    ..BuildOptions::default()
                },
            )
            .unwrap_or_else(|e| panic!("seed {seed} {method}: {e}"));
            let err = max_relative_error(&map, &truth);
            assert!(
                err < 1e-9,
                "seed {seed}, pitch {pitch_deg}, {method}: relative error {err:e}"
            );
            assert_camera_matches(&map, &truth, &format!("seed {seed} {method}"));
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
        "pitch {pitch_deg} roll {roll_deg}: worst relative error sideview {:.1e}, projective {:.1e}, fit {:.1e} over {SCENES} scenes",
        worst[0], worst[1], worst[2]
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
        })
        .unwrap();
        for method in [Method::Sideview, Method::Projective, Method::Fit] {
            let map = build_map(
                &scene,
                &BuildOptions {
                    method,
                    ..BuildOptions::default()
                },
            )
            .unwrap();
            let err = max_relative_error(&map, &truth);
            assert!(err < 1e-9, "seed {seed} {method}: {err:e}");
        }
    }
}

#[test]
fn view_on_floor_is_the_image_rectangle_on_the_floor() {
    use nalgebra::Vector3;
    use vpmap_metrology::synth::PinholeCamera;
    for (seed, pitch, roll) in [
        (1u64, 0.0, 0.0),
        (2, 10.0, -5.0),
        (3, 30.0, 4.0),
        (4, 45.0, 0.0),
    ] {
        let options = SynthOptions {
            seed,
            pitch_deg: pitch,
            roll_deg: roll,
            ..SynthOptions::default()
        };
        let (scene, truth) = synthesize(&options).unwrap();
        let map = build_map(&scene, &BuildOptions::default()).unwrap();
        let camera = PinholeCamera {
            image: options.image,
            focal_px: options.focal_px,
            principal_point_px: options.image.centre(),
            height_m: options.height_m,
            pitch_rad: pitch.to_radians(),
            roll_rad: roll.to_radians(),
        };
        let view = &map.camera.view_on_floor;
        assert!(view.len() >= 3, "seed {seed}: {view:?}");
        let (w, h) = (
            f64::from(options.image.width),
            f64::from(options.image.height),
        );
        let mut on_border = 0;
        for v in view {
            let p = camera.project(Vector3::new(v[0], v[1], 0.0)).unwrap();
            let border = [p.x.abs(), (p.x - w).abs(), p.y.abs(), (p.y - h).abs()]
                .into_iter()
                .fold(f64::INFINITY, f64::min);
            assert!(
                p.x > -1e-6 && p.x < w + 1e-6 && p.y > -1e-6 && p.y < h + 1e-6,
                "seed {seed}: {p:?}"
            );
            on_border += usize::from(border < 1e-6);
        }
        assert!(
            on_border >= 2,
            "seed {seed}: vertices must lie on the image border"
        );
        // Every object corner (all inside the image) lies inside the view polygon.
        let inside = |q: [f64; 2]| {
            (0..view.len()).all(|i| {
                let (a, b) = (view[i], view[(i + 1) % view.len()]);
                (b[0] - a[0]) * (q[1] - a[1]) - (b[1] - a[1]) * (q[0] - a[0]) >= -1e-9
            })
        };
        for o in &truth.objects {
            for c in &o.footprint {
                assert!(inside(*c), "seed {seed}: {c:?} outside the view");
            }
        }
    }
}

#[test]
fn camera_matrices_send_pixels_along_their_true_rays() {
    use nalgebra::{Matrix3, Vector3};
    for seed in 0..100 {
        let options = SynthOptions {
            seed,
            pitch_deg: (seed % 5) as f64 * 10.0,
            roll_deg: (seed % 7) as f64 * 3.0 - 9.0,
            ..SynthOptions::default()
        };
        let (scene, truth) = synthesize(&options).unwrap();
        let map = build_map(&scene, &BuildOptions::default()).unwrap();
        let k = Matrix3::from_fn(|r, c| map.camera.k_matrix[r][c]);
        let rot = Matrix3::from_fn(|r, c| map.camera.rotation_map_from_camera[r][c]);
        let k_inv = k.try_inverse().unwrap();
        let camera = Vector3::new(0.0, 0.0, truth.camera.height);
        for (px, world) in scene.floor.iter().zip(&truth.floor) {
            let ray = rot * k_inv * Vector3::new(px[0], px[1], 1.0);
            let truth_dir = Vector3::new(world[0], world[1], 0.0) - camera;
            let sin = ray.normalize().cross(&truth_dir.normalize()).norm();
            assert!(sin < 1e-9, "seed {seed}: ray off by {sin:e}");
            assert!(
                ray.dot(&truth_dir) > 0.0,
                "seed {seed}: ray points backwards"
            );
        }
    }
}

#[test]
fn noisy_scenes_build_or_fail_with_a_named_field() {
    // 2 px of noise on every clicked point, vanishing points re-fitted from the noisy edges:
    // a map comes out with every point in front of the camera and in range, or the error
    // names the scene field at fault. Never a panic.
    let mut failures = 0;
    for seed in 0..250u64 {
        let pitch = [0.0, 5.0, 15.0, 30.0, 45.0][(seed % 5) as usize];
        let (scene, _) = synthesize(&SynthOptions {
            seed,
            pitch_deg: pitch,
            noise_px: 2.0,
            vanishing_points: VanishingPointForm::Lines,
            ..SynthOptions::default()
        })
        .unwrap();
        for method in [Method::Sideview, Method::Projective, Method::Fit] {
            match build_map(
                &scene,
                &BuildOptions {
                    method,
                    ..BuildOptions::default()
                },
            ) {
                Ok(map) => {
                    let tilt = map.camera.pitch_deg.to_radians();
                    for p in map
                        .objects
                        .iter()
                        .flat_map(|o| &o.footprint)
                        .chain(&map.floor)
                    {
                        let depth = p[1] * tilt.cos() + map.camera.height * tilt.sin();
                        assert!(depth > 0.0, "seed {seed} {method}: {p:?} behind the camera");
                        assert!(p[0].hypot(p[1]) < 1e4 * map.camera.height);
                    }
                }
                Err(e) => {
                    failures += 1;
                    let text = e.to_string();
                    assert!(
                        text.contains('`') || text.contains("no real focal length"),
                        "seed {seed} {method}: unhelpful error {text}"
                    );
                }
            }
        }
    }
    eprintln!("noisy scenes: {failures} of 500 builds refused");
}

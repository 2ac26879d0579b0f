//! The experiment set-ups of the views real photos showed ([`VIEW_SETUPS`]): face-on boxes,
//! hidden base corners, boxes with their own yaw. Checked against the independent synthetic
//! camera's truth.

use vpmap_metrology::error::MetrologyError;
use vpmap_metrology::eval::{VIEW_SETUPS, noise_seed, noisy_scene, scene_seed};
use vpmap_metrology::map::{BuildOptions, build_map};
use vpmap_metrology::reconstruct::Method;
use vpmap_metrology::scene::{BoxView, ObjectShape};
use vpmap_metrology::synth::{Annotation, synthesize};

use crate::{assert_camera_matches, max_relative_error};

fn fit(sigma_px: f64) -> BuildOptions {
    BuildOptions {
        method: Method::Fit,
        click_sigma_px: Some(sigma_px),
    }
}

#[test]
fn every_view_setup_is_reproduced_exactly_by_the_fit() {
    for setup in &VIEW_SETUPS {
        for trial in 0..4 {
            let seed = scene_seed(3, setup, trial);
            let (scene, truth) = synthesize(&setup.synth_options(seed)).unwrap();
            // The vanishing points as the exact edges through the exact corners.
            let exact = noisy_scene(&scene, 0.0, noise_seed(seed, 0.0));
            for vp in &exact.vanishing_points {
                assert!(vp.point.is_none() && vp.lines.len() >= 2, "{}", setup.name);
            }
            let map = build_map(&exact, &fit(0.0))
                .unwrap_or_else(|e| panic!("{} trial {trial}: {e}", setup.name));
            let context = format!("{} trial {trial}", setup.name);
            assert_camera_matches(&map, &truth, &context);
            let err = max_relative_error(&map, &truth);
            assert!(err < 1e-9, "{context}: {err:e}");
        }
    }
}

#[test]
fn the_side_view_and_projective_methods_refuse_face_and_hidden_views_and_read_own_yaw() {
    for setup in &VIEW_SETUPS {
        let seed = scene_seed(3, setup, 1);
        let (scene, truth) = synthesize(&setup.synth_options(seed)).unwrap();
        let exact = noisy_scene(&scene, 0.0, noise_seed(seed, 0.0));
        for method in [Method::Sideview, Method::Projective] {
            let built = build_map(
                &exact,
                &BuildOptions {
                    method,
                    click_sigma_px: None,
                },
            );
            match setup.annotation {
                Annotation::FaceOn | Annotation::HiddenBase => {
                    let Err(MetrologyError::InvalidField { reason, .. }) = &built else {
                        panic!("{} {method}: {built:?}", setup.name)
                    };
                    assert!(reason.contains("(fit) reads any corners"), "{reason}");
                }
                Annotation::OwnYaw => {
                    let map = built.unwrap_or_else(|e| panic!("{} {method}: {e}", setup.name));
                    // The projective form puts each clicked corner on the floor, whatever
                    // the box's yaw; the side view draws the box along the room's directions.
                    let err = max_relative_error(&map, &truth);
                    if method == Method::Projective {
                        assert!(err < 1e-9, "{} {method}: {err:e}", setup.name);
                    } else {
                        assert!(err > 1e-3, "{} {method}: {err:e}", setup.name);
                    }
                }
                Annotation::Thesis => panic!("{} uses the thesis's annotation", setup.name),
            }
        }
    }
}

#[test]
fn each_view_clicks_the_corners_it_names() {
    for setup in &VIEW_SETUPS {
        let (scene, truth) = synthesize(&setup.synth_options(11)).unwrap();
        assert_eq!(scene.objects.len(), setup.objects());
        for (k, obj) in scene.objects.iter().enumerate().take(setup.boxes) {
            let ObjectShape::Box {
                view,
                base,
                top,
                own_yaw,
            } = obj.shape(k).unwrap()
            else {
                panic!("{} {}: not a box", setup.name, obj.name)
            };
            let names = |c: &vpmap_metrology::scene::BoxCorners| {
                c.given().map(|(c, _)| c.name()).collect::<Vec<_>>()
            };
            let (want_view, want_base, want_top): (BoxView, &[&str], &[&str]) =
                match setup.annotation {
                    Annotation::FaceOn => (
                        BoxView::Face,
                        &["front_left", "front_right"],
                        &["front_left", "front_right", "back_left", "back_right"],
                    ),
                    Annotation::HiddenBase => (
                        BoxView::Corner,
                        &["near"],
                        &["near", "right", "left", "far"],
                    ),
                    _ => (
                        BoxView::Corner,
                        &["near", "right", "left"],
                        &["near", "left"],
                    ),
                };
            assert_eq!(view, want_view, "{}", setup.name);
            assert_eq!(names(base), want_base, "{}", setup.name);
            assert_eq!(names(&top), want_top, "{}", setup.name);
            assert_eq!(
                own_yaw,
                setup.annotation == Annotation::OwnYaw && k % 2 == 1,
                "{} {}",
                setup.name,
                obj.name
            );
            // Boxes whose top face is clicked are lower than the camera.
            if matches!(
                setup.annotation,
                Annotation::FaceOn | Annotation::HiddenBase
            ) {
                assert!(truth.objects[k].height < setup.height_m, "{}", setup.name);
            }
            // Face-on: the front edge (0,0)-(1,0) is turned 3-10 degrees from the image
            // plane's horizontal, and left of right in the image.
            if setup.annotation == Annotation::FaceOn {
                let [p, q] = [truth.objects[k].footprint[0], truth.objects[k].footprint[1]];
                let turn = (q[1] - p[1]).atan2(q[0] - p[0]).to_degrees();
                assert!((3.0..=10.0).contains(&turn.abs()), "{}: {turn}", setup.name);
                let (fl, fr) = (base.front_left.unwrap(), base.front_right.unwrap());
                assert!(fl[0] < fr[0], "{}", setup.name);
            }
        }
    }
}

#[test]
fn own_yaw_boxes_give_the_room_vanishing_points_no_horizontal_edges() {
    let setup = VIEW_SETUPS.iter().find(|s| s.name == "3pp-yaw").unwrap();
    let (scene, _) = synthesize(&setup.synth_options(5)).unwrap();
    let lines = noisy_scene(&scene, 0.0, 1);
    // Every horizontal edge runs to its vanishing point: the own-yaw boxes' would not.
    for (k, vp) in lines.vanishing_points.iter().enumerate() {
        let p = scene.vanishing_points[k].point.unwrap();
        for l in &vp.lines {
            let (a, b) = ([l[2] - l[0], l[3] - l[1]], [p[0] - l[0], p[1] - l[1]]);
            let sine = (a[0] * b[1] - a[1] * b[0]).abs() / (a[0].hypot(a[1]) * b[0].hypot(b[1]));
            assert!(sine < 1e-9, "vanishing point {k}: {sine:e}");
        }
    }
    // The two room-aligned boxes' three horizontal edges each (base near-right, base
    // near-left, top near-left); every box's two vertical edges.
    let counts: Vec<usize> = lines
        .vanishing_points
        .iter()
        .map(|v| v.lines.len())
        .collect();
    assert_eq!(counts.iter().take(2).sum::<usize>(), 2 * 3, "{counts:?}");
    assert_eq!(counts[2], 2 * setup.boxes, "{counts:?}");
}

#[test]
fn noisy_view_scenes_build_with_error_bars() {
    for setup in &VIEW_SETUPS {
        let mut built = 0;
        for trial in 0..5 {
            let seed = scene_seed(3, setup, trial);
            let (scene, _) = synthesize(&setup.synth_options(seed)).unwrap();
            let noisy = noisy_scene(&scene, 1.0, noise_seed(seed, 1.0));
            if let Ok(map) = build_map(&noisy, &fit(1.0)) {
                built += 1;
                for o in &map.objects {
                    let u = o.uncertainty.as_ref().unwrap();
                    let c = u.centroid_covariance;
                    assert!(c[0][0] > 0.0 && c[0][0] * c[1][1] > c[0][1] * c[1][0]);
                }
            }
        }
        assert!(built >= 4, "{}: {built} of 5 built", setup.name);
    }
}

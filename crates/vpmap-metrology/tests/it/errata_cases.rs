//! The hand-picked cases of `../shared/thesis/errata.md`, each by name: where the printed
//! equations go wrong without the sign rules.

use nalgebra::{Vector2, Vector3};
use vpmap_metrology::calibration::Calibration;
use vpmap_metrology::map::{BuildOptions, build_map};
use vpmap_metrology::reconstruct::Method;
use vpmap_metrology::scene::{ImageSize, ScaleSpec, Scene};
use vpmap_metrology::synth::{PinholeCamera, SynthBox, Truth, render_scene};

use crate::max_relative_error;

/// The errata's camera: 1600 x 1200 px, focal 1000 px, principal point at the centre, 1.5 m
/// high (also used by the fit's tests).
pub(crate) fn camera(pitch_deg: f64, roll_deg: f64) -> PinholeCamera {
    PinholeCamera {
        image: ImageSize {
            width: 1600,
            height: 1200,
        },
        focal_px: 1000.0,
        principal_point_px: Vector2::new(800.0, 600.0),
        height_m: 1.5,
        pitch_rad: pitch_deg.to_radians(),
        roll_rad: roll_deg.to_radians(),
    }
}

fn room_axes(yaw_deg: f64) -> [Vector3<f64>; 2] {
    let y = yaw_deg.to_radians();
    [
        Vector3::new(y.cos(), y.sin(), 0.0),
        Vector3::new(-y.sin(), y.cos(), 0.0),
    ]
}

fn boxed(name: &str, corner: [f64; 2], a: f64, b: f64, height_m: f64, yaw_deg: f64) -> SynthBox {
    let y = yaw_deg.to_radians();
    SynthBox {
        name: name.to_owned(),
        corner: Vector2::new(corner[0], corner[1]),
        edge_a: Vector2::new(y.cos(), y.sin()) * a,
        edge_b: Vector2::new(-y.sin(), y.cos()) * b,
        height_m,
    }
}

fn build(
    cam: &PinholeCamera,
    boxes: &[SynthBox],
    floor: &[[f64; 2]],
    yaw_deg: f64,
) -> (Scene, Truth) {
    let floor: Vec<Vector2<f64>> = floor.iter().map(|p| Vector2::new(p[0], p[1])).collect();
    let (mut scene, truth) = render_scene(cam, room_axes(yaw_deg), boxes, &[], &floor).unwrap();
    scene.scale = Some(ScaleSpec {
        camera_height_m: Some(cam.height_m),
        ..ScaleSpec::default()
    });
    (scene, truth)
}

fn assert_exact(scene: &Scene, truth: &Truth) {
    for method in [Method::Sideview, Method::Projective, Method::Fit] {
        let map = build_map(
            scene,
            &BuildOptions {
                method,
                ..BuildOptions::default()
            },
        )
        .unwrap();
        let err = max_relative_error(&map, truth);
        assert!(err < 1e-9, "{method}: relative error {err:e}");
    }
}

/// Signed offset of a pixel from the principal point perpendicular to the horizon (up > 0).
fn offset_up(scene: &Scene, p: [f64; 2]) -> f64 {
    let vps = scene.resolve_vanishing_points().unwrap();
    let cal = Calibration::from_homogeneous(&vps, None, scene.image).unwrap();
    cal.frame.coords(Vector2::new(p[0], p[1])).y
}

#[test]
fn base_corners_above_and_below_the_principal_point() {
    // At 30 degrees pitch the principal point looks at the floor 2.6 m ahead: one box nearer
    // (base corner below O in the image, beta > 0), one farther (above O, beta < 0). Without
    // the signed beta of the errata, the far box's offset distance is wrong.
    let cam = camera(30.0, 0.0);
    let boxes = [
        boxed("near", [-0.3, 1.6], 0.5, 0.4, 0.6, 35.0),
        boxed("far", [0.4, 5.0], 0.8, 0.6, 0.9, 35.0),
    ];
    let (scene, truth) = build(
        &cam,
        &boxes,
        &[[-2.0, 1.2], [3.0, 1.2], [3.0, 8.0], [-2.0, 8.0]],
        35.0,
    );
    let near = scene.objects[0].base.unwrap().near.unwrap();
    let far = scene.objects[1].base.unwrap().near.unwrap();
    assert!(
        offset_up(&scene, near) < 0.0,
        "near box base must be below O"
    );
    assert!(offset_up(&scene, far) > 0.0, "far box base must be above O");
    assert_exact(&scene, &truth);
}

#[test]
fn top_corner_above_the_horizon() {
    // A box taller than the camera: its top corners are above the horizon (negative depth).
    let cam = camera(10.0, 0.0);
    let boxes = [
        boxed("ref", [-0.4, 2.0], 0.5, 0.5, 0.5, 30.0),
        boxed("cupboard", [0.6, 3.5], 0.6, 0.5, 2.2, 30.0),
    ];
    let (scene, truth) = build(
        &cam,
        &boxes,
        &[[-2.0, 1.5], [3.0, 1.5], [3.0, 7.0], [-2.0, 7.0]],
        30.0,
    );
    let vps = scene.resolve_vanishing_points().unwrap();
    let cal = Calibration::from_homogeneous(&vps, None, scene.image).unwrap();
    let top = scene.objects[1].top.unwrap().corners.near.unwrap();
    assert!(
        cal.frame.below_horizon_px(Vector2::new(top[0], top[1])) < 0.0,
        "the cupboard's top must lie above the horizon"
    );
    assert_exact(&scene, &truth);
}

#[test]
fn top_corner_above_the_horizon_two_point_perspective() {
    let cam = camera(0.0, 0.0);
    let boxes = [
        boxed("ref", [-0.4, 2.0], 0.5, 0.5, 0.5, 30.0),
        boxed("shelf", [0.6, 3.5], 0.6, 0.5, 1.9, 30.0),
    ];
    let (scene, truth) = build(
        &cam,
        &boxes,
        &[[-2.0, 1.5], [3.0, 1.5], [3.0, 7.0], [-2.0, 7.0]],
        30.0,
    );
    let top = scene.objects[1].top.unwrap().corners.near.unwrap();
    assert!(
        offset_up(&scene, top) > 0.0,
        "the shelf's top must lie above the horizon"
    );
    assert_exact(&scene, &truth);
}

#[test]
fn floor_corners_nearer_than_the_reference_object() {
    // h1 - hf < 0: the floor corner moves towards the station point.
    for pitch in [0.0, 30.0] {
        let cam = camera(pitch, 4.0);
        let boxes = [boxed("ref", [0.2, 3.5], 0.6, 0.5, 0.7, 40.0)];
        let (scene, truth) = build(
            &cam,
            &boxes,
            &[[-1.5, 2.2], [1.6, 2.1], [2.0, 6.0], [-1.8, 6.5]],
            40.0,
        );
        let base = scene.objects[0].base.unwrap().near.unwrap();
        assert!(
            offset_up(&scene, scene.floor[0]) < offset_up(&scene, base),
            "floor corner 0 must be nearer than the reference corner (lower in the image)"
        );
        assert_exact(&scene, &truth);
    }
}

#[test]
fn corners_on_both_sides_of_the_principal_point_with_roll() {
    // With roll, "above O" must be decided in the horizon frame, not by raw image rows
    // (Algorithm 1's `imcenter^y < v^y` test).
    let cam = camera(25.0, -9.0);
    let boxes = [
        boxed("a", [-1.2, 1.8], 0.4, 0.5, 0.8, 20.0),
        boxed("b", [1.0, 6.0], 0.7, 0.7, 1.2, 20.0),
    ];
    let (scene, truth) = build(
        &cam,
        &boxes,
        &[[-3.0, 1.5], [3.0, 1.5], [3.5, 9.0], [-3.0, 9.0]],
        20.0,
    );
    assert_exact(&scene, &truth);
}

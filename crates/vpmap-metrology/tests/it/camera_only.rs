//! The camera from vanishing points alone (no clicks, no objects), under every method, against
//! a pinhole camera written here: `K R` with the principal point off the image centre, the
//! room turned by a yaw, the camera pitched and rolled, the three vanishing points listed in
//! every order.

use nalgebra::{Matrix3, Vector2, Vector3};
use vpmap_metrology::map::{BuildOptions, FloorMap, build_map};
use vpmap_metrology::reconstruct::Method;
use vpmap_metrology::scene::Scene;

const WIDTH: u32 = 1600;
const HEIGHT: u32 = 1200;

/// An independent pinhole camera: camera frame x right, y down, z forward (OpenCV); world
/// frame x right, y forward, z up, the camera looking along +y before it is pitched down by
/// `pitch_deg` and rolled about its optical axis by `spin_deg`.
struct Pinhole {
    k: Matrix3<f64>,
    camera_from_world: Matrix3<f64>,
}

impl Pinhole {
    fn new(focal_px: f64, pp: [f64; 2], pitch_deg: f64, spin_deg: f64) -> Self {
        let level = Matrix3::new(1.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 1.0, 0.0);
        let (s, c) = pitch_deg.to_radians().sin_cos();
        let pitch = Matrix3::new(1.0, 0.0, 0.0, 0.0, c, -s, 0.0, s, c);
        let (s, c) = spin_deg.to_radians().sin_cos();
        let spin = Matrix3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0);
        Self {
            k: Matrix3::new(focal_px, 0.0, pp[0], 0.0, focal_px, pp[1], 0.0, 0.0, 1.0),
            camera_from_world: spin * pitch * level,
        }
    }

    /// A world direction's vanishing point, homogeneous pixels.
    fn vanishing_point(&self, d: Vector3<f64>) -> Vector3<f64> {
        self.k * self.camera_from_world * d
    }
}

/// The room's three directions: two horizontal ones turned by `yaw_deg` from world x, then up.
fn room(yaw_deg: f64) -> [Vector3<f64>; 3] {
    let (s, c) = yaw_deg.to_radians().sin_cos();
    [
        Vector3::new(c, s, 0.0),
        Vector3::new(-s, c, 0.0),
        Vector3::new(0.0, 0.0, 1.0),
    ]
}

fn point(v: Vector3<f64>) -> serde_json::Value {
    serde_json::json!({"point": [v.x / v.z, v.y / v.z]})
}

fn scene(entries: &[serde_json::Value]) -> Scene {
    let v = serde_json::json!({
        "version": 1,
        "image": {"width": WIDTH, "height": HEIGHT},
        "vanishing_points": entries,
    });
    Scene::from_json_str(&v.to_string()).unwrap_or_else(|e| panic!("{e}: {v}"))
}

fn build(scene: &Scene, method: Method) -> FloorMap {
    build_map(
        scene,
        &BuildOptions {
            method,
            ..BuildOptions::default()
        },
    )
    .unwrap_or_else(|e| panic!("{method}: {e}"))
}

const ORDERS: [[usize; 3]; 6] = [
    [0, 1, 2],
    [1, 0, 2],
    [0, 2, 1],
    [2, 0, 1],
    [1, 2, 0],
    [2, 1, 0],
];

/// The horizon's angle in the image (the line through the horizontal vanishing points,
/// pointing right), degrees: the roll as vpmap reports it.
fn horizon_deg(a: Vector3<f64>, b: Vector3<f64>) -> f64 {
    let mut d = Vector2::new(b.x / b.z - a.x / a.z, b.y / b.z - a.y / a.z);
    if d.x < 0.0 {
        d = -d;
    }
    d.y.atan2(d.x).to_degrees()
}

/// Angle difference of two undirected lines, degrees in `[0, 90]`.
fn line_gap_deg(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(180.0);
    d.min(180.0 - d)
}

#[test]
fn three_exact_vanishing_points_in_any_order_give_the_camera_under_every_method() {
    let pp = [812.375, 571.25];
    let focal = 1400.0;
    let mut cases = 0;
    for pitch in [0.5, 1.0, 5.0, 15.0, 30.0, 45.0, 60.0, -20.0] {
        for spin in [-8.0, 0.0, 5.0] {
            for yaw in [25.0, 40.0, 65.0] {
                let cam = Pinhole::new(focal, pp, pitch, spin);
                let vps = room(yaw).map(|d| cam.vanishing_point(d));
                let roll = horizon_deg(vps[0], vps[1]);
                for order in ORDERS {
                    let s = scene(&order.iter().map(|&i| point(vps[i])).collect::<Vec<_>>());
                    let context = format!("pitch {pitch} spin {spin} yaw {yaw} order {order:?}");
                    let fit = build(&s, Method::Fit);
                    for method in [Method::Fit, Method::Projective, Method::Sideview] {
                        let map = if method == Method::Fit {
                            fit.clone()
                        } else {
                            build(&s, method)
                        };
                        let c = &map.camera;
                        let pp_error = (c.principal_point[0] - pp[0])
                            .abs()
                            .max((c.principal_point[1] - pp[1]).abs());
                        assert!(
                            pp_error < 1e-9,
                            "{context} {method}: principal point {:?}",
                            c.principal_point
                        );
                        assert!(
                            (c.focal_px - focal).abs() < 1e-9,
                            "{context} {method}: focal {}",
                            c.focal_px
                        );
                        assert!(
                            (c.pitch_deg - pitch).abs() < 1e-9,
                            "{context} {method}: pitch {}",
                            c.pitch_deg
                        );
                        assert!(
                            (c.roll_deg - roll).abs() < 1e-9,
                            "{context} {method}: roll {} vs {roll}",
                            c.roll_deg
                        );
                        // The room's yaw: the first horizontal vanishing point listed.
                        let first = order.iter().copied().find(|&i| i != 2).unwrap_or(0);
                        let want = yaw + if first == 1 { 90.0 } else { 0.0 };
                        assert!(
                            line_gap_deg(c.room_yaw_deg, want) < 1e-7,
                            "{context} {method}: room yaw {} vs {want}",
                            c.room_yaw_deg
                        );
                        if order[2] == 2 {
                            assert!(
                                !map.warnings
                                    .iter()
                                    .any(|w| w.contains("taken as the vertical")),
                                "{context} {method}: {:?}",
                                map.warnings
                            );
                        } else {
                            assert!(
                                map.warnings
                                    .iter()
                                    .any(|w| w.contains("taken as the vertical")),
                                "{context} {method}: {:?}",
                                map.warnings
                            );
                        }
                    }
                    // The fit reports its principal point with error bars, in camera heights.
                    let u = fit.camera.uncertainty.expect("the fit's error bars");
                    assert!(u.principal_point_px_sd.is_some(), "{context}");
                    assert!(
                        u.focal_px_sd.is_finite() && u.focal_px_sd > 0.0,
                        "{context}"
                    );
                    assert!(u.room_yaw_deg_sd.is_finite(), "{context}");
                    assert!(
                        u.height_sd.abs() < f64::MIN_POSITIVE,
                        "{context}: no scale, no height to fix"
                    );
                    assert_eq!(fit.units, vpmap_metrology::map::Units::CameraHeights);
                    assert_eq!(
                        fit.fit.as_ref().map(|f| f.principal_point_fitted),
                        Some(true),
                        "{context}"
                    );
                    cases += 1;
                }
            }
        }
    }
    assert_eq!(cases, 8 * 3 * 3 * 6);
}

/// The standard deviation of a map's fitted principal point, pixels.
fn pp_sd(map: &FloorMap) -> [f64; 2] {
    map.camera
        .uncertainty
        .and_then(|u| u.principal_point_px_sd)
        .expect("a fitted principal point")
}

#[test]
fn a_far_vertical_vanishing_point_warns_that_the_principal_point_is_poorly_fixed() {
    // Nearly level: the vertical vanishing point 1400 / tan(0.5 deg) = 160,000 px away,
    // each point measured to 0.05 degree (as a careful hand-drawn one is).
    let cam = Pinhole::new(1400.0, [790.0, 610.0], 0.5, 2.0);
    let vps = room(35.0).map(|d| cam.vanishing_point(d));
    let measured = |v: Vector3<f64>| {
        let mut p = point(v);
        p["covariance_deg2"] = serde_json::json!([[0.0025, 0.0], [0.0, 0.0025]]);
        p
    };
    let map = build(&scene(&vps.map(measured)), Method::Fit);
    let sd = pp_sd(&map);
    assert!(sd[0] > 16.0, "sd {sd:?}");
    let warning = map
        .warnings
        .iter()
        .find(|w| w.contains("principal point") && w.contains("poorly fixed"))
        .unwrap_or_else(|| panic!("{:?}", map.warnings));
    assert!(
        warning.contains("vertical vanishing point lies"),
        "{warning}"
    );
    // ... and still exact.
    assert!((map.camera.principal_point[0] - 790.0).abs() < 1e-9);
    assert!((map.camera.focal_px - 1400.0).abs() < 1e-9);
    // Given bare, the points are facts (held to 0.001 degree, which is still 4 px along the
    // horizon here): they fix the principal point within the warning's 1 % of the diagonal,
    // and nothing is said.
    let map = build(&scene(&vps.map(point)), Method::Fit);
    let sd = pp_sd(&map);
    assert!(sd[0].hypot(sd[1]) < 10.0, "sd {sd:?}");
    assert!(
        !map.warnings.iter().any(|w| w.contains("principal point")),
        "{:?}",
        map.warnings
    );
    assert!((map.camera.principal_point[0] - 790.0).abs() < 1e-9);
}

#[test]
fn a_level_camera_with_the_vertical_given_as_a_direction_is_exact() {
    // Pitch 0: the vertical edges are parallel in the photo. The principal point on the
    // horizon is not fixed by the vanishing points: it is held at the image centre's foot.
    let centre = [f64::from(WIDTH) / 2.0, f64::from(HEIGHT) / 2.0];
    for spin in [0.0, 3.0, -6.0] {
        let cam = Pinhole::new(1250.0, centre, 0.0, spin);
        let vps = room(30.0).map(|d| cam.vanishing_point(d));
        let vertical = serde_json::json!({"direction": [vps[2].x, vps[2].y]});
        for at in 0..3 {
            let mut entries = vec![point(vps[0]), point(vps[1])];
            entries.insert(at, vertical.clone());
            let s = scene(&entries);
            for method in [Method::Fit, Method::Projective, Method::Sideview] {
                let map = build(&s, method);
                let c = &map.camera;
                let context = format!("spin {spin} direction at {at} {method}");
                assert!(
                    (c.focal_px - 1250.0).abs() < 1e-9,
                    "{context}: {}",
                    c.focal_px
                );
                assert!(c.pitch_deg.abs() < 1e-9, "{context}: pitch {}", c.pitch_deg);
                assert!(
                    (c.roll_deg - horizon_deg(vps[0], vps[1])).abs() < 1e-9,
                    "{context}: roll {}",
                    c.roll_deg
                );
                assert!(
                    (c.principal_point[0] - centre[0]).abs() < 1e-6
                        && (c.principal_point[1] - centre[1]).abs() < 1e-6,
                    "{context}: {:?}",
                    c.principal_point
                );
            }
        }
    }
}

#[test]
fn a_vanishing_point_direction_is_checked() {
    let cam = Pinhole::new(1250.0, [800.0, 600.0], 10.0, 0.0);
    let vps = room(30.0).map(|d| cam.vanishing_point(d));
    let cases = [
        (
            vec![
                point(vps[0]),
                point(vps[1]),
                serde_json::json!({"direction": [0.0, 0.0]}),
            ],
            "vanishing_points[2].direction",
            "zero vector",
        ),
        (
            vec![
                point(vps[0]),
                point(vps[1]),
                serde_json::json!({"direction": [0.0, 1.0], "point": [1.0, 2.0]}),
            ],
            "vanishing_points[2]",
            "not both",
        ),
        (
            vec![
                serde_json::json!({"direction": [1.0, 0.0]}),
                point(vps[1]),
                serde_json::json!({"direction": [0.0, 1.0]}),
            ],
            "vanishing_points[0].direction",
            "2 of them as directions",
        ),
        (
            vec![point(vps[0]), serde_json::json!({"direction": [1.0, 0.0]})],
            "vanishing_points[1].direction",
            "gives 2 vanishing points",
        ),
    ];
    for (entries, field, words) in cases {
        let v = serde_json::json!({
            "version": 1,
            "image": {"width": WIDTH, "height": HEIGHT},
            "vanishing_points": entries,
        });
        let e = Scene::from_json_str(&v.to_string())
            .unwrap_err()
            .to_string();
        assert!(e.contains(field) && e.contains(words), "{field}: {e}");
    }
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(2000))]

    /// The vertical vanishing point is found in any order for cameras held as people hold
    /// them: pitch 0.5-60 degrees either way, roll up to 10 degrees, walls 20-70 degrees
    /// from face-on.
    #[test]
    fn the_vertical_vanishing_point_is_found_in_any_order(
        pitch in 0.5f64..60.0,
        up in proptest::bool::ANY,
        spin in -10.0f64..10.0,
        yaw in 20.0f64..70.0,
        order in 0usize..6,
    ) {
        let cam = Pinhole::new(1100.0, [790.0, 620.0], if up { -pitch } else { pitch }, spin);
        let vps = room(yaw).map(|d| cam.vanishing_point(d));
        let listed: Vec<Vector3<f64>> = ORDERS[order].iter().map(|&i| vps[i] / vps[i].z).collect();
        let vertical = vpmap_metrology::calibration::vertical_index(&listed);
        proptest::prop_assert_eq!(vertical.map(|k| ORDERS[order][k]), Some(2));
    }
}

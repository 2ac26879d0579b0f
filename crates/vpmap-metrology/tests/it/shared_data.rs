//! The shared data sets: scenes from an independent simulator, and York Urban Database photos.
//! They live in `../shared/data` beside the workspace, not in the repository, so these tests
//! are `#[ignore]`d: a plain `cargo test` counts them as ignored (not as passed), and
//! `cargo test -- --ignored shared_data` runs them, failing when the data are absent.

use std::path::PathBuf;

use nalgebra::Vector2;
use vpmap_metrology::calibration::Calibration;
use vpmap_metrology::map::{BuildOptions, build_map};
use vpmap_metrology::reconstruct::Method;
use vpmap_metrology::scene::{ImageSize, Scene};
use vpmap_metrology::synth::Truth;

/// `../shared/data/<sub>`; fails, naming the folder, when it is absent.
fn shared(sub: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/data")
        .join(sub);
    assert!(
        dir.is_dir(),
        "shared data {} is absent (expected beside the project)",
        dir.display()
    );
    dir
}

#[test]
#[ignore = "needs ../shared/data/synthetic-scenes (absent from a fresh clone): cargo test -- --ignored shared_data"]
fn independent_synthetic_scenes_reconstruct_to_1e_9_m() {
    let dir = shared("synthetic-scenes");
    let mut seen = 0;
    let mut names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            p.extension().is_some_and(|e| e == "json")
                && !p.to_string_lossy().ends_with(".truth.json")
        })
        .collect();
    names.sort();
    for path in names {
        let scene = Scene::from_json_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
        let truth_path = path.with_extension("truth.json");
        let truth: Truth = serde_json::from_str(&std::fs::read_to_string(&truth_path).unwrap())
            .unwrap_or_else(|e| panic!("{}: {e}", truth_path.display()));
        for method in [Method::Sideview, Method::Projective, Method::Fit] {
            let map = build_map(
                &scene,
                &BuildOptions {
                    method,
                    ..BuildOptions::default()
                },
            )
            .unwrap();
            let name = path.file_name().unwrap().to_string_lossy();
            crate::assert_camera_matches(&map, &truth, &format!("{name} {method}"));
            for (m, t) in map.objects.iter().zip(&truth.objects) {
                for (a, b) in m.footprint.iter().zip(&t.footprint) {
                    let e = (a[0] - b[0]).hypot(a[1] - b[1]);
                    assert!(
                        e < 1e-9,
                        "{name} {method} {}: corner {a:?} vs {b:?}",
                        m.name
                    );
                }
                let e = (m.height.unwrap() - t.height).abs();
                assert!(
                    e < 1e-9,
                    "{name} {method} {}: height {:?} vs {}",
                    m.name,
                    m.height,
                    t.height
                );
            }
            for (a, b) in map.floor.iter().zip(&truth.floor) {
                let e = (a[0] - b[0]).hypot(a[1] - b[1]);
                assert!(e < 1e-9, "{name} {method}: floor {a:?} vs {b:?}");
            }
            assert_eq!(map.objects.len(), truth.objects.len());
            assert_eq!(map.floor.len(), truth.floor.len());
        }
        seen += 1;
    }
    assert_eq!(seen, 8, "expected the eight shared synthetic scenes");
}

#[derive(serde::Deserialize)]
struct Yud {
    width: u32,
    height: u32,
    #[serde(rename = "K")]
    k: [[f64; 3]; 3],
    vp_orthogonal_px: [[f64; 2]; 3],
    most_vertical_vp_index: usize,
}

#[test]
#[ignore = "needs ../shared/data/yud-train (absent from a fresh clone): cargo test -- --ignored shared_data"]
fn york_urban_orthogonal_vanishing_points_give_back_the_calibration() {
    let dir = shared("yud-train");
    let mut seen = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "json") {
            continue;
        }
        let yud: Yud = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
        let v = yud.most_vertical_vp_index;
        let mut vps: Vec<Vector2<f64>> = (0..3)
            .filter(|&i| i != v)
            .map(|i| Vector2::new(yud.vp_orthogonal_px[i][0], yud.vp_orthogonal_px[i][1]))
            .collect();
        vps.push(Vector2::new(
            yud.vp_orthogonal_px[v][0],
            yud.vp_orthogonal_px[v][1],
        ));
        let image = ImageSize {
            width: yud.width,
            height: yud.height,
        };
        let cal = Calibration::from_vanishing_points(&vps, None, image)
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let o = cal.principal_point_px();
        let name = path.display();
        assert!(
            (cal.focal_px - 674.918).abs() < 1e-3,
            "{name}: f = {}",
            cal.focal_px
        );
        assert!((o.x - 307.551).abs() < 1e-3, "{name}: ox = {}", o.x);
        assert!((o.y - 251.454).abs() < 1e-3, "{name}: oy = {}", o.y);
        assert!((cal.focal_px - yud.k[0][0]).abs() < 1e-6, "{name}: f vs K");
        seen += 1;
    }
    assert!(seen >= 50, "expected the YUD training images, found {seen}");
}

#[test]
#[ignore = "needs ../shared/data/yud-train (absent from a fresh clone): cargo test -- --ignored shared_data"]
fn york_urban_cameras_from_vanishing_points_alone_under_every_method() {
    // A scene of the three labelled orthogonal vanishing points and nothing else, in the
    // order the data set lists them (the vertical one second) and with the vertical one last:
    // every method, the default fit included, gives back K to 1e-6 px.
    let dir = shared("yud-train");
    let mut seen = 0;
    let mut names: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    names.sort();
    for path in names {
        let yud: Yud = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
        let v = yud.most_vertical_vp_index;
        let vertical_last: Vec<usize> = (0..3).filter(|&i| i != v).chain([v]).collect();
        for order in [vec![0, 1, 2], vertical_last] {
            let scene = serde_json::json!({
                "version": 1,
                "image": {"width": yud.width, "height": yud.height},
                "vanishing_points": order
                    .iter()
                    .map(|&i| serde_json::json!({"point": yud.vp_orthogonal_px[i]}))
                    .collect::<Vec<_>>(),
            });
            let scene = Scene::from_json_str(&scene.to_string()).unwrap();
            for method in [Method::Fit, Method::Projective, Method::Sideview] {
                let name = format!("{} {order:?} {method}", path.display());
                let map = build_map(
                    &scene,
                    &BuildOptions {
                        method,
                        ..BuildOptions::default()
                    },
                )
                .unwrap_or_else(|e| panic!("{name}: {e}"));
                let c = &map.camera;
                assert!(
                    (c.focal_px - yud.k[0][0]).abs() < 1e-6,
                    "{name}: f = {}",
                    c.focal_px
                );
                assert!(
                    (c.principal_point[0] - yud.k[0][2]).abs() < 1e-6
                        && (c.principal_point[1] - yud.k[1][2]).abs() < 1e-6,
                    "{name}: principal point {:?}",
                    c.principal_point
                );
                // The vertical vanishing point is reported last, wherever it was listed.
                let reported = c.vanishing_points[2];
                let want = yud.vp_orthogonal_px[v];
                assert!(
                    (reported[0] - want[0]).hypot(reported[1] - want[1])
                        < 1e-6 * want[0].hypot(want[1]).max(1.0),
                    "{name}: vertical {reported:?} vs {want:?}"
                );
            }
        }
        seen += 1;
    }
    assert!(seen >= 50, "expected the YUD training images, found {seen}");
}

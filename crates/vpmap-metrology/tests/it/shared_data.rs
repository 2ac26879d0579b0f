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

//! Rooms of several photos: the joint fit against the independent simulator's rooms
//! (`../shared/data/multiview-scenes`), and bad room files.

use std::path::PathBuf;

use serde::Deserialize;
use vpmap_metrology::map::{BuildOptions, FloorMap, build_map};
use vpmap_metrology::scene::Scene;

#[derive(Deserialize)]
struct RoomTruth {
    objects: Vec<TruthObject>,
    cameras: Vec<TruthCamera>,
}

#[derive(Deserialize)]
struct TruthObject {
    name: String,
    footprint: Vec<[f64; 2]>,
    height: f64,
}

#[derive(Deserialize)]
struct TruthCamera {
    position: [f64; 2],
    height: f64,
    focal_px: f64,
    pitch_deg: f64,
    roll_deg: f64,
    yaw_deg_in_frame: f64,
}

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

/// Largest distance from a truth corner to the nearest corner of the map's object.
fn footprint_error(map: &[[f64; 2]], truth: &[[f64; 2]]) -> f64 {
    truth
        .iter()
        .map(|t| {
            map.iter()
                .map(|m| (m[0] - t[0]).hypot(m[1] - t[1]))
                .fold(f64::INFINITY, f64::min)
        })
        .fold(0.0, f64::max)
}

/// The worst error in metres (positions, sizes, heights) and degrees/pixels of the cameras.
fn errors(map: &FloorMap, truth: &RoomTruth) -> (f64, f64) {
    let mut metres = 0.0f64;
    assert_eq!(map.objects.len(), truth.objects.len());
    for t in &truth.objects {
        let m = map
            .objects
            .iter()
            .find(|o| o.name == t.name)
            .unwrap_or_else(|| panic!("object {} missing", t.name));
        metres = metres.max(footprint_error(&m.footprint, &t.footprint));
        metres = metres.max((m.height.unwrap() - t.height).abs());
    }
    let mut camera = 0.0f64;
    assert_eq!(map.cameras.len(), truth.cameras.len());
    for (m, t) in map.cameras.iter().zip(&truth.cameras) {
        metres = metres
            .max((m.position[0] - t.position[0]).abs())
            .max((m.position[1] - t.position[1]).abs())
            .max((m.height - t.height).abs());
        // The simulator turns its yaw clockwise (from +y towards +x); the map's heading turns
        // counter-clockwise.
        let heading = m.heading_deg.unwrap();
        let d = (heading + t.yaw_deg_in_frame + 540.0).rem_euclid(360.0) - 180.0;
        camera = camera
            .max((m.focal_px - t.focal_px).abs())
            .max((m.pitch_deg - t.pitch_deg).abs())
            .max((m.roll_deg - t.roll_deg).abs())
            .max(d.abs());
    }
    (metres, camera)
}

#[test]
#[ignore = "needs ../shared/data/multiview-scenes (absent from a fresh clone): cargo test -- --ignored shared_data"]
fn shared_data_rooms_from_exact_clicks_reproduce_the_truth_to_1e_9_m() {
    let dir = shared("multiview-scenes");
    let mut paths: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            p.extension().is_some_and(|e| e == "json")
                && !p.to_string_lossy().ends_with(".truth.json")
        })
        .collect();
    paths.sort();
    assert!(
        paths.len() >= 8,
        "expected the eight rooms in {}",
        dir.display()
    );
    for path in paths {
        let scene = Scene::from_json_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
        let truth: RoomTruth = serde_json::from_str(
            &std::fs::read_to_string(path.with_extension("truth.json")).unwrap(),
        )
        .unwrap();
        let map = build_map(&scene, &BuildOptions::default())
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let (metres, camera) = errors(&map, &truth);
        println!(
            "{}: {} photos, worst {metres:.2e} m, cameras {camera:.2e} (px/deg); warnings {:?}",
            path.display(),
            scene.photo_count(),
            map.warnings
        );
        assert!(metres < 1e-9, "{}: {metres} m", path.display());
        assert!(camera < 1e-7, "{}: {camera}", path.display());
    }
}

//! Integration tests of vpmap-metrology: geometry against independent pinhole cameras.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::missing_panics_doc)]

mod bad_input;
mod camera_only;
mod covariances;
mod cropped;
mod errata_cases;
mod eval;
mod fit;
mod lens;
mod measured_vps;
mod placed_poorly;
mod random_scenes;
mod room_lens;
mod room_synth;
mod rooms;
mod rooms_noisy;
mod shared_data;
mod views;

use vpmap_metrology::map::FloorMap;
use vpmap_metrology::synth::Truth;

/// Largest coordinate error of a map against the truth, relative to the scene's extent
/// (largest distance of any true point from the station point), plus the largest relative
/// height error. Objects are compared corner by corner in order.
pub fn max_relative_error(map: &FloorMap, truth: &Truth) -> f64 {
    let extent = truth
        .objects
        .iter()
        .flat_map(|o| o.footprint.iter())
        .chain(truth.floor.iter())
        .map(|p| p[0].hypot(p[1]))
        .fold(0.0f64, f64::max)
        .max(truth.camera.height);
    let mut worst = 0.0f64;
    assert_eq!(map.objects.len(), truth.objects.len());
    for (m, t) in map.objects.iter().zip(&truth.objects) {
        assert_eq!(m.name, t.name);
        assert_eq!(m.footprint.len(), t.footprint.len(), "{}", t.name);
        for (a, b) in m.footprint.iter().zip(&t.footprint) {
            worst = worst.max((a[0] - b[0]).hypot(a[1] - b[1]) / extent);
        }
        let h = m.height.expect("height");
        worst = worst.max((h - t.height).abs() / t.height);
    }
    assert_eq!(map.floor.len(), truth.floor.len());
    for (a, b) in map.floor.iter().zip(&truth.floor) {
        worst = worst.max((a[0] - b[0]).hypot(a[1] - b[1]) / extent);
    }
    worst
}

/// The map's camera matches the truth: focal length to `1e-9` relative, pitch and roll to
/// `1e-9` degrees. `context` names the case in the failure message.
pub fn assert_camera_matches(map: &FloorMap, truth: &Truth, context: &str) {
    let (m, t) = (&map.camera, &truth.camera);
    assert!(
        (m.focal_px - t.focal_px).abs() < 1e-9 * t.focal_px,
        "{context}: focal {} vs {}",
        m.focal_px,
        t.focal_px
    );
    assert!(
        (m.pitch_deg - t.pitch_deg).abs() < 1e-9,
        "{context}: pitch {} vs {}",
        m.pitch_deg,
        t.pitch_deg
    );
    assert!(
        (m.roll_deg - t.roll_deg).abs() < 1e-9,
        "{context}: roll {} vs {}",
        m.roll_deg,
        t.roll_deg
    );
}

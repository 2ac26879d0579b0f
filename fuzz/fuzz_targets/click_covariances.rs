//! Click covariances (`click_covariances_px2`, as `vpmap snap` writes them) on the bundled
//! office scene: the input is a list of 33-byte records, each a click (one byte, an index into
//! the scene's clicked points) and its 2 x 2 matrix (four little-endian `f64`, any bits:
//! NaN, infinities, subnormals, 1e300). The scene's validation, then for an accepted set the
//! joint fit's floor map.
//!
//! Invariants: every refusal names the `click_covariances_px2` field and prints no number in
//! more than 20 digits; an accepted set's fit reports a finite pixel RMS and a finite
//! normalised RMS.
#![no_main]

use libfuzzer_sys::fuzz_target;
use vpmap_metrology::map::{BuildOptions, build_map};
use vpmap_metrology::scene::Scene;

/// The scene's clicked object points (the clicks a covariance weighs), as field paths.
fn click_fields(scene: &Scene) -> Vec<String> {
    let mut out = Vec::new();
    for (i, o) in scene.objects.iter().enumerate() {
        if let Some(b) = &o.base {
            out.extend(b.given().map(|(c, _)| format!("objects[{i}].base.{}", c.name())));
        }
        if let Some(t) = &o.top {
            out.extend(
                t.corners
                    .given()
                    .map(|(c, _)| format!("objects[{i}].top.{}", c.name())),
            );
            if t.point.is_some() {
                out.push(format!("objects[{i}].top.point"));
            }
        }
        if let Some(f) = &o.footprint {
            out.extend((0..f.len()).map(|k| format!("objects[{i}].footprint[{k}]")));
        }
    }
    out.extend((0..scene.floor.len()).map(|k| format!("floor[{k}]")));
    out
}

/// A digit run longer than 20 characters: a number printed in full instead of readably.
fn has_long_number(text: &str) -> bool {
    text.split(|c: char| !c.is_ascii_digit())
        .any(|run| run.len() > 20)
}

fuzz_target!(|data: &[u8]| {
    let Ok(mut scene) = Scene::from_json_str(include_str!("../../examples/office.json")) else {
        panic!("the bundled office scene does not read");
    };
    let fields = click_fields(&scene);
    for record in data.chunks_exact(33) {
        let Some(field) = fields.get(usize::from(record[0]) % fields.len()) else {
            return;
        };
        let mut v = [0.0; 4];
        for (k, slot) in v.iter_mut().enumerate() {
            let mut bytes = [0u8; 8];
            bytes.copy_from_slice(&record[1 + 8 * k..9 + 8 * k]);
            *slot = f64::from_le_bytes(bytes);
        }
        scene
            .click_covariances_px2
            .insert(field.clone(), [[v[0], v[1]], [v[2], v[3]]]);
    }
    if let Err(e) = scene.validate() {
        let message = e.to_string();
        if !message.contains("click_covariances_px2") {
            panic!("a refusal of a covariance names another field: {message}");
        }
        if has_long_number(&message) {
            panic!("a refusal prints a number in full: {message}");
        }
        return;
    }
    if let Ok(map) = build_map(&scene, &BuildOptions::default()) {
        let Some(fit) = &map.fit else {
            panic!("the fit's map has no fit report");
        };
        if !(fit.rms_residual_px.is_finite() && fit.rms_residual_px >= 0.0) {
            panic!("RMS residual {} px", fit.rms_residual_px);
        }
        let covariances = !scene.click_covariances_px2.is_empty();
        let normalised = fit.rms_normalised;
        if covariances && fit.clicks_with_covariance.is_some() {
            if !normalised.is_some_and(|n| n.is_finite() && n >= 0.0) {
                panic!("normalised RMS {normalised:?} with covariances");
            }
        } else if normalised.is_some() {
            panic!("normalised RMS {normalised:?} without covariances");
        }
    }
});

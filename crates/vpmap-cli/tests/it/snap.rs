//! `vpmap snap` end to end on a photo rendered from a synthetic scene (vpmap-vision's
//! renderer, the corners known), and its bad input.

use std::path::Path;

use vpmap_metrology::synth::{SynthOptions, synthesize};
use vpmap_vision::synthetic::photo::{PhotoOptions, render_photo};

use super::{files_in, vpmap};

fn read_json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// Each box click's exact corner and where the scene puts it.
type Pushed = Vec<([f64; 2], [f64; 2])>;

/// A rendered photo and its scene with every box click pushed `push` px off its corner.
fn setup(dir: &Path, push: [f64; 2]) -> (serde_json::Value, Pushed) {
    let (scene, truth) = synthesize(&SynthOptions {
        seed: 3,
        ..SynthOptions::default()
    })
    .unwrap();
    let photo = render_photo(&scene, &truth, &PhotoOptions::default()).unwrap();
    photo.image.save(dir.join("photo.png")).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&scene.to_json_string()).unwrap();
    let mut pairs = Vec::new();
    for o in v["objects"].as_array_mut().unwrap() {
        for level in ["base", "top"] {
            if let Some(corners) = o.get_mut(level).and_then(|c| c.as_object_mut()) {
                for (_, p) in corners.iter_mut() {
                    if let Some(a) = p.as_array_mut()
                        && a.len() == 2
                    {
                        let exact = [a[0].as_f64().unwrap(), a[1].as_f64().unwrap()];
                        let pushed = [exact[0] + push[0], exact[1] + push[1]];
                        *p = serde_json::json!(pushed);
                        pairs.push((exact, pushed));
                    }
                }
            }
        }
    }
    std::fs::write(dir.join("scene.json"), v.to_string()).unwrap();
    (v, pairs)
}

#[test]
fn snapped_clicks_move_towards_their_corners_and_build_with_their_covariances() {
    let dir = tempfile::tempdir().unwrap();
    let (_, pairs) = setup(dir.path(), [1.5, -1.0]);
    let out = dir.path().join("snapped.json");
    let o = vpmap(&[
        "snap",
        dir.path().join("photo.png").to_str().unwrap(),
        dir.path().join("scene.json").to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("px"), "each move is printed: {stdout}");
    let snapped = read_json(&out);
    let covs = snapped["click_covariances_px2"].as_object().unwrap();
    assert!(!covs.is_empty());
    // The pushed clicks (1.8 px off) come back closer to the corners than they were, in the
    // median over the box clicks.
    let mut after = Vec::new();
    for o in snapped["objects"].as_array().unwrap() {
        for level in ["base", "top"] {
            if let Some(c) = o.get(level).and_then(|c| c.as_object()) {
                for p in c.values().filter_map(|p| p.as_array()) {
                    if p.len() == 2 {
                        after.push([p[0].as_f64().unwrap(), p[1].as_f64().unwrap()]);
                    }
                }
            }
        }
    }
    assert_eq!(after.len(), pairs.len());
    let mut errors: Vec<f64> = pairs
        .iter()
        .zip(&after)
        .map(|((exact, _), got)| (got[0] - exact[0]).hypot(got[1] - exact[1]))
        .collect();
    errors.sort_by(f64::total_cmp);
    let median = errors[errors.len() / 2];
    assert!(
        median < 0.9,
        "median error after snapping {median} px (1.8 px before)"
    );
    // `vpmap build` reads the covariances.
    let build_out = dir.path().join("out");
    let o = vpmap(&[
        "build",
        out.to_str().unwrap(),
        "--out",
        build_out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let map = read_json(&build_out.join("map.json"));
    assert!(map["fit"]["clicks_with_covariance"].as_u64().unwrap() > 0);
    assert_eq!(map["fit"]["click_sigma_source"], "covariances");
}

/// `vpmap snap` fails with one line naming `needle`, and writes nothing.
fn refused(dir: &Path, photo: &Path, scene: &Path, needle: &str) {
    let out = dir.join("out").join("snapped.json");
    let o = vpmap(&[
        "snap",
        photo.to_str().unwrap(),
        scene.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "expected a refusal");
    assert!(
        stderr.starts_with("error: ") && stderr.contains(needle),
        "{needle:?} in {stderr}"
    );
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(
        files_in(&dir.join("out")).is_empty(),
        "nothing may be written"
    );
}

#[test]
fn a_click_outside_the_photo_a_size_mismatch_and_a_broken_photo_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let (v, _) = setup(dir.path(), [0.0, 0.0]);
    let photo = dir.path().join("photo.png");
    // A floor corner far outside the photo.
    let mut outside = v.clone();
    outside["floor"] = serde_json::json!([[100.0, 900.0], [5000.0, 900.0], [300.0, 1000.0]]);
    let p = dir.path().join("outside.json");
    std::fs::write(&p, outside.to_string()).unwrap();
    refused(dir.path(), &photo, &p, "5000");
    // The scene says another image size.
    let mut size = v.clone();
    size["image"]["width"] = serde_json::json!(800);
    let p = dir.path().join("size.json");
    std::fs::write(&p, size.to_string()).unwrap();
    refused(dir.path(), &photo, &p, "800");
    // A photo that is not an image.
    let broken = dir.path().join("broken.png");
    std::fs::write(&broken, b"not a photo at all").unwrap();
    refused(
        dir.path(),
        &broken,
        &dir.path().join("scene.json"),
        "broken.png",
    );
}

/// Regression: `vpmap snap` decoded the whole photo before comparing its size with the
/// scene's (1.9 s and 434 MB for a mismatched 8000 x 8000 photo). A PNG whose header claims
/// 12000 x 12000 pixels and holds none is refused for its size, from the header: decoding it
/// would have failed on the missing pixels instead.
#[test]
fn a_size_mismatch_is_refused_from_the_header_before_decoding() {
    let dir = tempfile::tempdir().unwrap();
    let _ = setup(dir.path(), [0.0, 0.0]);
    let claiming = dir.path().join("claiming.png");
    std::fs::write(&claiming, super::detect::png_claiming(12_000, 12_000)).unwrap();
    refused(
        dir.path(),
        &claiming,
        &dir.path().join("scene.json"),
        "but the photo is 12000 x 12000",
    );
}

/// Every box click of a scene's JSON, in the order `setup` pushed them.
fn box_clicks(v: &serde_json::Value) -> Vec<[f64; 2]> {
    let mut out = Vec::new();
    for o in v["objects"].as_array().unwrap() {
        for level in ["base", "top"] {
            if let Some(c) = o.get(level).and_then(|c| c.as_object()) {
                for p in c.values().filter_map(|p| p.as_array()) {
                    if p.len() == 2 {
                        out.push([p[0].as_f64().unwrap(), p[1].as_f64().unwrap()]);
                    }
                }
            }
        }
    }
    out
}

/// `vpmap snap` on a room of the same scene twice (both photos the rendered one): returns
/// the output as JSON with stdout and stderr.
fn snap_room(dir: &Path, photo: &Path, room: &serde_json::Value) -> (serde_json::Value, String) {
    let room_path = dir.join("room.json");
    std::fs::write(&room_path, room.to_string()).unwrap();
    let out = dir.join("snapped-room.json");
    let o = vpmap(&[
        "snap",
        photo.to_str().unwrap(),
        photo.to_str().unwrap(),
        room_path.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    (read_json(&out), stdout)
}

/// Regression: on a room file `vpmap snap` wrote `click_covariances_px2` at the room's top
/// level when nothing snapped (build then ignored it as an unknown field), and failed with
/// "the scene has no `objects[0].base.near`" when something did. Every photo is snapped on its
/// own photo and its covariances go inside it.
#[test]
fn a_room_is_snapped_photo_by_photo_with_covariances_inside_each_photo() {
    let dir = tempfile::tempdir().unwrap();
    let (v, pairs) = setup(dir.path(), [1.5, -1.0]);
    let room = serde_json::json!({"version": 1, "photos": [v, v]});
    // Something snaps.
    let (snapped, stdout) = snap_room(dir.path(), &dir.path().join("photo.png"), &room);
    assert!(snapped.get("click_covariances_px2").is_none(), "{snapped}");
    assert!(stdout.contains("photo 2"), "{stdout}");
    for k in 0..2 {
        let photo = &snapped["photos"][k];
        let covs = photo["click_covariances_px2"].as_object().unwrap();
        assert!(covs.contains_key("objects[0].base.near"), "{covs:?}");
        // The pushed clicks (1.8 px off) came back towards their corners, in the median.
        let mut errors: Vec<f64> = pairs
            .iter()
            .zip(box_clicks(photo))
            .map(|((exact, _), got)| (got[0] - exact[0]).hypot(got[1] - exact[1]))
            .collect();
        errors.sort_by(f64::total_cmp);
        assert!(errors[errors.len() / 2] < 0.9, "photo {k}: {errors:?}");
    }
    // Nothing snaps: on a blank photo every click stays, with the click noise's covariance,
    // written inside each photo.
    let blank = dir.path().join("blank.png");
    let size = (
        v["image"]["width"].as_u64().unwrap() as u32,
        v["image"]["height"].as_u64().unwrap() as u32,
    );
    image::DynamicImage::new_luma8(size.0, size.1)
        .save(&blank)
        .unwrap();
    let (kept, _) = snap_room(dir.path(), &blank, &room);
    assert!(kept.get("click_covariances_px2").is_none(), "{kept}");
    for k in 0..2 {
        let covs = kept["photos"][k]["click_covariances_px2"]
            .as_object()
            .unwrap();
        assert_eq!(
            covs["objects[0].base.near"],
            serde_json::json!([[4.0, 0.0], [0.0, 4.0]])
        );
        assert_eq!(kept["photos"][k]["objects"], v["objects"]);
    }
    // The room's covariances are read by build: no unknown-field warning.
    let kept_path = dir.path().join("snapped-room.json");
    let o = vpmap(&[
        "build",
        kept_path.to_str().unwrap(),
        "--out",
        dir.path().join("built").to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(!stderr.contains("unknown field"), "{stderr}");
    // One photo for a room of two is refused, naming both counts.
    let room_path = dir.path().join("room.json");
    refused(
        dir.path(),
        &dir.path().join("photo.png"),
        &room_path,
        "room of 2 photos but 1 photo file was given",
    );
}

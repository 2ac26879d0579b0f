//! Real photos with metric truth (`../shared/data/sunrgbd-dev`, three SUN RGB-D photos): the
//! README's flow with the vanishing points `detect` finds and the truth's box corners clicked
//! exactly. The error bars must hold the truth (issue 37): the truth inside the 95 % ellipse
//! for at least 80 % of the objects, none beyond a Mahalanobis distance squared of 20, the
//! median error at most 3 % of the distance. The truth is loose by a few centimetres, and photo
//! 000002's roll by about 2 degrees (its README), which is why the bounds are not tighter.
//! The camera's focal length, pitch, roll, principal point and room yaw are printed against
//! the truth's, with their standardised errors. `VPMAP_SUNRGBD_SCENES=DIR` writes each scene
//! built (`000003x4-scene.json`: photo 000003 enlarged four times) for `vpmap build`. The same
//! photos enlarged four times and cropped off their centres are checked too.

use std::path::PathBuf;

use vpmap_metrology::fit::CHI2_2DOF_95;
use vpmap_metrology::map::{BuildOptions, build_map};
use vpmap_metrology::scene::Scene;
use vpmap_vision::clicks::{scene_clicks, set_scene_click};
use vpmap_vision::photo::{PhotoLimits, decode_photo};
use vpmap_vision::scene::detected_scene;
use vpmap_vision::{DetectOptions, detect};

fn sunrgbd() -> Option<PathBuf> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/sunrgbd-dev");
    if dir.is_dir() {
        Some(dir)
    } else {
        eprintln!(
            "SKIPPED: {} is absent, so the SUN RGB-D photos were not checked",
            dir.display()
        );
        None
    }
}

/// One object: (photo, name, error m, Mahalanobis distance squared, distance from the camera m).
type Row = (String, String, f64, f64, f64);

/// Per object: (photo, name, error m, Mahalanobis distance squared, distance from the camera m),
/// with each photo enlarged `scale` times (Lanczos) and its clicks with it;
/// and the photos whose principal point prior the map widened (map/priors.rs).
/// With `crop`, each photo is cropped ([`crop_of`]) before anything else.
fn measure(dir: &std::path::Path, scale: u32, crop: bool) -> (Vec<Row>, Vec<String>) {
    let mut out = Vec::new();
    let mut widened = Vec::new();
    for id in ["000002", "000003", "000004"] {
        let folder = dir.join(id);
        let bytes = std::fs::read(folder.join(format!("{id}.jpg"))).unwrap();
        let mut photo = decode_photo(&bytes, &PhotoLimits::default()).unwrap().image;
        let [cx, cy, cw, ch] = if crop {
            crop_of(id)
        } else {
            [0, 0, photo.width(), photo.height()]
        };
        photo = photo.crop_imm(cx, cy, cw, ch);
        if scale > 1 {
            photo = photo.resize_exact(
                scale * photo.width(),
                scale * photo.height(),
                image::imageops::FilterType::Lanczos3,
            );
        }
        let det = detect(&photo, &DetectOptions::default()).unwrap();
        let detected = detected_scene(&det).unwrap();
        let mut scene: serde_json::Value = serde_json::from_str(&detected.json).unwrap();
        let clicked: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(folder.join("scene.json")).unwrap())
                .unwrap();
        for key in ["objects", "floor", "scale"] {
            if let Some(v) = clicked.get(key) {
                scene[key] = v.clone();
            }
        }
        let mut scene = Scene::from_json_str(&scene.to_string()).unwrap();
        // The clicks in the enlarged photo's pixels (a point x of the photo is at scale x).
        let factor = f64::from(scale);
        for click in scene_clicks(&scene.clone()) {
            let p = click.point_px;
            assert!(set_scene_click(
                &mut scene,
                click.place,
                [
                    factor * (p[0] - f64::from(cx)),
                    factor * (p[1] - f64::from(cy))
                ]
            ));
        }
        if let Some(d) = std::env::var_os("VPMAP_SUNRGBD_SCENES") {
            std::fs::write(
                std::path::Path::new(&d).join(format!(
                    "{id}x{scale}{}-scene.json",
                    if crop { "-cropped" } else { "" }
                )),
                scene.to_json_string(),
            )
            .unwrap();
        }
        // vpmap build's map: the lens undistorted, its uncertainty in the error bars.
        let map = build_map(&scene, &BuildOptions::default()).unwrap();
        if map
            .warnings
            .iter()
            .any(|w| w.starts_with("the photo's edges and clicks put the principal point"))
        {
            widened.push(id.to_owned());
        }
        let truth: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(folder.join("truth.json")).unwrap())
                .unwrap();
        let (cam, u) = (&map.camera, map.camera.uncertainty.unwrap());
        let z = |key: &str, value: f64, sd: f64| {
            let t = truth["camera"][key].as_f64().unwrap();
            format!(
                "{key} {value:.2} +- {sd:.2} (true {t:.2}, z {:.2})",
                (value - t) / sd
            )
        };
        let pp = u.principal_point_px_sd.map_or_else(
            || "principal point held".to_owned(),
            |sd| {
                let t = &truth["camera"]["principal_point"];
                let axis = |k: usize| {
                    let t = t[k].as_f64().unwrap() - f64::from([cx, cy][k]);
                    let v = cam.principal_point[k];
                    format!(
                        "{v:.1} +- {:.1} (true {t:.1}, z {:.2})",
                        sd[k],
                        (v - t) / sd[k]
                    )
                };
                format!("principal point x {}, y {}", axis(0), axis(1))
            },
        );
        // The room's yaw modulo a quarter turn (detect's VP1 may be the truth's second).
        let true_yaw = truth["camera"]["room_yaw_deg"].as_f64().unwrap();
        let yaw_error = (cam.room_yaw_deg - true_yaw + 45.0).rem_euclid(90.0) - 45.0;
        eprintln!(
            "{id} camera: {}, {}, {}, {pp}, room yaw {:.2} +- {:.2} (true {true_yaw:.2}, z {:.2})",
            z("focal_px", cam.focal_px, u.focal_px_sd),
            z("pitch_deg", cam.pitch_deg, u.pitch_deg_sd),
            z("roll_deg", cam.roll_deg, u.roll_deg_sd),
            cam.room_yaw_deg,
            u.room_yaw_deg_sd,
            yaw_error / u.room_yaw_deg_sd
        );
        for t in truth["objects"].as_array().unwrap() {
            let name = t["name"].as_str().unwrap();
            let o = map.objects.iter().find(|o| o.name == name).unwrap();
            let c = nalgebra::Vector2::new(o.centroid[0], o.centroid[1]);
            let tc = nalgebra::Vector2::new(
                t["centroid"][0].as_f64().unwrap(),
                t["centroid"][1].as_f64().unwrap(),
            );
            let e = c - tc;
            let m = o.uncertainty.as_ref().unwrap().centroid_covariance;
            let cov = nalgebra::Matrix2::new(m[0][0], m[0][1], m[1][0], m[1][1]);
            let d2 = (e.transpose() * cov.try_inverse().unwrap() * e)[(0, 0)];
            out.push((id.to_owned(), name.to_owned(), e.norm(), d2, tc.norm()));
        }
    }
    (out, widened)
}

/// A crop of photo `id` keeping every click, `[left, top, width, height]`: the true principal
/// point 50-75 px (7-10 % of the crop's diagonal) off the crop's centre.
fn crop_of(id: &str) -> [u32; 4] {
    match id {
        "000002" => [150, 0, 580, 530],
        "000003" => [0, 100, 730, 430],
        _ => [0, 0, 600, 450],
    }
}

#[test]
#[ignore = "needs ../shared/data (run with -- --ignored shared_data)"]
fn shared_data_sunrgbd_detected_vanishing_points_error_bars_hold_the_truth() {
    let Some(dir) = sunrgbd() else { return };
    let (rows, widened) = measure(&dir, 1, false);
    check_sunrgbd(&rows);
    assert!(widened.is_empty(), "whole photos widened: {widened:?}");
}

/// The same photos cropped off their centres ([`crop_of`]), their clicks with them: detect's
/// prior puts the principal point at the crop's centre, 50-75 px from the truth (7-10 sd).
/// Held there, photos 000002 and 000004 put their boxes 61-89 cm off at a Mahalanobis distance
/// squared up to 47; a photo whose evidence rejects the prior must be built with it widened,
/// and hold the truth.
#[test]
#[ignore = "needs ../shared/data (run with -- --ignored shared_data)"]
fn shared_data_sunrgbd_cropped_off_centre_error_bars_hold_the_truth() {
    let Some(dir) = sunrgbd() else { return };
    let (rows, widened) = measure(&dir, 1, true);
    eprintln!("principal point prior widened for {widened:?}");
    for (id, name, e, d2, dist) in rows.iter().filter(|r| !widened.contains(&r.0)) {
        eprintln!(
            "{id} {name:15} error {:5.1} cm ({:.1} % of {dist:.2} m), Mahalanobis^2 {d2:.2}: not widened",
            100.0 * e,
            100.0 * e / dist
        );
    }
    // Photo 000002's evidence of its principal point is too weak to reject the prior (a
    // chi-square of 5.6 against 9.21; docs/results.md): at least the other two must be found,
    // and their maps hold the truth.
    assert!(widened.len() >= 2, "widened only {widened:?}");
    let kept: Vec<_> = rows
        .into_iter()
        .filter(|r| widened.contains(&r.0))
        .collect();
    check_sunrgbd(&kept);
}

/// The same photos enlarged four times (2920 x 2120, a phone's size), their clicks with them:
/// detect works on a downscaled copy, so the maps and their error bars must hold the truth as
/// well as at the photos' own size.
#[test]
#[ignore = "needs ../shared/data (run with -- --ignored shared_data)"]
fn shared_data_sunrgbd_enlarged_four_times_error_bars_hold_the_truth() {
    let Some(dir) = sunrgbd() else { return };
    let (rows, widened) = measure(&dir, 4, false);
    check_sunrgbd(&rows);
    assert!(widened.is_empty(), "whole photos widened: {widened:?}");
}

/// Issue 37's bounds on the SUN RGB-D objects of [`measure`]: the truth inside the 95 %
/// ellipse for at least 80 %, none beyond a Mahalanobis distance squared of 20, the median
/// error at most 3 % of the distance.
fn check_sunrgbd(rows: &[Row]) {
    for (id, name, e, d2, dist) in rows {
        eprintln!(
            "{id} {name:15} error {:5.1} cm ({:.1} % of {dist:.2} m), Mahalanobis^2 {d2:.2}",
            100.0 * e,
            100.0 * e / dist
        );
    }
    assert!(!rows.is_empty());
    let inside = rows.iter().filter(|r| r.3 <= CHI2_2DOF_95).count();
    assert!(
        inside * 10 >= rows.len() * 8,
        "{inside} of {} inside",
        rows.len()
    );
    let worst = rows.iter().map(|r| r.3).fold(0.0, f64::max);
    assert!(worst <= 20.0, "Mahalanobis distance squared up to {worst}");
    let mut relative: Vec<f64> = rows.iter().map(|r| r.2 / r.4).collect();
    relative.sort_by(f64::total_cmp);
    let n = relative.len();
    let median = 0.5 * (relative[(n - 1) / 2] + relative[n / 2]);
    assert!(median <= 0.03, "median error {:.1} %", 100.0 * median);
}

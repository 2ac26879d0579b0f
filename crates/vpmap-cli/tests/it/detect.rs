//! `vpmap detect` and `vpmap eval-detect` end to end, on photos rendered from a known camera
//! by `vpmap_vision::synthetic` (an independent ray caster), and on three York Urban photos
//! from `../shared/data/yud-train` (ignored unless asked: `cargo test -- --ignored shared_data`).

use std::path::{Path, PathBuf};

use image::{DynamicImage, GrayImage, ImageFormat, Luma};
use vpmap_metrology::map::calibrate;
use vpmap_metrology::scene::Scene;
use vpmap_vision::synthetic::{RenderedScene, SceneRenderOptions, render_manhattan_scene};

use super::{assert_fails_cleanly, files_in, vpmap};

/// A small synthetic photo (debug builds run the detector unoptimised).
fn render(pitch_deg: f64, roll_deg: f64, yaw_deg: f64, seed: u64) -> RenderedScene {
    render_manhattan_scene(&SceneRenderOptions {
        width_px: 400,
        height_px: 300,
        focal_px: 380.0,
        pitch_rad: pitch_deg.to_radians(),
        roll_rad: roll_deg.to_radians(),
        yaw_rad: yaw_deg.to_radians(),
        boxes: 6,
        seed,
        ..SceneRenderOptions::default()
    })
}

fn save(image: &DynamicImage, path: &Path) {
    image.save(path).unwrap();
}

/// Angle between the lines along `a` and `b`, degrees.
fn angle_deg(a: [f64; 3], b: [f64; 3]) -> f64 {
    let dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let na = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    let nb = (b[0] * b[0] + b[1] * b[1] + b[2] * b[2]).sqrt();
    (dot.abs() / (na * nb)).min(1.0).acos().to_degrees()
}

fn read_json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// Detect on a rendered photo; check the files, the vanishing points against the truth, the
/// focal length, and that `vpmap build` takes the scene without a warning once a floor and an
/// object are added.
fn detect_and_build(
    truth: &RenderedScene,
    extra_args: &[&str],
    expected_points: usize,
    perspective: &str,
    focal_tolerance: f64,
) {
    let dir = tempfile::tempdir().unwrap();
    let photo = dir.path().join("photo.png");
    save(&truth.image, &photo);
    let out = dir.path().join("out");
    let scene_path = out.join("scene.json");
    let overlay = out.join("overlay.png");
    let mut args = vec![
        "detect",
        photo.to_str().unwrap(),
        "--out",
        scene_path.to_str().unwrap(),
        "--overlay",
        overlay.to_str().unwrap(),
    ];
    args.extend(extra_args);
    let o = vpmap(&args);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{stderr}");
    assert!(stderr.is_empty(), "no warnings expected: {stderr}");
    assert_eq!(files_in(&out), ["overlay.png", "scene.json"]);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains(&format!("{perspective} perspective")) && stdout.contains("ms"),
        "{stdout}"
    );

    // The photo, then a legend strip under it with every colour the drawing uses.
    let drawn = image::open(&overlay).unwrap().to_rgb8();
    assert_eq!(drawn.width(), truth.image.width());
    assert!(drawn.height() > truth.image.height(), "no legend strip");
    let strip: std::collections::HashSet<[u8; 3]> = drawn
        .enumerate_pixels()
        .filter(|(_, y, _)| *y >= truth.image.height())
        .map(|(_, _, p)| p.0)
        .collect();
    for colour in [
        [235, 45, 45],
        [40, 205, 60],
        [40, 120, 255],
        [255, 215, 0],
        [255, 0, 255],
    ] {
        assert!(strip.contains(&colour), "{colour:?} is not in the legend");
    }
    // How to get `vpmap` for the next step (the summary is wrapped at spaces).
    let words = stdout.split_whitespace().collect::<Vec<_>>().join(" ");
    assert!(
        words.contains("cargo install --path crates/vpmap-cli"),
        "{stdout}"
    );

    let text = std::fs::read_to_string(&scene_path).unwrap();
    let scene = Scene::from_json_str(&text).unwrap();
    assert_eq!(scene.version, 1);
    assert_eq!(
        (scene.image.width, scene.image.height),
        (truth.image.width(), truth.image.height())
    );
    assert_eq!(scene.vanishing_points.len(), expected_points, "{text}");
    assert!(scene.objects.is_empty() && scene.floor.is_empty());
    let raw: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(
        raw["perspective"],
        if expected_points == 2 { "2pp" } else { "3pp" }
    );

    // Each written vanishing point, seen through the scene's own camera (as `vpmap build`
    // sees it), runs along a true direction: the horizontals in either order, the vertical
    // third.
    let focal = scene.focal_px.unwrap();
    let pp = scene.principal_point.unwrap();
    let ray = |p: [f64; 2]| [(p[0] - pp[0]) / focal, (p[1] - pp[1]) / focal, 1.0];
    let truth_dirs = truth.directions_camera;
    let mut horizontal_matches = Vec::new();
    for (i, vp) in scene.vanishing_points.iter().enumerate() {
        assert!(vp.lines.len() >= 2, "vanishing point {i} has no evidence");
        let r = ray(vp.point.unwrap());
        let err = if i == 2 {
            angle_deg(r, truth_dirs[2])
        } else {
            let (a, b) = (angle_deg(r, truth_dirs[0]), angle_deg(r, truth_dirs[1]));
            horizontal_matches.push(usize::from(b < a));
            a.min(b)
        };
        assert!(
            err < 1.5,
            "vanishing point {i}: {err:.2} deg off the truth\n{text}"
        );
    }
    assert_ne!(
        horizontal_matches[0], horizontal_matches[1],
        "both horizontal vanishing points match one direction\n{text}"
    );

    let focal_error = focal / truth.intrinsics.focal_px - 1.0;
    assert!(
        focal_error.abs() < focal_tolerance,
        "focal {focal} px, off by {focal_error:.3}"
    );
    // The metrology recovers the same camera from the written points, without a warning.
    let cal = calibrate(&scene).unwrap();
    assert!(cal.warnings.is_empty(), "{:?}", cal.warnings);
    assert!((cal.focal_px - focal).abs() < 1e-3 * focal);

    // The user adds a floor and an object; `vpmap build` takes it without a warning.
    let (w, h) = (
        f64::from(truth.image.width()),
        f64::from(truth.image.height()),
    );
    let mut edited = raw.clone();
    edited["floor"] = serde_json::json!([
        [0.0, h - 1.0],
        [w - 1.0, h - 1.0],
        [w - 1.0, 0.8 * h],
        [0.0, 0.8 * h]
    ]);
    edited["objects"] = serde_json::json!([{
        "name": "mat",
        "footprint": [[0.4 * w, 0.9 * h], [0.6 * w, 0.9 * h], [0.5 * w, 0.95 * h]]
    }]);
    std::fs::write(&scene_path, edited.to_string()).unwrap();
    let built = dir.path().join("built");
    let o = vpmap(&[
        "build",
        scene_path.to_str().unwrap(),
        "--out",
        built.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{stderr}");
    assert!(stderr.is_empty(), "vpmap build warned: {stderr}");
    let map = read_json(&built.join("map.json"));
    assert_eq!(
        map["camera"]["perspective"],
        perspective_key(expected_points)
    );
    assert_eq!(map["objects"].as_array().unwrap().len(), 1);
}

fn perspective_key(points: usize) -> &'static str {
    if points == 2 { "2pp" } else { "3pp" }
}

#[test]
fn detect_three_point_synthetic_photo_then_build() {
    let truth = render(25.0, 3.0, 30.0, 1);
    detect_and_build(&truth, &[], 3, "three-point", 0.04);
}

#[test]
fn detect_level_synthetic_photo_writes_its_measured_tilt() {
    let truth = render(0.0, -2.0, 35.0, 2);
    // A level camera fixes the focal length only through the two horizontal vanishing
    // points' distance along the horizon, which short floor edges measure less well. Its
    // measured tilt is small but not zero: the far vertical point is written, three-point.
    detect_and_build(&truth, &[], 3, "three-point", 0.10);
}

#[test]
fn detect_level_synthetic_photo_within_the_two_point_tolerance_leaves_the_vertical_out() {
    let truth = render(0.0, -2.0, 35.0, 2);
    detect_and_build(
        &truth,
        &["--two-point-tolerance", "3"],
        2,
        "two-point",
        0.10,
    );
}

#[test]
fn detect_with_known_intrinsics_keeps_them() {
    let truth = render(20.0, 0.0, 25.0, 3);
    let dir = tempfile::tempdir().unwrap();
    let photo = dir.path().join("photo.png");
    save(&truth.image, &photo);
    let scene_path = dir.path().join("scene.json");
    let k = truth.intrinsics;
    let o = vpmap(&[
        "detect",
        photo.to_str().unwrap(),
        "--out",
        scene_path.to_str().unwrap(),
        "--focal-px",
        &k.focal_px.to_string(),
        "--principal-point",
        &format!("{},{}", k.principal_point_px[0], k.principal_point_px[1]),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("(given)"), "{stdout}");
    let scene = Scene::from_json_str(&std::fs::read_to_string(&scene_path).unwrap()).unwrap();
    assert!((scene.focal_px.unwrap() - k.focal_px).abs() < 1e-2);
    let pp = scene.principal_point.unwrap();
    assert!(
        (pp[0] - k.principal_point_px[0]).abs() + (pp[1] - k.principal_point_px[1]).abs() < 1e-2
    );
    assert!(calibrate(&scene).unwrap().warnings.is_empty());
}

/// A PNG whose header claims `width` x `height` pixels, with an empty data chunk (the shape
/// of a decompression bomb, without the bomb).
pub(super) fn png_claiming(width: u32, height: u32) -> Vec<u8> {
    let mut ihdr = width.to_be_bytes().to_vec();
    ihdr.extend(height.to_be_bytes());
    ihdr.extend([8, 0, 0, 0, 0]); // 8-bit grey
    let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
    for (kind, data) in [(b"IHDR", ihdr), (b"IDAT", vec![]), (b"IEND", vec![])] {
        png.extend((data.len() as u32).to_be_bytes());
        let mut chunk = kind.to_vec();
        chunk.extend(data);
        png.extend(&chunk);
        png.extend(crc32fast::hash(&chunk).to_be_bytes());
    }
    png
}

fn png_bytes(image: &DynamicImage) -> Vec<u8> {
    let mut bytes = Vec::new();
    image
        .write_to(&mut std::io::Cursor::new(&mut bytes), ImageFormat::Png)
        .unwrap();
    bytes
}

#[test]
fn bad_photos_are_one_line_errors_and_write_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let scene = out.join("scene.json");
    let overlay = out.join("overlay.png");
    let run = |photo: &Path, needle: &str| {
        assert_fails_cleanly(
            &[
                "detect",
                photo.to_str().unwrap(),
                "--out",
                scene.to_str().unwrap(),
                "--overlay",
                overlay.to_str().unwrap(),
            ],
            &out,
            needle,
        );
    };
    let text = dir.path().join("notes.jpg");
    std::fs::write(&text, "this is not a photo\n").unwrap();
    run(&text, "is not a JPEG or PNG photo");

    let rendered = render(25.0, 0.0, 30.0, 4);
    let full = png_bytes(&rendered.image);
    let truncated = dir.path().join("truncated.png");
    std::fs::write(&truncated, &full[..full.len() / 2]).unwrap();
    run(&truncated, "cannot decode the PNG photo");

    let blank = dir.path().join("blank.png");
    save(
        &DynamicImage::ImageLuma8(GrayImage::from_pixel(320, 240, Luma([128]))),
        &blank,
    );
    run(&blank, "no vanishing points found in");

    let tiny = dir.path().join("tiny.png");
    save(
        &DynamicImage::ImageLuma8(GrayImage::from_pixel(8, 8, Luma([0]))),
        &tiny,
    );
    run(&tiny, "8 x 8 pixels");

    let huge = dir.path().join("huge.png");
    std::fs::write(&huge, png_claiming(100_000, 100_000)).unwrap();
    run(&huge, "100000 x 100000 pixels");

    run(&dir.path().join("missing.jpg"), "cannot read photo");
}

#[test]
fn bad_options_are_one_line_errors_and_write_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let photo = dir.path().join("photo.png");
    save(&render(25.0, 0.0, 30.0, 5).image, &photo);
    let out = dir.path().join("out");
    let scene = out.join("scene.json");
    let p = photo.to_str().unwrap();
    let s = scene.to_str().unwrap();
    for (extra, needle) in [
        (vec!["--focal-px", "-300"], "--focal-px must be a positive"),
        (vec!["--focal-px", "NaN"], "--focal-px must be a positive"),
        (vec!["--focal-px", "5"], "--focal-px 5 is outside"),
        (vec!["--principal-point", "200;150"], "is not a point X,Y"),
        (
            vec!["--principal-point", "-5,150"],
            "lies outside the 400 x 300 photo",
        ),
        (vec!["--two-point-tolerance", "90"], "--two-point-tolerance"),
        (vec!["--max-side", "10"], "--max-side"),
        (vec!["--overlay", "o.jpg"], "must be a .png file"),
    ] {
        let mut args = vec!["detect", p, "--out", s];
        args.extend(extra);
        assert_fails_cleanly(&args, &out, needle);
    }
    // The photo itself is never overwritten.
    let o = vpmap(&["detect", p, "--out", p]);
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("would overwrite the photo"));
    assert!(image::open(&photo).is_ok());
}

/// A York Urban label file for a rendered scene (directions turned to y up).
fn yud_label(truth: &RenderedScene) -> String {
    let k = truth.intrinsics;
    let dirs: Vec<[f64; 3]> = truth
        .directions_camera
        .iter()
        .map(|d| [d[0], -d[1], d[2]])
        .collect();
    serde_json::json!({
        "K": [
            [k.focal_px, 0.0, k.principal_point_px[0]],
            [0.0, k.focal_px, k.principal_point_px[1]],
            [0.0, 0.0, 1.0]
        ],
        "vp_dirs_camera_yup": dirs,
        "most_vertical_vp_index": 2,
    })
    .to_string()
}

#[test]
fn eval_detect_on_labelled_synthetic_photos() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data");
    std::fs::create_dir(&data).unwrap();
    for (name, truth) in [
        ("a", render(25.0, 2.0, 30.0, 6)),
        ("b", render(15.0, -3.0, 60.0, 7)),
    ] {
        truth.image.save(data.join(format!("{name}.png"))).unwrap();
        std::fs::write(data.join(format!("{name}.json")), yud_label(&truth)).unwrap();
    }
    // A photo the detector refuses is a failure in the report, not an abort.
    let blank = render(25.0, 0.0, 30.0, 8);
    save(
        &DynamicImage::ImageLuma8(GrayImage::from_pixel(400, 300, Luma([90]))),
        &data.join("c.png"),
    );
    std::fs::write(data.join("c.json"), yud_label(&blank)).unwrap();
    // Files without a partner are ignored.
    std::fs::write(data.join("README.json"), "{}").unwrap();

    let out = dir.path().join("report");
    let o = vpmap(&[
        "eval-detect",
        data.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for needle in [
        "within 3 deg",
        "AUC@10 deg",
        "focal error, median",
        "horizon AUC@0.25",
        "Lu et al.",
    ] {
        assert!(stdout.contains(needle), "{needle:?} missing:\n{stdout}");
    }
    assert_eq!(files_in(&out), ["eval-detect.json", "summary.md"]);
    let report = read_json(&out.join("eval-detect.json"));
    let photos = report["photos"].as_array().unwrap();
    assert_eq!(photos.len(), 3);
    assert!(photos[2]["given_intrinsics"]["refused"].is_string());
    for run in ["given_intrinsics", "estimated_intrinsics"] {
        let s = &report["summary"][run];
        assert_eq!(s["images"], 3, "{s}");
        assert_eq!(s["refused"], 1, "{s}");
        assert_eq!(s["missed"], 3, "{s}");
        for photo in &photos[..2] {
            for e in photo[run]["errors_deg"].as_array().unwrap() {
                let e = e.as_f64().unwrap();
                assert!(e < 1.5, "{run}: {e} deg in {photo}");
            }
        }
        // Two photos of three detected, all within 3 degrees.
        let within3 = s["within_deg"][1]["fraction"].as_f64().unwrap();
        assert!((within3 - 2.0 / 3.0).abs() < 1e-9, "{s}");
        // The rendered labels are exactly orthogonal, so both horizons of the truth agree; the
        // written horizon is within 5 % of the image height (a miss for the refused photo).
        for photo in &photos[..2] {
            let h = photo[run]["horizon_error"].as_f64().unwrap();
            let hh = photo[run]["horizon_error_against_labelled_horizontal_vps"]
                .as_f64()
                .unwrap();
            assert!(
                h < 0.05 && (h - hh).abs() < 1e-6,
                "{run}: {h}, {hh} in {photo}"
            );
        }
        assert!(photos[2][run]["horizon_error"].is_null());
        let auc = s["horizon_error"]["auc"].as_f64().unwrap();
        assert!(auc > 0.8 * 2.0 / 3.0 && auc <= 2.0 / 3.0, "{s}");
    }
    let focal = &report["summary"]["estimated_intrinsics"]["focal_error"];
    assert!(focal["within_fraction"].as_f64().unwrap() > 0.6, "{focal}");
    assert!(report["summary"]["given_intrinsics"]["focal_error"].is_null());
    let md = std::fs::read_to_string(out.join("summary.md")).unwrap();
    assert!(
        md.contains("| within 3 deg |") && md.contains("## Refused"),
        "{md}"
    );
}

#[test]
fn eval_detect_needs_labelled_photos() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("nowhere");
    let o = vpmap(&["eval-detect", missing.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("does not exist"), "{stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");

    std::fs::write(dir.path().join("lonely.jpg"), "x").unwrap();
    let out = dir.path().join("report");
    let o = vpmap(&[
        "eval-detect",
        dir.path().to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("no labelled photos in"), "{stderr}");
    assert!(!out.exists());
}

fn yud_train() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/yud-train")
}

#[test]
#[ignore = "needs ../shared/data/yud-train (absent from a fresh clone): cargo test -- --ignored shared_data"]
fn shared_data_eval_detect_on_three_york_urban_photos() {
    let data = yud_train();
    assert!(
        data.is_dir(),
        "{} is absent: this test needs ../shared/data",
        data.display()
    );
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("report");
    let o = vpmap(&[
        "eval-detect",
        data.to_str().unwrap(),
        "--limit",
        "3",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("(first 3 of"), "{stdout}");
    let report = read_json(&out.join("eval-detect.json"));
    assert_eq!(report["photos"].as_array().unwrap().len(), 3);
    let given = &report["summary"]["given_intrinsics"];
    assert_eq!(given["vanishing_points"], 9);
    // With the true camera, most labelled vanishing points are found within 5 degrees.
    let within5 = given["within_deg"][2]["fraction"].as_f64().unwrap();
    assert!(within5 >= 6.0 / 9.0, "{given}");
}

//! Real photos: a few York Urban Database images, against their hand-labelled vanishing
//! points. Skipped (with a message) when `../shared/data/yud-train` is absent.
//!
//! The bounds are 1.5 to 2.5 times the errors measured when the test was written (see the
//! comments), so they catch regressions without tripping on harmless changes. The whole
//! training half is measured by `cargo run --release -p vpmap-vision --example yud_eval`.

use std::path::PathBuf;

use vpmap_vision::metrics::{manhattan_errors_deg, median};
use vpmap_vision::{DetectOptions, Detection, detect};

const PHOTOS: [&str; 6] = [
    "P1020177", "P1020833", "P1040795", "P1080025", "P1080093", "P1080096",
];

fn data_dir() -> Option<PathBuf> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/yud-train");
    if dir.join("P1020177.jpg").is_file() {
        Some(dir)
    } else {
        println!("SKIPPED: {} is absent", dir.display());
        None
    }
}

struct Truth {
    directions: [[f64; 3]; 3],
    vertical: usize,
    focal_px: f64,
    principal_point_px: [f64; 2],
}

fn truth(dir: &std::path::Path, name: &str) -> Truth {
    let text = std::fs::read_to_string(dir.join(format!("{name}.json"))).expect("json");
    let v: serde_json::Value = serde_json::from_str(&text).expect("parse");
    let num = |x: &serde_json::Value| x.as_f64().expect("number");
    let mut directions = [[0.0; 3]; 3];
    for (k, d) in directions.iter_mut().enumerate() {
        let row = &v["vp_dirs_camera_yup"][k];
        // The file's camera frame has y up: flip it to y down.
        *d = [num(&row[0]), -num(&row[1]), num(&row[2])];
    }
    Truth {
        directions,
        vertical: usize::try_from(v["most_vertical_vp_index"].as_u64().expect("index"))
            .expect("small"),
        focal_px: num(&v["K"][0][0]),
        principal_point_px: [num(&v["K"][0][2]), num(&v["K"][1][2])],
    }
}

fn errors(found: &Detection, t: &Truth) -> [f64; 3] {
    let v = &found.vanishing_points;
    let dirs = [
        v[0].direction_camera,
        v[1].direction_camera,
        v[2].direction_camera,
    ];
    manhattan_errors_deg(&dirs, 2, &t.directions, t.vertical)
}

#[test]
fn yud_photos_with_and_without_the_true_intrinsics() {
    let Some(dir) = data_dir() else {
        return;
    };
    let (mut with_k, mut without_k, mut focal_errors) = (Vec::new(), Vec::new(), Vec::new());
    for name in PHOTOS {
        let t = truth(&dir, name);
        let image = image::open(dir.join(format!("{name}.jpg"))).expect("photo");
        let known = DetectOptions {
            focal_px: Some(t.focal_px),
            principal_point_px: Some(t.principal_point_px),
            ..DetectOptions::default()
        };
        let a = detect(&image, &known).expect("detect with intrinsics");
        let b = detect(&image, &DetectOptions::default()).expect("detect without intrinsics");
        let (ea, eb) = (errors(&a, &t), errors(&b, &t));
        let focal_error = (b.intrinsics.focal_px / t.focal_px - 1.0).abs();
        println!(
            "{name}: with K {ea:.2?} deg, without {eb:.2?} deg, focal error {:.1} %",
            100.0 * focal_error
        );
        with_k.extend(ea);
        without_k.extend(eb);
        focal_errors.push(focal_error);
    }
    let max = |v: &[f64]| v.iter().copied().fold(0.0f64, f64::max);
    // Measured: median 0.36, max 1.93 degrees with K.
    assert!(median(&with_k) < 0.8, "median with K {}", median(&with_k));
    assert!(max(&with_k) < 3.0, "max with K {}", max(&with_k));
    // Measured: median 0.82, max 1.66 degrees without K.
    assert!(
        median(&without_k) < 1.6,
        "median without K {}",
        median(&without_k)
    );
    assert!(max(&without_k) < 3.5, "max without K {}", max(&without_k));
    // Measured: median 1.7 %, max 3.6 %.
    assert!(
        median(&focal_errors) < 0.05,
        "median focal error {}",
        median(&focal_errors)
    );
    assert!(
        max(&focal_errors) < 0.08,
        "max focal error {}",
        max(&focal_errors)
    );
}

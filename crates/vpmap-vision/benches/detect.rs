//! `detect` on a 640 x 480 photo and on a 1600 x 1200 one, on one core (a rayon pool of one
//! thread: `lsdetect` would otherwise spread its image passes over every core).
//!
//! Compared side by side in one group: LSD alone (`lsdetect` on the grey image at its own
//! scale 0.8, the reference the crate builds on), `detect` with the intrinsics given and
//! `detect` estimating them (the lens estimated, the default), and estimating them with the
//! photo taken as a pinhole's (`--lens none`: what the lens estimate costs). Inputs: a
//! synthetic scene at both sizes, and a York Urban Database photo when
//! `../shared/data/yud-train` is present.
//!
//! ```text
//! cargo bench -p vpmap-vision --bench detect
//! ```
#![allow(missing_docs, clippy::expect_used)]

use std::hint::black_box;
use std::path::PathBuf;

use criterion::{Criterion, criterion_group, criterion_main};
use image::DynamicImage;
use vpmap_vision::synthetic::{SceneRenderOptions, render_manhattan_scene};
use vpmap_vision::{DetectOptions, LensOption, detect};

fn inputs() -> Vec<(String, DynamicImage, DetectOptions)> {
    let scene = render_manhattan_scene(&SceneRenderOptions::default());
    let known = DetectOptions {
        focal_px: Some(scene.intrinsics.focal_px),
        principal_point_px: Some(scene.intrinsics.principal_point_px),
        ..DetectOptions::default()
    };
    let large = render_manhattan_scene(&SceneRenderOptions {
        width_px: 1600,
        height_px: 1200,
        focal_px: 1400.0,
        ..SceneRenderOptions::default()
    });
    let large_known = DetectOptions {
        focal_px: Some(large.intrinsics.focal_px),
        principal_point_px: Some(large.intrinsics.principal_point_px),
        ..DetectOptions::default()
    };
    let mut out = vec![
        ("640x480/synthetic".to_owned(), scene.image, known),
        ("1600x1200/synthetic".to_owned(), large.image, large_known),
    ];
    let yud = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/data/yud-train/P1020177.jpg");
    match image::open(&yud) {
        Ok(photo) => out.push((
            "640x480/yud-P1020177".to_owned(),
            photo,
            DetectOptions {
                focal_px: Some(674.918),
                principal_point_px: Some([307.551, 251.454]),
                ..DetectOptions::default()
            },
        )),
        Err(_) => println!("SKIPPED the YUD photo: {} is absent", yud.display()),
    }
    out
}

fn bench_detect(c: &mut Criterion) {
    // One core. Ignored if a pool already exists (another bench in the same process).
    let _ = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build_global();
    for (name, image, known) in inputs() {
        let mut group = c.benchmark_group(format!("detect-{name}"));
        let grey = image.to_luma8();
        let (w, h) = (grey.width() as usize, grey.height() as usize);
        group.bench_function("lsdetect-only", |b| {
            b.iter(|| lsdetect::detect(black_box(grey.as_raw()), w, h, lsdetect::SCALE));
        });
        group.bench_function("detect-intrinsics-given", |b| {
            b.iter(|| detect(black_box(&image), &known).expect("detect"));
        });
        group.bench_function("detect-intrinsics-estimated", |b| {
            b.iter(|| detect(black_box(&image), &DetectOptions::default()).expect("detect"));
        });
        let pinhole = DetectOptions {
            lens: LensOption::Pinhole,
            ..DetectOptions::default()
        };
        group.bench_function("detect-intrinsics-estimated-lens-none", |b| {
            b.iter(|| detect(black_box(&image), &pinhole).expect("detect"));
        });
        group.finish();
    }
}

criterion_group!(benches, bench_detect);
criterion_main!(benches);

//! Snapping one click on a 1600 x 1200 photo (issue 31's budget: under 5 ms).
//!
//! Compared side by side in one group: `snap_click` on a box corner (the photo prepared once
//! with `SnapImage::new`), `snap_click` on a flat part of the floor (no corner: it stays),
//! `SnapImage::new` itself (the grey copy made once per photo), and, as the reference a
//! segment-based snapper would pay per photo, LSD at the photo's full size
//! (`detect_segments`). The photo is a rendered room (`synthetic::photo`).
//!
//! ```text
//! cargo bench -p vpmap-vision --bench snap
//! ```
#![allow(missing_docs, clippy::expect_used)]

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use vpmap_metrology::synth::{SynthOptions, synthesize};
use vpmap_vision::snap::scene::scene_vanishing_points;
use vpmap_vision::snap::{SnapImage, SnapOptions, snap_click};
use vpmap_vision::synthetic::photo::{CornerKind, PhotoOptions, render_photo};
use vpmap_vision::{DetectOptions, detect_segments};

fn bench(c: &mut Criterion) {
    let (scene, truth) = synthesize(&SynthOptions::default()).expect("scene");
    let photo = render_photo(&scene, &truth, &PhotoOptions::default()).expect("photo");
    let image = SnapImage::new(&photo.image);
    let vps = scene_vanishing_points(&scene).expect("vanishing points");
    let corner = photo
        .corners
        .iter()
        .find(|c| c.visible && c.kind == CornerKind::BoxCorner)
        .expect("a visible box corner");
    let click = [corner.point_px[0] + 1.5, corner.point_px[1] - 1.0];
    let opts = SnapOptions::for_click_sigma(2.0);
    assert!(
        snap_click(&image, &vps, click, &opts)
            .expect("snap")
            .snapped()
    );
    // The floor half-way between the image's bottom corners' floor clicks: flat.
    let flat = [800.0, 1190.0];
    let mut group = c.benchmark_group("snap one click, 1600 x 1200");
    group.bench_function("snap_click (box corner)", |b| {
        b.iter(|| snap_click(&image, &vps, black_box(click), &opts));
    });
    group.bench_function("snap_click (flat floor)", |b| {
        b.iter(|| snap_click(&image, &vps, black_box(flat), &opts));
    });
    group.bench_function("SnapImage::new (once per photo)", |b| {
        b.iter(|| SnapImage::new(black_box(&photo.image)));
    });
    group.sample_size(10);
    let full = DetectOptions {
        max_side_px: 1600,
        ..DetectOptions::default()
    };
    group.bench_function("reference: LSD at full size (once per photo)", |b| {
        b.iter(|| detect_segments(black_box(&photo.image), &full));
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);

//! The joint fit of a room of 4 photos and 20 boxes (1 px of click noise, the vanishing points
//! given as the objects' own edges) beside the single-photo fit of a 20-object scene (the
//! reference, `build.rs`'s scene), in one group, side by side: the fit alone, then with its
//! error bars. `docs/results.md` reports the ratio.
#![allow(missing_docs, clippy::unwrap_used)]

use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use std::time::Duration;
use vpmap_metrology::fit::{FitOptions, fit_scene};
use vpmap_metrology::room::fit_room;
use vpmap_metrology::scene::Scene;
use vpmap_metrology::synth::{
    RoomSynthOptions, SynthOptions, VanishingPointForm, synthesize, synthesize_room,
};

/// The click noise of the scenes and of the fits' error bars, pixels.
const SIGMA_PX: f64 = 1.0;

/// `build.rs`'s 20-object scene: 19 boxes and a pentagonal footprint.
fn photo_20() -> Scene {
    synthesize(&SynthOptions {
        seed: 20,
        boxes: 19,
        prisms: 1,
        pitch_deg: 30.0,
        roll_deg: 4.0,
        noise_px: SIGMA_PX,
        vanishing_points: VanishingPointForm::Lines,
        ..SynthOptions::default()
    })
    .unwrap()
    .0
}

/// A room of 4 photos and 20 boxes.
fn room_4x20() -> Scene {
    synthesize_room(&RoomSynthOptions {
        seed: 20,
        photos: 4,
        boxes: 20,
        noise_px: SIGMA_PX,
        vanishing_points: VanishingPointForm::Lines,
        ..RoomSynthOptions::default()
    })
    .unwrap()
    .0
}

fn bench_room(c: &mut Criterion) {
    let photo = photo_20();
    let room = room_4x20();
    assert_eq!(photo.objects.len(), 20);
    assert_eq!(room.photo_count(), 4);
    let options = FitOptions {
        click_sigma_px: Some(SIGMA_PX),
    };
    let room_objects = fit_room(&room).unwrap().objects.len();
    assert_eq!(room_objects, 20, "every box in some photo");
    let mut g = c.benchmark_group("fit_20_objects_one_photo_vs_room_of_4");
    g.measurement_time(Duration::from_secs(4));
    g.bench_function("fit_scene_1_photo", |b| {
        b.iter(|| fit_scene(black_box(&photo), &options));
    });
    g.bench_function("fit_room_4_photos", |b| {
        b.iter(|| fit_room(black_box(&room)));
    });
    g.bench_function("fit_scene_1_photo_and_uncertainty", |b| {
        b.iter(|| {
            fit_scene(black_box(&photo), &options)
                .and_then(|f| f.uncertainty(black_box(&photo), &options))
        });
    });
    g.bench_function("fit_room_4_photos_and_uncertainty", |b| {
        b.iter(|| {
            fit_room(black_box(&room)).and_then(|f| f.uncertainty(black_box(&room), &options))
        });
    });
    g.finish();
}

criterion_group!(benches, bench_room);
criterion_main!(benches);

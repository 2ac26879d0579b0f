//! Building a 20-object scene: the side-view method against the projective form (the
//! reference), calibration and reconstruction alone, and the whole map with free space.
#![allow(missing_docs, clippy::unwrap_used)]

use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use vpmap_metrology::map::{BuildOptions, build_map, reconstruct_scene};
use vpmap_metrology::reconstruct::Method;
use vpmap_metrology::synth::{SynthOptions, synthesize};

fn scene_20() -> vpmap_metrology::scene::Scene {
    synthesize(&SynthOptions {
        seed: 20,
        boxes: 16,
        prisms: 4,
        pitch_deg: 30.0,
        roll_deg: 4.0,
        ..SynthOptions::default()
    })
    .unwrap()
    .0
}

fn bench_build(c: &mut Criterion) {
    let scene = scene_20();
    let mut g = c.benchmark_group("reconstruct_20_objects");
    for method in [Method::Projective, Method::Sideview] {
        g.bench_function(method.to_string(), |b| {
            b.iter(|| reconstruct_scene(black_box(&scene), method));
        });
    }
    g.finish();
    let mut g = c.benchmark_group("build_map_20_objects");
    for method in [Method::Projective, Method::Sideview] {
        g.bench_function(method.to_string(), |b| {
            b.iter(|| {
                build_map(
                    black_box(&scene),
                    &BuildOptions {
                        method,
                        ..BuildOptions::default()
                    },
                )
            });
        });
    }
    g.finish();
}

criterion_group!(benches, bench_build);
criterion_main!(benches);

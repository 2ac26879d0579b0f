//! Building a 20-object scene (19 boxes and a pentagonal footprint object, 1 px of click noise,
//! the vanishing points given as the objects' own edges): the joint fit against the side-view
//! method and the projective form (the references) in one group, side by side; the fit's
//! parts (the fit alone, then with its error bars); and calibration with reconstruction alone
//! for the two closed-form methods. The fit also as `vpmap detect` writes a scene, with and
//! without a lens distortion's sd. And the error bars of a scene whose footprint object has
//! many vertices (an ellipse of 100 and 200 clicked vertices), which grow with the vertices.
#![allow(missing_docs, clippy::unwrap_used)]

use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use std::time::Duration;
use vpmap_metrology::fit::{FitOptions, fit_scene};
use vpmap_metrology::map::{BuildOptions, build_map, reconstruct_scene};
use vpmap_metrology::reconstruct::Method;
use vpmap_metrology::scene::{LensDistortion, Scene};
use vpmap_metrology::synth::{SynthOptions, VanishingPointForm, synthesize};

/// The click noise of the scene and of the fit's error bars, pixels.
const SIGMA_PX: f64 = 1.0;

fn scene_20() -> Scene {
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

/// `scene` with its vanishing points as points with a 1-degree covariance each, and a
/// principal point prior of 1.5 % of the image diagonal at the image centre.
fn measured_vanishing_points(scene: &Scene) -> Scene {
    let points = scene.resolve_vanishing_points().unwrap();
    let mut out = scene.clone();
    for (v, p) in out.vanishing_points.iter_mut().zip(points) {
        v.point = Some([p.x / p.z, p.y / p.z]);
        v.lines.clear();
        v.covariance_deg2 = Some([[1.0, 0.0], [0.0, 1.0]]);
    }
    out.principal_point_sd_px = Some(0.015 * scene.image.diagonal());
    out
}

fn bench_build(c: &mut Criterion) {
    let scene = scene_20();
    assert_eq!(scene.objects.len(), 20);
    let mut g = c.benchmark_group("build_map_20_objects");
    g.measurement_time(Duration::from_secs(3));
    for method in [Method::Fit, Method::Projective, Method::Sideview] {
        // Every method builds this scene (a refusal would time an early exit).
        build_map(
            &scene,
            &BuildOptions {
                method,
                click_sigma_px: Some(SIGMA_PX),
            },
        )
        .unwrap();
        g.bench_function(method.to_string(), |b| {
            b.iter(|| {
                build_map(
                    black_box(&scene),
                    &BuildOptions {
                        method,
                        click_sigma_px: Some(SIGMA_PX),
                    },
                )
            });
        });
    }
    // As `vpmap detect` writes a scene: measured vanishing points, the principal point a
    // prior, and the lens's k with its sd (k_sd's spread costs two refits from the fit's answer,
    // map/lens.rs and fit/lens.rs).
    let measured = measured_vanishing_points(&scene);
    let mut with_lens = measured.clone();
    with_lens.lens_distortion = Some(LensDistortion {
        k: 0.0,
        k_sd: Some(0.008),
    });
    for (name, s) in [
        ("fit, measured vanishing points", &measured),
        ("fit, measured vanishing points and a lens k_sd", &with_lens),
    ] {
        build_map(s, &BuildOptions::default()).unwrap();
        g.bench_function(name, |b| {
            b.iter(|| build_map(black_box(s), &BuildOptions::default()));
        });
    }
    g.finish();
    // The fit's parts: the Levenberg-Marquardt fit alone, and the fit with its error bars
    // (the rest of `build_map` is the free space and the occlusion shadows, as for the others).
    let mut g = c.benchmark_group("fit_20_objects");
    g.measurement_time(Duration::from_secs(3));
    let options = FitOptions {
        click_sigma_px: Some(SIGMA_PX),
    };
    g.bench_function("fit_scene", |b| {
        b.iter(|| fit_scene(black_box(&scene), &options));
    });
    g.bench_function("fit_scene_and_uncertainty", |b| {
        b.iter(|| {
            fit_scene(black_box(&scene), &options)
                .and_then(|f| f.uncertainty(black_box(&scene), &options))
        });
    });
    // As `vpmap detect` writes them: each vanishing point a point with a 1-degree covariance,
    // the principal point a prior, the click noise estimated (the fit's rounds to the noise at
    // which clicks and vanishing points agree included).
    let measured = measured_vanishing_points(&scene);
    let estimated = FitOptions::default();
    fit_scene(&measured, &estimated).unwrap();
    g.bench_function("fit_scene_measured_vanishing_points", |b| {
        b.iter(|| fit_scene(black_box(&measured), &estimated));
    });
    g.bench_function("fit_scene_measured_vanishing_points_and_uncertainty", |b| {
        b.iter(|| {
            fit_scene(black_box(&measured), &estimated)
                .and_then(|f| f.uncertainty(black_box(&measured), &estimated))
        });
    });
    g.finish();
    let mut g = c.benchmark_group("reconstruct_20_objects");
    g.measurement_time(Duration::from_secs(2));
    for method in [Method::Projective, Method::Sideview] {
        g.bench_function(method.to_string(), |b| {
            b.iter(|| reconstruct_scene(black_box(&scene), method));
        });
    }
    g.finish();
}

/// The default synthetic scene with its footprint object's clicks replaced by `n` vertices on
/// an ellipse around their centroid (a round table's outline clicked densely), the top click
/// above the first.
fn scene_with_footprint_of(n: usize) -> Scene {
    let (mut scene, _) = synthesize(&SynthOptions {
        seed: 3,
        ..SynthOptions::default()
    })
    .unwrap();
    let object = scene
        .objects
        .iter_mut()
        .find(|o| o.footprint.is_some())
        .unwrap();
    let fp = object.footprint.as_ref().unwrap();
    let k = fp.len() as f64;
    let (cx, cy) = (
        fp.iter().map(|p| p[0]).sum::<f64>() / k,
        fp.iter().map(|p| p[1]).sum::<f64>() / k,
    );
    let vertices: Vec<[f64; 2]> = (0..n)
        .map(|i| {
            let t = std::f64::consts::TAU * i as f64 / n as f64;
            [cx + 120.0 * t.cos(), cy + 50.0 * t.sin()]
        })
        .collect();
    let top = [vertices[0][0], vertices[0][1] - 400.0];
    object.footprint = Some(vertices);
    object.top = Some(vpmap_metrology::scene::TopSpec {
        above: Some(0),
        point: Some(top),
        ..Default::default()
    });
    scene
}

fn bench_many_vertices(c: &mut Criterion) {
    let mut g = c.benchmark_group("footprint_vertices");
    g.measurement_time(Duration::from_secs(3));
    g.sample_size(10);
    let options = FitOptions {
        click_sigma_px: Some(SIGMA_PX),
    };
    for n in [100, 200] {
        let scene = scene_with_footprint_of(n);
        fit_scene(&scene, &options)
            .and_then(|f| f.uncertainty(&scene, &options))
            .unwrap();
        g.bench_function(format!("fit_scene_and_uncertainty_{n}"), |b| {
            b.iter(|| {
                fit_scene(black_box(&scene), &options)
                    .and_then(|f| f.uncertainty(black_box(&scene), &options))
            });
        });
    }
    g.finish();
}

criterion_group!(benches, bench_build, bench_many_vertices);
criterion_main!(benches);

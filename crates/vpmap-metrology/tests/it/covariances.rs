//! Clicks with their own covariance (`click_covariances_px2`, as `vpmap snap` writes them):
//! validated by name and value, and weighted by the fit.

use vpmap_metrology::map::{BuildOptions, FloorMap, build_map};
use vpmap_metrology::scene::Scene;
use vpmap_metrology::synth::{SynthOptions, synthesize};

fn scene() -> Scene {
    let (scene, _) = synthesize(&SynthOptions {
        seed: 11,
        ..SynthOptions::default()
    })
    .unwrap();
    scene
}

/// Every clicked object point's field path.
fn box_fields(scene: &Scene) -> Vec<(String, [f64; 2])> {
    let mut out = Vec::new();
    for (i, o) in scene.objects.iter().enumerate() {
        if let Some(f) = &o.footprint {
            for (k, p) in f.iter().enumerate() {
                out.push((format!("objects[{i}].footprint[{k}]"), *p));
            }
        }
        if let Some(t) = o.top.as_ref().and_then(|t| t.point) {
            out.push((format!("objects[{i}].top.point"), t));
        }
        if let Some(b) = &o.base {
            for (c, p) in b.given() {
                out.push((format!("objects[{i}].base.{}", c.name()), p));
            }
        }
        if let Some(t) = &o.top {
            for (c, p) in t.corners.given() {
                out.push((format!("objects[{i}].top.{}", c.name()), p));
            }
        }
    }
    out
}

fn build(scene: &Scene, sigma: Option<f64>) -> FloorMap {
    scene.validate().unwrap_or_else(|e| panic!("{e}"));
    build_map(
        scene,
        &BuildOptions {
            click_sigma_px: sigma,
            ..BuildOptions::default()
        },
    )
    .unwrap_or_else(|e| panic!("{e}"))
}

fn error_of(scene: &Scene, text: &str) -> String {
    let mut v: serde_json::Value = serde_json::from_str(&scene.to_json_string()).unwrap();
    v["click_covariances_px2"] = serde_json::from_str(text).unwrap();
    Scene::from_json_str(&v.to_string())
        .unwrap_err()
        .to_string()
}

#[test]
fn covariances_are_checked_by_name_and_value() {
    let s = scene();
    let e = error_of(&s, r#"{"objects[0].base.nowhere": [[1, 0], [0, 1]]}"#);
    assert!(
        e.contains("objects[0].base.nowhere") && e.contains("names no click"),
        "{e}"
    );
    let e = error_of(&s, r#"{"objects[0].base.near": [[1, 2], [2, 1]]}"#);
    assert!(e.contains("not positive definite"), "{e}");
    let e = error_of(&s, r#"{"objects[0].base.near": [[1, 0.5], [0.2, 1]]}"#);
    assert!(e.contains("not symmetric"), "{e}");
    let e = error_of(&s, r#"{"objects[0].base.near": [[1e9, 0], [0, 1]]}"#);
    assert!(e.contains("beyond the supported"), "{e}");
    // A good one is accepted and written back.
    let mut v: serde_json::Value = serde_json::from_str(&s.to_json_string()).unwrap();
    v["click_covariances_px2"] =
        serde_json::json!({"objects[0].base.near": [[0.04, 0.01], [0.01, 0.09]]});
    let back = Scene::from_json_str(&v.to_string()).unwrap();
    assert_eq!(back.click_covariances_px2.len(), 1);
    assert!(back.to_json_string().contains("click_covariances_px2"));
}

#[test]
fn unit_covariances_give_the_fit_of_1_px_clicks_and_larger_ones_larger_error_bars() {
    // Every clicked point at covariance I px^2 is the fit of 1 px clicks: the same map and
    // the same error bars. At 4 I px^2 (2 px) every object's error bars grow.
    let mut s = scene();
    let all: Vec<(String, [f64; 2])> = box_fields(&s);
    for (f, _) in &all {
        s.click_covariances_px2
            .insert(f.clone(), [[1.0, 0.0], [0.0, 1.0]]);
    }
    let weighted = build(&s, None);
    let mut plain_scene = s.clone();
    plain_scene.click_covariances_px2.clear();
    let plain = build(&plain_scene, Some(1.0));
    let fit = weighted.fit.as_ref().unwrap();
    assert_eq!(fit.click_sigma_source, "covariances");
    assert_eq!(fit.clicks_with_covariance, Some(all.len()));
    assert_eq!(plain.fit.as_ref().unwrap().clicks_with_covariance, None);
    let mut wider = s.clone();
    for c in wider.click_covariances_px2.values_mut() {
        *c = [[4.0, 0.0], [0.0, 4.0]];
    }
    let wider = build(&wider, None);
    for ((a, b), c) in weighted
        .objects
        .iter()
        .zip(&plain.objects)
        .zip(&wider.objects)
    {
        assert_eq!(a.footprint, b.footprint);
        let (ua, ub, uc) = (
            a.uncertainty.as_ref().unwrap(),
            b.uncertainty.as_ref().unwrap(),
            c.uncertainty.as_ref().unwrap(),
        );
        assert_eq!(ua, ub);
        // Between 1 and 4 times: the vanishing points (given exactly) fix part of it.
        for (wide, unit) in [
            (uc.centroid_covariance[0][0], ua.centroid_covariance[0][0]),
            (uc.centroid_covariance[1][1], ua.centroid_covariance[1][1]),
        ] {
            assert!(
                wide > 1.2 * unit && wide <= 4.0 * unit * (1.0 + 1e-9),
                "{wide} vs {unit}"
            );
        }
    }
}

#[test]
fn a_click_uncertain_along_one_direction_is_not_believed_along_it() {
    // One corner pushed 25 px sideways. Told that this click is uncertain by 100 px sideways
    // (and sure to 0.1 px up and down), the fit all but ignores the push; told nothing, it
    // bends every size around it.
    let s = scene();
    let (field, p) = box_fields(&s)[0].clone();
    let truth = build(&s, Some(1.0));
    let mut pushed = s.clone();
    let i: usize = field["objects[".len()..field.find(']').unwrap()]
        .parse()
        .unwrap();
    let corner = field.rsplit('.').next().unwrap().to_owned();
    let moved = [p[0] + 25.0, p[1]];
    let b = pushed.objects[i].base.as_mut().unwrap();
    let slot = vpmap_metrology::scene::BoxCorner::ALL
        .into_iter()
        .find(|c| c.name() == corner)
        .unwrap();
    *b.get_mut(slot) = Some(moved);
    let plain = build(&pushed, Some(1.0));
    let mut told = pushed.clone();
    told.click_covariances_px2
        .insert(field.clone(), [[1e4, 0.0], [0.0, 0.01]]);
    let weighted = build(&told, Some(1.0));
    let err = |m: &FloorMap| {
        m.objects
            .iter()
            .zip(&truth.objects)
            .flat_map(|(a, b)| a.footprint.iter().zip(&b.footprint))
            .map(|(a, b)| (a[0] - b[0]).hypot(a[1] - b[1]))
            .fold(0.0, f64::max)
    };
    let (e_plain, e_weighted) = (err(&plain), err(&weighted));
    assert!(e_plain > 0.01, "the push must matter: {e_plain} m");
    assert!(
        e_weighted < 0.05 * e_plain,
        "weighted {e_weighted} m vs plain {e_plain} m"
    );
}

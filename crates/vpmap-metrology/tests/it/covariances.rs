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

/// A digit run longer than 20 characters: a number printed in full instead of readably.
fn has_long_number(text: &str) -> bool {
    text.split(|c: char| !c.is_ascii_digit())
        .any(|run| run.len() > 20)
}

/// Regression: covariances of 1e300 and 1e-300 px^2 were called "not positive definite" with
/// 300-digit numbers, and a 1e-20 px^2 variance was accepted (the fit then blamed the
/// vanishing points' edges). Each is refused for its range, naming the field and the value in
/// a few digits.
#[test]
fn covariances_out_of_range_are_refused_with_compact_values() {
    let s = scene();
    for (text, needles) in [
        (
            r#"{"objects[0].base.near": [[1e300, 0], [0, 1e300]]}"#,
            &[
                "x variance 1.000e300 px^2",
                "beyond the supported 1000000 px^2",
            ][..],
        ),
        (
            r#"{"objects[0].base.near": [[1e-300, 0], [0, 1e-300]]}"#,
            &[
                "x variance 1.000e-300 px^2",
                "below the supported 1.000e-12 px^2",
            ],
        ),
        (
            r#"{"objects[0].base.near": [[1, 0], [0, 1e-20]]}"#,
            &["y variance 1.000e-20 px^2", "below the supported"],
        ),
        (
            r#"{"objects[0].base.near": [[1e5, 0], [0, 1e-9]]}"#,
            &["nearly singular", "condition number 1.000e14"],
        ),
        (
            r#"{"objects[0].base.near": [[0, 0], [0, 1]]}"#,
            &["x variance 0 px^2 is not positive"],
        ),
    ] {
        let e = error_of(&s, text);
        assert!(
            e.contains("click_covariances_px2.\"objects[0].base.near\""),
            "{e}"
        );
        for needle in needles {
            assert!(e.contains(needle), "{needle:?} in {e}");
        }
        assert!(!has_long_number(&e) && e.len() < 300, "{e}");
    }
    // The ends of the range are accepted.
    for text in [
        r#"{"objects[0].base.near": [[1e6, 0], [0, 1e6]]}"#,
        r#"{"objects[0].base.near": [[1e-12, 0], [0, 1e-12]]}"#,
    ] {
        let mut v: serde_json::Value = serde_json::from_str(&s.to_json_string()).unwrap();
        v["click_covariances_px2"] = serde_json::from_str(text).unwrap();
        assert!(Scene::from_json_str(&v.to_string()).is_ok(), "{text}");
    }
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

/// Regression: with `click_covariances_px2` the summary's "reprojection RMS ... px" and a
/// misplaced click's "lies X px (X sigma)" were both in standard deviations of each click
/// (covariances of 1e-150 px^2 gave "RMS 7.6e61 px"). With every click at 0.1 px (0.01 I
/// px^2), a click's sigmas are its pixels over 0.1 px, and the pixel RMS is near that of
/// the fit of plain clicks (not ten times it: the weights move the fit a little, as the
/// vanishing points are not weighted by the clicks' covariances).
#[test]
fn residuals_with_covariances_are_reported_in_pixels_and_sigmas() {
    let mut s = scene();
    // One box corner 6 px off, to be warned about.
    let (i, corner) = s
        .objects
        .iter()
        .enumerate()
        .find_map(|(i, o)| {
            o.base
                .as_ref()
                .and_then(|b| b.given().next().map(|(c, _)| (i, c)))
        })
        .unwrap();
    let field = format!("objects[{i}].base.{}", corner.name());
    let mut v: serde_json::Value = serde_json::from_str(&s.to_json_string()).unwrap();
    let p = &mut v["objects"][i]["base"][corner.name()];
    p[0] = serde_json::json!(p[0].as_f64().unwrap() + 6.0);
    s = Scene::from_json_str(&v.to_string()).unwrap();
    let plain = build(&s, Some(0.1));
    let sd_px = 0.1;
    for (f, _) in box_fields(&s) {
        s.click_covariances_px2
            .insert(f, [[sd_px * sd_px, 0.0], [0.0, sd_px * sd_px]]);
    }
    let weighted = build(&s, None);
    let (pf, wf) = (plain.fit.as_ref().unwrap(), weighted.fit.as_ref().unwrap());
    assert_eq!(wf.click_sigma_source, "covariances");
    assert_eq!(pf.rms_normalised, None);
    let ratio = wf.rms_residual_px / pf.rms_residual_px;
    assert!(
        (0.5..2.0).contains(&ratio),
        "{} px with covariances, {} px without",
        wf.rms_residual_px,
        pf.rms_residual_px
    );
    let normalised = wf.rms_normalised.unwrap();
    assert!(
        (normalised - wf.rms_residual_px / sd_px).abs() < 1e-9 * normalised,
        "{normalised} sigma, {} px",
        wf.rms_residual_px
    );
    // "`FIELD` of object "NAME" lies X px (Y sigma) ...": Y is X over 0.1 px, to the
    // printed digits.
    let warning = weighted
        .warnings
        .iter()
        .find(|w| w.contains(&format!("`{field}`")) && w.contains(" lies "))
        .unwrap_or_else(|| panic!("{:?}", weighted.warnings));
    let numbers: Vec<f64> = warning
        .split(['(', ' '])
        .filter_map(|t| t.parse().ok())
        .collect();
    let [px, sigmas] = numbers[..] else {
        panic!("{warning}")
    };
    assert!(px > 2.0 && px < 8.0, "{warning}");
    assert!(
        (sigmas - px / sd_px).abs() <= 0.05 / sd_px + 0.05,
        "{warning}"
    );
}

/// The same for a room: the room fit's residuals are whitened where a photo's clicks have
/// covariances; the report gives them in pixels (near the plain room fit's) and the
/// normalised RMS in sigmas.
#[test]
fn a_rooms_residuals_with_covariances_are_reported_in_pixels_and_sigmas() {
    use vpmap_metrology::synth::{RoomSynthOptions, synthesize_room};
    let (mut room, _) = synthesize_room(&RoomSynthOptions {
        seed: 5,
        photos: 2,
        noise_px: 0.5,
        ..RoomSynthOptions::default()
    })
    .unwrap();
    let plain = build(&room, Some(0.1));
    let sd_px = 0.1;
    let cov = [[sd_px * sd_px, 0.0], [0.0, sd_px * sd_px]];
    for (f, _) in box_fields(&room) {
        room.click_covariances_px2.insert(f, cov);
    }
    for photo in &mut room.other_photos {
        for (f, _) in box_fields(photo) {
            photo.click_covariances_px2.insert(f, cov);
        }
    }
    let weighted = build(&room, None);
    let (pf, wf) = (plain.fit.as_ref().unwrap(), weighted.fit.as_ref().unwrap());
    assert_eq!(wf.click_sigma_source, "covariances");
    assert!(wf.clicks_with_covariance.unwrap() > 10);
    let ratio = wf.rms_residual_px / pf.rms_residual_px;
    assert!(
        (0.5..2.0).contains(&ratio),
        "{} px with covariances, {} px without",
        wf.rms_residual_px,
        pf.rms_residual_px
    );
    let normalised = wf.rms_normalised.unwrap();
    assert!(
        (normalised - wf.rms_residual_px / sd_px).abs() < 1e-6 * normalised,
        "{normalised} sigma, {} px",
        wf.rms_residual_px
    );
}

#[test]
fn a_rooms_residuals_are_pixels_and_its_normalised_ones_sigmas() {
    use vpmap_metrology::room::fit_room;
    use vpmap_metrology::synth::{RoomSynthOptions, synthesize_room};
    // Every object click of every photo at 4 I px^2 (2 px), on clicks 1 px off: the
    // misfits in pixels are about the unweighted fit's (the weights differ from the plain
    // fit's estimated ones only in scale), and in sigmas half of them. Reported in sigmas,
    // as before this test, the pixel RMS would come out at half the plain fit's.
    let (plain, _) = synthesize_room(&RoomSynthOptions {
        seed: 3,
        photos: 3,
        noise_px: 1.0,
        ..RoomSynthOptions::default()
    })
    .unwrap();
    let mut weighted = plain.clone();
    let add = |s: &mut Scene| {
        for (f, _) in box_fields(s) {
            s.click_covariances_px2.insert(f, [[4.0, 0.0], [0.0, 4.0]]);
        }
    };
    add(&mut weighted);
    for p in &mut weighted.other_photos {
        add(p);
    }
    let a = fit_room(&plain).unwrap_or_else(|e| panic!("{e}"));
    let b = fit_room(&weighted).unwrap_or_else(|e| panic!("{e}"));
    assert!(a.rms_residual_px > 0.3, "{}", a.rms_residual_px);
    assert!(
        (a.rms_residual_px - b.rms_residual_px).abs() < 0.05 * a.rms_residual_px,
        "{} px unweighted, {} px weighted",
        a.rms_residual_px,
        b.rms_residual_px
    );
    assert_eq!(a.point_residuals.len(), b.point_residuals.len());
    for ((ra, rb), w) in a
        .point_residuals
        .iter()
        .zip(&b.point_residuals)
        .zip(&b.weighted_residuals)
    {
        assert_eq!(ra.field, rb.field);
        assert!((rb.distance_px - 2.0 * w).abs() < 1e-9, "{rb:?} {w}");
    }
    // Unweighted, the weighed residuals are the pixels.
    for (r, w) in a.point_residuals.iter().zip(&a.weighted_residuals) {
        assert!((r.distance_px - w).abs() < 1e-12);
    }
    // The map reports the same: pixels as pixels, the normalised RMS in sigmas.
    let map = build_map(&weighted, &BuildOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let fit = map.fit.as_ref().unwrap();
    assert!((fit.rms_residual_px - b.rms_residual_px).abs() < 1e-9);
    let normalised = fit.rms_normalised.unwrap();
    assert!(
        (normalised - b.rms_residual_px / 2.0 / fit.click_sigma_px).abs() < 1e-9,
        "{normalised} vs {} / 2 / {}",
        b.rms_residual_px,
        fit.click_sigma_px
    );
}

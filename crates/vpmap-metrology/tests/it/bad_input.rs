//! Every kind of bad input named by the floor-maps issue gets a clear error naming the field
//! and the value, never a panic.

use vpmap_metrology::MetrologyError;
use vpmap_metrology::map::{BuildOptions, build_map};
use vpmap_metrology::reconstruct::Method;
use vpmap_metrology::scene::Scene;

fn base_scene() -> serde_json::Value {
    serde_json::json!({
        "version": 1,
        "image": {"width": 1600, "height": 1200},
        "vanishing_points": [{"point": [-900.0, 600.0]}, {"point": [2400.0, 600.0]}],
        "objects": [{
            "name": "desk",
            "base": {"near": [800.0, 900.0], "right": [1000.0, 850.0], "left": [600.0, 860.0]},
            "top": {"near": [800.0, 700.0]}
        }],
        "floor": [[100.0, 1100.0], [1500.0, 1100.0], [1300.0, 700.0], [300.0, 700.0]],
    })
}

/// The thesis's method: these cases name its checks (the fit's are below).
fn build(v: &serde_json::Value) -> Result<(), MetrologyError> {
    build_with(v, Method::Sideview)
}

fn build_with(v: &serde_json::Value, method: Method) -> Result<(), MetrologyError> {
    let scene = Scene::from_json_str(&v.to_string())?;
    build_map(
        &scene,
        &BuildOptions {
            method,
            ..BuildOptions::default()
        },
    )
    .map(|_| ())
}

#[test]
fn the_fit_refuses_what_cannot_be_a_scene_too() {
    // (mutation, words the fit's message must contain)
    type Mutation = fn(&mut serde_json::Value);
    let cases: [(&str, Mutation, &[&str]); 6] = [
        (
            "coincident vanishing points",
            |v| v["vanishing_points"][1]["point"] = serde_json::json!([-900.0, 600.0]),
            &["coincide"],
        ),
        (
            "given vanishing points with no real focal length",
            |v| v["vanishing_points"][0]["point"] = serde_json::json!([900.0, 600.0]),
            &["no real focal length"],
        ),
        (
            "a floor corner on the given horizon",
            |v| v["floor"][2] = serde_json::json!([1300.0, 600.0]),
            &["floor[2]", "horizon"],
        ),
        (
            "a base corner above the given horizon",
            |v| v["objects"][0]["base"]["near"] = serde_json::json!([800.0, 500.0]),
            &["objects[0].base.near", "above the horizon"],
        ),
        (
            "a top corner below its base",
            |v| v["objects"][0]["top"]["near"] = serde_json::json!([800.0, 950.0]),
            &["\"desk\"", "below its base"],
        ),
        (
            "one edge's top below its base, the other's fine",
            |v| {
                v["objects"][0]["top"] =
                    serde_json::json!({"near": [800.0, 1000.0], "left": [600.0, 600.0]});
            },
            &["objects[0].top.near", "negative height"],
        ),
    ];
    for (what, mutate, words) in cases {
        let mut v = base_scene();
        mutate(&mut v);
        let e = build_with(&v, Method::Fit).expect_err(what).to_string();
        assert!(words.iter().all(|w| e.contains(w)), "{what}: {e}");
    }
}

fn err_text(v: &serde_json::Value) -> String {
    build(v).expect_err("must fail").to_string()
}

#[test]
fn the_base_scene_is_valid() {
    build(&base_scene()).unwrap();
}

#[test]
fn malformed_json() {
    let e = Scene::from_json_str("{\"version\": 1, \"image\": ").unwrap_err();
    assert!(matches!(e, MetrologyError::Json(_)), "{e}");
    assert!(e.to_string().contains("line 1"), "{e}");
}

#[test]
fn missing_field_is_named() {
    let mut v = base_scene();
    v.as_object_mut().unwrap().remove("vanishing_points");
    assert!(err_text(&v).contains("vanishing_points"));
}

#[test]
fn wrong_version() {
    let mut v = base_scene();
    v["version"] = 2.into();
    assert!(err_text(&v).contains("version"));
}

#[test]
fn non_finite_numbers_are_rejected() {
    // JSON has no NaN; serde_json refuses the token and numbers out of f64 range.
    let text = base_scene().to_string().replace("-900.0", "NaN");
    assert!(Scene::from_json_str(&text).is_err());
    let text = base_scene().to_string().replace("-900.0", "1e999");
    assert!(Scene::from_json_str(&text).is_err());
    // Scenes built in code can hold NaN: validation names the field.
    let mut scene = Scene::from_json_str(&base_scene().to_string()).unwrap();
    scene.objects[0]
        .base
        .as_mut()
        .unwrap()
        .left
        .as_mut()
        .unwrap()[1] = f64::NAN;
    let e = scene.validate().unwrap_err().to_string();
    assert!(
        e.contains("objects[0].base.left[1]") && e.contains("NaN"),
        "{e}"
    );
}

#[test]
fn coincident_vanishing_points() {
    let mut v = base_scene();
    v["vanishing_points"][1]["point"] = serde_json::json!([-900.0, 600.0]);
    let e = err_text(&v);
    assert!(
        e.contains("vanishing points 1 and 2 coincide at (-900.000, 600.000)"),
        "{e}"
    );
}

#[test]
fn parallel_lines() {
    let mut v = base_scene();
    v["vanishing_points"][0] = serde_json::json!({"lines": [[0, 0, 100, 10], [0, 50, 100, 60]]});
    let e = err_text(&v);
    assert!(
        e.contains("vanishing point 1") && e.contains("parallel"),
        "{e}"
    );
}

#[test]
fn parallel_vertical_lines_hint_at_two_point_perspective() {
    let mut v = base_scene();
    v["vanishing_points"]
        .as_array_mut()
        .unwrap()
        .push(serde_json::json!({"lines": [[800, 900, 800, 700], [600, 860, 600, 600]]}));
    let e = err_text(&v);
    assert!(
        e.contains("vanishing point 3") && e.contains("two horizontal"),
        "{e}"
    );
}

#[test]
fn no_real_focal_length_in_two_point_perspective() {
    let mut v = base_scene();
    // Both VPs right of the principal point: O lies outside the vanishing circle.
    v["vanishing_points"][0]["point"] = serde_json::json!([900.0, 600.0]);
    let e = err_text(&v);
    assert!(e.contains("no real focal length"), "{e}");
}

#[test]
fn orthocentre_with_no_real_focal_length() {
    let mut v = base_scene();
    // An obtuse VP triangle: the orthocentre lies beyond VP3.
    v["vanishing_points"]
        .as_array_mut()
        .unwrap()
        .push(serde_json::json!({"point": [800.0, 650.0]}));
    let e = err_text(&v);
    assert!(
        e.contains("no real focal length") && e.contains("OG * OC"),
        "{e}"
    );
}

#[test]
fn base_corner_above_the_horizon() {
    let mut v = base_scene();
    v["objects"][0]["base"]["near"] = serde_json::json!([800.0, 500.0]);
    let e = err_text(&v);
    assert!(
        e.contains("objects[0].base.near")
            && e.contains("(800.000, 500.000)")
            && e.contains("above"),
        "{e}"
    );
}

#[test]
fn floor_corner_on_the_horizon() {
    let mut v = base_scene();
    v["floor"][2] = serde_json::json!([1300.0, 600.0]);
    let e = err_text(&v);
    assert!(
        e.contains("floor[2]") && e.contains(" on the horizon"),
        "{e}"
    );
}

#[test]
fn scale_names_a_missing_object() {
    let mut v = base_scene();
    v["scale"] = serde_json::json!({"object": "table", "dimension": "length", "meters": 1.2});
    let e = err_text(&v);
    assert!(e.contains("\"table\"") && e.contains("desk"), "{e}");
}

#[test]
fn scale_with_two_forms_or_bad_values() {
    let mut v = base_scene();
    v["scale"] = serde_json::json!({"camera_height_m": 1.5, "object": "desk", "dimension": "height", "meters": 0.7});
    assert!(err_text(&v).contains("exactly one"));
    v["scale"] = serde_json::json!({"camera_height_m": -1.5});
    let e = err_text(&v);
    assert!(
        e.contains("scale.camera_height_m") && e.contains("-1.5"),
        "{e}"
    );
    v["scale"] = serde_json::json!({"object": "desk", "dimension": "width", "meters": 1.0});
    assert!(err_text(&v).contains("width"));
}

#[test]
fn vanishing_point_count() {
    let mut v = base_scene();
    v["vanishing_points"].as_array_mut().unwrap().truncate(1);
    assert!(err_text(&v).contains("has 1 entries"));
}

#[test]
fn object_shape_errors() {
    let mut v = base_scene();
    v["objects"][0]["footprint"] = serde_json::json!([[1, 2], [3, 4], [5, 6]]);
    assert!(err_text(&v).contains("both `base` and `footprint`"));
    let mut v = base_scene();
    v["objects"][0] = serde_json::json!({"name": "chair", "footprint": [[700, 900], [750, 880]]});
    assert!(err_text(&v).contains("at least 3 vertices, got 2"));
    let mut v = base_scene();
    v["objects"][0] = serde_json::json!({"name": "chair", "footprint": [[700, 900], [750, 880], [720, 860]], "top": {"above": 3, "point": [700, 800]}});
    assert!(err_text(&v).contains("top.above"));
    let mut v = base_scene();
    let dup = v["objects"][0].clone();
    v["objects"].as_array_mut().unwrap().push(dup);
    assert!(err_text(&v).contains("used by an earlier object"));
}

#[test]
fn top_below_base_is_a_negative_height() {
    let mut v = base_scene();
    v["objects"][0]["top"]["near"] = serde_json::json!([800.0, 950.0]);
    assert!(err_text(&v).contains("negative height"));
}

#[test]
fn empty_objects_and_floor_still_calibrate() {
    let mut v = base_scene();
    v["objects"] = serde_json::json!([]);
    v["floor"] = serde_json::json!([]);
    let scene = Scene::from_json_str(&v.to_string()).unwrap();
    let map = build_map(&scene, &BuildOptions::default()).unwrap();
    assert!(map.objects.is_empty() && map.free_space.is_empty());
    assert!(map.camera.focal_px > 0.0);
}

#[test]
fn identical_or_collinear_segments_fix_no_point() {
    for lines in [
        serde_json::json!([[0, 0, 10, 1], [0, 0, 10, 1]]),
        serde_json::json!([[0, 0, 10, 1], [20, 2, 30, 3]]),
    ] {
        let mut v = base_scene();
        v["vanishing_points"][0] = serde_json::json!({ "lines": lines });
        let e = err_text(&v);
        assert!(
            e.contains("vanishing_points[0].lines") && e.contains("one line"),
            "{e}"
        );
    }
}

#[test]
fn huge_numbers_are_errors_not_panics() {
    // Regressions: these reached geo's convex hull and union and panicked there.
    let mut v = base_scene();
    v["scale"] = serde_json::json!({"camera_height_m": 3e154});
    assert!(err_text(&v).contains("scale.camera_height_m"));
    let mut v = base_scene();
    v["floor"][2] = serde_json::json!([1300.0, 1e307]);
    let e = err_text(&v);
    assert!(
        e.contains("floor[2][1]") && e.contains("outside the supported range"),
        "{e}"
    );
    let mut v = base_scene();
    v["vanishing_points"][0]["point"] = serde_json::json!([-1e200, 600.0]);
    assert!(err_text(&v).contains("vanishing_points[0].point[0]"));
}

#[test]
fn top_below_base_on_one_edge_is_named() {
    // The near edge's top lies below its base; the left edge is fine. Averaging the two
    // estimates must not hide it.
    let mut v = base_scene();
    v["objects"][0]["top"] = serde_json::json!({"near": [800.0, 1000.0], "left": [600.0, 600.0]});
    let e = err_text(&v);
    assert!(
        e.contains("objects[0].top.near") && e.contains("negative height"),
        "{e}"
    );
}

#[test]
fn floor_point_a_hair_below_the_horizon_is_out_of_range() {
    let mut v = base_scene();
    v["floor"][2] = serde_json::json!([1300.0, 600.0001]);
    let e = err_text(&v);
    assert!(
        e.contains("floor[2]") && e.contains("too close to the horizon"),
        "{e}"
    );
}

#[test]
fn noisy_box_completed_behind_the_camera_is_an_error() {
    // Found by sweeping noisy synthetic scenes: 2 px of noise on a far box's corners put its
    // completed corner 1.9 km behind the camera, and the map was written anyway.
    use vpmap_metrology::synth::{SynthOptions, VanishingPointForm, synthesize};
    let (scene, _) = synthesize(&SynthOptions {
        seed: 39,
        pitch_deg: 15.0,
        roll_deg: 0.0,
        noise_px: 2.0,
        vanishing_points: VanishingPointForm::Lines,
        ..SynthOptions::default()
    })
    .unwrap();
    match build_map(&scene, &BuildOptions::default()) {
        Ok(map) => {
            for o in &map.objects {
                for p in &o.footprint {
                    assert!(p[1] > 0.0 && p[0].hypot(p[1]) < 1e3, "{}: {p:?}", o.name);
                }
            }
        }
        Err(e) => {
            let e = e.to_string();
            assert!(e.contains("objects[") || e.contains("floor["), "{e}");
        }
    }
}

#[test]
fn a_perspective_that_disagrees_with_the_vanishing_points_is_refused() {
    let mut v = base_scene();
    v["perspective"] = serde_json::json!("3pp");
    let e = err_text(&v);
    assert!(
        e.contains("perspective") && e.contains("\"3pp\"") && e.contains("2 vanishing points"),
        "{e}"
    );
    let mut v = base_scene();
    v["perspective"] = serde_json::json!("5pp");
    let e = err_text(&v);
    assert!(e.contains("5pp") && e.contains("2pp"), "{e}");
    let mut v = base_scene();
    v["perspective"] = serde_json::json!("2pp");
    build(&v).unwrap();
}

#[test]
fn a_floor_clicked_out_of_order_is_warned_about_by_every_method() {
    let mut v = base_scene();
    // A bow tie: the second and third corners swapped.
    v["floor"] = serde_json::json!([
        [100.0, 1100.0],
        [1300.0, 700.0],
        [1500.0, 1100.0],
        [300.0, 700.0]
    ]);
    let scene = Scene::from_json_str(&v.to_string()).unwrap();
    for method in [Method::Sideview, Method::Projective, Method::Fit] {
        let map = build_map(
            &scene,
            &BuildOptions {
                method,
                ..BuildOptions::default()
            },
        )
        .unwrap();
        assert!(
            map.warnings
                .iter()
                .any(|w| w.contains("floor outline crosses itself")),
            "{method}: {:?}",
            map.warnings
        );
    }
    // In order, no warning.
    let scene = Scene::from_json_str(&base_scene().to_string()).unwrap();
    let map = build_map(&scene, &BuildOptions::default()).unwrap();
    assert!(
        !map.warnings.iter().any(|w| w.contains("crosses itself")),
        "{:?}",
        map.warnings
    );
}

/// Regression: collinear vanishing-point segments were refused by the thesis's method only;
/// the default method (the joint fit) built a map from them, though docs/scene-format.md
/// lists them as refused.
#[test]
fn collinear_segments_are_refused_by_the_default_method_too() {
    let mut v = base_scene();
    v["vanishing_points"][0] = serde_json::json!({"lines": [[0, 0, 10, 1], [20, 2, 30, 3]]});
    let e = build_with(&v, Method::Fit)
        .expect_err("collinear")
        .to_string();
    assert!(
        e.contains("vanishing_points[0].lines") && e.contains("one line"),
        "{e}"
    );
}

/// Regression: `direction` with `lines` silently ignored the direction (the fit followed the
/// lines), while `point` with `direction` was refused.
#[test]
fn a_direction_with_lines_is_refused() {
    let mut v = base_scene();
    v["vanishing_points"]
        .as_array_mut()
        .unwrap()
        .push(serde_json::json!({
            "direction": [0.0, 1.0],
            "lines": [[700, 300, 705, 800], [900, 300, 898, 800]]
        }));
    let e = Scene::from_json_str(&v.to_string())
        .expect_err("direction with lines")
        .to_string();
    assert!(
        e.contains("vanishing_points[2]") && e.contains("`direction` or `lines`, not both"),
        "{e}"
    );
}

/// Regression: a 1 x 1 `image` (in a room's photo, or alone) was taken, and the fit then
/// blamed the vanishing points ("the fit runs off to a focal length of 1802 px (1274 image
/// diagonals)").
#[test]
fn a_one_pixel_image_is_refused_by_name() {
    let mut small = base_scene();
    small["image"] = serde_json::json!({"width": 1, "height": 1});
    for (v, field) in [
        (small.clone(), "`image`"),
        (
            serde_json::json!({"version": 1, "photos": [base_scene(), small]}),
            "photos[1] (photo 2)",
        ),
    ] {
        let e = build_with(&v, Method::Fit).expect_err("1 x 1").to_string();
        assert!(
            e.contains(field) && e.contains("1 x 1 pixels") && !e.contains("focal length"),
            "{e}"
        );
    }
}

#[test]
fn a_floor_corner_within_rounding_of_the_horizon_is_read_as_on_it() {
    // The stated tolerance: a point less than 1e-9 focal lengths (here about 1.6e-6 px) from
    // the horizon is on it, whichever side rounding put it; farther, it is below.
    for dy in [0.0, 1e-7, -1e-7, 1e-6] {
        let mut v = base_scene();
        v["floor"][2] = serde_json::json!([1300.0, 600.0 + dy]);
        let e = err_text(&v);
        assert!(
            e.contains("floor[2]") && e.contains(" on the horizon"),
            "{dy}: {e}"
        );
    }
    let mut v = base_scene();
    v["floor"][2] = serde_json::json!([1300.0, 600.0 - 1e-3]);
    let e = err_text(&v);
    assert!(
        e.contains("floor[2]") && e.contains(" above the horizon"),
        "{e}"
    );
}

#[test]
fn numbers_in_a_scene_file_are_read_correctly_rounded() {
    // Decimals of 18-20 significant digits that a parser without correct rounding reads one
    // unit in the last place off; the reference is the standard library's correctly rounded
    // parse. A click 1 ulp off would move a floor corner near the horizon across it.
    let texts = [
        "1983.030559428644220",
        "540.687964898110354",
        "132.34911341117422933814861",
        "1987.9934361392354795086",
    ];
    for t in texts {
        let text = base_scene()
            .to_string()
            .replace("[100.0,1100.0]", &format!("[{t},1100.0]"));
        assert!(text.contains(t), "{text}");
        let scene = Scene::from_json_str(&text).unwrap_or_else(|e| panic!("{e}"));
        let want: f64 = t.parse().unwrap();
        assert_eq!(scene.floor[0][0].to_bits(), want.to_bits(), "{t}");
    }
}

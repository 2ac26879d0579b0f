//! `POST /api/build`.

use crate::{OFFICE, assert_alive, base64_decode, get, post_json, request};

#[test]
fn office_example_builds_with_the_demo_camera_and_five_objects() {
    let reply = post_json(
        "/api/build?method=sideview&resolution=0.05&robot_radius=0.2&hidden_free=false",
        OFFICE,
    );
    assert_eq!(
        reply.status,
        200,
        "{}",
        String::from_utf8_lossy(&reply.body)
    );
    assert_eq!(reply.header("content-type"), Some("application/json"));
    let v = reply.json();
    let camera = &v["camera"];
    assert!((camera["pitch_deg"].as_f64().unwrap() - 25.0).abs() < 1e-6);
    assert!((camera["roll_deg"].as_f64().unwrap() - 3.0).abs() < 1e-6);
    assert!((camera["focal_px"].as_f64().unwrap() - 1100.0).abs() < 1e-6);
    assert!((camera["height"].as_f64().unwrap() - 1.6).abs() < 1e-9);
    assert_eq!(camera["perspective"], "3pp");
    let pp = camera["principal_point"].as_array().unwrap();
    assert!((pp[0].as_f64().unwrap() - 800.0).abs() < 1e-6);
    // The horizon crosses the image from x = 0 to x = 1600, falling by tan 3 deg.
    let h = &camera["horizon"];
    let (x0, y0) = (h[0][0].as_f64().unwrap(), h[0][1].as_f64().unwrap());
    let (x1, y1) = (h[1][0].as_f64().unwrap(), h[1][1].as_f64().unwrap());
    assert_eq!((x0, x1), (0.0, 1600.0));
    assert!(((y1 - y0) / 1600.0 - 3f64.to_radians().tan()).abs() < 1e-9);
    // The map as map.json writes it.
    let map = &v["map"];
    assert_eq!(map["version"], 1);
    assert_eq!(map["units"], "m");
    assert_eq!(map["method"], "sideview");
    let objects = map["objects"].as_array().unwrap();
    assert_eq!(objects.len(), 5);
    assert_eq!(objects[0]["name"], "bookcase");
    assert_eq!(v["units"], "m");
    // The pictures and the model.
    let svg = v["svg"].as_str().unwrap();
    assert!(
        svg.contains("<svg") && svg.contains("bookcase"),
        "{}",
        &svg[..200]
    );
    let glb = base64_decode(v["glb_base64"].as_str().unwrap());
    assert_eq!(&glb[..4], b"glTF");
    // The occupancy grid: a ROS map whose PGM holds width x height cells.
    let occ = &v["occupancy"];
    let (w, h) = (
        occ["width"].as_u64().unwrap() as usize,
        occ["height"].as_u64().unwrap() as usize,
    );
    let pgm = base64_decode(occ["pgm_base64"].as_str().unwrap());
    let header = format!("P5\n{w} {h}\n255\n");
    assert!(pgm.starts_with(header.as_bytes()));
    assert_eq!(pgm.len(), header.len() + w * h);
    assert_eq!(occ["resolution"], 0.05);
    assert!(occ["yaml"].as_str().unwrap().contains("mode: trinary"));
    let counts: u64 = ["free", "occupied", "unknown"]
        .iter()
        .map(|k| occ[k].as_u64().unwrap())
        .sum();
    assert_eq!(counts as usize, w * h);
    assert!(occ["origin"].as_array().unwrap().len() == 2);
    assert!(v["warnings"].as_array().unwrap().is_empty());
}

#[test]
fn projective_method_and_defaults() {
    let v = post_json("/api/build?method=projective", OFFICE).json();
    assert_eq!(v["map"]["method"], "projective");
    assert!((v["camera"]["pitch_deg"].as_f64().unwrap() - 25.0).abs() < 1e-6);
    // No query at all: the pipeline's default method at 0.05 m.
    let v = post_json("/api/build", OFFICE).json();
    let default = vpmap_pipeline::MapOptions::default().method.to_string();
    assert_eq!(v["map"]["method"], default.as_str());
    assert_eq!(v["occupancy"]["resolution"], 0.05);
    // A browser's string body arrives as text/plain.
    let reply = request(
        "POST",
        "/api/build",
        &[("Content-Type", "text/plain;charset=UTF-8")],
        OFFICE.as_bytes(),
    );
    assert_eq!(reply.status, 200);
}

#[test]
fn fit_method_answers_error_bars_for_the_given_click_noise() {
    let v = post_json("/api/build?method=fit&click_sigma=1.5", OFFICE).json();
    let map = &v["map"];
    assert_eq!(map["method"], "fit");
    assert_eq!(map["fit"]["click_sigma_px"], 1.5);
    assert_eq!(map["fit"]["click_sigma_source"], "given");
    assert!((v["camera"]["pitch_deg"].as_f64().unwrap() - 25.0).abs() < 1e-6);
    let camera_sd = &map["camera"]["uncertainty"];
    assert!(camera_sd["focal_px_sd"].as_f64().unwrap() > 0.0);
    let objects = map["objects"].as_array().unwrap();
    for o in objects {
        let u = &o["uncertainty"];
        let axes = u["centroid_ellipse_95"]["semi_axes"].as_array().unwrap();
        assert!(axes[0].as_f64().unwrap() >= axes[1].as_f64().unwrap());
        assert!(axes[1].as_f64().unwrap() > 0.0, "{}: {u}", o["name"]);
    }
    // The floor plan draws one ellipse per object and the ± values.
    let svg = v["svg"].as_str().unwrap();
    assert_eq!(
        svg.matches(r#"class="centroid-ellipse""#).count(),
        objects.len()
    );
    assert!(svg.contains(" ± "));
    // Twice the click noise, twice the error bars (first-order propagation).
    let w = post_json("/api/build?method=fit&click_sigma=3", OFFICE).json();
    let sd = |v: &serde_json::Value| v["map"]["objects"][0]["uncertainty"]["length_sd"].as_f64();
    let (a, b) = (sd(&v).unwrap(), sd(&w).unwrap());
    assert!((b / a - 2.0).abs() < 1e-6, "{a} {b}");
    // Other methods have none of it.
    let p = post_json("/api/build?method=projective", OFFICE).json();
    assert!(p["map"].get("fit").is_none() && p["map"]["objects"][0].get("uncertainty").is_none());
}

#[test]
fn unknown_scene_fields_are_warnings() {
    let scene = OFFICE.replacen('{', "{\"scael\": 3,", 1);
    let v = post_json("/api/build", &scene).json();
    let warnings = v["warnings"].as_array().unwrap();
    // The build's own warnings (the far desk and chair placed to +-0.3 m at 95 %) and one more.
    let plain = post_json("/api/build", OFFICE).json();
    let plain = plain["warnings"].as_array().unwrap();
    assert_eq!(warnings.len(), plain.len() + 1, "{warnings:?}");
    assert!(warnings[0].as_str().unwrap().contains("scael"));
    assert_eq!(&warnings[1..], &plain[..]);
}

pub(crate) fn malformed_and_refused_scenes_are_400_with_a_message() {
    let version_2 = OFFICE.replacen("\"version\": 1", "\"version\": 2", 1);
    let cases: [(&str, &str, &str); 12] = [
        ("/api/build", "{\"version\": 1,", "line"),
        ("/api/build", "[1, 2]", "JSON object"),
        ("/api/build", "   ", "empty"),
        ("/api/build", &version_2, "version"),
        ("/api/build?resolution=abc", OFFICE, "resolution"),
        ("/api/build?resolution=0", OFFICE, "resolution"),
        ("/api/build?method=magic", OFFICE, "magic"),
        ("/api/build?robot_radius=-1", OFFICE, "robot_radius"),
        ("/api/build?resolutoin=0.1", OFFICE, "resolutoin"),
        ("/api/build?click_sigma=0", OFFICE, "click_sigma is 0;"),
        ("/api/build?click_sigma=101", OFFICE, "at most 100"),
        ("/api/build?click_sigma=one", OFFICE, "click_sigma"),
    ];
    for (target, body, needle) in cases {
        let message = post_json(target, body).error(400);
        assert!(message.contains(needle), "{target} {body:.30}: {message}");
    }
    // A floor point above the horizon is named with its value.
    let mut v: serde_json::Value = serde_json::from_str(OFFICE).unwrap();
    v["floor"][0] = serde_json::json!([800.0, 10.0]);
    let message = post_json("/api/build", &v.to_string()).error(400);
    assert!(message.contains("floor[0]"), "{message}");
    // A resolution that would make a huge grid.
    let message = post_json("/api/build?resolution=0.001", OFFICE).error(400);
    assert!(message.contains("coarser resolution"), "{message}");
}

#[test]
fn bad_requests_are_answered_and_the_server_keeps_serving() {
    malformed_and_refused_scenes_are_400_with_a_message();
    assert_alive();
    // Wrong content type.
    let reply = request(
        "POST",
        "/api/build",
        &[("Content-Type", "image/png")],
        OFFICE.as_bytes(),
    );
    assert!(reply.error(400).contains("image/png"));
    // Not UTF-8.
    let reply = request(
        "POST",
        "/api/build",
        &[("Content-Type", "application/json")],
        b"{\xff\xfe}",
    );
    assert!(reply.error(400).contains("UTF-8"));
    // Empty body.
    assert!(post_json("/api/build", "").error(400).contains("empty"));
    // Over 4 MiB.
    let big = format!("{{\"pad\": \"{}\"}}", "x".repeat(5 << 20));
    let message = post_json("/api/build", &big).error(413);
    assert!(message.contains("limit"), "{message}");
    // GET on a POST route.
    let message = get("/api/build").error(405);
    assert!(message.contains("POST"), "{message}");
    assert_alive();
}

//! `POST /api/plan`.

use serde_json::{Value, json};

use crate::{OFFICE, assert_alive, get, post_json};

fn office() -> Value {
    serde_json::from_str(OFFICE).unwrap()
}

/// A plan request across the office, from the near left to the far right (as the README's
/// `vpmap plan` example).
fn request_body() -> Value {
    json!({
        "scene": office(),
        "method": "sideview",
        "resolution": 0.05,
        "robot_radius": 0.2,
        "start": [-1.5, 2.0],
        "goal": [2.0, 7.5],
        "planners": ["mbpp", "astar-ps", "optimal", "theta-star"],
    })
}

fn length(result: &Value) -> f64 {
    result["length_m"].as_f64().unwrap()
}

#[test]
fn paths_across_the_office() {
    let reply = post_json("/api/plan", &request_body().to_string());
    assert_eq!(
        reply.status,
        200,
        "{}",
        String::from_utf8_lossy(&reply.body)
    );
    let v = reply.json();
    let results = v["results"].as_array().unwrap();
    let names: Vec<&str> = results
        .iter()
        .map(|r| r["planner"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["mbpp", "astar-ps", "optimal", "theta-star"]);
    for r in results {
        assert_eq!(r["found"], true, "{}", r["planner"]);
        assert_eq!(r["skipped"], false);
        let waypoints = r["waypoints"].as_array().unwrap();
        assert!(waypoints.len() >= 2);
        // Waypoints are cell centres: the first within half a cell (diagonal) of the start.
        let (x, y) = (
            waypoints[0][0].as_f64().unwrap(),
            waypoints[0][1].as_f64().unwrap(),
        );
        assert!((x + 1.5).hypot(y - 2.0) <= 0.05 * 0.75, "({x}, {y})");
        assert!(r["time_ms"].as_f64().unwrap() >= 0.0);
    }
    let optimal = length(&results[2]);
    // The straight line is a lower bound, and nothing beats the exact optimum.
    assert!(optimal >= (3.5f64).hypot(5.5) - 0.1);
    assert!(length(&results[0]) >= optimal - 1e-9);
    assert!(length(&results[1]) >= optimal - 1e-9);
    assert!(length(&results[3]) >= optimal - 1e-9);
    // MBPP shows its bugs, walked cells in metres.
    let bugs = results[0]["bugs"].as_array().unwrap();
    assert!(!bugs.is_empty());
    assert!(
        bugs.iter()
            .any(|b| !b["cells"].as_array().unwrap().is_empty())
    );
    assert!(bugs.iter().any(|b| b["fate"] == "reached-goal"));
    for b in bugs {
        for key in ["cells", "hits", "leaves"] {
            assert!(b[key].is_array());
        }
    }
    // The grid is the one /api/build makes with the same parameters.
    let built = post_json("/api/build?resolution=0.05&robot_radius=0.2", OFFICE).json();
    for key in ["width", "height", "resolution", "origin"] {
        assert_eq!(v["grid"][key], built["occupancy"][key], "{key}");
    }
    assert_eq!(v["units"], "m");
}

#[test]
fn default_planners_and_unknown_floor() {
    let mut body = request_body();
    body.as_object_mut().unwrap().remove("planners");
    let v = post_json("/api/plan", &body.to_string()).json();
    let names: Vec<&str> = v["results"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["planner"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["mbpp", "astar-ps", "optimal"]);
    // Behind the bookcase the floor is hidden: unknown, refused unless allowed.
    let mut body = request_body();
    body["goal"] = json!([-0.9, 5.3]);
    let message = post_json("/api/plan", &body.to_string()).error(400);
    assert!(message.contains("unknown floor"), "{message}");
    body["hidden_free"] = json!(true);
    let reply = post_json("/api/plan", &body.to_string());
    assert_eq!(
        reply.status,
        200,
        "{}",
        String::from_utf8_lossy(&reply.body)
    );
}

#[test]
fn plans_on_the_fit_map_with_a_click_noise() {
    let mut body = request_body();
    body["method"] = json!("fit");
    body["click_sigma"] = json!(1.0);
    let v = post_json("/api/plan", &body.to_string()).json();
    let mbpp = &v["results"][0];
    assert_eq!(mbpp["planner"], "mbpp");
    assert_eq!(mbpp["found"], true, "{v}");
}

pub(crate) fn bad_plan_requests_are_400_with_a_message() {
    let with = |key: &str, value: Value| {
        let mut b = request_body();
        b[key] = value;
        b.to_string()
    };
    let crate_centroid = json!([0.094, 2.131]);
    let cases: Vec<(String, &str)> = vec![
        (
            with("start", crate_centroid.clone()),
            "start (0.094, 2.131) m lies on an obstacle",
        ),
        (
            with("goal", crate_centroid),
            "goal (0.094, 2.131) m lies on an obstacle",
        ),
        (with("start", json!([100.0, 100.0])), "outside the map"),
        (with("start", json!([1.0])), "start"),
        (with("planners", json!(["dijkstra"])), "dijkstra"),
        (with("planners", json!([])), "empty"),
        (with("resolution", json!(-1)), "resolution"),
        (with("method", json!("magic")), "magic"),
        (with("click_sigma", json!(0)), "click_sigma is 0;"),
        (
            with("click_sigma", json!("1px")),
            "`click_sigma` must be a number",
        ),
        (with("strat", json!([0, 0])), "strat"),
        (with("scene", json!({"version": 1})), "scene"),
        (with("scene", json!("office.json")), "scene"),
        ("{\"scene\": ".to_owned(), "line"),
        ("[]".to_owned(), "JSON object"),
        (String::new(), "empty"),
    ];
    for (body, needle) in cases {
        let message = post_json("/api/plan", &body).error(400);
        assert!(message.contains(needle), "{needle}: {message}");
    }
    let mut no_goal = request_body();
    no_goal.as_object_mut().unwrap().remove("goal");
    let message = post_json("/api/plan", &no_goal.to_string()).error(400);
    assert!(message.contains("goal"), "{message}");
}

#[test]
fn bad_plan_requests_are_answered_and_the_server_keeps_serving() {
    bad_plan_requests_are_400_with_a_message();
    assert!(get("/api/plan").error(405).contains("POST"));
    let message = post_json("/api/plan?fast=1", &request_body().to_string()).error(400);
    assert!(message.contains("fast"), "{message}");
    assert_alive();
}

//! `POST /api/plan` with the smooth planner: its poses checked against the occupancy grid
//! `/api/build` gives (decoded here from its PGM), not by vpmap's own validator.

use base64::Engine as _;
use serde_json::{Value, json};

use crate::{OFFICE, assert_alive, post_json};

const RESOLUTION: f64 = 0.05;
const RADIUS: f64 = 0.2;

fn request(start_heading: Option<f64>) -> Value {
    let mut body = json!({
        "scene": serde_json::from_str::<Value>(OFFICE).unwrap(),
        "method": "sideview",
        "resolution": RESOLUTION,
        "robot_radius": 0.2,
        "start": [-1.5, 2.0],
        "goal": [2.0, 7.5],
        "planners": ["smooth", "optimal"],
        "turning_radius": RADIUS,
    });
    if let Some(h) = start_heading {
        body["start_heading_deg"] = json!(h);
    }
    body
}

/// The grid of `/api/build` with the same parameters: width, height, origin and whether each
/// cell (row 0 at the top, as the plan's cells) blocks (occupied or unknown).
struct Grid {
    width: usize,
    height: usize,
    origin: [f64; 2],
    blocked: Vec<bool>,
}

fn grid() -> Grid {
    let built = post_json("/api/build?resolution=0.05&robot_radius=0.2", OFFICE).json();
    let occ = &built["occupancy"];
    let pgm = base64::engine::general_purpose::STANDARD
        .decode(occ["pgm_base64"].as_str().unwrap())
        .unwrap();
    // A binary PGM: "P5", width, height, maxval, one whitespace byte, then the pixels.
    let mut fields = Vec::new();
    let mut at = 0;
    while fields.len() < 4 {
        while pgm[at].is_ascii_whitespace() {
            at += 1;
        }
        if pgm[at] == b'#' {
            while pgm[at] != b'\n' {
                at += 1;
            }
            continue;
        }
        let begin = at;
        while !pgm[at].is_ascii_whitespace() {
            at += 1;
        }
        fields.push(String::from_utf8(pgm[begin..at].to_vec()).unwrap());
    }
    assert_eq!(fields[0], "P5");
    let (width, height): (usize, usize) = (fields[1].parse().unwrap(), fields[2].parse().unwrap());
    let pixels = &pgm[at + 1..];
    assert_eq!(pixels.len(), width * height);
    assert_eq!(width as u64, occ["width"].as_u64().unwrap());
    // ROS trinary: 254 free, 0 occupied, 205 unknown.
    let blocked = pixels.iter().map(|&p| p != 254).collect();
    let origin = [
        occ["origin"][0].as_f64().unwrap(),
        occ["origin"][1].as_f64().unwrap(),
    ];
    Grid {
        width,
        height,
        origin,
        blocked,
    }
}

impl Grid {
    /// Whether the unit square (one cell) centred on map point `(x, y)` overlaps the
    /// interior of no blocked cell.
    fn square_clear(&self, x: f64, y: f64) -> bool {
        let cx = (x - self.origin[0]) / RESOLUTION - 0.5;
        let cy = self.height as f64 - (y - self.origin[1]) / RESOLUTION - 0.5;
        let (lo_x, lo_y) = ((cx - 1.0).floor() as i64, (cy - 1.0).floor() as i64);
        for by in lo_y..=lo_y + 3 {
            for bx in lo_x..=lo_x + 3 {
                let overlaps =
                    (cx - bx as f64).abs() < 1.0 - 1e-9 && (cy - by as f64).abs() < 1.0 - 1e-9;
                if !overlaps {
                    continue;
                }
                let inside =
                    bx >= 0 && by >= 0 && (bx as usize) < self.width && (by as usize) < self.height;
                if !inside || self.blocked[by as usize * self.width + bx as usize] {
                    return false;
                }
            }
        }
        true
    }
}

fn wrap_deg(a: f64) -> f64 {
    (a + 180.0).rem_euclid(360.0) - 180.0
}

fn plan(body: &Value) -> Value {
    let reply = post_json("/api/plan", &body.to_string());
    assert_eq!(
        reply.status,
        200,
        "{}",
        String::from_utf8_lossy(&reply.body)
    );
    reply.json()
}

/// A smooth result's `poses` as `[x, y, heading_deg]`.
fn poses_of(smooth: &Value) -> Vec<[f64; 3]> {
    smooth["poses"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| [0, 1, 2].map(|i| p[i].as_f64().unwrap()))
        .collect()
}

/// The poses of the smooth result, checked: every pose's square clear on the grid, steps at
/// most a quarter cell, heading steps within step / R, ends at the asked start and goal.
fn checked_poses(v: &Value, grid: &Grid) -> Vec<[f64; 3]> {
    let r = &v["results"][0];
    assert_eq!(r["planner"], "smooth");
    assert_eq!(r["found"], true, "{r}");
    let s = &r["smooth"];
    let poses = poses_of(s);
    assert!(poses.len() > 10);
    for p in &poses {
        assert!(grid.square_clear(p[0], p[1]), "pose {p:?} is not clear");
    }
    let mut length = 0.0;
    for w in poses.windows(2) {
        let step = (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]);
        length += step;
        assert!(step <= RESOLUTION / 4.0 + 1e-9, "step {step} between {w:?}");
        let turn = wrap_deg(w[1][2] - w[0][2]).abs().to_radians();
        // An arc of length s turns by s / R; its chord is a hair shorter than s.
        assert!(
            turn <= step / RADIUS * 1.001 + 1e-9,
            "turn {turn} over {step} at {w:?}"
        );
    }
    // The ends are the cells of the asked points (within half a cell's diagonal).
    let (first, last) = (poses[0], poses[poses.len() - 1]);
    assert!(
        (first[0] + 1.5).hypot(first[1] - 2.0) <= RESOLUTION * 0.75,
        "{first:?}"
    );
    assert!(
        (last[0] - 2.0).hypot(last[1] - 7.5) <= RESOLUTION * 0.75,
        "{last:?}"
    );
    // The answer's measures agree with the poses.
    let reported = s["length"].as_f64().unwrap();
    assert!(
        length <= reported + 1e-6 && length >= reported * 0.99,
        "{length} vs {reported}"
    );
    assert!((r["length_m"].as_f64().unwrap() - reported).abs() < 1e-12);
    assert!(s["max_curvature"].as_f64().unwrap() <= 1.0 / RADIUS + 1e-9);
    assert_eq!(s["cusps"], 0);
    assert!(s["min_clearance"].as_f64().unwrap() >= 0.0);
    assert_eq!(r["waypoints"].as_array().unwrap().len(), poses.len());
    // Never shorter than the exact shortest path, which ignores turning.
    let optimal = v["results"][1]["length_m"].as_f64().unwrap();
    assert!(reported >= optimal - 1e-6, "{reported} < {optimal}");
    poses
}

#[test]
fn a_smooth_path_across_the_office_is_drivable_on_the_grid() {
    let grid = grid();
    let free = checked_poses(&plan(&request(None)), &grid);
    // A start heading as asked: the path leaves at it, then at another.
    for heading in [90.0, -90.0] {
        let poses = checked_poses(&plan(&request(Some(heading))), &grid);
        assert!(
            wrap_deg(poses[0][2] - heading).abs() < 1e-6,
            "{:?}",
            poses[0]
        );
    }
    // A goal heading too.
    let mut body = request(Some(0.0));
    body["goal_heading_deg"] = json!(180.0);
    let poses = checked_poses(&plan(&body), &grid);
    let last = poses[poses.len() - 1];
    assert!(wrap_deg(last[2] - 180.0).abs() < 1e-6, "{last:?}");
    assert!(!free.is_empty());
}

#[test]
fn a_map_without_scale_is_planned_in_camera_heights() {
    // Without its camera height the office is in camera heights (1.6 m each): the row says
    // so, and the same radius in those units gives a path no tighter than it.
    let mut body = request(None);
    body["scene"].as_object_mut().unwrap().remove("scale");
    body["turning_radius"] = json!(RADIUS / 1.6);
    body["start"] = json!([-1.5 / 1.6, 2.0 / 1.6]);
    body["goal"] = json!([2.0 / 1.6, 7.5 / 1.6]);
    body["robot_radius"] = json!(0.2 / 1.6);
    body["resolution"] = json!(0.05 / 1.6);
    let v = plan(&body);
    assert_eq!(v["units"], "camera_heights");
    let s = &v["results"][0]["smooth"];
    assert_eq!(s["units"], "camera_heights", "{s}");
    assert_eq!(s["found"], true, "{s}");
    assert!(s["max_curvature"].as_f64().unwrap() <= 1.6 / RADIUS + 1e-9);
    body["turning_radius"] = json!(100);
    let message = post_json("/api/plan", &body.to_string()).error(400);
    assert!(
        message.contains("is 100 camera heights, larger than the map"),
        "{message}"
    );
}

#[test]
fn bad_smooth_requests_are_400_naming_the_value() {
    let with = |key: &str, value: Value| {
        let mut b = request(None);
        b[key] = value;
        b.to_string()
    };
    let mut no_radius = request(None);
    no_radius.as_object_mut().unwrap().remove("turning_radius");
    let mut not_smooth = request(None);
    not_smooth["planners"] = json!(["optimal"]);
    let cases: Vec<(String, &str)> = vec![
        (
            with("turning_radius", json!(-0.5)),
            "`turning_radius` must be a positive number of map units, got -0.5",
        ),
        (with("turning_radius", json!(0)), "got 0"),
        (
            with("turning_radius", json!("1m")),
            "`turning_radius` must be a number",
        ),
        (
            with("turning_radius", json!(1000)),
            "`turning_radius` is 1000 m, larger than the map",
        ),
        (
            with("start_heading_deg", json!("north")),
            "`start_heading_deg` must be a number",
        ),
        (no_radius.to_string(), "needs field `turning_radius`"),
        (not_smooth.to_string(), "only used by the smooth planner"),
    ];
    for (body, needle) in cases {
        let message = post_json("/api/plan", &body).error(400);
        assert!(message.contains(needle), "{needle}: {message}");
    }
    assert_alive();
}

#[test]
fn no_room_to_turn_is_found_false_with_the_reason() {
    // A radius of 1 m does not fit the office's passages heading along x at both ends (a turn
    // needs a clear space about 2 m wide): no drivable path, said why. (The fastest such query
    // found: 25 ms with 348 Hybrid-A* expansions in a release build; the planner reads its time
    // limit only every 4,096 expansions, docs/web-api.md.)
    let mut body = request(Some(0.0));
    body["goal_heading_deg"] = json!(0.0);
    body["turning_radius"] = json!(1.0);
    body["planners"] = json!(["smooth"]);
    let v = plan(&body);
    let r = &v["results"][0];
    assert_eq!(r["found"], false, "{r}");
    let note = r["note"].as_str().unwrap();
    assert!(
        note.starts_with("no drivable path: ") && note.contains("turning radius 1 m"),
        "{note}"
    );
    assert_eq!(r["smooth"]["found"], false);
    assert!(r["waypoints"].as_array().unwrap().is_empty());
    assert!(r["length_m"].is_null());
}

#[test]
fn the_fuzzing_entry_point_checks_the_smooth_fields() {
    let check =
        |body: &Value| vpmap_web::fuzzing::plan_request(body.to_string().as_bytes(), 20_000.0);
    let mut body = request(Some(90.0));
    body["resolution"] = json!(0.1);
    body["goal_heading_deg"] = json!(-45.5);
    assert!(check(&body).is_ok());
    for (key, value, needle) in [
        ("turning_radius", json!(1e300), "larger than the map"),
        ("turning_radius", json!(-1e-300), "positive"),
        ("turning_radius", json!([0.2]), "must be a number"),
        ("goal_heading_deg", json!(true), "must be a number"),
        ("planners", json!(["smooth", "smooth", "astar"]), ""),
    ] {
        let mut b = body.clone();
        b[key] = value;
        match check(&b) {
            Err(e) => {
                assert_eq!(e.status.as_u16(), 400);
                assert!(
                    !needle.is_empty() && e.message.contains(needle),
                    "{key}: {}",
                    e.message
                );
            }
            Ok(()) => assert!(needle.is_empty(), "{key} accepted"),
        }
    }
    // The corpus input of the fuzz target for the smooth planner is a valid request.
    let corpus = std::fs::read(
        std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .join("../../fuzz/corpus/web_body/plan-office-smooth"),
    )
    .unwrap();
    let split = corpus.iter().position(|&b| b == b'\n').unwrap();
    assert!(vpmap_web::fuzzing::plan_request(&corpus[split + 1..], 20_000.0).is_ok());
}

#[test]
fn reverse_lets_the_robot_back_up_with_cusps_where_forward_goes_round() {
    // From (-1.5, 2) heading up the map to (-1.5, 4) heading down, radius 0.5 m: forward only
    // the robot must loop round; allowed to reverse it can turn and back in (a cusp).
    let grid = grid();
    let mut body = request(Some(90.0));
    body["goal"] = json!([-1.5, 4.0]);
    body["goal_heading_deg"] = json!(-90.0);
    body["turning_radius"] = json!(0.5);
    body["planners"] = json!(["smooth"]);
    let forward = plan(&body);
    body["reverse"] = json!(true);
    let backing = plan(&body);
    let measures = |v: &Value| {
        let s = &v["results"][0]["smooth"];
        assert_eq!(s["found"], true, "{s}");
        let poses = poses_of(s);
        // Each step: a quarter cell at most, turning within step / R, running along the
        // heading (+1) or against it (-1); every pose clear on the grid.
        let mut gears = Vec::new();
        for w in poses.windows(2) {
            let step = (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]);
            assert!(step <= RESOLUTION / 4.0 + 1e-9, "step {step} at {w:?}");
            let turn = wrap_deg(w[1][2] - w[0][2]).abs().to_radians();
            assert!(turn <= step / 0.5 * 1.001 + 1e-9, "turn {turn} at {w:?}");
            if step < 1e-9 {
                continue;
            }
            let going = (w[1][1] - w[0][1]).atan2(w[1][0] - w[0][0]).to_degrees();
            let mid = w[0][2] + wrap_deg(w[1][2] - w[0][2]) / 2.0;
            if wrap_deg(going - mid).abs() < 1.0 {
                gears.push(1);
            } else {
                assert!(
                    wrap_deg(going - mid - 180.0).abs() < 1.0,
                    "a step neither along nor against its heading at {w:?}"
                );
                gears.push(-1);
            }
        }
        for p in &poses {
            assert!(grid.square_clear(p[0], p[1]), "pose {p:?} is not clear");
        }
        let last = poses[poses.len() - 1];
        assert!(wrap_deg(last[2] + 90.0).abs() < 1e-6, "{last:?}");
        let cusps = gears.windows(2).filter(|g| g[0] != g[1]).count();
        assert_eq!(s["cusps"].as_u64().unwrap() as usize, cusps);
        (s["length"].as_f64().unwrap(), cusps, gears.contains(&-1))
    };
    let (forward_length, forward_cusps, forward_backs) = measures(&forward);
    let (backing_length, backing_cusps, backing_backs) = measures(&backing);
    assert_eq!((forward_cusps, forward_backs), (0, false));
    assert!(backing_cusps >= 1 && backing_backs);
    assert!(
        backing_length < forward_length,
        "{backing_length} vs {forward_length}"
    );
    // `reverse` is the smooth planner's, and a flag.
    let mut not_smooth = request(None);
    not_smooth["planners"] = json!(["optimal"]);
    not_smooth.as_object_mut().unwrap().remove("turning_radius");
    not_smooth["reverse"] = json!(false);
    let message = post_json("/api/plan", &not_smooth.to_string()).error(400);
    assert!(
        message.contains("field `reverse` is only used by the smooth planner"),
        "{message}"
    );
    body["reverse"] = json!("yes");
    let message = post_json("/api/plan", &body.to_string()).error(400);
    assert!(
        message.contains("field `reverse` must be true or false"),
        "{message}"
    );
}

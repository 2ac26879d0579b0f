//! `vpmap plan --planner smooth`: the JSON answer rebuilt into a curve and checked by the
//! independent validator, headings in cells and in metres, the SVG, "no drivable path" and
//! bad input.

#![allow(clippy::float_cmp)]

use std::f64::consts::PI;

use serde_json::Value;
use vpmap_plan::smooth::{Gear, Pose, Segment, SmoothCurve, SmoothRules};
use vpmap_plan::{Occupancy, OccupancyGrid, validate_smooth, write_ros_map};

use super::vpmap;

/// A 30 x 20 room with a wall hanging from the top at column 14 (rows 0-11) and a dead end
/// one cell wide at the bottom left (row 17, columns 0-6, walls on rows 16 and 18).
fn grid() -> OccupancyGrid {
    let mut g = OccupancyGrid::new(30, 20, 0.05, [1.0, -2.0], Occupancy::Free).unwrap();
    for y in 0..12 {
        g.set(14, y, Occupancy::Occupied).unwrap();
    }
    for x in 0..7 {
        g.set(x, 16, Occupancy::Occupied).unwrap();
        g.set(x, 18, Occupancy::Occupied).unwrap();
    }
    g.set(0, 17, Occupancy::Occupied).unwrap();
    g
}

pub(super) fn movingai_text(g: &OccupancyGrid) -> String {
    let mut s = format!(
        "type octile\nheight {}\nwidth {}\nmap\n",
        g.height(),
        g.width()
    );
    for y in 0..g.height() {
        for x in 0..g.width() {
            s.push(if g.is_free(x, y) { '.' } else { '@' });
        }
        s.push('\n');
    }
    s
}

fn json(args: &[&str]) -> Value {
    let o = vpmap(args);
    assert!(
        o.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    serde_json::from_slice(&o.stdout).unwrap()
}

pub(super) fn f(v: &Value) -> f64 {
    v.as_f64().unwrap()
}

/// The JSON's segments (Moving AI coordinates: the planner's own) as a curve.
pub(super) fn curve_of(v: &Value) -> SmoothCurve {
    let mut c = SmoothCurve::default();
    for s in v["segments"].as_array().unwrap() {
        let start = &s["start"];
        let radius = s["radius"].as_f64();
        let gear = if s["direction"] == "reverse" {
            Gear::Reverse
        } else {
            Gear::Forward
        };
        let curvature = match (radius, s["turn"].as_str()) {
            (Some(r), Some("left")) => gear.sign() / r,
            (Some(r), Some("right")) => -gear.sign() / r,
            _ => 0.0,
        };
        c.push(Segment {
            start: Pose::new(f(&start[0]), f(&start[1]), f(&start[2]).to_radians()),
            curvature,
            length: f(&s["length"]),
            gear,
        });
    }
    c
}

#[test]
fn smooth_json_in_cells_rebuilds_into_a_drivable_curve() {
    let dir = tempfile::tempdir().unwrap();
    let map = dir.path().join("room.map");
    let g = grid();
    std::fs::write(&map, movingai_text(&g)).unwrap();
    let v = json(&[
        "plan",
        map.to_str().unwrap(),
        "--planner",
        "smooth",
        "--turning-radius",
        "3",
        "--from",
        "4,4,90",
        "--to",
        "25,5,-90",
        "--json",
    ]);
    assert_eq!(v["found"], true, "{v}");
    assert_eq!(v["units"], "cells");
    let curve = curve_of(&v);
    let rules = SmoothRules {
        radius_cells: 3.0,
        start: Pose::new(4.0, 4.0, PI / 2.0),
        start_heading: true,
        goal: Pose::new(25.0, 5.0, -PI / 2.0),
        goal_heading: true,
        reverse: false,
        unknown_passable: false,
    };
    assert_eq!(validate_smooth(&g, &curve, &rules), Ok(()));
    assert!((curve.length() - f(&v["length"])).abs() < 1e-9);
    assert!(f(&v["length"]) >= f(&v["any_angle_length"]));
    assert!(f(&v["max_curvature"]) <= 1.0 / 3.0 + 1e-12);
    assert_eq!(v["cusps"], 0);
    let poses = v["poses"].as_array().unwrap();
    let p = |i: usize| [f(&poses[i][0]), f(&poses[i][1]), f(&poses[i][2])];
    assert_eq!(p(0), [4.0, 4.0, 90.0]);
    assert_eq!(p(poses.len() - 1), [25.0, 5.0, -90.0]);
    for i in 1..poses.len() {
        let (a, b) = (p(i - 1), p(i));
        assert!((a[0] - b[0]).hypot(a[1] - b[1]) <= 0.25 + 1e-9);
    }
    // The text line and the SVG with the tightest turn.
    let svg = dir.path().join("p.svg");
    let o = vpmap(&[
        "plan",
        map.to_str().unwrap(),
        "--planner",
        "smooth",
        "--turning-radius",
        "3",
        "--from",
        "4,4",
        "--to",
        "25,5",
        "--svg",
        svg.to_str().unwrap(),
    ]);
    let line = String::from_utf8_lossy(&o.stdout);
    assert!(line.starts_with("smooth: path found, length"), "{line}");
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.contains(r#"class="smooth-path""#) && text.contains(r#"class="tightest-turn""#));
}

#[test]
fn smooth_headings_in_metres_point_up_the_map() {
    let dir = tempfile::tempdir().unwrap();
    let yaml = dir.path().join("room.yaml");
    let g = grid();
    write_ros_map(&g, &yaml).unwrap();
    // Cell (4, 10)'s centre in metres; heading 90 degrees: +y, up the map, towards row 0.
    let (x, y) = (1.0 + 4.5 * 0.05, -2.0 + (20.0 - 10.5) * 0.05);
    let from = format!("--from={x},{y},90");
    let to = format!(
        "--to={},{},0",
        1.0 + 25.5 * 0.05,
        -2.0 + (20.0 - 10.5) * 0.05
    );
    let v = json(&[
        "plan",
        yaml.to_str().unwrap(),
        "--planner",
        "smooth",
        "--turning-radius",
        "0.15",
        &from,
        &to,
        "--json",
    ]);
    assert_eq!(v["found"], true, "{v}");
    assert_eq!(v["units"], "m");
    let poses = v["poses"].as_array().unwrap();
    assert!((f(&poses[0][2]) - 90.0).abs() < 1e-9);
    // The second pose is up (larger y), not across.
    assert!(f(&poses[1][1]) > f(&poses[0][1]) + 0.005, "{}", poses[1]);
    assert!((f(&poses[1][0]) - f(&poses[0][0])).abs() < 0.002);
    assert!(f(&v["max_curvature"]) <= 1.0 / 0.15 + 1e-9);
    let last = &poses[poses.len() - 1];
    assert!((f(&last[2]) - 0.0).abs() < 1e-9);
}

#[test]
fn smooth_no_room_and_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    let map = dir.path().join("room.map");
    std::fs::write(&map, movingai_text(&grid())).unwrap();
    let m = map.to_str().unwrap();
    // Facing the dead end's closed side: no room to move.
    let o = vpmap(&[
        "plan",
        m,
        "--planner",
        "smooth",
        "--turning-radius",
        "2",
        "--from",
        "1,17,180",
        "--to",
        "25,5",
    ]);
    assert_eq!(o.status.code(), Some(0));
    let line = String::from_utf8_lossy(&o.stdout);
    assert!(
        line.starts_with(
            "smooth: no drivable path: the start pose (1, 17) heading 180 degrees has no room"
        ),
        "{line}"
    );
    let v = json(&[
        "plan",
        m,
        "--planner",
        "smooth",
        "--turning-radius",
        "2",
        "--from",
        "1,17,180",
        "--to",
        "25,5",
        "--json",
    ]);
    assert_eq!(v["found"], false);
    assert_eq!(v["pose"], "start");
    assert!((f(&v["room"]) - 5.0).abs() < 1e-9);
    for (args, needle) in [
        (
            vec!["--turning-radius", "0"],
            "--turning-radius must be a positive number of cells, got 0",
        ),
        (
            vec!["--turning-radius", "inf"],
            "--turning-radius must be a positive number",
        ),
        (vec!["--turning-radius", "31"], "larger than the map"),
        (vec![], "needs --turning-radius"),
    ] {
        let mut all = vec![
            "plan",
            m,
            "--planner",
            "smooth",
            "--from",
            "4,4",
            "--to",
            "25,5",
        ];
        all.extend(args);
        let o = vpmap(&all);
        assert_eq!(o.status.code(), Some(1), "{all:?}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains(needle), "{all:?}: {err}");
        assert!(o.stdout.is_empty());
    }
    let o = vpmap(&[
        "plan",
        m,
        "--planner",
        "smooth",
        "--turning-radius",
        "2",
        "--from",
        "4,4,nan",
        "--to",
        "25,5",
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("not a finite number of degrees"));
    let o = vpmap(&[
        "plan",
        m,
        "--from",
        "4,4",
        "--to",
        "25,5",
        "--turning-radius",
        "2",
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("are for --planner smooth"));
}

#[test]
fn smooth_reverse_backs_out_of_the_dead_end_with_its_cusps_in_the_json_and_the_svg() {
    let dir = tempfile::tempdir().unwrap();
    let map = dir.path().join("room.map");
    let g = grid();
    std::fs::write(&map, movingai_text(&g)).unwrap();
    let svg = dir.path().join("p.svg");
    let v = json(&[
        "plan",
        map.to_str().unwrap(),
        "--planner",
        "smooth",
        "--turning-radius",
        "2",
        "--from",
        "1,17,180",
        "--to",
        "25,5,-90",
        "--reverse",
        "--svg",
        svg.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(v["found"], true, "{v}");
    let curve = curve_of(&v);
    let rules = SmoothRules {
        radius_cells: 2.0,
        start: Pose::new(1.0, 17.0, PI),
        start_heading: true,
        goal: Pose::new(25.0, 5.0, -PI / 2.0),
        goal_heading: true,
        reverse: true,
        unknown_passable: false,
    };
    assert_eq!(validate_smooth(&g, &curve, &rules), Ok(()));
    assert_eq!(curve.segments[0].gear, Gear::Reverse);
    let cusps = v["cusps"].as_u64().unwrap();
    // It backs out facing the dead end's wall and arrives driving up the map: it must
    // change gear on the way.
    assert!(cusps >= 1, "{v}");
    assert_eq!(cusps as usize, curve.cusps());
    let text = std::fs::read_to_string(&svg).unwrap();
    assert_eq!(text.matches(r#"class="cusp""#).count(), curve.cusps());
}

//! `vpmap navigate --planner smooth`: the driven curve of navigate.json rebuilt and checked
//! on the true map by the validator and pose by pose, the SVG, a drive caught facing a wall,
//! and refused inputs.

#![allow(clippy::float_cmp)]

use std::path::PathBuf;

use serde_json::Value;
use vpmap_plan::smooth::{Pose, SmoothRules};
use vpmap_plan::{Occupancy, OccupancyGrid, validate_smooth};

use super::plan_smooth::{curve_of, f, movingai_text};
use crate::{files_in, vpmap};

/// A 40 x 24 room with a wall down from the top at column 20 (rows 0-15), unknown to the
/// robot at the start.
fn truth_grid() -> OccupancyGrid {
    let mut g = OccupancyGrid::new(40, 24, 1.0, [0.0; 2], Occupancy::Free).unwrap();
    for y in 0..16 {
        g.set(20, y, Occupancy::Occupied).unwrap();
    }
    g
}

fn drive(dir: &std::path::Path, name: &str, extra: &[&str]) -> (std::process::Output, PathBuf) {
    let truth = dir.join("truth.map");
    std::fs::write(&truth, movingai_text(&truth_grid())).unwrap();
    let out = dir.join(name);
    let mut args = vec![
        "navigate",
        "--unknown",
        "--truth",
        truth.to_str().unwrap(),
        "--planner",
        "smooth",
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    (vpmap(&args), out)
}

fn read_json(out: &std::path::Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(out.join("navigate.json")).unwrap()).unwrap()
}

#[test]
fn navigate_smooth_drives_a_curve_that_is_drivable_on_the_truth() {
    let dir = tempfile::tempdir().unwrap();
    let (o, out) = drive(
        dir.path(),
        "r2",
        &[
            "--from",
            "5,8,90",
            "--to",
            "35,8",
            "--turning-radius",
            "2",
            "--sensor-range",
            "10",
        ],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(files_in(&out), ["navigate.json", "navigate.svg"]);
    let json = read_json(&out);
    assert_eq!(json["planner"], "smooth");
    assert_eq!(json["outcome"], "reached", "{}", json["reason"]);
    assert!(
        json["replans"].as_u64().unwrap() >= 1,
        "the wall was unknown"
    );
    assert!(f(&json["length"]) >= f(&json["optimum_any_angle"]) - 1e-9);
    assert!(f(&json["max_curvature"]) <= 0.5 + 1e-12);
    assert_eq!(json["cusps"], 0);
    // The segments rebuilt into a curve: drivable on the truth from the asked start pose.
    let curve = curve_of(&json);
    let rules = SmoothRules {
        radius_cells: 2.0,
        start: Pose::new(5.0, 8.0, 90f64.to_radians()),
        start_heading: true,
        goal: Pose::new(35.0, 8.0, 0.0),
        goal_heading: false,
        reverse: false,
        unknown_passable: false,
    };
    assert_eq!(validate_smooth(&truth_grid(), &curve, &rules), Ok(()));
    assert!((curve.length() - f(&json["length"])).abs() < 1e-6);
    // Poses: the asked start first, at most a quarter cell apart, the goal last.
    let poses = json["poses"].as_array().unwrap();
    let p = |i: usize| [f(&poses[i][0]), f(&poses[i][1]), f(&poses[i][2])];
    assert_eq!(p(0), [5.0, 8.0, 90.0]);
    let last = p(poses.len() - 1);
    assert!((last[0] - 35.0).abs() < 1e-6 && (last[1] - 8.0).abs() < 1e-6);
    for i in 1..poses.len() {
        let (a, b) = (p(i - 1), p(i));
        assert!((a[0] - b[0]).hypot(a[1] - b[1]) <= 0.25 + 1e-9);
    }
    assert_eq!(json["moves"].as_u64().unwrap() as usize, poses.len() - 1);
    // Every re-plan starts at the pose the robot stood at.
    for e in json["events"].as_array().unwrap() {
        let at = e["pose"].as_array().unwrap();
        let k = e["moves"].as_u64().unwrap() as usize;
        assert_eq!(f(&at[0]), p(k)[0]);
    }
    let svg = std::fs::read_to_string(out.join("navigate.svg")).unwrap();
    assert!(svg.contains("smooth-path"), "the driven curve is drawn");
    roxmltree::Document::parse(&svg).unwrap();
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.starts_with("smooth: reached after "), "{stdout}");
}

#[test]
fn navigate_smooth_caught_facing_a_wall_says_so_and_backs_up_with_reverse() {
    let dir = tempfile::tempdir().unwrap();
    let args = |reverse: bool| {
        let mut a = vec![
            "--from",
            "14,6,0",
            "--to",
            "35,6",
            "--turning-radius",
            "5",
            "--sensor-range",
            "2",
        ];
        if reverse {
            a.push("--reverse");
        }
        a
    };
    let (o, out) = drive(dir.path(), "forward", &args(false));
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let json = read_json(&out);
    assert_eq!(json["outcome"], "no drivable path from the robot's pose");
    assert_eq!(json["reached"], false);
    assert!(
        json["reason"]
            .as_str()
            .is_some_and(|r| r.contains("radius"))
    );
    let (o, out) = drive(dir.path(), "reverse", &args(true));
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let json = read_json(&out);
    assert_eq!(json["outcome"], "reached", "{}", json["reason"]);
    assert!(json["cusps"].as_u64().unwrap() >= 1);
    let rules = SmoothRules {
        radius_cells: 5.0,
        start: Pose::new(14.0, 6.0, 0.0),
        start_heading: true,
        goal: Pose::new(35.0, 6.0, 0.0),
        goal_heading: false,
        reverse: true,
        unknown_passable: false,
    };
    assert_eq!(
        validate_smooth(&truth_grid(), &curve_of(&json), &rules),
        Ok(())
    );
}

#[test]
fn navigate_smooth_refuses_bad_input_without_writing() {
    let dir = tempfile::tempdir().unwrap();
    let cases: [(&[&str], &str); 5] = [
        (&["--from", "5,8", "--to", "35,8"], "needs --turning-radius"),
        (
            &["--from", "5,8", "--to", "35,8", "--turning-radius", "-1"],
            "--turning-radius must be a positive number of cells, got -1",
        ),
        (
            &["--from", "5,8", "--to", "35,8", "--turning-radius", "500"],
            "larger than the map",
        ),
        (
            &["--from", "5,8,nan", "--to", "35,8", "--turning-radius", "2"],
            "not a finite number of degrees",
        ),
        (
            &["--from", "20,3", "--to", "35,8", "--turning-radius", "2"],
            "--from",
        ),
    ];
    for (extra, expect) in cases {
        let (o, out) = drive(dir.path(), "bad", extra);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{extra:?}");
        assert!(stderr.contains(expect), "{extra:?}: {stderr}");
        assert!(files_in(&out).is_empty(), "{extra:?} left files");
    }
    // The smooth planner's flags with another planner.
    let truth = dir.path().join("truth.map");
    let o = vpmap(&[
        "navigate",
        "--unknown",
        "--truth",
        truth.to_str().unwrap(),
        "--from",
        "5,8",
        "--to",
        "35,8",
        "--turning-radius",
        "2",
        "--out",
        dir.path().join("x").to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("are for --planner smooth"));
}

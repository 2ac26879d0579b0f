//! End-to-end tests of the `vpmap` binary.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::missing_panics_doc)]

mod bench;
mod detect;
mod eval;
mod hostile;
mod navigate;
mod navigate_smooth;
mod outputs;
mod plan_mbpp;
mod plan_smooth;
mod rooms;
mod snap;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn vpmap(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_vpmap"))
        .args(args)
        .output()
        .expect("run vpmap")
}

fn example() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples/office.json")
}

fn files_in(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .map(|rd| {
            rd.map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    names.sort();
    names
}

const OUTPUTS: [&str; 6] = [
    "map.json",
    "map.png",
    "map.svg",
    "model.glb",
    "occupancy.pgm",
    "occupancy.yaml",
];

#[test]
fn build_writes_every_output() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = vpmap(&[
        "build",
        example().to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--robot-radius",
        "0.1",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(files_in(&out), OUTPUTS);
    let map: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("map.json")).unwrap()).unwrap();
    assert_eq!(map["units"], "m");
    assert_eq!(map["camera"]["perspective"], "3pp");
    assert_eq!(map["objects"].as_array().unwrap().len(), 5);
    let yaml = std::fs::read_to_string(out.join("occupancy.yaml")).unwrap();
    for key in [
        "image: occupancy.pgm",
        "resolution:",
        "origin:",
        "negate:",
        "occupied_thresh:",
        "free_thresh:",
    ] {
        assert!(yaml.contains(key), "occupancy.yaml lacks {key}:\n{yaml}");
    }
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains("bookcase") && stdout.contains("pitch"),
        "{stdout}"
    );
}

#[test]
fn demo_reports_its_error_against_the_truth() {
    let dir = tempfile::tempdir().unwrap();
    for method in ["sideview", "projective"] {
        let out = dir.path().join(method);
        let o = vpmap(&["demo", "--out", out.to_str().unwrap(), "--method", method]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let stdout = String::from_utf8_lossy(&o.stdout);
        let line = stdout
            .lines()
            .find(|l| l.starts_with("error against the known truth"))
            .unwrap_or_else(|| panic!("no error line in:\n{stdout}"));
        // "... corners and floor 1.23e-15 m, heights ..."
        let pos: f64 = line
            .split("corners and floor ")
            .nth(1)
            .and_then(|s| s.split(' ').next())
            .and_then(|s| s.parse().ok())
            .unwrap_or_else(|| panic!("cannot parse {line}"));
        assert!(pos < 1e-9, "{method}: demo error {pos} m");
        assert_eq!(files_in(&out), OUTPUTS);
    }
}

/// The demo's printed `vpmap plan` command plans the same MBPP path on its map.json and draws
/// the bugs the demo counted into plan.svg; `demo` and `build` print the same grid (both use
/// the default robot radius).
#[test]
fn demo_prints_a_plan_command_that_draws_its_bugs() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("demo");
    let o = vpmap(&["demo", "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stdout = String::from_utf8_lossy(&o.stdout);
    let number_after = |text: &str, key: &str| -> f64 {
        text.split(key)
            .nth(1)
            .and_then(|s| s.split([' ', ',']).next())
            .and_then(|s| s.parse().ok())
            .unwrap_or_else(|| panic!("no number after {key:?} in {text}"))
    };
    let path_line = stdout
        .lines()
        .find(|l| l.starts_with("path: MBPP"))
        .unwrap();
    let length = number_after(path_line, "): ");
    let bugs = number_after(path_line, " m, ");
    let command = stdout
        .lines()
        .find_map(|l| l.trim_start().strip_prefix("vpmap plan "))
        .unwrap_or_else(|| panic!("no plan command in {stdout}"));
    let mut args = vec!["plan"];
    args.extend(command.split_whitespace());
    args.push("--json");
    let p = vpmap(&args);
    assert!(p.status.success(), "{}", String::from_utf8_lossy(&p.stderr));
    let v: serde_json::Value = serde_json::from_slice(&p.stdout).unwrap();
    assert!(
        (v["length"].as_f64().unwrap() - length).abs() < 0.006,
        "{v}"
    );
    assert_eq!(v["stats"]["bugs"].as_f64(), Some(bugs), "{v}");
    let svg = std::fs::read_to_string(out.join("plan.svg")).unwrap();
    assert!(svg.contains(r#"class="bug-track""#) && svg.contains("MBPP on map.json"));

    let built = dir.path().join("built");
    let b = vpmap(&[
        "build",
        example().to_str().unwrap(),
        "--out",
        built.to_str().unwrap(),
    ]);
    assert!(b.status.success(), "{}", String::from_utf8_lossy(&b.stderr));
    let grid_line = |text: &str| {
        text.lines()
            .find(|l| l.starts_with("occupancy grid"))
            .map(str::to_owned)
            .unwrap()
    };
    assert_eq!(
        grid_line(&stdout),
        grid_line(&String::from_utf8_lossy(&b.stdout))
    );
}

fn assert_fails_cleanly(args: &[&str], out: &Path, needle: &str) {
    let o = vpmap(args);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "expected failure for {args:?}");
    assert!(stderr.starts_with("error: "), "{stderr}");
    assert!(stderr.contains(needle), "expected {needle:?} in: {stderr}");
    assert_eq!(
        stderr.trim_end().lines().count(),
        1,
        "one-line error expected: {stderr}"
    );
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(
        files_in(out).is_empty(),
        "no output may be left behind, found {:?}",
        files_in(out)
    );
}

#[test]
fn bad_scenes_leave_no_files() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let scene = dir.path().join("scene.json");
    let o = out.to_str().unwrap();
    let s = scene.to_str().unwrap();

    std::fs::write(&scene, "{ not json").unwrap();
    assert_fails_cleanly(&["build", s, "--out", o], &out, "malformed");

    let good = std::fs::read_to_string(example()).unwrap();
    // The thesis's method refuses a floor point above the horizon of the scene's vanishing
    // points; the fit (the default) refuses a top corner below its base.
    let mut v: serde_json::Value = serde_json::from_str(&good).unwrap();
    v["objects"][0]["base"]["near"] = serde_json::json!([800.0, 10.0]);
    std::fs::write(&scene, v.to_string()).unwrap();
    assert_fails_cleanly(
        &["build", s, "--out", o, "--method", "sideview"],
        &out,
        "objects[0].base.near",
    );
    let mut v: serde_json::Value = serde_json::from_str(&good).unwrap();
    let near = v["objects"][0]["base"]["near"].clone();
    let below = near[1].as_f64().unwrap() + 150.0;
    v["objects"][0]["top"]["near"] = serde_json::json!([near[0], below]);
    std::fs::write(&scene, v.to_string()).unwrap();
    assert_fails_cleanly(&["build", s, "--out", o], &out, "objects[0].top.near");

    let mut v: serde_json::Value = serde_json::from_str(&good).unwrap();
    v["scale"] = serde_json::json!({"object": "sofa", "dimension": "height", "meters": 1.0});
    std::fs::write(&scene, v.to_string()).unwrap();
    assert_fails_cleanly(&["build", s, "--out", o], &out, "\"sofa\"");

    assert_fails_cleanly(
        &[
            "build",
            dir.path().join("missing.json").to_str().unwrap(),
            "--out",
            o,
        ],
        &out,
        "cannot read scene file",
    );
    assert_fails_cleanly(
        &[
            "build",
            example().to_str().unwrap(),
            "--out",
            o,
            "--resolution",
            "0",
        ],
        &out,
        "--resolution",
    );
    assert_fails_cleanly(
        &[
            "build",
            example().to_str().unwrap(),
            "--out",
            o,
            "--robot-radius",
            "NaN",
        ],
        &out,
        "--robot-radius",
    );
}

#[test]
fn unwritable_output_folder_is_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    // A regular file where the output folder should be.
    let blocker = dir.path().join("blocker");
    std::fs::write(&blocker, "x").unwrap();
    let out = blocker.join("out");
    let o = vpmap(&[
        "build",
        example().to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert!(stderr.contains("cannot create output folder"), "{stderr}");
    assert_eq!(std::fs::read_to_string(&blocker).unwrap(), "x");
}

#[test]
fn synth_then_build_round_trip() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("s.json");
    let o = vpmap(&[
        "synth",
        "--seed",
        "3",
        "--pitch",
        "0",
        "--roll",
        "-4",
        "--lines",
        "--out",
        scene.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(dir.path().join("s.truth.json").exists());
    let out = dir.path().join("out");
    let o = vpmap(&[
        "build",
        scene.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--method",
        "projective",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let map: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("map.json")).unwrap()).unwrap();
    assert_eq!(map["camera"]["perspective"], "2pp");
    assert_eq!(map["method"], "projective");
}

#[cfg(unix)]
#[test]
fn outputs_are_readable_by_others() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = vpmap(&["demo", "--out", out.to_str().unwrap()]);
    assert!(o.status.success());
    for name in OUTPUTS {
        let mode = std::fs::metadata(out.join(name))
            .unwrap()
            .permissions()
            .mode();
        assert_eq!(mode & 0o044, 0o044, "{name} has mode {mode:o}");
    }
}

#[test]
fn usage_errors_are_one_line() {
    for args in [
        vec!["build", "x.json", "--out", "o", "--resolution"],
        vec!["build", "--bogus"],
        vec!["frobnicate"],
    ] {
        let o = vpmap(&args);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.starts_with("error: "), "{stderr}");
        assert_eq!(stderr.trim_end().lines().count(), 1, "{args:?}: {stderr}");
    }
    // A negative number reaches the range check instead of confusing the parser.
    let o = vpmap(&[
        "build",
        example().to_str().unwrap(),
        "--out",
        "o",
        "--resolution",
        "-1",
    ]);
    assert!(String::from_utf8_lossy(&o.stderr).contains("--resolution must be a positive"));
}

#[test]
fn byte_order_mark_and_unknown_fields() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("bom.json");
    let mut text = std::fs::read_to_string(example()).unwrap();
    text = text.replacen('{', "{\"scael\": {\"camera_height_m\": 2},", 1);
    std::fs::write(&scene, format!("\u{feff}{text}")).unwrap();
    let out = dir.path().join("out");
    let o = vpmap(&[
        "build",
        scene.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{stderr}");
    assert!(stderr.contains("unknown field \"scael\""), "{stderr}");
    // A JSON array is not a scene, even though serde could read one positionally.
    std::fs::write(&scene, "[1, {\"width\": 10, \"height\": 10}, []]").unwrap();
    let out2 = dir.path().join("out2");
    assert_fails_cleanly(
        &[
            "build",
            scene.to_str().unwrap(),
            "--out",
            out2.to_str().unwrap(),
        ],
        &out2,
        "must be a JSON object",
    );
}

#[test]
fn a_failed_build_keeps_the_previous_outputs_and_creates_no_folders() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = vpmap(&[
        "build",
        example().to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success());
    let before = std::fs::read(out.join("map.json")).unwrap();
    std::fs::remove_file(out.join("model.glb")).unwrap();
    std::fs::create_dir(out.join("model.glb")).unwrap();
    let o = vpmap(&[
        "build",
        example().to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && stderr.contains("is a folder"),
        "{stderr}"
    );
    assert_eq!(std::fs::read(out.join("map.json")).unwrap(), before);
    assert!(out.join("occupancy.pgm").exists() && out.join("map.png").exists());
    // Nested folders that a failed run created are removed again.
    let bad = dir.path().join("bad.json");
    std::fs::write(&bad, "{\"version\": 2}").unwrap();
    let nested = dir.path().join("a/b/c");
    let o = vpmap(&[
        "build",
        bad.to_str().unwrap(),
        "--out",
        nested.to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    assert!(!dir.path().join("a").exists());
}

const WALLED: &str = "type octile\nheight 4\nwidth 7\nmap\n...@...\n...@...\n...@...\n...@...\n";

#[test]
fn plan_on_a_moving_ai_map_answers_found_and_not_found_with_exit_0() {
    let dir = tempfile::tempdir().unwrap();
    let map = dir.path().join("walled.map");
    std::fs::write(
        &map,
        WALLED.replace(
            "...@...\n...@...\n...@...\n...@...\n",
            "...@...\n...@...\n.......\n...@...\n",
        ),
    )
    .unwrap();
    let m = map.to_str().unwrap();
    let o = vpmap(&["plan", m, "--from", "0,0", "--to", "6,0", "--json"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["found"], true);
    assert_eq!(v["planner"], "astar");
    assert_eq!(v["units"], "cells");
    // Through the gap in row 2: 2 diagonals down, 2 straight, 2 diagonals up + ...: octile length.
    let length = v["length"].as_f64().unwrap();
    assert!(
        (length - (2.0 + 4.0 * 2f64.sqrt())).abs() < 1e-9,
        "{length}"
    );
    assert_eq!(v["waypoints"][0], serde_json::json!([0.0, 0.0]));
    // Any-angle planners cut the corners; the exact optimum is the shortest.
    let mut lengths = Vec::new();
    for planner in ["astar", "astar-ps", "theta-star", "optimal"] {
        let o = vpmap(&[
            "plan",
            m,
            "--from",
            "0,0",
            "--to",
            "6,0",
            "--json",
            "--planner",
            planner,
        ]);
        assert!(
            o.status.success(),
            "{planner}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        assert_eq!(v["planner"], planner);
        lengths.push(v["length"].as_f64().unwrap());
    }
    assert!(
        lengths[3] <= lengths[1] + 1e-9 && lengths[3] <= lengths[2] + 1e-9,
        "{lengths:?}"
    );
    assert!(
        lengths[1] <= lengths[0] + 1e-9 && lengths[3] < lengths[0],
        "{lengths:?}"
    );
    // A wall with no gap: answered, not found, exit 0.
    std::fs::write(&map, WALLED).unwrap();
    let svg = dir.path().join("p.svg");
    let o = vpmap(&[
        "plan",
        m,
        "--from",
        "0,0",
        "--to",
        "6,3",
        "--json",
        "--svg",
        svg.to_str().unwrap(),
    ]);
    assert!(o.status.success());
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["found"], false);
    assert!(std::fs::read_to_string(&svg).unwrap().starts_with("<svg"));
}

#[test]
fn plan_rejects_bad_queries_and_maps() {
    let dir = tempfile::tempdir().unwrap();
    let map = dir.path().join("walled.map");
    std::fs::write(&map, WALLED).unwrap();
    let m = map.to_str().unwrap();
    for (args, needle) in [
        (
            vec!["plan", m, "--from", "0,0", "--to", "9,0"],
            "outside the 7 x 4 map",
        ),
        (
            vec!["plan", m, "--from", "3,0", "--to", "0,0"],
            "lies on an obstacle",
        ),
        (
            vec!["plan", m, "--from", "0.5,0", "--to", "0,0"],
            "whole cell coordinates",
        ),
        (
            vec!["plan", m, "--from", "0;0", "--to", "0,0"],
            "is not a point X,Y",
        ),
        (
            vec!["plan", "nowhere.map", "--from", "0,0", "--to", "1,1"],
            "nowhere.map",
        ),
        (
            vec!["plan", "scene.txt", "--from", "0,0", "--to", "1,1"],
            "unknown map type",
        ),
    ] {
        let o = vpmap(&args);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {stderr}");
        assert!(
            stderr.contains(needle),
            "{args:?}: expected {needle:?} in {stderr}"
        );
        assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    }
    std::fs::write(&map, "type octile\nheight 2\nwidth 3\nmap\n...\n.x.\n").unwrap();
    let o = vpmap(&["plan", m, "--from", "0,0", "--to", "2,0"]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && stderr.contains("line 6"), "{stderr}");
}

#[test]
fn plan_across_a_built_floor_map_in_metres() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    assert!(
        vpmap(&["demo", "--out", out.to_str().unwrap()])
            .status
            .success()
    );
    for file in ["map.json", "occupancy.yaml"] {
        let o = vpmap(&[
            "plan",
            out.join(file).to_str().unwrap(),
            "--from",
            "-1.5,2",
            "--to",
            "2,7.5",
            "--json",
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        assert_eq!(v["found"], true, "{file}");
        assert_eq!(v["units"], "m");
        let length = v["length"].as_f64().unwrap();
        // At least the straight-line distance, and not absurdly longer.
        let straight = (3.5f64).hypot(5.5);
        assert!(
            length >= straight - 0.1 && length < 2.0 * straight,
            "{file}: {length}"
        );
    }
}

#[test]
fn synth_writes_the_visible_corner_annotations_and_the_fit_builds_them() {
    let dir = tempfile::tempdir().unwrap();
    for (annotation, key) in [
        ("face-on", "front_left"),
        ("hidden-base", "far"),
        ("own-yaw", "own_yaw"),
    ] {
        let scene = dir.path().join(format!("{annotation}.json"));
        let o = vpmap(&[
            "synth",
            "--seed",
            "3",
            "--pitch",
            "20",
            "--annotation",
            annotation,
            "--out",
            scene.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let text = std::fs::read_to_string(&scene).unwrap();
        assert!(text.contains(key), "{annotation}: no {key} in the scene");
        let out = dir.path().join(annotation);
        let o = vpmap(&[
            "build",
            scene.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let map: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("map.json")).unwrap()).unwrap();
        assert_eq!(map["method"], "fit");
        assert!(map["objects"][0]["uncertainty"]["centroid_ellipse_95"].is_object());
    }
}

#[test]
fn devices_and_fifos_are_refused_by_name_without_reading() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = out.to_str().unwrap();
    // A scene, a photo and a ROS map image that are character devices: refused at once, by
    // name, with nothing written (reading /dev/zero would fill the memory).
    assert_fails_cleanly(
        &["build", "/dev/zero", "--out", o],
        &out,
        "scene file /dev/zero is a character device",
    );
    let scene = dir.path().join("scene.json");
    let o2 = vpmap(&["detect", "/dev/urandom", "--out", scene.to_str().unwrap()]);
    let e = String::from_utf8_lossy(&o2.stderr);
    assert!(
        !o2.status.success() && e.contains("photo /dev/urandom is a character device"),
        "{e}"
    );
    let yaml = dir.path().join("m.yaml");
    std::fs::write(
        &yaml,
        "image: /dev/zero\nresolution: 0.05\norigin: [0, 0, 0]\n",
    )
    .unwrap();
    let o3 = vpmap(&[
        "plan",
        yaml.to_str().unwrap(),
        "--from",
        "0,0",
        "--to",
        "1,1",
    ]);
    let e = String::from_utf8_lossy(&o3.stderr);
    assert!(
        !o3.status.success() && e.contains("ROS map image /dev/zero is a character device"),
        "{e}"
    );
    #[cfg(unix)]
    {
        let fifo = dir.path().join("pipe.json");
        if std::process::Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .is_ok_and(|s| s.success())
        {
            assert_fails_cleanly(
                &["build", fifo.to_str().unwrap(), "--out", o],
                &out,
                "is a FIFO",
            );
        } else {
            eprintln!("SKIPPED: mkfifo is not available");
        }
    }
}

#[test]
fn plan_stops_mbpp_at_its_bug_step_budget_and_names_the_flag() {
    // A comb of walls with gaps at alternating ends, as a Moving AI map.
    let (w, h) = (40usize, 32usize);
    let mut rows = vec![vec!['.'; w]; h];
    for (k, y) in (2..h - 2).step_by(3).enumerate() {
        for (x, c) in rows[y].iter_mut().enumerate() {
            let gap = if k % 2 == 0 { x == w - 2 } else { x == 1 };
            if !gap {
                *c = '@';
            }
        }
    }
    let text = format!(
        "type octile\nheight {h}\nwidth {w}\nmap\n{}\n",
        rows.iter()
            .map(|r| r.iter().collect::<String>())
            .collect::<Vec<_>>()
            .join("\n")
    );
    let dir = tempfile::tempdir().unwrap();
    let map = dir.path().join("comb.map");
    std::fs::write(&map, text).unwrap();
    let m = map.to_str().unwrap();
    let ok = vpmap(&[
        "plan",
        m,
        "--from",
        "20,0",
        "--to",
        "20,31",
        "--planner",
        "mbpp",
    ]);
    assert!(
        ok.status.success(),
        "{}",
        String::from_utf8_lossy(&ok.stderr)
    );
    let o = vpmap(&[
        "plan",
        m,
        "--from",
        "20,0",
        "--to",
        "20,31",
        "--planner",
        "mbpp",
        "--max-bug-steps",
        "50",
    ]);
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && e.contains("50 bug steps") && e.contains("max_bug_steps"),
        "{e}"
    );
}

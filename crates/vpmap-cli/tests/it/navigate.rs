//! `vpmap navigate`: a run on small Moving AI maps, its files, and refused inputs.

use std::path::Path;

use crate::{files_in, vpmap};

/// Write a Moving AI map of `rows` ('.' free, '@' blocked).
fn write_map(path: &Path, rows: &[&str]) {
    let text = format!(
        "type octile\nheight {}\nwidth {}\nmap\n{}\n",
        rows.len(),
        rows[0].len(),
        rows.join("\n")
    );
    std::fs::write(path, text).unwrap();
}

const TRUTH: [&str; 8] = [
    "............",
    "............",
    "......@.....",
    "......@.....",
    "......@.....",
    "......@.....",
    "......@.....",
    "............",
];

#[test]
fn navigate_unknown_terrain_writes_json_and_svg() {
    let dir = tempfile::tempdir().unwrap();
    let truth = dir.path().join("truth.map");
    write_map(&truth, &TRUTH);
    for planner in ["astar", "astar-ps", "dstar-lite", "mbpp"] {
        let out = dir.path().join(planner);
        let o = vpmap(&[
            "navigate",
            "--unknown",
            "--truth",
            truth.to_str().unwrap(),
            "--from",
            "0,4",
            "--to",
            "11,4",
            "--planner",
            planner,
            "--sensor-range",
            "2",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(
            o.status.success(),
            "{planner}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        assert_eq!(files_in(&out), ["navigate.json", "navigate.svg"]);
        let json: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("navigate.json")).unwrap())
                .unwrap();
        assert_eq!(json["outcome"], "reached", "{planner}");
        assert_eq!(json["planner"], planner);
        let length = json["length"].as_f64().unwrap();
        let octile = json["optimum_octile"].as_f64().unwrap();
        let any_angle = json["optimum_any_angle"].as_f64().unwrap();
        // The wall is unknown at the start: the robot re-plans and drives at least the optimum.
        assert!(json["replans"].as_u64().unwrap() >= 1, "{planner}");
        assert!(
            length >= any_angle - 1e-9 && any_angle <= octile + 1e-9,
            "{planner}: {length}"
        );
        let first = &json["waypoints"][0];
        assert_eq!(
            (first[0].as_f64(), first[1].as_f64()),
            (Some(0.0), Some(4.0))
        );
        let svg = std::fs::read_to_string(out.join("navigate.svg")).unwrap();
        let doc = roxmltree::Document::parse(&svg).unwrap();
        assert!(doc.descendants().any(|n| n.has_tag_name("polyline")));
        assert!(svg.contains("re-planning point") && svg.contains("sensed free floor"));
        check_animation(&doc, &json);
    }
}

/// The SVG's animation: the robot starts on the start's cell centre and moves through the
/// driven waypoints with key times from 0 to 1, ascending, in proportion to the length
/// driven; each re-planning ring appears at a key time in (0, 1].
fn check_animation(doc: &roxmltree::Document, json: &serde_json::Value) {
    let robot = doc
        .descendants()
        .find(|n| n.attribute("class") == Some("robot"))
        .expect("an animated robot");
    let waypoints: Vec<(f64, f64)> = json["waypoints"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| (p[0].as_f64().unwrap(), p[1].as_f64().unwrap()))
        .collect();
    let number = |n: roxmltree::Node, a: &str| n.attribute(a).unwrap().parse::<f64>().unwrap();
    // Moving AI coordinates are cells; the SVG draws cell (x, y) at (x + 0.5, y + 0.5).
    assert_eq!(
        (number(robot, "cx"), number(robot, "cy")),
        (waypoints[0].0 + 0.5, waypoints[0].1 + 0.5)
    );
    let anims: Vec<_> = robot
        .children()
        .filter(|n| n.has_tag_name("animate"))
        .collect();
    assert_eq!(anims.len(), 2);
    let list = |n: roxmltree::Node, a: &str| -> Vec<f64> {
        n.attribute(a)
            .unwrap()
            .split(';')
            .map(|v| v.parse().unwrap())
            .collect()
    };
    let times = list(anims[0], "keyTimes");
    let xs = list(anims[0], "values");
    let ys = list(anims[1], "values");
    assert_eq!(
        (times.len(), xs.len(), ys.len()),
        (xs.len(), ys.len(), times.len())
    );
    assert_eq!((times[0], *times.last().unwrap()), (0.0, 1.0));
    assert!(times.windows(2).all(|w| w[0] < w[1]), "{times:?}");
    // Key times are the fractions of the driven length (the track's own length).
    let length = json["length"].as_f64().unwrap();
    let mut driven = 0.0;
    for k in 1..xs.len() {
        driven += (xs[k] - xs[k - 1]).hypot(ys[k] - ys[k - 1]);
        assert!(
            (driven / length - times[k]).abs() < 1e-4,
            "{k}: {driven} / {length}"
        );
    }
    let rings: Vec<f64> = doc
        .descendants()
        .filter(|n| n.has_tag_name("animate") && n.attribute("attributeName") == Some("opacity"))
        .map(|n| list(n, "keyTimes")[1])
        .collect();
    assert_eq!(rings.len() as u64, json["replans"].as_u64().unwrap());
    assert!(rings.iter().all(|&t| t > 0.0 && t <= 1.0), "{rings:?}");
    assert!(rings.windows(2).all(|w| w[0] <= w[1]), "{rings:?}");
}

#[test]
fn navigate_walled_in_goal_says_unreachable() {
    let dir = tempfile::tempdir().unwrap();
    let truth = dir.path().join("truth.map");
    write_map(
        &truth,
        &["........", "....@@@.", "....@.@.", "....@@@.", "........"],
    );
    let out = dir.path().join("out");
    let o = vpmap(&[
        "navigate",
        "--unknown",
        "--truth",
        truth.to_str().unwrap(),
        "--from",
        "0,0",
        "--to",
        "5,2",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains("goal unreachable after sensing"),
        "{stdout}"
    );
}

#[test]
fn navigate_stops_at_its_limits_and_names_the_flag() {
    let dir = tempfile::tempdir().unwrap();
    let truth = dir.path().join("truth.map");
    write_map(&truth, &TRUTH);
    let run = |extra: &[&str]| {
        let out = dir.path().join("out");
        let _ = std::fs::remove_dir_all(&out);
        let mut args = vec![
            "navigate",
            "--unknown",
            "--truth",
            truth.to_str().unwrap(),
            "--from",
            "0,4",
            "--to",
            "11,4",
            "--sensor-range",
            "2",
            "--out",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let o = vpmap(&args);
        let json = std::fs::read_to_string(out.join("navigate.json"))
            .ok()
            .map(|t| serde_json::from_str::<serde_json::Value>(&t).unwrap());
        (o, json)
    };
    // The wall is unknown at the start, so the drive needs a re-plan: with none allowed the
    // run stops there, says so and writes what it drove.
    let (o, json) = run(&["--max-replans", "0"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let json = json.unwrap();
    assert_eq!(json["outcome"], "re-plan limit reached", "{json}");
    assert_eq!(json["replans"], 0);
    let (o, json) = run(&["--max-moves", "3"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let json = json.unwrap();
    assert_eq!(json["outcome"], "move limit reached", "{json}");
    assert_eq!(json["moves"], 3);
    // A planner's budget is an error naming the flag that raises it; nothing is written.
    let (o, json) = run(&["--max-expansions", "2"]);
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(e.contains("with --max-expansions"), "{e}");
    assert!(json.is_none());
    let (o, _) = run(&["--timeout", "0"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("is not a time limit"));
}

#[test]
fn navigate_refuses_bad_input_without_writing() {
    let dir = tempfile::tempdir().unwrap();
    let truth = dir.path().join("truth.map");
    write_map(&truth, &TRUTH);
    let small = dir.path().join("small.map");
    write_map(&small, &TRUTH[..6]);
    let out = dir.path().join("out");
    let t = truth.to_str().unwrap();
    let o_s = out.to_str().unwrap();
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["--unknown", "--sensor-range", "0"], "--sensor-range 0"),
        (
            vec!["--unknown", "--sensor-range", "-3"],
            "--sensor-range -3",
        ),
        (
            vec!["--unknown", "--sensor-range", "NaN"],
            "--sensor-range NaN",
        ),
        (
            vec!["--unknown", "--sensor-range", "1e9"],
            "at most 256 cells",
        ),
        (vec![small.to_str().unwrap()], "12 x 6"),
        (vec!["--unknown", "--from", "6,3"], "--from"),
    ];
    for (extra, expect) in cases {
        let mut args = vec!["navigate", "--truth", t, "--out", o_s, "--to", "11,4"];
        if !extra.contains(&"--from") {
            args.extend(["--from", "0,4"]);
        }
        args.extend(extra.iter().copied());
        let o = vpmap(&args);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{extra:?}");
        assert!(stderr.contains(expect), "{extra:?}: {stderr}");
        assert!(files_in(&out).is_empty(), "{extra:?} left files");
    }
}

#[test]
fn bench_navigate_runs_every_online_planner_on_the_same_episodes() {
    let dir = tempfile::tempdir().unwrap();
    let map = dir.path().join("walls.map");
    let rows: Vec<String> = (0..24)
        .map(|y| {
            (0..24)
                .map(|x| {
                    if (x == 8 && y < 18) || (x == 16 && y > 5) {
                        '@'
                    } else {
                        '.'
                    }
                })
                .collect()
        })
        .collect();
    let rows: Vec<&str> = rows.iter().map(String::as_str).collect();
    write_map(&map, &rows);
    let out = dir.path().join("bench");
    let o = vpmap(&[
        "bench",
        "--navigate",
        "--per-map",
        "2",
        "--sensor-range",
        "3",
        "-o",
        out.to_str().unwrap(),
        map.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(files_in(&out), ["navigate.csv", "navigate.md"]);
    let csv = std::fs::read_to_string(out.join("navigate.csv")).unwrap();
    let rows: Vec<&str> = csv.lines().skip(1).collect();
    assert_eq!(rows.len(), 2 * 5, "{csv}");
    for planner in ["astar", "astar-ps", "dstar-lite", "mbpp", "dstar-lite-ties"] {
        assert_eq!(
            rows.iter()
                .filter(|r| r.contains(&format!(",{planner},")))
                .count(),
            2
        );
    }
    assert!(rows.iter().all(|r| r.contains(",reached,")), "{csv}");
    // The A* timed beside the common-tie D* Lite drive, forward and backward: time and
    // expansions in its rows only.
    assert!(csv.starts_with(
        "map,episode,start_x,start_y,goal_x,goal_y,planner,outcome,length_cells,planning_time_s,replans,expanded,astar_same_track_time_s,astar_same_track_expanded,backward_astar_same_track_time_s,backward_astar_same_track_expanded\n"
    ));
    for r in &rows {
        let f: Vec<&str> = r.split(',').collect();
        assert_eq!(f.len(), 16, "{r}");
        let shadow_filled = f[12..]
            .iter()
            .all(|v| v.parse::<f64>().is_ok_and(|x| x > 0.0));
        let shadow_empty = f[12..].iter().all(|v| v.is_empty());
        if f[6] == "dstar-lite-ties" {
            assert!(shadow_filled, "{r}");
        } else {
            assert!(shadow_empty, "{r}");
        }
    }
    let md = std::fs::read_to_string(out.join("navigate.md")).unwrap();
    assert!(
        md.contains("| walls.map |") && md.contains("D* Lite / A* time"),
        "{md}"
    );
    // By default D* Lite also drives under the common tie rule, with the tuned A* timed on
    // its track: the "same track" ratio is a number; without astar-ties there is no
    // equal-lengths column under that rule (nor its note).
    let cells_of = |prefix: &str| -> Vec<&str> {
        md.lines()
            .find(|l| l.starts_with(prefix))
            .unwrap()
            .split('|')
            .map(str::trim)
            .collect()
    };
    let (row, header) = (cells_of("| walls.map |"), cells_of("| map |"));
    assert_eq!(header.len(), row.len(), "{md}");
    assert_eq!(header[9], "same track: D* Lite / A* time", "{header:?}");
    assert!(row[9].parse::<f64>().is_ok_and(|r| r > 0.0), "{row:?}");
    assert_eq!(
        header[10], "same track: D* Lite / backward A* time",
        "{header:?}"
    );
    assert!(row[10].parse::<f64>().is_ok_and(|r| r > 0.0), "{row:?}");
    assert!(
        !md.contains("common ties") && !md.contains("`astar-ties` itself"),
        "{md}"
    );
    assert_eq!(header[11], "MBPP / D* Lite length", "{header:?}");
    // MBPP's mean length over D* Lite's (own ties ; common ties), from the CSV's lengths.
    let mean_length = |planner: &str| {
        let v: Vec<f64> = rows
            .iter()
            .map(|r| r.split(',').collect::<Vec<_>>())
            .filter(|f| f[6] == planner)
            .map(|f| f[8].parse::<f64>().unwrap())
            .collect();
        v.iter().sum::<f64>() / v.len() as f64
    };
    let expected = format!(
        "{:.2} ; {:.2}",
        mean_length("mbpp") / mean_length("dstar-lite"),
        mean_length("mbpp") / mean_length("dstar-lite-ties")
    );
    assert_eq!(row[11], expected, "{row:?}");
    // --publish writes its own section and leaves the planners' bench section alone; a
    // broken section is refused before any driving.
    let results = dir.path().join("results.md");
    let before = "# Results\n\n<!-- bench:begin -->\nkept\n<!-- bench:end -->\n";
    std::fs::write(&results, before).unwrap();
    let publish = |doc: &Path| {
        vpmap(&[
            "bench",
            "--navigate",
            "--per-map",
            "1",
            "--online-planners",
            "astar,dstar-lite",
            "-o",
            out.to_str().unwrap(),
            "--publish",
            doc.to_str().unwrap(),
            map.to_str().unwrap(),
        ])
    };
    let o = publish(&results);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(&results).unwrap();
    assert!(text.starts_with(before), "{text}");
    let section = &text[before.len()..];
    assert!(
        section.starts_with("\n<!-- bench-navigate:begin -->\n## Unknown terrain"),
        "{section}"
    );
    assert!(
        section.contains("| walls.map |") && section.ends_with("<!-- bench-navigate:end -->\n")
    );
    // With only A* and D* Lite, only their own comparison columns.
    assert!(
        section.contains(
            "| map | astar | dstar-lite | D* Lite / A* time | D* Lite = A* length |\n|---|---|---|---|---|\n"
        ) && !section.contains("same track")
            && !section.contains("MBPP"),
        "{section}"
    );
    std::fs::write(
        &results,
        "<!-- bench-navigate:end -->\n<!-- bench-navigate:begin -->\n",
    )
    .unwrap();
    let o = publish(&results);
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("broken `bench-navigate` section"));
    let bad = vpmap(&[
        "bench",
        "--navigate",
        "--sensor-range",
        "0",
        "-o",
        out.to_str().unwrap(),
        map.to_str().unwrap(),
    ]);
    assert!(!bad.status.success());
    assert!(String::from_utf8_lossy(&bad.stderr).contains("--sensor-range 0"));
}

//! `vpmap plan --planner mbpp`: the JSON answer, the text line, the SVG drawing of the bugs and
//! the errors. Paths are checked with the independent validator of `vpmap-plan` and their
//! lengths recomputed from the printed waypoints.

use std::path::Path;

use serde_json::Value;
use vpmap_plan::{
    CellXy, Occupancy, OccupancyGrid, parse_movingai_map, validate_path, write_ros_map,
};

use super::{WALLED, vpmap};

/// Two obstacles across the straight line from (0, 4) to (11, 4): bugs split at both.
const TWO_BLOCKS: &str = "type octile\nheight 8\nwidth 12\nmap\n\
    ............\n\
    ............\n\
    ....@@......\n\
    ....@@...@..\n\
    ....@@...@..\n\
    .........@..\n\
    ............\n\
    ............\n";

fn plan_json(args: &[&str]) -> Value {
    let o = vpmap(args);
    assert!(
        o.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    serde_json::from_slice(&o.stdout).unwrap_or_else(|e| {
        panic!(
            "{args:?}: not JSON ({e}): {}",
            String::from_utf8_lossy(&o.stdout)
        )
    })
}

fn points(waypoints: &Value) -> Vec<[f64; 2]> {
    waypoints
        .as_array()
        .expect("waypoints are a list")
        .iter()
        .map(|p| {
            let p = p.as_array().expect("a waypoint is [x, y]");
            assert_eq!(p.len(), 2, "{p:?}");
            [p[0].as_f64().unwrap(), p[1].as_f64().unwrap()]
        })
        .collect()
}

fn polyline_length(points: &[[f64; 2]]) -> f64 {
    points
        .windows(2)
        .map(|w| (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]))
        .sum()
}

/// Moving AI coordinates are whole cells.
fn cells(points: &[[f64; 2]]) -> Vec<CellXy> {
    points
        .iter()
        .map(|p| {
            assert!(p[0].fract() == 0.0 && p[1].fract() == 0.0, "{p:?}");
            CellXy::new(p[0] as usize, p[1] as usize)
        })
        .collect()
}

/// Check one printed path (`best` or an alternative) on a Moving AI map: from `start` to
/// `goal`, its length that of its waypoints, clear under the collision rule.
fn check_path(
    grid: &OccupancyGrid,
    what: &str,
    length: f64,
    waypoints: &Value,
    ends: [[f64; 2]; 2],
) {
    let pts = points(waypoints);
    assert_eq!(pts.first(), Some(&ends[0]), "{what}: {pts:?}");
    assert_eq!(pts.last(), Some(&ends[1]), "{what}: {pts:?}");
    assert!(
        (polyline_length(&pts) - length).abs() < 1e-9,
        "{what}: length {length} but its waypoints measure {}",
        polyline_length(&pts)
    );
    assert_eq!(validate_path(grid, &cells(&pts), false), Ok(()), "{what}");
}

#[test]
fn plan_mbpp_answers_with_alternatives_and_bug_statistics() {
    let dir = tempfile::tempdir().unwrap();
    let map = dir.path().join("blocks.map");
    std::fs::write(&map, TWO_BLOCKS).unwrap();
    let grid = parse_movingai_map(TWO_BLOCKS).unwrap();
    let m = map.to_str().unwrap();
    let query = ["plan", m, "--from", "0,4", "--to", "11,4", "--json"];
    let v = plan_json(&[&query[..], &["--planner", "mbpp"]].concat());
    let optimal = plan_json(&[&query[..], &["--planner", "optimal"]].concat());

    assert_eq!(v["found"], true, "{v}");
    assert_eq!(v["planner"], "mbpp");
    assert_eq!(v["units"], "cells");
    let best = v["length"].as_f64().unwrap();
    let shortest = optimal["length"].as_f64().unwrap();
    assert!(best >= shortest - 1e-9, "mbpp {best} < optimal {shortest}");
    let ends = [[0.0, 4.0], [11.0, 4.0]];
    check_path(&grid, "best", best, &v["waypoints"], ends);

    let alternatives = v["alternatives"].as_array().expect("alternatives list");
    assert!(!alternatives.is_empty(), "two obstacles give detours: {v}");
    for (i, alt) in alternatives.iter().enumerate() {
        let object = alt.as_object().expect("an alternative is an object");
        let mut keys: Vec<&str> = object.keys().map(String::as_str).collect();
        keys.sort_unstable();
        assert_eq!(keys, ["length", "waypoints"], "{alt}");
        let length = alt["length"].as_f64().unwrap();
        assert!(
            length >= best - 1e-9,
            "alternative {i}: {length} < best {best}"
        );
        check_path(
            &grid,
            &format!("alternative {i}"),
            length,
            &alt["waypoints"],
            ends,
        );
    }

    let stats = &v["stats"];
    let count = |key: &str| {
        stats[key]
            .as_u64()
            .unwrap_or_else(|| panic!("stats.{key} missing: {stats}"))
    };
    assert!(count("bugs") >= 2, "{stats}");
    assert!(count("hits") >= 2, "{stats}");
    assert_eq!(count("expanded"), count("bug_steps"));
    assert_eq!(count("generated"), count("bugs"));
    for key in ["waits", "replans", "los_checks", "los_cells"] {
        count(key);
    }
    assert!(stats["time_s"].as_f64().unwrap() >= 0.0);
    // The other planners' answers keep their shape.
    assert_eq!(optimal["alternatives"], serde_json::json!([]));
    assert!(optimal["stats"].get("bugs").is_none(), "{optimal}");

    // The text answer names the bugs and the alternatives.
    let o = vpmap(&[
        "plan",
        m,
        "--from",
        "0,4",
        "--to",
        "11,4",
        "--planner",
        "mbpp",
    ]);
    assert!(o.status.success());
    let line = String::from_utf8_lossy(&o.stdout);
    assert!(line.starts_with("mbpp: path found, length "), "{line}");
    assert!(
        line.contains(&format!("{} bugs", count("bugs")))
            && line.contains(&format!("{} alternative", alternatives.len())),
        "{line}"
    );
}

#[test]
fn plan_mbpp_lengths_and_alternatives_are_in_metres_on_a_ros_map() {
    let dir = tempfile::tempdir().unwrap();
    let cells = parse_movingai_map(TWO_BLOCKS).unwrap();
    let (resolution, origin) = (0.25, [-1.0, 2.0]);
    let mut grid = OccupancyGrid::new(
        cells.width(),
        cells.height(),
        resolution,
        origin,
        Occupancy::Free,
    )
    .unwrap();
    for y in 0..cells.height() {
        for x in 0..cells.width() {
            grid.set(x, y, cells.get(x, y).unwrap()).unwrap();
        }
    }
    let yaml = dir.path().join("blocks.yaml");
    write_ros_map(&grid, &yaml).unwrap();
    let map = dir.path().join("blocks.map");
    std::fs::write(&map, TWO_BLOCKS).unwrap();

    // Cell (x, y) has its centre at origin + ((x + 0.5) r, (height - y - 0.5) r).
    let centre = |x: f64, y: f64| {
        [
            origin[0] + (x + 0.5) * resolution,
            origin[1] + (cells.height() as f64 - y - 0.5) * resolution,
        ]
    };
    let (from, to) = (centre(0.0, 4.0), centre(11.0, 4.0));
    let from_arg = format!("--from={},{}", from[0], from[1]);
    let to_arg = format!("--to={},{}", to[0], to[1]);
    let metres = plan_json(&[
        "plan",
        yaml.to_str().unwrap(),
        &from_arg,
        &to_arg,
        "--planner",
        "mbpp",
        "--json",
    ]);
    let in_cells = plan_json(&[
        "plan",
        map.to_str().unwrap(),
        "--from",
        "0,4",
        "--to",
        "11,4",
        "--planner",
        "mbpp",
        "--json",
    ]);
    assert_eq!(metres["units"], "m");
    let length = metres["length"].as_f64().unwrap();
    assert!(
        (length - in_cells["length"].as_f64().unwrap() * resolution).abs() < 1e-9,
        "{length} m vs {} cells",
        in_cells["length"]
    );
    let alternatives = metres["alternatives"].as_array().unwrap();
    assert_eq!(
        alternatives.len(),
        in_cells["alternatives"].as_array().unwrap().len()
    );
    for (alt, alt_cells) in alternatives
        .iter()
        .zip(in_cells["alternatives"].as_array().unwrap())
    {
        let pts = points(&alt["waypoints"]);
        let alt_length = alt["length"].as_f64().unwrap();
        assert!(
            (polyline_length(&pts) - alt_length).abs() < 1e-9,
            "{alt_length} m but its waypoints measure {}",
            polyline_length(&pts)
        );
        let expected: Vec<[f64; 2]> = points(&alt_cells["waypoints"])
            .iter()
            .map(|p| centre(p[0], p[1]))
            .collect();
        for (p, q) in pts.iter().zip(&expected) {
            assert!(
                (p[0] - q[0]).abs() < 1e-9 && (p[1] - q[1]).abs() < 1e-9,
                "{pts:?} vs {expected:?}"
            );
        }
        assert_eq!(pts.len(), expected.len());
    }
}

#[test]
fn plan_mbpp_unreachable_goal_is_answered_not_found() {
    let dir = tempfile::tempdir().unwrap();
    let map = dir.path().join("walled.map");
    std::fs::write(&map, WALLED).unwrap();
    let m = map.to_str().unwrap();
    let v = plan_json(&[
        "plan",
        m,
        "--from",
        "0,0",
        "--to",
        "6,3",
        "--planner",
        "mbpp",
        "--json",
    ]);
    assert_eq!(v["found"], false, "{v}");
    assert_eq!(v["length"], Value::Null);
    assert_eq!(v["waypoints"], serde_json::json!([]));
    assert_eq!(v["alternatives"], serde_json::json!([]));
    assert!(v["stats"]["bugs"].as_u64().unwrap() >= 1, "{v}");
    let o = vpmap(&[
        "plan",
        m,
        "--from",
        "0,0",
        "--to",
        "6,3",
        "--planner",
        "mbpp",
    ]);
    assert_eq!(o.status.code(), Some(0));
    let line = String::from_utf8_lossy(&o.stdout);
    assert!(line.starts_with("mbpp: no path"), "{line}");
}

/// An element of a parsed XML document: its name and attributes.
#[derive(Debug)]
struct Element {
    name: String,
    attributes: Vec<(String, String)>,
}

impl Element {
    fn attribute(&self, name: &str) -> Option<&str> {
        self.attributes
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_str())
    }
}

/// Every element of an XML document in document order (roxmltree checks well-formedness).
fn parse_xml(text: &str) -> Result<Vec<Element>, String> {
    let doc = roxmltree::Document::parse(text).map_err(|e| e.to_string())?;
    Ok(doc
        .descendants()
        .filter(roxmltree::Node::is_element)
        .map(|n| Element {
            name: n.tag_name().name().to_owned(),
            attributes: n
                .attributes()
                .map(|a| (a.name().to_owned(), a.value().to_owned()))
                .collect(),
        })
        .collect())
}

fn read_svg(path: &Path) -> Vec<Element> {
    let text = std::fs::read_to_string(path).unwrap();
    let elements = parse_xml(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert_eq!(elements[0].name, "svg");
    elements
}

fn is_cell_centre_list(points: &str) -> bool {
    !points.is_empty()
        && points.split(' ').all(|p| {
            p.split(',').count() == 2
                && p.split(',').all(|c| {
                    c.strip_suffix(".5")
                        .is_some_and(|i| !i.is_empty() && i.chars().all(|d| d.is_ascii_digit()))
                })
        })
}

#[test]
fn plan_mbpp_svg_draws_every_bug_and_stays_valid_xml() {
    let dir = tempfile::tempdir().unwrap();
    let map = dir.path().join("blocks.map");
    std::fs::write(&map, TWO_BLOCKS).unwrap();
    let m = map.to_str().unwrap();
    let svg = dir.path().join("mbpp.svg");
    let v = plan_json(&[
        "plan",
        m,
        "--from",
        "0,4",
        "--to",
        "11,4",
        "--planner",
        "mbpp",
        "--json",
        "--svg",
        svg.to_str().unwrap(),
    ]);
    let elements = read_svg(&svg);
    let class = |e: &Element, c: &str| e.attribute("class") == Some(c);
    let tracks: Vec<&Element> = elements
        .iter()
        .filter(|e| e.name == "polyline" && class(e, "bug-track"))
        .collect();
    // Bugs of nested re-planning runs are counted but not drawn.
    let bugs = v["stats"]["bugs"].as_u64().unwrap() as usize;
    if v["stats"]["replans"] == 0 {
        assert_eq!(tracks.len(), bugs, "one track per bug");
    } else {
        assert!(
            (1..=bugs).contains(&tracks.len()),
            "{} tracks",
            tracks.len()
        );
    }
    let mut colours: Vec<&str> = Vec::new();
    for t in &tracks {
        let points = t.attribute("points").unwrap();
        assert!(is_cell_centre_list(points), "{points}");
        colours.push(t.attribute("stroke").expect("a track has its colour"));
    }
    colours.dedup();
    assert_eq!(
        colours.len(),
        tracks.len(),
        "neighbouring bugs share a colour"
    );
    // The first bug starts at the start.
    assert!(
        tracks[0]
            .attribute("points")
            .unwrap()
            .starts_with("0.5,4.5")
    );
    let hits = elements.iter().filter(|e| class(e, "bug-hits")).count();
    assert!(hits >= 1, "no hit drawn");
    assert!(elements.iter().any(|e| class(e, "bug-leave")));
    let alternatives = elements
        .iter()
        .position(|e| class(e, "alternatives"))
        .expect("alternatives drawn");
    let drawn_alternatives = elements[alternatives + 1..]
        .iter()
        .take_while(|e| e.name == "polyline" && e.attribute("class").is_none())
        .count();
    // The alternatives, then the chosen path: one more polyline.
    assert_eq!(
        drawn_alternatives,
        v["alternatives"].as_array().unwrap().len() + 1
    );
    assert!(elements.iter().any(|e| e.name == "text"), "no legend");

    // Other planners: the grid, the path, the title, axes and legend, no bug marks.
    let plain = dir.path().join("astar.svg");
    let o = vpmap(&[
        "plan",
        m,
        "--from",
        "0,4",
        "--to",
        "11,4",
        "--svg",
        plain.to_str().unwrap(),
    ]);
    assert!(o.status.success());
    let elements = read_svg(&plain);
    assert!(
        elements.iter().all(|e| !e
            .attribute("class")
            .is_some_and(|c| c.starts_with("bug") || c == "alternatives")),
        "{elements:?}"
    );
    assert_eq!(elements.iter().filter(|e| e.name == "polyline").count(), 1);
    let text = std::fs::read_to_string(&plain).unwrap();
    for needle in [
        "<title>A* on blocks.map</title>",
        ">column →<",
        ">start<",
        ">goal<",
        ">occupied cell<",
    ] {
        assert!(text.contains(needle), "{needle} missing from {text}");
    }

    // An unreachable goal: the bugs, no path.
    let walled = dir.path().join("walled.map");
    std::fs::write(&walled, WALLED).unwrap();
    let svg = dir.path().join("walled.svg");
    let v = plan_json(&[
        "plan",
        walled.to_str().unwrap(),
        "--from",
        "0,0",
        "--to",
        "6,3",
        "--planner",
        "mbpp",
        "--json",
        "--svg",
        svg.to_str().unwrap(),
    ]);
    assert_eq!(v["found"], false);
    let elements = read_svg(&svg);
    assert!(
        elements
            .iter()
            .any(|e| e.name == "polyline" && e.attribute("class") == Some("bug-track"))
    );
    assert!(
        elements
            .iter()
            .all(|e| e.name != "polyline" || e.attribute("class") == Some("bug-track"))
    );
}

#[test]
fn plan_mbpp_rejects_bad_input_with_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let map = dir.path().join("walled.map");
    std::fs::write(&map, WALLED).unwrap();
    let m = map.to_str().unwrap();
    let folder = dir.path().join("taken.svg");
    std::fs::create_dir(&folder).unwrap();
    let f = folder.to_str().unwrap();
    for (args, code, needle) in [
        (
            vec![
                "plan",
                m,
                "--from",
                "3,0",
                "--to",
                "0,0",
                "--planner",
                "mbpp",
            ],
            1,
            "lies on an obstacle",
        ),
        (
            vec![
                "plan",
                m,
                "--from",
                "0,0",
                "--to",
                "9,0",
                "--planner",
                "mbpp",
            ],
            1,
            "outside the 7 x 4 map",
        ),
        (
            vec![
                "plan",
                m,
                "--from",
                "0,0",
                "--to",
                "0,3",
                "--planner",
                "mbpp",
                "--svg",
                f,
            ],
            1,
            "is a folder",
        ),
        (
            vec![
                "plan",
                m,
                "--from",
                "0,0",
                "--to",
                "0,3",
                "--planner",
                "mbp",
            ],
            2,
            "mbp",
        ),
    ] {
        let o = vpmap(&args);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(code), "{args:?}: {stderr}");
        assert!(stderr.starts_with("error: "), "{stderr}");
        assert!(
            stderr.contains(needle),
            "{args:?}: expected {needle:?} in {stderr}"
        );
        assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
        assert!(o.stdout.is_empty(), "{args:?} printed an answer");
    }
}

//! Moving AI `.map` and `.scen` readers: quirky but valid inputs, every malformed case, and
//! the real benchmark files.

use std::collections::HashMap;

use vpmap_plan::{
    Occupancy, PlanError, parse_movingai_map, parse_scen, read_movingai_map, read_scen,
};

use crate::movingai_dir;

const F: Occupancy = Occupancy::Free;
const O: Occupancy = Occupancy::Occupied;

/// The message of a format error, after checking its line number.
fn map_error_at(text: &str, line: usize) -> String {
    match parse_movingai_map(text) {
        Err(e @ PlanError::MovingAi { line: l, .. }) => {
            assert_eq!(l, line, "{e}");
            e.to_string()
        }
        other => panic!("expected a format error at line {line}, got {other:?}"),
    }
}

fn scen_error_at(text: &str, line: usize) -> String {
    match parse_scen(text) {
        Err(e @ PlanError::MovingAi { line: l, .. }) => {
            assert_eq!(l, line, "{e}");
            e.to_string()
        }
        other => panic!("expected a format error at line {line}, got {other:?}"),
    }
}

#[test]
fn map_quirks_read_alike() {
    let plain = "type octile\nheight 2\nwidth 3\nmap\n.@T\nGSW\n";
    let expected = parse_movingai_map(plain).unwrap();
    assert_eq!(expected.cells(), &[F, O, O, F, F, O]);
    assert_eq!((expected.width(), expected.height()), (3, 2));
    for variant in [
        "type octile\r\nheight 2\r\nwidth 3\r\nmap\r\n.@T\r\nGSW\r\n",
        "type octile\r\nheight 2\r\nwidth 3\r\nmap\r\n.@T\r\nGSW",
        "type octile\nheight 2\nwidth 3\nmap\n.@T\nGSW",
        "type\toctile\nheight\t2\nwidth \t 3\nmap\n.@T\nGSW\n",
        "width 3\nheight 2\ntype octile\nmap\n.@T\nGSW\n",
        "Type Octile  \nHEIGHT 2\t\n\nwidth 3\nMap \n.@T  \nGSW\t\n\n\r\n",
        "  type octile\n height 2\nwidth 3\n\tmap\n.@T\nGSW\n",
    ] {
        assert_eq!(
            parse_movingai_map(variant).unwrap(),
            expected,
            "{variant:?}"
        );
    }
    // `O` is out of bounds as well.
    let grid = parse_movingai_map("type octile\nheight 1\nwidth 1\nmap\nO").unwrap();
    assert_eq!(grid.cells(), &[O]);
}

#[test]
fn malformed_maps_name_the_line_and_value() {
    let e = map_error_at("type octile\nheight 2\nwidth 3\nmap\n.@T\nGS\n", 6);
    assert!(
        e.contains("row 1 has 2 characters") && e.contains("width 3"),
        "{e}"
    );
    let e = map_error_at("type octile\nheight 2\nwidth 3\nmap\n.@T.\nGSW\n", 5);
    assert!(e.contains("4 characters"), "{e}");
    let e = map_error_at("type octile\nheight 2\nwidth 3\nmap\n.@T\nGxW\n", 6);
    assert!(
        e.contains("'x'") && e.contains("column 2") && e.contains("(1, 1)"),
        "{e}"
    );
    let e = map_error_at("type octile\nheight 2\nwidth 3\nmap\n.@T\n", 6);
    assert!(e.contains("too few rows") && e.contains("height 2"), "{e}");
    let e = map_error_at("type octile\nheight 1\nwidth 3\nmap\n.@T\n...\n", 6);
    assert!(e.contains("too many rows"), "{e}");
    let e = map_error_at("type octile\nheight 1\nwidth 3\nmap\n.@T\n\n...\n", 7);
    assert!(e.contains("too many rows"), "{e}");
    let e = map_error_at("type tile\nheight 1\nwidth 1\nmap\n.\n", 1);
    assert!(e.contains("`tile`") && e.contains("octile"), "{e}");
    let e = map_error_at("type octile\nheight 0\nwidth 1\nmap\n", 2);
    assert!(e.contains("`height` is 0"), "{e}");
    let e = map_error_at("type octile\nheight 1\nwidth -4\nmap\n.\n", 3);
    assert!(e.contains("`-4`"), "{e}");
    let e = map_error_at("type octile\nheight 1\nwidth 1.5\nmap\n.\n", 3);
    assert!(e.contains("`1.5`"), "{e}");
    let e = map_error_at("type octile\nheight 1\nheight 1\nwidth 1\nmap\n.\n", 3);
    assert!(e.contains("repeats") && e.contains("line 2"), "{e}");
    let e = map_error_at("type octile\nheight 1\ndepth 1\nwidth 1\nmap\n.\n", 3);
    assert!(e.contains("depth 1"), "{e}");
    let e = map_error_at("type octile\nheight 1\nwidth 1 2\nmap\n.\n", 3);
    assert!(e.contains("`2`"), "{e}");
    let e = map_error_at("type octile\nheight\nwidth 1\nmap\n.\n", 2);
    assert!(e.contains("no value"), "{e}");
    let e = map_error_at("type octile\nwidth 1\nmap\n.\n", 3);
    assert!(e.contains("height"), "{e}");
    let e = map_error_at("height 1\nwidth 1\nmap\n.\n", 3);
    assert!(e.contains("type"), "{e}");
    let e = map_error_at("type octile\nheight 1\nwidth 1\n", 4);
    assert!(e.contains("`map`"), "{e}");
    let e = map_error_at("", 1);
    assert!(e.contains("`map`"), "{e}");
    let e = map_error_at("type octile\nheight 1\nwidth 1\nmap 7\n.\n", 4);
    assert!(e.contains("`7`"), "{e}");
    assert!(matches!(
        parse_movingai_map("type octile\nheight 100000\nwidth 100000\nmap\n"),
        Err(PlanError::GridTooLarge { .. })
    ));
}

#[test]
fn scenario_quirks_read_alike() {
    let tabs = "version 1\n3\tmaps/dao/arena2.map\t281\t209\t100\t41\t98\t44\t3.82843\n";
    let expected = parse_scen(tabs).unwrap();
    assert_eq!(expected.len(), 1);
    let s = &expected[0];
    assert_eq!(
        (s.bucket, s.map.as_str(), s.width, s.height),
        (3, "maps/dao/arena2.map", 281, 209)
    );
    assert_eq!((s.start, s.goal), ((100, 41).into(), (98, 44).into()));
    assert!((s.optimal_length_cells - 3.82843).abs() < 1e-12);
    assert_eq!(s.map_file_name(), "arena2.map");
    for variant in [
        "version 1.0\n3 maps/dao/arena2.map 281 209 100 41 98 44 3.82843",
        "version 1\r\n3\tmaps/dao/arena2.map\t281\t209\t100\t41\t98\t44\t3.82843\r\n",
        "version\t1\n\n3  maps/dao/arena2.map \t281 209 100 41 98 44 3.82843  \n\n",
        "VERSION 1.0\r\n3\tmaps/dao/arena2.map\t281\t209\t100\t41\t98\t44\t3.82843",
    ] {
        assert_eq!(parse_scen(variant).unwrap(), expected, "{variant:?}");
    }
    let bare =
        parse_scen("version 1\n0\tBerlin_0_256.map\t256\t256\t248\t165\t249\t164\t2.00000000")
            .unwrap();
    assert_eq!(bare[0].map_file_name(), "Berlin_0_256.map");
    let windows = parse_scen("version 1\n0 maps\\sc1\\Aftershock.map 512 512 1 2 3 4 5").unwrap();
    assert_eq!(windows[0].map_file_name(), "Aftershock.map");
    assert!(parse_scen("version 1\n").unwrap().is_empty());
}

#[test]
fn malformed_scenarios_name_the_line_and_value() {
    let row = "0\ta.map\t10\t10\t1\t2\t3\t4\t5.5";
    let e = scen_error_at(&format!("version 2\n{row}"), 1);
    assert!(e.contains("version 2"), "{e}");
    let e = scen_error_at(&format!("{row}\n"), 1);
    assert!(e.contains("expected `version 1`"), "{e}");
    let e = scen_error_at("", 1);
    assert!(e.contains("empty"), "{e}");
    let e = scen_error_at(
        &format!("version 1\n{row}\n0\ta.map\t10\t10\t1\t2\t3\t4\n"),
        3,
    );
    assert!(e.contains("8 fields"), "{e}");
    let e = scen_error_at(&format!("version 1\n{row}\t7\n"), 2);
    assert!(e.contains("10 fields"), "{e}");
    let e = scen_error_at("version 1\n0\ta.map\t10\t10\t1\t-2\t3\t4\t5\n", 2);
    assert!(e.contains("start y") && e.contains("`-2`"), "{e}");
    let e = scen_error_at("version 1\nb\ta.map\t10\t10\t1\t2\t3\t4\t5\n", 2);
    assert!(e.contains("bucket"), "{e}");
    let e = scen_error_at("version 1\n0\ta.map\t10\t10\t1\t2\t3\t4\tfive\n", 2);
    assert!(e.contains("`five`"), "{e}");
    let e = scen_error_at("version 1\n0\ta.map\t10\t10\t1\t2\t3\t4\tNaN\n", 2);
    assert!(e.contains("finite"), "{e}");
    let e = scen_error_at("version 1\n0\ta.map\t10\t10\t1\t2\t3\t4\t-1\n", 2);
    assert!(e.contains("-1"), "{e}");
    let e = scen_error_at("version 1\n0\ta.map\t10\t10\t1\t2\t10\t4\t5\n", 2);
    assert!(e.contains("goal (10, 4)") && e.contains("10 x 10"), "{e}");
}

#[test]
#[ignore = "needs ../shared/data/movingai (absent from a fresh clone): cargo test -- --ignored shared_data"]
fn shared_data_every_benchmark_map_and_scenario_file_reads() {
    let dir = movingai_dir();
    let mut maps = HashMap::new();
    for set in std::fs::read_dir(dir.join("maps")).unwrap() {
        for file in std::fs::read_dir(set.unwrap().path()).unwrap() {
            let path = file.unwrap().path();
            let grid = read_movingai_map(&path).unwrap();
            let name = path.file_name().unwrap().to_string_lossy().into_owned();
            maps.insert(name, (grid.width(), grid.height()));
        }
    }
    assert!(maps.len() >= 18, "{} maps", maps.len());
    assert_eq!(maps["ht_chantry.map"], (162, 141));
    assert_eq!(maps["den520d.map"], (256, 257));
    let mut problems = 0;
    for set in std::fs::read_dir(dir.join("scen")).unwrap() {
        for file in std::fs::read_dir(set.unwrap().path()).unwrap() {
            let path = file.unwrap().path();
            let scen = read_scen(&path).unwrap();
            assert!(!scen.is_empty(), "{}", path.display());
            for s in &scen {
                assert_eq!(
                    maps.get(s.map_file_name()),
                    Some(&(s.width, s.height)),
                    "{}: {}",
                    path.display(),
                    s.map
                );
            }
            problems += scen.len();
        }
    }
    println!("{} maps, {problems} scenario problems read", maps.len());
    assert!(problems > 40_000, "{problems}");
}

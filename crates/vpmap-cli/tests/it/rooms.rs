//! `vpmap synth --photos N`, `vpmap build` on the bundled room and `vpmap eval --photos N`.

use crate::vpmap;

#[test]
fn synth_photos_writes_a_room_file_that_builds() {
    let dir = tempfile::tempdir().unwrap();
    let room = dir.path().join("room.json");
    let o = vpmap(&[
        "synth",
        "--photos",
        "3",
        "--seed",
        "4",
        "--out",
        room.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(&room).unwrap();
    let value: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(value["photos"].as_array().unwrap().len(), 3);
    // The bundled example is this room.
    let bundled = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/room.json");
    assert_eq!(text, std::fs::read_to_string(&bundled).unwrap());
    let out = dir.path().join("out");
    let o = vpmap(&[
        "build",
        bundled.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let map: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("map.json")).unwrap()).unwrap();
    assert_eq!(map["cameras"].as_array().unwrap().len(), 3);
    // --photos 1 is the single-photo scene of the same flags.
    let one = dir.path().join("one.json");
    let plain = dir.path().join("plain.json");
    for (path, extra) in [(&one, vec!["--photos", "1"]), (&plain, vec![])] {
        let mut args = vec!["synth", "--seed", "9", "--out", path.to_str().unwrap()];
        args.extend(extra);
        assert!(vpmap(&args).status.success());
    }
    assert_eq!(
        std::fs::read_to_string(&one).unwrap(),
        std::fs::read_to_string(&plain).unwrap()
    );
    for bad in [
        &["synth", "--photos", "9"][..],
        &["synth", "--photos", "2", "--prisms", "1"],
    ] {
        let mut args = bad.to_vec();
        let p = dir.path().join("bad.json");
        args.extend(["--out", p.to_str().unwrap()]);
        assert!(!vpmap(&args).status.success(), "{bad:?}");
    }
}

#[test]
fn eval_photos_reports_rooms_against_their_first_photo() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("eval");
    let o = vpmap(&[
        "eval",
        "--photos",
        "1,3",
        "--trials",
        "2",
        "--sigma",
        "1",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let md = std::fs::read_to_string(out.join("rooms.md")).unwrap();
    assert!(md.contains("| 3 | "), "{md}");
    assert!(out.join("rooms.csv").exists());
    assert!(
        !vpmap(&["eval", "--photos", "0", "--out", out.to_str().unwrap()])
            .status
            .success()
    );
    assert!(
        !vpmap(&["eval", "--boxes", "3", "--out", out.to_str().unwrap()])
            .status
            .success()
    );
}

#[test]
fn build_refuses_a_room_whose_photos_swap_two_names_and_writes_nothing() {
    // Photo 2 of the bundled room calls box0 "box1" and box1 "box0": exit 1, one line
    // naming the test and the objects, no output.
    let bundled = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/room.json");
    let mut room: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&bundled).unwrap()).unwrap();
    for o in room["photos"][1]["objects"].as_array_mut().unwrap() {
        let swapped = match o["name"].as_str().unwrap() {
            "box0" => "box1",
            "box1" => "box0",
            other => other,
        };
        o["name"] = serde_json::Value::String(swapped.to_owned());
    }
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("swapped.json");
    std::fs::write(&path, room.to_string()).unwrap();
    let out = dir.path().join("out");
    crate::assert_fails_cleanly(
        &[
            "build",
            path.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ],
        &out,
        "the room's photos do not fit together",
    );
    let o = vpmap(&[
        "build",
        path.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        stderr.contains("\"box0\"") && stderr.contains("\"box1\""),
        "{stderr}"
    );
    // The library's words, as `/api/build`, `/api/plan` and the Python module give them (issue
    // 39: the same text everywhere).
    let scene = vpmap_metrology::scene::Scene::from_json_str(&room.to_string()).unwrap();
    let want =
        vpmap_metrology::map::build_map(&scene, &vpmap_metrology::map::BuildOptions::default())
            .err()
            .map_or_else(|| panic!("the library built the room"), |e| e.to_string());
    assert_eq!(
        stderr.trim_end(),
        format!("error: building {}: {want}", path.display())
    );
}

/// The room fit's fixture with photo 2 tied to photo 1 by one box and no floor outlines: a
/// tie the map gives as an alternative.
fn tied_room() -> serde_json::Value {
    let fixture = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../vpmap-metrology/tests/fixtures/room-mv00.json");
    let mut room: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(fixture).unwrap()).unwrap();
    for o in room["photos"][1]["objects"].as_array_mut().unwrap() {
        if o["name"] == "box3" {
            o["name"] = serde_json::Value::String("box3-seen-from-2".to_owned());
        }
    }
    for p in room["photos"].as_array_mut().unwrap() {
        p["floor"] = serde_json::json!([]);
    }
    room
}

#[test]
fn build_takes_the_placement_a_room_file_pins_and_refuses_a_bad_one() {
    let dir = tempfile::tempdir().unwrap();
    let build = |room: &serde_json::Value, name: &str| {
        let path = dir.path().join(format!("{name}.json"));
        std::fs::write(&path, room.to_string()).unwrap();
        let out = dir.path().join(name);
        let o = vpmap(&[
            "build",
            path.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let text = std::fs::read_to_string(out.join("map.json")).unwrap();
        (
            serde_json::from_str::<serde_json::Value>(&text).unwrap(),
            String::from_utf8_lossy(&o.stderr).into_owned(),
        )
    };
    let mut room = tied_room();
    let (map, _) = build(&room, "free");
    let alt = map["alternatives"][0].clone();
    assert_eq!(alt["photo"], 2, "{}", map["alternatives"]);
    room["photos"][1]["placement_turn_deg"] = alt["placement_turn_deg"].clone();
    let (pinned, stderr) = build(&room, "pinned");
    assert!(pinned.get("alternatives").is_none(), "{pinned}");
    assert!(stderr.contains("photo 2's placement is pinned"), "{stderr}");
    let at = |m: &serde_json::Value| {
        [
            m["cameras"][1]["position"][0].as_f64().unwrap(),
            m["cameras"][1]["position"][1].as_f64().unwrap(),
        ]
    };
    let (a, b) = (at(&map), at(&pinned));
    assert!((a[0] - b[0]).hypot(a[1] - b[1]) > 0.5, "{a:?} {b:?}");
    // A turn that is not a quarter turn: refused by name, nothing written.
    room["photos"][1]["placement_turn_deg"] = serde_json::json!(100);
    let path = dir.path().join("bad.json");
    std::fs::write(&path, room.to_string()).unwrap();
    let out = dir.path().join("bad");
    crate::assert_fails_cleanly(
        &[
            "build",
            path.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ],
        &out,
        "scene field `photos[1].placement_turn_deg` is invalid: 100 is not a quarter turn: photo 2's placement turn must be 0, 90, 180 or 270 degrees",
    );
}

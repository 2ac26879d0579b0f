//! Issue 13's rough and silent cases on the command line: each gets a clear error naming the
//! value and the limit, in readable numbers, quickly and without writing anything.

use std::path::Path;

use super::{example, vpmap};

fn stderr_of(args: &[&str]) -> String {
    let o = vpmap(args);
    assert!(!o.status.success(), "{args:?} succeeded");
    assert!(o.stdout.is_empty() || !String::from_utf8_lossy(&o.stdout).contains("path found"));
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Build the example into `dir/out` and return its map.json.
fn built_map(dir: &Path) -> std::path::PathBuf {
    let out = dir.join("out");
    let o = vpmap(&[
        "build",
        example().to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    out.join("map.json")
}

/// A digit run longer than 20 characters: a number printed in full instead of readably.
fn has_long_number(text: &str) -> bool {
    text.split(|c: char| !c.is_ascii_digit())
        .any(|run| run.len() > 20)
}

#[test]
fn a_fine_resolution_is_refused_from_the_extent_before_allocating() {
    let dir = tempfile::tempdir().unwrap();
    let map = built_map(dir.path());
    let e = stderr_of(&[
        "plan",
        map.to_str().unwrap(),
        "--from",
        "-1.5,2",
        "--to",
        "2,7.5",
        "--resolution",
        "0.0007",
    ]);
    assert!(
        e.contains("0.0007 m a cell") && e.contains("too large") && e.contains("30000000 cells"),
        "{e}"
    );
}

#[test]
fn map_json_coordinates_and_versions_are_named_as_map_fields() {
    let dir = tempfile::tempdir().unwrap();
    let map = built_map(dir.path());
    let text = std::fs::read_to_string(&map).unwrap();
    let mut value: serde_json::Value = serde_json::from_str(&text).unwrap();
    value["floor"][0][0] = serde_json::json!(1e300);
    let far = dir.path().join("far.json");
    std::fs::write(&far, value.to_string()).unwrap();
    let e = stderr_of(&[
        "plan",
        far.to_str().unwrap(),
        "--from",
        "-1.5,2",
        "--to",
        "2,7.5",
    ]);
    assert!(
        e.contains("`floor[0][0]` is 1e300") && !has_long_number(&e),
        "{e}"
    );
    value["floor"][0][0] = serde_json::json!(1.0);
    value["version"] = serde_json::json!(2);
    let v2 = dir.path().join("v2.json");
    std::fs::write(&v2, value.to_string()).unwrap();
    let e = stderr_of(&[
        "plan",
        v2.to_str().unwrap(),
        "--from",
        "-1.5,2",
        "--to",
        "2,7.5",
    ]);
    assert!(
        e.contains("map.json field `version` is 2") && !e.contains("scene"),
        "{e}"
    );
}

#[test]
fn ros_yaml_values_out_of_range_are_refused_readably() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("m.pgm"),
        b"P5\n4 4\n255\n"
            .iter()
            .chain([254u8; 16].iter())
            .copied()
            .collect::<Vec<u8>>(),
    )
    .unwrap();
    let cases = [
        (
            "resolution: 1e-300\norigin: [0, 0, 0]\n",
            "`resolution` is 1e-300; it must be from 1e-5 to 10000",
        ),
        (
            "resolution: 0.05\norigin: [1e300, 0, 0]\n",
            "`origin` is [1e300, 0, 0]",
        ),
        (
            "resolution: 0.05\norigin: [0, 0, 0]\nnegate: foo\n",
            "expected 0, 1, true or false",
        ),
    ];
    for (i, (body, needle)) in cases.iter().enumerate() {
        let yaml = dir.path().join(format!("m{i}.yaml"));
        std::fs::write(&yaml, format!("image: m.pgm\n{body}")).unwrap();
        let e = stderr_of(&[
            "plan",
            yaml.to_str().unwrap(),
            "--from",
            "0.1,0.1",
            "--to",
            "0.1,0.1",
        ]);
        assert!(e.contains(needle), "{body}: {e}");
        assert!(
            !e.contains("untagged") && !has_long_number(&e),
            "{body}: {e}"
        );
    }
}

/// A PNG of `width` x `height` grey pixels (its data need not match a huge header).
fn png(width: u32, height: u32, data_rows: u32) -> Vec<u8> {
    let chunk = |kind: &[u8], data: &[u8]| {
        let mut c = (data.len() as u32).to_be_bytes().to_vec();
        c.extend_from_slice(kind);
        c.extend_from_slice(data);
        let mut crc = crc32fast::Hasher::new();
        crc.update(kind);
        crc.update(data);
        c.extend_from_slice(&crc.finalize().to_be_bytes());
        c
    };
    let mut ihdr = width.to_be_bytes().to_vec();
    ihdr.extend_from_slice(&height.to_be_bytes());
    ihdr.extend_from_slice(&[8, 0, 0, 0, 0]);
    let raw: Vec<u8> = (0..data_rows)
        .flat_map(|_| std::iter::once(0).chain(std::iter::repeat_n(254, width as usize)))
        .collect();
    let mut out = b"\x89PNG\r\n\x1a\n".to_vec();
    out.extend(chunk(b"IHDR", &ihdr));
    out.extend(chunk(b"IDAT", &stored_zlib(&raw)));
    out.extend(chunk(b"IEND", &[]));
    out
}

/// `data` as a zlib stream of stored (uncompressed) blocks.
fn stored_zlib(data: &[u8]) -> Vec<u8> {
    let mut out = vec![0x78, 0x01];
    let blocks: Vec<&[u8]> = data.chunks(65535).collect();
    for (i, block) in blocks.iter().enumerate() {
        out.push(u8::from(i + 1 == blocks.len()));
        let n = block.len() as u16;
        out.extend_from_slice(&n.to_le_bytes());
        out.extend_from_slice(&(!n).to_le_bytes());
        out.extend_from_slice(block);
    }
    let (mut a, mut b) = (1u32, 0u32);
    for &x in data {
        a = (a + u32::from(x)) % 65521;
        b = (b + a) % 65521;
    }
    out.extend_from_slice(&((b << 16) | a).to_be_bytes());
    out
}

#[test]
fn map_images_are_bounded_by_their_header_and_named_plainly() {
    let dir = tempfile::tempdir().unwrap();
    let yaml = |name: &str| {
        let path = dir.path().join(format!("{name}.yaml"));
        std::fs::write(
            &path,
            format!("image: {name}.png\nresolution: 0.05\norigin: [0, 0, 0]\n"),
        )
        .unwrap();
        path
    };
    // A header of 14000 x 14000 pixels in a file of a few hundred bytes.
    std::fs::write(dir.path().join("huge.png"), png(14_000, 14_000, 1)).unwrap();
    let e = stderr_of(&[
        "plan",
        yaml("huge").to_str().unwrap(),
        "--from",
        "0.1,0.1",
        "--to",
        "0.1,0.1",
    ]);
    assert!(
        e.contains("14000 x 14000") && e.contains("3.5 GB") && e.contains("540 MB"),
        "{e}"
    );
    // A damaged header checksum.
    let mut bad = png(8, 8, 8);
    bad[29] ^= 0xFF;
    std::fs::write(dir.path().join("bad.png"), bad).unwrap();
    let e = stderr_of(&[
        "plan",
        yaml("bad").to_str().unwrap(),
        "--from",
        "0.1,0.1",
        "--to",
        "0.1,0.1",
    ]);
    assert!(e.contains("IHDR") && !e.contains("ChunkType"), "{e}");
    // The same picture intact plans.
    std::fs::write(dir.path().join("good.png"), png(8, 8, 8)).unwrap();
    let o = vpmap(&[
        "plan",
        yaml("good").to_str().unwrap(),
        "--from",
        "0.1,0.1",
        "--to",
        "0.3,0.3",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn huge_cell_coordinates_are_shown_as_given() {
    let dir = tempfile::tempdir().unwrap();
    let map = dir.path().join("a.map");
    std::fs::write(
        &map,
        "type octile\nheight 4\nwidth 4\nmap\n....\n....\n....\n....\n",
    )
    .unwrap();
    let e = stderr_of(&[
        "plan",
        map.to_str().unwrap(),
        "--from",
        "1e20,1",
        "--to",
        "1,1",
    ]);
    assert!(
        e.contains("--from (1e20, 1) is outside the 4 x 4 map"),
        "{e}"
    );
    assert!(!has_long_number(&e), "{e}");
}

#[test]
fn scenes_follow_the_pages_rules() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(example()).unwrap();
    let scene: serde_json::Value = serde_json::from_str(&text).unwrap();
    // 501 objects: the page refuses them, and so does the command line.
    let mut many = scene.clone();
    let first = many["objects"][0].clone();
    many["objects"] = serde_json::Value::Array(
        (0..501)
            .map(|i| {
                let mut o = first.clone();
                o["name"] = serde_json::json!(format!("o{i}"));
                o
            })
            .collect(),
    );
    let path = dir.path().join("many.json");
    std::fs::write(&path, many.to_string()).unwrap();
    let out = dir.path().join("out");
    let e = stderr_of(&[
        "build",
        path.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(
        e.contains("`objects`") && e.contains("501") && e.contains("at most 500"),
        "{e}"
    );
    // An unknown field nested 200 deep: refused as malformed, not read with every
    // unknown-field warning silenced.
    let mut nested = scene;
    let mut deep = serde_json::json!(1);
    for _ in 0..200 {
        deep = serde_json::json!({ "a": deep });
    }
    nested["zzz"] = deep;
    let path = dir.path().join("nested.json");
    std::fs::write(&path, nested.to_string()).unwrap();
    let e = stderr_of(&[
        "build",
        path.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(e.contains("malformed"), "{e}");
    assert!(!out.exists());
}

/// A fuzz-found scene (`fuzz/regressions/web_body/build-svd-nan-fd183c8d`, its body): the joint
/// fit's start ran to a focal length of about 1e159, and nalgebra's SVD panicked (exit 101).
#[test]
fn a_runaway_starting_focal_length_is_an_error_not_a_panic() {
    let dir = tempfile::tempdir().unwrap();
    let input = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fuzz/regressions/web_body/build-svd-nan-fd183c8d");
    let text = std::fs::read_to_string(input).unwrap();
    let (_, body) = text.split_once('\n').unwrap();
    let path = dir.path().join("scene.json");
    std::fs::write(&path, body).unwrap();
    let out = dir.path().join("out");
    let o = vpmap(&[
        "build",
        path.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(!e.contains("panicked"), "{e}");
    assert!(e.contains("error:") && e.contains("objects[0]"), "{e}");
    assert!(!out.exists());
}

#[cfg(unix)]
#[test]
fn a_dangling_output_link_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let link = dir.path().join("out");
    std::os::unix::fs::symlink(dir.path().join("missing"), &link).unwrap();
    let e = stderr_of(&[
        "build",
        example().to_str().unwrap(),
        "--out",
        link.to_str().unwrap(),
    ]);
    assert!(
        e.contains("symbolic link") && e.contains("missing") && !e.contains("File exists"),
        "{e}"
    );
}

#[test]
fn planner_budgets_name_their_flags() {
    let dir = tempfile::tempdir().unwrap();
    let map = built_map(dir.path());
    let m = map.to_str().unwrap();
    let e = stderr_of(&[
        "plan",
        m,
        "--from",
        "-1.5,2",
        "--to",
        "2,7.5",
        "--max-expansions",
        "10",
    ]);
    assert!(
        e.contains("10 node expansions") && e.contains("--max-expansions"),
        "{e}"
    );
    let e = stderr_of(&[
        "plan",
        m,
        "--from",
        "-1.5,2",
        "--to",
        "2,7.5",
        "--planner",
        "theta-star",
        "--max-sight-cells",
        "5",
    ]);
    assert!(
        e.contains("line-of-sight") && e.contains("--max-sight-cells"),
        "{e}"
    );
    for bad in ["0", "-1", "abc", "1e9"] {
        let e = stderr_of(&[
            "plan",
            m,
            "--from",
            "-1.5,2",
            "--to",
            "2,7.5",
            "--timeout",
            bad,
        ]);
        assert!(
            e.contains("--timeout") && e.contains("seconds"),
            "{bad}: {e}"
        );
    }
    let e = stderr_of(&[
        "plan",
        m,
        "--from",
        "-1.5,2",
        "--to",
        "2,7.5",
        "--robot-radius",
        "1e300",
    ]);
    assert!(e.contains("at most 1000, got 1e300"), "{e}");
}

/// Regression: a missing input said "No such file or directory" twice (the reading error's
/// message held the system's reason and passed it on as its cause too).
#[test]
fn a_missing_file_is_named_once_with_its_reason_once() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("missing.json");
    let m = missing.to_str().unwrap();
    let out = dir.path().join("out");
    for args in [
        vec!["build", m, "--out", out.to_str().unwrap()],
        vec!["plan", m, "--from", "0,0", "--to", "1,1"],
        vec!["snap", m, m, "-o", out.to_str().unwrap()],
    ] {
        let e = stderr_of(&args);
        assert_eq!(e.matches("No such file or directory").count(), 1, "{e}");
        assert!(e.contains("missing.json"), "{e}");
    }
}

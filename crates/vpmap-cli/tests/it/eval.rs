//! `vpmap eval` end to end: a small run writes every file, is exact at zero noise and is the
//! same twice; bad arguments fail with one line and leave nothing behind.

use std::path::Path;

use crate::{files_in, vpmap};

/// The metrics whose perfect value is 100 (everything else is perfect at 0, `scale_factor`
/// at 1).
fn perfect(metric: &str) -> f64 {
    if metric.starts_with("area_overlap_pct") {
        100.0
    } else if metric == "scale_factor" {
        1.0
    } else {
        0.0
    }
}

fn small_run(out: &Path, extra: &[&str]) -> std::process::Output {
    let mut args = vec![
        "eval",
        "--out",
        out.to_str().unwrap(),
        "--trials",
        "1",
        "--sigma",
        "0,1",
        "--seed",
        "5",
    ];
    args.extend_from_slice(extra);
    vpmap(&args)
}

#[test]
fn a_small_run_writes_every_file_and_is_exact_without_noise() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("eval");
    let o = small_run(&out, &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(
        o.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let files = files_in(&out);
    for name in ["summary.json", "summary.md", "objects.csv", "failures.csv"] {
        assert!(
            files.contains(&name.to_owned()),
            "{name} missing: {files:?}"
        );
    }
    for metric in [
        "centroid_shift_pct",
        "centroid_distance_pct",
        "area_overlap_pct",
        "area_error_pct",
        "pose_error_deg",
        "skew_error_deg",
    ] {
        for ext in ["svg", "png"] {
            let name = format!("box_{metric}.{ext}");
            assert!(files.contains(&name), "{name} missing: {files:?}");
        }
        let svg = std::fs::read_to_string(out.join(format!("box_{metric}.svg"))).unwrap();
        roxmltree::Document::parse(&svg).unwrap();
        // One box per set-up, each labelled.
        assert!(svg.contains("2pp-9") && svg.contains("3pp-8"), "{metric}");
        assert!(std::fs::read(out.join(format!("box_{metric}.png"))).unwrap()[1..4] == *b"PNG");
    }

    // summary.json: the required keys, and at zero noise every metric is exact.
    let rows: Vec<serde_json::Value> =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let mut checked = 0;
    for row in &rows {
        for key in [
            "method", "sigma", "metric", "median", "p5", "p95", "min", "max",
        ] {
            assert!(row.get(key).is_some(), "{key} missing in {row}");
        }
        if row["sigma"].as_f64().unwrap() != 0.0 {
            continue;
        }
        let metric = row["metric"].as_str().unwrap();
        // No error bars at zero noise: the coverage rows are empty.
        if row["count"] == 0 {
            assert!(row["median"].is_null(), "{row}");
            continue;
        }
        for key in ["median", "p5", "p95", "min", "max"] {
            let v = row[key].as_f64().unwrap_or_else(|| panic!("{row}"));
            assert!(
                (v - perfect(metric)).abs() < 1e-6,
                "{metric} {key} = {v} at sigma 0: {row}"
            );
        }
        checked += 1;
    }
    assert!(checked > 100, "{checked} rows at sigma 0");
    let methods: std::collections::BTreeSet<&str> =
        rows.iter().map(|r| r["method"].as_str().unwrap()).collect();
    assert_eq!(methods.len(), 3);
    assert!(
        rows.iter()
            .any(|r| r["metric"] == "centroid_shift_pct_true_scale")
    );

    // objects.csv: every object of every set-up, both methods, both noise levels (less the
    // scenes refused at 1 px); at zero noise every value exact.
    let csv = std::fs::read_to_string(out.join("objects.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let sigma_col = header.iter().position(|h| *h == "sigma_px").unwrap();
    let first_metric = header
        .iter()
        .position(|h| *h == "centroid_shift_pct")
        .unwrap();
    let mut zero_rows = 0;
    for line in lines {
        let cells: Vec<&str> = line.split(',').collect();
        assert_eq!(cells.len(), header.len(), "{line}");
        if cells[sigma_col] != "0" {
            continue;
        }
        zero_rows += 1;
        for (name, cell) in header[first_metric..].iter().zip(&cells[first_metric..]) {
            if cell.is_empty() {
                // Error bars only under noise.
                let bars = ["centroid_in_ellipse_95", "centroid_mahalanobis_sq"];
                assert!(bars.contains(name) || name.ends_with("_2sd") || name.ends_with("_z"));
                continue;
            }
            let v: f64 = cell.parse().unwrap_or_else(|_| panic!("{name} = {cell:?}"));
            assert!((v - perfect(name)).abs() < 1e-6, "{name} = {v}: {line}");
        }
    }
    // 17 set-ups of 3-5 objects, 3 methods.
    assert!(zero_rows >= 3 * 17 * 3, "{zero_rows} rows at sigma 0");

    let md = std::fs::read_to_string(out.join("summary.md")).unwrap();
    for needle in [
        "fig. 6.8",
        "fig. 6.23",
        "±9.5%",
        "3pp-8",
        "(box_area_overlap_pct.png)",
        "refused",
    ] {
        assert!(md.contains(needle), "summary.md lacks {needle}");
    }

    // The same arguments give the same files, byte for byte.
    let again = dir.path().join("again");
    let o = small_run(&again, &[]);
    assert!(o.status.success());
    for name in files {
        assert_eq!(
            std::fs::read(out.join(&name)).unwrap(),
            std::fs::read(again.join(&name)).unwrap(),
            "{name} differs between two runs"
        );
    }
}

#[test]
fn publishing_writes_the_section_with_links_that_resolve() {
    let dir = tempfile::tempdir().unwrap();
    let docs = dir.path().join("docs");
    std::fs::create_dir(&docs).unwrap();
    let results = docs.join("results.md");
    std::fs::write(
        &results,
        "# Results\n\n<!-- eval:begin -->\nold\n<!-- eval:end -->\n\nafter\n",
    )
    .unwrap();
    let out = dir.path().join("out/eval");
    let o = small_run(
        &out,
        &[
            "--experiments",
            "2pp-1,3pp-1",
            "--methods",
            "sideview",
            "--publish",
            results.to_str().unwrap(),
        ],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(&results).unwrap();
    assert!(text.starts_with("# Results\n\n<!-- eval:begin -->\n## Map accuracy"));
    assert!(text.ends_with("<!-- eval:end -->\n\nafter\n"), "{text}");
    assert!(!text.contains("\nold\n"));
    assert!(text.contains("logical cores") && text.contains("eval --out"));
    let links: Vec<&str> = text
        .split("](")
        .skip(1)
        .map(|s| s.split(')').next().unwrap())
        .collect();
    assert_eq!(links.len(), 7, "{links:?}");
    for link in links {
        assert!(link.starts_with("../out/eval/"), "{link}");
        assert!(docs.join(link).exists(), "{link} does not resolve");
    }
}

#[test]
fn a_long_edge_run_publishes_its_own_section_beside_the_default_one() {
    let dir = tempfile::tempdir().unwrap();
    let results = dir.path().join("results.md");
    let before = "# Results\n\n<!-- eval:begin -->\nkept\n<!-- eval:end -->\n";
    std::fs::write(&results, before).unwrap();
    let out = dir.path().join("long");
    let run = |extra: &[&str]| {
        let mut args = vec!["--experiments", "2pp-1", "--methods", "sideview"];
        args.extend_from_slice(extra);
        small_run(&out, &args)
    };
    let o = run(&["--vp-edges", "long", "--publish", results.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(&results).unwrap();
    // The default section is untouched; the long-edge one is appended after it.
    assert!(text.starts_with(before), "{text}");
    let long = &text[before.len()..];
    assert!(
        long.starts_with("\n<!-- eval-long-edges:begin -->\n## Map accuracy"),
        "{long}"
    );
    assert!(long.ends_with("<!-- eval-long-edges:end -->\n"), "{long}");
    assert!(
        long.contains("long edges") && long.contains("--vp-edges long"),
        "{long}"
    );
    // A broken long-edge section is refused before any work.
    std::fs::write(
        &results,
        "<!-- eval-long-edges:end -->\n<!-- eval-long-edges:begin -->\n",
    )
    .unwrap();
    let o = run(&["--vp-edges", "long", "--publish", results.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("broken `eval-long-edges` section"));
}

fn assert_refused(args: &[&str], out: &Path, needle: &str) {
    let o = vpmap(args);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{args:?}: {stderr}");
    assert!(stderr.starts_with("error: "), "{stderr}");
    assert!(stderr.contains(needle), "expected {needle:?} in {stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    assert!(files_in(out).is_empty(), "left behind: {:?}", files_in(out));
}

#[test]
fn bad_arguments_fail_with_one_line_and_write_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = out.to_str().unwrap();
    for (args, needle) in [
        (vec!["--trials", "0"], "--trials"),
        (vec!["--sigma", "-1"], "--sigma"),
        (vec!["--sigma", "0,NaN"], "--sigma"),
        (vec!["--sigma", "1,inf"], "--sigma"),
        (vec!["--sigma", "1,x"], "is not a number"),
        (vec!["--sigma", "1,1"], "twice"),
        (
            vec!["--methods", "sideview,magic"],
            "unknown method \"magic\"",
        ),
        (vec!["--experiments", "5pp"], "is not a set-up"),
        (vec!["--sigma", "0,1", "--plot-sigma", "2"], "--plot-sigma"),
        (vec!["--vp-edges", "lines"], "is not an edge model"),
        (vec!["--vp-edges", ""], "is not an edge model"),
        (
            vec!["--vp-edges", "long", "--vp-edge-px", "5000"],
            "--vp-edge-px \"5000\" must be a length in pixels from 20 to 720",
        ),
        (
            vec!["--vp-edges", "long", "--vp-edge-px", "-600"],
            "--vp-edge-px",
        ),
        (
            vec!["--vp-edges", "long", "--vp-edge-px", "NaN"],
            "--vp-edge-px",
        ),
        (
            vec!["--vp-edges", "long", "--vp-edge-px", "abc"],
            "--vp-edge-px",
        ),
        (
            vec!["--vp-edges", "long", "--vp-edge-count", "1"],
            "--vp-edge-count",
        ),
        (
            vec!["--vp-edges", "long", "--vp-edge-count", "2.5"],
            "--vp-edge-count",
        ),
        (vec!["--vp-edge-px", "300"], "apply only to --vp-edges long"),
        (
            vec!["--vp-edge-count", "4"],
            "apply only to --vp-edges long",
        ),
    ] {
        let mut full = vec!["eval", "--out", o];
        if args[0] != "--trials" {
            full.extend(["--trials", "1"]);
        }
        full.extend(args);
        assert_refused(&full, &out, needle);
    }
    // An output folder under a regular file.
    let blocker = dir.path().join("blocker");
    std::fs::write(&blocker, "x").unwrap();
    let nested = blocker.join("out");
    assert_refused(
        &["eval", "--out", nested.to_str().unwrap(), "--trials", "1"],
        &nested,
        "cannot create output folder",
    );
    assert_eq!(std::fs::read_to_string(&blocker).unwrap(), "x");
    // A publish target with a broken section is refused before any work.
    let doc = dir.path().join("results.md");
    std::fs::write(&doc, "<!-- eval:end -->\n<!-- eval:begin -->\n").unwrap();
    assert_refused(
        &[
            "eval",
            "--out",
            o,
            "--trials",
            "1",
            "--publish",
            doc.to_str().unwrap(),
        ],
        &out,
        "broken `eval` section",
    );
    // A negative trial count is a usage error (exit 2).
    let usage = vpmap(&["eval", "--out", o, "--trials", "-3"]);
    assert_eq!(usage.status.code(), Some(2));
    assert!(!out.exists());
}

#[test]
fn long_vanishing_edges_are_exact_without_noise_and_named_in_the_report() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("long");
    let o = small_run(
        &out,
        &[
            "--vp-edges",
            "long",
            "--vp-edge-px",
            "500",
            "--vp-edge-count",
            "4",
        ],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let rows: Vec<serde_json::Value> =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let mut checked = 0;
    // (No error bars at zero noise: the coverage rows have no values.)
    for row in rows
        .iter()
        .filter(|r| r["sigma"].as_f64() == Some(0.0) && r["count"] != 0)
    {
        let metric = row["metric"].as_str().unwrap();
        let v = row["median"].as_f64().unwrap();
        assert!((v - perfect(metric)).abs() < 1e-6, "{metric} = {v}: {row}");
        assert_eq!(row["refused"].as_u64(), Some(0), "{row}");
        checked += 1;
    }
    assert!(checked > 100, "{checked} rows at sigma 0");
    let md = std::fs::read_to_string(out.join("summary.md")).unwrap();
    assert!(md.contains("vanishing points from 4 long edges of 500 px each"));
    assert!(md.contains("4 long straight edges of 500 px (`--vp-edges long`"));
    assert!(!md.contains("as the box edges through those noisy corners"));
    // The default names no long edges, and at 1 px the two models differ.
    let objects = dir.path().join("objects");
    assert!(small_run(&objects, &[]).status.success());
    let default_md = std::fs::read_to_string(objects.join("summary.md")).unwrap();
    assert!(default_md.contains("as the box edges through those noisy corners"));
    assert!(!default_md.contains("long edges"));
    assert_ne!(
        std::fs::read(out.join("objects.csv")).unwrap(),
        std::fs::read(objects.join("objects.csv")).unwrap()
    );
}

#[test]
fn the_views_run_publishes_its_own_section_with_refusals_and_coverage() {
    let dir = tempfile::tempdir().unwrap();
    let results = dir.path().join("results.md");
    let before = "# Results\n\n<!-- eval:begin -->\nkept\n<!-- eval:end -->\n";
    std::fs::write(&results, before).unwrap();
    let out = dir.path().join("views");
    let o = small_run(
        &out,
        &[
            "--experiments",
            "views",
            "--publish",
            results.to_str().unwrap(),
        ],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(&results).unwrap();
    assert!(text.starts_with(before), "{text}");
    let views = &text[before.len()..];
    assert!(
        views.starts_with("\n<!-- eval-views:begin -->\n## Map accuracy of the views"),
        "{views}"
    );
    for needle in [
        "2pp-face",
        "3pp-hidden",
        "3pp-yaw",
        "### Error-bar coverage",
        "### Per set-up at σ = 1 px",
        "invalid_field",
    ] {
        assert!(views.contains(needle), "the views section lacks {needle}");
    }
    // The side view and the projective form refuse every face-on and hidden-base scene; the
    // fit builds them, exact at zero noise.
    let failures = std::fs::read_to_string(out.join("failures.csv")).unwrap();
    for line in failures.lines().skip(1) {
        let cells: Vec<&str> = line.split(',').collect();
        assert!(cells[5] != "fit" || cells[4] != "0", "{line}");
        if cells[5] != "fit" {
            assert!(
                cells[0].contains("face") || cells[0].contains("hidden"),
                "{line}"
            );
            assert_eq!(cells[6], "invalid_field", "{line}");
        }
    }
    // 4 set-ups x 1 trial x 2 noise levels x 2 methods refused.
    assert!(failures.lines().count() > 4 * 2 * 2, "{failures}");
}

#[test]
fn the_navigate_run_drives_the_grown_fit_and_publishes_its_own_section() {
    let dir = tempfile::tempdir().unwrap();
    let results = dir.path().join("results.md");
    let before = "# Results\n\n<!-- eval:begin -->\nkept\n<!-- eval:end -->\n";
    std::fs::write(&results, before).unwrap();
    let out = dir.path().join("nav");
    let run = |extra: &[&str]| {
        let mut args = vec![
            "eval",
            "--navigate",
            "--trials",
            "1",
            "--sigma",
            "2",
            "--methods",
            "fit",
            "--out",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        vpmap(&args)
    };
    let o = run(&["--publish", results.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(files_in(&out), ["navigate.md"]);
    let text = std::fs::read_to_string(&results).unwrap();
    assert!(text.starts_with(before), "{text}");
    let section = &text[before.len()..];
    assert!(
        section.starts_with("\n<!-- eval-navigate:begin -->\n## What a map's error costs a robot"),
        "{section}"
    );
    assert!(
        section.ends_with("<!-- eval-navigate:end -->\n"),
        "{section}"
    );
    // The fitted map as built and grown by its error bars, each with both planners.
    for row in [
        "| 2 | fit | dstar-lite |",
        "| 2 | fit | mbpp |",
        "| 2 | fit, grown (95 %) | dstar-lite |",
        "| 2 | fit, grown (95 %) | mbpp |",
    ] {
        assert!(section.contains(row), "{row} missing: {section}");
    }
    assert!(section.contains("eval --navigate"), "{section}");
    // --grow-confidence 0 drives the maps as built only.
    let o = run(&["--grow-confidence", "0"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(!String::from_utf8_lossy(&o.stdout).contains("grown"));
}

#[test]
fn the_navigate_run_refuses_bad_arguments_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = out.to_str().unwrap();
    for (args, needle) in [
        (
            vec!["--grow-confidence", "1"],
            "--grow-confidence 1 must be from 0.5 to 0.9999",
        ),
        (vec!["--grow-confidence", "NaN"], "--grow-confidence NaN"),
        (vec!["--methods", "fit,fit"], "names fit twice"),
        (vec!["--trials", "0"], "--trials"),
        (vec!["--sigma", "-1"], "--sigma"),
    ] {
        let mut full = vec!["eval", "--navigate", "--out", o];
        if args[0] != "--trials" {
            full.extend(["--trials", "1"]);
        }
        full.extend(args);
        assert_refused(&full, &out, needle);
    }
    // Without --navigate the growth has no meaning.
    assert_refused(
        &[
            "eval",
            "--out",
            o,
            "--trials",
            "1",
            "--grow-confidence",
            "0.9",
        ],
        &out,
        "--grow-confidence 0.9 is for --navigate",
    );
}

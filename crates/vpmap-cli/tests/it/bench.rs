//! `vpmap bench` end to end, on tiny maps: the results table, its checks against
//! independent references (breadth-first connectivity, octile Dijkstra), the summary, the
//! plots, publishing, the fallback without benchmark data, and bad input.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::Path;
use std::process::Command;

use super::{files_in, vpmap};

/// Two components: the bottom-right corner is walled off.
const TWO_ROOMS: &str = "type octile\nheight 8\nwidth 10\nmap\n\
..........\n\
..@@@.....\n\
....@.....\n\
....@..@@@\n\
....@..@..\n\
.......@..\n\
..@@@..@..\n\
.......@..\n";

/// One component, two obstacles.
const OPEN: &str = "type octile\nheight 6\nwidth 8\nmap\n\
........\n\
.@@.....\n\
.@......\n\
........\n\
..@@@@..\n\
........\n";

/// The free cells of a `.map` text, row-major.
fn free_cells(map: &str) -> (usize, usize, Vec<bool>) {
    let rows: Vec<&str> = map
        .lines()
        .skip_while(|l| *l != "map")
        .skip(1)
        .filter(|l| !l.is_empty())
        .collect();
    let (w, h) = (rows[0].len(), rows.len());
    let free = rows
        .iter()
        .flat_map(|r| r.chars().map(|c| c == '.'))
        .collect();
    (w, h, free)
}

/// Octile shortest path lengths from `start` (8-connected, no corner cutting), by a plain
/// O(n^2) Dijkstra: the reference for the scenario optima and for connectivity.
fn octile_distances(map: &str, start: (usize, usize)) -> Vec<f64> {
    let (w, h, free) = free_cells(map);
    let ok = |x: i64, y: i64| {
        x >= 0 && y >= 0 && x < w as i64 && y < h as i64 && free[y as usize * w + x as usize]
    };
    let mut dist = vec![f64::INFINITY; w * h];
    let mut done = vec![false; w * h];
    dist[start.1 * w + start.0] = 0.0;
    while let Some(i) = (0..w * h)
        .filter(|&i| !done[i] && dist[i].is_finite())
        .min_by(|&a, &b| dist[a].total_cmp(&dist[b]))
    {
        done[i] = true;
        let (x, y) = ((i % w) as i64, (i / w) as i64);
        for dy in -1..=1i64 {
            for dx in -1..=1i64 {
                if (dx, dy) == (0, 0) || !ok(x + dx, y + dy) {
                    continue;
                }
                if dx != 0 && dy != 0 && !(ok(x + dx, y) && ok(x, y + dy)) {
                    continue;
                }
                let j = (y + dy) as usize * w + (x + dx) as usize;
                let step = if dx != 0 && dy != 0 { 2f64.sqrt() } else { 1.0 };
                if dist[i] + step < dist[j] {
                    dist[j] = dist[i] + step;
                }
            }
        }
    }
    dist
}

/// A scenario file for `OPEN` with optima from the reference Dijkstra.
fn open_scen() -> String {
    let (w, _, _) = free_cells(OPEN);
    let mut text = "version 1\n".to_owned();
    for (bucket, start, goal) in [
        (0, (0, 0), (7, 5)),
        (0, (0, 5), (7, 0)),
        (1, (0, 3), (7, 3)),
        (1, (3, 5), (3, 0)),
    ] {
        let d = octile_distances(OPEN, start)[goal.1 * w + goal.0];
        writeln!(
            text,
            "{bucket}\topen.map\t8\t6\t{}\t{}\t{}\t{}\t{d:.8}",
            start.0, start.1, goal.0, goal.1
        )
        .unwrap();
    }
    text
}

type Row = HashMap<String, String>;

fn read_csv(path: &Path) -> Vec<Row> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<String> = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_owned)
        .collect();
    lines
        .map(|l| {
            let fields: Vec<&str> = l.split(',').collect();
            assert_eq!(fields.len(), header.len(), "ragged row: {l}");
            header
                .iter()
                .cloned()
                .zip(fields.iter().map(|f| (*f).to_owned()))
                .collect()
        })
        .collect()
}

fn number(row: &Row, key: &str) -> Option<f64> {
    let v = &row[key];
    (!v.is_empty()).then(|| {
        v.parse()
            .unwrap_or_else(|_| panic!("{key} = {v:?} is not a number"))
    })
}

fn cell(row: &Row, x: &str, y: &str) -> (usize, usize) {
    (row[x].parse().unwrap(), row[y].parse().unwrap())
}

#[test]
fn bench_runs_checks_and_plots_tiny_maps() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("two_rooms.map"), TWO_ROOMS).unwrap();
    std::fs::write(d.join("open.map"), OPEN).unwrap();
    std::fs::write(d.join("open.scen"), open_scen()).unwrap();
    let out = d.join("out");
    let docs = d.join("docs");
    std::fs::create_dir(&docs).unwrap();
    let results_md = docs.join("results.md");
    std::fs::write(&results_md, "# Results\n\nKept.\n").unwrap();
    let o = vpmap(&[
        "bench",
        d.join("two_rooms.map").to_str().unwrap(),
        d.join("open.scen").to_str().unwrap(),
        "--per-map",
        "3",
        "--repeat",
        "1",
        "--out",
        out.to_str().unwrap(),
        "--publish",
        results_md.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{stderr}");

    let rows = read_csv(&out.join("results.csv"));
    let header = std::fs::read_to_string(out.join("results.csv")).unwrap();
    let header = header.lines().next().unwrap();
    for key in [
        "map",
        "category",
        "planner",
        "found",
        "valid",
        "length",
        "optimal_length",
        "time_s",
        "peak_bytes",
        "scen_octile_optimum",
    ] {
        assert!(header.split(',').any(|h| h == key), "no {key} in {header}");
    }
    // two_rooms: 3 solvable + 2 unsolvable queries; open: 3 scenario problems (one
    // component); five planners each.
    assert_eq!(rows.len(), (5 + 3) * 5, "{rows:#?}");
    let planners = ["mbpp", "astar-ps", "theta-star", "astar", "optimal"];
    let mut by_query: HashMap<(String, String), Vec<&Row>> = HashMap::new();
    for r in &rows {
        by_query
            .entry((r["map"].clone(), r["query"].clone()))
            .or_default()
            .push(r);
    }
    assert_eq!(by_query.len(), 8);
    let mut unsolvable = 0;
    for ((map, query), rs) in &by_query {
        let mut names: Vec<&str> = rs.iter().map(|r| r["planner"].as_str()).collect();
        names.sort_unstable();
        let mut expected = planners.to_vec();
        expected.sort_unstable();
        assert_eq!(names, expected, "{map} {query}");
        // Connectivity by the reference Dijkstra on the map text.
        let text = if map == "two_rooms" { TWO_ROOMS } else { OPEN };
        let (w, _, _) = free_cells(text);
        let (start, goal) = (
            cell(rs[0], "start_x", "start_y"),
            cell(rs[0], "goal_x", "goal_y"),
        );
        let reference = octile_distances(text, start)[goal.1 * w + goal.0];
        let connected = reference.is_finite();
        if !connected {
            unsolvable += 1;
            assert_eq!(rs[0]["origin"], "unsolvable");
        }
        let optimal = rs
            .iter()
            .find(|r| r["planner"] == "optimal")
            .and_then(|r| number(r, "length"));
        for r in rs {
            let who = format!("{map} query {query} {}", r["planner"]);
            assert_eq!(r["found"], connected.to_string(), "{who}");
            if connected {
                assert_eq!(r["valid"], "true", "{who}");
                let length = number(r, "length").unwrap();
                let optimal = optimal.unwrap();
                assert!(
                    length >= optimal - 1e-9 * optimal.max(1.0),
                    "{who}: {length} < {optimal}"
                );
                assert_eq!(number(r, "optimal_length"), Some(optimal), "{who}");
                if r["planner"] == "astar" {
                    assert!(
                        (length - reference).abs() < 1e-9,
                        "{who}: {length} vs {reference}"
                    );
                }
                if let Some(octile) = number(r, "scen_octile_optimum") {
                    assert!((octile - reference).abs() < 1e-6, "{who}");
                }
            } else {
                assert_eq!(r["valid"], "n/a", "{who}");
                assert!(r["length"].is_empty(), "{who}");
            }
            assert!(number(r, "time_s").unwrap() >= 0.0);
            let mbpp = r["planner"] == "mbpp";
            assert_eq!(r["bugs"].is_empty(), !mbpp, "{who}");
        }
    }
    assert_eq!(unsolvable, 2);

    let summary = std::fs::read_to_string(out.join("summary.md")).unwrap();
    assert!(summary.contains("### Per category"), "{summary}");
    assert!(summary.contains("Failures: none"), "{summary}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(json["failures"].as_array().map(Vec::len), Some(0));
    let all = &json["all"];
    assert_eq!(all["solvable_queries"], 6);
    assert_eq!(all["unsolvable_queries"], 2);
    let mbpp = &all["planners"]["mbpp"]["vs_astar_ps"];
    let compared = ["shorter", "equal", "longer"]
        .iter()
        .map(|k| mbpp[k].as_u64().unwrap())
        .sum::<u64>();
    assert_eq!(compared, 6);
    assert!(
        all["planners"]["optimal"]["mean_excess_over_optimal"]
            .as_f64()
            .unwrap()
            .abs()
            < 1e-12
    );

    let no_fonts = stderr.contains("no system fonts");
    for plot in ["runtime", "length", "excess"] {
        let svg = std::fs::read_to_string(out.join(format!("{plot}.svg"))).unwrap();
        let doc = roxmltree::Document::parse(&svg).unwrap_or_else(|e| panic!("{plot}.svg: {e}"));
        assert_eq!(doc.root_element().tag_name().name(), "svg");
        assert!(svg.contains("two_rooms"), "{plot}.svg lacks the map name");
        if !no_fonts {
            let png = std::fs::read(out.join(format!("{plot}.png"))).unwrap();
            assert!(png.starts_with(b"\x89PNG"), "{plot}.png");
        }
    }

    // Published: the section replaced, the rest kept, images linked relative to docs/.
    let published = std::fs::read_to_string(&results_md).unwrap();
    assert!(published.starts_with("# Results\n\nKept.\n"), "{published}");
    assert!(published.contains("<!-- bench:begin -->") && published.contains("<!-- bench:end -->"));
    let ext = if no_fonts { "svg" } else { "png" };
    let link = format!("](../out/runtime.{ext})");
    assert!(published.contains(&link), "no {link} in {published}");
    assert!(docs.join(format!("../out/runtime.{ext}")).exists());
}

#[test]
fn bench_without_data_benchmarks_generated_and_built_maps() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = Command::new(env!("CARGO_BIN_EXE_vpmap"))
        .args([
            "bench",
            "--planners",
            "mbpp,astar-ps",
            "--per-map",
            "2",
            "--repeat",
            "1",
            "--out",
            out.to_str().unwrap(),
        ])
        .env("VPMAP_MOVINGAI", dir.path().join("nowhere"))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{stderr}");
    assert!(
        stderr.contains("not found; benchmarking generated maps only"),
        "{stderr}"
    );
    let rows = read_csv(&out.join("results.csv"));
    let maps: std::collections::BTreeSet<&str> = rows.iter().map(|r| r["map"].as_str()).collect();
    assert!(maps.contains("generated-random-128"), "{maps:?}");
    assert!(maps.contains("generated-rooms-128"), "{maps:?}");
    assert!(maps.contains("built-office-1"), "{maps:?}");
    assert!(rows.iter().any(|r| r["category"] == "built"));
    // The rooms grid has a closed room: unsolvable queries, answered "no path" by both.
    let blocked: Vec<&Row> = rows
        .iter()
        .filter(|r| r["map"] == "generated-rooms-128" && r["origin"] == "unsolvable")
        .collect();
    assert_eq!(blocked.len(), 2 * 2);
    assert!(blocked.iter().all(|r| r["found"] == "false"));
    assert!(
        rows.iter()
            .filter(|r| r["reachable"] == "true")
            .all(|r| r["found"] == "true" && r["valid"] == "true")
    );
}

fn assert_bench_fails(args: &[&str], out: &Path, needle: &str) {
    let o = vpmap(args);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{args:?}: {stderr}");
    assert!(stderr.starts_with("error: "), "{stderr}");
    assert!(stderr.contains(needle), "expected {needle:?} in: {stderr}");
    assert_eq!(
        stderr.trim_end().lines().count(),
        1,
        "one line expected: {stderr}"
    );
    assert!(
        !out.exists() || files_in(out).is_empty(),
        "{:?}",
        files_in(out)
    );
}

#[test]
fn bench_rejects_bad_input_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let out = d.join("out");
    let o = out.to_str().unwrap();
    let good = d.join("open.map");
    std::fs::write(&good, OPEN).unwrap();
    let g = good.to_str().unwrap();
    let bad = d.join("bad.map");
    std::fs::write(&bad, "type octile\nheight 2\nwidth 3\nmap\n...\n.x.\n").unwrap();
    let orphan = d.join("orphan.scen");
    std::fs::write(
        &orphan,
        "version 1\n0\tgone.map\t8\t6\t0\t0\t1\t1\t1.41421356\n",
    )
    .unwrap();
    let on_wall = d.join("wall.scen");
    std::fs::write(&on_wall, "version 1\n0\topen.map\t8\t6\t1\t1\t0\t0\t1\n").unwrap();
    let missing = d.join("missing.map");
    for (args, needle) in [
        (
            vec!["bench", missing.to_str().unwrap(), "--out", o],
            "missing.map",
        ),
        (vec!["bench", bad.to_str().unwrap(), "--out", o], "line 6"),
        (
            vec!["bench", g, "--planners", "mbpp,dijkstra", "--out", o],
            "unknown planner `dijkstra`",
        ),
        (vec!["bench", g, "--per-map", "0", "--out", o], "--per-map"),
        (vec!["bench", g, "--repeat", "0", "--out", o], "--repeat"),
        (
            vec!["bench", g, "--optimal-limit", "-1", "--out", o],
            "--optimal-limit",
        ),
        (
            vec!["bench", orphan.to_str().unwrap(), "--out", o],
            "cannot find its map gone.map",
        ),
        (
            vec!["bench", on_wall.to_str().unwrap(), "--out", o],
            "is not a free cell",
        ),
        (vec!["bench", "notes.txt", "--out", o], "unknown input type"),
        (
            vec!["bench", "--smooth", "--queries", "0", "--out", o],
            "--queries must be at least 1",
        ),
        (
            vec!["bench", "--smooth", g, "--out", o],
            "--smooth runs on its own maps",
        ),
    ] {
        assert_bench_fails(&args, &out, needle);
    }
    // Usage errors are clap's: exit 2.
    let o2 = vpmap(&["bench", g, "--per-map", "many", "--out", o]);
    assert_eq!(o2.status.code(), Some(2));
    assert!(!out.exists());
}

//! Snapshots of the text reports people read, on small deterministic runs with the timings,
//! the date and the machine fixed. `cargo insta review` (or `INSTA_UPDATE=always`) accepts a
//! deliberate change; an unintended one fails here.

use std::collections::BTreeMap;
use std::time::Duration;

use vpmap_eval::Silent;
use vpmap_eval::accuracy::{self, Config};
use vpmap_eval::bench::{self, MapResult, NoMemoryProbe, Results};
use vpmap_eval::detection::report::Context;
use vpmap_eval::detection::{ImageResult, Run, RunOk};
use vpmap_metrology::eval::SETUPS;
use vpmap_plan::planner::PlannerKind;

#[test]
fn map_accuracy_summary() {
    let config = Config {
        trials: 3,
        // No zero noise: its errors are rounding noise (1e-13), not worth pinning.
        sigmas: vec![0.5, 1.0],
        plot_sigma: 1.0,
        setups: SETUPS
            .iter()
            .filter(|s| s.name == "2pp-1" || s.name == "3pp-1")
            .collect(),
        ..Config::default()
    };
    assert_eq!(config.setups.len(), 2);
    let results = accuracy::run_trials(&config, &Silent);
    let collected = accuracy::collect::collect(&config, &results);
    // SVG links, whether or not this machine has fonts for the PNGs.
    let image_of: BTreeMap<&'static str, String> = accuracy::collect::DESCRIBED
        .iter()
        .map(|d| (d.name, format!("box_{}.svg", d.name)))
        .collect();
    let md = accuracy::report::markdown(&config, &collected, &image_of, "");
    insta::assert_snapshot!("eval_summary_md", md);
    insta::assert_snapshot!(
        "eval_headline",
        accuracy::report::headline(&config, &collected)
    );
}

/// Every time 1 ms, every peak 0 bytes, every wall time 1 s.
fn fixed_timings(results: &mut Results) {
    results.wall_s = 1.0;
    for m in &mut results.maps {
        m.wall_s = 1.0;
        m.optimal_build_s = m.optimal_build_s.map(|_| 1e-3);
        for record in m.records.iter_mut().flatten().flatten() {
            record.time_s = 1e-3;
            record.peak_bytes = 0;
        }
    }
}

#[test]
fn bench_summary() {
    let planners = vec![
        PlannerKind::Mbpp,
        PlannerKind::AstarPs,
        PlannerKind::ThetaStar,
        PlannerKind::Astar,
        PlannerKind::Optimal,
    ];
    // The empty room and the rooms with doors (the random map is too slow for `optimal` in a
    // debug build).
    let maps: Vec<_> = bench::maps::generated_maps(2, 1)
        .unwrap()
        .into_iter()
        .filter(|m| !m.name.contains("random"))
        .collect();
    assert_eq!(maps.len(), 2);
    let measured: Vec<MapResult> = bench::measure_maps(
        maps,
        &planners,
        1,
        Duration::from_secs(600),
        &NoMemoryProbe,
        &Silent,
    )
    .unwrap();
    let mut results = Results {
        planners,
        maps: measured,
        command: "vpmap bench (test)".to_owned(),
        date: "2000-01-01 00:00 UTC".to_owned(),
        machine: "a test machine".to_owned(),
        repeat: 1,
        per_map: 2,
        seed: 1,
        wall_s: 0.0,
        optimal_limit_s: 600.0,
        notes: vec!["generated maps only (test)".to_owned()],
    };
    fixed_timings(&mut results);
    let summary = bench::summary::Summary::compute(&results);
    insta::assert_snapshot!(
        "bench_summary_md",
        bench::report::markdown(&results, &summary, "", "svg")
    );
    insta::assert_snapshot!("bench_console", bench::report::console(&results, &summary));
}

fn run(
    errors_deg: [Option<f64>; 3],
    focal_error: Option<f64>,
    horizon_error: Option<[f64; 2]>,
    time_ms: f64,
) -> Run {
    Run {
        time_ms: Some(time_ms),
        outcome: Ok(RunOk {
            errors_deg,
            // Own points a little closer to the labels, one of them missing.
            own_errors_deg: [errors_deg[0].map(|e| 0.6 * e), errors_deg[1], None],
            // Against the orthogonalised labels: the frame closer, the own points farther.
            against_orthogonal_deg: Some([
                errors_deg.map(|e| e.map(|e| 0.5 * e)),
                errors_deg.map(|e| e.map(|e| e + 0.3)),
            ]),
            // Distances squared that some ellipses hold (5.991 at 95 %) and some do not.
            ellipse_d2: errors_deg.map(|e| e.map(|e| 4.0 * e * e)),
            focal_z: focal_error.map(|e| 40.0 * e),
            // Standardised camera errors, some beyond 1.96 and some not; the principal point
            // only where the focal length was estimated.
            camera_z: Some(vpmap_eval::detection::coverage::CameraZ {
                pitch: [3.0 * time_ms.sin(), 0.5],
                roll: [0.3, -2.5 * time_ms.cos()],
                horizon: [2.5 * time_ms.sin(), 0.4],
                principal_point: focal_error.map(|e| [30.0 * e, -1.0]),
            }),
            focal_px: 700.0,
            focal_error,
            principal_point_px: [320.0, 240.0],
            perspective: "3pp",
            segments: 120,
            horizon_error,
            // One camera's k, each photo's estimate a little off it.
            lens: Some([-0.02 + 0.004 * time_ms.sin(), 0.005]),
            lens_segments_sd: Some(0.003),
        }),
    }
}

#[test]
fn detection_summary() {
    let results = vec![
        ImageResult {
            name: "P0000001".to_owned(),
            size_px: Some([640, 480]),
            vertical: 1,
            orthogonal_label_errors_deg: Some([0.4, 0.9, 2.0]),
            runs: [
                run(
                    [Some(0.4), Some(0.2), Some(1.5)],
                    None,
                    Some([0.01, 0.02]),
                    20.0,
                ),
                run(
                    [Some(0.9), Some(2.5), Some(4.0)],
                    Some(0.02),
                    Some([0.08, 0.03]),
                    30.0,
                ),
            ],
        },
        ImageResult {
            name: "P0000002".to_owned(),
            size_px: Some([640, 480]),
            vertical: 0,
            orthogonal_label_errors_deg: Some([0.2, 3.5, 0.7]),
            runs: [
                run([Some(0.1), Some(6.0), None], None, None, 25.0),
                Run {
                    time_ms: Some(12.0),
                    outcome: Err("found 3 segments, at least 8 needed".to_owned()),
                },
            ],
        },
        ImageResult {
            name: "P0000003".to_owned(),
            size_px: None,
            vertical: 2,
            orthogonal_label_errors_deg: None,
            runs: [0, 1].map(|_| Run {
                time_ms: None,
                outcome: Err("P0000003.jpg: not a JPEG or PNG".to_owned()),
            }),
        },
    ];
    let context = Context {
        dir: "yud-test".to_owned(),
        available: 4,
        max_side: 640,
        exif: false,
    };
    let report = vpmap_eval::detection::report(context, &results).unwrap();
    insta::assert_snapshot!("detect_table", report.table());
    insta::assert_snapshot!(
        "detect_summary_md",
        vpmap_eval::detection::report::markdown(&report.context, &results, &report.summaries)
    );
}

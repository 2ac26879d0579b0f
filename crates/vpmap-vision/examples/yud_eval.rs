//! Accuracy and speed of `vpmap_vision::detect` on the York Urban Database training half.
//!
//! ```text
//! cargo run --release -p vpmap-vision --example yud_eval [-- DIR [--verbose]]
//! ```
//!
//! DIR defaults to `../shared/data/yud-train` beside the workspace. Runs on one core (rayon
//! pool of one thread). For every photo: `detect` with the true intrinsics and without them;
//! errors of the three directions against the labelled ones (`vp_dirs_camera_yup`), matched
//! vertical to vertical and horizontals by the best assignment; without intrinsics the
//! directions come from the estimated camera.
#![allow(clippy::unwrap_used, clippy::expect_used, missing_docs)]

use std::path::PathBuf;
use std::time::Instant;

use vpmap_vision::metrics::{auc, fraction_below, manhattan_errors_deg, median};
use vpmap_vision::{DetectOptions, Detection, detect};

struct Truth {
    dirs: [[f64; 3]; 3],
    dirs_orth: [[f64; 3]; 3],
    vertical: usize,
    focal: f64,
    pp: [f64; 2],
}

fn dirs(v: &serde_json::Value) -> [[f64; 3]; 3] {
    let mut out = [[0.0; 3]; 3];
    for (k, d) in out.iter_mut().enumerate() {
        let row = &v[k];
        // y up -> y down.
        *d = [
            row[0].as_f64().unwrap(),
            -row[1].as_f64().unwrap(),
            row[2].as_f64().unwrap(),
        ];
    }
    out
}

fn load_truth(path: &std::path::Path) -> Truth {
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    Truth {
        dirs: dirs(&v["vp_dirs_camera_yup"]),
        dirs_orth: dirs(&v["vp_orthogonal_dirs_camera_yup"]),
        vertical: v["most_vertical_vp_index"].as_u64().unwrap() as usize,
        focal: v["K"][0][0].as_f64().unwrap(),
        pp: [
            v["K"][0][2].as_f64().unwrap(),
            v["K"][1][2].as_f64().unwrap(),
        ],
    }
}

fn errors(d: &Detection, t: &[[f64; 3]; 3], vertical: usize) -> [f64; 3] {
    let found: Vec<[f64; 3]> = d
        .vanishing_points
        .iter()
        .map(|v| v.direction_camera)
        .collect();
    let found = [found[0], found[1], found[2]];
    manhattan_errors_deg(&found, 2, t, vertical)
}

fn summary(label: &str, e: &[f64]) {
    println!(
        "{label:<34} <1: {:5.1} %  <3: {:5.1} %  <5: {:5.1} %  <10: {:5.1} %   AUC@3 {:5.1} %  AUC@5 {:5.1} %  AUC@10 {:5.1} %  median {:.2} deg",
        100.0 * fraction_below(e, 1.0),
        100.0 * fraction_below(e, 3.0),
        100.0 * fraction_below(e, 5.0),
        100.0 * fraction_below(e, 10.0),
        100.0 * auc(e, 3.0),
        100.0 * auc(e, 5.0),
        100.0 * auc(e, 10.0),
        median(e),
    );
}

fn main() {
    rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build_global()
        .unwrap();
    let args: Vec<String> = std::env::args().skip(1).collect();
    let verbose = args.iter().any(|a| a == "--verbose");
    let dir = args.iter().find(|a| !a.starts_with("--")).map_or_else(
        || PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/yud-train"),
        PathBuf::from,
    );
    let mut names: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "jpg"))
        .collect();
    names.sort();
    let (mut cal, mut cal_orth, mut unc, mut unc_orth, mut focal_err, mut pp_err) =
        (vec![], vec![], vec![], vec![], vec![], vec![]);
    let (mut t_cal, mut t_unc) = (0.0, 0.0);
    let mut failures = 0;
    for path in &names {
        let truth = load_truth(&path.with_extension("json"));
        let image = image::open(path).unwrap();
        let known = DetectOptions {
            focal_px: Some(truth.focal),
            principal_point_px: Some(truth.pp),
            ..DetectOptions::default()
        };
        let t0 = Instant::now();
        let a = detect(&image, &known);
        t_cal += t0.elapsed().as_secs_f64();
        let t0 = Instant::now();
        let b = detect(&image, &DetectOptions::default());
        t_unc += t0.elapsed().as_secs_f64();
        let name = path.file_stem().unwrap().to_string_lossy();
        if let (Ok(a), Ok(b)) = (&a, &b) {
            {
                let ea = errors(a, &truth.dirs, truth.vertical);
                let eb = errors(b, &truth.dirs, truth.vertical);
                cal.extend(ea);
                cal_orth.extend(errors(a, &truth.dirs_orth, truth.vertical));
                unc.extend(eb);
                unc_orth.extend(errors(b, &truth.dirs_orth, truth.vertical));
                let fe = (b.intrinsics.focal_px / truth.focal - 1.0) * 100.0;
                focal_err.push(fe.abs());
                let ppe = (b.intrinsics.principal_point_px[0] - truth.pp[0])
                    .hypot(b.intrinsics.principal_point_px[1] - truth.pp[1]);
                pp_err.push(ppe);
                if verbose {
                    println!(
                        "{name}: K given [{:5.2} {:5.2} {:5.2}]  K estimated [{:6.2} {:6.2} {:6.2}] f {:7.1} ({fe:+5.1} %) pp ({:.0}, {:.0}){} tilt {:4.1} {:?} segs {}",
                        ea[0],
                        ea[1],
                        ea[2],
                        eb[0],
                        eb[1],
                        eb[2],
                        b.intrinsics.focal_px,
                        b.intrinsics.principal_point_px[0],
                        b.intrinsics.principal_point_px[1],
                        if b.principal_point_estimated { "*" } else { "" },
                        b.vertical_tilt_deg,
                        b.perspective,
                        b.segments.len()
                    );
                }
            }
        } else {
            {
                failures += 1;
                println!(
                    "{name}: failed: {:?} / {:?}",
                    a.as_ref().err(),
                    b.as_ref().err()
                );
                cal.extend([90.0; 3]);
                unc.extend([90.0; 3]);
            }
        }
    }
    let n = names.len() as f64;
    println!(
        "{} photos from {} ({failures} failures)",
        names.len(),
        dir.display()
    );
    summary("true intrinsics given", &cal);
    summary("  (vs orthogonalised truth)", &cal_orth);
    summary("intrinsics estimated", &unc);
    summary("  (vs orthogonalised truth)", &unc_orth);
    let mut sorted = focal_err.clone();
    sorted.sort_by(f64::total_cmp);
    println!(
        "focal error (estimated): median {:.2} %, mean {:.2} %, 90th percentile {:.2} %, max {:.2} %; principal point error median {:.1} px",
        median(&focal_err),
        focal_err.iter().sum::<f64>() / focal_err.len().max(1) as f64,
        sorted
            .get((sorted.len() * 9) / 10)
            .copied()
            .unwrap_or(f64::NAN),
        sorted.last().copied().unwrap_or(f64::NAN),
        median(&pp_err),
    );
    println!(
        "time per photo (one core, decoding excluded): {:.1} ms with intrinsics, {:.1} ms without",
        t_cal / n * 1e3,
        t_unc / n * 1e3
    );
}

//! The data files of a map-accuracy run: `summary.json`, `objects.csv` and `failures.csv`.

use std::fmt::Write as _;

use serde::Serialize;
use vpmap_metrology::calibration::Perspective;

use super::collect::{Collected, Group, metric_names, object_row};
use super::config::{Config, Results};
use crate::error::{Result, ResultExt as _};

/// One row of `summary.json`.
#[derive(Serialize)]
struct Row<'a> {
    method: String,
    sigma: f64,
    metric: &'a str,
    median: Option<f64>,
    p5: Option<f64>,
    p95: Option<f64>,
    min: Option<f64>,
    max: Option<f64>,
    q1: Option<f64>,
    q3: Option<f64>,
    mean: Option<f64>,
    count: usize,
    perspective: Perspective,
    experiment: Option<&'static str>,
    scenes: usize,
    refused: usize,
}

/// `summary.json`: per method, noise level, perspective (then per set-up) and metric.
///
/// # Errors
/// When serialising fails.
pub fn summary_json(config: &Config, c: &Collected) -> Result<String> {
    let mut rows = Vec::new();
    let mut groups: Vec<(Group, Perspective, Option<&'static str>)> = Vec::new();
    for p in [Perspective::TwoPoint, Perspective::ThreePoint] {
        if config.setups.iter().any(|s| s.perspective == p) {
            groups.push((Group::Perspective(p), p, None));
        }
    }
    for (e, s) in config.setups.iter().enumerate() {
        groups.push((Group::Experiment(e), s.perspective, Some(s.name)));
    }
    for &(group, perspective, experiment) in &groups {
        for (m, method) in config.methods.iter().enumerate() {
            for (s, &sigma) in config.sigmas.iter().enumerate() {
                let refusals = c.refusals(config, m, s, group);
                for (k, metric) in c.metrics.iter().enumerate() {
                    let sum = c.summary(config, m, s, group, k);
                    rows.push(Row {
                        method: method.to_string(),
                        sigma,
                        metric,
                        median: sum.map(|x| x.median),
                        p5: sum.map(|x| x.p5),
                        p95: sum.map(|x| x.p95),
                        min: sum.map(|x| x.min),
                        max: sum.map(|x| x.max),
                        q1: sum.map(|x| x.q1),
                        q3: sum.map(|x| x.q3),
                        mean: sum.map(|x| x.mean),
                        count: sum.map_or(0, |x| x.count),
                        perspective,
                        experiment,
                        scenes: refusals.scenes,
                        refused: refusals.refused(),
                    });
                }
            }
        }
    }
    serde_json::to_string_pretty(&rows).context("serialising summary.json")
}

/// A number for a CSV file: 7 significant digits, empty when unknown.
fn csv_number(v: f64) -> String {
    if !v.is_finite() {
        return String::new();
    }
    let rounded: f64 = format!("{v:.6e}").parse().unwrap_or(v);
    format!("{rounded}")
}

/// A CSV field, quoted when it needs to be.
fn csv_text(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_owned()
    }
}

/// `objects.csv`: one row per object of every evaluated scene, noise level and method.
#[must_use]
pub fn objects_csv(config: &Config, results: &Results) -> String {
    let mut out = String::from(
        "experiment,perspective,trial,scene_seed,sigma_px,method,object,kind,reference",
    );
    for m in metric_names() {
        out.push(',');
        out.push_str(&m);
    }
    out.push('\n');
    for (setup, trials) in config.setups.iter().zip(&results.trials) {
        for trial in trials {
            for o in &trial.outcomes {
                let Ok(ev) = &o.result else { continue };
                for (i, object) in ev.objects.iter().enumerate() {
                    let _ = write!(
                        out,
                        "{},{},{},{},{},{},{},{},{}",
                        setup.name,
                        setup.perspective.name(),
                        trial.trial,
                        trial.scene_seed,
                        o.sigma_px,
                        o.method,
                        csv_text(&object.name),
                        match object.kind {
                            vpmap_metrology::reconstruct::ObjectKind::Box => "box",
                            vpmap_metrology::reconstruct::ObjectKind::Footprint => "footprint",
                        },
                        object.reference
                    );
                    for v in object_row(ev, i) {
                        out.push(',');
                        out.push_str(&csv_number(v));
                    }
                    out.push('\n');
                }
            }
        }
    }
    out
}

/// `failures.csv`: one row per scene a builder refused (or the set-up could not draw).
#[must_use]
pub fn failures_csv(config: &Config, results: &Results) -> String {
    let mut out =
        String::from("experiment,perspective,trial,scene_seed,sigma_px,method,category,message\n");
    for (setup, trials) in config.setups.iter().zip(&results.trials) {
        for trial in trials {
            for o in &trial.outcomes {
                let Err(f) = &o.result else { continue };
                let _ = writeln!(
                    out,
                    "{},{},{},{},{},{},{},{}",
                    setup.name,
                    setup.perspective.name(),
                    trial.trial,
                    trial.scene_seed,
                    o.sigma_px,
                    o.method,
                    f.category,
                    csv_text(&f.message)
                );
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_numbers_and_texts_are_written_by_hand_rules() {
        assert_eq!(csv_number(1.0 / 3.0), "0.3333333");
        assert_eq!(csv_number(f64::NAN), "");
        assert_eq!(csv_text("a,b"), "\"a,b\"");
    }
}

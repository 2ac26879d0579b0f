//! What `vpmap bench` writes from its [`Summary`]: `results.csv`, `summary.md`,
//! `summary.json` and a few console lines. The definitions of the figures are in
//! [`super::summary`].

use std::fmt::Write as _;

use serde_json::{Value, json};
use vpmap_plan::planner::PlannerKind;

use super::maps::{Origin, UNSOLVABLE_PER_MAP};
use super::plots::has_excess_plot;
use super::results::{MapResult, Results};
use super::summary::{Group, Summary, Versus, astar_ps_length, label, optimal_length};

/// Failures listed in full in the Markdown summary (all are in the JSON).
const FAILURES_SHOWN: usize = 40;

/// A CSV field, quoted when it must be.
fn csv_field(text: &str) -> String {
    if text.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_owned()
    }
}

fn opt<T: ToString>(v: Option<T>) -> String {
    v.map_or_else(String::new, |v| v.to_string())
}

/// The columns of `results.csv`.
pub const CSV_HEADER: [&str; 27] = [
    "map",
    "category",
    "query",
    "origin",
    "bucket",
    "start_x",
    "start_y",
    "goal_x",
    "goal_y",
    "reachable",
    "planner",
    "found",
    "valid",
    "length",
    "optimal_length",
    "length_over_optimal",
    "length_over_astar_ps",
    "scen_octile_optimum",
    "waypoints",
    "turning_deg",
    "alternatives",
    "bugs",
    "expanded",
    "los_checks",
    "peak_bytes",
    "time_s",
    "runs",
];

/// `results.csv`: one row per query and planner run (a skipped `optimal` has no row).
/// Lengths in cells, times in seconds.
#[must_use]
pub fn csv(results: &Results) -> String {
    let mut out = CSV_HEADER.join(",");
    out.push('\n');
    for m in &results.maps {
        for (q, query) in m.map.queries.iter().enumerate() {
            let optimal = optimal_length(results, m, q);
            let astar_ps = astar_ps_length(results, m, q);
            let (bucket, octile) = match query.origin {
                Origin::Scen {
                    bucket,
                    octile_optimum_cells,
                } => (Some(bucket), Some(octile_optimum_cells)),
                _ => (None, None),
            };
            for (&kind, record) in results.planners.iter().zip(&m.records[q]) {
                let Some(r) = record else { continue };
                let ratio = |reference: Option<f64>| {
                    opt(r
                        .length_cells
                        .zip(reference)
                        .and_then(|(l, x)| (x > 0.0).then(|| l / x)))
                };
                let fields = [
                    csv_field(&m.map.name),
                    csv_field(&m.map.category),
                    (q + 1).to_string(),
                    query.origin.name().to_owned(),
                    opt(bucket),
                    query.start.x.to_string(),
                    query.start.y.to_string(),
                    query.goal.x.to_string(),
                    query.goal.y.to_string(),
                    m.map
                        .components
                        .connected(query.start, query.goal)
                        .to_string(),
                    kind.name().to_owned(),
                    r.found.to_string(),
                    match &r.valid {
                        None => "n/a".to_owned(),
                        Some(v) => v.is_ok().to_string(),
                    },
                    opt(r.length_cells),
                    opt(optimal),
                    ratio(optimal),
                    ratio(astar_ps),
                    opt(octile),
                    if r.found {
                        r.waypoints.to_string()
                    } else {
                        String::new()
                    },
                    opt(r.turning_deg),
                    opt(r.alternatives),
                    opt(r.bugs),
                    opt(r.expanded),
                    opt(r.los_checks),
                    r.peak_bytes.to_string(),
                    r.time_s.to_string(),
                    r.runs.to_string(),
                ];
                out.push_str(&fields.join(","));
                out.push('\n');
            }
        }
    }
    out
}

fn percent(v: Option<f64>) -> String {
    v.map_or_else(|| "n/a".to_owned(), |v| format!("{:.2} %", 100.0 * v))
}

fn ratio_text(v: Option<f64>) -> String {
    v.map_or_else(|| "n/a".to_owned(), |v| format!("{v:.2}"))
}

fn ms_text(seconds: Option<f64>) -> String {
    match seconds {
        None => "n/a".to_owned(),
        Some(s) if s >= 0.1 => format!("{:.0}", s * 1e3),
        Some(s) if s >= 0.001 => format!("{:.2}", s * 1e3),
        Some(s) => format!("{:.3}", s * 1e3),
    }
}

fn versus_text(v: Option<Versus>) -> String {
    match v {
        Some(v) if v.total() > 0 => {
            let [s, e, l] = v.shares();
            format!(
                "{:.0} / {:.0} / {:.0} % ({}/{}/{})",
                100.0 * s,
                100.0 * e,
                100.0 * l,
                v.shorter,
                v.equal,
                v.longer
            )
        }
        _ => "n/a".to_owned(),
    }
}

fn queries_text(g: &Group) -> String {
    if g.unsolvable > 0 {
        format!("{} + {} unsolvable", g.solvable, g.unsolvable)
    } else {
        g.solvable.to_string()
    }
}

fn table_row(out: &mut String, cells: &[String]) {
    let _ = writeln!(out, "| {} |", cells.join(" | "));
}

fn table_head(out: &mut String, cells: &[String]) {
    table_row(out, cells);
    table_row(out, &vec!["---".to_owned(); cells.len()]);
}

/// The Markdown summary; images are linked as `{image_prefix}{name}.{image_ext}`.
#[must_use]
pub fn markdown(
    results: &Results,
    summary: &Summary,
    image_prefix: &str,
    image_ext: &str,
) -> String {
    let mut out = String::new();
    let planners = &results.planners;
    let mbpp_at = results.index_of(PlannerKind::Mbpp);
    let has_astar_ps = results.index_of(PlannerKind::AstarPs).is_some();
    let has_optimal = results.index_of(PlannerKind::Optimal).is_some();
    let _ = writeln!(
        out,
        "## Planners on benchmark maps (`vpmap bench`, thesis section 6.2)\n"
    );
    let _ = writeln!(out, "* Command: `{}`", results.command);
    let _ = writeln!(out, "* Date: {}", results.date);
    let _ = writeln!(out, "* Machine: {}", results.machine);
    let _ = writeln!(
        out,
        "* Queries: {} solvable per map (scenario problems spread over the buckets, or random \
         free-cell pairs spread over lengths, seed {}), plus {UNSOLVABLE_PER_MAP} unsolvable \
         ones on every map with more than one connected component",
        results.per_map, results.seed
    );
    let _ = writeln!(
        out,
        "* Timing: one thread, a fresh planner per run, one warm-up run, then the median of \
         {} timed run(s); a query whose warm-up run takes over {} s is timed by that run \
         alone. Lengths in cells. Wall time of the run: {:.0} s",
        results.repeat,
        super::measure::SINGLE_RUN_ABOVE.as_secs_f64(),
        results.wall_s
    );
    for note in &results.notes {
        let _ = writeln!(out, "* {note}");
    }
    out.push('\n');

    let _ = writeln!(out, "### Per category\n");
    if has_astar_ps {
        let _ = writeln!(
            out,
            "Runtime: geometric mean of each planner's time over A* PS's on the same query \
             (below 1: faster than A* PS).\n"
        );
        let others: Vec<usize> = (0..planners.len())
            .filter(|&p| planners[p] != PlannerKind::AstarPs)
            .collect();
        let mut head = vec![
            "category".to_owned(),
            "maps".to_owned(),
            "queries".to_owned(),
        ];
        head.extend(
            others
                .iter()
                .map(|&p| format!("{} / A* PS", label(planners[p]))),
        );
        table_head(&mut out, &head);
        for g in summary.categories.iter().chain([&summary.all]) {
            let mut row = vec![bold_if_all(g), g.maps.to_string(), queries_text(g)];
            row.extend(others.iter().map(|&p| ratio_text(g.planners[p].time_ratio)));
            table_row(&mut out, &row);
        }
        out.push('\n');
    }
    let _ = writeln!(
        out,
        "Path length: {}mean excess over the exact optimum{}.\n",
        if mbpp_at.is_some() && has_astar_ps {
            "share of solvable queries where MBPP's path is shorter / equal (within 1e-9) / \
             longer than A* PS's, and "
        } else {
            ""
        },
        if has_optimal {
            " (maps where `optimal` was skipped are left out)"
        } else {
            " (n/a: `optimal` was not run)"
        }
    );
    let optimal_at = results.index_of(PlannerKind::Optimal);
    let mut head = vec!["category".to_owned()];
    if mbpp_at.is_some() && has_astar_ps {
        head.push("MBPP vs A* PS: shorter / equal / longer".to_owned());
    }
    if optimal_at.is_some() {
        head.push("queries with an optimum".to_owned());
    }
    head.extend(planners.iter().map(|&k| format!("{} excess", label(k))));
    head.push("failures".to_owned());
    table_head(&mut out, &head);
    for g in summary.categories.iter().chain([&summary.all]) {
        let mut row = vec![bold_if_all(g)];
        if let Some(at) = mbpp_at.filter(|_| has_astar_ps) {
            row.push(versus_text(g.planners[at].vs_astar_ps));
        }
        if let Some(at) = optimal_at {
            row.push(format!(
                "{} of {}",
                g.planners[at].excess_queries, g.solvable
            ));
        }
        row.extend(g.planners.iter().map(|s| percent(s.mean_excess)));
        row.push(g.failures.to_string());
        table_row(&mut out, &row);
    }
    out.push('\n');

    let _ = writeln!(
        out,
        "![Mean runtime per map and planner]({image_prefix}runtime.{image_ext})\n\n\
         ![Mean path length per map and planner]({image_prefix}length.{image_ext})\n"
    );
    if has_excess_plot(planners) {
        let _ = writeln!(
            out,
            "![Mean excess over the optimum per map and planner]({image_prefix}excess.{image_ext})\n"
        );
    }

    let _ = writeln!(out, "### Per map: mean time per query, ms\n");
    if has_optimal {
        let _ = writeln!(
            out,
            "`optimal`'s time per query includes building its free space (a fresh planner per \
             run, like every planner); the build alone, once per map, is in its own column \
             (timed like a query: warm-up, then the median). A caller that keeps the planner pays it once per map.\n"
        );
    }
    let mut head = vec![
        "map".to_owned(),
        "category".to_owned(),
        "size".to_owned(),
        "free".to_owned(),
        "components".to_owned(),
        "corner cells".to_owned(),
        "queries".to_owned(),
    ];
    head.extend(planners.iter().map(|&k| label(k).to_owned()));
    if has_optimal {
        head.push("optimal's build, once per map".to_owned());
    }
    if mbpp_at.is_some() && has_astar_ps {
        head.push("MBPP / A* PS".to_owned());
    }
    table_head(&mut out, &head);
    for (m, g) in results.maps.iter().zip(&summary.maps) {
        let (w, h) = (m.map.grid.width(), m.map.grid.height());
        let free = m.map.components.passable_cells() as f64 / (w * h) as f64;
        let mut row = vec![
            format!("`{}`", m.map.name),
            m.map.category.clone(),
            format!("{w} x {h}"),
            format!("{:.0} %", 100.0 * free),
            m.map.components.count().to_string(),
            m.corner_cells.to_string(),
            queries_text(g),
        ];
        row.extend(g.planners.iter().map(|s| ms_text(s.mean_time_s)));
        if has_optimal {
            row.push(ms_text(m.optimal_build_s));
        }
        if let Some(at) = mbpp_at.filter(|_| has_astar_ps) {
            row.push(ratio_text(g.planners[at].time_ratio));
        }
        table_row(&mut out, &row);
    }
    out.push('\n');

    let _ = writeln!(
        out,
        "### Per map: largest peak heap of one query, MB\n\nBytes allocated during the \
         query above those in use before it, results included.\n"
    );
    let mut head = vec!["map".to_owned()];
    head.extend(planners.iter().map(|&k| label(k).to_owned()));
    table_head(&mut out, &head);
    for (m, g) in results.maps.iter().zip(&summary.maps) {
        let mut row = vec![format!("`{}`", m.map.name)];
        row.extend(g.planners.iter().map(|s| {
            if s.runs == 0 {
                "n/a".to_owned()
            } else {
                format!("{:.2}", s.max_peak_bytes as f64 / 1e6)
            }
        }));
        table_row(&mut out, &row);
    }
    out.push('\n');

    let _ = writeln!(
        out,
        "### Per map: mean path length, cells (mean excess over the optimum)\n"
    );
    let mut head = vec!["map".to_owned()];
    head.extend(planners.iter().map(|&k| label(k).to_owned()));
    if mbpp_at.is_some() && has_astar_ps {
        head.push("MBPP vs A* PS: shorter / equal / longer".to_owned());
    }
    table_head(&mut out, &head);
    for (m, g) in results.maps.iter().zip(&summary.maps) {
        let mut row = vec![format!("`{}`", m.map.name)];
        row.extend(
            g.planners
                .iter()
                .map(|s| match (s.mean_length_cells, s.mean_excess) {
                    (None, _) => "n/a".to_owned(),
                    (Some(l), None) => format!("{l:.2}"),
                    (Some(l), Some(e)) => format!("{l:.2} (+{:.2} %)", 100.0 * e),
                }),
        );
        if let Some(at) = mbpp_at.filter(|_| has_astar_ps) {
            row.push(versus_text(g.planners[at].vs_astar_ps));
        }
        table_row(&mut out, &row);
    }
    out.push('\n');

    let skipped: Vec<&MapResult> = results
        .maps
        .iter()
        .filter(|m| m.optimal_skipped.is_some())
        .collect();
    if has_optimal {
        if skipped.is_empty() {
            let _ = writeln!(out, "`optimal` ran on every map.\n");
        } else {
            let _ = writeln!(
                out,
                "`optimal` was skipped (limit: {} s for one query) on: {}. Their optimal lengths are empty and they are left out of the \
                 excess columns.\n",
                results.optimal_limit_s,
                skipped
                    .iter()
                    .map(|m| format!(
                        "`{}` ({})",
                        m.map.name,
                        m.optimal_skipped.as_deref().unwrap_or("")
                    ))
                    .collect::<Vec<_>>()
                    .join(", ")
            );
        }
    }
    if summary.failures.is_empty() {
        let _ = writeln!(
            out,
            "Failures: none. Every planner found a path exactly when breadth-first search \
             connects start and goal, every path passed the independent validator, and no \
             length was below the exact optimum."
        );
    } else {
        let _ = writeln!(out, "Failures ({}):\n", summary.failures.len());
        for f in summary.failures.iter().take(FAILURES_SHOWN) {
            let _ = writeln!(out, "* {f}");
        }
        if summary.failures.len() > FAILURES_SHOWN {
            let _ = writeln!(
                out,
                "* ... and {} more (see summary.json)",
                summary.failures.len() - FAILURES_SHOWN
            );
        }
    }
    out
}

fn bold_if_all(g: &Group) -> String {
    if g.name == "all" {
        "**all**".to_owned()
    } else {
        g.name.clone()
    }
}

fn group_json(results: &Results, g: &Group) -> Value {
    let mut planners = serde_json::Map::new();
    for (&kind, s) in results.planners.iter().zip(&g.planners) {
        let versus = s.vs_astar_ps.map(|v| {
            let [sh, eq, lo] = v.shares();
            json!({
                "shorter": v.shorter, "equal": v.equal, "longer": v.longer,
                "shorter_share": sh, "equal_share": eq, "longer_share": lo,
            })
        });
        planners.insert(
            kind.name().to_owned(),
            json!({
                "queries": s.runs,
                "mean_time_s": s.mean_time_s,
                "time_ratio_to_astar_ps": s.time_ratio,
                "time_ratio_queries": s.ratio_queries,
                "mean_excess_over_optimal": s.mean_excess,
                "max_excess_over_optimal": s.max_excess,
                "excess_queries": s.excess_queries,
                "mean_length": s.mean_length_cells,
                "mean_turning_deg": s.mean_turning_deg,
                "max_peak_bytes": s.max_peak_bytes,
                "vs_astar_ps": versus,
            }),
        );
    }
    json!({
        "name": g.name,
        "maps": g.maps,
        "solvable_queries": g.solvable,
        "unsolvable_queries": g.unsolvable,
        "failures": g.failures,
        "optimal_skipped_on": g.optimal_skipped,
        "planners": planners,
    })
}

/// `summary.json`: the summary's numbers (fractions, seconds, cells).
#[must_use]
pub fn json(results: &Results, summary: &Summary) -> Value {
    let maps: Vec<Value> = results
        .maps
        .iter()
        .zip(&summary.maps)
        .map(|(m, g)| {
            let mut v = group_json(results, g);
            if let Value::Object(o) = &mut v {
                o.insert("category".to_owned(), json!(m.map.category));
                o.insert("source".to_owned(), json!(m.map.source));
                o.insert("width".to_owned(), json!(m.map.grid.width()));
                o.insert("height".to_owned(), json!(m.map.grid.height()));
                o.insert(
                    "free_cells".to_owned(),
                    json!(m.map.components.passable_cells()),
                );
                o.insert("components".to_owned(), json!(m.map.components.count()));
                o.insert("corner_cells".to_owned(), json!(m.corner_cells));
                o.insert("optimal_skipped".to_owned(), json!(m.optimal_skipped));
                o.insert("optimal_build_s".to_owned(), json!(m.optimal_build_s));
                o.insert("wall_s".to_owned(), json!(m.wall_s));
            }
            v
        })
        .collect();
    json!({
        "command": results.command,
        "date": results.date,
        "machine": results.machine,
        "planners": results.planners.iter().map(|k| k.name()).collect::<Vec<_>>(),
        "per_map": results.per_map,
        "unsolvable_per_map": UNSOLVABLE_PER_MAP,
        "repeat": results.repeat,
        "seed": results.seed,
        "wall_s": results.wall_s,
        "length_units": "cells",
        "notes": results.notes,
        "categories": summary.categories.iter().map(|g| group_json(results, g)).collect::<Vec<_>>(),
        "all": group_json(results, &summary.all),
        "maps": maps,
        "failures": summary.failures,
    })
}

/// A few lines for the terminal: per category, MBPP's time ratio and length shares, and
/// every planner's mean excess.
#[must_use]
pub fn console(results: &Results, summary: &Summary) -> String {
    let mut out = String::new();
    let mbpp_at = results.index_of(PlannerKind::Mbpp);
    for g in summary.categories.iter().chain([&summary.all]) {
        let mut parts = Vec::new();
        if let Some(s) = mbpp_at.map(|at| &g.planners[at]) {
            if let Some(r) = s.time_ratio {
                parts.push(format!("MBPP/A* PS time {r:.2}"));
            }
            if let Some(v) = s.vs_astar_ps.filter(|v| v.total() > 0) {
                let [sh, eq, lo] = v.shares();
                parts.push(format!(
                    "MBPP shorter/equal/longer {:.0}/{:.0}/{:.0} %",
                    100.0 * sh,
                    100.0 * eq,
                    100.0 * lo
                ));
            }
        }
        let excess: Vec<String> = results
            .planners
            .iter()
            .zip(&g.planners)
            .filter_map(|(&k, s)| {
                s.mean_excess
                    .map(|e| format!("{} {:.2} %", k.name(), 100.0 * e))
            })
            .collect();
        if !excess.is_empty() {
            parts.push(format!("excess {}", excess.join(", ")));
        }
        parts.push(format!("{} failures", g.failures));
        let _ = writeln!(
            out,
            "{:<12} {:>3} maps, {:>4} queries: {}",
            g.name,
            g.maps,
            g.solvable + g.unsolvable,
            parts.join("; ")
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_fields_are_quoted_when_needed() {
        assert_eq!(csv_field("den520d"), "den520d");
        assert_eq!(csv_field("a,b"), "\"a,b\"");
        assert_eq!(csv_field("say \"hi\""), "\"say \"\"hi\"\"\"");
    }

    #[test]
    fn figures_read_as_the_tables_write_them() {
        let v = Versus {
            shorter: 1,
            equal: 2,
            longer: 1,
        };
        assert_eq!(versus_text(Some(v)), "25 / 50 / 25 % (1/2/1)");
        assert_eq!(ms_text(Some(0.0123)), "12.30");
        assert_eq!(percent(Some(0.0123)), "1.23 %");
    }
}

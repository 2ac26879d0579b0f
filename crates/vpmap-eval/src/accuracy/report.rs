//! What a map-accuracy run reads as: `summary.md` (the headline numbers, set-ups, refusals,
//! the error bars' coverage, one table per metric beside the thesis's ranges, the camera's
//! errors), its published section, and the console's headline.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use vpmap_metrology::calibration::Perspective;
use vpmap_metrology::eval::{CAMERA_COVERAGE_METRICS, COVERAGE_METRICS, OBJECT_METRICS, VpEdges};
use vpmap_metrology::synth::Annotation;

use super::collect::{
    CAMERA_COVERAGE_BASE, COVERAGE_BASE, Collected, DESCRIBED, Group, Refusals, SCENE_BASE,
};
use super::config::Config;
use crate::stats::Summary;

/// A number for a table: two decimals, or one significant digit when smaller than 0.005
/// (so an exact result reads `0` or `3e-12`, not `0.00`).
#[must_use]
pub fn fmt(v: f64) -> String {
    if v == 0.0 {
        "0".to_owned()
    } else if v.abs() < 0.005 {
        format!("{v:.0e}")
    } else {
        format!("{v:.2}")
    }
}

fn range(sum: Option<Summary>) -> [String; 3] {
    sum.map_or_else(
        || ["-".to_owned(), "-".to_owned(), "-".to_owned()],
        |s| {
            [
                fmt(s.median),
                format!("{} … {}", fmt(s.p5), fmt(s.p95)),
                format!("{} … {}", fmt(s.min), fmt(s.max)),
            ]
        },
    )
}

fn sigma_text(s: f64) -> String {
    format!("{s}")
}

/// The Markdown report (without a title): `image_prefix` is put before every image link.
pub fn markdown(
    config: &Config,
    c: &Collected,
    image_of: &BTreeMap<&'static str, String>,
    image_prefix: &str,
) -> String {
    let mut md = String::new();
    let sigmas: Vec<String> = config.sigmas.iter().map(|s| sigma_text(*s)).collect();
    let methods: Vec<String> = config.methods.iter().map(ToString::to_string).collect();
    let edges = match config.vp_edges {
        VpEdges::Objects => String::new(),
        VpEdges::Long(long) => format!(
            ", vanishing points from {} long edges of {} px each",
            long.per_vanishing_point, long.length_px
        ),
    };
    let _ = writeln!(
        md,
        "{} trials per experiment, seed {}, annotation noise σ = {} px, methods {}{edges}; box plots at σ = {} px.\n",
        config.trials,
        config.seed,
        sigmas.join(", "),
        methods.join(", "),
        sigma_text(config.plot_sigma)
    );
    md.push_str(&method_note(config.vp_edges));
    if super::has_views(&config.setups) {
        md.push_str(VIEWS_NOTE);
    }
    md.push_str(&at_a_glance(config, c));
    md.push_str("\n### Experiments\n\n");
    md.push_str("| set-up | perspective | camera height (m) | pitch (°) | roll (°) | focal (px) | image (px) | objects | scene |\n|---|---|---|---|---|---|---|---|---|\n");
    for s in &config.setups {
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} | {} | {} x {} | {} boxes + {} footprint | {} |",
            s.name,
            s.perspective.name().to_uppercase(),
            s.height_m,
            s.pitch_deg,
            s.roll_deg,
            s.focal_px,
            s.image.width,
            s.image.height,
            s.boxes,
            s.prisms,
            s.description
        );
    }
    md.push_str("\n### Scenes the builders refused\n\nA refused scene counts as a failure here and adds no object to the statistics.\n\n| method | σ (px) | 2PP refused | 3PP refused | reasons |\n|---|---|---|---|---|\n");
    for (m, method) in config.methods.iter().enumerate() {
        for (s, sigma) in config.sigmas.iter().enumerate() {
            let mut cells = Vec::new();
            let mut reasons = Refusals::default();
            for p in [Perspective::TwoPoint, Perspective::ThreePoint] {
                let r = c.refusals(config, m, s, Group::Perspective(p));
                cells.push(refused_text(&r));
                reasons.add(&r);
            }
            let why: Vec<String> = reasons
                .by_category
                .iter()
                .map(|(k, v)| format!("{k} {v}"))
                .collect();
            let _ = writeln!(
                md,
                "| {method} | {} | {} | {} | {} |",
                sigma_text(*sigma),
                cells[0],
                cells[1],
                if why.is_empty() {
                    "-".to_owned()
                } else {
                    why.join(", ")
                }
            );
        }
    }
    md.push_str(&coverage_section(config, c));
    if config
        .setups
        .iter()
        .any(|s| s.annotation != Annotation::Thesis)
    {
        md.push_str(&per_setup_section(config, c));
    }
    md.push_str("\n### The thesis's metrics, per object\n\nPercentiles over every object of every trial of the perspective's set-ups; `S_k`: the truth scaled by eq. 6.1, `true`: the map in metres against the truth in metres.\n");
    for (k, d) in DESCRIBED.iter().enumerate() {
        let _ = write!(
            md,
            "\n#### `{}`: {} ({})\n\nThesis, 2PP (fig. {}): {}. 3PP (fig. {}): {}.",
            d.name, d.title, d.unit, d.figures[0], d.thesis[0], d.figures[1], d.thesis[1]
        );
        if !d.errata.is_empty() {
            let _ = write!(md, " Errata (\"Under noise\"): {}.", d.errata);
        }
        md.push_str("\n\n| method | σ (px) | scale | 2PP median | 2PP p5 … p95 | 2PP min … max | 3PP median | 3PP p5 … p95 | 3PP min … max |\n|---|---|---|---|---|---|---|---|---|\n");
        for (scale, metric) in [("S_k", k), ("true", k + OBJECT_METRICS.len())] {
            for (m, method) in config.methods.iter().enumerate() {
                for (s, sigma) in config.sigmas.iter().enumerate() {
                    let [a, b, cc] = range(c.summary(
                        config,
                        m,
                        s,
                        Group::Perspective(Perspective::TwoPoint),
                        metric,
                    ));
                    let [x, y, z] = range(c.summary(
                        config,
                        m,
                        s,
                        Group::Perspective(Perspective::ThreePoint),
                        metric,
                    ));
                    let _ = writeln!(
                        md,
                        "| {method} | {} | {scale} | {a} | {b} | {cc} | {x} | {y} | {z} |",
                        sigma_text(*sigma)
                    );
                }
            }
        }
        if let Some(link) = image_of.get(d.name) {
            let _ = writeln!(
                md,
                "\n![{}: box plot per experiment at σ = {} px]({image_prefix}{link})",
                d.name,
                sigma_text(config.plot_sigma)
            );
        }
    }
    md.push_str("\n### The camera, per scene\n\nMedian [p5, p95] over the scenes a method built. `camera_height_error_pct` is the `S_k` variant's (the reference box's scale error); `scale_factor` is `S_k` itself.\n\n| method | σ (px) | perspective |");
    let scene_metrics: Vec<usize> = (SCENE_BASE..COVERAGE_BASE).collect();
    for &k in &scene_metrics {
        let _ = write!(md, " `{}` |", c.metrics[k]);
    }
    md.push_str("\n|---|---|---|");
    md.push_str(&"---|".repeat(scene_metrics.len()));
    md.push('\n');
    for (m, method) in config.methods.iter().enumerate() {
        for (s, sigma) in config.sigmas.iter().enumerate() {
            for p in [Perspective::TwoPoint, Perspective::ThreePoint] {
                if !config.setups.iter().any(|x| x.perspective == p) {
                    continue;
                }
                let _ = write!(
                    md,
                    "| {method} | {} | {} |",
                    sigma_text(*sigma),
                    p.name().to_uppercase()
                );
                for &k in &scene_metrics {
                    let cell = c
                        .summary(config, m, s, Group::Perspective(p), k)
                        .map_or_else(
                            || "-".to_owned(),
                            |x| format!("{} [{}, {}]", fmt(x.median), fmt(x.p5), fmt(x.p95)),
                        );
                    let _ = write!(md, " {cell} |");
                }
                md.push('\n');
            }
        }
    }
    md
}

/// Index in [`metric_names`] of an object metric's true-scale variant.
fn true_scale(metric: &str) -> usize {
    OBJECT_METRICS.len()
        + OBJECT_METRICS
            .iter()
            .position(|m| *m == metric)
            .unwrap_or(0)
}

/// `refused of scenes (pct %)`, or `-` without scenes.
fn refused_text(r: &Refusals) -> String {
    if r.scenes == 0 {
        "-".to_owned()
    } else {
        format!(
            "{} of {} ({:.1} %)",
            r.refused(),
            r.scenes,
            100.0 * r.refused() as f64 / r.scenes as f64
        )
    }
}

/// The perspectives the chosen set-ups have.
fn perspectives(config: &Config) -> Vec<Perspective> {
    [Perspective::TwoPoint, Perspective::ThreePoint]
        .into_iter()
        .filter(|p| config.setups.iter().any(|s| s.perspective == *p))
        .collect()
}

/// The headline numbers per method and noise level at the true scale: median overlap,
/// 95th-percentile centroid shift, refusals, and the fit's 95 % ellipse coverage.
fn at_a_glance(config: &Config, c: &Collected) -> String {
    let overlap = true_scale("area_overlap_pct");
    let shift = true_scale("centroid_shift_pct");
    let ellipse = COVERAGE_BASE;
    let mut md = String::from(
        "\n### At a glance\n\nPer object at the true scale (the map in metres against the truth in metres): median area overlap, 95th-percentile centroid shift, scenes refused, and the share of objects whose true centroid lies inside the reported 95 % ellipse (methods with error bars; see \"Error-bar coverage\").\n\n| method | σ (px) | perspective | median overlap (%) | p95 centroid shift (%) | refused | in 95 % ellipse |\n|---|---|---|---|---|---|---|\n",
    );
    for (m, method) in config.methods.iter().enumerate() {
        for (s, sigma) in config.sigmas.iter().enumerate() {
            for p in perspectives(config) {
                let g = Group::Perspective(p);
                let o = c.summary(config, m, s, g, overlap);
                let sh = c.summary(config, m, s, g, shift);
                let e = c.summary(config, m, s, g, ellipse);
                let _ = writeln!(
                    md,
                    "| {method} | {} | {} | {} | {} | {} | {} |",
                    sigma_text(*sigma),
                    p.name().to_uppercase(),
                    o.map_or_else(|| "-".to_owned(), |x| fmt(x.median)),
                    sh.map_or_else(|| "-".to_owned(), |x| fmt(x.p95)),
                    refused_text(&c.refusals(config, m, s, g)),
                    e.map_or_else(|| "-".to_owned(), |x| share(x.mean, x.count)),
                );
            }
        }
    }
    md
}

/// A share of objects, `93.5 % of 1200`.
fn share(mean: f64, count: usize) -> String {
    format!("{:.1} % of {count}", 100.0 * mean)
}

/// One row of the error-bar tables: a method, a noise level above zero and a perspective
/// (indices into the run's [`Config`]).
struct NoisyCell {
    method: usize,
    sigma: usize,
    perspective: Perspective,
}

impl NoisyCell {
    /// The row's first three cells, `| fit | 1 | 3PP`.
    fn label(&self, config: &Config) -> String {
        format!(
            "| {} | {} | {}",
            config.methods[self.method],
            sigma_text(config.sigmas[self.sigma]),
            self.perspective.name().to_uppercase()
        )
    }
}

/// Every method, noise level above zero and perspective of the run, in the tables' order.
fn noisy_cells(config: &Config) -> Vec<NoisyCell> {
    let mut out = Vec::new();
    for method in 0..config.methods.len() {
        for (sigma, value) in config.sigmas.iter().enumerate() {
            if *value > 0.0 {
                out.extend(
                    perspectives(config)
                        .into_iter()
                        .map(|perspective| NoisyCell {
                            method,
                            sigma,
                            perspective,
                        }),
                );
            }
        }
    }
    out
}

/// The error-bar coverage table: per method with error bars, noise level above zero and
/// perspective.
fn coverage_section(config: &Config, c: &Collected) -> String {
    let mut rows = String::new();
    for cell in noisy_cells(config) {
        let (m, s, g) = (
            cell.method,
            cell.sigma,
            Group::Perspective(cell.perspective),
        );
        let Some(centroid) = c.summary(config, m, s, g, COVERAGE_BASE) else {
            continue;
        };
        let _ = write!(rows, "{} | {}", cell.label(config), centroid.count);
        for k in 0..COVERAGE_METRICS.len() {
            let cell = c
                .summary(config, m, s, g, COVERAGE_BASE + k)
                .map_or_else(|| "-".to_owned(), |x| format!("{:.1}", 100.0 * x.mean));
            let _ = write!(rows, " | {cell}");
        }
        let d2 = c
            .summary(config, m, s, g, COVERAGE_BASE + COVERAGE_METRICS.len())
            .map_or_else(|| "-".to_owned(), |x| fmt(x.median));
        let _ = writeln!(rows, " | {d2} |");
    }
    if rows.is_empty() {
        return String::new();
    }
    format!(
        "\n### Error-bar coverage\n\nFor the objects a method gives error bars for (the fit's, computed for the true σ), at the true scale: the share (%) whose true centroid lies inside the reported 95 % ellipse (squared Mahalanobis distance with the reported centroid covariance at most 5.991, the 95 % point of χ² with 2 degrees of freedom), and whose true length, breadth, height and yaw lie within ±2 standard deviations of the reported ones (length: the map's longer side, against the true length of the same side; yaw: that side's direction). Calibrated error bars give about 95 % in every column and a median squared distance of 1.39 (χ² with 2 degrees of freedom); fewer mean the error bars are too small.\n\n| method | σ (px) | perspective | objects | centroid in 95 % ellipse | length within ±2σ | breadth within ±2σ | height within ±2σ | yaw within ±2σ | median d² |\n|---|---|---|---|---|---|---|---|---|---|\n{rows}{}",
        camera_coverage_table(config, c)
    )
}

/// The camera's error-bar coverage: per method with error bars, noise level above zero and
/// perspective, the share of scenes whose true focal length, pitch, roll and principal point
/// lie within `±2 sd` of the fitted camera's.
fn camera_coverage_table(config: &Config, c: &Collected) -> String {
    /// The columns' headings, in the order of `CAMERA_COVERAGE_METRICS`.
    const HEADINGS: [&str; 5] = [
        "focal within ±2σ",
        "pitch within ±2σ",
        "roll within ±2σ",
        "principal point x within ±2σ",
        "principal point y within ±2σ",
    ];
    let mut rows = Vec::new();
    for cell in noisy_cells(config) {
        let (m, s, g) = (
            cell.method,
            cell.sigma,
            Group::Perspective(cell.perspective),
        );
        let cells: Vec<Option<Summary>> = (0..CAMERA_COVERAGE_METRICS.len())
            .map(|k| c.summary(config, m, s, g, CAMERA_COVERAGE_BASE + k))
            .collect();
        let Some(scenes) = cells.iter().flatten().map(|x| x.count).max() else {
            continue;
        };
        rows.push((format!("{} | {scenes}", cell.label(config)), cells));
    }
    // A quantity no scene estimated (the principal point, which the scenes give) is left out.
    let columns: Vec<usize> = (0..HEADINGS.len())
        .filter(|&k| rows.iter().any(|(_, cells)| cells[k].is_some()))
        .collect();
    if rows.is_empty() {
        return String::new();
    }
    let mut md = "\nThe camera's error bars, per scene: the share (%) of the scenes a method built whose true focal length, pitch and roll (and principal point, each coordinate, where a fit estimated it) lie within ±2 standard deviations of the fitted camera's (`camera.uncertainty` in map.json). A two-point photo's pitch is held at 0, not estimated: it has no error bar (\"held\").\n\n| method | σ (px) | perspective | scenes |".to_owned();
    for &k in &columns {
        let _ = write!(md, " {} |", HEADINGS[k]);
    }
    md.push_str("\n|---|---|---|---|");
    md.push_str(&"---|".repeat(columns.len()));
    md.push('\n');
    for (label, cells) in &rows {
        md.push_str(label);
        for &k in &columns {
            let text = cells[k]
                .as_ref()
                .map_or_else(|| "(held)".to_owned(), |x| format!("{:.1}", 100.0 * x.mean));
            let _ = write!(md, " | {text}");
        }
        md.push_str(" |\n");
    }
    md
}

/// Per set-up at the plots' noise level: refusals, true-scale overlap and centroid shift,
/// coverage (for runs of the views of [`vpmap_metrology::eval::VIEW_SETUPS`], where each
/// set-up is a different way of seeing the boxes).
fn per_setup_section(config: &Config, c: &Collected) -> String {
    let Some(s) = config
        .sigmas
        .iter()
        .position(|x| (x - config.plot_sigma).abs() <= 1e-12)
    else {
        return String::new();
    };
    let overlap = true_scale("area_overlap_pct");
    let shift = true_scale("centroid_shift_pct");
    let mut md = format!(
        "\n### Per set-up at σ = {} px\n\nTrue scale, per object.\n\n| set-up | method | refused | median overlap (%) | p95 centroid shift (%) | in 95 % ellipse |\n|---|---|---|---|---|---|\n",
        sigma_text(config.plot_sigma)
    );
    for (e, setup) in config.setups.iter().enumerate() {
        for (m, method) in config.methods.iter().enumerate() {
            let g = Group::Experiment(e);
            let _ = writeln!(
                md,
                "| {} | {method} | {} | {} | {} | {} |",
                setup.name,
                refused_text(&c.refusals(config, m, s, g)),
                c.summary(config, m, s, g, overlap)
                    .map_or_else(|| "-".to_owned(), |x| fmt(x.median)),
                c.summary(config, m, s, g, shift)
                    .map_or_else(|| "-".to_owned(), |x| fmt(x.p95)),
                c.summary(config, m, s, g, COVERAGE_BASE)
                    .map_or_else(|| "-".to_owned(), |x| share(x.mean, x.count)),
            );
        }
    }
    md
}

/// How the numbers were made, for the report.
const METHOD_NOTE: &str = "Each trial draws a random scene of the set-up from vpmap's synthetic pinhole camera (seed from `--seed`, the set-up's name and the trial number), adds Gaussian noise of standard deviation σ pixels to every annotated point (box base corners and tops, footprint vertices, floor corners) and gives the vanishing points as the box edges through those noisy corners, which the builder intersects by least squares; every method builds the same noisy scene. The thesis's six metrics (section 6.1.1) are computed per object with the station point as origin, in two variants: `S_k`, the truth scaled to the model by eq. 6.1 from the first box (the reference object), and `true` (metric names with the suffix `_true_scale` in the files), the map in metres from the known camera height against the truth in metres. Pose errors are wrapped to (-180°, 180°], skew errors to (-90°, 90°] (a side is an undirected line; modelled and actual sides correspond by their annotated corners). Percentiles interpolate between order statistics (type 7). Box plots: box from the first to the third quartile, line at the median, whiskers at the 5th and 95th percentiles (not 1.5 IQR fences); nothing beyond them is drawn. The synthetic objects' sizes scale with the camera height and every metric is relative, so a set-up's camera height alone changes nothing: room-sized and table-top set-ups differ by focal length, image size, pitch, roll and object count. The thesis's ranges come from photos measured by hand, so they mix annotation, vanishing-point and ground-truth errors; here the truth is exact and only the annotation is noisy.\n";

/// What the views' set-ups are, for runs that have them.
const VIEWS_NOTE: &str = "\nThe views' set-ups reproduce what annotating real photos showed (issue 12), each in two-point (camera and objects of `2pp-2`) and three-point perspective (`3pp-1`). `*-face`: the room, and every box with it, turned 3-10° either way from square to the camera's viewing direction, boxes lower than the camera, each annotated in the face view by its two front base corners and its four top corners. `*-hidden`: boxes lower than the camera, annotated in the corner view by the near base corner and the four top corners. `*-yaw`: every second box turned from the room's axes by its own angle (15-40° either way) and marked `own_yaw`, annotated as the thesis does; its horizontal edges are not among the vanishing-point edges (they run to its own vanishing points), its vertical edges are. The side-view method and the projective form read only the thesis's corners (base near, right, left; top near, left), so they refuse the face-on and hidden-base scenes; they read the own-yaw scenes, where the side view draws every box along the room's directions and the projective form puts each clicked corner on the floor.\n";

/// What [`METHOD_NOTE`] says of the vanishing points with `--vp-edges objects`.
const OBJECT_EDGES_NOTE: &str = "gives the vanishing points as the box edges through those noisy corners, which the builder intersects by least squares";

/// [`METHOD_NOTE`] for the chosen vanishing-point edges.
fn method_note(edges: VpEdges) -> String {
    match edges {
        VpEdges::Objects => METHOD_NOTE.to_owned(),
        VpEdges::Long(long) => METHOD_NOTE.replacen(
            OBJECT_EDGES_NOTE,
            &format!(
                "gives each vanishing point as {} long straight edges of {} px (`--vp-edges long`: room lines such as floor-wall junctions and wall corners, each on the line from the vanishing point through a pixel drawn uniformly over the image, inside the image and on the far side of the vanishing point, i.e. the image of a 3D line in the vanishing direction in front of the true camera) whose end points get the same noise, which the builder intersects by least squares",
                long.per_vanishing_point, long.length_px
            ),
            1,
        ),
    }
}

/// The report's title: the default run, a `--vp-edges long` run and runs of the views'
/// set-ups are told apart.
#[must_use]
pub fn title(config: &Config) -> &'static str {
    match (config.vp_edges, super::has_views(&config.setups)) {
        (VpEdges::Objects, false) => "Map accuracy under annotation noise (`vpmap eval`)",
        (VpEdges::Long(_), false) => {
            "Map accuracy under annotation noise, vanishing points from long edges (`vpmap eval --vp-edges long`)"
        }
        (VpEdges::Objects, true) => {
            "Map accuracy of the views real photos show: face-on boxes, hidden base corners, own yaw (`vpmap eval --experiments views`)"
        }
        (VpEdges::Long(_), true) => {
            "Map accuracy of the views real photos show, vanishing points from long edges (`vpmap eval --experiments views --vp-edges long`)"
        }
    }
}

/// A few lines for the console: per method and noise level, the centroid shift and the
/// overlap.
#[must_use]
pub fn headline(config: &Config, c: &Collected) -> String {
    let mut out = String::new();
    let shift = 0;
    let overlap = 2;
    for (m, method) in config.methods.iter().enumerate() {
        for (s, sigma) in config.sigmas.iter().enumerate() {
            let mut parts = Vec::new();
            for p in [Perspective::TwoPoint, Perspective::ThreePoint] {
                let g = Group::Perspective(p);
                let (Some(a), Some(b)) = (
                    c.summary(config, m, s, g, shift),
                    c.summary(config, m, s, g, overlap),
                ) else {
                    continue;
                };
                let r = c.refusals(config, m, s, g);
                let ellipse = c
                    .summary(config, m, s, g, COVERAGE_BASE)
                    .map(|x| format!(", in 95 % ellipse {:.1} %", 100.0 * x.mean))
                    .unwrap_or_default();
                parts.push(format!(
                    "{} centroid shift {} % [{} … {}], overlap {} % [{} … {}], refused {}/{}{ellipse}",
                    p.name().to_uppercase(),
                    fmt(a.median),
                    fmt(a.p5),
                    fmt(a.p95),
                    fmt(b.median),
                    fmt(b.p5),
                    fmt(b.p95),
                    r.refused(),
                    r.scenes
                ));
            }
            let _ = writeln!(
                out,
                "{method:>10} σ {:>4} px: {}",
                sigma_text(*sigma),
                parts.join("; ")
            );
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_long_edge_note_replaces_the_object_edge_sentence() {
        assert!(METHOD_NOTE.contains(OBJECT_EDGES_NOTE));
        assert_eq!(method_note(VpEdges::Objects), METHOD_NOTE);
        let long = method_note(VpEdges::Long(
            vpmap_metrology::synth::LongEdgeOptions::default(),
        ));
        assert!(!long.contains(OBJECT_EDGES_NOTE));
        assert!(long.contains("3 long straight edges of 600 px"), "{long}");
    }

    #[test]
    fn numbers_are_formatted_by_hand_rules() {
        assert_eq!(fmt(0.0), "0");
        assert_eq!(fmt(3.2e-12), "3e-12");
        assert_eq!(fmt(-12.345), "-12.35");
    }
}

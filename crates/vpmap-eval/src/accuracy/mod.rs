//! Map accuracy under annotation noise on synthetic scenes, as in the thesis's
//! section 6.1 (figures 6.8-6.13 for 2PP, 6.18-6.23 for 3PP).
//!
//! Every chosen experiment set-up ([`vpmap_metrology::eval::SETUPS`] by default; the views real
//! photos showed are [`vpmap_metrology::eval::VIEW_SETUPS`]) draws [`Config::trials`] scenes; each
//! scene is built with every method at every noise level and compared with its truth
//! ([`vpmap_metrology::eval::run_trial`]). Scenes run in parallel (rayon); each scene's seed
//! depends only on ([`Config::seed`], set-up, trial), so the files are the same for the same
//! arguments whatever the thread count. [`report()`] makes these files ([`Report::files`]):
//!
//! | file | what |
//! |---|---|
//! | `summary.json` | rows `{method, sigma, metric, median, p5, p95, min, max, q1, q3, mean, count, perspective, experiment, scenes, refused}`: per perspective (`experiment` null) and per set-up; the error-bar checks (`centroid_in_ellipse_95`, `length_within_2sd`, ...: 1 or 0 per object) have the share covered as `mean` |
//! | `summary.md` | the headline numbers at the true scale, the set-ups, refusals, the error bars' coverage, one table per metric beside the thesis's reported ranges, the camera's errors |
//! | `box_<metric>.svg`, `.png` | the thesis's box plots: one box per set-up and method, 2PP and 3PP side by side, at [`Config::plot_sigma`] |
//! | `objects.csv` | one row per object, noise level and method: every metric, and for the fit's objects whether the truth lies within the error bars and by how many standard deviations |
//! | `failures.csv` | one row per scene a builder refused: the reason's category and message |
//!
//! [`Config::vp_edges`] chooses the edges the vanishing points are fitted to: `objects` (the boxes' own
//! edges through their noisy corners, the default) or `long` (per vanishing point
//! a few straight room lines of a given length spread over the image, each
//! the image of a 3D line in the vanishing direction in front of the true camera, their end
//! points clicked with the same noise; [`vpmap_metrology::eval::VpEdges`]).

pub mod collect;
pub mod config;
pub mod files;
pub mod plot;
pub mod report;

use std::collections::BTreeMap;
use std::path::Path;
use std::time::Duration;

use rayon::prelude::*;
use vpmap_metrology::eval::{Trial, TrialOptions, run_trial_with};

use crate::error::Result;
use crate::output::OutputSet;
use crate::progress::Progress;
use crate::publish::relative_link;

pub use collect::Collected;
pub use config::{
    Config, DEFAULT_TRIALS, MAX_SIGMA_PX, Results, has_views, section_name, select_setups,
    sigmas_from_text,
};

/// Run every trial of every set-up, in parallel (rayon); one [`Progress::step`] per scene.
pub fn run_trials(config: &Config, progress: &dyn Progress) -> Results {
    let work: Vec<(usize, u64)> = (0..config.setups.len())
        .flat_map(|s| (0..config.trials).map(move |t| (s, t)))
        .collect();
    progress.start(work.len() as u64);
    let done: Vec<(usize, Trial)> = work
        .par_iter()
        .filter_map(|&(s, t)| {
            let setup = config.setups.get(s)?;
            let trial = run_trial_with(
                setup,
                config.seed,
                t,
                &config.sigmas,
                &config.methods,
                &TrialOptions {
                    vp_edges: config.vp_edges,
                },
            );
            progress.step();
            Some((s, trial))
        })
        .collect();
    progress.finish();
    let mut trials: Vec<Vec<Trial>> = vec![Vec::new(); config.setups.len()];
    for (s, trial) in done {
        if let Some(list) = trials.get_mut(s) {
            list.push(trial);
        }
    }
    Results { trials }
}

/// A run's report: its summaries and its files.
pub struct Report {
    /// The values and their summaries per method, noise level, set-up and metric.
    pub collected: Collected,
    /// `summary.json`, `objects.csv`, `failures.csv`, the box plots and `summary.md`.
    pub files: OutputSet,
    /// The box plots are SVG only: the system has no fonts to render their PNGs.
    pub svg_only: bool,
    /// Per metric, the file name of its box plot as `summary.md` links it.
    image_of: BTreeMap<&'static str, String>,
}

/// Summarise a run and make its files.
///
/// # Errors
/// When a plot cannot be drawn or rendered, or the summary cannot be serialised.
pub fn report(config: &Config, results: &Results) -> Result<Report> {
    let collected = collect::collect(config, results);
    let mut files = OutputSet::default();
    files.add("summary.json", files::summary_json(config, &collected)?);
    files.add("objects.csv", files::objects_csv(config, results));
    files.add("failures.csv", files::failures_csv(config, results));
    let plots = plot::box_plots(config, &collected)?;
    let mut image_of = BTreeMap::new();
    for p in &plots {
        files.add(&format!("{}.svg", p.stem), p.svg.clone());
        let link = if let Some(png) = &p.png {
            files.add(&format!("{}.png", p.stem), png.clone());
            format!("{}.png", p.stem)
        } else {
            format!("{}.svg", p.stem)
        };
        image_of.insert(p.metric, link);
    }
    let body = report::markdown(config, &collected, &image_of, "");
    files.add(
        "summary.md",
        format!("# {}\n\n{body}", report::title(config)),
    );
    Ok(Report {
        collected,
        files,
        svg_only: plots.iter().any(|p| p.png.is_none()),
        image_of,
    })
}

impl Report {
    /// The section to publish into the Markdown file `doc`: where, when and how it was
    /// measured (`command`, the command line; `elapsed`, the run's time), then the report with
    /// its image links pointing into the folder `out`.
    #[must_use]
    pub fn published(
        &self,
        config: &Config,
        doc: &Path,
        out: &Path,
        command: &str,
        elapsed: Duration,
    ) -> String {
        let folder = doc
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        let link = relative_link(folder, out);
        let prefix = if link == "." {
            String::new()
        } else {
            format!("{link}/")
        };
        let body = report::markdown(config, &self.collected, &self.image_of, &prefix);
        crate::publish::published(report::title(config), &body, elapsed, command)
    }

    /// A few lines for the console: per method and noise level, the centroid shift and the
    /// overlap.
    #[must_use]
    pub fn headline(&self, config: &Config) -> String {
        report::headline(config, &self.collected)
    }
}

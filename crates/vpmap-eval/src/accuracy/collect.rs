//! The values of a map-accuracy run gathered per method, noise level, set-up and metric
//! ([`Collected`]), the metrics' names and descriptions, and their summaries.

use std::collections::BTreeMap;

use vpmap_metrology::calibration::Perspective;
use vpmap_metrology::eval::{
    CAMERA_COVERAGE_METRICS, COVERAGE_METRICS, MapEvaluation, OBJECT_METRICS, SCENE_METRICS,
    TRUE_SCALE_SUFFIX,
};

use super::config::{Config, Results};
use crate::stats::Summary;

/// How a metric is shown, with the thesis's figures and reported ranges (quoted from
/// section 6.1.2 and 6.1.3 of the thesis) and, where it has one, the errata's number.
pub struct Described {
    /// Metric name (the `S_k` variant's).
    pub name: &'static str,
    /// The thesis's caption of its box plot.
    pub title: &'static str,
    /// Unit shown on the axis.
    pub unit: &'static str,
    /// The value of a perfect reconstruction.
    pub perfect: f64,
    /// The 2PP and 3PP figures.
    pub figures: [&'static str; 2],
    /// What the thesis says about the 2PP and 3PP ranges.
    pub thesis: [&'static str; 2],
    /// What `../shared/thesis/errata.md` ("Under noise") measured, if anything.
    pub errata: &'static str,
}

/// The per-object metrics with the thesis's plots (and the height error, which it has not).
pub const DESCRIBED: [Described; 7] = [
    Described {
        name: "centroid_shift_pct",
        title: "percentage deviation of centroids",
        unit: "%",
        perfect: 0.0,
        figures: ["6.8", "6.18"],
        thesis: [
            "\"Worst case error in centroid shift ... is within ±9.5%\" (said of experiment 1)",
            "\"Worst case error in centroid shift ... is within +6%\"",
        ],
        errata: "at 1 px, 2PP: 95th percentile 5.2 % (side view) vs 3.1 % (projective)",
    },
    Described {
        name: "centroid_distance_pct",
        title: "percentage error in distances to centroids",
        unit: "%",
        perfect: 0.0,
        figures: ["6.9", "6.19"],
        thesis: [
            "\"the errors are within the range of ±5%\"",
            "\"the errors are within the range of ±3%\"",
        ],
        errata: "",
    },
    Described {
        name: "area_overlap_pct",
        title: "percentage area of overlap",
        unit: "%",
        perfect: 100.0,
        figures: ["6.10", "6.20"],
        thesis: [
            "\"the worst case mismatch was around 55% while the best case match showing the correct overlap was around 95%\"",
            "\"the worst case mismatch was around 55% while the best case match showing the correct overlap was around 95%\"",
        ],
        errata: "at 1 px: median about 92 % (2PP), 87-91 % (3PP 10-30°), 83 % (3PP 45°)",
    },
    Described {
        name: "area_error_pct",
        title: "percentage error in area measurement",
        unit: "%",
        perfect: 0.0,
        figures: ["6.11", "6.21"],
        thesis: ["\"within ±9%\"", "\"within ±25%\""],
        errata: "",
    },
    Described {
        name: "pose_error_deg",
        title: "error in angular pose of the centroids",
        unit: "deg",
        perfect: 0.0,
        figures: ["6.12", "6.22"],
        thesis: [
            "\"within ... ±6%\" (the thesis writes % for this angle, defined in degrees)",
            "\"within ... ±4%\" (% as printed; the metric is in degrees)",
        ],
        errata: "",
    },
    Described {
        name: "skew_error_deg",
        title: "error in skew angles",
        unit: "deg",
        perfect: 0.0,
        figures: ["6.13", "6.23"],
        thesis: [
            "\"within ... ±20%\" (% as printed; the metric is in degrees)",
            "\"within ... ±20%\" (% as printed; the metric is in degrees)",
        ],
        errata: "the side-view method has smaller skew errors than the projective form, its rectangle sides following the vanishing directions",
    },
    Described {
        name: "height_error_pct",
        title: "percentage error in heights",
        unit: "%",
        perfect: 0.0,
        figures: ["-", "-"],
        thesis: [
            "not plotted; section 6.1.2: \"percentage errors for some of the object's parameters reached around 5%, especially for ground height and d estimations\"",
            "not plotted",
        ],
        errata: "",
    },
];

/// The error-bar values per object (method `fit`), after [`COVERAGE_METRICS`] (1 inside,
/// 0 outside): the squared Mahalanobis distance of the true centroid and the standardised
/// errors of length, breadth, height and yaw.
pub const ERROR_BAR_METRICS: [&str; 5] = [
    "centroid_mahalanobis_sq",
    "length_z",
    "breadth_z",
    "height_z",
    "yaw_z",
];

/// The camera's error-bar values per scene (method `fit`), after [`CAMERA_COVERAGE_METRICS`]
/// (1 within `±2 sd`, 0 outside): the standardised errors of focal length, pitch, roll and
/// the principal point's two coordinates.
pub const CAMERA_ERROR_BAR_METRICS: [&str; 5] = [
    "focal_z",
    "pitch_z",
    "roll_z",
    "principal_point_x_z",
    "principal_point_y_z",
];

/// Every metric name, in the order of the value columns: the `S_k` object metrics, their
/// true-scale variants, the scene metrics, `scale_factor`, then the error-bar checks
/// ([`COVERAGE_METRICS`], 1 or 0) and values ([`ERROR_BAR_METRICS`]), and the camera's
/// ([`CAMERA_COVERAGE_METRICS`], [`CAMERA_ERROR_BAR_METRICS`]), empty without error bars.
#[must_use]
pub fn metric_names() -> Vec<String> {
    OBJECT_METRICS
        .iter()
        .map(|m| (*m).to_owned())
        .chain(
            OBJECT_METRICS
                .iter()
                .map(|m| format!("{m}{TRUE_SCALE_SUFFIX}")),
        )
        .chain(SCENE_METRICS.iter().map(|m| (*m).to_owned()))
        .chain(std::iter::once("scale_factor".to_owned()))
        .chain(COVERAGE_METRICS.iter().map(|m| (*m).to_owned()))
        .chain(ERROR_BAR_METRICS.iter().map(|m| (*m).to_owned()))
        .chain(CAMERA_COVERAGE_METRICS.iter().map(|m| (*m).to_owned()))
        .chain(CAMERA_ERROR_BAR_METRICS.iter().map(|m| (*m).to_owned()))
        .collect()
}

/// Index of the first scene metric in [`metric_names`].
pub(super) const SCENE_BASE: usize = 2 * OBJECT_METRICS.len();

/// Index of the first error-bar check in [`metric_names`] (after the scene metrics and
/// `scale_factor`).
pub(super) const COVERAGE_BASE: usize = SCENE_BASE + SCENE_METRICS.len() + 1;

/// Index of the first camera error-bar check in [`metric_names`].
pub(super) const CAMERA_COVERAGE_BASE: usize =
    COVERAGE_BASE + COVERAGE_METRICS.len() + ERROR_BAR_METRICS.len();

/// Whether the metric at index `k` of [`metric_names`] is one value per scene.
pub(super) fn per_scene(k: usize) -> bool {
    (SCENE_BASE..COVERAGE_BASE).contains(&k) || k >= CAMERA_COVERAGE_BASE
}

/// Every value of one scene's evaluation in [`metric_names`] order: per object the object
/// metrics, once per scene the scene metrics.
pub(super) fn object_row(ev: &MapEvaluation, object: usize) -> Vec<f64> {
    let Some(o) = ev.objects.get(object) else {
        return Vec::new();
    };
    let flag = |b: Option<bool>| b.map_or(f64::NAN, |b| if b { 1.0 } else { 0.0 });
    let (within, bars) = o.coverage.map_or(([f64::NAN; 5], [f64::NAN; 5]), |c| {
        (
            c.within().map(flag),
            [
                c.centroid_mahalanobis_sq,
                c.length_z.unwrap_or(f64::NAN),
                c.breadth_z.unwrap_or(f64::NAN),
                c.height_z.unwrap_or(f64::NAN),
                c.yaw_z.unwrap_or(f64::NAN),
            ],
        )
    });
    let (camera_within, camera_bars) =
        ev.camera_coverage
            .map_or(([f64::NAN; 5], [f64::NAN; 5]), |c| {
                (
                    c.within().map(flag),
                    c.values().map(|z| z.unwrap_or(f64::NAN)),
                )
            });
    o.sk.values()
        .into_iter()
        .chain(o.true_scale.values())
        .chain(ev.scene_values())
        .chain(std::iter::once(ev.scale_factor))
        .chain(within)
        .chain(bars)
        .chain(camera_within)
        .chain(camera_bars)
        .collect()
}

/// Refusals of one (method, noise level, set-up).
#[derive(Default, Clone)]
pub struct Refusals {
    /// Scenes attempted.
    pub scenes: usize,
    /// Per category, how many were refused.
    pub by_category: BTreeMap<&'static str, usize>,
}

impl Refusals {
    /// Scenes refused, in all categories.
    #[must_use]
    pub fn refused(&self) -> usize {
        self.by_category.values().sum()
    }

    /// Count `other`'s scenes and refusals too.
    pub fn add(&mut self, other: &Refusals) {
        self.scenes += other.scenes;
        for (k, v) in &other.by_category {
            *self.by_category.entry(k).or_default() += v;
        }
    }
}

/// The values of a run, by method, noise level, set-up and metric.
pub struct Collected {
    /// [`metric_names`].
    pub metrics: Vec<String>,
    values: Vec<Vec<f64>>,
    refusals: Vec<Refusals>,
    setups: usize,
    sigmas: usize,
}

/// Which scenes a summary covers.
#[derive(Clone, Copy)]
pub enum Group {
    /// Every chosen set-up of one perspective.
    Perspective(Perspective),
    /// One set-up (index into the chosen set-ups).
    Experiment(usize),
}

impl Collected {
    fn cell(&self, method: usize, sigma: usize, setup: usize) -> usize {
        (method * self.sigmas + sigma) * self.setups + setup
    }

    fn members(config: &Config, group: Group) -> Vec<usize> {
        (0..config.setups.len())
            .filter(|&e| match group {
                Group::Perspective(p) => config.setups[e].perspective == p,
                Group::Experiment(x) => x == e,
            })
            .collect()
    }

    /// The values of one metric over a group.
    #[must_use]
    pub fn values(
        &self,
        config: &Config,
        method: usize,
        sigma: usize,
        group: Group,
        metric: usize,
    ) -> Vec<f64> {
        Self::members(config, group)
            .into_iter()
            .flat_map(|e| {
                let cell = self.cell(method, sigma, e);
                self.values[cell * self.metrics.len() + metric]
                    .iter()
                    .copied()
            })
            .collect()
    }

    /// Summary of one metric over a group (`None` without values).
    #[must_use]
    pub fn summary(
        &self,
        config: &Config,
        method: usize,
        sigma: usize,
        group: Group,
        metric: usize,
    ) -> Option<Summary> {
        Summary::of(&self.values(config, method, sigma, group, metric))
    }

    /// Refusals over a group.
    #[must_use]
    pub fn refusals(&self, config: &Config, method: usize, sigma: usize, group: Group) -> Refusals {
        let mut total = Refusals::default();
        for e in Self::members(config, group) {
            total.add(&self.refusals[self.cell(method, sigma, e)]);
        }
        total
    }
}

/// Gather every value and refusal of a run.
#[must_use]
pub fn collect(config: &Config, results: &Results) -> Collected {
    let metrics = metric_names();
    let (nm, ns, ne) = (
        config.methods.len(),
        config.sigmas.len(),
        config.setups.len(),
    );
    let mut values = vec![Vec::new(); nm * ns * ne * metrics.len()];
    let mut refusals = vec![Refusals::default(); nm * ns * ne];
    for (e, trials) in results.trials.iter().enumerate() {
        for trial in trials {
            for o in &trial.outcomes {
                let (Some(m), Some(s)) = (
                    config.methods.iter().position(|x| *x == o.method),
                    config
                        .sigmas
                        .iter()
                        .position(|x| x.to_bits() == o.sigma_px.to_bits()),
                ) else {
                    continue;
                };
                let cell = (m * ns + s) * ne + e;
                refusals[cell].scenes += 1;
                match &o.result {
                    Ok(ev) => {
                        for i in 0..ev.objects.len() {
                            for (k, v) in object_row(ev, i).into_iter().enumerate() {
                                // Scene metrics once per scene, not once per object.
                                if !per_scene(k) || i == 0 {
                                    values[cell * metrics.len() + k].push(v);
                                }
                            }
                        }
                    }
                    Err(f) => *refusals[cell].by_category.entry(f.category).or_default() += 1,
                }
            }
        }
    }
    Collected {
        metrics,
        values,
        refusals,
        setups: ne,
        sigmas: ns,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_described_metric_is_an_object_metric_in_order() {
        for (d, m) in DESCRIBED.iter().zip(OBJECT_METRICS) {
            assert_eq!(d.name, m);
        }
        assert_eq!(metric_names()[SCENE_BASE], SCENE_METRICS[0]);
        assert_eq!(metric_names()[COVERAGE_BASE], COVERAGE_METRICS[0]);
        assert_eq!(
            metric_names()[CAMERA_COVERAGE_BASE],
            CAMERA_COVERAGE_METRICS[0]
        );
        assert!(per_scene(CAMERA_COVERAGE_BASE) && !per_scene(COVERAGE_BASE));
    }
}

//! What a map-accuracy run measures ([`Config`]: trials, seed, noise levels, methods, the
//! set-ups chosen by name with [`select_setups`], plots, vanishing-point edges), which section
//! of a results file it publishes into, and its raw results ([`Results`]).

use vpmap_metrology::eval::{SETUPS, Setup, Trial, VIEW_SETUPS, VpEdges};
use vpmap_metrology::reconstruct::Method;
use vpmap_metrology::synth::Annotation;

use crate::error::{Result, bail};

/// Trials per set-up by default: 200 scenes x about 4 objects per box of the plots; the
/// whole default run (three methods) takes about half a minute on two cores (see the
/// report's timing).
pub const DEFAULT_TRIALS: u64 = 200;

/// What to measure: the options of a map-accuracy run.
#[derive(Clone, Debug)]
pub struct Config {
    /// Trials (random scenes) per set-up.
    pub trials: u64,
    /// The run's seed; the same seed and options give the same files.
    pub seed: u64,
    /// Noise levels (standard deviation of every annotated point), pixels, ascending.
    pub sigmas: Vec<f64>,
    /// Methods in the order given.
    pub methods: Vec<Method>,
    /// The set-ups, in table order.
    pub setups: Vec<&'static Setup>,
    /// The box plots' noise level, pixels; one of [`Self::sigmas`].
    pub plot_sigma: f64,
    /// The edges the vanishing points are fitted to.
    pub vp_edges: VpEdges,
}

impl Default for Config {
    /// `vpmap eval`'s defaults: 200 trials, seed 0, noise 0, 0.5, 1, 2 and 4 px, the three
    /// methods (side view, projective, fit), the seventeen set-ups of [`SETUPS`], plots at
    /// 1 px, the objects' own edges.
    fn default() -> Self {
        Self {
            trials: DEFAULT_TRIALS,
            seed: 0,
            sigmas: vec![0.0, 0.5, 1.0, 2.0, 4.0],
            methods: vec![Method::Sideview, Method::Projective, Method::Fit],
            setups: SETUPS.iter().collect(),
            plot_sigma: 1.0,
            vp_edges: VpEdges::Objects,
        }
    }
}

/// Every trial of every chosen set-up, in (set-up, trial) order.
pub struct Results {
    /// Per chosen set-up (index into [`Config::setups`]), its trials in order.
    pub trials: Vec<Vec<Trial>>,
}

/// Whether a run includes set-ups of the views real photos showed
/// ([`vpmap_metrology::eval::VIEW_SETUPS`]: another annotation than the thesis's).
#[must_use]
pub fn has_views(setups: &[&Setup]) -> bool {
    setups.iter().any(|s| s.annotation != Annotation::Thesis)
}

/// The section of a results file a run publishes into: `eval` for the objects' own
/// vanishing-point edges, `eval-long-edges` for long edges, `eval-views` and
/// `eval-views-long-edges` for runs with the views' set-ups, so they can stand side by side.
#[must_use]
pub fn section_name(vp_edges: &VpEdges, setups: &[&Setup]) -> &'static str {
    match (vp_edges, has_views(setups)) {
        (VpEdges::Objects, false) => "eval",
        (VpEdges::Long(_), false) => "eval-long-edges",
        (VpEdges::Objects, true) => "eval-views",
        (VpEdges::Long(_), true) => "eval-views-long-edges",
    }
}

/// Largest annotation noise a run accepts, pixels (1 sigma per coordinate).
pub const MAX_SIGMA_PX: f64 = 100.0;

/// The noise levels of a comma-separated list of pixels (`vpmap eval --sigma 0,0.5,1,2`),
/// sorted; `-0` reads as 0.
///
/// # Errors
/// [`crate::EvalError::Invalid`] for a part that is not a number (`"x" is not a number; give
/// pixels such as 0,0.5,1,2,4`), outside 0 to [`MAX_SIGMA_PX`], or given twice.
///
/// # Example
/// ```
/// use vpmap_eval::accuracy::sigmas_from_text;
/// assert_eq!(sigmas_from_text(" 2, 0,1").unwrap(), vec![0.0, 1.0, 2.0]);
/// assert_eq!(sigmas_from_text("1,1").unwrap_err().to_string(), "1 is given twice");
/// ```
pub fn sigmas_from_text(text: &str) -> Result<Vec<f64>> {
    let mut sigmas = Vec::new();
    for part in text.split(',') {
        let part = part.trim();
        let Ok(v) = part.parse::<f64>() else {
            bail!("{part:?} is not a number; give pixels such as 0,0.5,1,2,4");
        };
        if !(v.is_finite() && (0.0..=MAX_SIGMA_PX).contains(&v)) {
            bail!(
                "{} must be a finite number of pixels from 0 to {MAX_SIGMA_PX}",
                vpmap_files::num(v)
            );
        }
        // `-0` is 0.
        sigmas.push(v + 0.0);
    }
    sigmas.sort_by(f64::total_cmp);
    if let Some(w) = sigmas.windows(2).find(|w| w[0].to_bits() == w[1].to_bits()) {
        bail!("{} is given twice", vpmap_files::num(w[0]));
    }
    Ok(sigmas)
}

/// The set-ups a comma-separated list of names chooses, in table order (the thesis's
/// seventeen of [`SETUPS`], then the views' six of [`VIEW_SETUPS`]): `all` (the seventeen),
/// `2pp` or `3pp` (theirs of that perspective), `views` (the six), or set-up names
/// (`2pp-1`, `3pp-yaw`; any case, spaces around them ignored).
///
/// # Errors
/// [`crate::EvalError::Invalid`] for a name that chooses nothing: `"4pp" is not a set-up; use
/// all, 2pp, 3pp, views or names among 2pp-1, ...`.
///
/// # Example
/// ```
/// use vpmap_eval::accuracy::select_setups;
/// assert_eq!(select_setups("3pp").unwrap().len(), 8);
/// assert_eq!(select_setups("3pp-2, 2pp-1").unwrap()[0].name, "2pp-1");
/// ```
pub fn select_setups(text: &str) -> Result<Vec<&'static Setup>> {
    // The thesis's seventeen, then the views' six; `all`, `2pp` and `3pp` choose among the
    // seventeen, `views` the six.
    let every: Vec<(&'static Setup, bool)> = SETUPS
        .iter()
        .map(|s| (s, false))
        .chain(VIEW_SETUPS.iter().map(|s| (s, true)))
        .collect();
    let mut chosen = vec![false; every.len()];
    for part in text.split(',') {
        let part = part.trim().to_ascii_lowercase();
        let mut matched = false;
        for ((setup, view), c) in every.iter().zip(chosen.iter_mut()) {
            let hit = match part.as_str() {
                "all" => !view,
                "views" => *view,
                "2pp" | "3pp" => !view && setup.name.starts_with(&part),
                name => setup.name == name,
            };
            if hit {
                *c = true;
                matched = true;
            }
        }
        if !matched {
            let names: Vec<&str> = every.iter().map(|(s, _)| s.name).collect();
            bail!(
                "{part:?} is not a set-up; use all, 2pp, 3pp, views or names among {}",
                names.join(", ")
            );
        }
    }
    Ok(every
        .into_iter()
        .zip(chosen)
        .filter_map(|((s, _), c)| c.then_some(s))
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn set_ups_are_chosen_by_name_group_or_all() {
        assert_eq!(select_setups("2pp").unwrap().len(), 9);
        assert_eq!(select_setups("all").unwrap().len(), 17);
        let views = select_setups("views").unwrap();
        assert_eq!(views.len(), 6);
        assert!(
            views
                .iter()
                .all(|s| s.name.contains('-') && !s.name.ends_with(char::is_numeric))
        );
        assert_eq!(select_setups("3pp-yaw,2pp-1").unwrap()[1].name, "3pp-yaw");
        assert_eq!(select_setups("all,views").unwrap().len(), 23);
        assert_eq!(select_setups("3pp-2,2pp-1").unwrap()[0].name, "2pp-1");
        let e = select_setups("4pp").unwrap_err().to_string();
        assert!(
            e.starts_with(
                "\"4pp\" is not a set-up; use all, 2pp, 3pp, views or names among 2pp-1, "
            ),
            "{e}"
        );
    }
}

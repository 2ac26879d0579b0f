//! The intrinsics' priors tested against the photo's evidence: a photo cropped off its centre
//! (or after its EXIF focal length was written) is not built as if it were whole.
//!
//! `vpmap detect` writes the principal point as a prior at the image centre with a standard
//! deviation of 1.5 % of the diagonal (`principal_point_sd_px`), and an EXIF focal length as a
//! prior of 4 % (`focal_px` with `focal_sd_px`): whole photos of real cameras have them there. A
//! photo cropped off its centre does not: with the priors as given the fit holds the principal
//! point near the crop's centre (and the focal length at the whole frame's EXIF value scaled to
//! the crop's diagonal), bends the pitch around them, and reports error bars as tight as for a
//! whole photo (SUN RGB-D's photos cropped 50-75 px off: boxes 19-89 cm off at a Mahalanobis
//! distance squared up to 47).
//!
//! The test: the fit again with every soft prior widened, the principal point's to
//! [`CROPPED_PRINCIPAL_POINT_SD_DIAGONALS`] of the diagonal (anywhere in the photo, as a crop
//! can put it) and the focal length's to [`WIDENED_FOCAL_SD_FRACTION`] of itself, from the
//! fit's answer ([`crate::fit::Fitted`]'s `cost_with_priors_widened`). Its negative
//! log-likelihood `J = cost / sigma^2` (the priors' terms included; weighed as the lens's
//! profile weighs it when the click noise is estimated, `super::lens_refine`) drops by
//!
//! `J(given) - J(widened) ~ (p - c)^T (S + S0)^-1 (p - c)`
//!
//! to first order (`p` where the evidence alone puts the intrinsics with covariance `S`, `c` the
//! priors' centres, `S0` their covariance): a prior-predictive check of the given priors, a
//! chi-square with as many degrees of freedom as the priors tested (2 for the principal point,
//! 1 for the focal length) when they are right. Above its 99 % point the priors are rejected;
//! with both, nested likelihood-ratio tests (each widening against the other alone, at 99 %)
//! keep only the widening the evidence needs (the better single one when either explains it).
//! The map is then built again, from scratch, with the rejected priors widened, and says so.
//! The 99 % point rather than the lens test's 95 % because a widened prior costs a whole photo
//! precision: one in a hundred whole photos pays it. A focal length's prior of less than
//! [`SOFT_FOCAL_SD_FRACTION`] of itself is a calibration (`vpmap detect --focal` writes 0.1 %)
//! and is not tested.
//!
//! References: M. Evans and H. Moshonov, "Checking for prior-data conflict", Bayesian Analysis
//! 1(4), 2006.

use super::lens_refine::{ClickNoise, weigh};
use crate::fit::Fitted;
use crate::fit::prior::{IntrinsicsPriors, PriorRefit};
use crate::interrupt::Interrupt;
use crate::room::RoomFitted;
use crate::scene::Scene;

/// The chi-square quantiles at 99 % of one, two and three degrees of freedom: how much better
/// the photo's evidence must fit with the focal length's prior, the principal point's, or both
/// widened for the map to widen them.
pub const PRIORS_REJECTED_CHI2: [f64; 3] = [
    6.634_896_601_021_214,
    9.210_340_371_976_184,
    11.344_866_730_144_373,
];

/// The standard deviation of the widened prior on the principal point, as a fraction of the
/// image diagonal (each coordinate): about a uniform spread over a 4:3 photo (its width over
/// the square root of 12 is 0.23 of the diagonal, its height's 0.17), as a crop can put it.
pub const CROPPED_PRINCIPAL_POINT_SD_DIAGONALS: f64 = 0.2;

/// The standard deviation of the widened prior on the focal length, as a fraction of it.
pub const WIDENED_FOCAL_SD_FRACTION: f64 = 1.0;

/// The least standard deviation of a focal length's prior that is tested, as a fraction of
/// it: a narrower one is a calibration.
pub const SOFT_FOCAL_SD_FRACTION: f64 = 0.01;

/// Priors the photo's evidence rejected.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct WidenedPriors {
    /// The priors as given.
    pub given: IntrinsicsPriors,
    /// The principal point's widened standard deviation, pixels (`None`: kept).
    pub principal_point_sd_px: Option<f64>,
    /// The focal length's widened standard deviation, pixels (`None`: kept).
    pub focal_sd_px: Option<f64>,
    /// Where the fit with them widened puts the intrinsics.
    pub found: PriorRefit,
    /// `J(given) - J(widened)`: how much better the evidence fits.
    pub chi2_drop: f64,
}

impl WidenedPriors {
    /// Degrees of freedom of the priors widened.
    fn dof(&self) -> usize {
        2 * usize::from(self.principal_point_sd_px.is_some())
            + usize::from(self.focal_sd_px.is_some())
    }
}

fn rejected_chi2(dof: usize) -> f64 {
    PRIORS_REJECTED_CHI2[dof.clamp(1, 3) - 1]
}

/// The test of the module documentation for one photo's `priors` (`diagonal_px` its image's),
/// `j0` the fit's `J`, `j` a refit's `J` from its cost, `refit` the fit again with the
/// principal point's and the focal length's priors widened to the standard deviations given.
fn test_priors(
    priors: IntrinsicsPriors,
    diagonal_px: f64,
    j0: f64,
    j: impl Fn(f64) -> f64,
    refit: impl Fn(Option<f64>, Option<f64>) -> Option<PriorRefit>,
) -> Option<WidenedPriors> {
    let wide_pp = CROPPED_PRINCIPAL_POINT_SD_DIAGONALS * diagonal_px;
    let less = |a: f64, b: f64| a.partial_cmp(&b) == Some(std::cmp::Ordering::Less);
    let pp_sd = priors
        .principal_point
        .filter(|(_, sd)| less(*sd, wide_pp))
        .map(|_| wide_pp);
    let focal_sd = priors
        .focal
        .filter(|(f, sd)| {
            !less(*sd, SOFT_FOCAL_SD_FRACTION * f) && less(*sd, WIDENED_FOCAL_SD_FRACTION * f)
        })
        .map(|(f, _)| WIDENED_FOCAL_SD_FRACTION * f);
    if pp_sd.is_none() && focal_sd.is_none() {
        return None;
    }
    let widened = |pp: Option<f64>, focal: Option<f64>, found: PriorRefit| WidenedPriors {
        given: priors,
        principal_point_sd_px: pp,
        focal_sd_px: focal,
        found,
        chi2_drop: j0 - j(found.cost),
    };
    // A NaN drop is no evidence against the priors.
    let rejects = |w: &WidenedPriors| w.chi2_drop > rejected_chi2(w.dof());
    let both = widened(pp_sd, focal_sd, refit(pp_sd, focal_sd)?);
    if !rejects(&both) {
        return None;
    }
    if pp_sd.is_none() || focal_sd.is_none() {
        return Some(both);
    }
    // Both priors: is each widening needed beyond the other alone?
    let pp_only = refit(pp_sd, None).map(|r| widened(pp_sd, None, r));
    let focal_only = refit(None, focal_sd).map(|r| widened(None, focal_sd, r));
    let jb = j(both.found.cost);
    let beyond = |alone: &Option<WidenedPriors>, dof: usize| {
        alone
            .as_ref()
            .is_none_or(|a| j(a.found.cost) - jb > rejected_chi2(dof))
    };
    let (need_pp, need_focal) = (beyond(&focal_only, 2), beyond(&pp_only, 1));
    let single = match (need_pp, need_focal) {
        (true, true) => None,
        (true, false) => pp_only,
        (false, true) => focal_only,
        (false, false) => [pp_only, focal_only]
            .into_iter()
            .flatten()
            .min_by(|a, b| j(a.found.cost).total_cmp(&j(b.found.cost))),
    };
    Some(single.filter(rejects).unwrap_or(both))
}

/// The widened priors when `fitted` (the fit of `scene`, a pinhole photo) rejects its
/// intrinsics' priors (see the module documentation); `None` when it does not, when it has no
/// priors to test, or when the refit fails.
pub(super) fn test_photo_priors(
    scene: &Scene,
    fitted: &Fitted,
    noise: ClickNoise,
    interrupt: &Interrupt,
) -> Option<WidenedPriors> {
    let m = fitted.problem_residual_count() as f64;
    test_priors(
        fitted.intrinsics_priors(),
        scene.image.diagonal(),
        weigh(noise, m, fitted.cost()),
        |cost| weigh(noise, m, cost),
        |pp, focal| fitted.cost_with_priors_widened(pp, focal, interrupt),
    )
}

/// For each photo of a room with priors on its intrinsics, the widened ones when the joint fit
/// rejects them ([`test_photo_priors`] for one photo of the joint fit: the room refitted with
/// that photo's priors widened, every placement as chosen, the other photos' priors as given):
/// `(photo, widened)`. `scene` is the room the fit was of.
pub(super) fn test_room_priors(
    scene: &Scene,
    fitted: &RoomFitted,
    noise: ClickNoise,
    interrupt: &Interrupt,
) -> Vec<(usize, WidenedPriors)> {
    let m = fitted.problem_residual_count() as f64;
    let j0 = weigh(noise, m, fitted.cost());
    scene
        .photos()
        .enumerate()
        .filter_map(|(n, photo)| {
            test_priors(
                fitted.intrinsics_priors(n),
                photo.image.diagonal(),
                j0,
                |cost| weigh(noise, m, cost),
                |pp, focal| fitted.cost_with_priors_widened(n, pp, focal, interrupt),
            )
            .map(|w| (n, w))
        })
        .collect()
}

/// `scene` (a photo of a room, or a single photo) with the priors `w` widened.
pub(super) fn widen(scene: &mut Scene, w: &WidenedPriors) {
    if let Some(sd) = w.principal_point_sd_px {
        scene.principal_point_sd_px = Some(sd);
    }
    if let Some(sd) = w.focal_sd_px {
        scene.focal_sd_px = Some(sd);
    }
}

/// The warning that priors were rejected but the fit with them widened failed (`why`), so the
/// map keeps them: `whose` is "the photo's" or "photo 2's".
pub(super) fn priors_kept_warning(
    whose: &str,
    w: &WidenedPriors,
    why: &crate::MetrologyError,
) -> String {
    format!(
        "{whose} edges and clicks reject the scene's priors on the intrinsics (a chi-square of {:.1} over {:.2}), but the fit with them widened fails ({why}): the map keeps them, and its error bars may be too tight",
        w.chi2_drop,
        rejected_chi2(w.dof())
    )
}

/// The warning that priors were widened: `whose` is "the photo's" or "photo 2's".
pub(super) fn priors_warning(whose: &str, w: &WidenedPriors) -> String {
    let mut found = Vec::new();
    let mut widths = Vec::new();
    if let (Some(sd), Some((c, s0))) = (w.principal_point_sd_px, w.given.principal_point) {
        let p = w.found.principal_point_px;
        found.push(format!(
            "the principal point at ({:.0}, {:.0}), {:.0} px from where the scene's prior holds it, ({:.0}, {:.0}) +- {s0:.1} px",
            p[0],
            p[1],
            (p[0] - c[0]).hypot(p[1] - c[1]),
            c[0],
            c[1]
        ));
        widths.push(format!("+- {sd:.0} px for the principal point"));
    }
    if let (Some(sd), Some((f0, s0))) = (w.focal_sd_px, w.given.focal) {
        let f = w.found.focal_px;
        found.push(format!(
            "the focal length at {f:.0} px, {:.0} % from the scene's prior {f0:.0} +- {s0:.0} px",
            100.0 * (f - f0).abs() / f0
        ));
        widths.push(format!("+- {sd:.0} px for the focal length"));
    }
    let dof = w.dof();
    format!(
        "{whose} edges and clicks put {}: better by a chi-square of {:.1} (over {:.2}, the 99 % point of {} degree{} of freedom), as in a photo cropped off its centre or after its EXIF focal length was written, so the map is built with {} widened to {}",
        found.join(" and "),
        w.chi2_drop,
        rejected_chi2(dof),
        ["one", "two", "three"][dof.clamp(1, 3) - 1],
        if dof == 1 { "" } else { "s" },
        if found.len() == 1 {
            "that prior"
        } else {
            "those priors"
        },
        widths.join(" and ")
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    const DIAGONAL: f64 = 1000.0;

    fn priors(pp: bool, focal_sd_fraction: Option<f64>) -> IntrinsicsPriors {
        IntrinsicsPriors {
            principal_point: pp.then_some(([400.0, 300.0], 15.0)),
            focal: focal_sd_fraction.map(|s| (800.0, s * 800.0)),
        }
    }

    /// The test with `J` of the fit 100 and of each refit as `j_of(pp widened, focal widened)`
    /// (`J` = cost here); which priors it widens, if any.
    fn widened_by(
        priors: IntrinsicsPriors,
        j_of: impl Fn(bool, bool) -> f64,
    ) -> Option<(bool, bool)> {
        test_priors(
            priors,
            DIAGONAL,
            100.0,
            |cost| cost,
            |pp, focal| {
                Some(PriorRefit {
                    cost: j_of(pp.is_some(), focal.is_some()),
                    principal_point_px: [0.0; 2],
                    focal_px: 0.0,
                })
            },
        )
        .map(|w| (w.principal_point_sd_px.is_some(), w.focal_sd_px.is_some()))
    }

    #[test]
    fn priors_are_widened_only_beyond_the_99_percent_point_of_their_degrees_of_freedom() {
        // The principal point alone: two degrees of freedom, 9.21.
        assert_eq!(widened_by(priors(true, None), |_, _| 91.0), None);
        assert_eq!(
            widened_by(priors(true, None), |_, _| 90.0),
            Some((true, false))
        );
        // The focal length alone: one, 6.63.
        assert_eq!(widened_by(priors(false, Some(0.04)), |_, _| 94.0), None);
        assert_eq!(
            widened_by(priors(false, Some(0.04)), |_, _| 93.0),
            Some((false, true))
        );
        // A drop that is no number is no evidence.
        assert_eq!(widened_by(priors(true, None), |_, _| f64::NAN), None);
    }

    #[test]
    fn a_calibrated_focal_length_or_a_prior_already_wide_is_not_tested() {
        // 0.1 % (a calibration): only the principal point is tested.
        assert_eq!(
            widened_by(priors(true, Some(0.001)), |pp, focal| {
                assert!(!focal, "a calibrated focal length was widened");
                if pp { 50.0 } else { 100.0 }
            }),
            Some((true, false))
        );
        assert_eq!(widened_by(priors(false, Some(0.001)), |_, _| 0.0), None);
        // A principal point prior as wide as the widened one.
        let wide = IntrinsicsPriors {
            principal_point: Some(([400.0, 300.0], 0.2 * DIAGONAL)),
            focal: None,
        };
        assert_eq!(widened_by(wide, |_, _| 0.0), None);
    }

    #[test]
    fn with_both_priors_nested_tests_keep_the_widening_the_evidence_needs() {
        // Only the principal point is wrong: widening the focal length alone barely helps.
        assert_eq!(
            widened_by(priors(true, Some(0.04)), |pp, focal| match (pp, focal) {
                (true, true) => 80.0,
                (true, false) => 81.0,
                _ => 99.0,
            }),
            Some((true, false))
        );
        // Only the focal length is wrong.
        assert_eq!(
            widened_by(priors(true, Some(0.04)), |pp, focal| match (pp, focal) {
                (true, true) => 80.0,
                (false, true) => 80.5,
                _ => 99.0,
            }),
            Some((false, true))
        );
        // Both are wrong: each alone leaves much of the drop.
        assert_eq!(
            widened_by(priors(true, Some(0.04)), |pp, focal| match (pp, focal) {
                (true, true) => 60.0,
                (true, false) => 80.0,
                (false, true) => 85.0,
                _ => 100.0,
            }),
            Some((true, true))
        );
        // Either alone explains it: the better one.
        assert_eq!(
            widened_by(priors(true, Some(0.04)), |pp, focal| match (pp, focal) {
                (true, true) => 80.0,
                (true, false) => 82.0,
                (false, true) => 81.0,
                _ => 100.0,
            }),
            Some((false, true))
        );
        // Jointly rejected (3 dof, 11.34) but no single widening rejects on its own: both.
        assert_eq!(
            widened_by(priors(true, Some(0.04)), |pp, focal| match (pp, focal) {
                (true, true) => 88.0,
                (true, false) => 92.0,
                (false, true) => 94.0,
                _ => 100.0,
            }),
            Some((true, true))
        );
    }
}

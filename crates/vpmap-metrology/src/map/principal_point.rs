//! The principal point's prior tested against the photo's evidence: a photo cropped off its
//! centre is not built as if it were whole.
//!
//! `vpmap detect` writes the principal point as a prior at the image centre with a standard
//! deviation of 1.5 % of the diagonal (`principal_point_sd_px`): whole photos of real cameras
//! have it there. A photo cropped off its centre does not, and with the prior as given the fit
//! holds the principal point near the crop's centre, bends the focal length and the pitch
//! around it, and reports error bars as tight as for a whole photo (SUN RGB-D's photos cropped
//! 50-75 px off: boxes 19-89 cm off at a Mahalanobis distance squared up to 47).
//!
//! The test: the fit again with the prior widened to [`CROPPED_PRINCIPAL_POINT_SD_DIAGONALS`]
//! of the diagonal (the principal point anywhere in the photo, as a crop can put it), from the
//! fit's answer ([`crate::fit::Fitted`]'s `refit_with_principal_point_sd`). Its negative
//! log-likelihood `J = cost / sigma^2` (the prior's term included; weighed as the lens's profile
//! weighs it when the click noise is estimated, `super::lens_refine`) drops by
//!
//! `J(given) - J(widened) ~ (p - c)^T (S + s0^2 I)^-1 (p - c)`
//!
//! to first order (`p` where the evidence alone puts the principal point with covariance `S`,
//! `c` the prior's centre, `s0` its sd): a prior-predictive check of the given prior, a
//! chi-square of two degrees of freedom when the prior is right. When the drop exceeds
//! [`PRINCIPAL_POINT_REJECTED_CHI2`] (its 99 % point), the map is built again, from scratch,
//! with the widened prior, and says so. The threshold is the 99 % point rather than the lens
//! test's 95 % because a widened principal point costs every whole photo precision: one in a
//! hundred whole photos pays it.
//!
//! References: M. Evans and H. Moshonov, "Checking for prior-data conflict", Bayesian Analysis
//! 1(4), 2006.

use super::lens_refine::{ClickNoise, weigh};
use crate::fit::Fitted;
use crate::interrupt::Interrupt;
use crate::room::RoomFitted;
use crate::scene::Scene;

/// The chi-square quantile of two degrees of freedom at 99 %: how much better the photo's
/// evidence must fit a principal point away from the prior's for the map to widen it.
pub const PRINCIPAL_POINT_REJECTED_CHI2: f64 = 9.210_340_371_976_184;

/// The standard deviation of the widened prior on the principal point, as a fraction of the
/// image diagonal (each coordinate): about a uniform spread over a 4:3 photo (its width over
/// the square root of 12 is 0.23 of the diagonal, its height's 0.17), as a crop can put it.
pub const CROPPED_PRINCIPAL_POINT_SD_DIAGONALS: f64 = 0.2;

/// A principal point prior the photo's evidence rejected.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct WidenedPrincipalPoint {
    /// The given prior's centre and standard deviation, pixels.
    pub given: ([f64; 2], f64),
    /// Where the fit with the widened prior puts the principal point, pixels.
    pub found_px: [f64; 2],
    /// The widened prior's standard deviation, pixels.
    pub sd_px: f64,
    /// `J(given) - J(widened)`: how much better the evidence fits.
    pub chi2_drop: f64,
}

/// The widened principal point when `fitted` (the fit of `scene`, a pinhole photo) rejects its
/// prior (see the module documentation); `None` when it does not, when the principal point is
/// held or already as wide, or when the refit fails.
pub(super) fn test_principal_point(
    scene: &Scene,
    fitted: &Fitted,
    noise: ClickNoise,
    interrupt: &Interrupt,
) -> Option<WidenedPrincipalPoint> {
    let s0 = fitted.principal_point_prior_sd()?;
    let centre = fitted.principal_point_prior_px()?;
    let wide = CROPPED_PRINCIPAL_POINT_SD_DIAGONALS * scene.image.diagonal();
    // Already as wide (or not a number): nothing to test.
    if s0.partial_cmp(&wide) != Some(std::cmp::Ordering::Less) {
        return None;
    }
    let (cost, found_px) = fitted.cost_with_principal_point_sd(wide, interrupt)?;
    let m = fitted.problem_residual_count() as f64;
    let chi2_drop = weigh(noise, m, fitted.cost()) - weigh(noise, m, cost);
    // A NaN drop is no evidence against the prior.
    (chi2_drop > PRINCIPAL_POINT_REJECTED_CHI2).then_some(WidenedPrincipalPoint {
        given: (centre, s0),
        found_px,
        sd_px: wide,
        chi2_drop,
    })
}

/// For each photo of a room whose principal point has a prior, the widened one when the joint
/// fit rejects the prior ([`test_principal_point`] for one photo of the joint fit: the room
/// refitted with that photo's prior widened, every placement as chosen, the other photos'
/// priors as given): `(photo, widened)`. `scene` is the room the fit was of.
pub(super) fn test_room_principal_points(
    scene: &Scene,
    fitted: &RoomFitted,
    noise: ClickNoise,
    interrupt: &Interrupt,
) -> Vec<(usize, WidenedPrincipalPoint)> {
    let m = fitted.problem_residual_count() as f64;
    let j0 = weigh(noise, m, fitted.cost());
    let mut out = Vec::new();
    for (n, photo) in scene.photos().enumerate() {
        let Some((centre, s0)) = fitted.principal_point_prior(n) else {
            continue;
        };
        let wide = CROPPED_PRINCIPAL_POINT_SD_DIAGONALS * photo.image.diagonal();
        if s0.partial_cmp(&wide) != Some(std::cmp::Ordering::Less) {
            continue;
        }
        let Some((cost, found_px)) = fitted.cost_with_principal_point_sd(n, wide, interrupt) else {
            continue;
        };
        let chi2_drop = j0 - weigh(noise, m, cost);
        if chi2_drop > PRINCIPAL_POINT_REJECTED_CHI2 {
            out.push((
                n,
                WidenedPrincipalPoint {
                    given: (centre, s0),
                    found_px,
                    sd_px: wide,
                    chi2_drop,
                },
            ));
        }
    }
    out
}

/// The warning that the principal point's prior was widened: `whose` is "the photo's" or
/// "photo 2's".
pub(super) fn principal_point_warning(whose: &str, w: &WidenedPrincipalPoint) -> String {
    let (c, s0) = w.given;
    format!(
        "{whose} edges and clicks put the principal point at ({:.0}, {:.0}), {:.0} px from where the scene's prior holds it, ({:.0}, {:.0}) +- {s0:.1} px: better by a chi-square of {:.1} (over {:.2}, the 99 % point of two degrees of freedom), as in a photo cropped off its centre, so the map is built with that prior widened to +- {:.0} px",
        w.found_px[0],
        w.found_px[1],
        (w.found_px[0] - c[0]).hypot(w.found_px[1] - c[1]),
        c[0],
        c[1],
        w.chi2_drop,
        PRINCIPAL_POINT_REJECTED_CHI2,
        w.sd_px
    )
}

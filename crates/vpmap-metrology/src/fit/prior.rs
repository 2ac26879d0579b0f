//! One photo's fit again with its intrinsics' priors widened, started from the fit's answer:
//! what the map's test of those priors needs ([`crate::map::build_map`]: a principal point
//! where the photo's edges and clicks put it rather than at the image centre, as for a cropped
//! photo; a focal length other than its EXIF's, as for a photo cropped after its EXIF was
//! written).
//!
//! The fit's problem is kept as the fit left it (the vanishing-point reading, the click noise it
//! estimated, every widening of disagreeing evidence): only the standard deviations of the
//! priors change. One Levenberg-Marquardt run from the fit's answer, as the lens's refits
//! (`fit/lens.rs`); only its cost and intrinsics are kept (the test needs no more, and a map
//! built with wider priors is fitted from scratch).

use super::model::VpEvidence;
use super::{Fitted, minimise};
use crate::interrupt::Interrupt;

/// The priors on a photo's intrinsics (the scene's `principal_point_sd_px` and
/// `focal_sd_px`), as its fit weighs them.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct IntrinsicsPriors {
    /// The principal point's centre and standard deviation (each coordinate), pixels.
    pub principal_point: Option<([f64; 2], f64)>,
    /// The focal length and its standard deviation, pixels.
    pub focal: Option<(f64, f64)>,
}

/// The priors among a photo's evidence.
pub(crate) fn intrinsics_priors(vps: &[VpEvidence]) -> IntrinsicsPriors {
    let mut out = IntrinsicsPriors::default();
    for e in vps {
        if let VpEvidence::Intrinsics {
            focal_px,
            principal_point_px,
            ..
        } = e
        {
            out.principal_point = out
                .principal_point
                .or(principal_point_px.map(|(p, sd)| ([p.x, p.y], sd)));
            out.focal = out.focal.or(*focal_px);
        }
    }
    out
}

/// The priors among a photo's evidence with their standard deviations replaced where given;
/// whether every prior asked for was there.
pub(crate) fn widen_priors(
    vps: &mut [VpEvidence],
    principal_point_sd_px: Option<f64>,
    focal_sd_px: Option<f64>,
) -> bool {
    let (mut pp_found, mut focal_found) = (false, false);
    for e in vps {
        if let VpEvidence::Intrinsics {
            focal_px,
            principal_point_px,
            ..
        } = e
        {
            if let (Some((_, sd)), Some(wide)) =
                (principal_point_px.as_mut(), principal_point_sd_px)
            {
                *sd = wide;
                pp_found = true;
            }
            if let (Some((_, sd)), Some(wide)) = (focal_px.as_mut(), focal_sd_px) {
                *sd = wide;
                focal_found = true;
            }
        }
    }
    (pp_found || principal_point_sd_px.is_none()) && (focal_found || focal_sd_px.is_none())
}

/// A refit with widened priors: its cost (as the fit's `cost`) and the intrinsics it puts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct PriorRefit {
    /// The cost, pixels squared.
    pub cost: f64,
    /// The principal point, pixels.
    pub principal_point_px: [f64; 2],
    /// The focal length, pixels.
    pub focal_px: f64,
}

impl Fitted {
    /// The priors on the fit's intrinsics.
    pub(crate) fn intrinsics_priors(&self) -> IntrinsicsPriors {
        intrinsics_priors(&self.problem.vps)
    }

    /// The fit again with the principal point's prior widened to `principal_point_sd_px` and
    /// the focal length's to `focal_sd_px` where given (same centres), from this fit's answer.
    /// `None` when a prior asked for is not there, when the refit does not converge, or when
    /// `interrupt` fires (the caller asks it).
    pub(crate) fn cost_with_priors_widened(
        &self,
        principal_point_sd_px: Option<f64>,
        focal_sd_px: Option<f64>,
        interrupt: &Interrupt,
    ) -> Option<PriorRefit> {
        let mut problem = self.problem.clone();
        if !widen_priors(&mut problem.vps, principal_point_sd_px, focal_sd_px) {
            return None;
        }
        problem.interrupt = interrupt.clone();
        let solution = minimise(&problem, self.x.clone()).filter(|s| s.converged)?;
        if interrupt.check().is_some() {
            return None;
        }
        let cam = problem.camera(&solution.x);
        Some(PriorRefit {
            cost: solution.cost,
            principal_point_px: [cam.principal_point_px.x, cam.principal_point_px.y],
            focal_px: cam.focal_px,
        })
    }
}

//! One photo's fit again with a wider prior on its principal point, started from the fit's
//! answer: what the map's test of that prior needs ([`crate::map::build_map`], a photo's
//! principal point where the photo's edges and clicks put it rather than at the image centre,
//! as for a cropped photo).
//!
//! The fit's problem is kept as the fit left it (the vanishing-point reading, the click noise it
//! estimated, every widening of disagreeing evidence): only the standard deviation of the
//! principal point's prior changes. One Levenberg-Marquardt run from the fit's answer, as the
//! lens's refits (`fit/lens.rs`); only its cost and principal point are kept (the test needs no
//! more, and a map built with the wider prior is fitted from scratch).

use super::model::VpEvidence;
use super::{Fitted, minimise};
use crate::interrupt::Interrupt;

impl Fitted {
    /// The standard deviation of the fit's prior on the principal point, pixels (`None` when
    /// the principal point is held or has no prior).
    pub(crate) fn principal_point_prior_sd(&self) -> Option<f64> {
        self.problem.vps.iter().find_map(|e| match e {
            VpEvidence::Intrinsics {
                principal_point_px: Some((_, sd)),
                ..
            } => Some(*sd),
            _ => None,
        })
    }

    /// The fit again with the principal point's prior widened to `sd_px` (same centre), from
    /// this fit's answer: its cost (as [`Fitted`]'s `cost`) and principal point, pixels.
    /// `None` when the fit has no prior on its principal point, when the refit does not
    /// converge, or when `interrupt` fires (the caller asks it).
    pub(crate) fn cost_with_principal_point_sd(
        &self,
        sd_px: f64,
        interrupt: &Interrupt,
    ) -> Option<(f64, [f64; 2])> {
        let mut problem = self.problem.clone();
        let mut found = false;
        for e in &mut problem.vps {
            if let VpEvidence::Intrinsics {
                principal_point_px: Some((_, sd)),
                ..
            } = e
            {
                *sd = sd_px;
                found = true;
            }
        }
        if !found {
            return None;
        }
        problem.interrupt = interrupt.clone();
        let solution = minimise(&problem, self.x.clone()).filter(|s| s.converged)?;
        if interrupt.check().is_some() {
            return None;
        }
        let p = problem.camera(&solution.x).principal_point_px;
        Some((solution.cost, [p.x, p.y]))
    }
}

impl Fitted {
    /// The centre of the fit's prior on the principal point, pixels (`None` without one).
    pub(crate) fn principal_point_prior_px(&self) -> Option<[f64; 2]> {
        self.problem.vps.iter().find_map(|e| match e {
            VpEvidence::Intrinsics {
                principal_point_px: Some((p, _)),
                ..
            } => Some([p.x, p.y]),
            _ => None,
        })
    }
}

//! One photo's fit again with a wider prior on its principal point, started from the fit's
//! answer: what the map's test of that prior needs ([`crate::map::build_map`], a photo's
//! principal point where the photo's edges and clicks put it rather than at the image centre,
//! as for a cropped photo).
//!
//! The fit's problem is kept as the fit left it (the vanishing-point reading, the click noise it
//! estimated, every widening of disagreeing evidence): only the standard deviation of the
//! principal point's prior changes. One Levenberg-Marquardt run from the fit's answer, as the
//! lens's refits (`fit/lens.rs`).

use super::model::VpEvidence;
use super::{Fitted, Solved, finish, minimise};
use crate::error::{MetrologyError, Result};
use crate::interrupt::Interrupt;
use crate::scene::Scene;

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
    /// this fit's answer. `scene` is the photo the fit was of.
    ///
    /// # Errors
    /// A fit without a prior on its principal point; a refit that does not converge or fails
    /// the fit's final checks; [`MetrologyError::Interrupted`] when `interrupt` fires.
    pub(crate) fn refit_with_principal_point_sd(
        &self,
        scene: &Scene,
        sd_px: f64,
        interrupt: &Interrupt,
    ) -> Result<Fitted> {
        let degenerate = |reason: String| MetrologyError::Degenerate {
            field: "principal_point_sd_px".to_owned(),
            reason,
        };
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
            return Err(degenerate(
                "the fit has no prior on the principal point to widen".to_owned(),
            ));
        }
        problem.interrupt = interrupt.clone();
        let solution = minimise(&problem, self.x.clone());
        if let Some(reason) = interrupt.check() {
            return Err(MetrologyError::Interrupted {
                work: format!(
                    "the fit of a photo of {} objects with the principal point's prior {sd_px} px",
                    scene.objects.len()
                ),
                reason,
            });
        }
        problem.interrupt = Interrupt::default();
        let solution = solution.filter(|s| s.converged).ok_or_else(|| {
            degenerate(format!(
                "the fit with the principal point's prior {sd_px} px does not converge"
            ))
        })?;
        finish(
            scene,
            Solved {
                problem,
                x: solution.x,
                cost: solution.cost,
                iterations: solution.iterations,
            },
            self.object_parts.clone(),
            self.floor_distance_parts,
        )
    }
}

impl Fitted {
    /// The fitted principal point, pixels.
    pub(crate) fn principal_point_px(&self) -> [f64; 2] {
        let p = self.problem.camera(&self.x).principal_point_px;
        [p.x, p.y]
    }

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

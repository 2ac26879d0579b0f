//! The joint fit again with one photo's intrinsics' priors widened, the placement held: what
//! the map's test of those priors needs ([`crate::map::build_map`], a cropped photo in a room),
//! as `room/lens.rs` refits a photo at another lens. Only the refit's cost and the photo's
//! intrinsics are kept: a room built with wider priors is fitted from scratch.

use super::fit::RoomFitted;
use crate::fit::prior::{IntrinsicsPriors, PriorRefit, intrinsics_priors, widen_priors};
use crate::fit::solve::minimise;
use crate::interrupt::Interrupt;

impl RoomFitted {
    /// The priors on photo `photo`'s intrinsics.
    pub(crate) fn intrinsics_priors(&self, photo: usize) -> IntrinsicsPriors {
        self.problem
            .photos
            .get(photo)
            .map(|b| intrinsics_priors(&b.vps))
            .unwrap_or_default()
    }

    /// The joint fit again with photo `photo`'s principal point prior widened to
    /// `principal_point_sd_px` and its focal length's to `focal_sd_px` where given (same
    /// centres), every photo's placement as chosen here, from this fit's answer. `None` when a
    /// prior asked for is not there, when the refit does not converge, or when `interrupt`
    /// fires (the caller asks it).
    pub(crate) fn cost_with_priors_widened(
        &self,
        photo: usize,
        principal_point_sd_px: Option<f64>,
        focal_sd_px: Option<f64>,
        interrupt: &Interrupt,
    ) -> Option<PriorRefit> {
        let mut problem = self.problem.clone();
        if !widen_priors(
            &mut problem.photos.get_mut(photo)?.vps,
            principal_point_sd_px,
            focal_sd_px,
        ) {
            return None;
        }
        problem.interrupt = interrupt.clone();
        let solution = minimise(&problem, self.x.clone()).filter(|s| s.converged)?;
        if interrupt.check().is_some() {
            return None;
        }
        let cam = problem.camera(&solution.x, photo);
        Some(PriorRefit {
            cost: solution.cost,
            principal_point_px: [cam.principal_point_px.x, cam.principal_point_px.y],
            focal_px: cam.focal_px,
        })
    }
}

//! The joint fit again with one photo's principal point prior widened, the placement held:
//! what the map's test of that prior needs ([`crate::map::build_map`], a cropped photo in a
//! room), as `room/lens.rs` refits a photo at another lens. Only the refit's cost and the
//! photo's principal point are kept: a room built with the wider prior is fitted from scratch.

use super::fit::RoomFitted;
use crate::fit::model::VpEvidence;
use crate::fit::solve::minimise;
use crate::interrupt::Interrupt;

impl RoomFitted {
    /// Photo `photo`'s prior on its principal point: its centre and standard deviation, pixels
    /// (`None` when the principal point is held or has no prior).
    pub(crate) fn principal_point_prior(&self, photo: usize) -> Option<([f64; 2], f64)> {
        self.problem
            .photos
            .get(photo)?
            .vps
            .iter()
            .find_map(|e| match e {
                VpEvidence::Intrinsics {
                    principal_point_px: Some((p, sd)),
                    ..
                } => Some(([p.x, p.y], *sd)),
                _ => None,
            })
    }

    /// The joint fit again with photo `photo`'s principal point prior widened to `sd_px` (same
    /// centre), every photo's placement as chosen here, from this fit's answer: its cost (as
    /// [`RoomFitted`]'s `cost`) and that photo's principal point, pixels. `None` when the photo
    /// has no prior on its principal point, when the refit does not converge, or when
    /// `interrupt` fires (the caller asks it).
    pub(crate) fn cost_with_principal_point_sd(
        &self,
        photo: usize,
        sd_px: f64,
        interrupt: &Interrupt,
    ) -> Option<(f64, [f64; 2])> {
        let mut problem = self.problem.clone();
        let mut found = false;
        for e in &mut problem.photos.get_mut(photo)?.vps {
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
        let p = problem.camera(&solution.x, photo).principal_point_px;
        Some((solution.cost, [p.x, p.y]))
    }
}

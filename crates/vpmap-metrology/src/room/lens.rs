//! The joint fit again with one photo's clicks undistorted by another lens `k`, the placement
//! held: what a room's error bars need to carry a photo's `k_sd`
//! ([`crate::map::build_map`] rebuilds the map with each photo's `k +- k_sd`).
//!
//! The chosen placement (every photo's quarter turn, every object's correspondence) is kept:
//! the refit is the same least-squares problem with that photo's clicked pixels and
//! vanishing-point segments moved to where the other `k` undistorts them (back through the
//! lens as given, forward through the other), each click covariance's whitening moved by the
//! two models' Jacobians, and started from the chosen fit's answer. One joint fit, no search.

use nalgebra::Vector2;

use super::fit::{Built, RoomFitted, finish, floor_below_horizons};
use crate::error::{MetrologyError, Result};
use crate::fit::model::VpEvidence;
use crate::fit::solve::minimise;
use crate::interrupt::Interrupt;
use crate::scene::{DivisionModel, Scene};

/// Where a pinhole pixel of the lens `from` lies for the lens `to`: the photo pixel it came
/// from (`from` undistorted it) undistorted by `to`; `None` beyond `from`'s reach.
fn moved(from: &DivisionModel, to: &DivisionModel, p: Vector2<f64>) -> Option<Vector2<f64>> {
    let raw = from.distort([p.x, p.y])?;
    let q = to.undistort(raw);
    Some(Vector2::new(q[0], q[1]))
}

/// Why a refit has no answer (the side of the lens's spread is left out).
fn unmovable(photo: usize, k: f64) -> MetrologyError {
    MetrologyError::Degenerate {
        field: format!("photos[{photo}].lens_distortion.k"),
        reason: format!(
            "photo {}'s clicks cannot be undistorted with k = {k}: a click lies beyond the lens's reach",
            photo + 1
        ),
    }
}

impl RoomFitted {
    /// The joint fit again with photo `photo`'s clicks undistorted by the lens `to` instead of
    /// `from` (the lens its clicks in this fit were undistorted by), every photo's placement
    /// as chosen here. `scene` is the room as a pinhole camera would have seen it with `to`
    /// (its floors give the refit's floor outlines).
    ///
    /// # Errors
    /// A click beyond either lens's reach; a refit that does not converge, puts a floor corner
    /// on or above a horizon or fails [`super::fit_room`]'s final checks;
    /// [`MetrologyError::Interrupted`] when `interrupt` fires.
    pub(crate) fn refit_with_lens(
        &self,
        scene: &Scene,
        photo: usize,
        from: &DivisionModel,
        to: &DivisionModel,
        interrupt: &Interrupt,
    ) -> Result<RoomFitted> {
        let mut problem = self.problem.clone();
        for s in problem
            .parts
            .iter_mut()
            .flat_map(|p| p.sightings.iter_mut())
            .filter(|s| s.photo == photo)
        {
            let raw = from
                .distort([s.pixel.x, s.pixel.y])
                .ok_or_else(|| unmovable(photo, from.k))?;
            s.pixel = moved(from, to, s.pixel).ok_or_else(|| unmovable(photo, from.k))?;
            // The covariance in pinhole pixels is J C J^T with J the undistortion's Jacobian at
            // the photo pixel; its whitening W (W^T W = the inverse) follows as W J_from J_to^-1.
            if let Some(w) = s.weight.as_mut() {
                let to_inverse = to
                    .undistort_jacobian(raw)
                    .try_inverse()
                    .ok_or_else(|| unmovable(photo, to.k))?;
                *w = *w * from.undistort_jacobian(raw) * to_inverse;
            }
        }
        if let Some(block) = problem.photos.get_mut(photo) {
            for vp in &mut block.vps {
                // Points and priors are the pinhole camera's already; segments were clicked.
                if let VpEvidence::Lines(segments) = vp {
                    for l in segments.iter_mut() {
                        let a = moved(from, to, Vector2::new(l[0], l[1]));
                        let b = moved(from, to, Vector2::new(l[2], l[3]));
                        let (Some(a), Some(b)) = (a, b) else {
                            return Err(unmovable(photo, from.k));
                        };
                        *l = [a.x, a.y, b.x, b.y];
                    }
                }
            }
        }
        problem.interrupt = interrupt.clone();
        let solution = minimise(&problem, self.x.clone());
        if let Some(reason) = interrupt.check() {
            return Err(MetrologyError::Interrupted {
                work: format!(
                    "the room fit of {} photos with photo {}'s lens k = {}",
                    problem.photos.len(),
                    photo + 1,
                    to.k
                ),
                reason,
            });
        }
        problem.interrupt = Interrupt::default();
        let solution = solution
            .filter(|s| s.converged)
            .ok_or_else(|| MetrologyError::Degenerate {
                field: format!("photos[{photo}].lens_distortion.k"),
                reason: format!(
                    "the room fit with photo {}'s lens k = {} does not converge",
                    photo + 1,
                    to.k
                ),
            })?;
        floor_below_horizons(scene, &problem, &solution.x)?;
        let built = Built {
            problem,
            x0: Vec::new(),
            object_of: self.object_of.clone(),
            floor_distance_parts: self.floor_distance_parts.clone(),
            names: self.objects.iter().map(|o| o.name.clone()).collect(),
            photo_axes: self.photo_axes.clone(),
        };
        finish(scene, built, solution.x, solution.iterations, Vec::new())
    }
}

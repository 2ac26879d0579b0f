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
use crate::fit::solve::minimise;
use crate::interrupt::Interrupt;
use crate::scene::{DivisionModel, Scene};

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
    /// The joint fit's cost at its answer (as [`crate::fit::Fitted`]'s), pixels squared.
    pub(crate) fn cost(&self) -> f64 {
        use crate::fit::solve::Model as _;
        self.problem.cost(&self.x)
    }

    /// How many residuals the joint fit's cost sums.
    pub(crate) fn problem_residual_count(&self) -> usize {
        use crate::fit::solve::Model as _;
        self.problem.residual_count()
    }

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
            let (raw, q) = from
                .move_to(to, [s.pixel.x, s.pixel.y])
                .ok_or_else(|| unmovable(photo, from.k))?;
            s.pixel = Vector2::new(q[0], q[1]);
            if let Some(w) = s.weight.as_mut() {
                *w = from
                    .whitening_moved_to(to, raw, *w)
                    .ok_or_else(|| unmovable(photo, to.k))?;
            }
        }
        if let Some(block) = problem.photos.get_mut(photo) {
            for vp in &mut block.vps {
                vp.move_lens(from, to)
                    .ok_or_else(|| unmovable(photo, from.k))?;
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
        let solution =
            solution
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::room::fit_room;
    use crate::scene::LensDistortion;
    use crate::synth::{RoomSynthOptions, VanishingPointForm, synthesize_room};

    /// Largest difference of two fits' object corners, heights and camera places, camera
    /// heights.
    fn difference(a: &RoomFitted, b: &RoomFitted) -> f64 {
        let mut worst = 0.0f64;
        assert_eq!(a.objects.len(), b.objects.len());
        for (p, q) in a.objects.iter().zip(&b.objects) {
            assert_eq!(p.name, q.name);
            for (u, v) in p.footprint.iter().zip(&q.footprint) {
                worst = worst.max((u - v).norm());
            }
            if let (Some(g), Some(h)) = (p.height, q.height) {
                worst = worst.max((g - h).abs());
            }
        }
        for (p, q) in a.photos.iter().zip(&b.photos) {
            worst = worst
                .max((p.position - q.position).norm())
                .max((p.height - q.height).abs());
        }
        worst
    }

    #[test]
    fn a_refit_at_another_k_is_the_fresh_fit_of_the_clicks_undistorted_by_it() {
        // Noisy clicks (so the answer depends on every pixel and weight), photo 2's with
        // covariances of their own, vanishing points as clicked segments, every photo through
        // a lens: the refit with photo 2's k changed (pixels, segments and whitenings moved
        // in place) must land where the whole room fit of the scene undistorted by that k
        // lands (its own placement search, its own undistortion of clicks and covariances).
        let (mut scene, _) = synthesize_room(&RoomSynthOptions {
            seed: 3,
            photos: 3,
            boxes: 6,
            noise_px: 0.7,
            vanishing_points: VanishingPointForm::Lines,
            ..RoomSynthOptions::default()
        })
        .unwrap_or_else(|e| panic!("{e}"));
        let lens = |k: f64| Some(LensDistortion { k, k_sd: None });
        scene.lens_distortion = lens(-0.05);
        for (n, p) in scene.other_photos.iter_mut().enumerate() {
            p.lens_distortion = lens(-0.04 - 0.01 * n as f64);
        }
        let second = &mut scene.other_photos[0];
        let fields: Vec<String> = second.clicks_by_field().into_keys().collect();
        assert!(fields.len() >= 8, "{fields:?}");
        for (i, f) in fields.into_iter().enumerate() {
            let s = 0.5 + 0.1 * (i % 5) as f64;
            second
                .click_covariances_px2
                .insert(f, [[s * s, 0.3 * s], [0.3 * s, 0.6]]);
        }
        let fitted = fit_room(&scene.undistorted()).unwrap_or_else(|e| panic!("{e}"));
        let mut shifted = scene.clone();
        shifted.other_photos[0].lens_distortion = lens(-0.09);
        let pinhole = shifted.undistorted();
        let fresh = fit_room(&pinhole).unwrap_or_else(|e| panic!("{e}"));
        let (Some(from), Some(to)) = (
            scene.other_photos[0].division_model(),
            shifted.other_photos[0].division_model(),
        ) else {
            panic!("no lens")
        };
        let refit = fitted
            .refit_with_lens(&pinhole, 1, &from, &to, &Interrupt::default())
            .unwrap_or_else(|e| panic!("{e}"));
        let moved_by_k = difference(&fitted, &fresh);
        let off = difference(&refit, &fresh);
        assert!(
            moved_by_k > 1e-3,
            "the k change moved the room by {moved_by_k:e} only"
        );
        assert!(
            off < 1e-7,
            "refit {off:e} camera heights from the fresh fit (k moved it {moved_by_k:e})"
        );
        // The same lens again: the fit itself.
        let same = fitted
            .refit_with_lens(&scene.undistorted(), 1, &from, &from, &Interrupt::default())
            .unwrap_or_else(|e| panic!("{e}"));
        assert!(difference(&same, &fitted) < 1e-9);
    }
}

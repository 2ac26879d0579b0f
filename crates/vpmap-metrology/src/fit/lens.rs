//! One photo's fit again with its clicks undistorted by another lens `k`, started from the
//! fit's answer: what the map's error bars need to carry the photo's `k_sd`
//! ([`crate::map::build_map`] refits at `k +- k_sd`).
//!
//! The fit's problem is kept as the fit left it (the vanishing-point reading, the principal
//! point fitted or held, the click noise it estimated and every widening of disagreeing
//! evidence): only the clicked pixels and the vanishing-point segments move to where the other
//! `k` undistorts them (back through the lens as given, forward through the other), and each
//! click covariance's whitening by the two models' Jacobians. One Levenberg-Marquardt run from
//! the fit's answer, no starts, no noise rounds: the consider parameter's linearisation point
//! is the fit itself, as the room's [`crate::room::RoomFitted`] refit does for a room.

use nalgebra::Vector2;

use super::model::Part;
use super::{Fitted, Solved, finish, minimise};
use crate::error::{MetrologyError, Result};
use crate::interrupt::Interrupt;
use crate::scene::{DivisionModel, Scene};

/// Why a click cannot be moved to the other lens.
fn unmovable(k: f64) -> MetrologyError {
    MetrologyError::Degenerate {
        field: "lens_distortion.k".to_owned(),
        reason: format!(
            "the clicks cannot be undistorted with k = {k}: a click lies beyond the lens's reach"
        ),
    }
}

/// Pinhole pixel `p` of lens `from` moved to lens `to` in place; the photo pixel it came from.
fn move_pixel(from: &DivisionModel, to: &DivisionModel, p: &mut Vector2<f64>) -> Result<[f64; 2]> {
    let (raw, q) = from
        .move_to(to, [p.x, p.y])
        .ok_or_else(|| unmovable(from.k))?;
    *p = Vector2::new(q[0], q[1]);
    Ok(raw)
}

impl Fitted {
    /// The fit's cost at its answer: the clicks' squared residuals (whitened by their
    /// covariances where they have one) plus the weighed evidence's chi-square times the
    /// square of the click noise it is expressed in, pixels squared.
    pub(crate) fn cost(&self) -> f64 {
        use super::solve::Model as _;
        self.problem.cost(&self.x)
    }

    /// How many residuals the fit's cost sums.
    pub(crate) fn problem_residual_count(&self) -> usize {
        use super::solve::Model as _;
        self.problem.residual_count()
    }

    /// The fit again with the clicks undistorted by the lens `to` instead of `from` (the lens
    /// its clicks were undistorted by), from this fit's answer. `scene` is the photo as a
    /// pinhole camera would have seen it with `to` (its floor outline is the map's).
    ///
    /// # Errors
    /// A click beyond either lens's reach; a refit that does not converge or fails the fit's
    /// final checks (a floor click on or above the horizon, a singular block);
    /// [`MetrologyError::Interrupted`] when `interrupt` fires.
    pub(crate) fn refit_with_lens(
        &self,
        scene: &Scene,
        from: &DivisionModel,
        to: &DivisionModel,
        interrupt: &Interrupt,
    ) -> Result<Fitted> {
        let mut problem = self.problem.clone();
        // Every clicked pixel moved, per part in its residuals' order (the weights' order).
        let mut raws: Vec<Vec<[f64; 2]>> = Vec::with_capacity(problem.parts.len());
        for part in &mut problem.parts {
            let mut here = Vec::new();
            match part {
                Part::Box { clicks, .. } => {
                    for c in clicks.iter_mut() {
                        here.push(move_pixel(from, to, &mut c.pixel)?);
                    }
                }
                Part::Footprint { vertices, top } => {
                    for v in vertices.iter_mut() {
                        here.push(move_pixel(from, to, v)?);
                    }
                    if let Some((_, p)) = top.as_mut() {
                        here.push(move_pixel(from, to, p)?);
                    }
                }
                Part::FloorPoint { pixel } => here.push(move_pixel(from, to, pixel)?),
            }
            raws.push(here);
        }
        for (weights, raws) in problem.weights.iter_mut().zip(&raws) {
            for (w, raw) in weights.iter_mut().zip(raws) {
                if let Some(w) = w.as_mut() {
                    *w = from
                        .whitening_moved_to(to, *raw, *w)
                        .ok_or_else(|| unmovable(to.k))?;
                }
            }
        }
        for vp in &mut problem.vps {
            vp.move_lens(from, to).ok_or_else(|| unmovable(from.k))?;
        }
        problem.interrupt = interrupt.clone();
        let solution = minimise(&problem, self.x.clone());
        if let Some(reason) = interrupt.check() {
            return Err(MetrologyError::Interrupted {
                work: format!(
                    "the fit of a photo of {} objects with the lens k = {}",
                    scene.objects.len(),
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
                    field: "lens_distortion.k".to_owned(),
                    reason: format!("the fit with the lens k = {} does not converge", to.k),
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fit::{FitOptions, fit_scene};
    use crate::scene::LensDistortion;
    use crate::synth::{SynthOptions, VanishingPointForm, synthesize};

    /// Largest difference of two fits' object corners and heights, camera heights, and of
    /// their cameras' focal lengths, pixels.
    fn difference(a: &Fitted, b: &Fitted) -> (f64, f64) {
        let mut worst = 0.0f64;
        let (p, q) = (&a.reconstruction.objects, &b.reconstruction.objects);
        assert_eq!(p.len(), q.len());
        for (o, r) in p.iter().zip(q) {
            for (u, v) in o.footprint.iter().zip(&r.footprint) {
                worst = worst.max((u - v).norm());
            }
            if let (Some(g), Some(h)) = (o.height, r.height) {
                worst = worst.max((g - h).abs());
            }
        }
        let focal = (a.calibration.focal_px - b.calibration.focal_px).abs();
        (worst, focal)
    }

    #[test]
    fn a_refit_at_another_k_is_the_fresh_fit_of_the_clicks_undistorted_by_it() {
        // Noisy clicks (so the answer depends on every pixel and weight), some with
        // covariances of their own, vanishing points as clicked segments, the photo through a
        // lens, the click noise given (the fit's weights do not depend on k): the refit with k
        // changed (pixels, segments and whitenings moved in place) must land where the whole
        // fit of the scene undistorted by that k lands (its own starts, its own undistortion
        // of clicks and covariances).
        let (mut scene, _) = synthesize(&SynthOptions {
            seed: 5,
            noise_px: 0.7,
            vanishing_points: VanishingPointForm::Lines,
            ..SynthOptions::default()
        })
        .unwrap_or_else(|e| panic!("{e}"));
        let fields: Vec<String> = scene.clicks_by_field().into_keys().collect();
        assert!(fields.len() >= 8, "{fields:?}");
        for (i, f) in fields.into_iter().enumerate().filter(|(i, _)| i % 2 == 0) {
            let s = 0.5 + 0.1 * (i % 5) as f64;
            scene
                .click_covariances_px2
                .insert(f, [[s * s, 0.3 * s], [0.3 * s, 0.6]]);
        }
        let lens = |k: f64| Some(LensDistortion { k, k_sd: None });
        scene.lens_distortion = lens(-0.05);
        let options = FitOptions {
            click_sigma_px: Some(1.0),
        };
        let fitted = fit_scene(&scene.undistorted(), &options).unwrap_or_else(|e| panic!("{e}"));
        let mut shifted = scene.clone();
        shifted.lens_distortion = lens(-0.09);
        let pinhole = shifted.undistorted();
        let fresh = fit_scene(&pinhole, &options).unwrap_or_else(|e| panic!("{e}"));
        let (Some(from), Some(to)) = (scene.division_model(), shifted.division_model()) else {
            panic!("no lens")
        };
        let refit = fitted
            .refit_with_lens(&pinhole, &from, &to, &Interrupt::default())
            .unwrap_or_else(|e| panic!("{e}"));
        let (moved_by_k, focal_moved) = difference(&fitted, &fresh);
        let (off, focal_off) = difference(&refit, &fresh);
        assert!(
            moved_by_k > 1e-3 && focal_moved > 0.1,
            "the k change moved the map by {moved_by_k:e} and the focal length by {focal_moved:e} px only"
        );
        assert!(
            off < 1e-7 && focal_off < 1e-6,
            "refit {off:e} camera heights and {focal_off:e} px from the fresh fit (k moved it {moved_by_k:e}, {focal_moved:e} px)"
        );
        // The same lens again: the fit itself.
        let same = fitted
            .refit_with_lens(&scene.undistorted(), &from, &from, &Interrupt::default())
            .unwrap_or_else(|e| panic!("{e}"));
        let (d, f) = difference(&same, &fitted);
        assert!(d < 1e-9 && f < 1e-7, "{d:e} {f:e}");
    }
}

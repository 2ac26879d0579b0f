//! Refinement of a hypothesis: segment assignments and a robust Levenberg-Marquardt fit.
//!
//! # Refinement
//! The best few hypotheses are refined by Levenberg-Marquardt on the residuals `r` of the
//! segments assigned to each direction (a segment supports its best direction when
//! `|r| <= 2` working pixels and `theta <= 3` degrees), with Cauchy weights (iteratively
//! reweighted, scale 1 pixel) and orthogonality built in: the unknowns are a rotation increment
//! `R = exp([w]x) R_0` and, when not given, `ln f` (weak log-normal prior: `sigma = 1` around
//! the longer side) and the principal point (Gaussian prior around the image centre,
//! `sigma = 0.1` longer sides). Assignments are redone between rounds; the refined hypothesis
//! with the best score wins.
//!
//! The principal point is freed only in clear three-point perspective, when the vertical
//! direction is tilted from the image plane by at least [`PRINCIPAL_POINT_MIN_TILT_DEG`]:
//! the orthocentre of the three vanishing points then fixes it. Closer to two-point
//! perspective it is not determined — exactly at zero pitch it lies on the horizon but may
//! slide along it (each position with its own focal length), and near it its distance from
//! the horizon trades off against the pitch — so it stays at the image centre.

use nalgebra::{Rotation3, Vector3};

use super::lm::levenberg_marquardt;
use super::model::{Frame, Seg, vertical_index};
use super::problem::{
    CAUCHY_SCALE_PX, INLIER_ANGLE_DEG, INLIER_DISTANCE_PX, LM_ITERATIONS,
    PRINCIPAL_POINT_MIN_TILT_DEG, Problem, REFINE_ROUNDS,
};

impl Problem<'_> {
    /// Whether the principal point is to be estimated for this frame.
    fn principal_point_free(&self, frame: &Frame) -> bool {
        if self.known_pp.is_some() {
            return false;
        }
        let vertical = vertical_index(&frame.rot);
        let tilt = frame
            .rot
            .get((2, vertical))
            .map_or(0.0, |z| z.abs().min(1.0).asin().to_degrees());
        tilt >= PRINCIPAL_POINT_MIN_TILT_DEG
    }

    /// Levenberg-Marquardt refinement with reassignment; returns the frame and whether the
    /// principal point was freed.
    pub(super) fn refine(&self, start: Frame) -> (Frame, bool) {
        let mut frame = start;
        let mut pp_free = false;
        let focal_free = self.known_focal.is_none();
        let focal_prior_centre = self.focal_prior.centre.ln();
        for round in 0..REFINE_ROUNDS {
            if round >= 1 {
                pp_free = self.principal_point_free(&frame);
            }
            let assigned = self.assign(&frame);
            if assigned.iter().filter(|a| a.is_some()).count() < 3 {
                break;
            }
            let base = frame;
            let pp_centre = self.default_pp();
            let work_px = self.norm.work_px;
            let build = |x: &[f64]| -> Frame {
                let w = Vector3::new(
                    x.first().copied().unwrap_or(0.0),
                    x.get(1).copied().unwrap_or(0.0),
                    x.get(2).copied().unwrap_or(0.0),
                );
                let rot = Rotation3::new(w).matrix() * base.rot;
                let mut cam = base.cam;
                let mut next = 3;
                if focal_free {
                    cam.focal = base.cam.focal * x.get(next).copied().unwrap_or(0.0).exp();
                    next += 1;
                }
                if pp_free {
                    cam.pp = [
                        base.cam.pp[0] + x.get(next).copied().unwrap_or(0.0),
                        base.cam.pp[1] + x.get(next + 1).copied().unwrap_or(0.0),
                    ];
                }
                Frame { rot, cam }
            };
            // Cauchy weights from the residuals at the start of the round.
            let start_vps = base.vps();
            let weights: Vec<f64> = self
                .segs
                .iter()
                .zip(&assigned)
                .map(|(s, a)| {
                    a.and_then(|k| start_vps.get(k)).map_or(0.0, |v| {
                        let r = s.residual(v) * work_px / CAUCHY_SCALE_PX;
                        1.0 / (1.0 + r * r)
                    })
                })
                .collect();
            let residuals = |x: &[f64], out: &mut Vec<f64>| {
                out.clear();
                let f = build(x);
                let vps = f.vps();
                for ((s, a), w) in self.segs.iter().zip(&assigned).zip(&weights) {
                    if let Some(v) = a.and_then(|k| vps.get(k)) {
                        out.push(w.sqrt() * s.residual(v) * work_px / CAUCHY_SCALE_PX);
                    }
                }
                if focal_free {
                    out.push(
                        (f.cam.focal.ln() - focal_prior_centre) / self.focal_prior.sigma_refine,
                    );
                }
                if pp_free {
                    out.push((f.cam.pp[0] - pp_centre[0]) / self.pp_sigma);
                    out.push((f.cam.pp[1] - pp_centre[1]) / self.pp_sigma);
                }
            };
            let dims = 3 + usize::from(focal_free) + 2 * usize::from(pp_free);
            let x = levenberg_marquardt(vec![0.0; dims], residuals, LM_ITERATIONS);
            let next = build(&x);
            if next.rot.iter().all(|v| v.is_finite())
                && next.cam.focal.is_finite()
                && next.cam.focal > 1e-3
                && next.cam.pp.iter().all(|v| v.is_finite())
            {
                frame = next;
            }
        }
        (frame, pp_free)
    }

    /// The direction each segment supports, if any.
    pub(super) fn assign(&self, frame: &Frame) -> Vec<Option<usize>> {
        let vps = frame.vps();
        self.segs
            .iter()
            .map(|s| best_support(s, &vps, self.norm.work_px))
            .collect()
    }
}

/// The vanishing point (index into `vps`) that segment `s` supports, if any.
pub(super) fn best_support(s: &Seg, vps: &[Vector3<f64>; 3], work_px: f64) -> Option<usize> {
    let sin2_max = INLIER_ANGLE_DEG.to_radians().sin().powi(2);
    let mut best: Option<(usize, f64)> = None;
    for (k, v) in vps.iter().enumerate() {
        let e = s.sin2(v);
        if e < sin2_max && best.is_none_or(|b| e < b.1) {
            best = Some((k, e));
        }
    }
    let (k, _) = best?;
    let r = vps.get(k).map_or(f64::INFINITY, |v| s.residual(v)).abs() * work_px;
    (r <= INLIER_DISTANCE_PX).then_some(k)
}

//! The evidence with its own uncertainty (measured vanishing points, the intrinsics' priors)
//! against the clicks: the click noise at which they agree ([`rescale_evidence`]), a measured
//! vanishing point that disagrees far beyond its error bars widened
//! ([`widen_disagreeing_evidence`]), and the warnings that name them.

use nalgebra::Vector2;

use super::model::{self, vp_direction};
use super::solve::{Model, Problem, minimise};
use super::{Fitted, MIN_CLICK_SIGMA_PX, MIN_DOF_FOR_SIGMA, Solved};

/// The chi-square quantile with 2 degrees of freedom at 99.9 %: `-2 ln 0.001`. A measured
/// vanishing point farther than this from where the fit puts it is taken to disagree with
/// the clicks: a right one does so once in a thousand fits.
const CHI2_2DOF_999: f64 = 13.815_510_557_964_274;

/// Most rounds of widening disagreeing evidence.
const MAX_WIDEN_ROUNDS: usize = 3;

/// A measured vanishing point whose error bars [`widen_disagreeing_evidence`] widened.
pub(super) struct Widened {
    /// Its group (0, 1 horizontal, 2 vertical).
    group: usize,
    /// Its squared Mahalanobis distance from the first fit.
    chi2: f64,
    /// Its angle from the first fit, degrees.
    angle_deg: f64,
    /// How many times its standard deviations were widened in all.
    factor: f64,
}

/// Each measured vanishing point's squared Mahalanobis distance from where the fitted camera
/// puts it, and the angle (radians); `None` for other evidence.
fn evidence_distances(problem: &Problem, x: &[f64]) -> Vec<Option<(f64, f64)>> {
    let cam = problem.camera(x);
    problem
        .vps
        .iter()
        .enumerate()
        .map(|(g, e)| {
            let model::VpEvidence::Measured {
                at,
                chart,
                whitening,
                ..
            } = e
            else {
                return None;
            };
            let v = cam.vanishing_point(vp_direction(&cam, g));
            let o = chart.offset_rad(*at, v)?;
            let o = Vector2::new(o[0], o[1]);
            Some(((whitening * o).norm_squared(), o.norm()))
        })
        .collect()
}

/// Robustness to a wrong detected vanishing point: when the fit puts a measured vanishing
/// point beyond its 99.9 % ellipse ([`CHI2_2DOF_999`]), the clicks and it disagree far more
/// than its covariance allows (an occluding bar's edges taken for a room direction, say).
/// Its covariance is then widened by `chi2 / 2` (its squared distance over the mean of a
/// chi-square of two degrees of freedom: the covariance at which the disagreement is
/// ordinary) and the fit run again from where it stands, at most [`MAX_WIDEN_ROUNDS`] times;
/// the map's error bars then carry the disagreement instead of hiding it. Returns the fit
/// and what was widened.
pub(super) fn widen_disagreeing_evidence(
    mut solved: Solved,
    rescale: bool,
) -> (Solved, Vec<Widened>) {
    let mut widened: Vec<Widened> = Vec::new();
    for _ in 0..MAX_WIDEN_ROUNDS {
        let distances = evidence_distances(&solved.problem, &solved.x);
        let far: Vec<(usize, f64, f64)> = distances
            .iter()
            .enumerate()
            .filter_map(|(g, d)| d.map(|(chi2, angle)| (g, chi2, angle)))
            .filter(|(_, chi2, _)| chi2.is_finite() && *chi2 > CHI2_2DOF_999)
            .collect();
        if far.is_empty() {
            break;
        }
        let mut problem = solved.problem.clone();
        for &(g, chi2, _) in &far {
            if let Some(model::VpEvidence::Measured { whitening, .. }) = problem.vps.get_mut(g) {
                *whitening *= (2.0 / chi2).sqrt();
            }
        }
        match minimise(&problem, solved.x.clone()) {
            Some(sol) if sol.converged && sol.x.iter().all(|v| v.is_finite()) => {
                for &(g, chi2, angle) in &far {
                    let grow = (chi2 / 2.0).sqrt();
                    match widened.iter_mut().find(|w| w.group == g) {
                        Some(w) => w.factor *= grow,
                        None => widened.push(Widened {
                            group: g,
                            chi2,
                            angle_deg: angle.to_degrees(),
                            factor: grow,
                        }),
                    }
                }
                solved = Solved {
                    problem,
                    x: sol.x,
                    cost: sol.cost,
                    iterations: solved.iterations + sol.iterations,
                };
                if rescale {
                    solved = rescale_evidence(solved);
                }
            }
            _ => break,
        }
    }
    (solved, widened)
}

/// Most rounds of re-estimating the click noise that weighed evidence is expressed in.
const MAX_SIGMA_ROUNDS: usize = 4;

/// With evidence of its own uncertainty (measured vanishing points, intrinsics' priors) and
/// the click noise estimated from the residuals: the noise at which the clicks' residuals
/// and that evidence agree, and the fit again at it. The cost is `sum r_click^2 + sigma^2
/// chi2_evidence`; its estimate of `sigma^2` is `sum r_click^2 / (dof - chi2_evidence)`,
/// whose fixed point makes the error bars' `cost / dof` equal `sigma^2` (never below
/// [`MIN_CLICK_SIGMA_PX`], as there). Too few redundant observations: 1 px, as the error
/// bars' default.
pub(super) fn rescale_evidence(mut solved: Solved) -> Solved {
    if !solved.problem.vps.iter().any(|e| e.scale().is_some()) {
        return solved;
    }
    for _ in 0..MAX_SIGMA_ROUNDS {
        let problem = &solved.problem;
        let dof = problem.residual_count().saturating_sub(problem.len());
        let Some(r) = problem.residuals(&solved.x) else {
            return solved;
        };
        let mut at = 0;
        let mut evidence_chi2 = 0.0;
        for e in &problem.vps {
            let n = model::vp_residual_count(e);
            if let Some(scale) = e.scale() {
                evidence_chi2 += r[at..at + n]
                    .iter()
                    .map(|v| (v / scale) * (v / scale))
                    .sum::<f64>();
            }
            at += n;
        }
        let clicks: f64 = r[at..].iter().map(|v| v * v).sum();
        let current = problem
            .vps
            .iter()
            .find_map(model::VpEvidence::scale)
            .unwrap_or(1.0);
        let sigma = if dof < MIN_DOF_FOR_SIGMA {
            1.0
        } else {
            let free = (dof as f64 - evidence_chi2).max(0.25 * dof as f64);
            (clicks / free).sqrt().max(MIN_CLICK_SIGMA_PX)
        };
        if (sigma / current - 1.0).abs() < 0.01 {
            return solved;
        }
        let mut problem = problem.clone();
        for e in &mut problem.vps {
            e.set_scale(sigma);
        }
        match minimise(&problem, solved.x.clone()) {
            Some(sol) if sol.converged && sol.x.iter().all(|v| v.is_finite()) => {
                solved = Solved {
                    problem,
                    x: sol.x,
                    cost: sol.cost,
                    iterations: solved.iterations + sol.iterations,
                };
            }
            _ => return solved,
        }
    }
    solved
}

/// The chi-square quantile with 2 degrees of freedom at 99 %: `-2 ln 0.01`.
const CHI2_2DOF_99: f64 = 9.210_340_371_976_184;

/// A warning for each measured vanishing point the fitted camera puts outside its 99 %
/// ellipse: the clicks (and the other evidence) disagree with it beyond its error bars.
pub(super) fn evidence_warnings(fitted: &Fitted, order: [usize; 3]) -> Vec<String> {
    evidence_distances(&fitted.problem, &fitted.x)
        .into_iter()
        .enumerate()
        .filter_map(|(g, d)| d.map(|(chi2, angle)| (g, chi2, angle)))
        .filter(|(_, chi2, _)| *chi2 > CHI2_2DOF_99)
        .map(|(g, chi2, angle)| {
            let index = order.get(g).copied().unwrap_or(g);
            let what = if g == 2 { "vertical" } else { "horizontal" };
            format!(
                "vanishing point {} ({what}) lies {:.2} degrees ({:.1} sigma) from where the clicks put it: the clicked corners and the vanishing point disagree beyond its error bars; check its edges (or the point, if given), or the clicks of the boxes along it",
                index + 1,
                angle.to_degrees(),
                chi2.sqrt()
            )
        })
        .collect()
}

/// A warning for each measured vanishing point [`widen_disagreeing_evidence`] widened, naming
/// it as the scene lists it (`order`), by how much it disagreed and how many times its error
/// bars were widened.
pub(super) fn widened_warnings(widened: &[Widened], order: [usize; 3]) -> Vec<String> {
    widened
        .iter()
        .map(|w| {
            let index = order.get(w.group).copied().unwrap_or(w.group);
            let what = if w.group == 2 {
                "vertical"
            } else {
                "horizontal"
            };
            format!(
                "vanishing point {} ({what}) lay {:.2} degrees ({:.1} sigma) from where the clicks put it: the clicked corners and the vanishing point disagree far beyond its error bars (an edge of something else taken for the room's, or a point given as exact that is not), so its error bars were widened {:.1} times to agree and the map's follow; check its edges, or the clicks of the boxes along it",
                index + 1,
                w.angle_deg,
                w.chi2.sqrt(),
                w.factor
            )
        })
        .collect()
}

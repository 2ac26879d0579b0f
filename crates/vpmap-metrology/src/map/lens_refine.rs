//! The lens a photo's clicks agree on: the given `k` refined by the clicks when they reject it.
//!
//! A scene's `lens_distortion` (`k` with `k_sd`, as `vpmap detect` estimates it from the
//! photo's long edges) is a prior, not a fact: the clicked corners see the lens too, and boxes
//! drawn through the wrong `k` do not close. The profile of the fit's negative log-likelihood
//! over `k`,
//!
//! `J(k) = cost(k) / sigma^2 + ((k - k0) / k_sd)^2`,
//!
//! is taken from refits of the photo at other lenses (each from the fit's answer with
//! everything the fit chose held, [`crate::fit::Fitted`]'s `refit_with_lens`, as the lens's
//! error bars do): `cost(k)` the clicks' squared residuals plus the weighed evidence, `sigma`
//! the fit's click noise; when that noise is estimated from the residuals (which a wrong lens
//! inflates), `m ln(cost(k) + m s0^2)` over the `m` residuals in place of `cost(k) / sigma^2`,
//! the profile likelihood over the noise with the clicks' rounding `s0` added.
//!
//! The minimum is found on whole steps of `k_sd`, then by parabolas through three refits at
//! the profile's own width, twice. The first steps, `k0 +- k_sd`, are the lens spread's own
//! refits (`super::lens`), and the search ends there when their parabola's vertex is not half
//! the test's chi-square below `J(k0)`: a lens its clicks do not reject costs no refit more. When the best `k` lowers `J` below `J(k0)` by
//! more than the chi-square quantile of one degree of freedom at 95 %
//! ([`LENS_REJECTED_CHI2`]: a likelihood ratio test of the given `k`), the map is built again
//! with the best `k` and the standard deviation the profile's curvature gives (never more than
//! `k_sd`); otherwise the given lens stands. Exact clicks through the given lens leave it
//! exactly as it is (`J` is least at `k0`), and so do clicks that cannot tell one lens from
//! another.

use crate::fit::Fitted;
use crate::interrupt::Interrupt;
use crate::room::RoomFitted;
use crate::scene::{DivisionModel, LensDistortion, MAX_DIVISION_STRETCH, Scene};

/// The chi-square quantile of one degree of freedom at 95 %: how much better than the given
/// lens the clicks must fit another for the map to take it.
pub const LENS_REJECTED_CHI2: f64 = 3.841_458_820_694_124;

/// The farthest from the given `k` the profile looks, in its standard deviations.
const MAX_STEPS: i32 = 6;

/// How the profile weighs the clicks' cost: by a known click noise, or (the noise estimated
/// from the residuals) by the profile likelihood over it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum ClickNoise {
    /// `cost / sigma^2`: a given `--click-sigma`, clicks with their own covariances (1), or
    /// the default 1 px.
    Known(f64),
    /// `m ln(cost + m s0^2)`, `m` residuals: the noise estimated from the same residuals,
    /// which a wrong lens inflates; `s0` the rounding of clicks to whole pixels
    /// ([`crate::fit::MIN_CLICK_SIGMA_PX`]), the noise no click is free of.
    Estimated,
}

/// A lens the clicks preferred to the given one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct RefinedLens {
    /// The given `k` and `k_sd`.
    pub given: [f64; 2],
    /// The lens the map takes: the profile's minimum and its standard deviation.
    pub lens: LensDistortion,
    /// `J(k0) - J(k)`: how much better the clicks fit it.
    pub chi2_drop: f64,
}

/// The vertex `t` and the half-width `w` (`J` rises by 1 at `t +- w`) of the parabola through
/// `J` at `t - h`, `t0`, `t + h`; `None` when it does not open upwards.
fn parabola(t0: f64, h: f64, jm: f64, j0: f64, jp: f64) -> Option<(f64, f64)> {
    let second = (jm - 2.0 * j0 + jp) / (h * h);
    (second > 0.0 && second.is_finite())
        .then(|| (t0 - 0.5 * (jp - jm) / (h * second), (2.0 / second).sqrt()))
}

/// How a refit's cost enters the profile (see [`ClickNoise`]), with `m` residuals.
pub(super) fn weigh(noise: ClickNoise, m: f64, cost: f64) -> f64 {
    match noise {
        ClickNoise::Known(sigma) => cost / (sigma * sigma),
        ClickNoise::Estimated => {
            m * (cost + m * crate::fit::MIN_CLICK_SIGMA_PX * crate::fit::MIN_CLICK_SIGMA_PX).ln()
        }
    }
}

/// The profile's minimum over `k = k0 + t sd` (see the module documentation), `cost_at(k)`
/// the refit's cost at `k` (`None` where it fails), `j0` the profile at `k0`: the lens the
/// clicks fit when they reject `k0`, and by how much.
fn profile_minimum(
    k0: f64,
    sd: f64,
    j0: f64,
    noise: ClickNoise,
    m: f64,
    known: &[(f64, f64)],
    cost_at: impl Fn(f64) -> Option<f64>,
) -> Option<(LensDistortion, f64)> {
    if !(sd > 0.0 && sd.is_finite() && j0.is_finite()) {
        return None;
    }
    // J at k0 + t sd; a refit the lens's spread already made is not made again.
    let profile = |t: f64| -> Option<f64> {
        if t == 0.0 {
            return Some(j0);
        }
        let k = k0 + t * sd;
        let cost = known
            .iter()
            .find(|(kk, _)| (kk - k).abs() <= 1e-12 * sd)
            .map(|(_, c)| *c)
            .or_else(|| cost_at(k))?;
        let j = weigh(noise, m, cost) + t * t;
        j.is_finite().then_some(j)
    };
    // Whole steps of sd: -1 to 1 first (the spread's refits), the screening below; then -2 and
    // 2, and outwards while the least is at an end.
    let mut samples: Vec<(i32, f64)> = (-1..=1)
        .filter_map(|t| profile(f64::from(t)).map(|j| (t, j)))
        .collect();
    let [(-1, jm), (0, jz), (1, jp)] = samples[..] else {
        return None;
    };
    if screened_out(j0, jm, jz, jp) {
        return None;
    }
    samples.extend(
        [-2, 2]
            .into_iter()
            .filter_map(|t| profile(f64::from(t)).map(|j| (t, j))),
    );
    samples.sort_by_key(|s| s.0);
    loop {
        let &(best, _) = samples.iter().min_by(|a, b| a.1.total_cmp(&b.1))?;
        let (lo, hi) = (samples.first()?.0, samples.last()?.0);
        let next = if best == hi && hi < MAX_STEPS {
            hi + 1
        } else if best == lo && lo > -MAX_STEPS {
            lo - 1
        } else {
            break;
        };
        let j = profile(f64::from(next))?;
        samples.push((next, j));
        samples.sort_by_key(|s| s.0);
    }
    let &(best, jb) = samples.iter().min_by(|a, b| a.1.total_cmp(&b.1))?;
    let at = |t: i32| samples.iter().find(|s| s.0 == t).map(|s| s.1);
    let (jm, jp) = (at(best - 1)?, at(best + 1)?);
    let (mut t, mut w) = parabola(f64::from(best), 1.0, jm, jb, jp)?;
    if screened_out(j0, jm, jb, jp) {
        return None;
    }
    let (mut t_best, mut j_best) = (f64::from(best), jb);
    // Again at the profile's own scale, twice: a sharp profile is no parabola over whole sds.
    for _ in 0..2 {
        let h = w.clamp(1e-4, 1.0);
        let (jm, jt, jp) = (profile(t - h)?, profile(t)?, profile(t + h)?);
        for (tt, jj) in [(t - h, jm), (t, jt), (t + h, jp)] {
            if jj < j_best {
                (t_best, j_best) = (tt, jj);
            }
        }
        let Some((t2, w2)) = parabola(t, h, jm, jt, jp) else {
            break;
        };
        (t, w) = (t2, w2);
    }
    if let Some(j) = profile(t).filter(|j| *j < j_best) {
        (t_best, j_best) = (t, j);
    }
    let chi2_drop = j0 - j_best;
    // A NaN drop is no evidence against the given lens.
    if chi2_drop.is_nan() || chi2_drop <= LENS_REJECTED_CHI2 {
        return None;
    }
    Some((
        LensDistortion {
            k: k0 + t_best * sd,
            k_sd: Some((w * sd).min(sd)),
        },
        chi2_drop,
    ))
}

/// Whether the parabola through `J` at three whole steps `jm`, `jz`, `jp` says the clicks
/// cannot reject the given lens (`J(k0) = j0`): its vertex not even half the test's
/// chi-square below `j0` (or no vertex, the three not opening upwards, with none of them
/// that far below). Spares the refits of the finer search.
fn screened_out(j0: f64, jm: f64, jz: f64, jp: f64) -> bool {
    let second = jm - 2.0 * jz + jp;
    let least = if second > 0.0 {
        jz - (jp - jm).powi(2) / (8.0 * second)
    } else {
        jm.min(jz).min(jp)
    };
    j0 - least <= 0.5 * LENS_REJECTED_CHI2
}

/// The lens `scene`'s clicks agree on, when they reject the given one (see the module
/// documentation); `None` when they do not, when the scene gives no `k_sd`, or when the
/// profile cannot be taken (refits that fail around the given `k`).
pub(super) fn refine_lens(
    scene: &Scene,
    fitted: &Fitted,
    known: &[(f64, f64)],
    noise: ClickNoise,
    interrupt: &Interrupt,
) -> Option<RefinedLens> {
    let LensDistortion {
        k: k0,
        k_sd: Some(sd),
    } = scene.lens_distortion?
    else {
        return None;
    };
    let from = scene.division_model()?;
    let m = fitted.problem_residual_count() as f64;
    let cost_at = |k: f64| -> Option<f64> {
        let mut s = scene.clone();
        s.lens_distortion = Some(LensDistortion { k, k_sd: None });
        let to = s.division_model()?;
        if to.stretch(s.image) > MAX_DIVISION_STRETCH {
            return None;
        }
        let refit = fitted
            .refit_with_lens(&s.undistorted(), &from, &to, interrupt)
            .ok()?;
        Some(refit.cost())
    };
    let j0 = weigh(noise, m, fitted.cost());
    let (lens, chi2_drop) = profile_minimum(k0, sd, j0, noise, m, known, cost_at)?;
    Some(RefinedLens {
        given: [k0, sd],
        lens,
        chi2_drop,
    })
}

/// For each photo of a room with a `k_sd`, the lens its clicks agree on when they reject the
/// given one ([`refine_lens`] for one photo of the joint fit: the room refitted with that
/// photo's clicks through other lenses, every placement as chosen, the others' lenses as
/// given): `(photo, refined)`.
pub(super) fn refine_room_lenses(
    scene: &Scene,
    fitted: &RoomFitted,
    known: &[Vec<(f64, f64)>],
    noise: ClickNoise,
    interrupt: &Interrupt,
) -> Vec<(usize, RefinedLens)> {
    let m = fitted.problem_residual_count() as f64;
    let j0 = weigh(noise, m, fitted.cost());
    let mut out = Vec::new();
    for (n, photo) in scene.photos().enumerate() {
        let Some(LensDistortion {
            k: k0,
            k_sd: Some(sd),
        }) = photo.lens_distortion
        else {
            continue;
        };
        let Some(from) = photo.division_model() else {
            continue;
        };
        let cost_at = |k: f64| -> Option<f64> {
            let lens = LensDistortion { k, k_sd: None };
            let to = DivisionModel::new(k, photo.image, photo.principal_point);
            if to.stretch(photo.image) > MAX_DIVISION_STRETCH {
                return None;
            }
            let mut s = scene.clone();
            s.photo_mut(n)?.lens_distortion = Some(lens);
            let refit = fitted
                .refit_with_lens(&s.undistorted(), n, &from, &to, interrupt)
                .ok()?;
            Some(refit.cost())
        };
        let known = known.get(n).map_or(&[][..], Vec::as_slice);
        if let Some((lens, chi2_drop)) = profile_minimum(k0, sd, j0, noise, m, known, cost_at) {
            out.push((
                n,
                RefinedLens {
                    given: [k0, sd],
                    lens,
                    chi2_drop,
                },
            ));
        }
    }
    out
}

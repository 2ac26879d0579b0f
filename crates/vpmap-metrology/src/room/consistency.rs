//! The room's consistency test, before anything is written: do the photos fit together about
//! as well as each fits alone?
//!
//! Each photo's own fit leaves a misfit `C_k` (its clicks and vanishing-point edges) over
//! `d_k` degrees of freedom; the joint fit leaves `C` over `d`. Joining the photos adds
//! `m = d - sum d_k` constraints (the shared objects, the shared room directions); if they
//! hold, the joint misfit grows by `C - sum C_k ~ sigma^2 chi^2(m)`, and
//! `F = ((C - sum C_k) / m) / s^2`, with `s^2 = sum C_k / sum d_k` the photos' own click
//! variance (at least the rounding of a click, `MIN_CLICK_SIGMA_PX^2`), follows Fisher's
//! `F(m, sum d_k)` (a likelihood-ratio test of the room against its photos alone). The room
//! is refused when `F` exceeds the distribution's upper [`LEVEL`] point: a consistent room is
//! refused once in a thousand. Without redundant clicks in the photos (`sum d_k = 0`) the
//! variance is 1 px^2 and the test is the chi-square one.
//!
//! The photos' own fits of a few short edges absorb part of the noise (their misfit per
//! degree of freedom comes out below the click variance: 0.32 px for clicks of 0.5 px on a
//! shared room), which inflates `F`; so the room is refused only when it is also **far
//! worse**: the joint fit's click sigma (`sqrt(C / d)`) at least [`FAR_WORSE_SIGMA_RATIO`]
//! times the photos' own `s`.

use super::model::RoomProblem;
use crate::error::MetrologyError;
use crate::fit::MIN_CLICK_SIGMA_PX;
use crate::fit::solve::Model;

use super::align::PhotoFit;

/// Each clicked point's part, photo and squared residual, for the residuals of `problem`
/// whose points start at `at` (after the vanishing-point groups).
fn point_residuals_of(
    problem: &RoomProblem,
    residuals: &[f64],
    mut at: usize,
) -> Vec<(usize, (usize, f64))> {
    let mut out = Vec::new();
    for (i, part) in problem.parts.iter().enumerate() {
        for s in &part.sightings {
            let r = residuals.get(at).copied().unwrap_or(0.0).powi(2)
                + residuals.get(at + 1).copied().unwrap_or(0.0).powi(2);
            out.push((i, (s.photo, r)));
            at += 2;
        }
    }
    out
}

/// The test's level: the share of consistent rooms its F test alone would refuse.
pub const LEVEL: f64 = 0.001;

/// How much larger the joint fit's click sigma (its misfit per degree of freedom) must be
/// than the photos' own for a room to be "far worse" than its photos alone.
pub const FAR_WORSE_SIGMA_RATIO: f64 = 2.0;

/// The standard normal's upper [`LEVEL`] point.
const Z_LEVEL: f64 = 3.090_232_306_167_813;

/// The upper [`LEVEL`] point of Fisher's F distribution with `m` and `d` degrees of freedom
/// (`d = None`: infinite), by Paulson's normal approximation of the cube root (within a few
/// per cent for `d >= 3`).
pub(crate) fn f_upper(m: usize, d: Option<usize>) -> f64 {
    let a = 2.0 / (9.0 * m.max(1) as f64);
    let Some(d) = d else {
        // m F ~ chi^2(m): Wilson-Hilferty.
        return (1.0 - a + Z_LEVEL * a.sqrt()).powi(3);
    };
    let b = 2.0 / (9.0 * d.max(1) as f64);
    // (1 - b) u - (1 - a) = z sqrt(b u^2 + a), u = F^(1/3): the larger root.
    let (p, q) = (1.0 - b, 1.0 - a);
    let z2 = Z_LEVEL * Z_LEVEL;
    let qa = p * p - z2 * b;
    let qb = -2.0 * p * q;
    let qc = q * q - z2 * a;
    let disc = qb * qb - 4.0 * qa * qc;
    if qa <= 0.0 || disc < 0.0 {
        return f64::INFINITY;
    }
    let u = (-qb + disc.sqrt()) / (2.0 * qa);
    u.powi(3)
}

/// What the test found.
#[derive(Debug, Clone)]
pub(crate) struct Consistency {
    /// `F` and the level's point.
    pub f: f64,
    pub threshold: f64,
    /// Constraints joining adds, and the photos' own degrees of freedom.
    pub m: usize,
    pub d: usize,
    /// The click variance, px^2.
    pub variance: f64,
    /// The joint fit's misfit per degree of freedom, px^2.
    pub joint_variance: f64,
    /// Per photo: its misfit's growth in click variances.
    pub photo_growth: Vec<f64>,
    /// Objects by their joint misfit, worst first: name and squared residual in click
    /// variances.
    pub objects: Vec<(String, f64)>,
}

impl Consistency {
    pub fn refused(&self) -> bool {
        self.f > self.threshold
            && self.joint_variance >= FAR_WORSE_SIGMA_RATIO.powi(2) * self.variance
    }
}

/// The test of the joint fit `x` of `problem` (parts named `names`) against the photos' own
/// fits.
pub(crate) fn test(
    fits: &[PhotoFit],
    problem: &RoomProblem,
    x: &[f64],
    names: &[String],
) -> Consistency {
    let own: Vec<(f64, usize)> = fits
        .iter()
        .map(|f| {
            let p = &f.fitted.problem;
            (
                p.cost(&f.fitted.x),
                p.residual_count().saturating_sub(p.len()),
            )
        })
        .collect();
    let own_cost: f64 = own.iter().map(|o| o.0).sum();
    let d: usize = own.iter().map(|o| o.1).sum();
    let variance = if d > 0 {
        (own_cost / d as f64).max(MIN_CLICK_SIGMA_PX * MIN_CLICK_SIGMA_PX)
    } else {
        1.0
    };
    // The joint misfit per photo.
    let residuals = problem.residuals(x).unwrap_or_default();
    let mut joint = vec![0.0; fits.len()];
    let mut at = 0;
    for g in 0..problem.camera_group_count() {
        let len = problem.camera_group_len(g);
        let k = problem.groups.get(g).map_or(0, |g| g.0);
        let s: f64 = residuals.iter().skip(at).take(len).map(|r| r * r).sum();
        if let Some(j) = joint.get_mut(k) {
            *j += s;
        }
        at += len;
    }
    let mut objects: Vec<(String, f64)> = Vec::new();
    for (i, s) in point_residuals_of(problem, &residuals, at) {
        if let Some(j) = joint.get_mut(s.0) {
            *j += s.1;
        }
        if let Some(name) = names.get(i) {
            match objects.iter_mut().find(|o| &o.0 == name) {
                Some(o) => o.1 += s.1 / variance,
                None => objects.push((name.clone(), s.1 / variance)),
            }
        }
    }
    objects.sort_by(|a, b| b.1.total_cmp(&a.1));
    let joint_cost: f64 = joint.iter().sum();
    let joint_dof = problem.residual_count().saturating_sub(problem.len());
    let m = joint_dof.saturating_sub(d).max(1);
    let f = ((joint_cost - own_cost).max(0.0) / m as f64) / variance;
    let photo_growth = joint
        .iter()
        .zip(&own)
        .map(|(j, o)| (j - o.0) / variance)
        .collect();
    Consistency {
        f,
        threshold: f_upper(m, (d > 0).then_some(d)),
        m,
        d,
        variance,
        joint_variance: joint_cost / joint_dof.max(1) as f64,
        photo_growth,
        objects,
    }
}

/// The refusal: the test, the photos and objects that disagree, the alternative's cost and
/// what to do.
pub(crate) fn refusal(
    c: &Consistency,
    alternative: Option<String>,
    shared: &[Vec<String>],
) -> MetrologyError {
    let mut photos: Vec<(usize, f64)> = c.photo_growth.iter().copied().enumerate().collect();
    photos.sort_by(|a, b| b.1.total_cmp(&a.1));
    let worst: Vec<(usize, f64)> = photos.iter().copied().take(2).collect();
    let named: Vec<String> = worst
        .iter()
        .map(|(k, g)| {
            format!(
                "photo {} (its clicks' misfit grows by {g:.0} click variances)",
                k + 1
            )
        })
        .collect();
    let objects: Vec<String> = c
        .objects
        .iter()
        .take(3)
        .map(|(n, v)| format!("{n:?} ({v:.0})"))
        .collect();
    let mut common: Vec<String> = Vec::new();
    if let [(a, _), (b, _)] = worst.as_slice()
        && let (Some(sa), Some(sb)) = (shared.get(*a), shared.get(*b))
    {
        common = sa.iter().filter(|n| sb.contains(n)).cloned().collect();
    }
    let rename = if common.is_empty() {
        "check that the objects they share with the other photos are named alike only where they are the same object".to_owned()
    } else {
        format!(
            "check that {} {} the same object{} in photos {} and {} (rename any that is not), each clicked at its own corners",
            common
                .iter()
                .map(|n| format!("{n:?}"))
                .collect::<Vec<_>>()
                .join(" and "),
            if common.len() == 1 { "is" } else { "are" },
            if common.len() == 1 { "" } else { "s" },
            worst[0].0.min(worst[1].0) + 1,
            worst[0].0.max(worst[1].0) + 1,
        )
    };
    MetrologyError::InconsistentRoom {
        reason: format!(
            "the joint fit's misfit exceeds what the photos' own clicks allow (F = {:.1} over {} constraints and {} degrees of freedom, above {:.2}, the test's upper {} % point; click sigma {:.2} px jointly against {:.2} px from the photos alone, more than {} times); {} disagree most; the objects that misfit most are {} (squared residuals in click variances); {}; {}, or click one more object seen in both",
            c.f,
            c.m,
            c.d,
            c.threshold,
            LEVEL * 100.0,
            c.joint_variance.sqrt(),
            c.variance.sqrt(),
            FAR_WORSE_SIGMA_RATIO,
            named.join(" and "),
            objects.join(", "),
            alternative.unwrap_or_else(|| {
                "no other placement of the photos comes near it in the placement search or could be fitted".to_owned()
            }),
            rename,
        ),
    }
}

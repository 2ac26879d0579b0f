//! Numbers on the picture: 1-2-5 grid steps and scale-bar lengths, and how many decimals
//! they are written with.

/// The 1-2-5 step for grid lines over `span`: 1 when that gives 5 to 20 lines (whole metres or
/// camera heights), else the step whose line count is nearest 10.
#[must_use]
pub(crate) fn grid_step(span: f64) -> f64 {
    if !(span.is_finite() && span > 0.0) {
        return 1.0;
    }
    if (5.0..=20.0).contains(&span) {
        return 1.0;
    }
    let e = span.log10().floor() as i32;
    let mut best = (f64::INFINITY, 1.0);
    for k in (e - 2)..=(e + 1) {
        for m in [1.0, 2.0, 5.0] {
            let step = m * 10f64.powi(k);
            let score = (span / step / 10.0).ln().abs();
            if score < best.0 {
                best = (score, step);
            }
        }
    }
    best.1
}

/// The largest 1-2-5 value not above `limit` (for the scale bar).
pub(crate) fn nice_at_most(limit: f64) -> f64 {
    if !(limit.is_finite() && limit > 0.0) {
        return 1.0;
    }
    let e = limit.log10().floor() as i32;
    let mut best = 10f64.powi(e - 1);
    for k in (e - 1)..=e {
        for m in [1.0, 2.0, 5.0] {
            let v = m * 10f64.powi(k);
            if v <= limit * (1.0 + 1e-12) && v > best {
                best = v;
            }
        }
    }
    best
}

/// Decimals that show a multiple of `step` exactly (0 for 1 m, 1 for 0.5 m, 2 for 0.05 m).
pub(crate) fn decimals_for(step: f64) -> usize {
    let d = -(step.log10() + 1e-9).floor();
    if d.is_finite() && d > 0.0 {
        d.min(12.0) as usize
    } else {
        0
    }
}

/// `v` with `decimals` decimals and no minus sign on zero.
pub(crate) fn fmt_num(v: f64, decimals: usize) -> String {
    let s = format!("{v:.decimals$}");
    match s.strip_prefix('-') {
        Some(rest) if rest.chars().all(|c| c == '0' || c == '.') => rest.to_owned(),
        _ => s,
    }
}

/// Multiples `k` (as floats) of `step` with `k * step` in `[lo, hi]`, at most 200 of them.
pub(crate) fn grid_indices(lo: f64, hi: f64, step: f64) -> impl Iterator<Item = f64> {
    let first = (lo / step).ceil();
    let last = (hi / step).floor();
    let count = if first.is_finite() && last.is_finite() && last >= first {
        ((last - first) as u32 + 1).min(200)
    } else {
        0
    };
    (0..count).map(move |i| first + f64::from(i))
}

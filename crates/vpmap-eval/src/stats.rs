//! Every statistic the reports print: quantiles, medians, means, box-plot figures, fractions
//! within a threshold and the area under the error curve.
//!
//! Quantiles are Hyndman and Fan's type 7 (linear interpolation between order statistics, the
//! default of R and NumPy): `x[h]` interpolated at `h = (n - 1) q` over the sorted values.
//! [`median`] is the mean of the middle two for an even count, as the benchmark's times have
//! always been reported; it can differ from `quantile(.., 0.5)` in the last bit.
//!
//! # References
//! - R. J. Hyndman, Y. Fan, *Sample quantiles in statistical packages*, The American
//!   Statistician 50 (1996).

use serde::Serialize;

/// The `q` quantile (`0 <= q <= 1`, clamped) of sorted values, type 7: `x[h]` interpolated at
/// `h = (n - 1) q`. `NaN` for no values. Infinities (misses counted as infinite errors) sort
/// last and are not interpolated: a quantile falling between a finite value and an infinite
/// one is infinite, one falling exactly on a finite value is that value.
///
/// # Example
/// ```
/// use vpmap_eval::stats::quantile;
/// assert_eq!(quantile(&[10.0, 20.0], 0.3), 13.0);
/// assert_eq!(quantile(&[1.0, f64::INFINITY], 0.5), f64::INFINITY);
/// assert!(quantile(&[], 0.5).is_nan());
/// ```
#[must_use]
pub fn quantile(sorted: &[f64], q: f64) -> f64 {
    let Some(last) = sorted.len().checked_sub(1) else {
        return f64::NAN;
    };
    let h = last as f64 * q.clamp(0.0, 1.0);
    let lo = h.floor() as usize;
    let hi = (lo + 1).min(last);
    let (Some(&a), Some(&b)) = (sorted.get(lo), sorted.get(hi)) else {
        return f64::NAN;
    };
    if a.is_infinite() || b.is_infinite() {
        return if h > lo as f64 { b } else { a };
    }
    a + (b - a) * (h - lo as f64)
}

/// [`quantile`] of unsorted values (sorted here, `NaN` last); `None` for no values.
#[must_use]
pub fn quantile_of(values: &[f64], q: f64) -> Option<f64> {
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    (!sorted.is_empty()).then(|| quantile(&sorted, q))
}

/// The median of the values that are not `NaN`: the middle one, or the mean of the middle two
/// for an even count. `None` when there are none.
///
/// # Example
/// ```
/// use vpmap_eval::stats::median;
/// assert_eq!(median(&[4.0, 1.0, f64::NAN]), Some(2.5));
/// assert_eq!(median(&[]), None);
/// ```
#[must_use]
pub fn median(values: &[f64]) -> Option<f64> {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| !x.is_nan()).collect();
    v.sort_by(f64::total_cmp);
    let n = v.len();
    let at = |k: usize| v.get(k).copied();
    if n % 2 == 1 {
        at(n / 2)
    } else {
        Some(0.5 * (at(n.checked_sub(2)? / 2)? + at(n / 2)?))
    }
}

/// The arithmetic mean; `None` for no values.
#[must_use]
pub fn mean(values: &[f64]) -> Option<f64> {
    (!values.is_empty()).then(|| values.iter().sum::<f64>() / values.len() as f64)
}

/// The fraction of `values` at most `threshold` (infinite values count, and are above it);
/// 0 for no values.
#[must_use]
pub fn fraction_at_most(values: &[f64], threshold: f64) -> f64 {
    let n = values.len().max(1) as f64;
    values.iter().filter(|&&e| e <= threshold).count() as f64 / n
}

/// The area under the cumulative error curve up to `limit`, normalised to 1: the mean of
/// `max(0, 1 - e / limit)` over the errors `e` (an infinite or `NaN` error adds 0); 0 for no
/// values.
#[must_use]
pub fn auc(errors: &[f64], limit: f64) -> f64 {
    let n = errors.len().max(1) as f64;
    errors
        .iter()
        .map(|&e| (1.0 - e / limit).max(0.0))
        .sum::<f64>()
        / n
}

/// The largest [`auc`] up to `limit_high` that any errors can reach when their [`auc`] up to
/// `limit_low` (`0 < limit_low <= limit_high`) is `auc_low`.
///
/// `1 - auc(e, L)` is the mean of `min(e, L) / L`, and `min(e, limit_high) >= min(e,
/// limit_low)`, so `1 - auc(e, limit_high) >= (limit_low / limit_high) (1 - auc(e,
/// limit_low))`. A published triple of AA@3/5/10 that breaks this was not measured as the area
/// under one error curve (docs/detection.md, "Against GlobustVP").
///
/// # Example
/// ```
/// use vpmap_eval::stats::auc_ceiling;
/// // Errors whose AUC@3 is 67.6 % have an AUC@10 of at most 90.3 %.
/// assert!((auc_ceiling(0.676, 3.0, 10.0) - 0.9028).abs() < 1e-12);
/// ```
#[must_use]
pub fn auc_ceiling(auc_low: f64, limit_low: f64, limit_high: f64) -> f64 {
    1.0 - limit_low / limit_high * (1.0 - auc_low)
}

/// Order statistics of a sample, the figures of a box plot: quantiles by [`quantile`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Summary {
    /// Number of values.
    pub count: usize,
    /// Smallest value.
    pub min: f64,
    /// 5th percentile.
    pub p5: f64,
    /// First quartile.
    pub q1: f64,
    /// Median.
    pub median: f64,
    /// Third quartile.
    pub q3: f64,
    /// 95th percentile.
    pub p95: f64,
    /// Largest value.
    pub max: f64,
    /// Arithmetic mean.
    pub mean: f64,
}

impl Summary {
    /// Summarise the finite values of a sample (`None` when there are none).
    ///
    /// # Example
    /// ```
    /// use vpmap_eval::stats::Summary;
    /// let s = Summary::of(&[3.0, 1.0, 2.0, 4.0, f64::NAN]).unwrap();
    /// assert_eq!((s.count, s.min, s.median, s.max), (4, 1.0, 2.5, 4.0));
    /// assert!((s.q1 - 1.75).abs() < 1e-12);
    /// ```
    #[must_use]
    pub fn of(values: &[f64]) -> Option<Self> {
        let mut sorted: Vec<f64> = values.iter().copied().filter(|v| v.is_finite()).collect();
        if sorted.is_empty() {
            return None;
        }
        sorted.sort_by(f64::total_cmp);
        let (&min, &max) = (sorted.first()?, sorted.last()?);
        Some(Self {
            count: sorted.len(),
            min,
            p5: quantile(&sorted, 0.05),
            q1: quantile(&sorted, 0.25),
            median: quantile(&sorted, 0.5),
            q3: quantile(&sorted, 0.75),
            p95: quantile(&sorted, 0.95),
            max,
            mean: sorted.iter().sum::<f64>() / sorted.len() as f64,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// The ceiling holds for any errors (misses included): checked against `auc` itself on
        /// random samples, the two limits drawn too.
        #[test]
        fn no_errors_beat_the_auc_ceiling(
            errors in proptest::collection::vec(prop_oneof![0.0..20.0f64, Just(f64::INFINITY)], 1..40),
            limit_low in 0.5..10.0f64,
            factor in 1.0..4.0f64,
        ) {
            let limit_high = limit_low * factor;
            let ceiling = auc_ceiling(auc(&errors, limit_low), limit_low, limit_high);
            prop_assert!(auc(&errors, limit_high) <= ceiling + 1e-12);
        }
    }

    #[test]
    fn the_auc_ceiling_is_reached_by_errors_at_zero_or_beyond_the_higher_limit() {
        // Errors all at 3 give AUC@3 = 0 and AUC@10 = 0.7, exactly the ceiling. Half the
        // errors exact and half beyond 10 give AUC@3 = AUC@10 = 0.5, far below the ceiling
        // 1 - 0.3 * 0.5 = 0.85.
        let at_three = [3.0; 4];
        assert!(close(
            auc(&at_three, 10.0),
            auc_ceiling(auc(&at_three, 3.0), 3.0, 10.0)
        ));
        let split = [0.0, 0.0, 12.0, f64::INFINITY];
        assert!(auc(&split, 10.0) < auc_ceiling(auc(&split, 3.0), 3.0, 10.0) - 0.3);
    }

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-12
    }

    #[test]
    fn quantiles_interpolate_between_order_statistics() {
        // Type 7: h = (n - 1) q. For 1..=21, the 5th percentile is x[1] = 2, the median x[10].
        let values: Vec<f64> = (1..=21).map(f64::from).collect();
        let s = Summary::of(&values).unwrap_or_else(|| panic!("no summary"));
        assert!(close(s.p5, 2.0) && close(s.median, 11.0) && close(s.p95, 20.0));
        assert!(close(s.q1, 6.0) && close(s.q3, 16.0) && close(s.mean, 11.0));
        assert!(close(quantile(&[10.0, 20.0], 0.3), 13.0));
        assert!(quantile(&[], 0.5).is_nan());
        assert!(Summary::of(&[f64::NAN]).is_none());
    }

    #[test]
    fn misses_sort_last_and_are_not_interpolated() {
        let v = [3.0, f64::INFINITY, 1.0, 2.0];
        assert_eq!(quantile_of(&v, 0.5), Some(2.5));
        assert_eq!(quantile_of(&v, 0.9), Some(f64::INFINITY));
        assert_eq!(quantile_of(&[1.0, f64::INFINITY], 0.0), Some(1.0));
        assert_eq!(
            quantile_of(&[f64::INFINITY, f64::INFINITY], 0.5),
            Some(f64::INFINITY)
        );
        assert_eq!(quantile_of(&[], 0.5), None);
    }

    #[test]
    fn medians_means_fractions_and_areas() {
        assert_eq!(median(&[3.0, 1.0, 2.0]), Some(2.0));
        assert_eq!(median(&[4.0, 1.0]), Some(2.5));
        assert_eq!(median(&[f64::NAN]), None);
        assert_eq!(mean(&[1.0, 2.0]), Some(1.5));
        assert_eq!(mean(&[]), None);
        let e = [0.5, 2.0, f64::INFINITY, 4.0];
        assert!(close(fraction_at_most(&e, 2.0), 0.5));
        assert!(close(auc(&e, 4.0), (0.875 + 0.5) / 4.0));
        assert!(close(auc(&[], 4.0), 0.0));
    }
}

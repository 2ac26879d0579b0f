//! D* Lite's queue keys `[k1; k2]`, held exactly in integers: [`NarrowKey`] (16 bytes,
//! without tie weights), [`TieKey`] (24 bytes, under the common tie rule) while the step
//! counts stay under a million, and [`WideKey`] (48 bytes, any counts) once they outgrow that.

use super::cost::StepCost;

/// `sqrt 2` in units of `2^-64`, rounded: the diagonal step of [`fixed_length`].
const SQRT_2_FIXED: u128 = 26_087_635_650_665_564_425;

/// Step counts below this (per component) keep [`fixed_length`] exactly ordered; `k_m`
/// is folded into the keys before it gets there ([`Search::rekey`](super::search::Search::rekey)).
const FIXED_EXACT_BELOW: u32 = 1 << 27;

/// The length of `c` in units of `2^-64` cells (`sqrt 2` rounded to that unit): for
/// step counts below `2^27` its error (under `2^-37`) is far below the smallest gap between
/// two different lengths (`|x - y sqrt 2| >= 1 / (x + y sqrt 2)`, over `10^-9`), so it
/// orders lengths exactly and equal lengths (equal step counts) stay equal.
#[inline]
fn fixed_length(c: StepCost) -> u128 {
    if c.is_finite() {
        (u128::from(c.straight) << 64) + u128::from(c.diagonal) * SQRT_2_FIXED
    } else {
        u128::MAX
    }
}

/// A queue key `[k1; k2]`, compared lexicographically, held exactly: [`NarrowKey`]
/// without tie weights and while the step counts are small, [`WideKey`] otherwise.
pub(super) trait QueueKey: Copy + Ord + std::fmt::Debug {
    /// Larger than every key [`QueueKey::new`] returns: the key given to a cell whose key
    /// does not fit, until the search is widened.
    const MAX: Self;
    /// `k_m`'s step counts are folded into the keys
    /// ([`Search::rekey`](super::search::Search::rekey)) before either reaches this.
    const KM_LIMIT: u32;
    /// The key `[k1; k2]`, or `None` when this type cannot hold it exactly.
    fn new(k1: StepCost, k2: StepCost) -> Option<Self>;
    /// Whether the first part's length is at most `other`'s (tie weights aside).
    fn k1_length_le(self, other: Self) -> bool;
}

/// A key of any step counts and tie weights: each part's length ([`fixed_length`], `2^-64`
/// cells) and then its tie weight; 48 bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(super) struct WideKey {
    k1: u128,
    k1_weight: u64,
    k2: u128,
    k2_weight: u64,
}

impl QueueKey for WideKey {
    const MAX: Self = Self {
        k1: u128::MAX,
        k1_weight: u64::MAX,
        k2: u128::MAX,
        k2_weight: u64::MAX,
    };
    const KM_LIMIT: u32 = FIXED_EXACT_BELOW / 2;

    #[inline]
    fn new(k1: StepCost, k2: StepCost) -> Option<Self> {
        Some(Self {
            k1: fixed_length(k1),
            k1_weight: k1.weight,
            k2: fixed_length(k2),
            k2_weight: k2.weight,
        })
    }

    #[inline]
    fn k1_length_le(self, other: Self) -> bool {
        self.k1 <= other.k1
    }
}

/// `sqrt 2` in units of `2^-42`, rounded: the diagonal step of [`narrow_length`].
const SQRT_2_NARROW: u64 = 6_219_777_023_951;

/// Step counts up to this (per component) keep [`narrow_length`] exactly ordered and
/// within 64 bits.
pub(super) const NARROW_MAX_STEPS: u32 = 1_000_000;

/// The length of `c` in units of `2^-42` cells, or `None` for a count over
/// [`NARROW_MAX_STEPS`] (infinite: `u64::MAX`). Exact order: two different lengths of
/// counts up to `n = 10^6` differ by `|x - y sqrt 2| >= 1 / (x + y sqrt 2) > 4.1e-7` cells,
/// while the rounded `sqrt 2` errs by at most `2^-43` a diagonal step, `1.2e-7` cells over
/// `10^6` of them; the longest length, `2.42e6` cells, stays below `2^22`, so the sum fits
/// in 64 bits. Equal counts give equal lengths.
#[inline]
fn narrow_length(c: StepCost) -> Option<u64> {
    if !c.is_finite() {
        Some(u64::MAX)
    } else if c.straight <= NARROW_MAX_STEPS && c.diagonal <= NARROW_MAX_STEPS {
        Some((u64::from(c.straight) << 42) + u64::from(c.diagonal) * SQRT_2_NARROW)
    } else {
        None
    }
}

/// A key without tie weights (the common tie rule off) and of step counts up to
/// [`NARROW_MAX_STEPS`]: each part's length ([`narrow_length`]); 16 bytes, a third of a
/// [`WideKey`], which makes the queue's sifting about a quarter faster.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(super) struct NarrowKey(u128);

impl QueueKey for NarrowKey {
    const MAX: Self = Self(u128::MAX);
    const KM_LIMIT: u32 = NARROW_MAX_STEPS / 4;

    #[inline]
    fn new(k1: StepCost, k2: StepCost) -> Option<Self> {
        if (k1.is_finite() && k1.weight != 0) || (k2.is_finite() && k2.weight != 0) {
            return None;
        }
        let (k1, k2) = (narrow_length(k1)?, narrow_length(k2)?);
        Some(Self((u128::from(k1) << 64) | u128::from(k2)))
    }

    #[inline]
    fn k1_length_le(self, other: Self) -> bool {
        self.0 >> 64 <= other.0 >> 64
    }
}

/// A key of step counts up to [`NARROW_MAX_STEPS`] under the common tie rule: each part's
/// length ([`narrow_length`]) and their tie weight once, ordered as `(k1 length, weight, k2
/// length)`. Both parts have the same weight (`k1 = k2 + h + k_m`, and the heuristic and
/// `k_m` are octile lengths of weight 0), so this is the order of [`WideKey`]'s four parts;
/// a key whose parts' weights differ is not held. 24 bytes (a [`NarrowKey`] and its
/// comparison are smaller still: measured, each type is the faster one for its mode).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(super) struct TieKey {
    k1: u64,
    weight: u64,
    k2: u64,
}

impl QueueKey for TieKey {
    const MAX: Self = Self {
        k1: u64::MAX,
        weight: u64::MAX,
        k2: u64::MAX,
    };
    const KM_LIMIT: u32 = NARROW_MAX_STEPS / 4;

    #[inline]
    fn new(k1: StepCost, k2: StepCost) -> Option<Self> {
        match (k1.is_finite(), k2.is_finite()) {
            (false, false) => Some(Self::MAX),
            (true, true) if k1.weight == k2.weight => Some(Self {
                k1: narrow_length(k1)?,
                weight: k1.weight,
                k2: narrow_length(k2)?,
            }),
            _ => None,
        }
    }

    #[inline]
    fn k1_length_le(self, other: Self) -> bool {
        self.k1 <= other.k1
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use std::cmp::Ordering;

    use super::*;

    /// The exact length order and its integer keys agree with each other and with the
    /// lengths in high precision, also on near ties (Pell pairs: 99^2 - 2 * 70^2 = 1).
    #[test]
    fn lengths_compare_exactly_and_their_fixed_point_keys_keep_the_order() {
        let c = |straight, diagonal| StepCost {
            straight,
            diagonal,
            weight: 0,
        };
        let mut pairs = vec![c(99, 0), c(0, 70), c(3363, 0), c(0, 2378), c(1, 1), c(2, 0)];
        // Large near ties: 114243^2 - 2 * 80782^2 = -1 ... scaled into big counts.
        pairs.extend([c(114_243, 0), c(0, 80_782), c(1 << 26, 7), c(7, 1 << 26)]);
        for a in 0..40 {
            for d in 0..30 {
                pairs.push(c(a, d));
            }
        }
        for &p in &pairs {
            for &q in &pairs {
                let exact = p.cmp_length(q);
                assert_eq!(exact, q.cmp_length(p).reverse());
                assert_eq!(fixed_length(p).cmp(&fixed_length(q)), exact, "{p:?} {q:?}");
                assert_eq!(exact == Ordering::Equal, p == q);
                // f64 agrees where the values are far apart.
                if (p.length() - q.length()).abs() > 1e-6 {
                    assert_eq!(p.length().partial_cmp(&q.length()), Some(exact));
                }
            }
        }
        assert!(c(99, 0) > c(0, 70)); // 99 > 70 sqrt 2 = 98.9949...
        assert!(StepCost::INF > c(u32::MAX - 1, u32::MAX - 1));
        assert!(!c(1, 0).add(StepCost::INF).is_finite());
    }

    /// The narrow keys' lengths order exactly like the exact comparison up to
    /// [`NARROW_MAX_STEPS`], on the nearest ties there are (Pell pairs up to a million
    /// steps: `665857^2 - 2 * 470832^2 = 1`), and refuse larger counts.
    #[test]
    fn narrow_lengths_order_exactly_up_to_their_limit() {
        let c = |straight, diagonal| StepCost {
            straight,
            diagonal,
            weight: 0,
        };
        let max = NARROW_MAX_STEPS;
        let mut pairs = vec![c(0, 0), c(1, 0), c(0, 1), c(max, max), c(max, 0), c(0, max)];
        // Pell pairs (x, y) with x^2 - 2 y^2 = +-1: x straight against y diagonal steps.
        for (x, y) in [
            (3, 2),
            (7, 5),
            (99, 70),
            (3363, 2378),
            (114_243, 80_782),
            (665_857, 470_832),
        ] {
            pairs.extend([c(x, 0), c(0, y), c(x + 1, 0), c(x - 1, 0), c(0, y + 1)]);
            // The same near tie shifted to large common counts.
            pairs.extend([c(x + max - 665_857, max - y), c(max, max - y)]);
            pairs.extend([c(max - x, y), c(max - x, 0), c(max, y)]);
        }
        for a in (0..max).step_by(99_991) {
            for d in (0..max).step_by(77_773) {
                pairs.push(c(a, d));
            }
        }
        for &p in &pairs {
            for &q in &pairs {
                let (np, nq) = (narrow_length(p).unwrap(), narrow_length(q).unwrap());
                assert_eq!(np.cmp(&nq), p.cmp_length(q), "{p:?} {q:?}");
            }
        }
        assert_eq!(narrow_length(StepCost::INF), Some(u64::MAX));
        assert_eq!(narrow_length(c(max + 1, 0)), None);
        assert_eq!(narrow_length(c(0, max + 1)), None);
        assert!(narrow_length(c(max, max)).unwrap() < u64::MAX);
        // The rounded sqrt 2 against the 2^-64 one.
        let scaled = u128::from(SQRT_2_NARROW) << 22;
        assert!(scaled.abs_diff(SQRT_2_FIXED) <= 1 << 21);
        // Tie weights do not fit a narrow key; infinite costs do.
        assert!(NarrowKey::new(StepCost::step(false, 1), StepCost::ZERO).is_none());
        assert_eq!(
            NarrowKey::new(StepCost::INF, StepCost::INF),
            Some(NarrowKey::MAX)
        );
    }

    /// Tie keys order like the wide keys (lengths exactly, then the weight) and refuse parts
    /// of different weights.
    #[test]
    fn tie_keys_order_like_wide_keys() {
        let c = |straight, diagonal, weight| StepCost {
            straight,
            diagonal,
            weight,
        };
        let h = StepCost::octile(7, 3);
        let mut parts = vec![StepCost::INF];
        for (s, d) in [
            (0, 0),
            (99, 0),
            (0, 70),
            (3, 1),
            (4, 0),
            (665_857, 0),
            (0, 470_832),
        ] {
            for w in [0, 1, 5, u64::from(u32::MAX) * 3] {
                parts.push(c(s, d, w));
            }
        }
        let keys: Vec<(Option<TieKey>, WideKey)> = parts
            .iter()
            .map(|&m| {
                let k1 = m.add(h);
                (TieKey::new(k1, m), WideKey::new(k1, m).unwrap())
            })
            .collect();
        for (a, wa) in &keys {
            for (b, wb) in &keys {
                assert_eq!(a.unwrap().cmp(&b.unwrap()), wa.cmp(wb), "{wa:?} {wb:?}");
            }
        }
        assert!(TieKey::new(c(5, 0, 1), c(1, 0, 2)).is_none());
        assert!(TieKey::new(c(5, 0, 1), StepCost::INF).is_none());
        assert!(TieKey::new(c(NARROW_MAX_STEPS + 1, 0, 0), c(0, 0, 0)).is_none());
    }
}

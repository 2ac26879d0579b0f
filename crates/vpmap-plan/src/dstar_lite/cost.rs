//! D* Lite's path costs: exact counts of straight and diagonal steps plus, under the common
//! tie rule, a sum of tie weights ([`StepCost`]); the cells' [`tie_weight`]s; and the 128-bit
//! packing the per-cell arrays store them in.

use std::cmp::Ordering;
use std::f64::consts::SQRT_2;

/// A path cost: exact counts of straight and diagonal steps (length
/// `straight + diagonal * sqrt 2` cells) and, under the common tie rule, the sum of the entered cells'
/// [`tie_weight`]s. Ordered by length (exactly), then by weight. [`StepCost::INF`] is
/// larger than every finite cost.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct StepCost {
    /// Straight steps (`u32::MAX`: infinite).
    pub(crate) straight: u32,
    /// Diagonal steps.
    pub(crate) diagonal: u32,
    /// Sum of tie weights.
    pub(crate) weight: u64,
}

impl StepCost {
    /// Zero.
    pub(crate) const ZERO: Self = Self {
        straight: 0,
        diagonal: 0,
        weight: 0,
    };
    /// Infinite: no path.
    pub(crate) const INF: Self = Self {
        straight: u32::MAX,
        diagonal: u32::MAX,
        weight: u64::MAX,
    };

    /// Whether the cost is finite.
    #[inline]
    pub(crate) fn is_finite(self) -> bool {
        self.straight != u32::MAX
    }

    /// The sum (infinite when either is).
    #[inline]
    pub(crate) fn add(self, other: Self) -> Self {
        if !self.is_finite() || !other.is_finite() {
            return Self::INF;
        }
        Self {
            straight: self
                .straight
                .saturating_add(other.straight)
                .min(u32::MAX - 1),
            diagonal: self.diagonal.saturating_add(other.diagonal),
            weight: self.weight.saturating_add(other.weight),
        }
    }

    /// One step: straight or diagonal, entering a cell of tie weight `weight`.
    #[inline]
    pub(crate) fn step(diagonal: bool, weight: u32) -> Self {
        Self {
            straight: u32::from(!diagonal),
            diagonal: u32::from(diagonal),
            weight: u64::from(weight),
        }
    }

    /// The octile distance between two cells (weight 0: a lower bound of every path's
    /// cost, and consistent).
    #[inline]
    pub(crate) fn octile(dx: usize, dy: usize) -> Self {
        let (long, short) = if dx >= dy { (dx, dy) } else { (dy, dx) };
        Self {
            straight: u32::try_from(long - short).unwrap_or(u32::MAX - 1),
            diagonal: u32::try_from(short).unwrap_or(u32::MAX - 1),
            weight: 0,
        }
    }

    /// Length, cells (exact to the last bit for equal step counts: like A*'s).
    #[inline]
    pub(crate) fn length(self) -> f64 {
        f64::from(self.straight) + f64::from(self.diagonal) * SQRT_2
    }

    /// Compare the lengths exactly: `s1 + d1 sqrt 2` against `s2 + d2 sqrt 2` as the sign
    /// of `x - y sqrt 2` with `x = s1 - s2`, `y = d2 - d1`, which is never zero unless both
    /// are (`sqrt 2` is irrational).
    #[inline]
    pub(crate) fn cmp_length(self, other: Self) -> Ordering {
        match (self.is_finite(), other.is_finite()) {
            (false, false) => return Ordering::Equal,
            (false, true) => return Ordering::Greater,
            (true, false) => return Ordering::Less,
            (true, true) => {}
        }
        let x = i64::from(self.straight) - i64::from(other.straight);
        let y = i64::from(other.diagonal) - i64::from(self.diagonal);
        match (x.signum(), y.signum()) {
            (0, 0) => Ordering::Equal,
            (sx, sy) if sx >= 0 && sy <= 0 => Ordering::Greater,
            (sx, sy) if sx <= 0 && sy >= 0 => Ordering::Less,
            (sx, _) => {
                // Same signs: compare x^2 with 2 y^2.
                let x2 = u128::from(x.unsigned_abs()) * u128::from(x.unsigned_abs());
                let y2 = 2 * u128::from(y.unsigned_abs()) * u128::from(y.unsigned_abs());
                if (x2 > y2) == (sx > 0) {
                    Ordering::Greater
                } else {
                    Ordering::Less
                }
            }
        }
    }
}

impl Ord for StepCost {
    #[inline]
    fn cmp(&self, other: &Self) -> Ordering {
        self.cmp_length(*other)
            .then_with(|| self.weight.cmp(&other.weight))
    }
}

impl PartialOrd for StepCost {
    #[inline]
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

/// The tie weight of cell `(x, y)`: a fixed pseudo-random 32-bit number (the SplitMix64
/// finaliser of the cell's coordinates), the same for every map and planner.
#[must_use]
pub fn tie_weight(x: usize, y: usize) -> u32 {
    let mut z = (x as u64) ^ ((y as u64) << 32) ^ 0x9e37_79b9_7f4a_7c15;
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    (z ^ (z >> 31)) as u32
}

/// A [`StepCost`] packed in 128 bits, zero for [`StepCost::INF`] (so that the per-cell
/// arrays start as zeroed memory, which the allocator hands out without writing it):
/// `straight + 1`, `diagonal`, `weight` from the top.
#[inline]
pub(super) fn pack(c: StepCost) -> u128 {
    if c.is_finite() {
        (u128::from(c.straight + 1) << 96) | (u128::from(c.diagonal) << 64) | u128::from(c.weight)
    } else {
        0
    }
}

/// The [`StepCost`] of [`pack`]ed bits.
#[inline]
pub(super) fn unpack(p: u128) -> StepCost {
    if p == 0 {
        StepCost::INF
    } else {
        StepCost {
            straight: ((p >> 96) as u32).wrapping_sub(1),
            diagonal: (p >> 64) as u32,
            weight: p as u64,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tie_weights_are_fixed_and_spread() {
        assert_eq!(tie_weight(3, 4), tie_weight(3, 4));
        assert_ne!(tie_weight(3, 4), tie_weight(4, 3));
        let mut w: Vec<u32> = (0..64)
            .flat_map(|y| (0..64).map(move |x| tie_weight(x, y)))
            .collect();
        w.sort_unstable();
        w.dedup();
        assert_eq!(w.len(), 64 * 64);
        // Roughly uniform: the median near 2^31.
        let median = f64::from(w[w.len() / 2]) / f64::from(u32::MAX);
        assert!((median - 0.5).abs() < 0.05, "{median}");
    }
}

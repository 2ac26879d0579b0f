//! Choices between placements that are functions of the room, not of the order its photos
//! 2..n are listed in.
//!
//! Two placements that reproduce the clicks equally well (a photo tied by one box, either half
//! turn about the box's centre reproducing exact clicks exactly) have joint-fit costs that
//! differ by float noise only, and that noise follows the order the photos are listed in (the
//! order of the sums, of the unknowns, of the minimiser's steps). So costs are compared only
//! beyond their numerical noise ([`same_cost`]), and what remains is decided by a key of the
//! placement that does not depend on the order ([`PhotoKeys::placement`]): each photo's
//! quarter turn against photo 1's room directions (numbered from the two photos' own vanishing
//! points, so a function of those two photos alone), keyed by the photo's own content.

use crate::scene::Scene;

/// Relative part of [`same_cost`]'s tolerance. The minimiser stops when a step gains at most
/// `1e-14` of the cost or moves the parameters by at most `1e-13` of their size
/// (`fit/solve.rs`), and a sum of `m` squares carries about `m` ulps (`1e-16`) of rounding:
/// the cost of one converged placement is known to about `1e-13` of itself. `1e-9` is ten
/// thousand times that, and as a difference of chi-square (`1e-9` of `m` click variances) no
/// likelihood can tell it from nothing for any room the fit takes.
pub(super) const COST_RELATIVE_TOLERANCE: f64 = 1e-9;

/// Absolute part of [`same_cost`]'s tolerance, squared pixels per residual: `(1e-6 px)^2`.
/// Exact clicks leave a cost of rounding alone, about `1e-20` px^2 a residual (a residual of
/// `1e-10` px: a step of `1e-13` of a parameter through the image's `1e3` px per unit); a
/// millionth of a pixel is ten thousand times that and a ten-thousandth of the finest click
/// (`0.01` px).
pub(super) const COST_PER_RESIDUAL_TOLERANCE_PX2: f64 = 1e-12;

/// Whether two joint-fit costs (squared pixels, of fits of `residuals` residuals) are equal
/// to within their numerical noise: `|a - b| <= residuals` [`COST_PER_RESIDUAL_TOLERANCE_PX2`]
/// `+` [`COST_RELATIVE_TOLERANCE`] `max(a, b)`.
pub(super) fn same_cost(a: f64, b: f64, residuals: usize) -> bool {
    (a - b).abs()
        <= residuals as f64 * COST_PER_RESIDUAL_TOLERANCE_PX2
            + COST_RELATIVE_TOLERANCE * a.abs().max(b.abs())
}

/// Absolute tolerance of two placement hypotheses' scores (`room/hypotheses.rs`, roughly
/// squared pixels of click noise), squared pixels: the score is a difference of sums of
/// weighted squares of up to `1e9` px^2, which rounding leaves about `1e-7` px^2 uncertain
/// (exact ties measured `0` to `2e-9` px^2 apart); `1e-4` is above that and far below what
/// tells hypotheses apart (the starts are taken within 25 px^2 of the best).
pub(super) const SCORE_TOLERANCE_PX2: f64 = 1e-4;

/// Whether two placement hypotheses' scores (squared pixels) are equal to within their
/// numerical noise: `|a - b| <=` [`SCORE_TOLERANCE_PX2`] `+` [`COST_RELATIVE_TOLERANCE`]
/// `max(a, b)`.
pub(super) fn same_score(a: f64, b: f64) -> bool {
    (a - b).abs() <= SCORE_TOLERANCE_PX2 + COST_RELATIVE_TOLERANCE * a.abs().max(b.abs())
}

/// Each photo's identity in the room: its annotations as the room file gives them (its JSON:
/// image size, vanishing points, objects and their clicks, floor, scale, pins), which a room
/// file does not otherwise name. Two photos with the same key are the same annotations, and
/// exchanging them changes nothing.
pub(crate) struct PhotoKeys(Vec<String>);

impl PhotoKeys {
    /// The keys of `scene`'s photos, in photo order.
    pub fn new(scene: &Scene) -> Self {
        Self(
            scene
                .photos()
                .map(|p| serde_json::to_string(p).unwrap_or_default())
                .collect(),
        )
    }

    /// Photo `k`'s key (empty past the last photo).
    pub fn photo(&self, k: usize) -> &str {
        self.0.get(k).map_or("", String::as_str)
    }

    /// Each photo's rank among the keys: how many photos have a lesser key (equal keys, equal
    /// ranks). Ranks order as the keys do, so [`Self::placement`] with ranks in place of keys
    /// orders placements alike, without comparing the keys' long strings each time.
    pub fn ranks(&self) -> Vec<usize> {
        self.0
            .iter()
            .map(|k| self.0.iter().filter(|o| *o < k).count())
            .collect()
    }

    /// A placement's key, the same for every order of photos 2..n: each photo after the
    /// first as its key and its quarter turn (`quarters[k]`), sorted.
    pub fn placement(&self, quarters: &[u8]) -> Vec<(&str, u8)> {
        let mut key: Vec<(&str, u8)> = quarters
            .iter()
            .enumerate()
            .skip(1)
            .map(|(k, &q)| (self.photo(k), q))
            .collect();
        key.sort_unstable();
        key
    }
}

/// Of `candidates`, the one of least `cost` (squared pixels, of fits of `residuals`
/// residuals) beyond [`same_cost`]'s tolerance; among those of the least cost within it, the
/// one of least `key`. `None` without candidates.
pub(super) fn least<K: Ord>(
    candidates: impl IntoIterator<Item = usize>,
    cost: impl Fn(usize) -> f64,
    residuals: usize,
    key: impl Fn(usize) -> K,
) -> Option<usize> {
    let candidates: Vec<usize> = candidates.into_iter().collect();
    let best = candidates.iter().map(|&i| cost(i)).min_by(f64::total_cmp)?;
    candidates
        .into_iter()
        .filter(|&i| same_cost(cost(i), best, residuals))
        .min_by_key(|&i| key(i))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn costs_float_noise_apart_are_the_same_and_a_hundredth_of_a_click_variance_is_not() {
        // Exact clicks: two fits of 400 residuals at 1e-24 and 3e-22 px^2.
        assert!(same_cost(1e-24, 3e-22, 400));
        // Noisy clicks: 400 residuals of 1 px, 1e-12 of the cost apart.
        assert!(same_cost(400.0, 400.0 * (1.0 + 1e-12), 400));
        // A hundredth of a 1 px click variance apart is a real difference.
        assert!(!same_cost(400.0, 400.01, 400));
        assert!(!same_cost(0.0, 0.01, 400));
    }

    #[test]
    fn scores_float_noise_apart_are_the_same_and_a_hundredth_of_a_pixel_squared_is_not() {
        // Exact ties measured 0 to 2e-9 px^2 apart.
        assert!(same_score(0.0, 2e-9));
        assert!(same_score(1e6, 1e6 * (1.0 + 1e-12)));
        assert!(!same_score(0.0, 0.01));
        assert!(!same_score(30.0, 30.01));
    }

    #[test]
    fn ranks_order_photos_as_their_keys_and_equal_keys_share_one() {
        let keys = PhotoKeys(vec!["c".into(), "a".into(), "b".into(), "a".into()]);
        assert_eq!(keys.ranks(), vec![3, 0, 2, 0]);
    }

    #[test]
    fn the_least_cost_wins_beyond_the_tolerance_and_the_least_key_within_it() {
        let costs = [2.0, 1.0 + 1e-12, 1.0, 1.5];
        let keys = ["c", "a", "b", "0"];
        assert_eq!(least(0..4, |i| costs[i], 10, |i| keys[i]), Some(1));
        assert_eq!(least([0, 2, 3], |i| costs[i], 10, |i| keys[i]), Some(2));
        assert_eq!(least([], |i| costs[i], 10, |i| keys[i]), None);
    }
}

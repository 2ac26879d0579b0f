//! The analytic connections between two poses that [`super::fillet`] and
//! [`super::hybrid`] try, shortest first: forward only, the six Dubins words
//! ([`super::dubins`]); with reverse allowed, those and the [`SLOTS`] Reeds-Shepp candidates
//! ([`super::reeds_shepp`]), whose shortest is never longer than the shortest Dubins word.
//! A word is named by its index: `0..6` the Dubins words, `6..` the Reeds-Shepp ones.

use super::curve::{Pose, SmoothCurve};
use super::dubins::{WORDS, dubins_distance, word_curve, word_table};
use super::reeds_shepp::{SLOTS, rs_distance, rs_slot_curve, rs_table};

/// How many words there are with reverse allowed.
pub const MAX_WORDS: usize = WORDS.len() + SLOTS;

/// How many words there are: [`MAX_WORDS`] with reverse allowed, six without.
#[must_use]
pub const fn word_count(reverse: bool) -> usize {
    if reverse { MAX_WORDS } else { WORDS.len() }
}

/// The lengths (cells) of the words from `from` to `to`, infinite for a word with no
/// solution and for every Reeds-Shepp word when `reverse` is off. A finite Reeds-Shepp
/// entry is a candidate: [`curve`] may still find its curve ends elsewhere (round-off at a
/// formula's edge) and return `None`.
#[must_use]
pub fn table(from: Pose, to: Pose, radius: f64, reverse: bool) -> [f64; MAX_WORDS] {
    let mut out = [f64::INFINITY; MAX_WORDS];
    let (dubins, rs) = out.split_at_mut(WORDS.len());
    dubins.copy_from_slice(&word_table(from, to, radius));
    if reverse {
        rs.copy_from_slice(&rs_table(from, to, radius));
    }
    out
}

/// The curve of word `index` from `from` to `to` (`None` when it has none).
#[must_use]
pub fn curve(from: Pose, to: Pose, radius: f64, index: usize) -> Option<SmoothCurve> {
    match index.checked_sub(WORDS.len()) {
        None => word_curve(from, to, radius, index),
        Some(slot) => rs_slot_curve(from, to, radius, slot),
    }
}

/// The length of the shortest connection, cells: the Dubins distance, or with reverse the
/// Reeds-Shepp distance (a lower bound of any path when reverse is allowed, which the
/// Dubins distance is not).
#[must_use]
pub fn distance(from: Pose, to: Pose, radius: f64, reverse: bool) -> f64 {
    if reverse {
        rs_distance(from, to, radius)
    } else {
        dubins_distance(from, to, radius)
    }
}

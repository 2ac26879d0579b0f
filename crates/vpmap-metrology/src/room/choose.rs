//! Choosing among a room's converged placements: ties the clicks leave open broken by the
//! physical checks (`room/checks.rs`) and said when they remain (a warning, an alternative),
//! exact ties by a choice that no order of the photos changes (`room/canonical.rs`);
//! the consistency test (`room/consistency.rs`) refusing a room whose photos do not fit
//! together, naming the photos, the objects and the best other placement; and the refusal of
//! a room none of whose placements converged.

use super::align::PhotoFit;
use super::canonical::{PhotoKeys, least, same_score};
use super::checks::{OVERLAP_SHARE, physical};
use super::consistency;
use super::fit::{RoomAlternative, Solved, solve};
use super::hypotheses::{Hypothesis, Ties};
use crate::error::{MetrologyError, Result};
use crate::fit::solve::Model;
use crate::interrupt::Interrupt;
use crate::scene::Scene;

/// The chi-square difference (in click variances) under which two hypotheses fit about
/// equally.
const TIE_CHI2: f64 = 4.0;

/// The refusal of a room none of whose placements converged: by the consistency test's names
/// when the photos are far from fitting together (the least-cost unconverged fit, costs within
/// their numerical noise by the placement key, so that no order of the photos changes which),
/// else the fit's failure, else the first error met in the starts' order (`failure`).
pub(super) fn refuse_unconverged(
    fits: &[PhotoFit],
    keys: &PhotoKeys,
    unconverged: &[Solved],
    failure: Option<MetrologyError>,
) -> MetrologyError {
    // A fit that did not converge: refused, by the consistency test's names when its
    // photos are far from fitting together.
    let residuals = unconverged
        .iter()
        .map(|u| u.built.problem.residual_count())
        .max()
        .unwrap_or(0);
    let pick = least(
        0..unconverged.len(),
        |i| unconverged[i].cost,
        residuals,
        |i| keys.placement(&unconverged[i].quarters),
    );
    if let Some(u) = pick.and_then(|i| unconverged.get(i)) {
        let rms = (u.cost / u.built.problem.residual_count().max(1) as f64).sqrt();
        let test = consistency::test(fits, &u.built.problem, &u.x, &u.built.names);
        let objects: Vec<Vec<String>> = fits
            .iter()
            .map(|f| f.objects.iter().map(|o| o.name.clone()).collect())
            .collect();
        return if test.refused() {
            consistency::refusal(
                &test,
                Some(format!(
                    "the joint fit did not converge in {} iterations ({rms:.3} px RMS) from any placement",
                    u.iterations
                )),
                &objects,
            )
        } else {
            MetrologyError::Degenerate {
                field: "photos".to_owned(),
                reason: format!(
                    "the room fit did not converge in {} iterations (reprojection error {rms:.3} px RMS): check that objects named the same in several photos are the same object",
                    u.iterations
                ),
            }
        };
    }
    failure.unwrap_or_else(|| MetrologyError::Degenerate {
        field: "photos".to_owned(),
        reason: "no placement of the room's photos".to_owned(),
    })
}

/// Whether hypothesis `h` turns photo `k` otherwise than `quarters` and every other photo as
/// they do.
fn other_turn_of(h: &Hypothesis, quarters: &[u8], k: usize) -> bool {
    quarters.iter().enumerate().all(|(m, &q)| {
        let own = h.quarters.get(m).copied().flatten().unwrap_or(0);
        if m == k { own != q } else { own == q }
    })
}

/// Of the beam's hypotheses `all`, the one that turns photo `k` otherwise than `quarters` and
/// every other photo as they do, of the least score beyond [`same_score`]'s tolerance (a
/// rectangle's other half turn before its quarter turns), then of photo `k`'s least turn (a
/// square box's turns tied exactly): the same for every order of the photos.
pub(super) fn flip_start<'a>(
    all: &'a [Hypothesis],
    quarters: &[u8],
    k: usize,
) -> Option<&'a Hypothesis> {
    let turns: Vec<&Hypothesis> = all
        .iter()
        .filter(|h| other_turn_of(h, quarters, k))
        .collect();
    let best = turns.iter().map(|h| h.score).min_by(f64::total_cmp)?;
    let near = |h: &&&Hypothesis| same_score(h.score, best);
    turns
        .iter()
        .filter(near)
        .min_by_key(|h| h.quarters.get(k).copied().flatten())
        .copied()
}

/// Of the placements `candidates` (indices into `results`), those with the fewest
/// `violations` (all, without), then the least cost beyond its numerical noise, then the
/// least placement key (`room/canonical.rs`): a function of the room, not of the order its
/// photos are listed in.
fn preferred(
    results: &[Solved],
    violations: Option<&[usize]>,
    candidates: impl Iterator<Item = usize>,
    keys: &PhotoKeys,
) -> Option<usize> {
    let candidates: Vec<usize> = candidates.filter(|&i| i < results.len()).collect();
    let count = |i: usize| violations.map_or(0, |v| v.get(i).copied().unwrap_or(usize::MAX));
    let fewest = candidates.iter().map(|&i| count(i)).min()?;
    let residuals = results
        .first()
        .map_or(0, |r| r.built.problem.residual_count());
    least(
        candidates.into_iter().filter(|&i| count(i) == fewest),
        |i| results[i].cost,
        residuals,
        |i| keys.placement(&results[i].quarters),
    )
}

/// Whether `a` places photo `k` otherwise than `b` and every other photo as `b` does.
fn differs_only_in(a: &Solved, b: &Solved, k: usize) -> bool {
    a.quarters.len() == b.quarters.len()
        && a.quarters
            .iter()
            .zip(&b.quarters)
            .enumerate()
            .all(|(m, (p, q))| (m == k) != (p == q))
}

/// Most rounds of [`break_ties`]'s search for a placement the physical checks favour.
const MAX_TIE_ROUNDS: usize = 8;

/// Hypotheses (`results`, converged, sorted by cost) that fit about equally: the likelihood
/// cannot choose, so the walls do (the one that keeps every camera and floor inside every
/// photo's walls), and the build says so. Between equal violation counts the lower cost wins
/// only beyond its numerical noise, then the least placement key (`room/canonical.rs`): the
/// chosen placement and the alternative said are the same for every order of photos 2..n. The chosen one is put first; the ties no check
/// decides are returned as alternatives, and every tie is said in `warnings`.
///
/// A photo's tie is judged against the chosen placement with that photo alone turned
/// otherwise (`flip` fits it from the beam's hypothesis when the started ones do not hold it;
/// at most one joint fit per photo and round), so that the checks' counts differ by what that
/// photo's turn does, not by other photos placed otherwise too; a turn the checks favour is
/// taken and the photos are looked at again (the violations fall every round, at most
/// [`MAX_TIE_ROUNDS`]). Without such a placement, the most likely tied one that places the
/// photo otherwise is the comparison.
pub(super) fn break_ties(
    scene: &Scene,
    fits: &[PhotoFit],
    ties: &Ties,
    results: &mut Vec<Solved>,
    variance: f64,
    warnings: &mut Vec<String>,
    flip: &mut dyn FnMut(&Solved, usize) -> Option<Solved>,
) -> Vec<RoomAlternative> {
    let n = fits.len();
    let best_cost = results.first().map_or(0.0, |r| r.cost);
    let in_tie = |r: &Solved| (r.cost - best_cost) / variance < TIE_CHI2;
    let mut tied = results.iter().take_while(|r| in_tie(r)).count();
    let mut alternatives = Vec::new();
    if tied <= 1 {
        return alternatives;
    }
    let count = |r: &Solved| {
        physical(
            scene,
            &r.built.problem,
            &r.x,
            &r.built.names,
            Some(variance),
        )
        .total()
    };
    let keys = PhotoKeys::new(scene);
    let mut violations: Vec<usize> = results[..tied].iter().map(count).collect();
    let pick = preferred(results, Some(&violations), 0..tied, &keys).unwrap_or(0);
    results.swap(0, pick);
    violations.swap(0, pick);
    let mut tried: Vec<Vec<u8>> = results[..tied].iter().map(|r| r.quarters.clone()).collect();
    for _ in 0..MAX_TIE_ROUNDS {
        for k in 1..n {
            if (1..tied).any(|j| differs_only_in(&results[j], &results[0], k)) {
                continue;
            }
            let Some(s) = flip(&results[0], k) else {
                continue;
            };
            if tried.contains(&s.quarters) || !in_tie(&s) {
                continue;
            }
            tried.push(s.quarters.clone());
            violations.insert(tied, count(&s));
            results.insert(tied, s);
            tied += 1;
        }
        // A placement differing in one photo that the checks favour is taken.
        let better = preferred(
            results,
            Some(&violations),
            (1..tied)
                .filter(|&j| violations[j] < violations[0])
                .filter(|&j| (1..n).any(|k| differs_only_in(&results[j], &results[0], k))),
            &keys,
        );
        let Some(j) = better else { break };
        results.swap(0, j);
        violations.swap(0, j);
    }
    // The rest by cost again (the refusal names the best other placement first).
    let mut rest: Vec<(Solved, usize)> = results
        .drain(1..)
        .zip(violations.drain(1..).chain(std::iter::repeat(usize::MAX)))
        .collect();
    rest.sort_by(|a, b| a.0.cost.total_cmp(&b.0.cost));
    tied = 1 + rest.iter().filter(|(r, _)| in_tie(r)).count();
    for (r, v) in rest {
        results.push(r);
        violations.push(v);
    }
    let chosen = &results[0];
    // Photo by photo: the placement that turns it alone otherwise, else the most likely of the
    // tied that places it otherwise (the runner-up of the whole room may differ in other
    // photos only, and a photo whose other turn fits as well must still be said).
    for k in 1..n {
        let other = |j: &usize| results[*j].quarters[k] != chosen.quarters[k];
        let only = (1..tied).filter(|&j| differs_only_in(&results[j], chosen, k));
        let Some(j) = preferred(results, None, only, &keys)
            .or_else(|| preferred(results, None, (1..tied).filter(other), &keys))
        else {
            continue;
        };
        let second = &results[j];
        let decided = violations[0] < violations[j];
        let turn = (4 + i32::from(second.quarters[k]) - i32::from(chosen.quarters[k])) % 4 * 90;
        let shared = ties.shared_by(k);
        warnings.push(format!(
            "photo {} is tied to the room only by {}, which fit{} about as well with photo {} turned by {turn} degrees (cost {:.3} against {:.3} px^2): {}; to be sure, name one more object seen in photo {} and another photo",
            k + 1,
            quoted(&shared),
            if shared.len() == 1 { "s" } else { "" },
            k + 1,
            second.cost,
            chosen.cost,
            if decided {
                format!(
                    "the map takes the turn the room's physical checks favour ({} violations against {}: cameras, floor corners and boxes inside the walls the photos' floor outlines show, boxes not overlapping, no camera inside a box)",
                    violations[0], violations[j]
                )
            } else {
                "the map uses the better one".to_owned()
            },
            k + 1
        ));
        if !decided {
            alternatives.push(RoomAlternative {
                photo: k,
                turn_deg: turn,
                placement_turn_deg: i32::from(second.quarters[k]) * 90,
                cost_px2: second.cost,
                chosen_cost_px2: chosen.cost,
            });
        }
    }
    alternatives
}

/// Refuse the room when the chosen placement `best` fails the consistency test, naming the
/// best other placement (`results`, the other converged ones; else the best other hypothesis
/// of `all`, fitted now; else the least-cost unconverged fit).
#[allow(clippy::too_many_arguments)]
pub(super) fn refuse_if_inconsistent(
    scene: &Scene,
    fits: &[PhotoFit],
    order: &[usize],
    all: &[Hypothesis],
    best: &Solved,
    results: Vec<Solved>,
    unconverged: Vec<Solved>,
    interrupt: &Interrupt,
) -> Result<()> {
    let n = fits.len();
    let test = consistency::test(fits, &best.built.problem, &best.x, &best.built.names);
    if test.refused() {
        // The best other placement (the least cost, as `break_ties` chooses), fitted if it
        // was not.
        let mut others: Vec<Solved> = results
            .into_iter()
            .filter(|r| r.quarters != best.quarters)
            .collect();
        let mut other = preferred(&others, None, 0..others.len(), &PhotoKeys::new(scene))
            .map(|i| others.swap_remove(i));
        if other.is_none()
            && let Some(h) = all.iter().find(|h| {
                h.quarters
                    .iter()
                    .map(|q| q.unwrap_or(0))
                    .ne(best.quarters.iter().copied())
            })
        {
            other = solve(scene, fits, order, h, false, interrupt).ok();
        }
        if other.is_none() {
            other = unconverged
                .into_iter()
                .min_by(|a, b| a.cost.total_cmp(&b.cost));
        }
        let alternative = other.map(|o| {
            let turns: Vec<String> = (1..n)
                .filter(|&k| o.quarters[k] != best.quarters[k])
                .map(|k| {
                    let turn = (4 + i32::from(o.quarters[k]) - i32::from(best.quarters[k])) % 4 * 90;
                    format!("photo {} turned by {turn} degrees", k + 1)
                })
                .collect();
            format!(
                "the best other placement ({}) fits worse or no better: cost {:.3} against {:.3} px^2",
                turns.join(", "),
                o.cost,
                best.cost
            )
        });
        let objects: Vec<Vec<String>> = fits
            .iter()
            .map(|f| f.objects.iter().map(|o| o.name.clone()).collect())
            .collect();
        return Err(consistency::refusal(&test, alternative, &objects));
    }
    Ok(())
}

/// The chosen map's cameras that stand inside an object (`room/checks.rs`: deeper than
/// [`OVERLAP_SHARE`] of the box's size from its edges), each said by name: a camera cannot
/// stand inside an object, so the map is wrong there (a box named the same in two photos that
/// is not one box, or a pinned placement the room does not have), though its clicks fit.
pub(super) fn cameras_inside_objects(scene: &Scene, best: &Solved) -> Vec<String> {
    let pinned = scene.placement_pins().iter().any(Option::is_some);
    physical(scene, &best.built.problem, &best.x, &best.built.names, None)
        .cameras_inside
        .iter()
        .map(|(k, name)| {
            format!(
                "photo {}'s camera stands inside object {name:?} on this map (more than {:.0} % of the box's size inside its edges), which no real room allows: check that the objects photo {} shares with the other photos are the same objects{}",
                k + 1,
                OVERLAP_SHARE * 100.0,
                k + 1,
                if pinned {
                    ", and the `placement_turn_deg` that pins a photo's placement"
                } else {
                    ""
                }
            )
        })
        .collect()
}

fn quoted(names: &[String]) -> String {
    let q: Vec<String> = names.iter().map(|n| format!("{n:?}")).collect();
    match q.len() {
        0 => "no object".to_owned(),
        1 => format!("object {}", q[0]),
        _ => format!("objects {}", q.join(", ")),
    }
}

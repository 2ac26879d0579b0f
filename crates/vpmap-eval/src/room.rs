//! Rooms of several photos: `vpmap eval --photos N`. Per number of photos and noise level,
//! `trials` synthetic rooms ([`vpmap_metrology::synth::synthesize_room`]) are mapped jointly
//! and from their first photo alone, and each shared object also from every photo that shows
//! it alone ([`vpmap_metrology::eval::run_room_trial`], whose documentation says what is
//! measured and how); the rooms run in parallel (rayon), each room's seed depends only on
//! (seed, photos, trial).
//!
//! The report ([`room_report`]) is one Markdown table per noise level: per number of photos the
//! objects' position and size errors (median and 95th percentile, metres), the 95 % ellipses'
//! coverage, the share of the room's floor known (median, and the share of rooms with at least
//! 90 % known), each beside the first photo alone, the share the true cameras see (the most a
//! map can know), and the share of shared objects whose joint
//! position error is below the better of their single-photo errors (also for the joint map
//! given every camera height, as the photos alone are, and per listing photo in its own
//! frame); then issue 39's placement figures (the joint maps are given photos 2..n in a
//! shuffled order: silent wrong maps, ties said and resolved right, ellipse coverage); then the
//! issue's targets, met or not. [`room_csv`] has one row per object, map and noise level.

use std::fmt::Write as _;

use rayon::prelude::*;
use vpmap_metrology::eval::{
    RoomMapErrors, RoomObjectErrors, RoomTrial, RoomTrialOptions, SharedObject, run_room_trial,
};

use crate::progress::Progress;
use crate::stats::quantile_of;

/// The section of `docs/results.md` the room evaluation publishes.
pub const ROOM_SECTION: &str = "eval-rooms";

/// Options of [`run_rooms`].
#[derive(Debug, Clone, PartialEq)]
pub struct RoomEvalOptions {
    /// Rooms per number of photos.
    pub trials: u64,
    /// Seed of the run.
    pub seed: u64,
    /// Numbers of photos, each 1 to [`vpmap_metrology::synth::MAX_ROOM_PHOTOS`].
    pub photos: Vec<usize>,
    /// Noise levels, pixels.
    pub sigmas_px: Vec<f64>,
    /// Boxes per room.
    pub boxes: usize,
}

impl Default for RoomEvalOptions {
    fn default() -> Self {
        Self {
            trials: 100,
            seed: 0,
            photos: vec![1, 2, 3, 4],
            sigmas_px: vec![0.5, 1.0, 2.0],
            boxes: 6,
        }
    }
}

/// Run every room trial: one list per number of photos, in the order of `options.photos`.
#[must_use]
pub fn run_rooms(options: &RoomEvalOptions, progress: &dyn Progress) -> Vec<Vec<RoomTrial>> {
    let work: Vec<(usize, u64)> = options
        .photos
        .iter()
        .flat_map(|&n| (0..options.trials).map(move |t| (n, t)))
        .collect();
    progress.start(work.len() as u64);
    let done: Vec<RoomTrial> = work
        .par_iter()
        .map(|&(photos, t)| {
            let trial = run_room_trial(
                options.seed,
                t,
                &RoomTrialOptions {
                    photos,
                    boxes: options.boxes,
                    sigmas_px: options.sigmas_px.clone(),
                },
            );
            progress.step();
            trial
        })
        .collect();
    progress.finish();
    options
        .photos
        .iter()
        .map(|&n| done.iter().filter(|t| t.photos == n).cloned().collect())
        .collect()
}

/// What one number of photos and one noise level gave.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RoomRow {
    /// Rooms mapped jointly.
    pub rooms: usize,
    /// Rooms the joint fit refused (or that could not be drawn).
    pub refused: usize,
    /// Every object of the joint maps.
    pub joint_position_m: Vec<f64>,
    /// Size errors (length, breadth, height) of the joint maps.
    pub joint_size_m: Vec<f64>,
    /// Ellipse coverage of the joint maps.
    pub joint_covered: Vec<bool>,
    /// Floor known by the joint maps.
    pub joint_floor: Vec<f64>,
    /// Floor in some photo's view of the joint maps.
    pub joint_in_view: Vec<f64>,
    /// Floor the true cameras see (the most a map can know).
    pub joint_visible: Vec<f64>,
    /// Floor the first true camera sees.
    pub first_visible: Vec<f64>,
    /// The same of the first photo alone.
    pub first_position_m: Vec<f64>,
    /// Size errors of the first photo alone.
    pub first_size_m: Vec<f64>,
    /// Ellipse coverage of the first photo alone.
    pub first_covered: Vec<bool>,
    /// Floor known by the first photo alone.
    pub first_floor: Vec<f64>,
    /// Floor in view of the first photo alone.
    pub first_in_view: Vec<f64>,
    /// First photos alone refused.
    pub first_refused: usize,
    /// Per shared object: joint error below the best single-photo error.
    pub shared_better: Vec<bool>,
    /// The same, the joint map given every camera height (as the photos alone).
    pub shared_better_equal: Vec<bool>,
    /// Per shared object and listing photo: the joint map given every camera height, in that
    /// photo's frame, below that photo's map alone.
    pub shared_better_in_frame: Vec<bool>,
    /// Joint maps (photos 2..n shuffled) with a box more than [`WRONG_BOX_M`] off or a
    /// centroid at a squared Mahalanobis distance above [`WRONG_MAHALANOBIS_SQ`] that say
    /// no tie and do not warn that box's place or size uncertain.
    pub silent_wrong: usize,
    /// The same, off by the Mahalanobis distance (the error bars do not cover it).
    pub silent_wrong_mahalanobis: usize,
    /// Joint maps wrong so, with no tie said, whose every wrong box a warning names as
    /// uncertain ([`FloorMap::warns_uncertain`](vpmap_metrology::map::FloorMap::warns_uncertain)).
    pub wrong_said: usize,
    /// Joint maps that say a tie (alternatives or the tie warning).
    pub ties_said: usize,
    /// Of those, the ones whose every box is within [`WRONG_BOX_M`] and its error bars.
    pub ties_right: usize,
}

/// A joint map's box this far from the truth (its worst corner) is wrong, metres (issue 39).
pub const WRONG_BOX_M: f64 = 0.25;

/// A joint map's box centroid at this squared Mahalanobis distance from the truth is wrong
/// (issue 39).
pub const WRONG_MAHALANOBIS_SQ: f64 = 30.0;

fn add_map(
    m: &RoomMapErrors,
    position: &mut Vec<f64>,
    size: &mut Vec<f64>,
    covered: &mut Vec<bool>,
    floor: &mut Vec<f64>,
    in_view: &mut Vec<f64>,
) {
    for o in &m.objects {
        position.push(o.position_error_m);
        size.extend([o.length_error_m, o.breadth_error_m, o.height_error_m]);
        covered.extend(o.in_ellipse_95);
    }
    floor.push(m.floor_known);
    in_view.push(m.floor_in_view);
}

/// The rows of one number of photos' trials at one noise level.
#[must_use]
pub fn room_row(trials: &[RoomTrial], sigma_px: f64) -> RoomRow {
    let mut r = RoomRow::default();
    for t in trials {
        let Some(outcome) = t
            .outcomes
            .iter()
            .find(|o| o.sigma_px.to_bits() == sigma_px.to_bits())
        else {
            r.refused += 1;
            continue;
        };
        let Ok(ev) = &outcome.result else {
            r.refused += 1;
            continue;
        };
        r.rooms += 1;
        r.joint_visible.push(ev.floor_visible);
        r.first_visible.push(ev.first_floor_visible);
        add_map(
            &ev.joint,
            &mut r.joint_position_m,
            &mut r.joint_size_m,
            &mut r.joint_covered,
            &mut r.joint_floor,
            &mut r.joint_in_view,
        );
        match &ev.first_photo {
            Ok(first) => add_map(
                first,
                &mut r.first_position_m,
                &mut r.first_size_m,
                &mut r.first_covered,
                &mut r.first_floor,
                &mut r.first_in_view,
            ),
            Err(_) => r.first_refused += 1,
        }
        r.shared_better
            .extend(ev.shared.iter().filter_map(SharedObject::joint_better));
        r.shared_better_equal.extend(
            ev.shared
                .iter()
                .filter_map(SharedObject::equal_information_better),
        );
        r.shared_better_in_frame
            .extend(ev.shared.iter().flat_map(SharedObject::better_in_frames));
        let is_far = |o: &&RoomObjectErrors| o.corner_error_m > WRONG_BOX_M;
        let is_outside =
            |o: &&RoomObjectErrors| o.mahalanobis_sq.is_some_and(|m| m > WRONG_MAHALANOBIS_SQ);
        let wrong: Vec<&RoomObjectErrors> = ev
            .joint
            .objects
            .iter()
            .filter(|o| is_far(o) || is_outside(o))
            .collect();
        if ev.tie_said {
            r.ties_said += 1;
            if wrong.is_empty() {
                r.ties_right += 1;
            }
        } else if !wrong.is_empty() {
            // Wrong boxes the map names as uncertain are said, not silent.
            let unsaid: Vec<&&RoomObjectErrors> =
                wrong.iter().filter(|o| !o.uncertainty_said).collect();
            if unsaid.is_empty() {
                r.wrong_said += 1;
            } else {
                r.silent_wrong += 1;
                if unsaid.iter().any(|o| is_outside(o)) {
                    r.silent_wrong_mahalanobis += 1;
                }
            }
        }
    }
    r
}

fn share(flags: &[bool]) -> Option<f64> {
    (!flags.is_empty()).then(|| flags.iter().filter(|b| **b).count() as f64 / flags.len() as f64)
}

fn pct(v: Option<f64>) -> String {
    v.map_or_else(|| "-".to_owned(), |v| format!("{:.1} %", 100.0 * v))
}

fn metres(values: &[f64]) -> String {
    match (quantile_of(values, 0.5), quantile_of(values, 0.95)) {
        (Some(a), Some(b)) => format!("{a:.3} / {b:.3}"),
        _ => "-".to_owned(),
    }
}

fn at_least(values: &[f64], threshold: f64) -> Option<f64> {
    (!values.is_empty())
        .then(|| values.iter().filter(|v| **v >= threshold).count() as f64 / values.len() as f64)
}

/// The Markdown report: one table per noise level, then the targets.
#[must_use]
pub fn room_report(options: &RoomEvalOptions, trials: &[Vec<RoomTrial>]) -> String {
    let mut md = String::new();
    let _ = writeln!(
        md,
        "{} rooms per number of photos ({} boxes drawn per room, 4-7 m a side, cameras near its corners looking in), seed {}. \
         Each cell: the joint map | the first photo alone. Errors in metres, median / 95th percentile; \
         size = |length|, |breadth| and |height| errors together. Photos alone are given their true camera height as scale.\n",
        options.trials, options.boxes, options.seed
    );
    for &sigma in &options.sigmas_px {
        let _ = writeln!(md, "### sigma = {sigma} px\n");
        md.push_str("| photos | rooms (refused) | position error | size error | truth in 95 % ellipse | floor in view, median | floor known, median | floor the true cameras see, median | rooms with >= 90 % known | shared objects better than their best photo alone | the same, joint map given every camera height | better than each photo alone, in its frame (every camera height) |\n");
        md.push_str("|---|---|---|---|---|---|---|---|---|---|---|---|\n");
        for (&n, list) in options.photos.iter().zip(trials) {
            let r = room_row(list, sigma);
            let _ = writeln!(
                md,
                "| {n} | {} ({}) | {} \\| {} | {} \\| {} | {} \\| {} | {} \\| {} | {} \\| {} | {} \\| {} | {} \\| {} | {} of {} | {} | {} of {} |",
                r.rooms,
                r.refused,
                metres(&r.joint_position_m),
                metres(&r.first_position_m),
                metres(&r.joint_size_m),
                metres(&r.first_size_m),
                pct(share(&r.joint_covered)),
                pct(share(&r.first_covered)),
                pct(quantile_of(&r.joint_in_view, 0.5)),
                pct(quantile_of(&r.first_in_view, 0.5)),
                pct(quantile_of(&r.joint_floor, 0.5)),
                pct(quantile_of(&r.first_floor, 0.5)),
                pct(quantile_of(&r.joint_visible, 0.5)),
                pct(quantile_of(&r.first_visible, 0.5)),
                pct(at_least(&r.joint_floor, 0.9)),
                pct(at_least(&r.first_floor, 0.9)),
                pct(share(&r.shared_better)),
                r.shared_better.len(),
                pct(share(&r.shared_better_equal)),
                pct(share(&r.shared_better_in_frame)),
                r.shared_better_in_frame.len(),
            );
        }
        md.push('\n');
    }
    md.push_str(&placement(options, trials));
    md.push_str(&refusals(options, trials));
    md.push_str(&targets(options, trials));
    md
}

/// Issue 39's placement figures: the joint maps were given photos 2..n in a shuffled order.
fn placement(options: &RoomEvalOptions, trials: &[Vec<RoomTrial>]) -> String {
    let mut md = format!(
        "### Placement (issue 39): photos 2..n in a shuffled order\n\n\
         A joint map is wrong when a box's worst corner is more than {WRONG_BOX_M} m from the truth \
         or its centroid at a squared Mahalanobis distance above {WRONG_MAHALANOBIS_SQ}; silent when \
         it says no tie (no `alternatives`, no tie warning) and no warning names that box's place or \
         size as uncertain.\n\n\
         | sigma | photos | rooms | refused | silent wrong (of them beyond the error bars) | wrong, the box named uncertain | ties said | ties said and right | truth in 95 % ellipse |\n\
         |---|---|---|---|---|---|---|---|---|\n"
    );
    for &sigma in &options.sigmas_px {
        for (&n, list) in options.photos.iter().zip(trials) {
            if n < 2 {
                continue;
            }
            let r = room_row(list, sigma);
            let _ = writeln!(
                md,
                "| {sigma} px | {n} | {} | {} | {} ({}) | {} | {} | {} | {} |",
                r.rooms + r.refused,
                r.refused,
                r.silent_wrong,
                r.silent_wrong_mahalanobis,
                r.wrong_said,
                r.ties_said,
                r.ties_right,
                pct(share(&r.joint_covered)),
            );
        }
    }
    md.push('\n');
    md
}

/// Every room the joint fit refused (or that could not be drawn), with the reason.
fn refusals(options: &RoomEvalOptions, trials: &[Vec<RoomTrial>]) -> String {
    let mut md = String::new();
    for t in trials.iter().flatten() {
        if let Some(f) = &t.draw {
            let _ = writeln!(
                md,
                "- {} photos, trial {} (`vpmap synth --photos {} --seed {}`): not drawn: {}",
                t.photos, t.trial, t.photos, t.scene_seed, f.message
            );
        }
        for o in &t.outcomes {
            if let Err(f) = &o.result {
                let _ = writeln!(
                    md,
                    "- {} photos, trial {} (`vpmap synth --photos {} --seed {}`), sigma {} px: refused ({}): {}",
                    t.photos, t.trial, t.photos, t.scene_seed, o.sigma_px, f.category, f.message
                );
            }
        }
    }
    if md.is_empty() {
        String::new()
    } else {
        let _ = options;
        format!("### Rooms refused\n\n{md}\n")
    }
}

/// The three targets against the measured figures.
fn targets(options: &RoomEvalOptions, trials: &[Vec<RoomTrial>]) -> String {
    let mut md =
        String::from("### Targets (issue 29)\n\n| target | measured | met |\n|---|---|---|\n");
    let met = |ok: bool| if ok { "yes" } else { "no" };
    let row_for = |n: usize, sigma: f64| {
        options
            .photos
            .iter()
            .position(|&p| p == n)
            .and_then(|i| trials.get(i))
            .map(|list| room_row(list, sigma))
    };
    if options.sigmas_px.contains(&1.0) {
        for &n in options.photos.iter().filter(|&&n| n >= 2) {
            if let Some(r) = row_for(n, 1.0) {
                if let Some(c) = share(&r.joint_covered) {
                    let _ = writeln!(
                        md,
                        "| {n} photos, sigma 1 px: truth inside the 95 % ellipse for 92-98 % of objects | {} | {} |",
                        pct(Some(c)),
                        met((0.92..=0.98).contains(&c))
                    );
                }
                if let Some(s) = share(&r.shared_better) {
                    let equal = pct(share(&r.shared_better_equal));
                    let _ = writeln!(
                        md,
                        "| {n} photos, sigma 1 px: a shared object's position error below the better of its single-photo errors in >= 80 % | {} ({equal} with every camera height) | {} |",
                        pct(Some(s)),
                        met(s >= 0.8)
                    );
                }
            }
        }
    }
    for &sigma in &options.sigmas_px {
        if let Some(r) = row_for(3, sigma) {
            let (joint, first) = (
                quantile_of(&r.joint_floor, 0.5),
                quantile_of(&r.first_floor, 0.5),
            );
            if let (Some(j), Some(f)) = (joint, first) {
                let _ = writeln!(
                    md,
                    "| 3 photos, sigma {sigma} px: >= 90 % of the floor known where one photo knows 40-70 % (medians) | {} where one photo knows {} (the true cameras see {}) | {} |",
                    pct(Some(j)),
                    pct(Some(f)),
                    pct(quantile_of(&r.joint_visible, 0.5)),
                    met(j >= 0.9 && (0.4..=0.7).contains(&f))
                );
            }
        }
    }
    md
}

/// One row per object, map and noise level:
/// `photos,trial,scene_seed,sigma_px,map,object,listed_by,position_error_m,length_error_m,breadth_error_m,height_error_m,in_ellipse_95,joint_better,joint_better_every_camera_height,floor_in_view,floor_known,floor_visible`
/// (`floor_visible`: what the map's true cameras see, the ceiling of `floor_known`).
#[must_use]
pub fn room_csv(trials: &[Vec<RoomTrial>]) -> String {
    let mut csv = String::from(
        "photos,trial,scene_seed,sigma_px,map,object,listed_by,position_error_m,length_error_m,breadth_error_m,height_error_m,in_ellipse_95,joint_better,joint_better_every_camera_height,floor_in_view,floor_known,floor_visible\n",
    );
    for t in trials.iter().flatten() {
        for o in &t.outcomes {
            let Ok(ev) = &o.result else { continue };
            let maps = [
                ("joint", Some(&ev.joint)),
                ("first_photo", ev.first_photo.as_ref().ok()),
            ];
            for (name, m) in maps {
                let Some(m) = m else { continue };
                for e in &m.objects {
                    let shared = ev
                        .shared
                        .iter()
                        .find(|s| s.name == e.name)
                        .filter(|_| name == "joint");
                    let better = shared.and_then(SharedObject::joint_better);
                    let better_equal = shared.and_then(SharedObject::equal_information_better);
                    let visible = if name == "joint" {
                        ev.floor_visible
                    } else {
                        ev.first_floor_visible
                    };
                    let flag = |b: Option<bool>| b.map_or(String::new(), |b| b.to_string());
                    let _ = writeln!(
                        csv,
                        "{},{},{},{},{name},{},{},{},{},{},{},{},{},{},{},{},{}",
                        t.photos,
                        t.trial,
                        t.scene_seed,
                        o.sigma_px,
                        e.name,
                        e.photos,
                        e.position_error_m,
                        e.length_error_m,
                        e.breadth_error_m,
                        e.height_error_m,
                        flag(e.in_ellipse_95),
                        flag(better),
                        flag(better_equal),
                        m.floor_in_view,
                        m.floor_known,
                        visible
                    );
                }
            }
        }
    }
    csv
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;
    use crate::progress::Silent;

    #[test]
    fn a_small_run_reports_every_number_of_photos() {
        let options = RoomEvalOptions {
            trials: 2,
            photos: vec![1, 3],
            sigmas_px: vec![1.0],
            ..RoomEvalOptions::default()
        };
        let trials = run_rooms(&options, &Silent);
        assert_eq!(trials.len(), 2);
        assert!(trials.iter().all(|l| l.len() == 2));
        let r = room_row(&trials[1], 1.0);
        assert_eq!(r.rooms + r.refused, 2);
        let md = room_report(&options, &trials);
        assert!(md.contains("### sigma = 1 px"), "{md}");
        assert!(md.contains("| 3 | "), "{md}");
        assert!(md.contains("### Targets"), "{md}");
        assert!(md.contains("### Placement (issue 39)"), "{md}");
        assert!(md.contains("| 1 px | 3 | 2 | "), "{md}");
        let csv = room_csv(&trials);
        assert!(csv.lines().count() > 1);
        let columns = csv.lines().next().unwrap().split(',').count();
        assert!(
            csv.lines().all(|l| l.split(',').count() == columns),
            "{csv}"
        );
    }
}

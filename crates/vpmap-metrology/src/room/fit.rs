//! The joint fit of a room's photos: every camera and every object at once, to every click
//! and vanishing-point segment of every photo ([`fit_room`]).

use nalgebra::Vector2;

use super::align::{
    PhotoFit, Placed, Pose, average_boxes, candidate_poses, heading, in_photo, photo_block,
    place_objects, placed_index, record_maps, room_axes, sightings,
};
use super::canonical::PhotoKeys;
use super::choose::{
    break_ties, cameras_inside_objects, flip_start, refuse_if_inconsistent, refuse_unconverged,
};
use super::hypotheses::{Hypothesis, Search, Ties, join_order, starts};
use super::model::{Place, RoomPart, RoomProblem, Shape, Sighting};
use crate::calibration::{Calibration, Perspective};
use crate::error::{MetrologyError, Result};
use crate::fit::model::{BoxAxes, Part, px};
use crate::fit::solve::{Model, Singular, minimise};
use crate::fit::{FitOptions, MAX_FOCAL_DIAGONALS, PointResidual, calibration_of, fit_scene_until};
use crate::interrupt::Interrupt;
use crate::reconstruct::{ObjectKind, ReconstructedObject};
use crate::scene::{Scale, Scene};

/// One photo's camera after the room fit.
#[derive(Debug, Clone)]
pub struct FittedPhoto {
    /// Its camera as a calibration in its own map frame (focal length, principal point,
    /// pitch, roll, the vanishing points the fit predicts).
    pub calibration: Calibration,
    /// Its room directions' angle from its own `+x`, radians.
    pub room_yaw_rad: f64,
    /// Its station point in the room frame (the first photo's map frame), first camera
    /// heights.
    pub position: Vector2<f64>,
    /// Its height above the floor, first camera heights.
    pub height: f64,
    /// The angle from the room frame's axes to its own map frame's (its horizontal viewing
    /// direction, counter-clockwise from the room frame's `+y`), radians.
    pub heading_rad: f64,
    /// Whether its principal point was fitted.
    pub principal_point_fitted: bool,
}

/// A placement of one photo that fits the room about as well as the chosen one (a tie the
/// clicks and the physical checks leave open).
#[derive(Debug, Clone, PartialEq)]
pub struct RoomAlternative {
    /// The photo, from 0.
    pub photo: usize,
    /// Its turn from the chosen placement, degrees counter-clockwise (90, 180 or 270).
    pub turn_deg: i32,
    /// Its quarter turn against photo 1's room directions in this placement, degrees (0, 90,
    /// 180 or 270): the room file's `placement_turn_deg` that asks the fit for it.
    pub placement_turn_deg: i32,
    /// The joint fit's cost with the photo so turned, squared pixels.
    pub cost_px2: f64,
    /// The chosen placement's cost, squared pixels.
    pub chosen_cost_px2: f64,
}

/// The result of [`fit_room`].
#[derive(Debug, Clone)]
pub struct RoomFitted {
    /// Every photo's camera, in photo order.
    pub photos: Vec<FittedPhoto>,
    /// Every object once, in the order first seen (photo 1's objects in scene order, then
    /// photo 2's new ones, ...), room frame, first camera heights.
    pub objects: Vec<ReconstructedObject>,
    /// Each photo's floor outline in the room frame.
    pub floors: Vec<Vec<Vector2<f64>>>,
    /// Root-mean-square reprojection error of every clicked point, pixels.
    pub rms_residual_px: f64,
    /// Residuals minus parameters.
    pub degrees_of_freedom: usize,
    /// Levenberg-Marquardt iterations of the chosen hypothesis.
    pub iterations: usize,
    /// Every clicked point's misfit, pixels (without the clicks' covariances).
    pub point_residuals: Vec<PointResidual>,
    /// Every clicked point's misfit as the fit weighs it, in the order of `point_residuals`:
    /// with a covariance (`click_covariances_px2`), the whitened residual's length (in
    /// standard deviations of that click); without, its length in pixels (a 1 px click).
    pub weighted_residuals: Vec<f64>,
    /// Notes: the photos' own notes, and correspondences the data leave open.
    pub warnings: Vec<String>,
    /// Placements that fit about as well as the chosen one and that no physical check
    /// rules out: one per photo placed otherwise.
    pub alternatives: Vec<RoomAlternative>,
    pub(crate) problem: RoomProblem,
    pub(crate) x: Vec<f64>,
    /// For each photo, each scene object's room object index.
    pub(crate) object_of: Vec<Vec<usize>>,
    /// Each photo's floor-distance points' parts, when its scale is a floor distance.
    pub(crate) floor_distance_parts: Vec<Option<[usize; 2]>>,
    /// For each photo, each scene box's axes turned into the room frame.
    pub(crate) photo_axes: Vec<Vec<Option<BoxAxes>>>,
}

/// The placement of every photo for one whole-room hypothesis.
struct Placement {
    poses: Vec<Option<Pose>>,
    placed: Vec<Placed>,
}

/// Place every photo as hypothesis `h` has it, in join order `order`: each photo's objects
/// not yet in the room from its pose, its footprints' vertices matched to the room's.
fn place_all(fits: &[PhotoFit], order: &[usize], h: &Hypothesis) -> Placement {
    let n = fits.len();
    let first_cam = fits[0].camera();
    let mut poses: Vec<Option<Pose>> = vec![None; n];
    let mut placed: Vec<Placed> = Vec::new();
    place_objects(
        &fits[0],
        &Pose {
            quarter: 0,
            heading_rad: 0.0,
            scale: 1.0,
            position: Vector2::zeros(),
        },
        &mut placed,
        0,
    );
    for &k in order.iter().skip(1) {
        let (Some(q), Some((scale, position))) = (
            h.quarters.get(k).copied().flatten(),
            h.placements.get(k).copied().flatten(),
        ) else {
            continue;
        };
        let candidates = candidate_poses(
            &fits[k],
            first_cam.room_yaw_rad,
            &first_cam,
            &placed,
            Some(q),
        );
        let maps = candidates.first().map(|c| c.2.clone()).unwrap_or_default();
        let pose = Pose {
            quarter: q,
            heading_rad: heading(first_cam.room_yaw_rad, fits[k].camera().room_yaw_rad, q),
            scale,
            position,
        };
        record_maps(&mut placed, k, &maps);
        place_objects(&fits[k], &pose, &mut placed, k);
        poses[k] = Some(pose);
    }
    average_boxes(fits, &poses, &mut placed);
    Placement { poses, placed }
}

/// The problem, its start and index maps for one placement.
pub(super) struct Built {
    pub(super) problem: RoomProblem,
    pub(super) x0: Vec<f64>,
    pub(super) object_of: Vec<Vec<usize>>,
    pub(super) floor_distance_parts: Vec<Option<[usize; 2]>>,
    pub(super) names: Vec<String>,
    pub(super) photo_axes: Vec<Vec<Option<BoxAxes>>>,
}

/// Each photo's camera height in metres, where its scale gives one.
fn known_camera_heights(photos: &[&Scene]) -> Result<Vec<Option<f64>>> {
    photos
        .iter()
        .enumerate()
        .map(|(k, p)| {
            Ok(match p.scale().map_err(|e| in_photo(k, e))? {
                Some(Scale::CameraHeight(h)) => Some(h),
                _ => None,
            })
        })
        .collect()
}

/// The problem for one placement; `hold` holds the known camera heights of photos after the
/// first (when the first's is known too).
fn build(scene: &Scene, fits: &[PhotoFit], placement: &Placement, hold: bool) -> Result<Built> {
    let photos: Vec<&Scene> = scene.photos().collect();
    let heights = if hold {
        known_camera_heights(&photos)?
    } else {
        Vec::new()
    };
    let mut blocks = Vec::new();
    let mut x0 = Vec::new();
    for (k, fit) in fits.iter().enumerate() {
        // A photo's known camera height holds its height in the fit when the first photo's
        // is known too (the frame's unit is the first camera's height).
        let fixed = match (
            heights.first().copied().flatten(),
            heights.get(k).copied().flatten(),
        ) {
            (Some(first), Some(own)) => Some(own / first),
            _ => None,
        };
        let (b, x) = photo_block(fit, placement.poses[k].as_ref(), fixed);
        blocks.push(b);
        x0.extend(x);
    }
    // Objects in the order first seen.
    let mut names: Vec<String> = Vec::new();
    for p in &photos {
        for o in &p.objects {
            if !names.contains(&o.name) {
                names.push(o.name.clone());
            }
        }
    }
    let mut parts = Vec::new();
    let mut params = Vec::new();
    for name in &names {
        let w = &placement.placed[placed_index(&placement.placed, name)?];
        let mut seen: Vec<Sighting> = Vec::new();
        for (k, fit) in fits.iter().enumerate() {
            if let Some(o) = fit.objects.iter().find(|o| &o.name == name) {
                let quarter = placement.poses[k].map_or(0, |p| p.quarter);
                seen.extend(sightings(k, o, quarter, w));
            }
        }
        parts.push(RoomPart {
            shape: w.shape,
            sightings: seen,
        });
        params.extend(w.params.iter().copied());
    }
    let object_of = photos
        .iter()
        .map(|p| {
            p.objects
                .iter()
                .map(|o| names.iter().position(|n| n == &o.name).unwrap_or(0))
                .collect()
        })
        .collect();
    // Each photo's floor-distance points, started where its own camera puts them.
    let mut floor_distance_parts = vec![None; photos.len()];
    let problem0 = RoomProblem::new(blocks.clone(), Vec::new());
    let views = problem0.views(&x0);
    for (k, p) in photos.iter().enumerate() {
        if let Some(Scale::FloorDistance(fd)) = p.scale()? {
            let first = parts.len();
            for (end, q) in [("from", fd.from), ("to", fd.to)] {
                let own = views[k]
                    .cam
                    .floor_point(px(q))
                    .unwrap_or_else(|| Vector2::new(0.0, 1.0));
                let at = views[k].room_from_own(own);
                params.extend([at.x, at.y]);
                parts.push(RoomPart {
                    shape: Shape::Point,
                    sightings: vec![Sighting {
                        photo: k,
                        place: Place::Point,
                        pixel: px(q),
                        field: format!("photos[{k}].scale.floor_distance.{end}"),
                        weight: p
                            .click_covariances_px2
                            .get(&format!("scale.floor_distance.{end}"))
                            .and_then(|c| crate::fit::whitening(*c)),
                    }],
                });
            }
            floor_distance_parts[k] = Some([first, first + 1]);
        }
    }
    let problem = RoomProblem::new(blocks, parts);
    x0.extend(params);
    let photo_axes = fits
        .iter()
        .enumerate()
        .map(|(k, fit)| {
            let quarter = placement.poses[k].map_or(0, |p| p.quarter);
            fit.objects
                .iter()
                .map(|o| match &o.part {
                    Part::Box { axes, .. } => Some(room_axes(*axes, quarter)),
                    _ => None,
                })
                .collect()
        })
        .collect();
    Ok(Built {
        problem,
        x0,
        object_of,
        floor_distance_parts,
        names,
        photo_axes,
    })
}

/// A converged hypothesis.
pub(super) struct Solved {
    pub(super) built: Built,
    pub(super) x: Vec<f64>,
    pub(super) cost: f64,
    pub(super) iterations: usize,
    pub(super) quarters: Vec<u8>,
    hypothesis: Hypothesis,
    /// Whether the minimiser converged (an unconverged fit is only tested for consistency,
    /// to name what disagrees).
    pub(super) converged: bool,
}

/// The joint fit from hypothesis `h` (`hold`: the known camera heights held).
pub(super) fn solve(
    scene: &Scene,
    fits: &[PhotoFit],
    order: &[usize],
    h: &Hypothesis,
    hold: bool,
    interrupt: &Interrupt,
) -> Result<Solved> {
    stop_if_interrupted(scene, interrupt)?;
    let placement = place_all(fits, order, h);
    let mut built = build(scene, fits, &placement, hold)?;
    built.problem.interrupt = interrupt.clone();
    let sol = minimise(&built.problem, built.x0.clone());
    // An interrupted minimiser returns where it was: not a result.
    stop_if_interrupted(scene, interrupt)?;
    built.problem.interrupt = Interrupt::default();
    let sol = sol.ok_or_else(|| {
        MetrologyError::Degenerate {
            field: "photos".to_owned(),
            reason: "the room fit's starting point puts a clicked point behind a camera: check that objects named the same in several photos are the same object".to_owned(),
        }
    })?;
    if sol.converged {
        floor_below_horizons(scene, &built.problem, &sol.x)?;
    }
    let quarters = placement
        .poses
        .iter()
        .map(|p| p.map_or(0, |p| p.quarter))
        .collect();
    Ok(Solved {
        built,
        x: sol.x,
        cost: sol.cost,
        iterations: sol.iterations,
        quarters,
        hypothesis: h.clone(),
        converged: sol.converged,
    })
}

/// Every photo's floor corners below its fitted camera's horizon: a hypothesis whose joint fit
/// puts one on or above it is refused (and the next one tried), naming the corner and how
/// far above the horizon it came out.
pub(super) fn floor_below_horizons(scene: &Scene, problem: &RoomProblem, x: &[f64]) -> Result<()> {
    let views = problem.views(&x[..problem.camera_len]);
    for (k, p) in scene.photos().enumerate() {
        let Some(v) = views.get(k) else { continue };
        for (i, q) in p.floor.iter().enumerate() {
            if v.cam.floor_point(px(*q)).is_none() {
                return Err(in_photo(
                    k,
                    MetrologyError::NotBelowHorizon {
                        field: format!("floor[{i}]"),
                        x: q[0],
                        y: q[1],
                        distance_px: -v.cam.below_horizon_px(px(*q)),
                        side: "on or above",
                    },
                ));
            }
        }
    }
    Ok(())
}

/// Most objects in all of a room's photos together (an object shown in three photos counts
/// three times): the room fit's work grows with them (its placement hypotheses, each a joint
/// fit of every photo's objects). [`fit_room`] refuses a larger room before fitting anything
/// (issue 40 found 4 photos of 500 objects taking 20 s, 16 of 100 taking 50 s).
pub const MAX_ROOM_SIGHTINGS: usize = 1000;

/// What a room fit is, for messages: `the room fit of 4 photos and 2000 objects`.
fn room_work(scene: &Scene) -> String {
    let sightings: usize = scene.photos().map(|p| p.objects.len()).sum();
    format!(
        "the room fit of {} photos and {sightings} objects",
        scene.photo_count()
    )
}

fn stop_if_interrupted(scene: &Scene, interrupt: &Interrupt) -> Result<()> {
    match interrupt.check() {
        Some(reason) => Err(MetrologyError::Interrupted {
            work: room_work(scene),
            reason,
        }),
        None => Ok(()),
    }
}

/// Refuse a room with more than [`MAX_ROOM_SIGHTINGS`] objects in all its photos, naming each
/// photo's count.
fn check_room_size(scene: &Scene) -> Result<()> {
    let counts: Vec<usize> = scene.photos().map(|p| p.objects.len()).collect();
    let total: usize = counts.iter().sum();
    if total <= MAX_ROOM_SIGHTINGS {
        return Ok(());
    }
    let each: Vec<String> = counts.iter().map(usize::to_string).collect();
    Err(MetrologyError::InvalidField {
        field: "photos".to_owned(),
        reason: format!(
            "the room's {} photos hold {total} objects in all ({}), more than the {MAX_ROOM_SIGHTINGS} a room fit takes (an object counts once in each photo that shows it); split the room or annotate fewer objects",
            counts.len(),
            each.join(" + ")
        ),
    })
}

/// Fit every photo of a room at once ([`crate::room`]); never interrupted (see
/// [`fit_room_until`]).
///
/// # Errors
/// As [`fit_room_until`], never [`MetrologyError::Interrupted`].
pub fn fit_room(scene: &Scene) -> Result<RoomFitted> {
    fit_room_until(scene, &Interrupt::default())
}

/// Fit every photo of a room at once ([`crate::room`]), stopping early when `interrupt` fires:
/// it is looked at before each photo's own fit, before each placement hypothesis and at every
/// evaluation of the joint fit.
///
/// # Errors
/// A room with more than [`MAX_ROOM_SIGHTINGS`] objects in all its photos
/// ([`MetrologyError::InvalidField`], before any fit); a photo whose own fit fails
/// ([`MetrologyError::InPhoto`]); a room whose photos cannot be placed or whose fit does not
/// converge; an object the clicks of all photos together do not fix (naming it); a box with
/// its top below its base; [`MetrologyError::InconsistentRoom`] when the photos fit together
/// far worse than each alone (naming the photos and objects that disagree);
/// [`MetrologyError::Interrupted`] when `interrupt` fires.
pub fn fit_room_until(scene: &Scene, interrupt: &Interrupt) -> Result<RoomFitted> {
    scene.validate()?;
    check_room_size(scene)?;
    let photos: Vec<&Scene> = scene.photos().collect();
    let mut fits = Vec::with_capacity(photos.len());
    for (k, p) in photos.iter().enumerate() {
        stop_if_interrupted(scene, interrupt)?;
        let fitted = fit_scene_until(p, &FitOptions::default(), interrupt);
        stop_if_interrupted(scene, interrupt)?;
        let fitted = fitted.map_err(|e| in_photo(k, e))?;
        fits.push(PhotoFit::new(fitted, p));
    }
    let ties = Ties::new(&fits);
    let keys = PhotoKeys::new(scene);
    let order = join_order(&fits, &ties, &keys);
    let pins = scene.placement_pins();
    let pinned = |k: usize| pins.get(k).copied().flatten();
    let all = Search::new(&fits, &ties, &keys)
        .with_pins(pins.clone())
        .run(&order)
        .map_err(|k| MetrologyError::Degenerate {
            field: format!("photos[{k}]"),
            reason: format!(
                "photo {} cannot be placed in the room{}: the objects it shares with the others do not fix its scale (give them sizes in both photos)",
                k + 1,
                pinned(k).map_or_else(String::new, |q| format!(
                    " turned by {} degrees as its `placement_turn_deg` pins it",
                    u16::from(q) * 90
                ))
            ),
        })?;
    // The joint fit from the best few whole-room hypotheses; the first failure is reported
    // when none converges.
    let mut results: Vec<Solved> = Vec::new();
    let mut failure = None;
    for h in starts(&all) {
        match solve(scene, &fits, &order, h, false, interrupt) {
            Ok(s) => results.push(s),
            Err(e @ MetrologyError::Interrupted { .. }) => return Err(e),
            Err(e) => {
                failure.get_or_insert(e);
            }
        }
    }
    let (mut results, unconverged): (Vec<Solved>, Vec<Solved>) =
        results.into_iter().partition(|s| s.converged);
    if results.is_empty() {
        return Err(refuse_unconverged(&fits, &keys, &unconverged, failure));
    }
    results.sort_by(|a, b| a.cost.total_cmp(&b.cost));
    let mut warnings: Vec<String> = Vec::new();
    for (k, f) in fits.iter().enumerate() {
        for w in &f.fitted.calibration.warnings {
            warnings.push(format!("photo {}: {w}", k + 1));
        }
    }
    for (k, q) in pins.iter().enumerate() {
        if let Some(q) = q {
            warnings.push(format!(
                "photo {}'s placement is pinned by its `placement_turn_deg` ({} degrees): the room fit tried no other turn of it; remove the field to let the fit choose",
                k + 1,
                u16::from(*q) * 90
            ));
        }
    }
    let best_cost = results[0].cost;
    let dof = results[0]
        .built
        .problem
        .residual_count()
        .saturating_sub(results[0].built.problem.len())
        .max(1);
    let variance = (best_cost / dof as f64).max(crate::fit::MIN_CLICK_SIGMA_PX.powi(2));
    // A tied photo's other turn with every other photo as chosen, from the beam's hypotheses
    // (one joint fit each), for the physical checks to compare placements that differ in it alone.
    let mut flip = |chosen: &Solved, k: usize| {
        let h = flip_start(&all, &chosen.quarters, k)?;
        solve(scene, &fits, &order, h, false, interrupt)
            .ok()
            .filter(|s| s.converged)
    };
    let alternatives = break_ties(
        scene,
        &fits,
        &ties,
        &mut results,
        variance,
        &mut warnings,
        &mut flip,
    );
    let best = results.swap_remove(0);
    let best = hold_known_heights(scene, &fits, &order, best, variance, interrupt)?;
    refuse_if_inconsistent(
        scene,
        &fits,
        &order,
        &all,
        &best,
        results,
        unconverged,
        interrupt,
    )?;
    warnings.extend(cameras_inside_objects(scene, &best));
    let mut fitted = finish(scene, best.built, best.x, best.iterations, warnings)?;
    fitted.alternatives = alternatives;
    Ok(fitted)
}

/// The upper 1 % point of the chi-square distribution with `m` degrees of freedom
/// (Wilson-Hilferty; within 1 % of the exact value for every `m`).
fn chi2_99(m: usize) -> f64 {
    let m = m.max(1) as f64;
    let z = 2.326_347_874_040_841;
    let a = 2.0 / (9.0 * m);
    m * (1.0 - a + z * a.sqrt()).powi(3)
}

/// The chosen hypothesis refitted with the known camera heights of photos after the first
/// held (the ratio of each to the first's), when the clicks agree with them: the cost may
/// grow by at most the chi-square 99 % point for as many constraints (a likelihood-ratio
/// test, in the fit's click variance `variance`). Heights the clicks contradict are not
/// held: the fit keeps them as scales, and the map names both in its scale warning.
fn hold_known_heights(
    scene: &Scene,
    fits: &[PhotoFit],
    order: &[usize],
    free: Solved,
    variance: f64,
    interrupt: &Interrupt,
) -> Result<Solved> {
    let photos: Vec<&Scene> = scene.photos().collect();
    let heights = known_camera_heights(&photos)?;
    let held = if heights.first().copied().flatten().is_some() {
        heights.iter().skip(1).filter(|h| h.is_some()).count()
    } else {
        0
    };
    if held == 0 {
        return Ok(free);
    }
    match solve(scene, fits, order, &free.hypothesis, true, interrupt) {
        Ok(s) if s.converged && (s.cost - free.cost) / variance <= chi2_99(held) => Ok(s),
        Err(e @ MetrologyError::Interrupted { .. }) => Err(e),
        _ => Ok(free),
    }
}

/// The room fitted at `x` (the minimiser's answer to `built`'s problem after `iterations`).
pub(super) fn finish(
    scene: &Scene,
    built: Built,
    x: Vec<f64>,
    iterations: usize,
    mut warnings: Vec<String>,
) -> Result<RoomFitted> {
    let problem = &built.problem;
    let photos: Vec<&Scene> = scene.photos().collect();
    let nc = problem.camera_len;
    let views = problem.views(&x[..nc]);
    for (k, v) in views.iter().enumerate() {
        let diagonal = photos[k].image.diagonal();
        if v.cam.focal_px > MAX_FOCAL_DIAGONALS * diagonal || v.cam.focal_px <= 0.0 {
            return Err(in_photo(
                k,
                MetrologyError::Degenerate {
                    field: "vanishing_points".to_owned(),
                    reason: format!(
                        "the room fit runs off to a focal length of {:.0} px: the vanishing points' edges are too short or nearly parallel to fix the camera",
                        v.cam.focal_px
                    ),
                },
            ));
        }
        if !(v.height.is_finite() && v.height > 0.0) {
            return Err(MetrologyError::Degenerate {
                field: format!("photos[{k}]"),
                reason: format!(
                    "photo {} comes out with its camera {:.3} camera heights above the floor: check the objects it shares with the others",
                    k + 1,
                    v.height
                ),
            });
        }
    }
    let normal = problem
        .normal(&x)
        .ok_or_else(|| MetrologyError::Degenerate {
            field: "photos".to_owned(),
            reason: "a clicked point lies behind its fitted camera".to_owned(),
        })?;
    if let Some(block) = normal.singular_block() {
        return Err(match block {
            Singular::Camera => MetrologyError::Degenerate {
                field: "photos".to_owned(),
                reason: "the photos' vanishing points and shared objects do not fix every camera (a singular covariance): give longer vanishing-point edges, or tie each photo by more corners of shared objects".to_owned(),
            },
            Singular::Part(p) => {
                let what = built
                    .names
                    .get(p)
                    .map_or_else(|| "a floor-distance point".to_owned(), |n| format!("object {n:?}"));
                MetrologyError::Degenerate {
                    field: "photos".to_owned(),
                    reason: format!(
                        "the clicks of {what} in all photos together do not determine its size or place (a singular covariance): click more of its corners"
                    ),
                }
            }
        });
    }
    let room_cam = views[0].cam;
    let mut objects = Vec::with_capacity(built.names.len());
    for (i, name) in built.names.iter().enumerate() {
        let part = &problem.parts[i];
        let p = problem.part_params(&x, i);
        let corner = |a: u8, b: u8| {
            let v = part.point(&room_cam, p, Place::Corner(a, b, 0));
            Vector2::new(v.x, v.y)
        };
        let (kind, footprint, height) = match part.shape {
            Shape::Box { has_top, .. } => {
                let scale = p[0].hypot(p[1]).max(1.0);
                if p[2].abs() <= 1e-9 * scale || p[3].abs() <= 1e-9 * scale {
                    return Err(MetrologyError::Degenerate {
                        field: "photos".to_owned(),
                        reason: format!(
                            "object {name:?} comes out with a side of no length ({:.3} x {:.3} camera heights): its corners in the photos cannot belong to one box",
                            p[2], p[3]
                        ),
                    });
                }
                let h = has_top.then(|| p[4]);
                (
                    ObjectKind::Box,
                    vec![corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)],
                    h,
                )
            }
            Shape::Footprint { n, has_top } => (
                ObjectKind::Footprint,
                (0..n)
                    .map(|v| Vector2::new(p[2 * v], p[2 * v + 1]))
                    .collect(),
                has_top.then(|| p[2 * n]),
            ),
            Shape::Point => continue,
        };
        if let Some(h) = height
            && h <= 0.0
        {
            return Err(MetrologyError::Degenerate {
                field: "photos".to_owned(),
                reason: format!(
                    "object {name:?} comes out with its top {:.3} camera heights below its base: check that its top corners are named like the base corners below them in every photo",
                    -h
                ),
            });
        }
        objects.push(ReconstructedObject {
            name: name.clone(),
            kind,
            footprint,
            height,
        });
    }
    let mut floors = Vec::with_capacity(photos.len());
    for (k, p) in photos.iter().enumerate() {
        let mut floor = Vec::with_capacity(p.floor.len());
        for (i, q) in p.floor.iter().enumerate() {
            let own = views[k].cam.floor_point(px(*q)).ok_or_else(|| {
                in_photo(
                    k,
                    MetrologyError::NotBelowHorizon {
                        field: format!("floor[{i}]"),
                        x: q[0],
                        y: q[1],
                        distance_px: -views[k].cam.below_horizon_px(px(*q)),
                        side: "on or above",
                    },
                )
            })?;
            floor.push(views[k].room_from_own(own));
        }
        floors.push(floor);
    }
    // The residuals as the fit weighs them, and in pixels (without the clicks' whitening).
    let residuals = problem.residuals(&x).unwrap_or_default();
    let pixel_residuals = if problem.has_click_covariances() {
        let mut unweighted = problem.clone();
        for s in unweighted
            .parts
            .iter_mut()
            .flat_map(|p| p.sightings.iter_mut())
        {
            s.weight = None;
        }
        unweighted.residuals(&x).unwrap_or_default()
    } else {
        residuals.clone()
    };
    let mut point_residuals = Vec::new();
    let mut weighted_residuals = Vec::new();
    // The cameras' residuals first, then each part's, two per sighting.
    let mut at: usize = (0..problem.camera_group_count())
        .map(|g| problem.camera_group_len(g))
        .sum();
    let length = |r: &[f64], at: usize| {
        r.get(at)
            .copied()
            .unwrap_or(0.0)
            .hypot(r.get(at + 1).copied().unwrap_or(0.0))
    };
    for (i, part) in problem.parts.iter().enumerate() {
        for s in &part.sightings {
            if let Some(name) = built.names.get(i) {
                point_residuals.push(PointResidual {
                    object: name.clone(),
                    field: s.field.clone(),
                    distance_px: length(&pixel_residuals, at),
                });
                weighted_residuals.push(length(&residuals, at));
            }
            at += 2;
        }
    }
    let clicks = point_residuals.len().max(1);
    let rms = (point_residuals
        .iter()
        .map(|r| r.distance_px * r.distance_px)
        .fold(0.0, |a, b| a + b)
        / clicks as f64)
        .sqrt();
    let fitted_photos = views
        .iter()
        .enumerate()
        .map(|(k, v)| {
            let perspective = if photos[k].vanishing_points.len() == 3 {
                Perspective::ThreePoint
            } else {
                Perspective::TwoPoint
            };
            FittedPhoto {
                calibration: calibration_of(&v.cam, perspective),
                room_yaw_rad: v.cam.room_yaw_rad,
                position: v.position,
                height: v.height,
                heading_rad: v.heading_rad,
                principal_point_fitted: problem.photos[k].fixed_pp.is_none(),
            }
        })
        .collect();
    warnings.dedup();
    Ok(RoomFitted {
        photos: fitted_photos,
        objects,
        floors,
        rms_residual_px: rms,
        degrees_of_freedom: problem.residual_count().saturating_sub(problem.len()),
        iterations,
        point_residuals,
        weighted_residuals,
        warnings,
        alternatives: Vec::new(),
        problem: built.problem,
        x,
        object_of: built.object_of,
        floor_distance_parts: built.floor_distance_parts,
        photo_axes: built.photo_axes,
    })
}

#[cfg(test)]
mod tests {
    use std::time::Duration;

    use super::*;
    use crate::interrupt::Interruption;
    use crate::synth::{RoomSynthOptions, synthesize_room};

    fn room(boxes: usize) -> Scene {
        synthesize_room(&RoomSynthOptions {
            seed: 6,
            photos: 4,
            boxes,
            ..RoomSynthOptions::default()
        })
        .map_or_else(|e| panic!("{e}"), |(scene, _)| scene)
    }

    #[test]
    fn an_interrupted_room_fit_stops_naming_the_room_and_an_uninterrupted_one_fits() {
        let scene = room(8);
        let e = fit_room_until(&scene, &Interrupt::default().with_timeout(Duration::ZERO))
            .err()
            .unwrap_or_else(|| panic!("not interrupted"));
        assert!(
            matches!(
                &e,
                MetrologyError::Interrupted {
                    work,
                    reason: Interruption::TimeLimit { .. },
                } if work.starts_with("the room fit of 4 photos and ")
            ),
            "{e}"
        );
        let far = Interrupt::default().with_timeout(Duration::from_secs(3600));
        assert!(fit_room_until(&scene, &far).is_ok());
    }

    #[test]
    fn a_room_of_more_than_1000_objects_in_all_its_photos_is_refused_before_fitting() {
        let mut scene = room(100);
        // The photo of the most objects again and again, until the room holds more than the
        // limit.
        let most = scene.photos().max_by_key(|p| p.objects.len()).map_or_else(
            || panic!("no photo"),
            |p| Scene {
                other_photos: Vec::new(),
                ..p.clone()
            },
        );
        let total = |s: &Scene| s.photos().map(|p| p.objects.len()).sum::<usize>();
        while total(&scene) <= MAX_ROOM_SIGHTINGS {
            scene.other_photos.push(most.clone());
        }
        assert!(scene.photo_count() <= crate::scene::MAX_PHOTOS);
        let e = fit_room(&scene)
            .err()
            .map(|e| e.to_string())
            .unwrap_or_default();
        assert!(
            e.contains(&format!(
                "the room's {} photos hold {} objects in all",
                scene.photo_count(),
                total(&scene)
            )) && e.contains("more than the 1000"),
            "{e}"
        );
    }

    #[test]
    fn the_chi_square_99_percent_point_is_within_1_percent_of_the_tables() {
        // Upper 1 % points of the chi-square distribution (standard tables).
        let table = [
            (1, 6.634_897),
            (2, 9.210_340),
            (3, 11.344_867),
            (5, 15.086_272),
            (10, 23.209_251),
            (15, 30.577_914),
        ];
        for (m, exact) in table {
            let got = chi2_99(m);
            assert!((got - exact).abs() < 0.01 * exact, "{m}: {got} vs {exact}");
        }
    }
}

//! The joint maximum-likelihood fit: camera and every object at once, to every clicked point
//! and vanishing-point segment.
//!
//! Model (`fit/model.rs`): a pinhole camera one camera height above the floor (focal length,
//! pitch, roll; the principal point held at the given value or the image centre, or fitted in
//! three-point perspective when the data fix it well), the room's two horizontal directions
//! (one yaw angle), and each object: a box by one floor corner, its two sides along the
//! room's directions (or turned by its own yaw) and its height; a footprint object by its
//! vertices and height. Objective: the sum of squared reprojection errors, in pixels, of every
//! clicked corner and vertex and of every vanishing-point segment (the distance of its end
//! points from the line through its midpoint and the predicted vanishing point), which under
//! independent Gaussian click noise is the maximum-likelihood estimate (Hartley & Zisserman,
//! *Multiple View Geometry*, 2nd ed., sections 4.2-4.3 and appendix A6).
//!
//! Start: the projective form's camera (vanishing points with the principal point held), and
//! each object by linear least squares on its clicks' rays; also the cameras the clicked boxes'
//! own edges imply (`fit/box_edges.rs`), for given vanishing points that are far off. Minimiser: sparse
//! Levenberg-Marquardt (`fit/solve.rs`). Error bars: the inverse of `J^T J` times the click
//! variance, propagated to each reported quantity by its gradient (first order), as in
//! Criminisi, Reid & Zisserman, "Single view metrology", IJCV 40(2), 2000, section 5.

mod blocks;
mod box_edges;
mod evidence;
mod fitted;
mod init;
mod lens;
pub(crate) mod model;
pub(crate) mod prior;
pub(crate) mod solve;
pub(crate) mod uncertainty;

use nalgebra::{Vector2, Vector3};

use crate::calibration::{Calibration, HorizonFrame, Perspective};
use crate::error::{MetrologyError, Result};
use crate::interrupt::Interrupt;
use crate::reconstruct::{
    Method, ObjectKind, ReconstructedObject, Reconstruction, require_below_horizon,
};
use crate::scene::{BoxCorner, BoxView, ObjectShape, PixelPoint, Scene};

use evidence::{evidence_warnings, rescale_evidence, widen_disagreeing_evidence, widened_warnings};
pub(crate) use fitted::click_sigma;
pub(crate) use init::whitening;
use model::{Camera, Part, px, vp_direction};
pub(crate) use solve::Problem;
use solve::{Model, Singular, minimise};

pub use fitted::{FitOptions, Fitted, MIN_CLICK_SIGMA_PX, MIN_DOF_FOR_SIGMA, PointResidual};
pub use uncertainty::{CHI2_2DOF_95, FitUncertainty, ellipse_95};

/// Largest focal length the fit accepts, in image diagonals (a 1.5 degree field of view).
pub const MAX_FOCAL_DIAGONALS: f64 = 40.0;

/// The standard deviation (degrees, each axis of the scene's chart) with which the fit weighs
/// a vanishing point given as a `point` or `direction` without `covariance_deg2`: such a
/// point is a fact (docs/scene-format.md; the thesis takes every vanishing point so), and
/// 0.001 degree is as exact as the fit can hold one. It is 0.02 px at a 1,000 px focal
/// length, so no click noise moves it, yet 17 times the fit's finite-difference step in the
/// camera's angles (1e-6 radian), so its residual stays smooth. Until 2026-11-30 such a point
/// weighed as much as one click at a focal length's distance, which neither the format nor
/// the thesis says: on the shared rooms its ellipses held 99.2 % of the true centres, with
/// twice the error of the same points weighed as facts (docs/results.md).
pub const GIVEN_POINT_SD_DEG: f64 = 1e-3;

/// Fit the camera and every object of a validated scene of a pinhole camera: a scene with a
/// `lens_distortion` is fitted as [`Scene::undistorted`] gives it (as [`crate::map::build_map`]
/// does, which also adds the lens's uncertainty to the error bars).
///
/// # Errors
/// - [`MetrologyError::InvalidField`] for a scene whose `lens_distortion` has a `k` other than
///   0: undistort it first;
/// - [`MetrologyError::InvalidField`] when an object's clicks do not fix it, naming the
///   corner to add;
/// - [`MetrologyError::Degenerate`] when the fit does not converge, a box comes out with its
///   top below its base, or the data do not determine a quantity (a singular covariance),
///   naming the object and what to add;
/// - the vanishing-point errors of [`Scene::resolve_vanishing_points`] when no starting
///   camera can be found.
pub fn fit_scene(scene: &Scene, options: &FitOptions) -> Result<Fitted> {
    fit_scene_until(scene, options, &Interrupt::default())
}

/// [`fit_scene`], stopping early when `interrupt` fires: it is looked at before every
/// Levenberg-Marquardt iteration of every start, so the fit stops within one iteration.
///
/// # Errors
/// As [`fit_scene`], and [`MetrologyError::Interrupted`] when `interrupt` fires.
pub fn fit_scene_until(
    scene: &Scene,
    options: &FitOptions,
    interrupt: &Interrupt,
) -> Result<Fitted> {
    let result = fit_scene_orders(scene, options, interrupt);
    // An interrupted minimiser returns where it was: not a result (nor its failure).
    stop_if_interrupted(scene, interrupt)?;
    let mut fitted = result?;
    fitted.problem.interrupt = Interrupt::default();
    Ok(fitted)
}

/// [`MetrologyError::Interrupted`] when `interrupt` has fired, naming the photo's fit.
pub(crate) fn stop_if_interrupted(scene: &Scene, interrupt: &Interrupt) -> Result<()> {
    match interrupt.check() {
        Some(reason) => Err(MetrologyError::Interrupted {
            work: format!("the fit of a photo of {} objects", scene.objects.len()),
            reason,
        }),
        None => Ok(()),
    }
}

/// The fit of every reading of the vanishing points (see [`fit_scene`]).
fn fit_scene_orders(scene: &Scene, options: &FitOptions, interrupt: &Interrupt) -> Result<Fitted> {
    if let Some(lens) = scene.lens_distortion.filter(|l| l.k != 0.0) {
        return Err(MetrologyError::InvalidField {
            field: "lens_distortion".to_owned(),
            reason: format!(
                "k = {}: the fit takes a pinhole camera's clicks; fit Scene::undistorted() (vpmap build does)",
                lens.k
            ),
        });
    }
    check_below_given_horizon(scene)?;
    // Each reading of which vanishing point is vertical; the best fit wins, the first on a
    // tie (init::vanishing_point_orders).
    let mut best: Option<(f64, Fitted)> = None;
    let mut first_error = None;
    for order in init::vanishing_point_orders(scene)? {
        stop_if_interrupted(scene, interrupt)?;
        match fit_order(scene, order, options, interrupt) {
            Ok(fitted) => {
                let cost = fitted.problem.cost(&fitted.x);
                if best
                    .as_ref()
                    .is_none_or(|(b, _)| cost < b - TIE_COST_PX2 * b.max(1.0))
                {
                    best = Some((cost, fitted));
                }
            }
            Err(e) => {
                first_error.get_or_insert(e);
            }
        }
    }
    match (best, first_error) {
        (Some((_, fitted)), _) => Ok(fitted),
        (None, Some(e)) => Err(e),
        (None, None) => Err(MetrologyError::Degenerate {
            field: "vanishing_points".to_owned(),
            reason: "the fit found no reading of the vanishing points".to_owned(),
        }),
    }
}

/// Relative difference of two fits' costs under which they count as equally good.
const TIE_COST_PX2: f64 = 1e-9;

/// The fit for one reading of the vanishing points: the principal point fitted where the
/// scene allows it, else (or when that fails) held at the image centre, with a warning.
fn fit_order(
    scene: &Scene,
    order: [usize; 3],
    options: &FitOptions,
    interrupt: &Interrupt,
) -> Result<Fitted> {
    match fit_with(scene, true, order, options, interrupt) {
        Ok(fitted) => Ok(fitted),
        Err((e, false)) => Err(e),
        // The vanishing points did not fix the principal point after all (nearly parallel
        // edges meeting far outside the image): hold it at the image centre and say so.
        Err((free_error, true)) => {
            let mut fitted =
                fit_with(scene, false, order, options, interrupt).map_err(|(e, _)| e)?;
            fitted.calibration.warnings.push(format!(
                "the three vanishing points do not fix the principal point ({free_error}); it was held at the image centre ({:.1}, {:.1})",
                scene.image.centre().x,
                scene.image.centre().y
            ));
            Ok(fitted)
        }
    }
}

/// The fit with the principal point fitted where the scene allows it (`fit_pp`) or held;
/// on failure the error and whether the principal point was fitted.
fn fit_with(
    scene: &Scene,
    fit_pp: bool,
    order: [usize; 3],
    options: &FitOptions,
    interrupt: &Interrupt,
) -> std::result::Result<Fitted, (MetrologyError, bool)> {
    // Evidence with its own uncertainty weighs against the clicks in their noise: given, 1 px
    // for clicks with covariances (absolute), else estimated below.
    let has_covariances = !scene.click_covariances_px2.is_empty();
    let known_sigma = options
        .click_sigma_px
        .or_else(|| has_covariances.then_some(1.0));
    let mut starts = init::build(scene, fit_pp, order, known_sigma, init::Cameras::Given)
        .map_err(|e| (e, false))?;
    let pp_free = starts.first().is_some_and(|s| s.problem.fixed_pp.is_none());
    // From the best start; the others only when it fails or ends with residuals far above
    // a pixel (a local minimum, or a camera running off to infinite focal length). When none
    // of the given vanishing points' cameras fits well, the cameras the clicked boxes' own
    // edges imply are tried too (a detected point taken from the wrong edges).
    let mut best: Option<(Solved, usize)> = None;
    let mut first_error = None;
    let mut good = false;
    let mut next = 0;
    let mut box_edges_tried = false;
    while !good {
        let Some(start) = starts.get_mut(next) else {
            if box_edges_tried {
                break;
            }
            box_edges_tried = true;
            match init::build(scene, fit_pp, order, known_sigma, init::Cameras::BoxEdges) {
                Ok(more) => starts.extend(more),
                Err(e) => {
                    first_error.get_or_insert(e);
                }
            }
            continue;
        };
        let k = next;
        next += 1;
        stop_if_interrupted(scene, interrupt).map_err(|e| (e, false))?;
        start.problem.interrupt = interrupt.clone();
        match run(scene, &start.problem, start.x0.clone()) {
            Ok(sol) => {
                let dof = start
                    .problem
                    .residual_count()
                    .saturating_sub(start.problem.len())
                    .max(1);
                good = sol.cost / dof as f64 <= GOOD_FIT_PX2;
                if best.as_ref().is_none_or(|(b, _)| sol.cost < b.cost) {
                    best = Some((sol, k));
                }
            }
            Err(e) => {
                first_error.get_or_insert(e);
            }
        }
    }
    let Some((best, k)) = best else {
        let e = first_error.unwrap_or_else(|| MetrologyError::Degenerate {
            field: "objects".to_owned(),
            reason: "the fit found no starting point".to_owned(),
        });
        return Err((e, pp_free));
    };
    let built = &starts[k];
    let best = if known_sigma.is_none() {
        rescale_evidence(best)
    } else {
        best
    };
    let (best, widened) = widen_disagreeing_evidence(best, known_sigma.is_none());
    let mut fitted = finish(
        scene,
        best,
        built.object_parts.clone(),
        built.floor_distance_parts,
    )
    .map_err(|e| (e, pp_free))?;
    fitted
        .calibration
        .warnings
        .extend(built.warnings.iter().cloned());
    fitted
        .calibration
        .warnings
        .extend(evidence_warnings(&fitted, order));
    fitted
        .calibration
        .warnings
        .extend(widened_warnings(&widened, order));
    Ok(fitted)
}

/// Mean squared residual (pixels squared) under which a fit from the first start is taken
/// without trying the others: clicks within about 3 px.
const GOOD_FIT_PX2: f64 = 9.0;

/// With every vanishing point given as a point the horizon is known: a floor point clicked on
/// or above it cannot be on the floor, and is refused by name, as the other methods do,
/// before it can bend the fit; given vanishing points that calibrate no camera are refused.
fn check_below_given_horizon(scene: &Scene) -> Result<()> {
    let exact = scene
        .vanishing_points
        .iter()
        .all(|v| v.point.is_some() && v.lines.len() < 2 && v.covariance_deg2.is_none());
    let cal = match crate::camera::calibrate(scene) {
        Ok(cal) => cal,
        // Vanishing points given as points are facts: if they calibrate no camera, no fit
        // can honour them. Fitted to segments, they are evidence the fit weighs with the
        // objects', so only points that coincide are refused.
        Err(e) if exact || matches!(e, MetrologyError::CoincidentVanishingPoints { .. }) => {
            return Err(e);
        }
        Err(_) => return Ok(()),
    };
    if !exact {
        // Fitted to segments, the horizon is evidence too (short noisy edges put it tens of
        // pixels off): the fit places it, and `finish` checks the floor clicks against it.
        return Ok(());
    }
    let check = |field: String, p: PixelPoint| require_below_horizon(&cal, &field, p).map(|_| ());
    for (i, obj) in scene.objects.iter().enumerate() {
        if let Some(b) = &obj.base {
            for (c, p) in b.given() {
                check(format!("objects[{i}].base.{}", c.name()), p)?;
            }
        }
        if let Some(f) = &obj.footprint {
            for (k, p) in f.iter().enumerate() {
                check(format!("objects[{i}].footprint[{k}]"), *p)?;
            }
        }
    }
    for (k, p) in scene.floor.iter().enumerate() {
        check(format!("floor[{k}]"), *p)?;
    }
    Ok(())
}

/// A converged minimisation with its problem.
struct Solved {
    problem: Problem,
    x: Vec<f64>,
    cost: f64,
    iterations: usize,
}

fn run(scene: &Scene, problem: &Problem, x0: Vec<f64>) -> Result<Solved> {
    let sol = minimise(problem, x0).ok_or_else(|| MetrologyError::Degenerate {
        field: "objects".to_owned(),
        reason: "the fit's starting point puts a clicked point behind the camera; check that the vanishing points belong to the room's directions".to_owned(),
    })?;
    let diagonal = scene.image.diagonal();
    if sol.x[0] > MAX_FOCAL_DIAGONALS * diagonal {
        return Err(MetrologyError::Degenerate {
            field: "vanishing_points".to_owned(),
            reason: format!(
                "the fit runs off to a focal length of {:.0} px ({:.0} image diagonals): the vanishing points' edges are too short or nearly parallel to fix the camera; click longer edges towards each vanishing point",
                sol.x[0],
                sol.x[0] / diagonal
            ),
        });
    }
    if !sol.converged {
        return Err(MetrologyError::Degenerate {
            field: "objects".to_owned(),
            reason: format!(
                "the fit did not converge in {} iterations (reprojection error {:.3} px RMS); check for a misplaced click",
                sol.iterations,
                (sol.cost / problem.residual_count().max(1) as f64).sqrt()
            ),
        });
    }
    Ok(Solved {
        problem: problem.clone(),
        x: sol.x,
        cost: sol.cost,
        iterations: sol.iterations,
    })
}

/// The vanishing point of a map direction as a finite pixel (points at infinity are pushed
/// to 1e12 px along their direction).
fn finite_vp(cam: &Camera, d: Vector3<f64>) -> Vector2<f64> {
    let v = cam.vanishing_point(d);
    let w = if v.z.abs() < 1e-12 * v.x.hypot(v.y).max(1.0) {
        1e-12 * v.x.hypot(v.y).max(1.0) * if v.z < 0.0 { -1.0 } else { 1.0 }
    } else {
        v.z
    };
    Vector2::new(v.x / w, v.y / w)
}

pub(crate) fn calibration_of(cam: &Camera, perspective: Perspective) -> Calibration {
    let o = cam.principal_point_px;
    // The horizon: through the vanishing point of the camera's forward horizontal direction,
    // along the image of the floor's line at infinity.
    let ahead = finite_vp(cam, Vector3::new(0.0, 1.0, 0.0));
    let side = cam.vanishing_point(Vector3::new(1.0, 0.0, 0.0));
    let ahead_h = cam.vanishing_point(Vector3::new(0.0, 1.0, 0.0));
    let line = ahead_h.cross(&side);
    let mut along = Vector2::new(line.y, -line.x).normalize();
    if along.x < 0.0 || (along.x == 0.0 && along.y > 0.0) {
        along = -along;
    }
    let up = Vector2::new(along.y, -along.x);
    let mut vps = vec![
        finite_vp(cam, vp_direction(cam, 0)),
        finite_vp(cam, vp_direction(cam, 1)),
    ];
    if perspective == Perspective::ThreePoint {
        vps.push(finite_vp(cam, vp_direction(cam, 2)));
    }
    Calibration {
        perspective,
        focal_px: cam.focal_px,
        pitch_rad: cam.pitch_rad,
        roll_rad: along.y.atan2(along.x),
        vanishing_points_px: vps,
        frame: HorizonFrame {
            origin_px: o,
            along,
            up,
            horizon_offset_px: (ahead - o).dot(&up),
        },
        warnings: Vec::new(),
    }
}

fn finish(
    scene: &Scene,
    solved: Solved,
    object_parts: Vec<usize>,
    floor_distance_parts: Option<[usize; 2]>,
) -> Result<Fitted> {
    let Solved {
        problem,
        x,
        cost,
        iterations,
    } = solved;
    let cam = problem.camera(&x);
    let perspective = if scene.vanishing_points.len() == 3 {
        Perspective::ThreePoint
    } else {
        Perspective::TwoPoint
    };
    let normal = problem
        .normal(&x)
        .ok_or_else(|| MetrologyError::Degenerate {
            field: "objects".to_owned(),
            reason: "a clicked point lies behind the fitted camera".to_owned(),
        })?;
    if let Some(block) = normal.singular_block() {
        return Err(singular_error(scene, &problem, &object_parts, block));
    }
    let calibration = calibration_of(&cam, perspective);
    // A floor point clicked on or above the fitted horizon cannot be on the floor: refuse it
    // by name, as the other methods do, rather than bend the fit around it.
    for (i, _) in scene.objects.iter().enumerate() {
        match &problem.parts[object_parts[i]] {
            Part::Box { clicks, .. } => {
                for c in clicks.iter().filter(|c| c.place.2 == 0) {
                    require_below_horizon(
                        &calibration,
                        &format!("objects[{i}].{}", c.name),
                        [c.pixel.x, c.pixel.y],
                    )?;
                }
            }
            Part::Footprint { vertices, .. } => {
                for (k, v) in vertices.iter().enumerate() {
                    require_below_horizon(
                        &calibration,
                        &format!("objects[{i}].footprint[{k}]"),
                        [v.x, v.y],
                    )?;
                }
            }
            Part::FloorPoint { .. } => {}
        }
    }
    let mut objects = Vec::with_capacity(scene.objects.len());
    for (i, obj) in scene.objects.iter().enumerate() {
        let part_index = object_parts[i];
        let part = &problem.parts[part_index];
        let p = &x[problem.offsets[part_index]..problem.offsets[part_index] + part.len()];
        let (kind, footprint, height) = match part {
            Part::Box {
                axes,
                has_top,
                own_yaw,
                ..
            } => {
                let corner = |i: u8, j: u8| {
                    let c = Part::box_corner(&cam, *axes, *own_yaw, *has_top, p, (i, j, 0));
                    Vector2::new(c.x, c.y)
                };
                let h = has_top.then(|| p[4]);
                // Each top click must lie above its edge's base: the height at which its ray
                // passes closest to the vertical through the fitted base corner.
                let Part::Box { clicks, .. } = part else {
                    continue;
                };
                for c in clicks.iter().filter(|c| c.place.2 == 1) {
                    let base = Part::box_corner(
                        &cam,
                        *axes,
                        *own_yaw,
                        *has_top,
                        p,
                        (c.place.0, c.place.1, 0),
                    );
                    let r = cam.ray(c.pixel);
                    let horizontal = Vector2::new(r.x, r.y);
                    if horizontal.norm_squared() > 0.0 {
                        let t = Vector2::new(base.x, base.y).dot(&horizontal)
                            / horizontal.norm_squared();
                        let height = 1.0 + r.z * t;
                        if t > 0.0 && height < 0.0 {
                            return Err(MetrologyError::Degenerate {
                                field: format!("objects[{i}].{}", c.name),
                                reason: format!(
                                    "object {:?} comes out with a negative height ({height:.6} camera heights) at this corner: the top point lies below its base in the image",
                                    obj.name
                                ),
                            });
                        }
                    }
                }
                if let Some(h) = h
                    && h <= 0.0
                {
                    return Err(MetrologyError::Degenerate {
                        field: format!("objects[{i}].top"),
                        reason: format!(
                            "object {:?} comes out with its top {:.3} camera heights below its base: the top corners cannot belong to this box (check that each top corner is named like the base corner below it)",
                            obj.name, -h
                        ),
                    });
                }
                // A negative side is the same box with that axis pointing the other way;
                // only a side of no length is wrong.
                let scale = p[0].hypot(p[1]).max(1.0);
                if p[2].abs() <= 1e-9 * scale || p[3].abs() <= 1e-9 * scale {
                    return Err(MetrologyError::Degenerate {
                        field: format!("objects[{i}]"),
                        reason: format!(
                            "object {:?} comes out with a side of no length ({:.3} x {:.3} camera heights): its corners cannot belong to one box; check their names",
                            obj.name, p[2], p[3]
                        ),
                    });
                }
                (
                    ObjectKind::Box,
                    vec![corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)],
                    h,
                )
            }
            Part::Footprint { vertices, top } => {
                let fp = (0..vertices.len())
                    .map(|k| Vector2::new(p[2 * k], p[2 * k + 1]))
                    .collect();
                let h = top.map(|_| p[2 * vertices.len()]);
                if let Some(h) = h
                    && h < 0.0
                {
                    return Err(MetrologyError::Degenerate {
                        field: format!("objects[{i}].top.point"),
                        reason: format!(
                            "object {:?} comes out with a negative height ({h:.6} camera heights): the top point lies below its base in the image",
                            obj.name
                        ),
                    });
                }
                (ObjectKind::Footprint, fp, h)
            }
            Part::FloorPoint { .. } => continue,
        };
        objects.push(ReconstructedObject {
            name: obj.name.clone(),
            kind,
            footprint,
            height,
        });
    }
    let floor = scene
        .floor
        .iter()
        .enumerate()
        .map(|(i, p)| {
            cam.floor_point(px(*p))
                .ok_or_else(|| MetrologyError::NotBelowHorizon {
                    field: format!("floor[{i}]"),
                    x: p[0],
                    y: p[1],
                    distance_px: -cam.below_horizon_px(px(*p)),
                    side: "on or above",
                })
        })
        .collect::<Result<Vec<_>>>()?;
    // The residuals as the fit weighs them, and in pixels (without the clicks' whitening).
    let residuals = problem.residuals(&x).unwrap_or_default();
    let pixel_residuals = if problem.has_click_covariances() {
        let mut unweighted = problem.clone();
        unweighted.weights.clear();
        unweighted.residuals(&x).unwrap_or_default()
    } else {
        residuals.clone()
    };
    let weighted_residuals = point_residuals(scene, &problem, &object_parts, &residuals)
        .into_iter()
        .map(|r| r.distance_px)
        .collect();
    let point_residuals = point_residuals(scene, &problem, &object_parts, &pixel_residuals);
    let clicks = point_residuals.len().max(1);
    // Folded from +0: an empty sum of f64 is -0, which would print as "-0.00 px".
    let rms = (point_residuals
        .iter()
        .map(|r| r.distance_px * r.distance_px)
        .fold(0.0, |a, b| a + b)
        / clicks as f64)
        .sqrt();
    let principal_point_fitted = problem.fixed_pp.is_none();
    let _ = cost;
    Ok(Fitted {
        calibration,
        reconstruction: Reconstruction {
            method: Method::Fit,
            objects,
            floor,
        },
        rms_residual_px: rms,
        degrees_of_freedom: problem.residual_count().saturating_sub(problem.len()),
        iterations,
        principal_point_fitted,
        point_residuals,
        weighted_residuals,
        room_yaw_rad: cam.room_yaw_rad,
        problem,
        x,
        object_parts,
        floor_distance_parts,
    })
}

fn point_residuals(
    scene: &Scene,
    problem: &Problem,
    object_parts: &[usize],
    residuals: &[f64],
) -> Vec<PointResidual> {
    let mut starts = Vec::with_capacity(problem.parts.len());
    let mut at: usize = problem.vps.iter().map(model::vp_residual_count).sum();
    for part in &problem.parts {
        starts.push(at);
        at += part.residual_count();
    }
    let dist = |k: usize| {
        residuals
            .get(k)
            .copied()
            .unwrap_or(0.0)
            .hypot(residuals.get(k + 1).copied().unwrap_or(0.0))
    };
    let mut out = Vec::new();
    for (i, obj) in scene.objects.iter().enumerate() {
        let part_index = object_parts[i];
        let start = starts[part_index];
        match &problem.parts[part_index] {
            Part::Box { clicks, .. } => {
                for (k, c) in clicks.iter().enumerate() {
                    out.push(PointResidual {
                        object: obj.name.clone(),
                        field: format!("objects[{i}].{}", c.name),
                        distance_px: dist(start + 2 * k),
                    });
                }
            }
            Part::Footprint { vertices, top } => {
                for k in 0..vertices.len() {
                    out.push(PointResidual {
                        object: obj.name.clone(),
                        field: format!("objects[{i}].footprint[{k}]"),
                        distance_px: dist(start + 2 * k),
                    });
                }
                if top.is_some() {
                    out.push(PointResidual {
                        object: obj.name.clone(),
                        field: format!("objects[{i}].top.point"),
                        distance_px: dist(start + 2 * vertices.len()),
                    });
                }
            }
            Part::FloorPoint { .. } => {}
        }
    }
    out
}

fn singular_error(
    scene: &Scene,
    problem: &Problem,
    object_parts: &[usize],
    block: Singular,
) -> MetrologyError {
    match block {
        Singular::Camera => MetrologyError::Degenerate {
            field: "vanishing_points".to_owned(),
            reason: "the vanishing points and clicks do not fix the camera (a singular covariance): give more or longer edges towards each vanishing point".to_owned(),
        },
        Singular::Part(p) => {
            let Some(i) = object_parts.iter().position(|&q| q == p) else {
                return MetrologyError::Degenerate {
                    field: "scale.floor_distance".to_owned(),
                    reason: "the floor distance's points are not fixed by the camera".to_owned(),
                };
            };
            let obj = &scene.objects[i];
            let advice = match (&problem.parts[p], obj.shape(i)) {
                (Part::Box { view, clicks, .. }, Ok(ObjectShape::Box { .. })) => {
                    let missing = missing_corner(*view, clicks);
                    format!("add `{missing}`")
                }
                _ => "click its vertices apart from each other".to_owned(),
            };
            MetrologyError::Degenerate {
                field: format!("objects[{i}]"),
                reason: format!(
                    "the clicks of object {:?} do not determine its size or place (a singular covariance): {advice}",
                    obj.name
                ),
            }
        }
    }
}

/// A corner not yet clicked, base corners first.
fn missing_corner(view: BoxView, clicks: &[model::CornerClick]) -> String {
    for top in [false, true] {
        for c in BoxCorner::ALL.into_iter().filter(|c| c.view() == view) {
            let (i, j) = c.grid_index();
            if !clicks.iter().any(|k| k.place == (i, j, u8::from(top))) {
                return format!("{}.{}", if top { "top" } else { "base" }, c.name());
            }
        }
    }
    "more corners".to_owned()
}

/// What to click to pin down an uncertain size of scene object `index` (`what`: length,
/// breadth or height): the corners the box lacks, base first.
#[must_use]
pub fn advice_for(scene: &Scene, index: usize, what: &str) -> String {
    let Some(obj) = scene.objects.get(index) else {
        return String::new();
    };
    match obj.shape(index) {
        Ok(ObjectShape::Box {
            view, base, top, ..
        }) => {
            let mut missing = Vec::new();
            for (level, corners) in [("base", base), ("top", &top)] {
                for c in BoxCorner::ALL.into_iter().filter(|c| c.view() == view) {
                    if corners.get(c).is_none() {
                        missing.push(format!("`{level}.{}`", c.name()));
                    }
                }
            }
            if missing.is_empty() {
                "click its corners more carefully, or use longer edges for the vanishing points"
                    .to_owned()
            } else if what == "height" {
                let tops: Vec<&String> = missing.iter().filter(|m| m.starts_with("`top")).collect();
                if tops.is_empty() {
                    format!("add {}", missing[0])
                } else {
                    format!("add {} (a top corner)", tops[0])
                }
            } else {
                format!(
                    "add {} if you can see it",
                    missing[..missing.len().min(2)].join(" or ")
                )
            }
        }
        _ => "click its vertices and top point more carefully".to_owned(),
    }
}

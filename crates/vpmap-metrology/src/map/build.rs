//! Building the map: everything `vpmap build` computes, from a validated scene to a
//! [`FloorMap`].

use geo::{Area, BooleanOps, Centroid, Polygon};
use nalgebra::Vector2;

use super::cameras::camera_report;
use super::options::BuildOptions;
use super::reconstruction::{
    box_size, check_plausible, meters_per_camera_height, reconstruct_scene,
};
use super::regions::{free_space, occlusion_shadow, ring, to_polygons};
use super::types::{FitReport, FloorMap, MapObject, Units};
use super::warnings::{crossing_warnings, fit_warnings, position_warnings};
use crate::camera::room_yaw_rad;
use crate::error::Result;
use crate::fit::{FitOptions, fit_scene_until};
use crate::interrupt::Interrupt;
use crate::reconstruct::{Method, ObjectKind};
use crate::scene::Scene;

/// Everything `vpmap build` computes, from a validated scene to a [`FloorMap`].
///
/// # Errors
/// Any calibration, reconstruction or scale error, naming the scene field and value.
///
/// # Example
/// ```
/// use vpmap_metrology::map::{build_map, BuildOptions, Units};
/// use vpmap_metrology::synth::{SynthOptions, synthesize};
/// let (scene, truth) = synthesize(&SynthOptions { seed: 7, ..SynthOptions::default() }).unwrap();
/// let map = build_map(&scene, &BuildOptions::default()).unwrap();
/// assert_eq!(map.units, Units::Meters);
/// assert!((map.objects[0].footprint[0][1] - truth.objects[0].footprint[0][1]).abs() < 1e-9);
/// ```
pub fn build_map(scene: &Scene, options: &BuildOptions) -> Result<FloorMap> {
    build_map_until(scene, options, &Interrupt::default())
}

/// [`build_map`], stopping early when `interrupt` fires while a photo's fit
/// ([`crate::fit::fit_scene_until`], method `fit`) or a room's
/// ([`crate::room::fit_room_until`]) runs.
///
/// # Errors
/// As [`build_map`], and [`crate::MetrologyError::Interrupted`] when `interrupt` fires.
pub fn build_map_until(
    scene: &Scene,
    options: &BuildOptions,
    interrupt: &Interrupt,
) -> Result<FloorMap> {
    scene.validate()?;
    let pinhole = scene.undistorted();
    if !scene.other_photos.is_empty() {
        let (mut fitted, mut map) = room(scene, &pinhole, options, interrupt)?;
        let mut scene = std::borrow::Cow::Borrowed(scene);
        let mut said = Vec::new();
        // A photo's intrinsics priors the room's evidence rejects (a crop) are widened
        // (map/priors.rs), the room fitted again from scratch with them.
        let widened = noise_of(&map).map_or_else(Vec::new, |noise| {
            super::priors::test_room_priors(&pinhole, &fitted.0, noise, interrupt)
        });
        crate::fit::stop_if_interrupted(&scene, interrupt)?;
        if !widened.is_empty() {
            let mut wide = scene.clone().into_owned();
            for (n, w) in &widened {
                if let Some(p) = wide.photo_mut(*n) {
                    super::priors::widen(p, w);
                }
            }
            let whose = |n: usize| format!("photo {}'s", n + 1);
            match room(&wide, &wide.undistorted(), options, interrupt) {
                Ok(again) => {
                    (fitted, map) = again;
                    scene = std::borrow::Cow::Owned(wide);
                    said.extend(
                        widened
                            .iter()
                            .map(|(n, w)| super::priors::priors_warning(&whose(*n), w)),
                    );
                }
                Err(e @ crate::MetrologyError::Interrupted { .. }) => return Err(e),
                Err(e) => said.extend(
                    widened
                        .iter()
                        .map(|(n, w)| super::priors::priors_kept_warning(&whose(*n), w, &e)),
                ),
            }
        }
        // A photo's lens its clicks reject gives way to the one they agree on
        // (map/lens_refine.rs), the room fitted again from scratch with it.
        let refined = noise_of(&map).map_or_else(Vec::new, |noise| {
            super::lens_refine::refine_room_lenses(&scene, &fitted.0, &fitted.1, noise, interrupt)
        });
        crate::fit::stop_if_interrupted(&scene, interrupt)?;
        if !refined.is_empty() {
            let mut again = scene.into_owned();
            for (n, r) in &refined {
                if let Some(p) = again.photo_mut(*n) {
                    p.lens_distortion = Some(r.lens);
                }
                said.push(lens_warning(&format!("photo {}'s", n + 1), r));
            }
            (_, map) = room(&again, &again.undistorted(), options, interrupt)?;
        }
        map.warnings.splice(0..0, said);
        return Ok(map);
    }
    let (mut fitted, mut map) = single_photo(scene, &pinhole, options, interrupt)?;
    let mut scene = std::borrow::Cow::Borrowed(scene);
    let mut said = Vec::new();
    // Intrinsics priors the photo's evidence rejects (a crop) are widened (map/priors.rs),
    // the photo fitted again from scratch with them.
    let widened = fitted.as_ref().and_then(|(f, _)| {
        super::priors::test_photo_priors(&pinhole, f, noise_of(&map)?, interrupt)
    });
    crate::fit::stop_if_interrupted(&scene, interrupt)?;
    if let Some(w) = widened {
        let mut wide = scene.clone().into_owned();
        super::priors::widen(&mut wide, &w);
        match single_photo(&wide, &wide.undistorted(), options, interrupt) {
            Ok(again) => {
                (fitted, map) = again;
                scene = std::borrow::Cow::Owned(wide);
                said.push(super::priors::priors_warning("the photo's", &w));
            }
            Err(e @ crate::MetrologyError::Interrupted { .. }) => return Err(e),
            Err(e) => said.push(super::priors::priors_kept_warning("the photo's", &w, &e)),
        }
    }
    // A lens the clicks reject gives way to the one they agree on (map/lens_refine.rs).
    let refined = fitted.as_ref().and_then(|(f, costs)| {
        super::lens_refine::refine_lens(&scene, f, costs, noise_of(&map)?, interrupt)
    });
    crate::fit::stop_if_interrupted(&scene, interrupt)?;
    if let Some(r) = refined {
        let mut again = scene.into_owned();
        again.lens_distortion = Some(r.lens);
        (_, map) = single_photo(&again, &again.undistorted(), options, interrupt)?;
        said.push(lens_warning("the", &r));
    }
    map.warnings.splice(0..0, said);
    Ok(map)
}

/// How the lens's profile weighs the clicks of `map`'s fit (`None` without a fit).
fn noise_of(map: &FloorMap) -> Option<super::lens_refine::ClickNoise> {
    let report = map.fit.as_ref()?;
    Some(if report.click_sigma_source == "residuals" {
        super::lens_refine::ClickNoise::Estimated
    } else {
        super::lens_refine::ClickNoise::Known(report.click_sigma_px)
    })
}

/// The warning that the clicks refined a lens: `whose` is "the" (a photo) or "photo 2's".
fn lens_warning(whose: &str, r: &super::lens_refine::RefinedLens) -> String {
    format!(
        "the clicks disagree with {whose} lens distortion the scene gives, k = {} +- {}: they fit k = {:.5} +- {:.5} better by a chi-square of {:.1} (over {:.2}, the 95 % point of one degree of freedom), so the map is built with it",
        r.given[0],
        r.given[1],
        r.lens.k,
        r.lens.k_sd.unwrap_or(0.0),
        r.chi2_drop,
        super::lens_refine::LENS_REJECTED_CHI2
    )
}

/// A room's map (`pinhole` is `scene` undistorted by its photos' lenses) and the joint fit
/// behind it with, per photo, the costs of its lens spread's refits; each photo's spread in the
/// error bars.
///
/// # Errors
/// As [`build_map`]; [`crate::MetrologyError::Interrupted`] when `interrupt` fires.
fn room(
    scene: &Scene,
    pinhole: &Scene,
    options: &BuildOptions,
    interrupt: &Interrupt,
) -> Result<((crate::room::RoomFitted, Vec<LensCosts>), FloorMap)> {
    let fitted = super::room::fit_room_map(pinhole, options, interrupt)?;
    let mut map = super::room::room_map(pinhole, &fitted, options)?;
    let costs = super::lens::add_room_lens_spread(
        scene,
        &fitted,
        &mut map,
        |s, f| super::room::room_map(s, f, options),
        interrupt,
    )?;
    for (report, photo) in map.cameras.iter_mut().zip(scene.photos()) {
        report.lens_distortion = photo.lens_distortion;
    }
    map.camera.lens_distortion = scene.lens_distortion;
    Ok(((fitted, costs), map))
}

/// The costs of refits at other lenses a build has already paid for (the lens spread's):
/// `(k, cost)`.
type LensCosts = Vec<(f64, f64)>;

/// One photo's map (`pinhole` is `scene` undistorted by its lens) and the fit behind it
/// (method `fit`) with the costs of its lens spread's refits, the spread in its error bars.
///
/// # Errors
/// As [`build_map`]; [`crate::MetrologyError::Interrupted`] when `interrupt` fires.
fn single_photo(
    scene: &Scene,
    pinhole: &Scene,
    options: &BuildOptions,
    interrupt: &Interrupt,
) -> Result<(Option<(crate::fit::Fitted, LensCosts)>, FloorMap)> {
    let fitted = if options.method == Method::Fit {
        // The given click noise also weighs the evidence that has its own uncertainty.
        Some(fit_scene_until(
            pinhole,
            &FitOptions {
                click_sigma_px: options.click_sigma_px,
            },
            interrupt,
        )?)
    } else {
        None
    };
    let mut map = photo_map(pinhole, options, fitted.as_ref(), true)?;
    map.camera.lens_distortion = scene.lens_distortion;
    let costs = std::cell::RefCell::new(Vec::new());
    if let Some(fitted) = &fitted {
        // The fit again at k +- k_sd from its own answer (fit/lens.rs), mapped alike; each
        // refit's cost kept for the lens's profile.
        super::lens::add_lens_spread(scene, &mut map, |shifted, from, to| {
            let refit = fitted.refit_with_lens(shifted, from, to, interrupt)?;
            costs.borrow_mut().push((to.k, refit.cost()));
            photo_map(shifted, options, Some(&refit), false)
        });
    }
    // The lens's spread leaves out a fit that failed; one that was interrupted is no map.
    crate::fit::stop_if_interrupted(scene, interrupt)?;
    Ok((fitted.map(|f| (f, costs.into_inner())), map))
}

/// The map of one photo as a pinhole camera saw it (clicks undistorted): from `fitted` (method
/// `fit`, with its error bars when `uncertainty`), else by the scene's method. Without
/// `uncertainty` (a lens spread's refit, [`super::lens`]) only the objects and the camera are
/// reported: the free floor and the hidden regions are left empty.
fn photo_map(
    scene: &Scene,
    options: &BuildOptions,
    fitted: Option<&crate::fit::Fitted>,
    uncertainty: bool,
) -> Result<FloorMap> {
    let (cal, rec, factor) = if let Some(f) = fitted {
        check_plausible(&f.calibration, &f.reconstruction)?;
        (
            f.calibration.clone(),
            f.reconstruction.clone(),
            f.meters_per_camera_height(scene)?,
        )
    } else {
        let (cal, rec) = reconstruct_scene(scene, options.method)?;
        let factor = meters_per_camera_height(scene, &cal, &rec)?;
        (cal, rec, factor)
    };
    let (k, units) = match factor {
        Some(f) => (f, Units::Meters),
        None => (1.0, Units::CameraHeights),
    };
    let scaled = |v: &Vector2<f64>| v * k;
    let mut objects = Vec::with_capacity(rec.objects.len());
    let mut footprints = Vec::with_capacity(rec.objects.len());
    for o in &rec.objects {
        let fp: Vec<Vector2<f64>> = o.footprint.iter().map(scaled).collect();
        let poly = Polygon::new(ring(&fp), vec![]);
        let centroid = poly.centroid().map_or([f64::NAN; 2], |c| [c.x(), c.y()]);
        objects.push(MapObject {
            name: o.name.clone(),
            kind: o.kind,
            footprint: fp.iter().map(|p| [p.x, p.y]).collect(),
            height: o.height.map(|h| h * k),
            size: match o.kind {
                ObjectKind::Box => box_size(&fp),
                ObjectKind::Footprint => None,
            },
            centroid,
            area: poly.unsigned_area(),
            uncertainty: None,
        });
        footprints.push(fp);
    }
    let floor: Vec<Vector2<f64>> = rec.floor.iter().map(scaled).collect();
    let reach = 2.0
        * floor
            .iter()
            .chain(footprints.iter().flatten())
            .map(Vector2::norm)
            .fold(k, f64::max);
    // The free floor and what the objects hide from the camera: polygon operations that a
    // lens spread's map (its objects and camera only, `uncertainty` false) goes without.
    let (free, hidden) = if uncertainty {
        let free_mp = free_space(&floor, &footprints);
        let shadows: Vec<Polygon<f64>> = footprints
            .iter()
            .zip(&objects)
            .filter_map(|(fp, o)| occlusion_shadow(fp, o.height, k, reach))
            .collect();
        let hidden = if shadows.is_empty() || free_mp.0.is_empty() {
            Vec::new()
        } else {
            to_polygons(&free_mp.intersection(&geo::unary_union(&shadows)))
        };
        (to_polygons(&free_mp), hidden)
    } else {
        (Vec::new(), Vec::new())
    };
    let view_reach = 0.75 * reach.max(3.0 * k);
    let mut warnings = cal.warnings.clone();
    warnings.extend(crossing_warnings(scene, &rec));
    let mut camera_uncertainty = None;
    let mut fit_report = None;
    if let Some(f) = fitted.filter(|_| uncertainty) {
        let fit_options = FitOptions {
            click_sigma_px: options.click_sigma_px,
        };
        let u = f.uncertainty(scene, &fit_options)?;
        warnings.extend(fit_warnings(scene, f, &u));
        for (o, ou) in objects.iter_mut().zip(&u.objects) {
            o.uncertainty = Some(ou.clone());
        }
        warnings.extend(position_warnings(
            &objects,
            units,
            u.click_sigma_px,
            "snap its corners and click all it shows, or add a photo that sees it from nearer",
        ));
        camera_uncertainty = Some(u.camera);
        fit_report = Some(FitReport {
            click_sigma_px: u.click_sigma_px,
            click_sigma_source: u.click_sigma_source.to_owned(),
            rms_residual_px: f.rms_residual_px,
            rms_normalised: f
                .problem
                .weights
                .iter()
                .flatten()
                .any(Option::is_some)
                .then(|| crate::map::warnings::rms(&f.weighted_residuals) / u.click_sigma_px),
            degrees_of_freedom: f.degrees_of_freedom,
            iterations: f.iterations,
            principal_point_fitted: f.principal_point_fitted,
            clicks_with_covariance: Some(
                f.problem
                    .weights
                    .iter()
                    .flatten()
                    .filter(|w| w.is_some())
                    .count(),
            )
            .filter(|n| *n > 0),
        });
    }
    Ok(FloorMap {
        version: 1,
        units,
        method: options.method,
        camera: camera_report(
            &cal,
            scene.image,
            fitted.map_or_else(|| room_yaw_rad(&cal), |f| f.room_yaw_rad),
            k,
            view_reach,
            camera_uncertainty,
        ),
        cameras: Vec::new(),
        objects,
        floor: floor.iter().map(|p| [p.x, p.y]).collect(),
        free_space: free,
        hidden,
        warnings,
        alternatives: Vec::new(),
        fit: fit_report,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn free_area_is_the_floor_minus_the_footprints() {
        // Synthetic objects stand apart inside the floor, so the areas simply subtract.
        let (scene, _) = crate::synth::synthesize(&crate::synth::SynthOptions::default()).unwrap();
        let map = build_map(&scene, &BuildOptions::default()).unwrap();
        let floor: Vec<Vector2<f64>> = map.floor.iter().map(|p| Vector2::new(p[0], p[1])).collect();
        let floor_area = Polygon::new(ring(&floor), vec![]).unsigned_area();
        let objects: f64 = map.objects.iter().map(|o| o.area).sum();
        let expected = floor_area - objects;
        assert!(
            (map.free_area() - expected).abs() < 1e-9 * floor_area,
            "{} vs {expected}",
            map.free_area()
        );
    }
}

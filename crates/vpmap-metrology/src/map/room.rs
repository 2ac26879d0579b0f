//! The map of a room of several photos: the joint fit's objects and cameras in the first
//! photo's frame; the floor free where any photo sees free floor, hidden only where no photo
//! sees it.

use geo::{Area, BooleanOps, Centroid, Contains, MultiPolygon, Polygon};
use nalgebra::Vector2;

use super::cameras::{camera_report, placed};
use super::options::BuildOptions;
use super::reconstruction::box_size;
use super::regions::{occlusion_shadow, ring, to_polygons};
use super::types::{FitReport, FloorMap, MapAlternative, MapObject, Units};
use super::warnings::{
    WARN_RELATIVE_SD, WARN_RESIDUAL_SIGMAS, poorly_fixed_camera, position_warnings,
};
use crate::error::{MetrologyError, Result};
use crate::fit::FitOptions;
use crate::interrupt::Interrupt;
use crate::reconstruct::{Method, ObjectKind};
use crate::room::{RoomFitted, fit_room_until};
use crate::scene::Scene;

fn polygon(points: &[Vector2<f64>]) -> Polygon<f64> {
    Polygon::new(ring(points), vec![])
}

fn union(polygons: &[Polygon<f64>]) -> MultiPolygon<f64> {
    if polygons.is_empty() {
        MultiPolygon::new(Vec::new())
    } else {
        geo::unary_union(polygons)
    }
}

/// The joint fit of a room file for its map ([`super::build_map`] for a scene with other
/// photos; [`room_map`] makes the map of it).
pub(super) fn fit_room_map(
    scene: &Scene,
    options: &BuildOptions,
    interrupt: &Interrupt,
) -> Result<RoomFitted> {
    if options.method != Method::Fit {
        return Err(MetrologyError::InvalidField {
            field: "photos".to_owned(),
            reason: format!(
                "a room of {} photos is mapped by the joint fit (method fit); the {} method reads one photo",
                scene.photo_count(),
                options.method
            ),
        });
    }
    let fitted = fit_room_until(scene, interrupt)?;
    if let Some(reason) = interrupt.check() {
        return Err(MetrologyError::Interrupted {
            work: format!("the room map of {} photos", scene.photo_count()),
            reason,
        });
    }
    Ok(fitted)
}

/// The map of a room file from its joint fit `fitted` (of `scene`, clicks undistorted).
pub(super) fn room_map(
    scene: &Scene,
    fitted: &RoomFitted,
    options: &BuildOptions,
) -> Result<FloorMap> {
    let u = fitted.uncertainty(
        scene,
        &FitOptions {
            click_sigma_px: options.click_sigma_px,
        },
    )?;
    let (k, units) = match u.meters_per_unit {
        Some(k) => (k, Units::Meters),
        None => (1.0, Units::CameraHeights),
    };
    let mut objects = Vec::with_capacity(fitted.objects.len());
    let mut footprints = Vec::with_capacity(fitted.objects.len());
    for (o, ou) in fitted.objects.iter().zip(&u.objects) {
        let fp: Vec<Vector2<f64>> = o.footprint.iter().map(|p| p * k).collect();
        let poly = polygon(&fp);
        objects.push(MapObject {
            name: o.name.clone(),
            kind: o.kind,
            footprint: fp.iter().map(|p| [p.x, p.y]).collect(),
            height: o.height.map(|h| h * k),
            size: match o.kind {
                ObjectKind::Box => box_size(&fp),
                ObjectKind::Footprint => None,
            },
            centroid: poly.centroid().map_or([f64::NAN; 2], |c| [c.x(), c.y()]),
            area: poly.unsigned_area(),
            uncertainty: Some(ou.clone()),
        });
        footprints.push(fp);
    }
    let floors: Vec<Vec<Vector2<f64>>> = fitted
        .floors
        .iter()
        .map(|f| f.iter().map(|p| p * k).collect())
        .collect();
    let floor_polys: Vec<Polygon<f64>> = floors
        .iter()
        .filter(|f| f.len() >= 3)
        .map(|f| polygon(f))
        .collect();
    let obstacles: Vec<Polygon<f64>> = footprints
        .iter()
        .filter(|f| f.len() >= 3)
        .map(|f| polygon(f))
        .collect();
    let floor_union = union(&floor_polys);
    let free_mp = if obstacles.is_empty() {
        floor_union.clone()
    } else {
        floor_union.difference(&union(&obstacles))
    };
    let reach = 2.0
        * floors
            .iter()
            .flatten()
            .chain(footprints.iter().flatten())
            .map(Vector2::norm)
            .fold(k, f64::max);
    // What each photo sees: its floor outline minus every object's shadow from its camera.
    let mut seen = Vec::new();
    for (p, floor) in fitted.photos.iter().zip(&floors) {
        if floor.len() < 3 {
            continue;
        }
        let at = p.position * k;
        let station = geo::Point::new(at.x, at.y);
        let shadows: Vec<Polygon<f64>> = footprints
            .iter()
            .zip(&objects)
            // A camera standing over an object's footprint (on it, or the clicks say so)
            // looks down on it: it hides only the floor under itself.
            .filter(|(fp, _)| !polygon(fp).contains(&station))
            .filter_map(|(fp, o)| {
                let local: Vec<Vector2<f64>> = fp.iter().map(|q| q - at).collect();
                let s = occlusion_shadow(&local, o.height, p.height * k, reach + at.norm())?;
                Some(polygon(
                    &s.exterior()
                        .coords()
                        .map(|c| Vector2::new(c.x, c.y) + at)
                        .collect::<Vec<_>>(),
                ))
            })
            .collect();
        let view = MultiPolygon::new(vec![polygon(floor)]);
        seen.push(if shadows.is_empty() {
            view
        } else {
            view.difference(&union(&shadows))
        });
    }
    let seen_all = seen
        .into_iter()
        .reduce(|a, b| a.union(&b))
        .unwrap_or_else(|| MultiPolygon::new(Vec::new()));
    let hidden = to_polygons(&free_mp.difference(&seen_all));
    // The floor outline: the largest piece of the photos' floors together.
    let outline: Vec<[f64; 2]> = floor_union
        .0
        .iter()
        .max_by(|a, b| a.unsigned_area().total_cmp(&b.unsigned_area()))
        .map(|p| {
            let mut pts: Vec<[f64; 2]> = p.exterior().coords().map(|c| [c.x, c.y]).collect();
            if pts.len() > 1 && pts.first() == pts.last() {
                pts.pop();
            }
            pts
        })
        .unwrap_or_default();
    let view_reach = 0.75 * reach.max(3.0 * k);
    let cameras: Vec<_> = fitted
        .photos
        .iter()
        .zip(&u.photos)
        .zip(scene.photos())
        .map(|((p, pu), photo)| {
            placed(
                camera_report(
                    &p.calibration,
                    photo.image,
                    p.room_yaw_rad,
                    p.height * k,
                    view_reach,
                    Some(pu.camera),
                ),
                p.position * k,
                p.heading_rad,
            )
        })
        .collect();
    let mut warnings = fitted.warnings.clone();
    warnings.extend(u.warnings.iter().cloned());
    for (n, ((p, pu), photo)) in fitted
        .photos
        .iter()
        .zip(&u.photos)
        .zip(scene.photos())
        .enumerate()
    {
        for w in poorly_fixed_camera(photo, &p.calibration, &pu.camera, u.click_sigma_px) {
            warnings.push(format!("photo {}: {w}", n + 1));
        }
    }
    for (n, p) in fitted.photos.iter().enumerate() {
        let station = geo::Point::new(p.position.x * k, p.position.y * k);
        for (fp, o) in footprints.iter().zip(&objects) {
            if polygon(fp).contains(&station) {
                warnings.push(format!(
                    "photo {} stands inside the footprint of object {:?}: check that the objects named the same in several photos are the same object",
                    n + 1,
                    o.name
                ));
            }
        }
    }
    for &(i, what, rel) in &u.relative_size_sd {
        if rel > WARN_RELATIVE_SD
            && let Some(o) = fitted.objects.get(i)
        {
            warnings.push(format!(
                "object {:?}: its {what} is uncertain by +-{:.0} % (1 sigma, for {:.2} px clicks) in all photos together; click more of its corners",
                o.name,
                100.0 * rel,
                u.click_sigma_px
            ));
        }
    }
    warnings.extend(position_warnings(
        &objects,
        units,
        u.click_sigma_px,
        "snap its corners and click all they show in every photo that shows it, or add a photo that sees it from nearer",
    ));
    for (r, weighted) in fitted
        .point_residuals
        .iter()
        .zip(&fitted.weighted_residuals)
    {
        let sigmas = weighted / u.click_sigma_px;
        if u.click_sigma_px > 0.0 && sigmas > WARN_RESIDUAL_SIGMAS {
            warnings.push(format!(
                "`{}` of object {:?} lies {:.1} px ({:.1} sigma) from the fitted room: a misplaced click, or not the same object in every photo?",
                r.field, r.object, r.distance_px, sigmas
            ));
        }
    }
    let covariances = {
        use crate::fit::solve::Model as _;
        fitted.problem.has_click_covariances()
    };
    Ok(FloorMap {
        version: 1,
        units,
        method: Method::Fit,
        camera: cameras[0].clone(),
        cameras,
        objects,
        floor: outline,
        free_space: to_polygons(&free_mp),
        hidden,
        warnings,
        alternatives: fitted
            .alternatives
            .iter()
            .map(|a| MapAlternative {
                photo: a.photo + 1,
                turn_deg: a.turn_deg,
                placement_turn_deg: a.placement_turn_deg,
                cost_px2: a.cost_px2,
                chosen_cost_px2: a.chosen_cost_px2,
            })
            .collect(),
        fit: Some(FitReport {
            click_sigma_px: u.click_sigma_px,
            click_sigma_source: u.click_sigma_source.to_owned(),
            rms_residual_px: fitted.rms_residual_px,
            rms_normalised: covariances
                .then(|| super::warnings::rms(&fitted.weighted_residuals) / u.click_sigma_px),
            degrees_of_freedom: fitted.degrees_of_freedom,
            iterations: fitted.iterations,
            principal_point_fitted: fitted.photos.iter().all(|p| p.principal_point_fitted),
            clicks_with_covariance: Some(
                fitted
                    .problem
                    .parts
                    .iter()
                    .flat_map(|p| p.sightings.iter())
                    .filter(|s| s.weight.is_some())
                    .count(),
            )
            .filter(|n| *n > 0),
        }),
    })
}

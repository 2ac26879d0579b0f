//! The reconstruction a map is built from: the scene reconstructed with one method in camera
//! heights, refused where no camera could have seen it, and the scale in metres its known
//! length implies.

use nalgebra::Vector2;

use super::types::BoxSize;
use crate::calibration::Calibration;
use crate::camera::calibrate;
use crate::error::{MetrologyError, Result};
use crate::fit::{FitOptions, fit_scene};
use crate::projective::Projective;
use crate::reconstruct::{FloorProjection, Method, ObjectKind, Reconstruction, reconstruct};
use crate::scene::{Dimension, Scale, Scene};
use crate::sideview::SideView;

/// Reconstruct a validated scene with one method, in camera heights.
///
/// # Errors
/// As [`calibrate`] and [`reconstruct`].
pub fn reconstruct_scene(scene: &Scene, method: Method) -> Result<(Calibration, Reconstruction)> {
    if method == Method::Fit {
        let fitted = fit_scene(scene, &FitOptions::default())?;
        check_plausible(&fitted.calibration, &fitted.reconstruction)?;
        return Ok((fitted.calibration, fitted.reconstruction));
    }
    let cal = calibrate(scene)?;
    let rec = match method {
        Method::Sideview => reconstruct(scene, method, &SideView::new(&cal, scene))?,
        Method::Projective | Method::Fit => reconstruct(scene, method, &Projective::new(&cal))?,
    };
    check_plausible(&cal, &rec)?;
    Ok((cal, rec))
}

/// Farthest a mapped point may lie from the station point, in camera heights. A point farther
/// out sits within a fraction of a pixel of the horizon, where its position is meaningless.
pub const MAX_RANGE_CAMERA_HEIGHTS: f64 = 1e4;

/// Reject reconstructions no camera could have seen: points beyond [`MAX_RANGE_CAMERA_HEIGHTS`],
/// footprint corners behind the camera (a box completed from corners that disagree with the
/// vanishing points), and footprints of zero area.
pub(super) fn check_plausible(cal: &Calibration, rec: &Reconstruction) -> Result<()> {
    let (sin, cos) = cal.pitch_rad.sin_cos();
    let check = |field: String, p: &Vector2<f64>| -> Result<()> {
        if !(p.x.is_finite() && p.y.is_finite()) || p.norm() > MAX_RANGE_CAMERA_HEIGHTS {
            return Err(MetrologyError::Degenerate {
                field,
                reason: format!(
                    "the point lands {:.3e} camera heights from the camera, too close to the horizon to measure",
                    p.norm()
                ),
            });
        }
        // Depth along the optical axis of a floor point, camera height 1.
        if p.y * cos + sin <= 0.0 {
            return Err(MetrologyError::Degenerate {
                field,
                reason: format!(
                    "the footprint corner comes out at ({:.3}, {:.3}) camera heights, behind the camera: the annotated corners disagree with the vanishing points",
                    p.x, p.y
                ),
            });
        }
        Ok(())
    };
    for (i, o) in rec.objects.iter().enumerate() {
        for (j, p) in o.footprint.iter().enumerate() {
            check(format!("objects[{i}] ({:?}) corner {j}", o.name), p)?;
        }
        let twice_area: f64 = (0..o.footprint.len())
            .map(|j| {
                let (a, b) = (o.footprint[j], o.footprint[(j + 1) % o.footprint.len()]);
                a.x * b.y - a.y * b.x
            })
            .sum();
        let size = o.footprint.iter().map(Vector2::norm).fold(0.0, f64::max);
        if twice_area.abs() <= 1e-12 * size * size {
            return Err(MetrologyError::Degenerate {
                field: format!("objects[{i}]"),
                reason: format!(
                    "object {:?} has a footprint of zero area: its corners lie on one line",
                    o.name
                ),
            });
        }
    }
    for (i, p) in rec.floor.iter().enumerate() {
        check(format!("floor[{i}]"), p)?;
    }
    Ok(())
}

pub(super) fn box_size(footprint: &[Vector2<f64>]) -> Option<BoxSize> {
    if footprint.len() != 4 {
        return None;
    }
    let a = (footprint[1] - footprint[0]).norm();
    let b = (footprint[3] - footprint[0]).norm();
    Some(BoxSize {
        length: a.max(b),
        breadth: a.min(b),
    })
}

/// Metres per camera height implied by the scene's scale, or `None` without a scale.
///
/// # Errors
/// When the scale refers to a length that the reconstruction cannot measure (an object
/// without a top, a footprint object's length, a floor point above the horizon).
pub fn meters_per_camera_height(
    scene: &Scene,
    cal: &Calibration,
    rec: &Reconstruction,
) -> Result<Option<f64>> {
    let Some(scale) = scene.scale()? else {
        return Ok(None);
    };
    let (measured, field) = match scale {
        Scale::CameraHeight(h) => return Ok(Some(h)),
        Scale::FloorDistance(fd) => {
            let proj: Box<dyn FloorProjection> = match rec.method {
                Method::Sideview => Box::new(SideView::new(cal, scene)),
                Method::Projective | Method::Fit => Box::new(Projective::new(cal)),
            };
            let a = proj.floor_point("scale.floor_distance.from", fd.from)?;
            let b = proj.floor_point("scale.floor_distance.to", fd.to)?;
            ((a - b).norm() / fd.meters, "scale.floor_distance")
        }
        Scale::Object {
            name,
            dimension,
            meters,
        } => {
            let obj = rec.objects.iter().find(|o| o.name == name).ok_or_else(|| {
                MetrologyError::UnknownScaleObject {
                    name: name.clone(),
                    known: String::new(),
                }
            })?;
            let value = match dimension {
                Dimension::Height => obj.height.ok_or_else(|| MetrologyError::InvalidField {
                    field: "scale.dimension".to_owned(),
                    reason: format!(
                        "is \"height\", but object {name:?} has no top point to measure it"
                    ),
                })?,
                Dimension::Length | Dimension::Breadth => {
                    let size = match obj.kind {
                        ObjectKind::Box => box_size(&obj.footprint),
                        ObjectKind::Footprint => None,
                    }
                    .ok_or_else(|| MetrologyError::InvalidField {
                        field: "scale.dimension".to_owned(),
                        reason: format!(
                            "length and breadth are defined for boxes only; object {name:?} is a footprint (use \"height\" or a floor distance)"
                        ),
                    })?;
                    if dimension == Dimension::Length {
                        size.length
                    } else {
                        size.breadth
                    }
                }
            };
            (value / meters, "scale.meters")
        }
        Scale::Edge { name, ends, meters } => {
            let obj = rec.objects.iter().find(|o| o.name == name).ok_or_else(|| {
                MetrologyError::UnknownScaleObject {
                    name: name.clone(),
                    known: String::new(),
                }
            })?;
            let (a, b) = (ends[0].grid_index(), ends[1].grid_index());
            let fp = &obj.footprint;
            // Footprint order near, right, far, left: (0, 0), (1, 0), (1, 1), (0, 1).
            let corner = |i: u8, j: u8| match (i, j) {
                (0, 0) => fp[0],
                (1, 0) => fp[1],
                (1, _) => fp[2],
                _ => fp[3],
            };
            let value = if a.2 == b.2 {
                (corner(a.0, a.1) - corner(b.0, b.1)).norm()
            } else {
                obj.height.ok_or_else(|| MetrologyError::InvalidField {
                    field: "scale.edge".to_owned(),
                    reason: format!(
                        "is vertical, but object {name:?} has no top point to measure it"
                    ),
                })?
            };
            (value / meters, "scale.edge")
        }
    };
    if !(measured.is_finite() && measured > 0.0) {
        return Err(MetrologyError::Degenerate {
            field: field.to_owned(),
            reason: format!(
                "the known length measures {measured} camera heights per metre in the reconstruction; it must be positive"
            ),
        });
    }
    Ok(Some(1.0 / measured))
}

//! A whole map compared with its truth: every object in both scale variants, and the camera.

use serde::Serialize;

use super::coverage::{CameraCoverage, Coverage, camera_coverage, coverage};
use super::metrics::{ObjectErrors, object_errors, percent_error, rectangle_size, scale_factor};
use crate::error::{MetrologyError, Result};
use crate::map::{FloorMap, MapPoint, Units};
use crate::reconstruct::ObjectKind;
use crate::synth::Truth;

/// Names of the per-scene metrics, in the order of [`MapEvaluation::scene_values`].
pub const SCENE_METRICS: [&str; 4] = [
    "pitch_error_deg",
    "roll_error_deg",
    "focal_error_pct",
    "camera_height_error_pct",
];

/// Errors of the estimated camera.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CameraErrors {
    /// Estimated minus true pitch, degrees.
    pub pitch_error_deg: f64,
    /// Estimated minus true roll, degrees.
    pub roll_error_deg: f64,
    /// `(f_m - f_a) / f_a * 100`.
    pub focal_error_pct: f64,
}

/// One object's errors in both scale variants.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ObjectEvaluation {
    /// The object's name.
    pub name: String,
    /// Box or footprint.
    pub kind: ObjectKind,
    /// Whether it is the reference object of `S_k`.
    pub reference: bool,
    /// Against the truth scaled by `S_k` (eq. 6.1).
    pub sk: ObjectErrors,
    /// Against the truth at the true scale (the map in metres).
    pub true_scale: ObjectErrors,
    /// Whether the truth lies within the object's error bars (method `fit`: objects with
    /// [`crate::map::ObjectUncertainty`]; `None` otherwise).
    pub coverage: Option<Coverage>,
}

/// A map compared with its truth.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MapEvaluation {
    /// `S_k` of eq. 6.1 (1 for a perfect reconstruction).
    pub scale_factor: f64,
    /// The camera's errors.
    pub camera: CameraErrors,
    /// `(H_m - H_a / S_k) / (H_a / S_k) * 100`: the camera height in the `S_k` variant (the
    /// true-scale variant's is 0 by construction).
    pub camera_height_error_pct: f64,
    /// Per object, in scene order.
    pub objects: Vec<ObjectEvaluation>,
    /// Whether the true camera lies within the camera's error bars (method `fit`; `None`
    /// otherwise).
    pub camera_coverage: Option<CameraCoverage>,
}

impl MapEvaluation {
    /// The per-scene metrics in the order of [`SCENE_METRICS`].
    #[must_use]
    pub fn scene_values(&self) -> [f64; 4] {
        [
            self.camera.pitch_error_deg,
            self.camera.roll_error_deg,
            self.camera.focal_error_pct,
            self.camera_height_error_pct,
        ]
    }
}

/// Compare a map built at the true scale (in metres) with its truth: every object in both
/// scale variants, and the camera.
///
/// Objects are matched by position in scene order (their names must agree); the reference
/// object of `S_k` is the first box.
///
/// # Errors
/// [`MetrologyError::InvalidField`] when the map is not in metres, its objects do not match
/// the truth's or it has no box; [`MetrologyError::Degenerate`] from [`scale_factor`] and
/// [`object_errors`].
pub fn evaluate_map(map: &FloorMap, truth: &Truth) -> Result<MapEvaluation> {
    let invalid = |reason: String| MetrologyError::InvalidField {
        field: "eval".to_owned(),
        reason,
    };
    if map.units != Units::Meters {
        return Err(invalid(
            "the map must be in metres (a scene with its true scale) to compare with the truth"
                .to_owned(),
        ));
    }
    if map.objects.len() != truth.objects.len() {
        return Err(invalid(format!(
            "the map has {} objects, the truth {}",
            map.objects.len(),
            truth.objects.len()
        )));
    }
    if let Some((m, t)) = map
        .objects
        .iter()
        .zip(&truth.objects)
        .find(|(m, t)| m.name != t.name)
    {
        return Err(invalid(format!(
            "map object {:?} faces truth object {:?}",
            m.name, t.name
        )));
    }
    let reference = map
        .objects
        .iter()
        .position(|o| o.kind == ObjectKind::Box)
        .ok_or_else(|| {
            invalid("the scene has no box to serve as the reference object".to_owned())
        })?;
    let modelled_size = map
        .objects
        .get(reference)
        .and_then(|o| o.size.or_else(|| rectangle_size(&o.footprint)));
    let actual_size = truth
        .objects
        .get(reference)
        .and_then(|o| rectangle_size(&o.footprint));
    let (Some(modelled_size), Some(actual_size)) = (modelled_size, actual_size) else {
        return Err(invalid(
            "the reference box has no length and breadth".to_owned(),
        ));
    };
    let s_k = scale_factor(actual_size, modelled_size)?;
    let mut objects = Vec::with_capacity(map.objects.len());
    for (i, (m, t)) in map.objects.iter().zip(&truth.objects).enumerate() {
        let scaled: Vec<MapPoint> = t
            .footprint
            .iter()
            .map(|p| [p[0] / s_k, p[1] / s_k])
            .collect();
        objects.push(ObjectEvaluation {
            name: m.name.clone(),
            kind: m.kind,
            reference: i == reference,
            sk: object_errors(&m.footprint, m.height, &scaled, Some(t.height / s_k))?,
            true_scale: object_errors(&m.footprint, m.height, &t.footprint, Some(t.height))?,
            coverage: coverage(m, t),
        });
    }
    Ok(MapEvaluation {
        scale_factor: s_k,
        camera: CameraErrors {
            pitch_error_deg: map.camera.pitch_deg - truth.camera.pitch_deg,
            roll_error_deg: map.camera.roll_deg - truth.camera.roll_deg,
            focal_error_pct: percent_error(map.camera.focal_px, truth.camera.focal_px),
        },
        camera_height_error_pct: percent_error(map.camera.height, truth.camera.height / s_k),
        objects,
        camera_coverage: camera_coverage(&map.camera, &truth.camera),
    })
}

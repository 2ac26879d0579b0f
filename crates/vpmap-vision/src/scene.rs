//! From a [`Detection`] to a scene file (`docs/scene-format.md`), as `vpmap detect` writes it.
//!
//! Used by `vpmap detect` and by `vpmap serve`'s `/api/detect`, so both write the same file:
//! * the vertical vanishing point is the one flagged `vertical`, the other two are the
//!   horizontal ones, in the detection's order;
//! * the two horizontal directions are made orthogonal to the vertical one and to each other,
//!   each turned by the same amount about the vertical (the orthogonal pair symmetric about
//!   their bisectors). The vertical direction is kept as detected, so the horizon written (the
//!   line through the two horizontal points) is the measured one: the camera is never levelled;
//! * a horizontal point (nearly) at infinity is turned, with the other, about the vertical
//!   until it lies within [`MAX_VANISHING_POINT_OFFSET_PX`] of the principal point (this keeps
//!   the horizon);
//! * the scene is three-point perspective, with the vertical point written, unless the
//!   detection is two-point ([`Detection::perspective`], the tilt under
//!   [`crate::DetectOptions::two_point_tolerance_deg`]) or the vertical point lies farther than
//!   [`MAX_VANISHING_POINT_OFFSET_PX`] from the principal point (the vertical direction within
//!   about `focal / 1e7` rad of the image plane). A two-point scene leaves the vertical point
//!   out and still writes the measured horizon and the principal point the detector used: the
//!   scene format's two-point calibration then moves that principal point onto the horizon (a
//!   warning when it is more than 1 % of the image height off), and a reconstruction that keeps
//!   the principal point fits the pitch to the horizon instead;
//! * each vanishing point is written as `point` with up to
//!   [`MAX_LINES_PER_VANISHING_POINT`] of its longest supporting segments as `lines`; the
//!   vertical one only in three-point perspective;
//! * each written vanishing point carries its covariance (`covariance_deg2`,
//!   [`crate::uncertainty`]): its segments' spread plus the measured floor, in the chart of the
//!   scene's `focal_px` and `principal_point`;
//! * the principal point is written as a prior, not a fact: the image centre with
//!   `principal_point_sd_px` = [`PRINCIPAL_POINT_PRIOR_SD`] of the image diagonal (the fit refines
//!   it with the vanishing points and the clicks), unless the detection was given one
//!   ([`crate::DetectOptions::principal_point_px`]: a calibration), which is written as known;
//!   when the edges put it off the centre ([`Detection::principal_point_off_centre`]: a photo
//!   cropped off its centre, in clear three-point perspective) the prior's sd is
//!   [`CROPPED_PRINCIPAL_POINT_SD_DIAGONALS`] of the diagonal instead, as wide as `vpmap build`
//!   makes a prior its clicks reject, with a warning ([`DetectedScene::off_centre_warning`]);
//!   `focal_px` is the detector's estimate, a starting value the fit refines (its information
//!   is in the vanishing points already, so no prior is written for it, which would count it
//!   twice), or the given one with `focal_sd_px` [`GIVEN_FOCAL_SD`] of it;
//! * the scene written must calibrate ([`vpmap_metrology::map::calibrate`]).

use std::f64::consts::FRAC_1_SQRT_2;

use crate::detection::{Detection, Segment};
use crate::uncertainty::{VpCovariance, vp_covariance};
use nalgebra::{Vector2, Vector3};
use vpmap_metrology::calibration::{Calibration, Perspective};
use vpmap_metrology::map::{CROPPED_PRINCIPAL_POINT_SD_DIAGONALS, calibrate};
use vpmap_metrology::scene::{Scene, VpChart};

/// Farthest a written vanishing point may lie from the principal point, pixels.
pub const MAX_VANISHING_POINT_OFFSET_PX: f64 = 1e7;
/// Most supporting segments written per vanishing point (the longest ones).
pub const MAX_LINES_PER_VANISHING_POINT: usize = 40;
/// Shortest segment written as evidence, pixels.
const MIN_LINE_LENGTH_PX: f64 = 2.0;
/// A vanishing point resting on fewer segments than this is worth a warning
/// ([`DetectedScene::thinly_supported`]).
pub const FEW_SEGMENTS: usize = 6;
/// The standard deviation of the principal point's prior around the image centre, as a fraction
/// of the image diagonal (each coordinate): calibrated cameras' principal points lie within
/// about 1.4 % of the diagonal from the centre (York Urban 1.4 %, SUN RGB-D 0, ScanNet under
/// 0.2 %), so 1.5 % holds them inside 1 sd.
pub const PRINCIPAL_POINT_PRIOR_SD: f64 = 0.015;

/// The standard deviation of a focal length given to the detector (a calibration), as a
/// fraction of it.
pub const GIVEN_FOCAL_SD: f64 = 1e-3;

/// The vanishing points' names in messages, in role order ([`DetectedScene::roles`]).
pub const VP_NAMES: [&str; 3] = ["horizontal VP1", "horizontal VP2", "vertical VP3"];

type Vec3 = Vector3<f64>;

/// The camera a detected scene gives before any click, with its standard deviations
/// ([`DetectedScene::camera_estimate`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraEstimate {
    /// Focal length, pixels.
    pub focal_px: f64,
    /// Its standard deviation, pixels.
    pub focal_sd_px: f64,
    /// Principal point, pixels.
    pub principal_point_px: [f64; 2],
    /// Its standard deviations `[x, y]`, pixels, when the fit placed it (a written prior and
    /// three finite vanishing points); `None` when it was held.
    pub principal_point_sd_px: Option<[f64; 2]>,
    /// Pitch (positive looking down), degrees.
    pub pitch_deg: f64,
    /// Its standard deviation, degrees.
    pub pitch_sd_deg: f64,
    /// Roll, degrees.
    pub roll_deg: f64,
    /// Its standard deviation, degrees.
    pub roll_sd_deg: f64,
    /// The standard deviation of the horizon's offset from the principal point, pixels.
    pub horizon_sd_px: f64,
}

/// The scene written for a detection, and what it took.
#[derive(Debug, Clone)]
pub struct DetectedScene {
    /// The scene file's text, laid out like the examples of `docs/scene-format.md`.
    pub json: String,
    /// 2PP or 3PP, as written: 3PP exactly when the vertical vanishing point is written.
    pub perspective: Perspective,
    /// The camera as `vpmap build` recovers it from the scene.
    pub calibration: Calibration,
    /// Indices into `Detection::vanishing_points`: first horizontal, second horizontal,
    /// vertical.
    pub roles: [usize; 3],
    /// The directions written, in role order, camera frame (x right, y down, z forward).
    pub directions: [[f64; 3]; 3],
    /// The points written, in role order (the vertical one `None` in 2PP).
    pub points_px: [Option<[f64; 2]>; 3],
    /// Segments written as `lines`, per role (0 for the vertical in 2PP).
    pub lines_written: [usize; 3],
    /// Each written vanishing point's covariance, in role order (`None` for a vanishing point
    /// not written).
    pub covariances: [Option<VpCovariance>; 3],
    /// The principal point written and its standard deviation (`None`: held as known).
    pub principal_point_px: ([f64; 2], Option<f64>),
    /// The chart the covariances are stated in (the written focal length and principal point).
    pub chart: VpChart,
    /// The largest angle any vanishing direction was turned by, degrees.
    pub adjusted_deg: f64,
}

impl DetectedScene {
    /// The camera the written scene alone gives (its vanishing points with their covariances
    /// and the principal point's prior, no objects) and its standard deviations: the joint
    /// fit's camera before any click. `None` when that fit fails.
    #[must_use]
    pub fn camera_estimate(&self) -> Option<CameraEstimate> {
        let written = Scene::from_json_str(&self.json).ok()?;
        let scene = written.undistorted();
        let options = vpmap_metrology::fit::FitOptions::default();
        let fitted = vpmap_metrology::fit::fit_scene(&scene, &options).ok()?;
        let u = fitted.uncertainty(&scene, &options).ok()?;
        let cal = &fitted.calibration;
        // The horizon's offset from the principal point is f tan(pitch): its sd by the chain
        // rule, focal and pitch taken as independent (their correlation is small next to the
        // pitch's own share).
        let pitch = cal.pitch_rad;
        let sd_pitch = u.camera.pitch_deg_sd.to_radians();
        let horizon_sd_px = (cal.focal_px / pitch.cos().powi(2) * sd_pitch)
            .hypot(pitch.tan() * u.camera.focal_px_sd);
        Some(CameraEstimate {
            focal_px: cal.focal_px,
            focal_sd_px: u.camera.focal_px_sd,
            principal_point_px: [cal.frame.origin_px.x, cal.frame.origin_px.y],
            principal_point_sd_px: u.camera.principal_point_px_sd,
            pitch_deg: pitch.to_degrees(),
            pitch_sd_deg: u.camera.pitch_deg_sd,
            roll_deg: cal.roll_rad.to_degrees(),
            roll_sd_deg: u.camera.roll_deg_sd,
            horizon_sd_px,
        })
    }

    /// The warning for a photo whose edges put the principal point off its centre
    /// ([`Detection::principal_point_off_centre`]): where they put it, and the widened prior
    /// the scene carries instead of the centre's.
    #[must_use]
    pub fn off_centre_warning(&self, det: &Detection) -> Option<String> {
        if !det.principal_point_off_centre {
            return None;
        }
        let ([cx, cy], sd) = self.principal_point_px;
        let [x, y] = det.intrinsics.principal_point_px;
        Some(format!(
            "the edges put the principal point at ({x:.1}, {y:.1}), {:.0} px from the image centre ({cx:.1}, {cy:.1}): the photo looks cropped off its centre, so the scene's prior on the principal point is widened to +- {:.1} px (1 sd) for vpmap build to place it with the clicks",
            (x - cx).hypot(y - cy),
            sd.unwrap_or(0.0)
        ))
    }

    /// The written vanishing points resting on fewer than [`FEW_SEGMENTS`] segments of `det`,
    /// in role order: each one's name ([`VP_NAMES`]) and its number of segments.
    #[must_use]
    pub fn thinly_supported(&self, det: &Detection) -> Vec<(&'static str, usize)> {
        self.roles
            .iter()
            .zip(VP_NAMES)
            .filter_map(|(&i, name)| {
                let n = det.vanishing_points.get(i)?.segments.len();
                (n < FEW_SEGMENTS).then_some((name, n))
            })
            .collect()
    }

    /// Signed distance of the written horizon above the principal point the detector used
    /// (`det`'s), pixels, perpendicular to the horizon; positive when the camera looks down.
    #[must_use]
    pub fn horizon_offset_px(&self, det: &Detection) -> f64 {
        let cal = &self.calibration;
        let [cx, cy] = det.intrinsics.principal_point_px;
        cal.vanishing_points_px.first().map_or(0.0, |vp| {
            (vp.x - cx) * cal.frame.up.x + (vp.y - cy) * cal.frame.up.y
        })
    }
}

/// Why a detection gives no scene.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct SceneError(String);

fn fail<T>(message: impl Into<String>) -> Result<T, SceneError> {
    Err(SceneError(message.into()))
}

/// `a / |a|`, or `None` for a (nearly) zero or non-finite vector.
fn normalize(a: Vec3) -> Option<Vec3> {
    let n = a.norm();
    (n.is_finite() && n > 1e-12).then(|| a / n)
}

/// Rotate `v` about the unit axis `k` by `angle_rad` (Rodrigues' formula).
fn rotate(v: Vec3, k: Vec3, angle_rad: f64) -> Vec3 {
    let (s, c) = angle_rad.sin_cos();
    v * c + k.cross(&v) * s + k * (k.dot(&v) * (1.0 - c))
}

/// Angle between the lines along `a` and `b` (sign-free), degrees.
fn line_angle_deg(a: Vec3, b: Vec3) -> f64 {
    a.cross(&b).norm().atan2(a.dot(&b).abs()).to_degrees()
}

/// The image point of direction `d` (`None` when parallel to the image plane).
fn pixel_of_direction(d: Vec3, f: f64, c: [f64; 2]) -> Option<[f64; 2]> {
    (d.z.abs() > 0.0)
        .then(|| [c[0] + f * d.x / d.z, c[1] + f * d.y / d.z])
        .filter(|p| p[0].is_finite() && p[1].is_finite())
}

/// `v` to `digits` significant digits.
fn round_sig(v: f64, digits: i32) -> f64 {
    if v == 0.0 || !v.is_finite() {
        return v;
    }
    let magnitude = v.abs().log10().floor() as i32;
    round_to(v, digits - 1 - magnitude)
}

fn round_to(v: f64, decimals: i32) -> f64 {
    let s = 10f64.powi(decimals);
    (v * s).round() / s + 0.0
}

/// Which detected vanishing point plays which part: horizontal, horizontal, vertical.
fn roles(det: &Detection) -> Result<[usize; 3], SceneError> {
    let n = det.vanishing_points.len();
    let verticals: Vec<usize> = (0..n)
        .filter(|&i| det.vanishing_points[i].vertical)
        .collect();
    let horizontals: Vec<usize> = (0..n)
        .filter(|&i| !det.vanishing_points[i].vertical)
        .collect();
    match (verticals.as_slice(), horizontals.as_slice()) {
        ([v], [a, b]) => Ok([*a, *b, *v]),
        _ => fail(format!(
            "the detector returned {n} vanishing points ({} vertical); expected two horizontal and one vertical",
            verticals.len()
        )),
    }
}

/// The orthogonal frame nearest the detected directions, the vertical kept as detected (see the
/// module documentation).
fn manhattan_frame(h1: Vec3, h2: Vec3, v: Vec3) -> Result<[Vec3; 3], SceneError> {
    let Some(v) = normalize(v) else {
        return fail("the vertical vanishing direction is degenerate");
    };
    let Some(a) = normalize(h1 - v * h1.dot(&v)) else {
        return fail("the first horizontal vanishing direction is parallel to the vertical one");
    };
    let Some(b) = normalize(h2 - v * h2.dot(&v)) else {
        return fail("the second horizontal vanishing direction is parallel to the vertical one");
    };
    let (Some(u), Some(w)) = (normalize(a + b), normalize(a - b)) else {
        return fail("the two horizontal vanishing points coincide");
    };
    Ok([(u + w) * FRAC_1_SQRT_2, (u - w) * FRAC_1_SQRT_2, v])
}

/// Turn the horizontal pair about the vertical until neither point lies farther than
/// [`MAX_VANISHING_POINT_OFFSET_PX`] from the principal point.
fn keep_points_in_reach(frame: &mut [Vec3; 3], focal_px: f64) {
    let min_z = (focal_px / MAX_VANISHING_POINT_OFFSET_PX).min(0.5);
    for i in 0..2 {
        let d = frame[i];
        if d.z.abs() >= min_z {
            continue;
        }
        let g = frame[2].cross(&d).z;
        if g.abs() < min_z {
            continue;
        }
        let sign = if d.z == 0.0 {
            g.signum()
        } else {
            (d.z * g).signum()
        };
        let angle = sign * (2.0 * min_z / g.abs()).min(0.1);
        frame[0] = rotate(frame[0], frame[2], angle);
        frame[1] = rotate(frame[1], frame[2], angle);
    }
}

/// The image point of `d`, clamped to [`MAX_VANISHING_POINT_OFFSET_PX`] from `c`.
fn written_point(d: Vec3, f: f64, c: [f64; 2]) -> [f64; 2] {
    match pixel_of_direction(d, f, c) {
        Some(p) if (p[0] - c[0]).hypot(p[1] - c[1]) <= MAX_VANISHING_POINT_OFFSET_PX => p,
        _ => {
            let n = d.x.hypot(d.y).max(f64::MIN_POSITIVE);
            [
                c[0] + d.x / n * MAX_VANISHING_POINT_OFFSET_PX,
                c[1] + d.y / n * MAX_VANISHING_POINT_OFFSET_PX,
            ]
        }
    }
}

/// The longest supporting segments of one vanishing point, as `[x1, y1, x2, y2]`.
fn evidence(det: &Detection, vp: usize) -> Vec<[f64; 4]> {
    let Some(v) = det.vanishing_points.get(vp) else {
        return Vec::new();
    };
    let mut lines: Vec<(f64, [f64; 4])> = v
        .segments
        .iter()
        .filter_map(|&i| det.segments.get(i))
        .map(|s| {
            let l = [
                round_to(s.start_px[0], 2),
                round_to(s.start_px[1], 2),
                round_to(s.end_px[0], 2),
                round_to(s.end_px[1], 2),
            ];
            ((l[0] - l[2]).hypot(l[1] - l[3]), l)
        })
        .filter(|(len, l)| *len >= MIN_LINE_LENGTH_PX && l.iter().all(|v| v.is_finite()))
        .collect();
    lines.sort_by(|a, b| b.0.total_cmp(&a.0));
    lines.truncate(MAX_LINES_PER_VANISHING_POINT);
    lines.into_iter().map(|(_, l)| l).collect()
}

fn number(v: f64) -> String {
    serde_json::to_string(&v).unwrap_or_else(|_| "null".to_owned())
}

fn numbers(values: &[f64]) -> String {
    let parts: Vec<String> = values.iter().map(|&v| number(v)).collect();
    format!("[{}]", parts.join(", "))
}

/// A vanishing point as written: its point, covariance (degrees squared) and segments.
type WrittenVp = ([f64; 2], [[f64; 2]; 2], Vec<[f64; 4]>);

/// The scene file's text: one point or segment per line, fields in reading order.
fn scene_json(
    image_size_px: [u32; 2],
    perspective: Perspective,
    vanishing_points: &[WrittenVp],
    principal_point: ([f64; 2], Option<f64>),
    focal_px: (f64, Option<f64>),
    lens: Option<(f64, f64)>,
) -> String {
    let vps: Vec<String> = vanishing_points
        .iter()
        .map(|(point, cov, lines)| {
            let cov = format!("[{}, {}]", numbers(&cov[0]), numbers(&cov[1]));
            if lines.is_empty() {
                return format!(
                    "    {{\"point\": {}, \"covariance_deg2\": {cov}}}",
                    numbers(point)
                );
            }
            let lines: Vec<String> = lines
                .iter()
                .map(|l| format!("       {}", numbers(l)))
                .collect();
            format!(
                "    {{\"point\": {}, \"covariance_deg2\": {cov},\n     \"lines\": [\n{}\n     ]}}",
                numbers(point),
                lines.join(",\n")
            )
        })
        .collect();
    let pp_sd = principal_point
        .1
        .map(|sd| format!("\n  \"principal_point_sd_px\": {},", number(sd)))
        .unwrap_or_default();
    let focal_sd = focal_px
        .1
        .map(|sd| format!("\n  \"focal_sd_px\": {},", number(sd)))
        .unwrap_or_default();
    let lens = lens
        .map(|(k, sd)| {
            let sd = if sd > 0.0 {
                format!(", \"k_sd\": {}", number(sd))
            } else {
                String::new()
            };
            format!("\n  \"lens_distortion\": {{\"k\": {}{sd}}},", number(k))
        })
        .unwrap_or_default();
    format!(
        "{{\n  \"version\": 1,\n  \"image\": {{\"width\": {}, \"height\": {}}},\n  \"perspective\": \"{}\",\n  \"vanishing_points\": [\n{}\n  ],\n  \"principal_point\": {},{pp_sd}\n  \"focal_px\": {},{focal_sd}{lens}\n  \"objects\": [],\n  \"floor\": []\n}}\n",
        image_size_px[0],
        image_size_px[1],
        perspective.name(),
        vps.join(",\n"),
        numbers(&principal_point.0),
        number(focal_px.0)
    )
}

/// The scene for `det` (see the module documentation).
///
/// # Errors
/// When the detection does not hold two horizontal and one vertical vanishing point, its
/// directions are degenerate, or the written scene does not calibrate.
pub fn detected_scene(det: &Detection) -> Result<DetectedScene, SceneError> {
    let roles = roles(det)?;
    let f = det.intrinsics.focal_px;
    let c = det.intrinsics.principal_point_px;
    if !(f.is_finite() && f > 0.0 && c[0].is_finite() && c[1].is_finite()) {
        return fail(format!(
            "the detector returned an unusable camera: focal {f} px, principal point ({}, {})",
            c[0], c[1]
        ));
    }
    let mut detected = [Vec3::zeros(); 3];
    for (k, &i) in roles.iter().enumerate() {
        let Some(vp) = det.vanishing_points.get(i) else {
            return fail(format!("vanishing point {i} is missing"));
        };
        detected[k] = Vector3::from(vp.direction_camera);
    }
    let mut frame = manhattan_frame(detected[0], detected[1], detected[2])?;
    keep_points_in_reach(&mut frame, f);
    let vertical_in_reach = pixel_of_direction(frame[2], f, c)
        .is_some_and(|p| (p[0] - c[0]).hypot(p[1] - c[1]) <= MAX_VANISHING_POINT_OFFSET_PX);
    let perspective = if det.perspective == Perspective::ThreePoint && vertical_in_reach {
        Perspective::ThreePoint
    } else {
        Perspective::TwoPoint
    };
    let adjusted_deg = (0..3)
        .map(|i| line_angle_deg(detected[i], frame[i]))
        .fold(0.0, f64::max);
    let count = if perspective == Perspective::TwoPoint {
        2
    } else {
        3
    };
    // The principal point as written: a prior at the image centre, or the given one as known.
    let [w, h] = det.image_size_px;
    let written_pp = if det.principal_point_given {
        ([round_to(c[0], 3), round_to(c[1], 3)], None)
    } else {
        let diagonal = f64::from(w).hypot(f64::from(h));
        let sd = if det.principal_point_off_centre {
            CROPPED_PRINCIPAL_POINT_SD_DIAGONALS
        } else {
            PRINCIPAL_POINT_PRIOR_SD
        };
        (
            [0.5 * f64::from(w), 0.5 * f64::from(h)],
            Some(round_to(sd * diagonal, 3)),
        )
    };
    // The focal length: given (a calibration, held), or from EXIF (an independent prior the
    // fit weighs), else the detector's estimate as a starting value only.
    let written_focal = match det.focal_prior {
        _ if !det.focal_estimated => (round_to(f, 3), Some(round_to(GIVEN_FOCAL_SD * f, 6))),
        Some((prior, sd)) => (round_to(prior, 3), Some(round_to(sd * prior, 3))),
        None => (round_to(f, 3), None),
    };
    let chart = VpChart {
        focal_px: written_focal.0,
        centre_px: Vector2::new(written_pp.0[0], written_pp.0[1]),
    };
    let pinhole_segments = det.pinhole_segments();
    let mut points_px = [None; 3];
    let mut lines_written = [0; 3];
    let mut covariances = [None; 3];
    let mut specs = Vec::with_capacity(3);
    for k in 0..count {
        let p = written_point(frame[k], f, c);
        let p = [round_to(p[0], 6), round_to(p[1], 6)];
        points_px[k] = Some(p);
        let support: Vec<&Segment> = det
            .vanishing_points
            .get(roles[k])
            .map(|v| {
                v.segments
                    .iter()
                    .filter_map(|&i| pinhole_segments.get(i))
                    .collect()
            })
            .unwrap_or_default();
        let cov = vp_covariance(&chart, Vector3::new(p[0], p[1], 1.0), &support);
        let written_cov = cov.covariance_deg2.map(|row| row.map(|v| round_sig(v, 6)));
        covariances[k] = Some(cov);
        let lines = evidence(det, roles[k]);
        lines_written[k] = lines.len();
        specs.push((p, written_cov, lines));
    }
    let json = scene_json(
        det.image_size_px,
        perspective,
        &specs,
        written_pp,
        written_focal,
        det.lens.map(|l| (round_to(l.k(), 6), round_sig(l.k_sd, 4))),
    );
    let scene = Scene::from_json_str(&json)
        .map_err(|e| SceneError(format!("the detected scene is not valid: {e}")))?;
    let calibration = calibrate(&scene)
        .map_err(|e| SceneError(format!("the detected vanishing points give no camera: {e}")))?;
    Ok(DetectedScene {
        json,
        perspective,
        calibration,
        roles,
        directions: frame.map(Into::into),
        points_px,
        lines_written,
        covariances,
        principal_point_px: written_pp,
        chart,
        adjusted_deg,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::detection::{Intrinsics, Segment, VanishingPoint};

    fn detection(frame: [Vec3; 3], perspective: Perspective) -> Detection {
        let (f, c) = (800.0, [320.0, 240.0]);
        Detection {
            image_size_px: [640, 480],
            segments: vec![Segment {
                start_px: [10.0, 10.0],
                end_px: [100.0, 20.0],
                strength: 1.0,
            }],
            vanishing_points: (0..3)
                .map(|i| VanishingPoint {
                    point_px: pixel_of_direction(frame[i], f, c),
                    direction_camera: frame[i].into(),
                    segments: if i == 0 { vec![0] } else { vec![] },
                    vertical: i == 2,
                    own_point: None,
                })
                .collect(),
            intrinsics: Intrinsics {
                focal_px: f,
                principal_point_px: c,
            },
            focal_estimated: true,
            principal_point_estimated: true,
            principal_point_off_centre: false,
            principal_point_given: false,
            focal_prior: None,
            perspective,
            vertical_tilt_deg: 0.0,
            lens: None,
        }
    }

    /// The room's axes seen by a camera turned by `yaw` and pitched down by `pitch`.
    fn world_axes(yaw: f64, pitch: f64) -> [Vec3; 3] {
        let x_axis = Vector3::new(1.0, 0.0, 0.0);
        let x = rotate(Vector3::new(yaw.cos(), 0.0, yaw.sin()), x_axis, pitch);
        let z = rotate(Vector3::new(-yaw.sin(), 0.0, yaw.cos()), x_axis, pitch);
        let v = rotate(Vector3::new(0.0, 1.0, 0.0), x_axis, pitch);
        [x, z, v]
    }

    #[test]
    fn three_point_scene_calibrates_to_the_detected_camera() {
        let det = detection(world_axes(0.5, 0.3), Perspective::ThreePoint);
        let s = detected_scene(&det).unwrap_or_else(|e| panic!("{e}"));
        assert!((s.calibration.focal_px - 800.0).abs() < 1e-3);
        assert!((s.calibration.pitch_rad - 0.3).abs() < 1e-5);
        assert!(
            s.calibration.warnings.is_empty(),
            "{:?}",
            s.calibration.warnings
        );
        assert!(s.adjusted_deg < 1e-6);
        assert!(s.json.contains("\"perspective\": \"3pp\""), "{}", s.json);
        assert!(s.json.contains("[10.0, 10.0, 100.0, 20.0]"), "{}", s.json);
    }

    /// Where `line` (homogeneous, pixels) crosses `x`, pixels.
    fn y_at(line: Vec3, x: f64) -> f64 {
        -(line.x * x + line.z) / line.y
    }

    /// The line through the scene's two horizontal vanishing points.
    fn written_horizon(s: &DetectedScene) -> Vec3 {
        let [Some(a), Some(b), _] = s.points_px else {
            panic!("no horizontal points: {:?}", s.points_px);
        };
        Vector3::new(a[0], a[1], 1.0).cross(&Vector3::new(b[0], b[1], 1.0))
    }

    #[test]
    fn a_principal_point_off_the_centre_is_written_with_a_widened_prior_and_said() {
        // The detector's principal point 60 px left of the centre: with the flag the prior
        // about the centre is widened to 0.2 of the 800 px diagonal, with a warning naming
        // where the edges put it; without it, 1.5 % and no warning.
        let mut det = detection(world_axes(0.5, 0.3), Perspective::ThreePoint);
        det.intrinsics.principal_point_px = [260.0, 240.0];
        for (flag, sd) in [(false, 12.0), (true, 160.0)] {
            det.principal_point_off_centre = flag;
            let s = detected_scene(&det).unwrap_or_else(|e| panic!("{e}"));
            assert_eq!(s.principal_point_px, ([320.0, 240.0], Some(sd)));
            let scene = Scene::from_json_str(&s.json).unwrap_or_else(|e| panic!("{e}"));
            assert_eq!(scene.principal_point_sd_px, Some(sd));
            let warning = s.off_centre_warning(&det);
            assert_eq!(warning.is_some(), flag, "{warning:?}");
            if let Some(w) = warning {
                assert!(w.contains("(260.0, 240.0), 60 px"), "{w}");
                assert!(w.contains("+- 160.0 px"), "{w}");
            }
        }
    }

    #[test]
    fn nearly_level_camera_keeps_its_measured_tilt() {
        // Looking down 1.5 degrees, the second horizontal 0.4 degrees off orthogonal. The old
        // writer levelled this camera (turning every direction by 1.5 degrees); now the
        // vertical is written and the scene calibrates to the measured pitch.
        let mut frame = world_axes(-0.7, 1.5f64.to_radians());
        frame[1] = rotate(frame[1], frame[2], 0.4f64.to_radians());
        let det = detection(frame, Perspective::ThreePoint);
        let s = detected_scene(&det).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(s.perspective, Perspective::ThreePoint);
        assert!(s.json.contains("\"perspective\": \"3pp\""), "{}", s.json);
        let vertical = s.points_px[2].unwrap_or_else(|| panic!("{}", s.json));
        // Straight below the principal point, f / tan(1.5 deg) = 30547.6 px down.
        assert!((vertical[0] - 320.0).abs() < 1e-6, "{vertical:?}");
        assert!(
            (vertical[1] - (240.0 + 800.0 / 1.5f64.to_radians().tan())).abs() < 1e-3,
            "{vertical:?}"
        );
        assert!(
            s.calibration.warnings.is_empty(),
            "{:?}",
            s.calibration.warnings
        );
        assert!((s.calibration.pitch_rad - 1.5f64.to_radians()).abs() < 1e-7);
        assert!((s.calibration.focal_px - 800.0).abs() < 1e-3);
        // Only the horizontals were turned, by half the 0.4 degrees each.
        assert!((s.adjusted_deg - 0.2).abs() < 1e-6, "{}", s.adjusted_deg);
        // The horizon is 800 tan(1.5 deg) = 20.95 px above the principal point, level.
        let h = written_horizon(&s);
        for x in [0.0, 640.0] {
            let y = y_at(h, x);
            assert!(
                (y - (240.0 - 800.0 * 1.5f64.to_radians().tan())).abs() < 1e-6,
                "{y}"
            );
        }
    }

    #[test]
    fn two_point_detection_keeps_the_measured_horizon() {
        // The same camera judged two-point (a 3-degree tolerance): the vertical point is left
        // out, but the horizon written is still the measured one, not moved to the principal
        // point, and the directions are only made orthogonal.
        let mut frame = world_axes(-0.7, 1.5f64.to_radians());
        frame[1] = rotate(frame[1], frame[2], 0.4f64.to_radians());
        let det = detection(frame, Perspective::TwoPoint);
        let s = detected_scene(&det).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(s.perspective, Perspective::TwoPoint);
        assert!(s.points_px[2].is_none());
        assert!(s.json.contains("\"perspective\": \"2pp\""), "{}", s.json);
        assert!(s.adjusted_deg < 0.21, "{}", s.adjusted_deg);
        let h = written_horizon(&s);
        let y = y_at(h, 320.0);
        assert!(
            (y - (240.0 - 800.0 * 1.5f64.to_radians().tan())).abs() < 1e-6,
            "{y}"
        );
        // The scene format's two-point calibration moves the principal point onto it, and
        // says so.
        assert!(
            (s.calibration.principal_point_px().y - y).abs() < 1e-6,
            "{:?}",
            s.calibration.principal_point_px()
        );
        assert_eq!(
            s.calibration.warnings.len(),
            1,
            "{:?}",
            s.calibration.warnings
        );
    }

    #[test]
    fn a_vertical_in_the_image_plane_makes_a_two_point_scene() {
        // Exactly level: the vertical point is at infinity, so it cannot be written.
        let det = detection(world_axes(0.5, 0.0), Perspective::ThreePoint);
        let s = detected_scene(&det).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(s.perspective, Perspective::TwoPoint);
        assert!(s.points_px[2].is_none());
        assert!(
            s.calibration.warnings.is_empty(),
            "{:?}",
            s.calibration.warnings
        );
        assert!((s.calibration.focal_px - 800.0).abs() < 1e-3);
        // Looking down so little that the vertical point lies beyond reach: two-point too.
        let tiny = (800.0 / (2.0 * MAX_VANISHING_POINT_OFFSET_PX)).atan();
        let det = detection(world_axes(0.5, tiny), Perspective::ThreePoint);
        let s = detected_scene(&det).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(s.perspective, Perspective::TwoPoint);
        // Just within reach: three-point, with the right pitch.
        let small = (800.0 / (0.5 * MAX_VANISHING_POINT_OFFSET_PX)).atan();
        let det = detection(world_axes(0.5, small), Perspective::ThreePoint);
        let s = detected_scene(&det).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(s.perspective, Perspective::ThreePoint);
        assert!(
            (s.calibration.pitch_rad / small - 1.0).abs() < 1e-3,
            "{} vs {small}",
            s.calibration.pitch_rad
        );
        assert!((s.calibration.focal_px - 800.0).abs() < 1e-2);
    }

    #[test]
    fn two_verticals_are_refused() {
        let mut det = detection(world_axes(0.5, 0.3), Perspective::ThreePoint);
        det.vanishing_points[0].vertical = true;
        assert!(detected_scene(&det).is_err());
    }
}

//! From a [`Detection`] to a scene file (`docs/scene-format.md`).
//!
//! The scene holds the two horizontal vanishing points and, in three-point perspective only,
//! the vertical one, each as `point` with its supporting segments as `lines` (the evidence a
//! person checks and edits), plus `principal_point`, `focal_px`, a `perspective` note that
//! `vpmap build` knows, and empty `objects` and `floor` for the user to fill in.
//!
//! The points written are made exactly consistent with the camera, so that `vpmap build`
//! recovers the detected focal length and principal point without warnings:
//! * the two horizontal directions are made orthogonal to the vertical one and to each other
//!   (each turned by the same amount, about the vertical);
//! * in two-point perspective the scene format takes the camera as level (pitch 0), so the
//!   frame is turned by the smallest rotation that puts the vertical direction in the image
//!   plane (by less than `--two-point-tolerance`); the horizon then passes through the
//!   principal point;
//! * a horizontal direction (nearly) parallel to the image plane, whose point is at (or near)
//!   infinity, is turned about the vertical, with the other one, until its point lies within
//!   [`MAX_VANISHING_POINT_OFFSET_PX`] of the principal point (the scene format needs finite
//!   points).
//!
//! How far the directions moved is reported (`adjusted_deg`).

use std::f64::consts::FRAC_1_SQRT_2;

use anyhow::{Context, Result, anyhow, bail};
use vpmap_metrology::calibration::{Calibration, Perspective};
use vpmap_metrology::map::calibrate;
use vpmap_metrology::scene::Scene;
use vpmap_vision::Detection;

use super::geom::{
    Vec3, add, cross, dot, line_angle_deg, normalize, pixel_of_direction, rotate, rotate_like,
    scale, sub,
};

/// Farthest a written vanishing point may lie from the principal point, pixels. The scene
/// format accepts up to 1e12, but the other horizontal point then sits within `f^2 / 1e12` px
/// of the principal point, too close to write exactly. Keeping a point within 1e7 px turns
/// the directions by at most `2 f / 1e7` radians (0.01 degree for `f` = 900 px).
pub const MAX_VANISHING_POINT_OFFSET_PX: f64 = 1e7;

/// Most supporting segments written per vanishing point (the longest ones).
pub const MAX_LINES_PER_VANISHING_POINT: usize = 40;

/// Shortest segment written as evidence, pixels.
const MIN_LINE_LENGTH_PX: f64 = 2.0;

/// Which of the detection's vanishing points play which part.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Roles {
    /// Indices into `Detection::vanishing_points`: first horizontal, second horizontal,
    /// vertical.
    pub order: [usize; 3],
}

impl Roles {
    /// The vertical vanishing point is the one flagged `vertical`; the other two, in the
    /// detection's order, are the horizontal ones.
    pub fn of(det: &Detection) -> Result<Self> {
        let n = det.vanishing_points.len();
        let verticals: Vec<usize> = (0..n)
            .filter(|&i| det.vanishing_points[i].vertical)
            .collect();
        let horizontals: Vec<usize> = (0..n)
            .filter(|&i| !det.vanishing_points[i].vertical)
            .collect();
        match (verticals.as_slice(), horizontals.as_slice()) {
            ([v], [a, b]) => Ok(Self {
                order: [*a, *b, *v],
            }),
            _ => bail!(
                "the detector returned {n} vanishing points ({} vertical); expected two horizontal and one vertical",
                verticals.len()
            ),
        }
    }
}

/// The scene written for a detection, and what it took.
pub struct DetectedScene {
    /// Its JSON text, as written.
    pub json: String,
    /// 2PP or 3PP.
    pub perspective: Perspective,
    /// The camera as `vpmap build` will recover it from the scene.
    pub calibration: Calibration,
    /// The roles of the detection's vanishing points.
    pub roles: Roles,
    /// The directions written, in role order (horizontal, horizontal, vertical), camera frame.
    pub directions: [Vec3; 3],
    /// The points written, in role order (the vertical one `None` in 2PP).
    pub points_px: [Option<[f64; 2]>; 3],
    /// Segments written as `lines`, per role (0 for the vertical in 2PP).
    pub lines_written: [usize; 3],
    /// The largest angle any vanishing direction was turned by, degrees.
    pub adjusted_deg: f64,
}

fn round_to(v: f64, decimals: i32) -> f64 {
    let s = 10f64.powi(decimals);
    (v * s).round() / s + 0.0
}

/// The orthogonal frame nearest the detected directions: horizontals orthogonal to the
/// vertical and to each other, turned by equal angles; levelled in 2PP.
fn manhattan_frame(h1: Vec3, h2: Vec3, v: Vec3, level: bool) -> Result<[Vec3; 3]> {
    let v = normalize(v).context("the vertical vanishing direction is degenerate")?;
    let a = normalize(sub(h1, scale(v, dot(h1, v))))
        .context("the first horizontal vanishing direction is parallel to the vertical one")?;
    let b = normalize(sub(h2, scale(v, dot(h2, v))))
        .context("the second horizontal vanishing direction is parallel to the vertical one")?;
    // a and b are unit vectors in the horizontal plane; their bisectors u, w are orthonormal,
    // and the orthogonal pair symmetric about them is the nearest one.
    let (Some(u), Some(w)) = (normalize(add(a, b)), normalize(sub(a, b))) else {
        bail!("the two horizontal vanishing points coincide");
    };
    let mut frame = [
        scale(add(u, w), FRAC_1_SQRT_2),
        scale(sub(u, w), FRAC_1_SQRT_2),
        v,
    ];
    if level {
        let level_v = normalize([v[0], v[1], 0.0])
            .context("the vertical direction points along the optical axis")?;
        for d in &mut frame {
            *d = rotate_like(*d, v, level_v);
        }
        frame[2] = level_v;
    }
    Ok(frame)
}

/// Turn the horizontal pair about the vertical until neither point lies farther than
/// [`MAX_VANISHING_POINT_OFFSET_PX`] from the principal point (by `2 f / MAX` radians at most,
/// unless the vertical runs along the optical axis, when no such turn helps and the point is
/// clamped instead).
fn keep_points_in_reach(frame: &mut [Vec3; 3], focal_px: f64) {
    let min_z = (focal_px / MAX_VANISHING_POINT_OFFSET_PX).min(0.5);
    for i in 0..2 {
        let d = frame[i];
        if d[2].abs() >= min_z {
            continue;
        }
        let g = cross(frame[2], d)[2];
        if g.abs() < min_z {
            // The vertical runs along the optical axis: no turn about it helps.
            continue;
        }
        let sign = if d[2] == 0.0 {
            g.signum()
        } else {
            (d[2] * g).signum()
        };
        let angle = sign * (2.0 * min_z / g.abs()).min(0.1);
        frame[0] = rotate(frame[0], frame[2], angle);
        frame[1] = rotate(frame[1], frame[2], angle);
    }
}

/// The image point of `d`, clamped to [`MAX_VANISHING_POINT_OFFSET_PX`] from `c`.
fn written_point(d: Vec3, f: f64, c: [f64; 2]) -> [f64; 2] {
    let along = |len: f64| {
        let n = d[0].hypot(d[1]).max(f64::MIN_POSITIVE);
        [c[0] + d[0] / n * len, c[1] + d[1] / n * len]
    };
    match pixel_of_direction(d, f, c) {
        Some(p) if (p[0] - c[0]).hypot(p[1] - c[1]) <= MAX_VANISHING_POINT_OFFSET_PX => p,
        _ => along(MAX_VANISHING_POINT_OFFSET_PX),
    }
}

/// The longest supporting segments of one vanishing point, as `[x1, y1, x2, y2]`.
fn evidence(det: &Detection, vp: usize) -> Vec<[f64; 4]> {
    let mut lines: Vec<(f64, [f64; 4])> = det.vanishing_points[vp]
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

/// A number as JSON (shortest round-trip form).
fn number(v: f64) -> String {
    serde_json::to_string(&v).unwrap_or_else(|_| "null".to_owned())
}

fn numbers(values: &[f64]) -> String {
    let parts: Vec<String> = values.iter().map(|&v| number(v)).collect();
    format!("[{}]", parts.join(", "))
}

/// The scene file's text, laid out like the examples of `docs/scene-format.md` (one point or
/// segment per line, fields in reading order; `serde_json`'s pretty printer would put every
/// number on its own line, and its maps sort the keys). `perspective` is not part of
/// [`Scene`] (the number of vanishing points decides) but `vpmap build` accepts it silently.
fn scene_json(
    image_size_px: [u32; 2],
    perspective: Perspective,
    vanishing_points: &[([f64; 2], Vec<[f64; 4]>)],
    principal_point: [f64; 2],
    focal_px: f64,
) -> String {
    let vps: Vec<String> = vanishing_points
        .iter()
        .map(|(point, lines)| {
            if lines.is_empty() {
                return format!("    {{\"point\": {}}}", numbers(point));
            }
            let lines: Vec<String> = lines
                .iter()
                .map(|l| format!("       {}", numbers(l)))
                .collect();
            format!(
                "    {{\"point\": {},\n     \"lines\": [\n{}\n     ]}}",
                numbers(point),
                lines.join(",\n")
            )
        })
        .collect();
    format!(
        "{{\n  \"version\": 1,\n  \"image\": {{\"width\": {}, \"height\": {}}},\n  \"perspective\": \"{}\",\n  \"vanishing_points\": [\n{}\n  ],\n  \"principal_point\": {},\n  \"focal_px\": {},\n  \"objects\": [],\n  \"floor\": []\n}}\n",
        image_size_px[0],
        image_size_px[1],
        match perspective {
            Perspective::TwoPoint => "2pp",
            Perspective::ThreePoint => "3pp",
        },
        vps.join(",\n"),
        numbers(&principal_point),
        number(focal_px)
    )
}

/// The scene for `det`: see the module documentation.
///
/// # Errors
/// When the detection does not hold two horizontal and one vertical vanishing point, its
/// directions are degenerate, or the written scene does not calibrate (which would be a bug).
pub fn detected_scene(det: &Detection) -> Result<DetectedScene> {
    let roles = Roles::of(det)?;
    let f = det.intrinsics.focal_px;
    let c = det.intrinsics.principal_point_px;
    if !(f.is_finite() && f > 0.0 && c[0].is_finite() && c[1].is_finite()) {
        bail!(
            "the detector returned an unusable camera: focal {f} px, principal point ({}, {})",
            c[0],
            c[1]
        );
    }
    let perspective = match det.perspective {
        vpmap_vision::Perspective::TwoPoint => Perspective::TwoPoint,
        vpmap_vision::Perspective::ThreePoint => Perspective::ThreePoint,
    };
    let detected: [Vec3; 3] = roles
        .order
        .map(|i| det.vanishing_points[i].direction_camera);
    let mut frame = manhattan_frame(
        detected[0],
        detected[1],
        detected[2],
        perspective == Perspective::TwoPoint,
    )?;
    keep_points_in_reach(&mut frame, f);
    let adjusted_deg = (0..3)
        .map(|i| line_angle_deg(detected[i], frame[i]))
        .fold(0.0, f64::max);

    let mut points_px = [None; 3];
    let mut specs: Vec<([f64; 2], Vec<[f64; 4]>)> = Vec::with_capacity(3);
    let mut lines_written = [0; 3];
    let count = if perspective == Perspective::TwoPoint {
        2
    } else {
        3
    };
    for k in 0..count {
        let p = written_point(frame[k], f, c);
        points_px[k] = Some(p);
        let lines = evidence(det, roles.order[k]);
        lines_written[k] = lines.len();
        specs.push(([round_to(p[0], 6), round_to(p[1], 6)], lines));
    }
    let json = scene_json(
        det.image_size_px,
        perspective,
        &specs,
        [round_to(c[0], 3), round_to(c[1], 3)],
        round_to(f, 3),
    );
    let scene =
        Scene::from_json_str(&json).map_err(|e| anyhow!("the detected scene is not valid: {e}"))?;
    let calibration = calibrate(&scene)
        .map_err(|e| anyhow!("the detected vanishing points give no camera: {e}"))?;
    Ok(DetectedScene {
        json,
        perspective,
        calibration,
        roles,
        directions: frame,
        points_px,
        lines_written,
        adjusted_deg,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use vpmap_vision::{Intrinsics, Segment, VanishingPoint};

    fn detection(frame: [Vec3; 3], perspective: vpmap_vision::Perspective) -> Detection {
        let (f, c) = (800.0, [320.0, 240.0]);
        let segments = vec![
            Segment {
                start_px: [10.0, 10.0],
                end_px: [100.0, 20.0],
                strength: 1.0,
            },
            Segment {
                start_px: [10.0, 50.0],
                end_px: [120.0, 55.0],
                strength: 1.0,
            },
        ];
        Detection {
            image_size_px: [640, 480],
            segments,
            vanishing_points: (0..3)
                .map(|i| VanishingPoint {
                    point_px: pixel_of_direction(frame[i], f, c),
                    direction_camera: frame[i],
                    segments: if i == 0 { vec![0, 1] } else { vec![] },
                    vertical: i == 2,
                })
                .collect(),
            intrinsics: Intrinsics {
                focal_px: f,
                principal_point_px: c,
            },
            focal_estimated: true,
            principal_point_estimated: true,
            perspective,
            vertical_tilt_deg: 0.0,
        }
    }

    fn vanishing_point_count(s: &DetectedScene) -> usize {
        Scene::from_json_str(&s.json).map_or(0, |scene| scene.vanishing_points.len())
    }

    /// A camera frame's world axes for yaw `yaw` and pitch `pitch` (looking down), radians.
    fn world_axes(yaw: f64, pitch: f64) -> [Vec3; 3] {
        let down = [0.0, 1.0, 0.0];
        let x = rotate([yaw.cos(), 0.0, yaw.sin()], [1.0, 0.0, 0.0], pitch);
        let z = rotate([-yaw.sin(), 0.0, yaw.cos()], [1.0, 0.0, 0.0], pitch);
        let v = rotate(down, [1.0, 0.0, 0.0], pitch);
        [x, z, v]
    }

    #[test]
    fn three_point_scene_calibrates_to_the_detected_camera() {
        let frame = world_axes(0.5, 0.3);
        let det = detection(frame, vpmap_vision::Perspective::ThreePoint);
        let s = detected_scene(&det).unwrap_or_else(|e| panic!("{e:#}"));
        assert_eq!(vanishing_point_count(&s), 3);
        assert!((s.calibration.focal_px - 800.0).abs() < 1e-3);
        assert!((s.calibration.pitch_rad.to_degrees() - 0.3f64.to_degrees()).abs() < 1e-3);
        assert!(
            s.calibration.warnings.is_empty(),
            "{:?}",
            s.calibration.warnings
        );
        assert!(s.adjusted_deg < 1e-6, "{}", s.adjusted_deg);
        assert_eq!(s.lines_written, [2, 0, 0]);
        assert!(s.json.contains("\"perspective\": \"3pp\""), "{}", s.json);
    }

    #[test]
    fn nearly_level_camera_is_levelled_for_two_point_perspective() {
        // 1.5 degrees of pitch and horizontals 0.4 degrees from orthogonal.
        let mut frame = world_axes(-0.7, 1.5f64.to_radians());
        frame[1] = rotate(frame[1], frame[2], 0.4f64.to_radians());
        let det = detection(frame, vpmap_vision::Perspective::TwoPoint);
        let s = detected_scene(&det).unwrap_or_else(|e| panic!("{e:#}"));
        assert_eq!(vanishing_point_count(&s), 2);
        assert!(
            s.calibration.warnings.is_empty(),
            "{:?}",
            s.calibration.warnings
        );
        assert!((s.calibration.focal_px - 800.0).abs() < 1e-3);
        assert!(
            s.adjusted_deg > 1.4 && s.adjusted_deg < 2.0,
            "{}",
            s.adjusted_deg
        );
        assert!(s.points_px[2].is_none());
    }

    #[test]
    fn wall_seen_square_on_keeps_its_far_vanishing_point_finite() {
        let frame = world_axes(0.0, 0.0);
        let det = detection(frame, vpmap_vision::Perspective::TwoPoint);
        let s = detected_scene(&det).unwrap_or_else(|e| panic!("{e:#}"));
        let p = s.points_px[0].unwrap_or_default();
        assert!(p[0].abs() <= 1.1 * MAX_VANISHING_POINT_OFFSET_PX, "{p:?}");
        assert!((s.calibration.focal_px - 800.0).abs() < 1e-2 * 800.0);
        assert!(
            s.calibration.warnings.is_empty(),
            "{:?}",
            s.calibration.warnings
        );
    }
}

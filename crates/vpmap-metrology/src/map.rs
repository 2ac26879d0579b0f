//! The floor map: the result of `vpmap build`, as written to `map.json`.
//!
//! Frame: origin at the station point, `+x` right, `+y` forward along the camera's horizontal
//! viewing direction, `+z` up. Units: metres when the scene gives a scale, else camera heights.
//! The format is documented for users in `docs/map-format.md`.

use geo::{
    Area, BooleanOps, Centroid, ConvexHull, Coord, LineString, MultiPoint, MultiPolygon, Point,
    Polygon,
};
use nalgebra::Vector2;
use serde::{Deserialize, Serialize};

use crate::calibration::{Calibration, Perspective};
pub use crate::camera::{MapPoint, calibrate, room_yaw_rad, rotation_map_from_camera};
use crate::error::{MetrologyError, Result};
use crate::fit::{FitOptions, Fitted, fit_scene};
use crate::projective::Projective;
use crate::reconstruct::{FloorProjection, Method, ObjectKind, Reconstruction, reconstruct};
use crate::scene::{Dimension, ImageSize, Scale, Scene};
use crate::sideview::SideView;
pub use crate::uncertainty::{CameraUncertainty, Ellipse, ObjectUncertainty};

/// Length unit of a map.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Units {
    /// Metres (the scene gave a scale).
    #[serde(rename = "m")]
    Meters,
    /// Camera heights (no scale given; the camera height is 1).
    #[serde(rename = "camera_heights")]
    CameraHeights,
}

/// The camera as reported in a map.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CameraReport {
    /// "2pp" or "3pp".
    pub perspective: Perspective,
    /// Focal length, pixels.
    pub focal_px: f64,
    /// Principal point used, pixels.
    pub principal_point: [f64; 2],
    /// Pitch, degrees, positive when the camera looks down.
    pub pitch_deg: f64,
    /// Roll, degrees: the horizon's angle in the image, positive when it falls to the right.
    pub roll_deg: f64,
    /// The room's yaw: the direction on the floor of the first horizontal vanishing point's
    /// edges, degrees counter-clockwise from `+x` (the second runs 90 degrees from it).
    #[serde(default)]
    pub room_yaw_deg: f64,
    /// Camera height above the floor, in the map's units.
    pub height: f64,
    /// The intrinsic matrix `K = [[f, 0, cx], [0, f, cy], [0, 0, 1]]` (pixels; square pixels,
    /// no skew), row by row.
    #[serde(default)]
    pub k_matrix: [[f64; 3]; 3],
    /// Rotation from the camera frame (x right, y down, z along the optical axis, as in
    /// OpenCV) to the map frame, row by row: a ray `K^-1 (u, v, 1)` in camera coordinates
    /// points along `R` times it in the map frame.
    #[serde(default)]
    pub rotation_map_from_camera: [[f64; 3]; 3],
    /// Position of the camera `[x, y, z]` in the map frame (always `[0, 0, height]`).
    pub position: [f64; 3],
    /// The photo's size.
    pub image: ImageSize,
    /// Vanishing points used, pixels.
    pub vanishing_points: Vec<[f64; 2]>,
    /// The fit's error bars (method `fit` only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub uncertainty: Option<CameraUncertainty>,
    /// Horizontal field of view: angles of the image's left and right extent, degrees from
    /// `+y`, negative to the left.
    pub horizontal_fov_deg: [f64; 2],
    /// The floor the photo shows: the image rectangle projected onto the floor, cut where it
    /// reaches 1.5 times the farthest mapped point (the part near the horizon runs to
    /// infinity). A convex polygon, counter-clockwise.
    #[serde(default)]
    pub view_on_floor: Vec<MapPoint>,
}

/// Footprint side lengths of a box.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BoxSize {
    /// Longer side.
    pub length: f64,
    /// Shorter side.
    pub breadth: f64,
}

/// One object of the map.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MapObject {
    /// Name from the scene.
    pub name: String,
    /// "box" or "footprint".
    pub kind: ObjectKind,
    /// Floor corners: a box's near, right, far, left; a footprint's vertices in scene order.
    pub footprint: Vec<MapPoint>,
    /// Height above the floor (`null` when the scene gives no top point).
    pub height: Option<f64>,
    /// A box's side lengths.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub size: Option<BoxSize>,
    /// Footprint centroid.
    pub centroid: MapPoint,
    /// Footprint area.
    pub area: f64,
    /// The fit's error bars for this object (method `fit` only; absent otherwise).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub uncertainty: Option<ObjectUncertainty>,
}

/// How the joint fit went (method `fit` only).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FitReport {
    /// The click noise the error bars are computed for, pixels (1 sigma per coordinate).
    pub click_sigma_px: f64,
    /// Where it comes from: `"given"` (set by the user), `"residuals"` (estimated from the
    /// fit's residuals, the data over-determining the model) or `"default"` (1 px).
    pub click_sigma_source: String,
    /// Root-mean-square reprojection error of the clicked points, pixels.
    pub rms_residual_px: f64,
    /// Residuals minus parameters.
    pub degrees_of_freedom: usize,
    /// Levenberg-Marquardt iterations.
    pub iterations: usize,
    /// Whether the principal point was fitted (else held at the given or central value).
    pub principal_point_fitted: bool,
}

/// A polygon with holes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PolygonWithHoles {
    /// Outer ring (not repeated at the end).
    pub exterior: Vec<MapPoint>,
    /// Inner rings.
    pub holes: Vec<Vec<MapPoint>>,
}

/// A floor map (`map.json`, version 1).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FloorMap {
    /// Format version: 1.
    pub version: u32,
    /// Length unit of every coordinate and length.
    pub units: Units,
    /// Reconstruction method used.
    pub method: Method,
    /// The camera.
    pub camera: CameraReport,
    /// The objects, in scene order.
    pub objects: Vec<MapObject>,
    /// The floor outline (may be empty).
    pub floor: Vec<MapPoint>,
    /// The floor minus every footprint.
    pub free_space: Vec<PolygonWithHoles>,
    /// The parts of the free space the camera cannot see because objects stand in the way
    /// (each object's occlusion shadow as seen from the camera, clipped to the free space).
    /// The occupancy grid marks them unknown.
    #[serde(default)]
    pub hidden: Vec<PolygonWithHoles>,
    /// Notes for the user.
    pub warnings: Vec<String>,
    /// How the joint fit went (method `fit` only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fit: Option<FitReport>,
}

/// Options of [`build_map`].
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct BuildOptions {
    /// Reconstruction method.
    pub method: Method,
    /// The click noise the fit's error bars are computed for, pixels (1 sigma per
    /// coordinate); `None`: estimated from the residuals when the data over-determine the
    /// model, else 1 px ([`crate::fit::FitOptions`]). Method `fit` only.
    pub click_sigma_px: Option<f64>,
}

/// Relative standard deviation of a size above which the build warns.
pub const WARN_RELATIVE_SD: f64 = 0.2;
/// Misfit of a clicked point, in click sigmas, above which the build warns.
pub const WARN_RESIDUAL_SIGMAS: f64 = 3.0;

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
fn check_plausible(cal: &Calibration, rec: &Reconstruction) -> Result<()> {
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

fn box_size(footprint: &[Vector2<f64>]) -> Option<BoxSize> {
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

fn ring(points: &[Vector2<f64>]) -> LineString<f64> {
    LineString::from(
        points
            .iter()
            .map(|p| Coord { x: p.x, y: p.y })
            .collect::<Vec<_>>(),
    )
}

fn unclosed(ls: &LineString<f64>) -> Vec<MapPoint> {
    let mut pts: Vec<MapPoint> = ls.coords().map(|c| [c.x, c.y]).collect();
    if pts.len() > 1 && pts.first() == pts.last() {
        pts.pop();
    }
    pts
}

/// The floor outline minus the object footprints, as polygons with holes.
#[must_use]
pub fn free_space(floor: &[Vector2<f64>], footprints: &[Vec<Vector2<f64>>]) -> MultiPolygon<f64> {
    if floor.len() < 3 {
        return MultiPolygon::new(Vec::new());
    }
    let floor_poly = MultiPolygon::new(vec![Polygon::new(ring(floor), vec![])]);
    let obstacles: Vec<Polygon<f64>> = footprints
        .iter()
        .filter(|f| f.len() >= 3)
        .map(|f| Polygon::new(ring(f), vec![]))
        .collect();
    if obstacles.is_empty() {
        return floor_poly;
    }
    let union = geo::unary_union(&obstacles);
    floor_poly.difference(&union)
}

/// The floor hidden behind one object, seen from a camera at `camera_height` above the
/// station point (the origin): the convex hull of the footprint and of the top outline
/// projected from the camera onto the floor (`v -> v H / (H - h)`). An object as tall as the
/// camera or taller hides everything behind it; its shadow is cut at `reach` from the station
/// point. Objects without a height hide nothing (their height is unknown).
#[must_use]
pub fn occlusion_shadow(
    footprint: &[Vector2<f64>],
    height: Option<f64>,
    camera_height: f64,
    reach: f64,
) -> Option<Polygon<f64>> {
    let h = height?;
    if footprint.len() < 3 || h <= 0.0 {
        return None;
    }
    let mut points: Vec<Point<f64>> = footprint.iter().map(|p| Point::new(p.x, p.y)).collect();
    for p in footprint {
        let r = p.norm();
        if r == 0.0 {
            continue;
        }
        let stretch = if h < camera_height {
            (camera_height / (camera_height - h)).min(reach / r)
        } else {
            reach / r
        };
        let q = p * stretch.max(1.0);
        points.push(Point::new(q.x, q.y));
    }
    Some(MultiPoint::new(points).convex_hull())
}

/// The image rectangle's floor footprint, cut at forward distance `reach` (in units where the
/// camera height is `camera_height`), by the closed form of the errata: a point at
/// horizon-frame offset `(x, y)` from `O` lies on the floor at
/// `X = H x / (d sin(theta) - y cos(theta))`, `Y = H (d cos(theta) + y sin(theta)) / (d sin(theta) - y cos(theta))`.
fn view_on_floor(
    cal: &Calibration,
    image: ImageSize,
    camera_height: f64,
    reach: f64,
) -> Vec<MapPoint> {
    let (d, th) = (cal.focal_px, cal.pitch_rad);
    let (s, c) = th.sin_cos();
    // The image row (horizon frame) whose floor points lie `reach` ahead on the centre line.
    let y_far = d * (reach * s - camera_height * c) / (reach * c + camera_height * s);
    let (w, h) = (f64::from(image.width), f64::from(image.height));
    let corners = [
        Vector2::new(0.0, 0.0),
        Vector2::new(w, 0.0),
        Vector2::new(w, h),
        Vector2::new(0.0, h),
    ]
    .map(|p| cal.frame.coords(p));
    // Clip the rectangle (horizon frame) to y <= y_far.
    let mut clipped: Vec<Vector2<f64>> = Vec::new();
    for i in 0..4 {
        let (p, q) = (corners[i], corners[(i + 1) % 4]);
        if p.y <= y_far {
            clipped.push(p);
        }
        if (p.y <= y_far) != (q.y <= y_far) {
            clipped.push(p + (q - p) * ((y_far - p.y) / (q.y - p.y)));
        }
    }
    let mut out: Vec<MapPoint> = clipped
        .iter()
        .filter_map(|v| {
            let den = d * s - v.y * c;
            (den > 0.0).then(|| {
                [
                    camera_height * v.x / den,
                    camera_height * (d * c + v.y * s) / den,
                ]
            })
        })
        .collect();
    // Counter-clockwise in the map frame.
    let twice_area: f64 = (0..out.len())
        .map(|i| {
            let (a, b) = (out[i], out[(i + 1) % out.len()]);
            a[0] * b[1] - a[1] * b[0]
        })
        .sum();
    if twice_area < 0.0 {
        out.reverse();
    }
    out
}

/// Polygons with holes as `map.json` writes them (rings not closed).
#[must_use]
pub fn to_polygons(mp: &MultiPolygon<f64>) -> Vec<PolygonWithHoles> {
    mp.0.iter()
        .map(|p| PolygonWithHoles {
            exterior: unclosed(p.exterior()),
            holes: p.interiors().iter().map(unclosed).collect(),
        })
        .collect()
}

/// The first two non-adjacent edges of a closed ring that touch or cross, as edge indices
/// (edge `i` runs from point `i` to point `i + 1`), or `None` for a simple ring.
#[must_use]
pub fn self_crossing(ring: &[Vector2<f64>]) -> Option<(usize, usize)> {
    let n = ring.len();
    if n < 4 {
        return None;
    }
    let orient = |a: Vector2<f64>, b: Vector2<f64>, c: Vector2<f64>| {
        let v = (b - a).perp(&(c - a));
        let scale = (b - a).norm() * (c - a).norm();
        if v.abs() <= 1e-12 * scale {
            0.0
        } else {
            v.signum()
        }
    };
    let on = |a: Vector2<f64>, b: Vector2<f64>, p: Vector2<f64>| {
        p.x >= a.x.min(b.x) && p.x <= a.x.max(b.x) && p.y >= a.y.min(b.y) && p.y <= a.y.max(b.y)
    };
    for i in 0..n {
        let (a, b) = (ring[i], ring[(i + 1) % n]);
        for j in i + 2..n {
            if i == 0 && j == n - 1 {
                continue;
            }
            let (c, d) = (ring[j], ring[(j + 1) % n]);
            let (o1, o2, o3, o4) = (
                orient(a, b, c),
                orient(a, b, d),
                orient(c, d, a),
                orient(c, d, b),
            );
            let crosses = (o1 * o2 < 0.0 && o3 * o4 < 0.0)
                || (o1 == 0.0 && on(a, b, c))
                || (o2 == 0.0 && on(a, b, d))
                || (o3 == 0.0 && on(c, d, a))
                || (o4 == 0.0 && on(c, d, b));
            if crosses {
                return Some((i, j));
            }
        }
    }
    None
}

/// Warnings for a floor outline or a footprint object that crosses itself (clicked out of
/// order): its area, and so the free space, would be wrong.
fn crossing_warnings(scene: &Scene, rec: &Reconstruction) -> Vec<String> {
    let mut out = Vec::new();
    if let Some((i, j)) = self_crossing(&rec.floor) {
        out.push(format!(
            "the floor outline crosses itself (its edges from floor[{i}] and floor[{j}]): click the floor corners in order around the floor; the free space is wrong as it stands"
        ));
    }
    for (k, o) in rec.objects.iter().enumerate() {
        if o.kind == ObjectKind::Footprint
            && let Some((i, j)) = self_crossing(&o.footprint)
        {
            let name = scene
                .objects
                .get(k)
                .map_or(o.name.as_str(), |s| s.name.as_str());
            out.push(format!(
                "the footprint of object {name:?} crosses itself (its edges from footprint[{i}] and footprint[{j}]): click its vertices in order around it"
            ));
        }
    }
    out
}

/// The fit's warnings: sizes uncertain by more than [`WARN_RELATIVE_SD`] (naming the corner
/// that would help) and clicks farther than [`WARN_RESIDUAL_SIGMAS`] click sigmas from the
/// fitted model (a misplaced click).
fn fit_warnings(scene: &Scene, fitted: &Fitted, u: &crate::fit::FitUncertainty) -> Vec<String> {
    let mut out = Vec::new();
    for &(i, what, rel) in &u.relative_size_sd {
        if rel > WARN_RELATIVE_SD
            && let Some(obj) = scene.objects.get(i)
        {
            out.push(format!(
                "object {:?}: its {what} is uncertain by +-{:.0} % (1 sigma, for {:.2} px clicks); {}",
                obj.name,
                100.0 * rel,
                u.click_sigma_px,
                crate::fit::advice_for(scene, i, what)
            ));
        }
    }
    out.extend(camera_warnings(scene, fitted, u));
    if u.click_sigma_px > 0.0 {
        for r in &fitted.point_residuals {
            if r.distance_px > WARN_RESIDUAL_SIGMAS * u.click_sigma_px {
                out.push(format!(
                    "`{}` of object {:?} lies {:.1} px ({:.1} sigma) from the fitted box: a misplaced click?",
                    r.field,
                    r.object,
                    r.distance_px,
                    r.distance_px / u.click_sigma_px
                ));
            }
        }
    }
    out
}

/// Largest standard deviation of a fitted principal point, as a fraction of the image
/// diagonal, before a warning.
pub const WARN_PRINCIPAL_POINT_SD_DIAGONALS: f64 = 0.01;

/// Largest relative standard deviation of the fitted focal length before a warning.
pub const WARN_FOCAL_SD_FRACTION: f64 = 0.05;

/// Warnings for a camera the vanishing points fix poorly: a principal point or focal length
/// with a large error bar, naming the vanishing point farthest from the image (the one whose
/// direction a pixel of noise turns most).
fn camera_warnings(scene: &Scene, fitted: &Fitted, u: &crate::fit::FitUncertainty) -> Vec<String> {
    let mut out = Vec::new();
    let centre = scene.image.centre();
    let far = fitted
        .calibration
        .vanishing_points_px
        .iter()
        .enumerate()
        .map(|(k, v)| (k, (v - centre).norm()))
        .max_by(|a, b| a.1.total_cmp(&b.1));
    let far_text = far.map_or_else(String::new, |(k, d)| {
        format!(
            ": the {} vanishing point lies {d:.0} px ({:.0} image diagonals) from the image centre",
            if k == 2 { "vertical" } else { "horizontal" },
            d / scene.image.diagonal()
        )
    });
    let cam = &u.camera;
    if let Some([sx, sy]) = cam.principal_point_px_sd
        && sx.hypot(sy) > WARN_PRINCIPAL_POINT_SD_DIAGONALS * scene.image.diagonal()
    {
        let pp = fitted.calibration.principal_point_px();
        out.push(format!(
            "the principal point ({:.1}, {:.1}) is poorly fixed, +-({sx:.1}, {sy:.1}) px (1 sigma, for {:.2} px clicks){far_text}; give longer edges towards it, or the principal point if it is known",
            pp.x, pp.y, u.click_sigma_px
        ));
    }
    let f = fitted.calibration.focal_px;
    if cam.focal_px_sd > WARN_FOCAL_SD_FRACTION * f {
        out.push(format!(
            "the focal length {f:.1} px is poorly fixed, +-{:.1} px ({:.0} %, 1 sigma, for {:.2} px clicks){far_text}; give longer edges towards it, or `focal_px` if it is known",
            cam.focal_px_sd,
            100.0 * cam.focal_px_sd / f,
            u.click_sigma_px
        ));
    }
    out
}

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
    scene.validate()?;
    let fitted = if options.method == Method::Fit {
        Some(fit_scene(scene, &FitOptions::default())?)
    } else {
        None
    };
    let (cal, rec, factor) = if let Some(f) = &fitted {
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
    let free_mp = free_space(&floor, &footprints);
    let reach = 2.0
        * floor
            .iter()
            .chain(footprints.iter().flatten())
            .map(Vector2::norm)
            .fold(k, f64::max);
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
    let free = to_polygons(&free_mp);
    let corners = [
        Vector2::new(0.0, 0.0),
        Vector2::new(f64::from(scene.image.width), 0.0),
        Vector2::new(0.0, f64::from(scene.image.height)),
        Vector2::new(f64::from(scene.image.width), f64::from(scene.image.height)),
    ];
    let xs = corners.map(|c| cal.frame.coords(c).x);
    let d0 = cal.top_view_distance_px();
    let fov = [
        xs.iter().copied().fold(f64::INFINITY, f64::min),
        xs.iter().copied().fold(f64::NEG_INFINITY, f64::max),
    ]
    .map(|x| x.atan2(d0).to_degrees());
    let o = cal.principal_point_px();
    let view = view_on_floor(&cal, scene.image, k, 0.75 * reach.max(3.0 * k));
    let mut warnings = cal.warnings.clone();
    warnings.extend(crossing_warnings(scene, &rec));
    let mut camera_uncertainty = None;
    let mut fit_report = None;
    if let Some(f) = &fitted {
        let fit_options = FitOptions {
            click_sigma_px: options.click_sigma_px,
        };
        let u = f.uncertainty(scene, &fit_options)?;
        warnings.extend(fit_warnings(scene, f, &u));
        for (o, ou) in objects.iter_mut().zip(&u.objects) {
            o.uncertainty = Some(ou.clone());
        }
        camera_uncertainty = Some(u.camera);
        fit_report = Some(FitReport {
            click_sigma_px: u.click_sigma_px,
            click_sigma_source: u.click_sigma_source.to_owned(),
            rms_residual_px: f.rms_residual_px,
            degrees_of_freedom: f.degrees_of_freedom,
            iterations: f.iterations,
            principal_point_fitted: f.principal_point_fitted,
        });
    }
    Ok(FloorMap {
        version: 1,
        units,
        method: options.method,
        camera: CameraReport {
            perspective: cal.perspective,
            focal_px: cal.focal_px,
            principal_point: [o.x, o.y],
            pitch_deg: cal.pitch_rad.to_degrees(),
            roll_deg: cal.roll_rad.to_degrees(),
            room_yaw_deg: fitted
                .as_ref()
                .map_or_else(|| room_yaw_rad(&cal), |f| f.room_yaw_rad)
                .to_degrees(),
            height: k,
            k_matrix: [
                [cal.focal_px, 0.0, o.x],
                [0.0, cal.focal_px, o.y],
                [0.0, 0.0, 1.0],
            ],
            rotation_map_from_camera: rotation_map_from_camera(cal.pitch_rad, cal.roll_rad),
            position: [0.0, 0.0, k],
            image: scene.image,
            vanishing_points: cal.vanishing_points_px.iter().map(|v| [v.x, v.y]).collect(),
            uncertainty: camera_uncertainty,
            horizontal_fov_deg: fov,
            view_on_floor: view,
        },
        objects,
        floor: floor.iter().map(|p| [p.x, p.y]).collect(),
        free_space: free,
        hidden,
        warnings,
        fit: fit_report,
    })
}

impl FloorMap {
    /// Parse a map from JSON text.
    ///
    /// # Errors
    /// [`MetrologyError::Json`] when the text is not a version-1 map.
    pub fn from_json_str(text: &str) -> Result<Self> {
        let map: FloorMap =
            serde_json::from_str(text).map_err(|e| MetrologyError::Json(e.to_string()))?;
        if map.version != 1 {
            return Err(MetrologyError::UnsupportedVersion {
                file: "map.json",
                version: u64::from(map.version),
            });
        }
        Ok(map)
    }

    /// The map as pretty-printed JSON.
    #[must_use]
    pub fn to_json_string(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_default()
    }

    /// Area of the free space (exteriors minus holes), in the map's units squared.
    #[must_use]
    pub fn free_area(&self) -> f64 {
        self.free_space
            .iter()
            .map(|p| {
                let ring = |pts: &[MapPoint]| {
                    LineString::from(pts.iter().map(|q| (q[0], q[1])).collect::<Vec<_>>())
                };
                Polygon::new(ring(&p.exterior), p.holes.iter().map(|h| ring(h)).collect())
                    .unsigned_area()
            })
            .sum::<f64>()
            // An empty sum of floats is -0.0.
            + 0.0
    }

    /// Axis-aligned bounds `(min, max)` of the floor, the objects and the station point.
    #[must_use]
    pub fn bounds(&self) -> (MapPoint, MapPoint) {
        let mut lo = [0.0f64, 0.0];
        let mut hi = [0.0f64, 0.0];
        let all = self
            .floor
            .iter()
            .chain(self.objects.iter().flat_map(|o| o.footprint.iter()));
        for p in all {
            for i in 0..2 {
                lo[i] = lo[i].min(p[i]);
                hi[i] = hi[i].max(p[i]);
            }
        }
        (lo, hi)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use geo::Contains;
    use rand::{RngExt, SeedableRng};

    /// Does the segment from the camera to a floor point pass through the axis-aligned box?
    /// (Slab test: independent of the convex-hull construction.)
    fn ray_hits_box(camera_h: f64, p: Vector2<f64>, lo: [f64; 3], hi: [f64; 3]) -> bool {
        let origin = [0.0, 0.0, camera_h];
        let dir = [p.x, p.y, -camera_h];
        let (mut t0, mut t1) = (0.0f64, 1.0f64);
        for k in 0..3 {
            if dir[k].abs() < 1e-15 {
                if origin[k] < lo[k] || origin[k] > hi[k] {
                    return false;
                }
                continue;
            }
            let (a, b) = ((lo[k] - origin[k]) / dir[k], (hi[k] - origin[k]) / dir[k]);
            t0 = t0.max(a.min(b));
            t1 = t1.min(a.max(b));
        }
        t0 <= t1
    }

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

    #[test]
    fn occlusion_shadow_matches_ray_casting() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        for &(h, camera_h) in &[(0.8, 1.5), (2.0, 1.5), (0.3, 1.0)] {
            let (lo, hi) = ([0.5, 2.0, 0.0], [1.3, 2.6, h]);
            let fp = [
                Vector2::new(lo[0], lo[1]),
                Vector2::new(hi[0], lo[1]),
                Vector2::new(hi[0], hi[1]),
                Vector2::new(lo[0], hi[1]),
            ];
            let shadow = occlusion_shadow(&fp, Some(h), camera_h, 100.0).unwrap();
            let footprint = Polygon::new(ring(&fp), vec![]);
            let mut hidden_seen = 0;
            for _ in 0..4000 {
                let p = Vector2::new(rng.random_range(-3.0..5.0), rng.random_range(0.1..12.0));
                let pt = Point::new(p.x, p.y);
                if footprint.contains(&pt) {
                    continue;
                }
                let expected = ray_hits_box(camera_h, p, lo, hi);
                hidden_seen += usize::from(expected);
                assert_eq!(
                    shadow.contains(&pt),
                    expected,
                    "h {h}, camera {camera_h}: point {p:?}"
                );
            }
            assert!(hidden_seen > 20, "the test must see hidden points");
        }
    }
}

//! The fit's starting point: the camera from the vanishing points with the principal point
//! held (the projective form's calibration, in closed form), or from the points the clicked
//! boxes' edges give (`box_edges.rs`), and each object by linear least squares on the rays of
//! its clicks.

use nalgebra::{DMatrix, DVector, Matrix2, Matrix3, Vector2, Vector3};

use super::GIVEN_POINT_SD_DEG;
use super::model::{BoxAxes, Camera, CornerClick, Part, VpEvidence, px};
use super::solve::{Model, Problem};
use crate::camera::rotation_map_from_camera;
use crate::error::{MetrologyError, Result};
use crate::interrupt::Interrupt;
use crate::scene::{ImageSize, ObjectShape, Scale, Scene, VpChart};

/// The problem and where to start it.
pub(crate) struct Built {
    pub problem: Problem,
    pub x0: Vec<f64>,
    pub object_parts: Vec<usize>,
    pub floor_distance_parts: Option<[usize; 2]>,
    /// Notes on how the vanishing points were read (which one was taken as vertical).
    pub warnings: Vec<String>,
}

/// The least-squares intersection of segments' lines, homogeneous pixel coordinates (may be
/// at infinity); `None` when the lines' moment matrix has no finite decomposition.
pub(super) fn homogeneous_vp(lines: &[[f64; 4]], image: ImageSize) -> Option<Vector3<f64>> {
    let c = image.centre();
    let s = image.diagonal();
    let mut m = Matrix3::<f64>::zeros();
    for seg in lines {
        let a = Vector3::new((seg[0] - c.x) / s, (seg[1] - c.y) / s, 1.0);
        let b = Vector3::new((seg[2] - c.x) / s, (seg[3] - c.y) / s, 1.0);
        let l = a.cross(&b);
        let norm = l.x.hypot(l.y);
        if norm > f64::EPSILON {
            let l = l / norm;
            m += l * l.transpose();
        }
    }
    let eig = crate::linalg::symmetric_eigen(m)?;
    let k = eig.eigenvalues.imin();
    let v = eig.eigenvectors.column(k);
    // Back to pixels: (x, y, w) -> (x s + c w, y s + c w, w).
    Some(Vector3::new(v.x * s + c.x * v.z, v.y * s + c.y * v.z, v.z))
}

/// `K^-1 v` for a homogeneous pixel `v`.
fn camera_direction(v: Vector3<f64>, pp: Vector2<f64>, f: f64) -> Vector3<f64> {
    Vector3::new((v.x - pp.x * v.z) / f, (v.y - pp.y * v.z) / f, v.z)
}

/// Focal length from two orthogonal vanishing directions with the principal point known:
/// `(v1 - o).(v2 - o) + f^2 = 0`.
fn focal_from_pair(a: Vector3<f64>, b: Vector3<f64>, pp: Vector2<f64>) -> Option<f64> {
    let (ax, ay) = (a.x - pp.x * a.z, a.y - pp.y * a.z);
    let (bx, by) = (b.x - pp.x * b.z, b.y - pp.y * b.z);
    let den = a.z * b.z;
    if den.abs() < 1e-300 {
        return None;
    }
    let f2 = -(ax * bx + ay * by) / den;
    (f2 > 0.0 && f2.is_finite()).then(|| f2.sqrt())
}

/// Camera parameters `[f, pitch, roll, room yaw]` from the vanishing points and a focal
/// length.
fn camera_params(vps: &[Vector3<f64>], pp: Vector2<f64>, f: f64, level: bool) -> Option<[f64; 4]> {
    let d1 = camera_direction(vps[0], pp, f);
    let d2 = camera_direction(vps[1], pp, f);
    let mut up = d1.cross(&d2);
    if up.norm() < 1e-300 {
        return None;
    }
    up = up.normalize();
    if up.y > 0.0 {
        up = -up;
    }
    if level {
        // The horizon through the principal point: up lies in the image plane.
        up.z = 0.0;
        if up.norm() < 1e-300 {
            return None;
        }
        up = up.normalize();
    }
    let pitch = (-up.z).clamp(-1.0, 1.0).asin();
    let roll = up.x.atan2(-up.y);
    let r = rotation_map_from_camera(pitch, roll);
    let r = Matrix3::from_fn(|i, j| r[i][j]);
    let m = r * d1;
    let yaw = m.y.atan2(m.x);
    [f, pitch, roll, yaw]
        .iter()
        .all(|v| v.is_finite())
        .then_some([f, pitch, roll, yaw])
}

/// A box's parameters (origin, sides, height; not the yaw) by linear least squares on its
/// clicks' rays, for one axis assignment and yaw offset; `None` when the system is rank
/// deficient.
fn linear_box(
    cam: &Camera,
    clicks: &[CornerClick],
    axes: BoxAxes,
    has_top: bool,
    yaw: f64,
) -> Option<Vec<f64>> {
    let (e1, e2) = Part::box_axes(cam, axes, yaw);
    let n = 4 + usize::from(has_top);
    let mut a = DMatrix::zeros(3 * clicks.len(), n);
    let mut b = DVector::zeros(3 * clicks.len());
    for (row, c) in clicks.iter().enumerate() {
        let r = cam.ray(c.pixel).normalize();
        let (i, j, k) = (
            f64::from(c.place.0),
            f64::from(c.place.1),
            f64::from(c.place.2),
        );
        let rows = [
            ([0.0, r.z, i * e1.y * r.z, j * e2.y * r.z, -k * r.y], -r.y),
            ([-r.z, 0.0, -i * e1.x * r.z, -j * e2.x * r.z, k * r.x], r.x),
            (
                [
                    r.y,
                    -r.x,
                    i * (e1.x * r.y - e1.y * r.x),
                    j * (e2.x * r.y - e2.y * r.x),
                    0.0,
                ],
                0.0,
            ),
        ];
        for (q, (coef, rhs)) in rows.iter().enumerate() {
            for col in 0..n {
                a[(3 * row + q, col)] = coef[col];
            }
            b[3 * row + q] = *rhs;
        }
    }
    let svd = crate::linalg::svd(a)?;
    let sv = &svd.singular_values;
    if sv.min() <= 1e-10 * sv.max() {
        return None;
    }
    let z = svd.solve(&b, 0.0).ok()?;
    let p: Vec<f64> = z.iter().copied().collect();
    p.iter().all(|v| v.is_finite()).then_some(p)
}

/// The best starting box over the axis assignments (and yaw offsets for a box with its own
/// yaw), by reprojection error; signs flipped so both sides are positive.
fn start_box(
    cam: &Camera,
    clicks: &[CornerClick],
    view: crate::scene::BoxView,
    has_top: bool,
    own_yaw: bool,
) -> Option<(Part, Vec<f64>)> {
    let yaws: Vec<f64> = if own_yaw {
        (-9..=9).map(|k| f64::from(k) * 5f64.to_radians()).collect()
    } else {
        vec![0.0]
    };
    let mut best: Option<(f64, Part, Vec<f64>)> = None;
    // Keep the candidate that reprojects best (all its corners in front of the camera).
    let mut consider = |axes: BoxAxes, p: Vec<f64>| {
        let part = Part::Box {
            view,
            clicks: clicks.to_vec(),
            axes,
            has_top,
            own_yaw,
        };
        let mut r = vec![0.0; part.residual_count()];
        if !part.residuals(cam, &p, &mut r) {
            return false;
        }
        let cost: f64 = r.iter().map(|v| v * v).sum();
        if best.as_ref().is_none_or(|(c, _, _)| cost < *c) {
            best = Some((cost, part, p));
        }
        true
    };
    let mut found = false;
    for first in 0..2 {
        for &yaw in &yaws {
            let mut axes = BoxAxes {
                first,
                sign1: 1.0,
                sign2: 1.0,
            };
            let Some(mut p) = linear_box(cam, clicks, axes, has_top, yaw) else {
                continue;
            };
            if own_yaw {
                p.push(yaw);
            }
            if p[2] < 0.0 {
                axes.sign1 = -1.0;
                p[2] = -p[2];
            }
            if p[3] < 0.0 {
                axes.sign2 = -1.0;
                p[3] = -p[3];
            }
            found |= consider(axes, p);
        }
    }
    if !found {
        // The linear start puts a corner behind this camera (a poor starting camera): start
        // from a small box standing on the floor under the first base click instead; the fit
        // moves it.
        let base = clicks.iter().find(|c| c.place.2 == 0)?;
        let q = start_floor_point(cam, base.pixel);
        let size = 0.1 * q.norm().max(0.1);
        for first in 0..2 {
            let axes = BoxAxes {
                first,
                sign1: 1.0,
                sign2: 1.0,
            };
            let (e1, e2) = Part::box_axes(cam, axes, 0.0);
            let (i, j) = (f64::from(base.place.0), f64::from(base.place.1));
            let origin = q - e1 * (i * size) - e2 * (j * size);
            let mut p = vec![origin.x, origin.y, size, size];
            if has_top {
                p.push(size);
            }
            if own_yaw {
                p.push(0.0);
            }
            consider(axes, p);
        }
    }
    best.map(|(_, part, p)| (part, p))
}

/// A floor point for a pixel, or a far point along its ray's bearing when it lies on or
/// above the horizon of the starting camera.
fn start_floor_point(cam: &Camera, pixel: Vector2<f64>) -> Vector2<f64> {
    cam.floor_point(pixel).unwrap_or_else(|| {
        let r = cam.ray(pixel);
        let h = Vector2::new(r.x, r.y);
        if h.norm() > 0.0 {
            h.normalize() * 100.0
        } else {
            Vector2::new(0.0, 100.0)
        }
    })
}

/// Height of the vertical over a floor point that the ray through `top` passes closest to.
fn start_height(cam: &Camera, base: Vector2<f64>, top: Vector2<f64>) -> f64 {
    let r = cam.ray(top);
    let c = Vector3::new(0.0, 0.0, 1.0);
    let horizontal = Vector2::new(r.x, r.y);
    let t = if horizontal.norm_squared() > 0.0 {
        base.dot(&horizontal) / horizontal.norm_squared()
    } else {
        0.0
    };
    (c + r * t).z
}

/// The object parts, their starting parameters, each scene object's part and the scale's
/// floor points' parts.
type StartParts = (Vec<Part>, Vec<f64>, Vec<usize>, Option<[usize; 2]>);

/// The object parts and their starting parameters for one starting camera.
fn start_parts(scene: &Scene, cam: &Camera) -> Result<StartParts> {
    let mut parts = Vec::new();
    let mut params = Vec::new();
    let mut object_parts = Vec::new();
    for (i, obj) in scene.objects.iter().enumerate() {
        object_parts.push(parts.len());
        match obj.shape(i)? {
            ObjectShape::Box {
                view,
                base,
                top,
                own_yaw,
            } => {
                let mut clicks = Vec::new();
                for (level, corners) in [(0u8, base), (1u8, &top)] {
                    for (c, p) in corners.given() {
                        let (a, b) = c.grid_index();
                        clicks.push(CornerClick {
                            place: (a, b, level),
                            pixel: px(p),
                            name: format!(
                                "{}.{}",
                                if level == 1 { "top" } else { "base" },
                                c.name()
                            ),
                        });
                    }
                }
                let has_top = top.given().next().is_some();
                let (part, p) = start_box(cam, &clicks, view, has_top, own_yaw).ok_or_else(|| {
                    MetrologyError::Degenerate {
                        field: format!("objects[{i}]"),
                        reason: format!(
                            "the clicks of object {:?} do not fit a box in front of the camera: check the corner names (near, right, left, far as seen from the camera) and that the vanishing points belong to the box's edges",
                            obj.name
                        ),
                    }
                })?;
                parts.push(part);
                params.extend(p);
            }
            ObjectShape::Footprint { polygon, top } => {
                let vertices: Vec<Vector2<f64>> = polygon.iter().map(|p| px(*p)).collect();
                let floor: Vec<Vector2<f64>> = vertices
                    .iter()
                    .map(|v| start_floor_point(cam, *v))
                    .collect();
                for f in &floor {
                    params.extend([f.x, f.y]);
                }
                if let Some((k, t)) = top {
                    params.push(start_height(cam, floor[k], px(t)));
                }
                parts.push(Part::Footprint {
                    vertices,
                    top: top.map(|(k, t)| (k, px(t))),
                });
            }
        }
    }
    let mut floor_distance_parts = None;
    if let Some(Scale::FloorDistance(fd)) = scene.scale()? {
        let first = parts.len();
        for p in [fd.from, fd.to] {
            let f = start_floor_point(cam, px(p));
            params.extend([f.x, f.y]);
            parts.push(Part::FloorPoint { pixel: px(p) });
        }
        floor_distance_parts = Some([first, first + 1]);
    }
    Ok((parts, params, object_parts, floor_distance_parts))
}

/// The whitening of a click with covariance `cov` (px^2): `W` with `W^T W = cov^-1`, so
/// that `W r` has unit covariance; scaled by 1 px so that the weighted residual is in
/// pixels of a 1 px click. `None` when the matrix has no Cholesky factor (validation refuses
/// such a covariance).
pub(crate) fn whitening(cov: [[f64; 2]; 2]) -> Option<Matrix2<f64>> {
    let m = Matrix2::new(cov[0][0], cov[0][1], cov[1][0], cov[1][1]);
    let l = m.cholesky()?.l();
    l.try_inverse()
}

/// Per part, per clicked point (in its residuals' order), the whitening of the click's
/// covariance when the scene gives one (`click_covariances_px2`).
pub(crate) fn click_weights(
    scene: &Scene,
    parts: &[Part],
    object_parts: &[usize],
    floor_distance_parts: Option<[usize; 2]>,
) -> Vec<Vec<Option<Matrix2<f64>>>> {
    let covs = &scene.click_covariances_px2;
    if covs.is_empty() {
        return Vec::new();
    }
    let weight = |field: String| covs.get(&field).and_then(|c| whitening(*c));
    let mut out: Vec<Vec<Option<Matrix2<f64>>>> = parts
        .iter()
        .map(|p| vec![None; p.residual_count() / 2])
        .collect();
    for (i, &k) in object_parts.iter().enumerate() {
        match &parts[k] {
            Part::Box { clicks, .. } => {
                for (n, c) in clicks.iter().enumerate() {
                    out[k][n] = weight(format!("objects[{i}].{}", c.name));
                }
            }
            Part::Footprint { vertices, top } => {
                for (n, slot) in out[k].iter_mut().take(vertices.len()).enumerate() {
                    *slot = weight(format!("objects[{i}].footprint[{n}]"));
                }
                if top.is_some() {
                    out[k][vertices.len()] = weight(format!("objects[{i}].top.point"));
                }
            }
            Part::FloorPoint { .. } => {}
        }
    }
    if let Some([a, b]) = floor_distance_parts {
        out[a][0] = weight("scale.floor_distance.from".to_owned());
        out[b][0] = weight("scale.floor_distance.to".to_owned());
    }
    out
}

/// Every clicked box corner of the scene, pixels.
fn box_clicks(scene: &Scene) -> Vec<[f64; 2]> {
    let mut out = Vec::new();
    for o in &scene.objects {
        if let Some(b) = &o.base {
            out.extend(b.given().map(|(_, p)| p));
        }
        if let Some(t) = &o.top {
            out.extend(t.corners.given().map(|(_, p)| p));
        }
    }
    out
}

/// The scene's vanishing-point evidence and each one as a homogeneous pixel point, in the
/// order given.
fn evidence(scene: &Scene) -> Result<(Vec<VpEvidence>, Vec<Vector3<f64>>)> {
    let all: Vec<VpEvidence> = scene
        .vanishing_points
        .iter()
        .map(|v| {
            // A direction (a point at infinity) before a point, as the scene reads them.
            let given = v
                .direction
                .map(|[x, y]| Vector3::new(x, y, 0.0))
                .or_else(|| v.point.map(|[x, y]| Vector3::new(x, y, 1.0)));
            match given {
                Some(at) if v.lines.len() < 2 || v.covariance_deg2.is_some() => {
                    // A point without a covariance is a fact (docs/scene-format.md).
                    let sd = GIVEN_POINT_SD_DEG.to_radians();
                    let cov = v
                        .covariance_deg2
                        .map_or([[sd * sd, 0.0], [0.0, sd * sd]], |c| {
                            c.map(|row| row.map(|c| c.to_radians().to_radians()))
                        });
                    VpEvidence::Measured {
                        at,
                        chart: VpChart::of_scene(scene),
                        // Validation refuses a covariance without a Cholesky factor.
                        whitening: whitening(cov).unwrap_or_else(Matrix2::zeros),
                        scale_px: 1.0,
                    }
                }
                _ => VpEvidence::Lines(v.lines.clone()),
            }
        })
        .collect();
    let points = all
        .iter()
        .enumerate()
        .map(|(i, e)| match e {
            VpEvidence::Lines(l) => {
                homogeneous_vp(l, scene.image).ok_or_else(|| MetrologyError::Degenerate {
                    field: format!("vanishing_points[{i}].lines"),
                    reason: "the segments' coordinates are too large for their intersection to be computed: give them in pixels of the image".to_owned(),
                })
            }
            VpEvidence::Measured { at, .. } => Ok(*at),
            VpEvidence::Intrinsics { .. } => Err(MetrologyError::Degenerate {
                field: format!("vanishing_points[{i}]"),
                reason: "is not a vanishing point".to_owned(),
            }),
        })
        .collect::<Result<Vec<Vector3<f64>>>>()?;
    Ok((all, points))
}

/// The readings of the scene's vanishing points to fit, each as the indices of the
/// horizontal ones and then the vertical one: the closed forms' reading
/// ([`crate::calibration::reading`]) first, then the other of the listed order and the one
/// opposite the most level side when it differs. The fit's likelihood chooses between them
/// (the objects' vertical edges tell); where it cannot (vanishing points alone fit any
/// reading equally), the first wins. One reading for two vanishing points.
///
/// # Errors
/// When a vanishing point's segments have no computable intersection.
pub(crate) fn vanishing_point_orders(scene: &Scene) -> Result<Vec<[usize; 3]>> {
    let (_, points) = evidence(scene)?;
    let documented = [0, 1, 2];
    let Some(first) = crate::calibration::reading(&points, scene.vanishing_points_labelled())
    else {
        return Ok(vec![documented]);
    };
    let level = crate::calibration::vertical_last_order(&points).unwrap_or(documented);
    let other = if first == documented {
        level
    } else {
        documented
    };
    Ok(if other == first {
        vec![first]
    } else {
        vec![first, other]
    })
}

/// Where the starting cameras come from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Cameras {
    /// The given (or detected) vanishing points.
    Given,
    /// The vanishing points the clicked boxes' own edges give (`box_edges.rs`); no start when
    /// they give none.
    BoxEdges,
}

/// Build the problem and its starting points, best (lowest starting cost) first.
///
/// `fit_pp`: whether the principal point is a parameter when the scene allows it (three
/// finite vanishing points and no given principal point); else it is held at the given
/// value or the image centre. `order`: which vanishing points are horizontal and which is
/// vertical ([`vanishing_point_orders`]). `evidence_sigma_px`: the click noise that evidence
/// with its own uncertainty (measured vanishing points, intrinsics' priors) is expressed in,
/// when known (else 1 px until the fit estimates it).
///
/// # Errors
/// When an object's clicks fit no box in front of any starting camera, or the scene's
/// shapes or scale are invalid.
pub(crate) fn build(
    scene: &Scene,
    fit_pp: bool,
    order: [usize; 3],
    evidence_sigma_px: Option<f64>,
    cameras: Cameras,
) -> Result<Vec<Built>> {
    let (mut all, mut points) = evidence(scene)?;
    // The documented order: the horizontal vanishing points as given, the vertical one last.
    let mut warnings = Vec::new();
    if points.len() == 3 {
        if order[2] != 2 {
            warnings.push(crate::calibration::reorder_warning(&points, order));
        }
        let (p, a) = (points.clone(), all.clone());
        points = order.iter().map(|&i| p[i]).collect();
        all = order.iter().map(|&i| a[i].clone()).collect();
    }
    // A segment drawn between two clicked box corners repeats those clicks: the box model
    // already runs that edge to its vanishing point, so counting the segment again would count
    // the same click noise twice (and make the error bars too small). It helps the start only.
    let clicked = box_clicks(scene);
    let is_click = |x: f64, y: f64| {
        clicked
            .iter()
            .any(|c| (c[0] - x).abs() + (c[1] - y).abs() < 1e-9)
    };
    let vps: Vec<VpEvidence> = all
        .into_iter()
        .map(|e| match e {
            VpEvidence::Lines(l) => VpEvidence::Lines(
                l.into_iter()
                    .filter(|s| !(is_click(s[0], s[1]) && is_click(s[2], s[3])))
                    .collect(),
            ),
            other => other,
        })
        .collect();
    // The principal point: given, or fitted from three finite vanishing points (starting at
    // their orthocentre, and at the image centre), or held at the image centre.
    let finite: Vec<Vector2<f64>> = points
        .iter()
        .filter_map(crate::calibration::finite_point)
        .collect();
    // A vanishing point counts as given when it is a point or has segments of its own: the
    // vertical one measured only by box edges between clicked corners repeats those clicks,
    // which fix the principal point poorly (and first-order error bars badly).
    let vertical_measured = vps.get(2).is_some_and(|e| match e {
        VpEvidence::Lines(l) => !l.is_empty(),
        VpEvidence::Measured { .. } => true,
        VpEvidence::Intrinsics { .. } => false,
    });
    // A principal point with a standard deviation is a prior the fit refines (at the given
    // point, else the image centre).
    let pp_prior = scene.principal_point_sd_px.map(|sd| {
        (
            scene
                .principal_point
                .map_or_else(|| scene.image.centre(), px),
            sd,
        )
    });
    let free_pp = fit_pp
        && (pp_prior.is_some()
            || (scene.principal_point.is_none() && finite.len() == 3 && vertical_measured));
    let mut pp_starts = Vec::new();
    if free_pp
        && finite.len() == 3
        && let Some(o) = crate::calibration::orthocentre(finite[0], finite[1], finite[2])
        && pp_prior.is_none_or(|(p, sd)| (o - p).norm() <= 3.0 * sd)
    {
        pp_starts.push(o);
    }
    pp_starts.push(
        scene
            .principal_point
            .map_or_else(|| scene.image.centre(), px),
    );
    let (camera_len, fixed) = if free_pp {
        (6, None)
    } else {
        (4, Some(pp_starts[0]))
    };
    let mut vps = vps;
    let focal_prior = scene.focal_px.zip(scene.focal_sd_px);
    let pp_prior = pp_prior.filter(|_| free_pp);
    if focal_prior.is_some() || pp_prior.is_some() {
        vps.push(VpEvidence::Intrinsics {
            focal_px: focal_prior,
            principal_point_px: pp_prior,
            scale_px: 1.0,
        });
    }
    if let Some(sigma) = evidence_sigma_px {
        for e in &mut vps {
            e.set_scale(sigma);
        }
    }
    let mut candidates: Vec<(f64, Built)> = Vec::new();
    let mut first_error = None;
    // The cameras the given vanishing points imply, or those the clicked boxes' own edges
    // imply (`box_edges.rs`): when a detected point is wrong, only the second start near the
    // clicks' camera.
    let points = match cameras {
        Cameras::Given => points,
        Cameras::BoxEdges => match super::box_edges::box_edge_points(scene, &points, scene.image) {
            Some(p) => p,
            None => return Ok(Vec::new()),
        },
    };
    for &pp in &pp_starts {
        // Starting focal lengths: from each pair of vanishing points, the scene's, and the range
        // of real lenses (0.4 to 2 image diagonals); vanishing points from short noisy edges can
        // put the first far off, where the fit runs towards an orthographic camera.
        let mut focals = Vec::new();
        focals.extend(focal_from_pair(points[0], points[1], pp));
        if points.len() == 3 {
            focals.extend(focal_from_pair(points[0], points[2], pp));
            focals.extend(focal_from_pair(points[1], points[2], pp));
        }
        focals.extend(scene.focal_px);
        let d = scene.image.diagonal();
        focals.extend([0.4 * d, 0.6 * d, 0.8 * d, 1.1 * d, 1.5 * d, 2.0 * d]);
        // Two-point perspective: the scene format defines the camera as level (pitch 0).
        let level = scene.vanishing_points.len() == 2;
        for f in focals {
            let Some(c) = camera_params(&points, pp, f, level) else {
                continue;
            };
            // The camera that best explains the vanishing-point evidence alone (orthogonal room
            // directions seen from the held principal point), before any object.
            let alone = Problem {
                camera_len,
                fixed_pp: fixed,
                fixed_pitch: level,
                parts: Vec::new(),
                offsets: Vec::new(),
                vps: vps.clone(),
                weights: Vec::new(),
                interrupt: Interrupt::default(),
            };
            let mut c = c.to_vec();
            if free_pp {
                c.extend([pp.x, pp.y]);
            }
            // (Not for the boxes' own points: that would take them back to the given ones.)
            if cameras == Cameras::Given
                && let Some(sol) = super::solve::minimise(&alone, c.clone())
                && sol.x.iter().all(|v| v.is_finite())
                && sol.x[0] > 0.0
            {
                c.copy_from_slice(&sol.x[..camera_len]);
            }
            let cam = Camera::from_params(&c, fixed);
            let (parts, params, object_parts, floor_distance_parts) = match start_parts(scene, &cam)
            {
                Ok(v) => v,
                Err(e) => {
                    first_error.get_or_insert(e);
                    continue;
                }
            };
            let mut offsets = Vec::with_capacity(parts.len());
            let mut at = camera_len;
            for p in &parts {
                offsets.push(at);
                at += p.len();
            }
            let weights = click_weights(scene, &parts, &object_parts, floor_distance_parts);
            let problem = Problem {
                camera_len,
                fixed_pp: fixed,
                fixed_pitch: level,
                parts,
                offsets,
                vps: vps.clone(),
                weights,
                interrupt: Interrupt::default(),
            };
            let mut x0 = c;
            x0.extend(params);
            let cost = problem.cost(&x0);
            if cost.is_finite() {
                candidates.push((
                    cost,
                    Built {
                        problem,
                        x0,
                        object_parts,
                        floor_distance_parts,
                        warnings: warnings.clone(),
                    },
                ));
            }
        }
    }
    candidates.sort_by(|a, b| a.0.total_cmp(&b.0));
    match (candidates.is_empty(), first_error) {
        (false, _) => Ok(candidates.into_iter().map(|(_, b)| b).collect()),
        (true, Some(e)) => Err(e),
        (true, None) => Err(MetrologyError::NoRealFocalLength(
            "the vanishing points give no starting camera for the fit: each pair of them must be orthogonal directions seen from the principal point".to_owned(),
        )),
    }
}

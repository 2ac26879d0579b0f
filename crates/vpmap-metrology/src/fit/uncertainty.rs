//! Error bars: the fit's covariance `sigma^2 (J^T J)^-1` propagated to what the map reports,
//! and the scale in metres.
//!
//! Each reported value `q(x)` (an object's centroid, sides, height and yaw, the camera's
//! height, all times the scale `k(x)` in metres per camera height) gets its gradient `g` by
//! central differences over the parameters it depends on; its variance is
//! `sigma^2 g^T (J^T J)^-1 g`, computed with the same Schur-complement solve as a fit step.

use nalgebra::{DMatrix, DVector, Matrix2, Vector2};

use super::fitted::{FitOptions, Fitted, click_sigma};
use super::model::{BoxAxes, Camera, Part};
use super::solve::{Factored, Model, Problem};
use crate::error::{MetrologyError, Result};
use crate::scene::{Dimension, Scale, Scene};
use crate::uncertainty::{CameraUncertainty, Ellipse, ObjectUncertainty};

/// The chi-square quantile with 2 degrees of freedom at 95 %: `-2 ln 0.05`.
pub const CHI2_2DOF_95: f64 = 5.991_464_547_107_979;

/// The fit's error bars in the map's units.
#[derive(Debug, Clone, PartialEq)]
pub struct FitUncertainty {
    /// Per scene object, in scene order.
    pub objects: Vec<ObjectUncertainty>,
    /// The camera's.
    pub camera: CameraUncertainty,
    /// The click noise used, pixels.
    pub click_sigma_px: f64,
    /// `"given"`, `"residuals"` or `"default"` ([`FitOptions::click_sigma_px`]).
    pub click_sigma_source: &'static str,
    /// Relative standard deviation of each object's sides and height (the largest), for
    /// warnings: `(object index, which, relative sd)`.
    pub relative_size_sd: Vec<(usize, &'static str, f64)>,
}

/// What the scale measures in the fitted model.
#[derive(Debug, Clone, Copy)]
enum Measure {
    /// No scale: camera heights.
    Unit,
    /// The camera height in metres.
    CameraHeight(f64),
    /// A known length (metres) of something the model measures.
    Length { meters: f64, what: Measured },
}

#[derive(Debug, Clone, Copy)]
enum Measured {
    /// Parameter `index` of part `part` (a box side or height, a footprint height).
    Param { part: usize, index: usize },
    /// The longer (or shorter) side of a box.
    Side { part: usize, longer: bool },
    /// The distance between two floor points.
    FloorDistance { a: usize, b: usize },
}

fn params<'a>(problem: &Problem, x: &'a [f64], part: usize) -> &'a [f64] {
    &x[problem.offsets[part]..problem.offsets[part] + problem.parts[part].len()]
}

impl Measured {
    fn value(self, problem: &Problem, x: &[f64]) -> f64 {
        match self {
            Measured::Param { part, index } => params(problem, x, part)[index].abs(),
            Measured::Side { part, longer } => {
                let p = params(problem, x, part);
                let (a, b) = (p[2].abs(), p[3].abs());
                if longer { a.max(b) } else { a.min(b) }
            }
            Measured::FloorDistance { a, b } => {
                let (p, q) = (params(problem, x, a), params(problem, x, b));
                (p[0] - q[0]).hypot(p[1] - q[1])
            }
        }
    }

    fn parts(self) -> Vec<usize> {
        match self {
            Measured::Param { part, .. } | Measured::Side { part, .. } => vec![part],
            Measured::FloorDistance { a, b } => vec![a, b],
        }
    }
}

impl Measure {
    /// Metres per camera height at `x`.
    fn factor(self, problem: &Problem, x: &[f64]) -> f64 {
        match self {
            Measure::Unit => 1.0,
            Measure::CameraHeight(h) => h,
            Measure::Length { meters, what } => meters / what.value(problem, x),
        }
    }

    fn parts(self) -> Vec<usize> {
        match self {
            Measure::Length { what, .. } => what.parts(),
            _ => Vec::new(),
        }
    }
}

/// A box's two side directions on the floor (its own yaw, the parameter after its sides and
/// height, applied), for parameters `p` and camera `cam`.
fn box_frame(
    cam: &Camera,
    axes: BoxAxes,
    has_top: bool,
    own_yaw: bool,
    p: &[f64],
) -> (Vector2<f64>, Vector2<f64>) {
    let yaw = if own_yaw {
        p[4 + usize::from(has_top)]
    } else {
        0.0
    };
    Part::box_axes(cam, axes, yaw)
}

/// An object's centroid, longer and shorter side, height and yaw (camera heights, radians),
/// for a part with parameters `p` and camera `cam` (whose room directions the part's axes
/// follow).
pub(crate) fn part_values(cam: &Camera, part: &Part, p: &[f64]) -> [f64; 6] {
    match part {
        Part::Box {
            axes,
            has_top,
            own_yaw,
            ..
        } => {
            let (e1, e2) = box_frame(cam, *axes, *has_top, *own_yaw, p);
            let c = Vector2::new(p[0], p[1]) + e1 * (0.5 * p[2]) + e2 * (0.5 * p[3]);
            let (a, b) = (p[2].abs(), p[3].abs());
            let long_axis = if a >= b { e1 } else { e2 };
            [
                c.x,
                c.y,
                a.max(b),
                a.min(b),
                if *has_top { p[4] } else { 0.0 },
                long_axis.y.atan2(long_axis.x),
            ]
        }
        Part::Footprint { vertices, top } => {
            let n = vertices.len();
            let v: Vec<Vector2<f64>> = (0..n)
                .map(|k| Vector2::new(p[2 * k], p[2 * k + 1]))
                .collect();
            let (mut a2, mut cx, mut cy) = (0.0, 0.0, 0.0);
            for k in 0..n {
                let (a, b) = (v[k], v[(k + 1) % n]);
                let cr = a.x * b.y - b.x * a.y;
                a2 += cr;
                cx += (a.x + b.x) * cr;
                cy += (a.y + b.y) * cr;
            }
            let (cx, cy) = if a2.abs() > 0.0 {
                (cx / (3.0 * a2), cy / (3.0 * a2))
            } else {
                (0.0, 0.0)
            };
            [cx, cy, 0.0, 0.0, top.map_or(0.0, |_| p[2 * n]), 0.0]
        }
        Part::FloorPoint { .. } => [p[0], p[1], 0.0, 0.0, 0.0, 0.0],
    }
}

/// The floor corners of a part with parameters `p`, for camera `cam`, in the fit's units:
/// a box's four (`origin + i a e1 + j b e2`), a footprint's vertices, a floor point itself.
pub(crate) fn part_corners(cam: &Camera, part: &Part, p: &[f64]) -> Vec<Vector2<f64>> {
    match part {
        Part::Box {
            axes,
            has_top,
            own_yaw,
            ..
        } => {
            let (e1, e2) = box_frame(cam, *axes, *has_top, *own_yaw, p);
            let o = Vector2::new(p[0], p[1]);
            [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
                .iter()
                .map(|&(i, j)| o + e1 * (i * p[2]) + e2 * (j * p[3]))
                .collect()
        }
        Part::Footprint { vertices, .. } => (0..vertices.len())
            .map(|k| Vector2::new(p[2 * k], p[2 * k + 1]))
            .collect(),
        Part::FloorPoint { .. } => vec![Vector2::new(p[0], p[1])],
    }
}

/// Wrap an angle difference to `(-pi/2, pi/2]` (a box's yaw is defined modulo 180 degrees).
pub(crate) fn wrap_half_turn(d: f64) -> f64 {
    let pi = std::f64::consts::PI;
    let mut d = d % pi;
    if d > pi / 2.0 {
        d -= pi;
    } else if d <= -pi / 2.0 {
        d += pi;
    }
    d
}

/// Gradients of `f` (several outputs) over the camera and the listed parts, as the blocks
/// [`Factored::solve`] takes.
pub(crate) fn gradients<const N: usize, M: Model>(
    problem: &M,
    x: &[f64],
    parts: &[usize],
    f: impl Fn(&[f64]) -> [f64; N],
    angular: [bool; N],
) -> Vec<(DVector<f64>, Vec<DVector<f64>>)> {
    gradients_of(problem, x, parts, |xs| f(xs).to_vec(), &angular)
}

/// [`gradients`] of a function with as many outputs as `angular` has entries (an output
/// whose `angular` is true is an angle modulo a half turn).
pub(crate) fn gradients_of<M: Model>(
    problem: &M,
    x: &[f64],
    parts: &[usize],
    f: impl Fn(&[f64]) -> Vec<f64>,
    angular: &[bool],
) -> Vec<(DVector<f64>, Vec<DVector<f64>>)> {
    let n = angular.len();
    let nc = problem.camera_len();
    let mut out: Vec<(DVector<f64>, Vec<DVector<f64>>)> = (0..n)
        .map(|_| {
            (
                DVector::zeros(nc),
                (0..problem.part_count())
                    .map(|p| DVector::zeros(problem.part_len(p)))
                    .collect(),
            )
        })
        .collect();
    let mut xs = x.to_vec();
    let mut column = |index: usize| -> Vec<f64> {
        let h = 1e-6 * x[index].abs().max(1.0);
        xs[index] = x[index] + h;
        let plus = f(&xs);
        xs[index] = x[index] - h;
        let minus = f(&xs);
        xs[index] = x[index];
        (0..n)
            .map(|k| {
                let (p, m) = (
                    plus.get(k).copied().unwrap_or(f64::NAN),
                    minus.get(k).copied().unwrap_or(f64::NAN),
                );
                let diff = if angular[k] {
                    wrap_half_turn(p - m)
                } else {
                    p - m
                };
                diff / (2.0 * h)
            })
            .collect()
    };
    for c in (0..nc).filter(|&c| !problem.camera_fixed(c)) {
        let d = column(c);
        for k in 0..n {
            out[k].0[c] = d[k];
        }
    }
    let mut seen = Vec::new();
    for &part in parts {
        if seen.contains(&part) {
            continue;
        }
        seen.push(part);
        for i in 0..problem.part_len(part) {
            let d = column(problem.part_offset(part) + i);
            for k in 0..n {
                out[k].1[part][i] = d[k];
            }
        }
    }
    out
}

/// The covariance matrix of the values whose gradients are `g`: `sigma^2 G^T (J^T J)^-1 G`,
/// one solve a gradient, made exactly symmetric.
pub(crate) fn covariance(f: &Factored, sigma: f64, g: &[Gradient]) -> DMatrix<f64> {
    // Only the parts some gradient touches enter (a gradient is zero outside the camera and
    // the few parts its value depends on).
    let parts: Vec<usize> = (0..g.first().map_or(0, |a| a.1.len()))
        .filter(|&p| g.iter().any(|a| a.1[p].iter().any(|v| *v != 0.0)))
        .collect();
    let solved: Vec<Gradient> = g
        .iter()
        .map(|b| f.solve_parts(&b.0, &b.1, &parts))
        .collect();
    let dot = |a: &Gradient, y: &Gradient| {
        a.0.dot(&y.0)
            + parts
                .iter()
                .zip(&y.1)
                .map(|(&p, q)| a.1[p].dot(q))
                .sum::<f64>()
    };
    let n = g.len();
    let mut m = DMatrix::zeros(n, n);
    for i in 0..n {
        for j in i..n {
            let v = 0.5 * sigma * sigma * (dot(&g[i], &solved[j]) + dot(&g[j], &solved[i]));
            m[(i, j)] = v;
            m[(j, i)] = v;
        }
    }
    m
}

/// `g_a^T (J^T J)^-1 g_b`.
pub(crate) fn quad(
    f: &Factored,
    a: &(DVector<f64>, Vec<DVector<f64>>),
    b: &(DVector<f64>, Vec<DVector<f64>>),
) -> f64 {
    let (yc, yo) = f.solve(&b.0, &b.1);
    a.0.dot(&yc) + a.1.iter().zip(&yo).map(|(p, q)| p.dot(q)).sum::<f64>()
}

/// The 95 % ellipse of a 2x2 covariance; unbounded (infinite semi-axes) for a covariance
/// with a non-finite entry.
#[must_use]
pub fn ellipse_95(centre: [f64; 2], cov: [[f64; 2]; 2]) -> Ellipse {
    let m = Matrix2::new(cov[0][0], cov[0][1], cov[1][0], cov[1][1]);
    let Some(eig) = crate::linalg::symmetric_eigen(m) else {
        // No finite covariance: an ellipse of unbounded size says so.
        return Ellipse {
            centre,
            semi_axes: [f64::INFINITY, f64::INFINITY],
            angle_deg: 0.0,
        };
    };
    let (big, small) = if eig.eigenvalues[0] >= eig.eigenvalues[1] {
        (0, 1)
    } else {
        (1, 0)
    };
    let v = eig.eigenvectors.column(big);
    Ellipse {
        centre,
        semi_axes: [
            (CHI2_2DOF_95 * eig.eigenvalues[big].max(0.0)).sqrt(),
            (CHI2_2DOF_95 * eig.eigenvalues[small].max(0.0)).sqrt(),
        ],
        angle_deg: v.y.atan2(v.x).to_degrees().rem_euclid(180.0),
    }
}

/// A gradient block as [`Factored::solve`] takes it: camera part, then per part.
pub(crate) type Gradient = (DVector<f64>, Vec<DVector<f64>>);

/// One object's error bars, in map units: `at` gives the camera and the object's parameters
/// at a parameter vector (its [`part_values`] in camera heights, and its [`part_corners`],
/// whose covariances give [`ObjectUncertainty::corner_sd`]), `k_at` the metres per camera
/// height there, `cov` the covariance matrix of a set of gradients ([`covariance`]); `parts`
/// are the parts they depend on. Also the relative standard deviations of its sides and
/// height, for the warnings. `None` when the centroid's covariance is not finite (a singular
/// fit). Shared by one photo's fit and a room's.
pub(crate) fn object_error_bars<M: Model>(
    problem: &M,
    x: &[f64],
    parts: &[usize],
    part: &Part,
    at: impl for<'a> Fn(&'a [f64]) -> (Camera, &'a [f64]),
    k_at: impl Fn(&[f64]) -> f64,
    cov: impl Fn(&[Gradient]) -> DMatrix<f64>,
) -> Option<(ObjectUncertainty, Vec<(&'static str, f64)>)> {
    let values = |xs: &[f64]| {
        let (cam, p) = at(xs);
        part_values(&cam, part, p)
    };
    // The six values and each floor corner's two coordinates (map units), in one pass.
    let n_corners = {
        let (cam, p) = at(x);
        part_corners(&cam, part, p).len()
    };
    let mut angular = vec![false; 6 + 2 * n_corners];
    angular[5] = true;
    let g = gradients_of(
        problem,
        x,
        parts,
        |xs| {
            let (cam, p) = at(xs);
            let v = part_values(&cam, part, p);
            let k = k_at(xs);
            let mut out = vec![v[0] * k, v[1] * k, v[2] * k, v[3] * k, v[4] * k, v[5]];
            out.extend(
                part_corners(&cam, part, p)
                    .iter()
                    .flat_map(|q| [q.x * k, q.y * k]),
            );
            out
        },
        &angular,
    );
    // The six values' covariance, and each corner's own 2 x 2 block (never the corners'
    // cross terms, which nothing reads: a footprint of n vertices would pay n^2 products).
    let m = cov(&g[..6]);
    let sd = |i: usize| m[(i, i)].max(0.0).sqrt();
    let two = |m: &DMatrix<f64>, i: usize| {
        [
            [m[(i, i)], m[(i, i + 1)]],
            [m[(i + 1, i)], m[(i + 1, i + 1)]],
        ]
    };
    let block = |i: usize| two(&m, i);
    let v = values(x);
    let k = k_at(x);
    let centroid = block(0);
    if !centroid.iter().flatten().all(|v| v.is_finite()) {
        return None;
    }
    // Each corner's sd along its least certain direction; the largest.
    let corner_sd = (0..n_corners)
        .map(|c| {
            let corner = cov(&g[6 + 2 * c..8 + 2 * c]);
            ellipse_95([0.0, 0.0], two(&corner, 0)).semi_axes[0] / CHI2_2DOF_95.sqrt()
        })
        .fold(None, |m: Option<f64>, s| Some(m.map_or(s, |m| m.max(s))));
    let is_box = matches!(part, Part::Box { .. });
    let has_height = match part {
        Part::Box { has_top, .. } => *has_top,
        Part::Footprint { top, .. } => top.is_some(),
        Part::FloorPoint { .. } => false,
    };
    let (len_sd, br_sd, h_sd) = (sd(2), sd(3), sd(4));
    let mut relative = Vec::new();
    if is_box {
        relative.push(("length", len_sd / (v[2] * k)));
        relative.push(("breadth", br_sd / (v[3] * k)));
    }
    if has_height {
        relative.push(("height", h_sd / (v[4] * k)));
    }
    Some((
        ObjectUncertainty {
            centroid_covariance: centroid,
            centroid_ellipse_95: ellipse_95([v[0] * k, v[1] * k], centroid),
            corner_sd,
            length_sd: is_box.then_some(len_sd),
            breadth_sd: is_box.then_some(br_sd),
            height_sd: has_height.then_some(h_sd),
            yaw_deg: is_box.then(|| v[5].to_degrees().rem_euclid(180.0)),
            yaw_sd_deg: is_box.then(|| sd(5).to_degrees()),
        },
        relative,
    ))
}

impl Fitted {
    fn measure(&self, scene: &Scene) -> Result<Measure> {
        let Some(scale) = scene.scale()? else {
            return Ok(Measure::Unit);
        };
        let part_of = |name: &str| -> Result<usize> {
            scene
                .objects
                .iter()
                .position(|o| o.name == name)
                .map(|i| self.object_parts[i])
                .ok_or_else(|| MetrologyError::UnknownScaleObject {
                    name: name.to_owned(),
                    known: String::new(),
                })
        };
        let no_top = |name: &str| MetrologyError::InvalidField {
            field: "scale".to_owned(),
            reason: format!(
                "measures a height, but object {name:?} has no top point to measure it"
            ),
        };
        Ok(match scale {
            Scale::CameraHeight(h) => Measure::CameraHeight(h),
            Scale::FloorDistance(fd) => {
                let [a, b] =
                    self.floor_distance_parts
                        .ok_or_else(|| MetrologyError::InvalidField {
                            field: "scale.floor_distance".to_owned(),
                            reason: "was not part of the fit".to_owned(),
                        })?;
                Measure::Length {
                    meters: fd.meters,
                    what: Measured::FloorDistance { a, b },
                }
            }
            Scale::Edge { name, ends, meters } => {
                let part = part_of(&name)?;
                let (a, b) = (ends[0].grid_index(), ends[1].grid_index());
                let index = if a.0 != b.0 {
                    2
                } else if a.1 != b.1 {
                    3
                } else {
                    match &self.problem.parts[part] {
                        Part::Box { has_top: true, .. } => 4,
                        _ => return Err(no_top(&name)),
                    }
                };
                Measure::Length {
                    meters,
                    what: Measured::Param { part, index },
                }
            }
            Scale::Object {
                name,
                dimension,
                meters,
            } => {
                let part = part_of(&name)?;
                let what = match (&self.problem.parts[part], dimension) {
                    (Part::Box { has_top: true, .. }, Dimension::Height) => {
                        Measured::Param { part, index: 4 }
                    }
                    (
                        Part::Footprint {
                            vertices,
                            top: Some(_),
                        },
                        Dimension::Height,
                    ) => Measured::Param {
                        part,
                        index: 2 * vertices.len(),
                    },
                    (_, Dimension::Height) => return Err(no_top(&name)),
                    (Part::Box { .. }, d) => Measured::Side {
                        part,
                        longer: d == Dimension::Length,
                    },
                    _ => {
                        return Err(MetrologyError::InvalidField {
                            field: "scale.dimension".to_owned(),
                            reason: format!(
                                "length and breadth are defined for boxes only; object {name:?} is a footprint (use \"height\" or a floor distance)"
                            ),
                        });
                    }
                };
                Measure::Length { meters, what }
            }
        })
    }

    /// Metres per camera height from the scene's scale (`None` without a scale).
    ///
    /// # Errors
    /// When the scale measures something the fit does not have (a height of an object
    /// without a top), or measures zero.
    pub fn meters_per_camera_height(&self, scene: &Scene) -> Result<Option<f64>> {
        let m = self.measure(scene)?;
        if matches!(m, Measure::Unit) {
            return Ok(None);
        }
        let k = m.factor(&self.problem, &self.x);
        if !(k.is_finite() && k > 0.0) {
            return Err(MetrologyError::Degenerate {
                field: "scale".to_owned(),
                reason: format!(
                    "the known length measures {k} metres per camera height in the fit; it must be positive"
                ),
            });
        }
        Ok(Some(k))
    }

    /// The error bars of every object and of the camera, in the map's units.
    ///
    /// # Errors
    /// As [`Fitted::meters_per_camera_height`]; [`MetrologyError::Degenerate`] when the
    /// covariance is singular.
    pub fn uncertainty(&self, scene: &Scene, options: &FitOptions) -> Result<FitUncertainty> {
        let problem = &self.problem;
        let x = &self.x;
        let measure = self.measure(scene)?;
        let cost: f64 = problem
            .residuals(x)
            .map_or(0.0, |r| r.iter().map(|v| v * v).sum());
        let (sigma, source) = click_sigma(options, cost, problem);
        let singular = || MetrologyError::Degenerate {
            field: "objects".to_owned(),
            reason: "the fit's covariance is singular: the clicks do not determine every size"
                .to_owned(),
        };
        let normal = problem.normal(x).ok_or_else(singular)?;
        let factored = normal.factor(0.0).map_err(|_| singular())?;
        let var = |a: &(DVector<f64>, Vec<DVector<f64>>), b: &(DVector<f64>, Vec<DVector<f64>>)| {
            sigma * sigma * quad(&factored, a, b)
        };
        let sd = |g: &(DVector<f64>, Vec<DVector<f64>>)| var(g, g).max(0.0).sqrt();
        let k_at = |x: &[f64]| measure.factor(problem, x);
        let mut objects = Vec::with_capacity(scene.objects.len());
        let mut relative = Vec::new();
        for (i, _) in scene.objects.iter().enumerate() {
            let part = self.object_parts[i];
            let mut parts = vec![part];
            parts.extend(measure.parts());
            let (u, rel) = object_error_bars(
                problem,
                x,
                &parts,
                &problem.parts[part],
                |xs: &[f64]| (problem.camera(xs), params(problem, xs, part)),
                k_at,
                |g: &[Gradient]| covariance(&factored, sigma, g),
            )
            .ok_or_else(singular)?;
            relative.extend(rel.into_iter().map(|(what, r)| (i, what, r)));
            objects.push(u);
        }
        let pp_fitted = problem.fixed_pp.is_none();
        let g = gradients(
            problem,
            x,
            &measure.parts(),
            |xs| {
                let cam = problem.camera(xs);
                [
                    xs[0],
                    xs[1],
                    xs[2],
                    k_at(xs),
                    cam.room_yaw_rad,
                    cam.principal_point_px.x,
                    cam.principal_point_px.y,
                ]
            },
            [false, false, false, false, true, false, false],
        );
        Ok(FitUncertainty {
            objects,
            camera: CameraUncertainty {
                focal_px_sd: sd(&g[0]),
                pitch_deg_sd: sd(&g[1]).to_degrees(),
                roll_deg_sd: sd(&g[2]).to_degrees(),
                height_sd: sd(&g[3]),
                principal_point_px_sd: pp_fitted.then(|| [sd(&g[5]), sd(&g[6])]),
                room_yaw_deg_sd: sd(&g[4]).to_degrees(),
                position_sd: None,
                heading_deg_sd: None,
            },
            click_sigma_px: sigma,
            click_sigma_source: source,
            relative_size_sd: relative,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_solve_over_the_touched_parts_equals_the_full_solve() {
        // A noisy synthetic scene's fit: every object's corner and value gradients, their
        // covariance by `covariance` (each gradient solved once, over the parts it touches)
        // against `quad` (the full solve of every pair).
        let (problem, x) = crate::fit::solve::tests::fitted();
        let (problem, x) = (&problem, &x);
        let f = problem.normal(x).unwrap().factor(0.0).unwrap();
        let sigma = 1.3;
        let mut checked = 0;
        let n = problem.part_count();
        for part in 0..n {
            // Its own part and another's (as a scale's parts join an object's).
            let touched = [part, (part + 1) % n];
            let mut g = gradients(
                problem,
                x,
                &touched,
                |xs| {
                    // Its values, the first scaled by the other part's (as a scale's factor
                    // enters an object's values in metres).
                    let mut v = part_values(
                        &problem.camera(xs),
                        &problem.parts[part],
                        params(problem, xs, part),
                    );
                    v[0] *= 1.0 + 0.1 * params(problem, xs, touched[1])[0];
                    v
                },
                [false, false, false, false, false, true],
            );
            g.extend(gradients_of(
                problem,
                x,
                &touched,
                |xs| {
                    part_corners(
                        &problem.camera(xs),
                        &problem.parts[part],
                        params(problem, xs, part),
                    )
                    .iter()
                    .flat_map(|p| [p.x, p.y])
                    .collect()
                },
                &vec![
                    false;
                    2 * part_corners(
                        &problem.camera(x),
                        &problem.parts[part],
                        params(problem, x, part)
                    )
                    .len()
                ],
            ));
            let m = covariance(&f, sigma, &g);
            for i in 0..g.len() {
                for j in 0..g.len() {
                    let full =
                        sigma * sigma * 0.5 * (quad(&f, &g[i], &g[j]) + quad(&f, &g[j], &g[i]));
                    let scale = (m[(i, i)] * m[(j, j)]).sqrt().max(1e-300);
                    assert!(
                        (m[(i, j)] - full).abs() <= 1e-9 * scale,
                        "part {part} ({i}, {j}): {} against {full}",
                        m[(i, j)]
                    );
                    checked += 1;
                }
            }
        }
        assert!(checked > 100, "{checked} entries");
    }
}

//! The room fit's error bars and scale: the covariance of the whole fit, `sigma^2 (J^T
//! J)^-1`, propagated to each object's centroid, sizes and yaw and to each camera's pose, by
//! the same first-order rule as for one photo ([`crate::fit`]); and the scale in metres from
//! every known length the photos give, combined by their inverse variances.

use nalgebra::{DVector, Vector2};

use super::align::corner_in_room;
use super::fit::RoomFitted;
use super::model::{Place, RoomProblem, Shape};
use crate::error::{MetrologyError, Result};
use crate::fit::model::{Camera, Part};
use crate::fit::solve::Model;
use crate::fit::uncertainty::{covariance, gradients, object_error_bars, quad};
use crate::fit::{FitOptions, click_sigma};
use crate::scene::{BoxView, Dimension, Scale, Scene};
use crate::uncertainty::{CameraUncertainty, ObjectUncertainty};

/// One photo's camera error bars in a room.
#[derive(Debug, Clone, PartialEq)]
pub struct PhotoUncertainty {
    /// Focal length, pitch, roll, height, principal point, room yaw, station point and
    /// heading.
    pub camera: CameraUncertainty,
}

/// The room fit's error bars in the map's units, and its scale.
#[derive(Debug, Clone, PartialEq)]
pub struct RoomUncertainty {
    /// Per room object, in [`RoomFitted::objects`] order.
    pub objects: Vec<ObjectUncertainty>,
    /// Per photo.
    pub photos: Vec<PhotoUncertainty>,
    /// Metres per first camera height (`None` without any scale).
    pub meters_per_unit: Option<f64>,
    /// The click noise used, pixels.
    pub click_sigma_px: f64,
    /// `"given"`, `"residuals"` or `"default"`.
    pub click_sigma_source: &'static str,
    /// `(object index, which, relative sd)` for the warnings.
    pub relative_size_sd: Vec<(usize, &'static str, f64)>,
    /// Scales that disagree beyond their error bars.
    pub warnings: Vec<String>,
}

/// What one known length measures in the room model.
#[derive(Debug, Clone)]
enum Measured {
    /// A photo's camera height.
    CameraHeight { photo: usize },
    /// Parameter `index` of part `part`.
    Param { part: usize, index: usize },
    /// The longer or shorter side of a box.
    Side { part: usize, longer: bool },
    /// The distance between two points of one part.
    Between { part: usize, a: Place, b: Place },
    /// The distance between two floor points.
    FloorDistance { a: usize, b: usize },
}

/// One photo's known length: what it measures, in metres, and how it reads.
#[derive(Debug, Clone)]
struct Known {
    what: Measured,
    meters: f64,
    words: String,
}

fn params<'a>(problem: &RoomProblem, x: &'a [f64], part: usize) -> &'a [f64] {
    problem.part_params(x, part)
}

impl Known {
    /// The measured value, first camera heights.
    fn value(&self, problem: &RoomProblem, x: &[f64]) -> f64 {
        match &self.what {
            Measured::CameraHeight { photo } => {
                problem.views(&x[..problem.camera_len])[*photo].height
            }
            Measured::Param { part, index } => params(problem, x, *part)[*index].abs(),
            Measured::Side { part, longer } => {
                let p = params(problem, x, *part);
                let (a, b) = (p[2].abs(), p[3].abs());
                if *longer { a.max(b) } else { a.min(b) }
            }
            Measured::Between { part, a, b } => {
                let room = problem.camera(x, 0);
                let p = params(problem, x, *part);
                let rp = &problem.parts[*part];
                (rp.point(&room, p, *a) - rp.point(&room, p, *b)).norm()
            }
            Measured::FloorDistance { a, b } => {
                let (p, q) = (params(problem, x, *a), params(problem, x, *b));
                (p[0] - q[0]).hypot(p[1] - q[1])
            }
        }
    }

    /// Metres per first camera height.
    fn factor(&self, problem: &RoomProblem, x: &[f64]) -> f64 {
        self.meters / self.value(problem, x)
    }

    fn parts(&self) -> Vec<usize> {
        match &self.what {
            Measured::CameraHeight { .. } => Vec::new(),
            Measured::Param { part, .. }
            | Measured::Side { part, .. }
            | Measured::Between { part, .. } => vec![*part],
            Measured::FloorDistance { a, b } => vec![*a, *b],
        }
    }
}

impl RoomProblem {
    /// Photo `k`'s own camera for the full vector or camera block `x`.
    fn camera_at(&self, x: &[f64], k: usize) -> Camera {
        self.camera(&x[..self.camera_len], k)
    }
}

impl RoomFitted {
    /// Every known length the photos give.
    fn known_lengths(&self, scene: &Scene) -> Result<Vec<Known>> {
        let mut out = Vec::new();
        for (k, photo) in scene.photos().enumerate() {
            let in_photo = |e| MetrologyError::InPhoto {
                photo: k,
                error: Box::new(e),
            };
            let Some(scale) = photo.scale().map_err(in_photo)? else {
                continue;
            };
            let part_of = |name: &str| -> Result<usize> {
                photo
                    .objects
                    .iter()
                    .position(|o| o.name == name)
                    .map(|i| self.object_of[k][i])
                    .ok_or_else(|| MetrologyError::UnknownScaleObject {
                        name: name.to_owned(),
                        known: String::new(),
                    })
            };
            let no_top = |name: &str| {
                in_photo(MetrologyError::InvalidField {
                    field: "scale".to_owned(),
                    reason: format!(
                        "measures a height, but object {name:?} has no top point in any photo"
                    ),
                })
            };
            let (what, meters, words) = match scale {
                Scale::CameraHeight(h) => (
                    Measured::CameraHeight { photo: k },
                    h,
                    format!("photo {}'s camera height {h} m", k + 1),
                ),
                Scale::FloorDistance(fd) => {
                    let [a, b] = self.floor_distance_parts[k].ok_or_else(|| {
                        in_photo(MetrologyError::InvalidField {
                            field: "scale.floor_distance".to_owned(),
                            reason: "was not part of the fit".to_owned(),
                        })
                    })?;
                    (
                        Measured::FloorDistance { a, b },
                        fd.meters,
                        format!("photo {}'s floor distance {} m", k + 1, fd.meters),
                    )
                }
                Scale::Edge { name, ends, meters } => {
                    let part = part_of(&name)?;
                    let index = photo
                        .objects
                        .iter()
                        .position(|o| o.name == name)
                        .unwrap_or(0);
                    let Shape::Box { axes: room, .. } = self.problem.parts[part].shape else {
                        return Err(no_top(&name));
                    };
                    let turned = self.photo_axes[k][index].unwrap_or(room);
                    let place = |e: &crate::scene::BoxPoint| {
                        let (i, j, t) = e.grid_index();
                        let (a, b) = corner_in_room(turned, room, i, j);
                        Place::Corner(a, b, t)
                    };
                    if ends.iter().any(|e| e.top)
                        && !matches!(
                            self.problem.parts[part].shape,
                            Shape::Box { has_top: true, .. }
                        )
                    {
                        return Err(no_top(&name));
                    }
                    (
                        Measured::Between {
                            part,
                            a: place(&ends[0]),
                            b: place(&ends[1]),
                        },
                        meters,
                        format!(
                            "photo {}'s edge {}-{} of {name:?}, {meters} m",
                            k + 1,
                            ends[0].name(),
                            ends[1].name()
                        ),
                    )
                }
                Scale::Object {
                    name,
                    dimension,
                    meters,
                } => {
                    let part = part_of(&name)?;
                    let what = match (self.problem.parts[part].shape, dimension) {
                        (Shape::Box { has_top: true, .. }, Dimension::Height) => {
                            Measured::Param { part, index: 4 }
                        }
                        (Shape::Footprint { n, has_top: true }, Dimension::Height) => {
                            Measured::Param { part, index: 2 * n }
                        }
                        (_, Dimension::Height) => return Err(no_top(&name)),
                        (Shape::Box { .. }, d) => Measured::Side {
                            part,
                            longer: d == Dimension::Length,
                        },
                        _ => {
                            return Err(in_photo(MetrologyError::InvalidField {
                                field: "scale.dimension".to_owned(),
                                reason: format!(
                                    "length and breadth are defined for boxes only; object {name:?} is a footprint (use \"height\" or a floor distance)"
                                ),
                            }));
                        }
                    };
                    (
                        what,
                        meters,
                        format!(
                            "photo {}'s {} of {name:?}, {meters} m",
                            k + 1,
                            format!("{dimension:?}").to_lowercase()
                        ),
                    )
                }
            };
            out.push(Known {
                what,
                meters,
                words,
            });
        }
        Ok(out)
    }

    /// The error bars of every object and camera, and the scale, in the map's units.
    ///
    /// # Errors
    /// A scale that measures something the fit does not have or measures zero; a singular
    /// covariance.
    pub fn uncertainty(&self, scene: &Scene, options: &FitOptions) -> Result<RoomUncertainty> {
        let problem = &self.problem;
        let x = &self.x;
        let cost: f64 = problem
            .residuals(x)
            .map_or(0.0, |r| r.iter().map(|v| v * v).sum());
        let (sigma, source) = click_sigma(options, cost, problem);
        let singular = || MetrologyError::Degenerate {
            field: "photos".to_owned(),
            reason: "the room fit's covariance is singular: the clicks do not determine every size"
                .to_owned(),
        };
        let normal = problem.normal(x).ok_or_else(singular)?;
        let factored = normal.factor(0.0).map_err(|_| singular())?;
        let var = |a: &(DVector<f64>, Vec<DVector<f64>>), b: &(DVector<f64>, Vec<DVector<f64>>)| {
            sigma * sigma * quad(&factored, a, b)
        };
        let sd = |g: &(DVector<f64>, Vec<DVector<f64>>)| var(g, g).max(0.0).sqrt();
        // The scale: every known length, combined by inverse variance.
        let known = self.known_lengths(scene)?;
        let mut warnings = Vec::new();
        let mut weights = Vec::with_capacity(known.len());
        let mut estimates = Vec::with_capacity(known.len());
        for kl in &known {
            let k = kl.factor(problem, x);
            if !(k.is_finite() && k > 0.0) {
                return Err(MetrologyError::Degenerate {
                    field: "scale".to_owned(),
                    reason: format!(
                        "{} measures {k} metres per camera height in the fit; it must be positive",
                        kl.words
                    ),
                });
            }
            let g = gradients(
                problem,
                x,
                &kl.parts(),
                |xs| [kl.factor(problem, xs)],
                [false],
            );
            let s = sd(&g[0]);
            estimates.push((k, s));
            weights.push(if s > 0.0 {
                1.0 / (s * s)
            } else {
                f64::INFINITY
            });
        }
        // Exact scales (a camera height, sd 0) win outright.
        let exact = weights.iter().filter(|w| w.is_infinite()).count();
        let total: f64 = weights.iter().filter(|w| w.is_finite()).sum();
        let weights: Vec<f64> = weights
            .iter()
            .map(|w| {
                if exact > 0 {
                    if w.is_infinite() {
                        1.0 / exact as f64
                    } else {
                        0.0
                    }
                } else {
                    w / total
                }
            })
            .collect();
        for a in 0..estimates.len() {
            for b in a + 1..estimates.len() {
                let ((ka, sa), (kb, sb)) = (estimates[a], estimates[b]);
                if (ka - kb).abs() > 1.96 * (sa * sa + sb * sb).sqrt() {
                    let used = match (sa == 0.0, sb == 0.0) {
                        (true, false) => format!("the map uses {}", known[a].words),
                        (false, true) => format!("the map uses {}", known[b].words),
                        _ => "the map uses their weighted mean".to_owned(),
                    };
                    warnings.push(format!(
                        "the known lengths disagree by more than their error bars: {} gives {ka:.4} +- {sa:.4} m per camera height, {} gives {kb:.4} +- {sb:.4}; {used}",
                        known[a].words, known[b].words
                    ));
                }
            }
        }
        let scale_parts: Vec<usize> = known.iter().flat_map(Known::parts).collect();
        let k_at = |xs: &[f64]| -> f64 {
            if known.is_empty() {
                1.0
            } else {
                known
                    .iter()
                    .zip(&weights)
                    .map(|(kl, w)| w * kl.factor(problem, xs))
                    .sum()
            }
        };
        let k = k_at(x);
        let mut objects = Vec::with_capacity(self.objects.len());
        let mut relative = Vec::new();
        for (i, _) in self.objects.iter().enumerate() {
            let part = i;
            let mut parts = vec![part];
            parts.extend(scale_parts.iter().copied());
            let shape = as_part(problem.parts[part].shape);
            let (u, rel) = object_error_bars(
                problem,
                x,
                &parts,
                &shape,
                |xs: &[f64]| (problem.camera_at(xs, 0), params(problem, xs, part)),
                k_at,
                |g: &[crate::fit::uncertainty::Gradient]| covariance(&factored, sigma, g),
            )
            .ok_or_else(singular)?;
            relative.extend(rel.into_iter().map(|(what, r)| (i, what, r)));
            objects.push(u);
        }
        let mut photos = Vec::with_capacity(problem.photos.len());
        for (photo, block) in problem.photos.iter().enumerate() {
            let g = gradients(
                problem,
                x,
                &scale_parts,
                |xs| {
                    let c = &xs[..problem.camera_len];
                    let view = problem.views(c)[photo];
                    let k = k_at(xs);
                    [
                        view.cam.focal_px,
                        view.cam.pitch_rad,
                        xs[block.offset + 2],
                        view.height * k,
                        view.cam.room_yaw_rad,
                        view.cam.principal_point_px.x,
                        view.cam.principal_point_px.y,
                        view.position.x * k,
                        view.position.y * k,
                        view.heading_rad,
                    ]
                },
                [
                    false, false, false, false, true, false, false, false, false, true,
                ],
            );
            let posed = block.posed;
            photos.push(PhotoUncertainty {
                camera: CameraUncertainty {
                    focal_px_sd: sd(&g[0]),
                    pitch_deg_sd: sd(&g[1]).to_degrees(),
                    roll_deg_sd: sd(&g[2]).to_degrees(),
                    height_sd: sd(&g[3]),
                    principal_point_px_sd: block.fixed_pp.is_none().then(|| [sd(&g[5]), sd(&g[6])]),
                    room_yaw_deg_sd: sd(&g[4]).to_degrees(),
                    position_sd: posed.then(|| [sd(&g[7]), sd(&g[8])]),
                    heading_deg_sd: posed.then(|| sd(&g[9]).to_degrees()),
                },
            });
        }
        Ok(RoomUncertainty {
            objects,
            photos,
            meters_per_unit: (!known.is_empty()).then_some(k),
            click_sigma_px: sigma,
            click_sigma_source: source,
            relative_size_sd: relative,
            warnings,
        })
    }
}

/// A room shape as a one-photo part of the same parameter layout, for
/// [`crate::fit::uncertainty::part_values`].
fn as_part(shape: Shape) -> Part {
    match shape {
        Shape::Box {
            axes,
            has_top,
            own_yaw,
        } => Part::Box {
            view: BoxView::Corner,
            clicks: Vec::new(),
            axes,
            has_top,
            own_yaw,
        },
        Shape::Footprint { n, has_top } => Part::Footprint {
            vertices: vec![Vector2::zeros(); n],
            top: has_top.then(|| (0, Vector2::zeros())),
        },
        Shape::Point => Part::FloorPoint {
            pixel: Vector2::zeros(),
        },
    }
}

//! Reading a scene file and validating it: the limits on its numbers and sizes, each object's
//! shape, the scale's form, and the fields vpmap does not read.

use super::types::{
    BoxCorner, BoxCorners, BoxPoint, ObjectShape, ObjectSpec, Perspective, PixelPoint, Scale,
    Scene, TopSpec,
};
use crate::error::{MetrologyError, Result};

/// Largest magnitude of an annotated image coordinate, pixels: points are clicked in (or near)
/// the photo.
pub const MAX_POINT_PX: f64 = 1e7;
/// Largest magnitude of a vanishing point's coordinate, pixels (nearly parallel edges put it
/// far away; beyond this it is at infinity for any real camera).
pub const MAX_VANISHING_POINT_PX: f64 = 1e12;
/// Smallest side of a scene's `image`, pixels (as `vpmap detect` reads photos): a smaller
/// one is no photo's size, and the fit would measure every click against it.
pub const MIN_IMAGE_SIDE_PX: u32 = 16;
/// Largest known length in a `scale`, metres.
pub const MAX_SCALE_M: f64 = 1e6;
/// Largest variance of a click covariance, px^2 (a 1000 px standard deviation).
pub const MAX_CLICK_VARIANCE_PX2: f64 = 1e6;
/// Smallest variance of a click covariance, px^2 (a 1e-6 px standard deviation: no click is
/// surer; a smaller one would outweigh every other click of the fit).
pub const MIN_CLICK_VARIANCE_PX2: f64 = 1e-12;
/// Largest condition number of a click covariance (its larger eigenvalue over its smaller):
/// beyond it the click is sure along one line only and its weight matrix is numerically
/// singular.
pub const MAX_CLICK_COVARIANCE_CONDITION: f64 = 1e12;

/// A number in a message: plain when it reads well, else in four significant digits of
/// exponent form (`1.000e300`, not 301 digits).
fn compact(v: f64) -> String {
    if v == 0.0 || !v.is_finite() || (1e-4..1e7).contains(&v.abs()) {
        format!("{v}")
    } else {
        format!("{v:.3e}")
    }
}

fn check_coords(field: &str, p: &[f64], limit: f64) -> Result<()> {
    for (i, v) in p.iter().enumerate() {
        if !v.is_finite() {
            return Err(MetrologyError::NonFinite {
                field: format!("{field}[{i}]"),
                value: *v,
            });
        }
        if v.abs() > limit {
            return Err(MetrologyError::InvalidField {
                field: format!("{field}[{i}]"),
                reason: format!("{v:e} px is outside the supported range of +-{limit:e} px"),
            });
        }
    }
    Ok(())
}

/// A direction: finite and not zero.
fn check_direction(field: &str, d: PixelPoint) -> Result<()> {
    check_coords(field, &d, MAX_VANISHING_POINT_PX)?;
    if d[0] == 0.0 && d[1] == 0.0 {
        return Err(MetrologyError::InvalidField {
            field: field.to_owned(),
            reason: format!(
                "is the zero vector ({}, {}): give the direction the edges run along",
                d[0], d[1]
            ),
        });
    }
    Ok(())
}

fn check_point(field: &str, p: PixelPoint) -> Result<()> {
    check_coords(field, &p, MAX_POINT_PX)
}

fn check_positive(field: &str, v: f64) -> Result<()> {
    if !v.is_finite() {
        return Err(MetrologyError::NonFinite {
            field: field.to_owned(),
            value: v,
        });
    }
    if v <= 0.0 {
        return Err(MetrologyError::InvalidField {
            field: field.to_owned(),
            reason: format!("must be positive, got {v}"),
        });
    }
    Ok(())
}

fn check_length_m(field: &str, v: f64) -> Result<()> {
    check_positive(field, v)?;
    if v > MAX_SCALE_M {
        return Err(MetrologyError::InvalidField {
            field: field.to_owned(),
            reason: format!("{v:e} m is beyond the supported {MAX_SCALE_M:e} m"),
        });
    }
    Ok(())
}

/// The box's corners checked: one naming scheme, at least one base corner, and corners at
/// both ends of each floor axis (else the box's extent along it is not fixed).
fn box_shape<'a>(
    field: &str,
    name: &str,
    base: &'a BoxCorners,
    top: TopSpec,
    own_yaw: bool,
) -> Result<ObjectShape<'a>> {
    if top.above.is_some() || top.point.is_some() {
        return Err(MetrologyError::InvalidField {
            field: format!("{field}.top"),
            reason: format!(
                "object {name:?} is a box (it has `base`): give top corners by name (e.g. `top.near`), not `above`/`point`"
            ),
        });
    }
    let given: Vec<(bool, BoxCorner)> = base
        .given()
        .map(|(c, _)| (false, c))
        .chain(top.corners.given().map(|(c, _)| (true, c)))
        .collect();
    let Some(&(_, first)) = given.first() else {
        return Err(MetrologyError::InvalidField {
            field: format!("{field}.base"),
            reason: format!(
                "object {name:?} gives no corners: click the base corners you can see (e.g. `base.near`, `base.right`, `base.left`)"
            ),
        });
    };
    let view = first.view();
    if let Some(&(on_top, other)) = given.iter().find(|(_, c)| c.view() != view) {
        return Err(MetrologyError::InvalidField {
            field: format!(
                "{field}.{}.{}",
                if on_top { "top" } else { "base" },
                other.name()
            ),
            reason: format!(
                "object {name:?} mixes the corner view (near, right, left, far) with the face view (front_left, front_right, back_left, back_right): `{}` and `{}`; name every corner of one box in one view",
                first.name(),
                other.name()
            ),
        });
    }
    if base.given().next().is_none() {
        let (_, c) = given[0];
        return Err(MetrologyError::InvalidField {
            field: format!("{field}.base"),
            reason: format!(
                "object {name:?} gives only top corners, which do not fix how tall it is: add at least one base corner (e.g. `base.{}`, below `top.{}`)",
                c.name(),
                c.name()
            ),
        });
    }
    for axis in 0..2 {
        let ends = |v: u8| {
            given.iter().any(|(_, c)| {
                let (i, j) = c.grid_index();
                (if axis == 0 { i } else { j }) == v
            })
        };
        if !(ends(0) && ends(1)) {
            // Suggest the corner beside the first given one across this axis.
            let (i, j) = first.grid_index();
            let (ai, aj) = if axis == 0 { (1 - i, j) } else { (i, 1 - j) };
            let add = BoxCorner::at(view, ai, aj);
            return Err(MetrologyError::InvalidField {
                field: format!("{field}.base"),
                reason: format!(
                    "the corners of object {name:?} ({}) do not fix its extent from `{}` towards `{}`: add `base.{}` (or `top.{}`)",
                    given
                        .iter()
                        .map(|(t, c)| format!("{}.{}", if *t { "top" } else { "base" }, c.name()))
                        .collect::<Vec<_>>()
                        .join(", "),
                    first.name(),
                    add.name(),
                    add.name(),
                    add.name()
                ),
            });
        }
    }
    Ok(ObjectShape::Box {
        view,
        base,
        top: top.corners,
        own_yaw,
    })
}

impl ObjectSpec {
    /// The object's shape, or an error naming what is missing.
    ///
    /// # Errors
    /// When the object has neither or both of `base` and `footprint`, or a top annotation
    /// that does not fit its kind. `index` is used in the error's field path.
    pub fn shape(&self, index: usize) -> Result<ObjectShape<'_>> {
        let field = format!("objects[{index}]");
        let top = self.top.unwrap_or_default();
        match (&self.base, &self.footprint) {
            (Some(base), None) => box_shape(&field, &self.name, base, top, self.own_yaw),
            (None, Some(polygon)) => {
                if polygon.len() < 3 {
                    return Err(MetrologyError::InvalidField {
                        field: format!("{field}.footprint"),
                        reason: format!(
                            "needs at least 3 vertices, got {} (object {:?})",
                            polygon.len(),
                            self.name
                        ),
                    });
                }
                if let Some((c, _)) = top.corners.given().next() {
                    return Err(MetrologyError::InvalidField {
                        field: format!("{field}.top.{}", c.name()),
                        reason: format!(
                            "object {:?} has a `footprint`: give `top.above` and `top.point`, not box corners",
                            self.name
                        ),
                    });
                }
                if self.own_yaw {
                    return Err(MetrologyError::InvalidField {
                        field: format!("{field}.own_yaw"),
                        reason: format!(
                            "object {:?} has a `footprint`, whose vertices are free: `own_yaw` is for boxes",
                            self.name
                        ),
                    });
                }
                let top = match (top.above, top.point) {
                    (Some(i), Some(p)) => {
                        if i >= polygon.len() {
                            return Err(MetrologyError::InvalidField {
                                field: format!("{field}.top.above"),
                                reason: format!(
                                    "is {i}, but the footprint has only {} vertices (indices 0..={})",
                                    polygon.len(),
                                    polygon.len() - 1
                                ),
                            });
                        }
                        Some((i, p))
                    }
                    (None, None) => None,
                    _ => {
                        return Err(MetrologyError::InvalidField {
                            field: format!("{field}.top"),
                            reason: "give both `above` and `point`".to_owned(),
                        });
                    }
                };
                Ok(ObjectShape::Footprint { polygon, top })
            }
            (Some(_), Some(_)) => Err(MetrologyError::InvalidField {
                field: field.clone(),
                reason: format!(
                    "object {:?} has both `base` and `footprint`; give one",
                    self.name
                ),
            }),
            (None, None) => Err(MetrologyError::InvalidField {
                field,
                reason: format!(
                    "object {:?} has neither `base` (a box) nor `footprint`",
                    self.name
                ),
            }),
        }
    }
}

/// Smallest standard deviation a vanishing point's covariance may give, degrees.
pub const MIN_VP_SD_DEG: f64 = 1e-6;

/// Largest standard deviation a vanishing point's covariance may give, degrees.
pub const MAX_VP_SD_DEG: f64 = 90.0;

/// A vanishing point's covariance: finite, symmetric, positive definite, each standard
/// deviation (of the principal axes) within [`MIN_VP_SD_DEG`]..[`MAX_VP_SD_DEG`].
fn check_covariance_deg2(field: &str, m: [[f64; 2]; 2]) -> Result<()> {
    for (r, row) in m.iter().enumerate() {
        for (c, v) in row.iter().enumerate() {
            if !v.is_finite() {
                return Err(MetrologyError::NonFinite {
                    field: format!("{field}[{r}][{c}]"),
                    value: *v,
                });
            }
        }
    }
    let [[a, b], [b2, d]] = m;
    let shown = format!("[[{a:.4e}, {b:.4e}], [{b2:.4e}, {d:.4e}]] deg^2");
    if (b - b2).abs() > 1e-9 * a.abs().max(d.abs()).max(f64::MIN_POSITIVE) {
        return Err(MetrologyError::InvalidField {
            field: field.to_owned(),
            reason: format!("is not symmetric: {shown}"),
        });
    }
    // Principal variances of the symmetric matrix.
    let large = 0.5 * (a + d) + (0.25 * (a - d) * (a - d) + b * b).sqrt();
    // The smaller one from the determinant: `mean - spread` cancels to 0 for very unequal ones.
    let small = (a * d - b * b) / large;
    if !(small > 0.0 && a > 0.0 && d > 0.0) {
        return Err(MetrologyError::InvalidField {
            field: field.to_owned(),
            reason: format!("is not positive definite: {shown}"),
        });
    }
    if small.sqrt() < MIN_VP_SD_DEG || large.sqrt() > MAX_VP_SD_DEG {
        return Err(MetrologyError::InvalidField {
            field: field.to_owned(),
            reason: format!(
                "gives standard deviations of {:.4e} to {:.4e} degrees; they must lie within {MIN_VP_SD_DEG:e} to {MAX_VP_SD_DEG} degrees",
                small.sqrt(),
                large.sqrt()
            ),
        });
    }
    Ok(())
}

/// Most objects a scene may have (the same on the command line and the page).
pub const MAX_OBJECTS: usize = 500;

/// Most points a floor outline or footprint, and most segments a vanishing point, may have.
pub const MAX_POINTS: usize = 1000;

impl Scene {
    /// Refuse a scene with more than [`MAX_OBJECTS`] objects or a list longer than
    /// [`MAX_POINTS`]: the fit's work grows with them, and no photo needs more.
    fn check_sizes(&self) -> Result<()> {
        let too_many = |field: String, n: usize, max: usize| MetrologyError::InvalidField {
            field,
            reason: format!("it has {n} entries; a scene may have at most {max}"),
        };
        if self.objects.len() > MAX_OBJECTS {
            return Err(too_many(
                "objects".to_owned(),
                self.objects.len(),
                MAX_OBJECTS,
            ));
        }
        if self.floor.len() > MAX_POINTS {
            return Err(too_many("floor".to_owned(), self.floor.len(), MAX_POINTS));
        }
        for (i, o) in self.objects.iter().enumerate() {
            if let Some(fp) = &o.footprint
                && fp.len() > MAX_POINTS
            {
                return Err(too_many(
                    format!("objects[{i}].footprint"),
                    fp.len(),
                    MAX_POINTS,
                ));
            }
        }
        for (i, v) in self.vanishing_points.iter().enumerate() {
            if v.lines.len() > MAX_POINTS {
                return Err(too_many(
                    format!("vanishing_points[{i}].lines"),
                    v.lines.len(),
                    MAX_POINTS,
                ));
            }
        }
        Ok(())
    }

    /// Parse and validate a scene from JSON text.
    ///
    /// # Errors
    /// [`MetrologyError::Json`] for malformed JSON or missing fields (with line and column),
    /// and any error of [`Scene::validate`].
    ///
    /// A room file (`{"version": 1, "photos": [SCENE, ...]}`, [`Scene::other_photos`]) is
    /// read into its first photo with the others beside it; an error in one photo is
    /// [`MetrologyError::InPhoto`].
    pub fn from_json_str(text: &str) -> Result<Self> {
        let json = |e: serde_json::Error| MetrologyError::Json(e.to_string());
        let value: serde_json::Value = serde_json::from_str(text).map_err(json)?;
        let scene = if super::room::is_room_value(&value) {
            // Parsed again from the text, so that errors keep their line and column.
            let room: super::room::RoomFile = serde_json::from_str(text).map_err(json)?;
            room.into_scene()?
        } else {
            serde_json::from_str(text).map_err(json)?
        };
        scene.validate()?;
        Ok(scene)
    }

    /// The scene as pretty-printed JSON: a room file when it has other photos.
    #[must_use]
    pub fn to_json_string(&self) -> String {
        if self.other_photos.is_empty() {
            serde_json::to_string_pretty(self).unwrap_or_default()
        } else {
            serde_json::to_string_pretty(&self.room_file()).unwrap_or_default()
        }
    }

    /// Check everything that does not need the camera: version, finiteness, object shapes,
    /// unique names, the scale's form; for a room, each photo (an error names it,
    /// [`MetrologyError::InPhoto`]) and what ties the photos into one room.
    ///
    /// # Errors
    /// The first problem found, naming the field and the value.
    pub fn validate(&self) -> Result<()> {
        if self.other_photos.is_empty() {
            self.validate_photo()?;
            return self.validate_placement_pins();
        }
        for (k, p) in self.photos().enumerate() {
            p.validate_photo()
                .map_err(|error| MetrologyError::InPhoto {
                    photo: k,
                    error: Box::new(error),
                })?;
        }
        self.validate_room()
    }

    /// [`Scene::validate`] for one photo.
    fn validate_photo(&self) -> Result<()> {
        if self.version != 1 {
            return Err(MetrologyError::UnsupportedVersion {
                file: "scene",
                version: self.version,
            });
        }
        if self.image.width == 0 || self.image.height == 0 {
            return Err(MetrologyError::InvalidField {
                field: "image".to_owned(),
                reason: format!(
                    "size must be positive, got {}x{}",
                    self.image.width, self.image.height
                ),
            });
        }
        if self.image.width.min(self.image.height) < MIN_IMAGE_SIDE_PX {
            return Err(MetrologyError::InvalidField {
                field: "image".to_owned(),
                reason: format!(
                    "is {} x {} pixels; a photo is at least {MIN_IMAGE_SIDE_PX} pixels a side: give the photo's width and height",
                    self.image.width, self.image.height
                ),
            });
        }
        let n = self.vanishing_points.len();
        if !(2..=3).contains(&n) {
            return Err(MetrologyError::VanishingPointCount(n));
        }
        self.check_sizes()?;
        if let Some(p) = self.perspective {
            let expected = match p {
                Perspective::TwoPoint => 2,
                Perspective::ThreePoint => 3,
            };
            if expected != n {
                return Err(MetrologyError::InvalidField {
                    field: "perspective".to_owned(),
                    reason: format!(
                        "is \"{}\", but the scene gives {n} vanishing points; give {expected}, or leave `perspective` out (the number of vanishing points decides)",
                        p.name()
                    ),
                });
            }
        }
        let directions = self
            .vanishing_points
            .iter()
            .filter(|v| v.direction.is_some())
            .count();
        for (i, vp) in self.vanishing_points.iter().enumerate() {
            let field = format!("vanishing_points[{i}]");
            if let Some(d) = vp.direction {
                check_direction(&format!("{field}.direction"), d)?;
                if vp.point.is_some() {
                    return Err(MetrologyError::InvalidField {
                        field,
                        reason: "give `point` or `direction`, not both".to_owned(),
                    });
                }
                if !vp.lines.is_empty() {
                    return Err(MetrologyError::InvalidField {
                        field,
                        reason: format!(
                            "give `direction` or `lines`, not both (the fit would follow the {} lines and ignore the direction)",
                            vp.lines.len()
                        ),
                    });
                }
                if n != 3 || directions > 1 {
                    return Err(MetrologyError::InvalidField {
                        field: format!("{field}.direction"),
                        reason: format!(
                            "a vanishing point at infinity is supported as one of three (the vertical one of a level camera); this scene gives {n} vanishing points, {directions} of them as directions"
                        ),
                    });
                }
            } else if let Some(p) = vp.point {
                check_coords(&format!("{field}.point"), &p, MAX_VANISHING_POINT_PX)?;
            } else if vp.lines.len() < 2 {
                return Err(MetrologyError::InvalidField {
                    field,
                    reason: format!(
                        "give `point`, `direction` or at least 2 `lines` (got {} lines)",
                        vp.lines.len()
                    ),
                });
            }
            for (j, l) in vp.lines.iter().enumerate() {
                check_coords(&format!("{field}.lines[{j}]"), l, MAX_POINT_PX)?;
                if (l[0] - l[2]).hypot(l[1] - l[3]) < 1e-9 {
                    return Err(MetrologyError::InvalidField {
                        field: format!("{field}.lines[{j}]"),
                        reason: format!(
                            "segment has zero length: both ends at ({}, {})",
                            l[0], l[1]
                        ),
                    });
                }
            }
            if vp.point.is_none()
                && vp.direction.is_none()
                && super::vanishing::intersect_segments(&vp.lines, self.image)
                    == Err(super::vanishing::SegmentFit::Collinear)
            {
                return Err(MetrologyError::InvalidField {
                    field: format!("{field}.lines"),
                    reason: "the segments lie on one line, so they do not fix a point: click edges on different lines that run to the vanishing point".to_owned(),
                });
            }
        }
        if let Some(p) = self.principal_point {
            check_point("principal_point", p)?;
        }
        if let Some(f) = self.focal_px {
            check_positive("focal_px", f)?;
        }
        self.check_camera_uncertainty()?;
        let mut names = std::collections::BTreeSet::new();
        for (i, obj) in self.objects.iter().enumerate() {
            if obj.name.trim().is_empty() {
                return Err(MetrologyError::InvalidField {
                    field: format!("objects[{i}].name"),
                    reason: "is empty".to_owned(),
                });
            }
            if !names.insert(obj.name.as_str()) {
                return Err(MetrologyError::InvalidField {
                    field: format!("objects[{i}].name"),
                    reason: format!("{:?} is used by an earlier object", obj.name),
                });
            }
            let field = format!("objects[{i}]");
            match obj.shape(i)? {
                ObjectShape::Box { base, top, .. } => {
                    for (c, p) in base.given() {
                        check_point(&format!("{field}.base.{}", c.name()), p)?;
                    }
                    for (c, p) in top.given() {
                        check_point(&format!("{field}.top.{}", c.name()), p)?;
                    }
                }
                ObjectShape::Footprint { polygon, top } => {
                    for (j, p) in polygon.iter().enumerate() {
                        check_point(&format!("{field}.footprint[{j}]"), *p)?;
                    }
                    if let Some((_, p)) = top {
                        check_point(&format!("{field}.top.point"), p)?;
                    }
                }
            }
        }
        if !self.floor.is_empty() && self.floor.len() < 3 {
            return Err(MetrologyError::InvalidField {
                field: "floor".to_owned(),
                reason: format!(
                    "needs at least 3 corners for an outline (or none), got {}",
                    self.floor.len()
                ),
            });
        }
        for (i, p) in self.floor.iter().enumerate() {
            check_point(&format!("floor[{i}]"), *p)?;
        }
        self.scale()?;
        self.check_click_covariances()?;
        self.check_lens_distortion()?;
        Ok(())
    }

    /// The vanishing points' covariances and the intrinsics' standard deviations: finite,
    /// positive (definite) and in the range [`MIN_VP_SD_DEG`]..[`MAX_VP_SD_DEG`] (vanishing
    /// points), at most the image diagonal (principal point) or the focal length itself
    /// (focal length); a vanishing point's covariance needs its `point` or `direction`, and
    /// `focal_sd_px` needs `focal_px`.
    fn check_camera_uncertainty(&self) -> Result<()> {
        for (i, vp) in self.vanishing_points.iter().enumerate() {
            let Some(m) = vp.covariance_deg2 else {
                continue;
            };
            let field = format!("vanishing_points[{i}].covariance_deg2");
            if vp.point.is_none() && vp.direction.is_none() {
                return Err(MetrologyError::InvalidField {
                    field,
                    reason: "belongs to a `point` or `direction`; this vanishing point gives only `lines` (their own spread is their uncertainty)".to_owned(),
                });
            }
            check_covariance_deg2(&field, m)?;
        }
        let diagonal = self.image.diagonal();
        if let Some(sd) = self.principal_point_sd_px {
            check_positive("principal_point_sd_px", sd)?;
            if sd > diagonal {
                return Err(MetrologyError::InvalidField {
                    field: "principal_point_sd_px".to_owned(),
                    reason: format!(
                        "{sd:.4e} px is more than the image diagonal ({diagonal:.1} px): leave it out to let the vanishing points alone place the principal point"
                    ),
                });
            }
        }
        if let Some(sd) = self.focal_sd_px {
            check_positive("focal_sd_px", sd)?;
            let Some(f) = self.focal_px else {
                return Err(MetrologyError::InvalidField {
                    field: "focal_sd_px".to_owned(),
                    reason: "is the uncertainty of `focal_px`, which the scene does not give"
                        .to_owned(),
                });
            };
            if sd > f {
                return Err(MetrologyError::InvalidField {
                    field: "focal_sd_px".to_owned(),
                    reason: format!(
                        "{sd:.4e} px is more than the focal length itself ({f} px): leave it out for a focal length the fit finds alone"
                    ),
                });
            }
        }
        Ok(())
    }

    /// Each click covariance names a click of the scene and is a finite, symmetric, positive
    /// definite matrix with variances from [`MIN_CLICK_VARIANCE_PX2`] to
    /// [`MAX_CLICK_VARIANCE_PX2`] and a condition number of at most
    /// [`MAX_CLICK_COVARIANCE_CONDITION`].
    fn check_click_covariances(&self) -> Result<()> {
        if self.click_covariances_px2.is_empty() {
            return Ok(());
        }
        let known = self.clicks_by_field();
        for (key, m) in &self.click_covariances_px2 {
            let field = format!("click_covariances_px2.\"{key}\"");
            if !known.contains_key(key) {
                return Err(MetrologyError::InvalidField {
                    field,
                    reason: "names no click of this scene (expected a field path such as `objects[0].base.near` or `floor[2]`)".to_owned(),
                });
            }
            for (r, row) in m.iter().enumerate() {
                for (c, v) in row.iter().enumerate() {
                    if !v.is_finite() {
                        return Err(MetrologyError::NonFinite {
                            field: format!("{field}[{r}][{c}]"),
                            value: *v,
                        });
                    }
                }
            }
            let [[a, b], [b2, d]] = *m;
            let matrix = || {
                format!(
                    "[[{}, {}], [{}, {}]] px^2",
                    compact(a),
                    compact(b),
                    compact(b2),
                    compact(d)
                )
            };
            for (axis, v) in [("x", a), ("y", d)] {
                if v > MAX_CLICK_VARIANCE_PX2 {
                    return Err(MetrologyError::InvalidField {
                        field,
                        reason: format!(
                            "its {axis} variance {} px^2 is beyond the supported {} px^2 (a {} px standard deviation; a click that uncertain tells nothing)",
                            compact(v),
                            compact(MAX_CLICK_VARIANCE_PX2),
                            compact(MAX_CLICK_VARIANCE_PX2.sqrt())
                        ),
                    });
                }
                if v < MIN_CLICK_VARIANCE_PX2 {
                    return Err(MetrologyError::InvalidField {
                        field,
                        reason: if v > 0.0 {
                            format!(
                                "its {axis} variance {} px^2 is below the supported {} px^2 (a {} px standard deviation; no click is that sure)",
                                compact(v),
                                compact(MIN_CLICK_VARIANCE_PX2),
                                compact(MIN_CLICK_VARIANCE_PX2.sqrt())
                            )
                        } else {
                            format!(
                                "its {axis} variance {} px^2 is not positive: {}",
                                compact(v),
                                matrix()
                            )
                        },
                    });
                }
            }
            // Both variances lie in [1e-12, 1e6]: nothing below over- or underflows.
            if (b - b2).abs() > 1e-9 * a.max(d) {
                return Err(MetrologyError::InvalidField {
                    field,
                    reason: format!("is not symmetric: {}", matrix()),
                });
            }
            // The eigenvalues of the symmetric matrix: the larger directly, the smaller as the
            // determinant over it (no cancellation).
            let largest = 0.5 * (a + d) + (0.5 * (a - d)).hypot(b);
            let determinant = a * d - b * b;
            let smallest = determinant / largest;
            if determinant <= 0.0 || smallest <= 0.0 {
                return Err(MetrologyError::InvalidField {
                    field,
                    reason: format!(
                        "is not positive definite: {} (the covariance |sxy| must be below sqrt(sxx syy))",
                        matrix()
                    ),
                });
            }
            if largest > MAX_CLICK_COVARIANCE_CONDITION * smallest {
                return Err(MetrologyError::InvalidField {
                    field,
                    reason: format!(
                        "is nearly singular: {} has condition number {} (at most {}): the click would be sure along one line only",
                        matrix(),
                        compact(largest / smallest),
                        compact(MAX_CLICK_COVARIANCE_CONDITION)
                    ),
                });
            }
        }
        Ok(())
    }

    /// The validated scale, if any.
    ///
    /// # Errors
    /// When the `scale` object gives none or more than one form, or a non-positive length, or
    /// names an object that does not exist.
    pub fn scale(&self) -> Result<Option<Scale>> {
        let Some(s) = &self.scale else {
            return Ok(None);
        };
        let forms = usize::from(s.camera_height_m.is_some())
            + usize::from(s.object.is_some())
            + usize::from(s.floor_distance.is_some());
        if forms != 1 {
            return Err(MetrologyError::InvalidField {
                field: "scale".to_owned(),
                reason: format!(
                    "give exactly one of `camera_height_m`, `object` (with `dimension` and `meters`) or `floor_distance`; got {forms}"
                ),
            });
        }
        if let Some(h) = s.camera_height_m {
            check_length_m("scale.camera_height_m", h)?;
            return Ok(Some(Scale::CameraHeight(h)));
        }
        if let Some(fd) = s.floor_distance {
            check_point("scale.floor_distance.from", fd.from)?;
            check_point("scale.floor_distance.to", fd.to)?;
            check_length_m("scale.floor_distance.meters", fd.meters)?;
            return Ok(Some(Scale::FloorDistance(fd)));
        }
        let name = s.object.clone().unwrap_or_default();
        let Some(index) = self.objects.iter().position(|o| o.name == name) else {
            return Err(MetrologyError::UnknownScaleObject {
                name,
                known: self
                    .objects
                    .iter()
                    .map(|o| o.name.as_str())
                    .collect::<Vec<_>>()
                    .join(", "),
            });
        };
        if let Some(edge) = &s.edge {
            if s.dimension.is_some() {
                return Err(MetrologyError::InvalidField {
                    field: "scale".to_owned(),
                    reason: "give `edge` or `dimension`, not both".to_owned(),
                });
            }
            let Some(meters) = s.meters else {
                return Err(MetrologyError::InvalidField {
                    field: "scale.meters".to_owned(),
                    reason: "missing: the known length in metres".to_owned(),
                });
            };
            check_length_m("scale.meters", meters)?;
            let mut ends = [BoxPoint {
                corner: BoxCorner::Near,
                top: false,
            }; 2];
            for (k, text) in edge.iter().enumerate() {
                ends[k] = BoxPoint::parse(text).ok_or_else(|| MetrologyError::InvalidField {
                    field: format!("scale.edge[{k}]"),
                    reason: format!(
                        "{text:?} is not a box corner: write `base.` or `top.` and a corner name (near, right, left, far, front_left, front_right, back_left, back_right)"
                    ),
                })?;
            }
            let view = match self.objects[index].shape(index)? {
                ObjectShape::Box { view, .. } => view,
                ObjectShape::Footprint { .. } => {
                    return Err(MetrologyError::InvalidField {
                        field: "scale.edge".to_owned(),
                        reason: format!(
                            "object {name:?} is a footprint, not a box: use `dimension: \"height\"` or `floor_distance`"
                        ),
                    });
                }
            };
            if let Some(p) = ends.iter().find(|p| p.corner.view() != view) {
                return Err(MetrologyError::InvalidField {
                    field: "scale.edge".to_owned(),
                    reason: format!(
                        "`{}` is named in the other view than object {name:?}'s corners",
                        p.name()
                    ),
                });
            }
            let (a, b) = (ends[0].grid_index(), ends[1].grid_index());
            let differ =
                usize::from(a.0 != b.0) + usize::from(a.1 != b.1) + usize::from(a.2 != b.2);
            if differ != 1 {
                return Err(MetrologyError::InvalidField {
                    field: "scale.edge".to_owned(),
                    reason: format!(
                        "`{}` and `{}` are not the two ends of one edge of the box",
                        ends[0].name(),
                        ends[1].name()
                    ),
                });
            }
            return Ok(Some(Scale::Edge { name, ends, meters }));
        }
        let Some(dimension) = s.dimension else {
            return Err(MetrologyError::InvalidField {
                field: "scale.dimension".to_owned(),
                reason: "missing: give `edge` (e.g. [\"base.near\", \"base.right\"]) or `dimension` (\"length\", \"breadth\" or \"height\")".to_owned(),
            });
        };
        let Some(meters) = s.meters else {
            return Err(MetrologyError::InvalidField {
                field: "scale.meters".to_owned(),
                reason: "missing: the known length in metres".to_owned(),
            });
        };
        check_length_m("scale.meters", meters)?;
        Ok(Some(Scale::Object {
            name,
            dimension,
            meters,
        }))
    }
}

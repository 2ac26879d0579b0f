//! The scene file: what a user annotates on one photo (format version 1).
//!
//! Pixel coordinates, origin at the image's top-left corner, x right, y down.
//! The format is documented for users in `docs/scene-format.md`; this module is its
//! reference implementation. [`Scene::from_json_str`] parses and validates in one step,
//! so every later stage can rely on finite numbers and well-formed objects.

use nalgebra::{Matrix3, Vector2, Vector3};
use serde::{Deserialize, Serialize};

use crate::error::{MetrologyError, Result};

/// A pixel position `[x, y]`.
pub type PixelPoint = [f64; 2];

/// Image size in pixels.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ImageSize {
    /// Width, pixels.
    pub width: u32,
    /// Height, pixels.
    pub height: u32,
}

impl ImageSize {
    /// The image centre `(width / 2, height / 2)`.
    #[must_use]
    pub fn centre(&self) -> Vector2<f64> {
        Vector2::new(f64::from(self.width) / 2.0, f64::from(self.height) / 2.0)
    }

    /// Length of the image diagonal, pixels.
    #[must_use]
    pub fn diagonal(&self) -> f64 {
        f64::from(self.width).hypot(f64::from(self.height))
    }
}

/// One vanishing point: a point, a direction (a point at infinity), or two or more image
/// segments whose lines meet there.
///
/// When a point and segments are both present, `point` wins and `lines` are kept as the
/// evidence a person can check (that is how `vpmap detect` writes them).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct VanishingPointSpec {
    /// The vanishing point itself, pixels.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub point: Option<PixelPoint>,
    /// The vanishing point at infinity: the image direction `[dx, dy]` its edges run along
    /// (they are parallel in the photo), e.g. the vertical of a level camera. At most one
    /// entry of a scene with three vanishing points.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub direction: Option<PixelPoint>,
    /// Segments `[x1, y1, x2, y2]` whose lines meet at the vanishing point (least squares).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub lines: Vec<[f64; 4]>,
}

/// One corner of a box, named by its place as the camera sees it.
///
/// Two naming schemes, one per box (they describe the same eight corners of a box seen two
/// ways):
///
/// * **corner view** (the thesis's): the vertical edge nearest the camera is `near`, its
///   neighbours at the image-right and image-left ends of the visible faces are `right` and
///   `left`, the hidden one is `far`;
/// * **face view** (a box seen nearly face-on): the face towards the camera has `front_left`
///   and `front_right`, the face away from it `back_left` and `back_right`.
///
/// Each name is a vertical edge; with `base` or `top` it is a corner. In both schemes the
/// corners sit at `(i, j)` in `{0, 1}^2` on the box's two floor axes
/// ([`BoxCorner::grid_index`]): `near`/`front_left` `(0, 0)`, `right`/`front_right` `(1, 0)`,
/// `left`/`back_left` `(0, 1)`, `far`/`back_right` `(1, 1)`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum BoxCorner {
    /// Corner view: the vertical edge nearest the camera (the thesis's p, v).
    Near,
    /// Corner view: the edge at the image-right end of the visible faces (q).
    Right,
    /// Corner view: the edge at the image-left end of the visible faces (r, s).
    Left,
    /// Corner view: the hidden edge opposite `near`.
    Far,
    /// Face view: the left edge of the face towards the camera.
    FrontLeft,
    /// Face view: the right edge of the face towards the camera.
    FrontRight,
    /// Face view: the left edge of the face away from the camera.
    BackLeft,
    /// Face view: the right edge of the face away from the camera.
    BackRight,
}

/// Which naming scheme a box's corners use ([`BoxCorner`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum BoxView {
    /// `near`, `right`, `left`, `far`: a box seen across one of its vertical edges.
    Corner,
    /// `front_left`, `front_right`, `back_left`, `back_right`: a box seen face-on.
    Face,
}

impl BoxCorner {
    /// Every corner name, corner view first.
    pub const ALL: [BoxCorner; 8] = [
        Self::Near,
        Self::Right,
        Self::Left,
        Self::Far,
        Self::FrontLeft,
        Self::FrontRight,
        Self::BackLeft,
        Self::BackRight,
    ];

    /// The scene file's spelling.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Near => "near",
            Self::Right => "right",
            Self::Left => "left",
            Self::Far => "far",
            Self::FrontLeft => "front_left",
            Self::FrontRight => "front_right",
            Self::BackLeft => "back_left",
            Self::BackRight => "back_right",
        }
    }

    /// The naming scheme the corner belongs to.
    #[must_use]
    pub fn view(self) -> BoxView {
        match self {
            Self::Near | Self::Right | Self::Left | Self::Far => BoxView::Corner,
            _ => BoxView::Face,
        }
    }

    /// The corner's place `(i, j)` on the box's two floor axes: the corner stands at
    /// `origin + i * a * e1 + j * b * e2` for side lengths `a`, `b` along unit axes `e1`, `e2`.
    #[must_use]
    pub fn grid_index(self) -> (u8, u8) {
        match self {
            Self::Near | Self::FrontLeft => (0, 0),
            Self::Right | Self::FrontRight => (1, 0),
            Self::Left | Self::BackLeft => (0, 1),
            Self::Far | Self::BackRight => (1, 1),
        }
    }

    /// The corner of `view` at grid place `(i, j)`.
    #[must_use]
    pub fn at(view: BoxView, i: u8, j: u8) -> Self {
        match (view, i, j) {
            (BoxView::Corner, 0, 0) => Self::Near,
            (BoxView::Corner, 1, 0) => Self::Right,
            (BoxView::Corner, 0, _) => Self::Left,
            (BoxView::Corner, _, _) => Self::Far,
            (BoxView::Face, 0, 0) => Self::FrontLeft,
            (BoxView::Face, 1, 0) => Self::FrontRight,
            (BoxView::Face, 0, _) => Self::BackLeft,
            (BoxView::Face, _, _) => Self::BackRight,
        }
    }
}

/// Corners of a box in one horizontal plane (its base or its top), each optional: give the
/// ones you can see. A box uses one naming scheme ([`BoxCorner`]).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct BoxCorners {
    /// Corner view: nearest the camera (the thesis's p).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub near: Option<PixelPoint>,
    /// Corner view: at the image-right end of the visible faces (q).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub right: Option<PixelPoint>,
    /// Corner view: at the image-left end of the visible faces (r).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub left: Option<PixelPoint>,
    /// Corner view: opposite `near` (usually hidden).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub far: Option<PixelPoint>,
    /// Face view: left corner of the face towards the camera.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub front_left: Option<PixelPoint>,
    /// Face view: right corner of the face towards the camera.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub front_right: Option<PixelPoint>,
    /// Face view: left corner of the face away from the camera.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub back_left: Option<PixelPoint>,
    /// Face view: right corner of the face away from the camera.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub back_right: Option<PixelPoint>,
}

impl BoxCorners {
    /// The point given for a corner, if any.
    #[must_use]
    pub fn get(&self, corner: BoxCorner) -> Option<PixelPoint> {
        match corner {
            BoxCorner::Near => self.near,
            BoxCorner::Right => self.right,
            BoxCorner::Left => self.left,
            BoxCorner::Far => self.far,
            BoxCorner::FrontLeft => self.front_left,
            BoxCorner::FrontRight => self.front_right,
            BoxCorner::BackLeft => self.back_left,
            BoxCorner::BackRight => self.back_right,
        }
    }

    /// A mutable handle on a corner's point.
    pub fn get_mut(&mut self, corner: BoxCorner) -> &mut Option<PixelPoint> {
        match corner {
            BoxCorner::Near => &mut self.near,
            BoxCorner::Right => &mut self.right,
            BoxCorner::Left => &mut self.left,
            BoxCorner::Far => &mut self.far,
            BoxCorner::FrontLeft => &mut self.front_left,
            BoxCorner::FrontRight => &mut self.front_right,
            BoxCorner::BackLeft => &mut self.back_left,
            BoxCorner::BackRight => &mut self.back_right,
        }
    }

    /// The given corners with their points, in [`BoxCorner::ALL`] order.
    pub fn given(&self) -> impl Iterator<Item = (BoxCorner, PixelPoint)> + '_ {
        BoxCorner::ALL
            .into_iter()
            .filter_map(|c| self.get(c).map(|p| (c, p)))
    }

    /// Every point, mutably (for noise models).
    pub fn points_mut(&mut self) -> impl Iterator<Item = &mut PixelPoint> {
        [
            &mut self.near,
            &mut self.right,
            &mut self.left,
            &mut self.far,
            &mut self.front_left,
            &mut self.front_right,
            &mut self.back_left,
            &mut self.back_right,
        ]
        .into_iter()
        .flatten()
    }
}

/// The older name of [`BoxCorners`] (a box's base corners).
pub type BoxBase = BoxCorners;

/// The top annotation of an object.
///
/// A box gives any of its top corners by the names of [`BoxCorners`] (the thesis's v is
/// `near`, s is `left`). A footprint object gives `above` (index of the footprint vertex under
/// the top point) and `point`.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct TopSpec {
    /// Box: the top corners, by the names of [`BoxCorners`].
    #[serde(flatten)]
    pub corners: BoxCorners,
    /// Footprint object: index of the footprint vertex below `point`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub above: Option<usize>,
    /// Footprint object: the top point above vertex `above`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub point: Option<PixelPoint>,
}

/// One object on the floor: a box (`base`) or a general footprint polygon (`footprint`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ObjectSpec {
    /// A name, unique in the scene.
    pub name: String,
    /// Box objects: the visible base corners.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub base: Option<BoxCorners>,
    /// Footprint objects: the visible base polygon, in order.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub footprint: Option<Vec<PixelPoint>>,
    /// The top annotation (optional: without it the object has no height).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub top: Option<TopSpec>,
    /// Box objects: the box is turned on the floor by its own angle rather than lined up with
    /// the room's two horizontal directions (the fit then estimates its yaw).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub own_yaw: bool,
}

/// Which dimension of an object a known length refers to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Dimension {
    /// The longer side of a box's footprint.
    Length,
    /// The shorter side of a box's footprint.
    Breadth,
    /// The object's height.
    Height,
}

/// A known distance between two floor points in the image.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FloorDistance {
    /// First floor point, pixels.
    pub from: PixelPoint,
    /// Second floor point, pixels.
    pub to: PixelPoint,
    /// Their distance on the floor, metres.
    pub meters: f64,
}

/// One known length that fixes the map's scale (exactly one form is given).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct ScaleSpec {
    /// The camera's height above the floor, metres.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub camera_height_m: Option<f64>,
    /// Name of the object whose dimension is known.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub object: Option<String>,
    /// Which dimension of `object` is known (legacy: `length`/`breadth` mean the longer and
    /// shorter side of the reconstruction; prefer `edge`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dimension: Option<Dimension>,
    /// The box edge of `object` whose length is known, by its two corners, e.g.
    /// `["base.near", "base.right"]` or `["base.left", "top.left"]` (a vertical edge).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub edge: Option<[String; 2]>,
    /// The known dimension of `object`, metres.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub meters: Option<f64>,
    /// A known distance between two floor points.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub floor_distance: Option<FloorDistance>,
}

/// The validated meaning of a [`ScaleSpec`].
#[derive(Debug, Clone, PartialEq)]
pub enum Scale {
    /// The camera height is known, metres.
    CameraHeight(f64),
    /// One dimension of a named object is known, metres.
    Object {
        /// The object's name.
        name: String,
        /// Which dimension.
        dimension: Dimension,
        /// Its length, metres.
        meters: f64,
    },
    /// The length of one edge of a named box is known.
    Edge {
        /// The object's name.
        name: String,
        /// The edge's two corners.
        ends: [BoxPoint; 2],
        /// Its length, metres.
        meters: f64,
    },
    /// The floor distance between two image points is known.
    FloorDistance(FloorDistance),
}

/// One corner of a box: a vertical edge ([`BoxCorner`]) at the base or at the top, spelt
/// `base.near`, `top.front_left`, ...
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BoxPoint {
    /// Which vertical edge.
    pub corner: BoxCorner,
    /// At the top (else at the base).
    pub top: bool,
}

impl BoxPoint {
    /// Parse `base.<corner>` or `top.<corner>`.
    #[must_use]
    pub fn parse(text: &str) -> Option<Self> {
        let (level, name) = text.split_once('.')?;
        let top = match level {
            "base" => false,
            "top" => true,
            _ => return None,
        };
        let corner = BoxCorner::ALL.into_iter().find(|c| c.name() == name)?;
        Some(Self { corner, top })
    }

    /// The scene file's spelling, e.g. `base.near`.
    #[must_use]
    pub fn name(self) -> String {
        format!(
            "{}.{}",
            if self.top { "top" } else { "base" },
            self.corner.name()
        )
    }

    /// Place `(i, j, k)` on the box: [`BoxCorner::grid_index`] and `k = 1` at the top.
    #[must_use]
    pub fn grid_index(self) -> (u8, u8, u8) {
        let (i, j) = self.corner.grid_index();
        (i, j, u8::from(self.top))
    }
}

/// A scene file, version 1.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Scene {
    /// Format version; must be 1.
    pub version: u64,
    /// The photo's size.
    pub image: ImageSize,
    /// Two horizontal vanishing points (any order), then optionally the vertical one.
    pub vanishing_points: Vec<VanishingPointSpec>,
    /// The principal point, pixels (default: image centre in 2PP, orthocentre in 3PP).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub principal_point: Option<PixelPoint>,
    /// A focal length from elsewhere (e.g. `vpmap detect`), pixels: checked against the
    /// vanishing points, which win.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub focal_px: Option<f64>,
    /// Objects standing on the floor.
    #[serde(default)]
    pub objects: Vec<ObjectSpec>,
    /// Visible floor corners in order around the floor outline.
    #[serde(default)]
    pub floor: Vec<PixelPoint>,
    /// One known length (optional; without it lengths are in camera heights).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scale: Option<ScaleSpec>,
    /// `"2pp"` or `"3pp"` as `vpmap detect` judged the photo (informational: the number of
    /// vanishing points decides; a value that disagrees with it is refused).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub perspective: Option<crate::calibration::Perspective>,
}

/// The kind of an object, after validation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ObjectShape<'a> {
    /// A box: the corners given, in one naming scheme.
    Box {
        /// The naming scheme of the corners given.
        view: BoxView,
        /// Base corners given.
        base: &'a BoxCorners,
        /// Top corners given (all `None` without a top).
        top: BoxCorners,
        /// Whether the box has its own yaw rather than the room's directions.
        own_yaw: bool,
    },
    /// A footprint polygon with an optional top point above one vertex.
    Footprint {
        /// Base polygon.
        polygon: &'a [PixelPoint],
        /// `(vertex index, top point)`.
        top: Option<(usize, PixelPoint)>,
    },
}

/// A box in the thesis's annotation: base corners near, right, left (p, q, r) and optional
/// top corners above near (v) and left (s). What the side-view and projective methods read.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ThesisBox {
    /// Base corner nearest the camera (p).
    pub near: PixelPoint,
    /// Base corner at the image-right end (q).
    pub right: PixelPoint,
    /// Base corner at the image-left end (r).
    pub left: PixelPoint,
    /// Top corner above `near` (v).
    pub top_near: Option<PixelPoint>,
    /// Top corner above `left` (s).
    pub top_left: Option<PixelPoint>,
}

impl ObjectShape<'_> {
    /// The box in the thesis's annotation, for the side-view and projective methods.
    ///
    /// # Errors
    /// [`MetrologyError::InvalidField`] naming what is missing or extra when the box is not
    /// annotated as those methods need (base near, right and left; tops only above near and
    /// left, near first).
    pub fn thesis_box(&self, index: usize, name: &str, method: &str) -> Result<Option<ThesisBox>> {
        let ObjectShape::Box {
            view, base, top, ..
        } = self
        else {
            return Ok(None);
        };
        let field = format!("objects[{index}]");
        let advice = "the default method (fit) reads any corners that fix the box";
        if *view == BoxView::Face {
            return Err(MetrologyError::InvalidField {
                field,
                reason: format!(
                    "object {name:?} is annotated face-on (front_left, ...); the {method} method needs the corner view's base.near, base.right and base.left: {advice}"
                ),
            });
        }
        let (Some(near), Some(right), Some(left)) = (base.near, base.right, base.left) else {
            let missing: Vec<&str> = [
                ("near", base.near),
                ("right", base.right),
                ("left", base.left),
            ]
            .iter()
            .filter(|(_, p)| p.is_none())
            .map(|(n, _)| *n)
            .collect();
            return Err(MetrologyError::InvalidField {
                field: format!("{field}.base"),
                reason: format!(
                    "object {name:?} lacks base.{}; the {method} method needs base.near, base.right and base.left: {advice}",
                    missing.join(" and base.")
                ),
            });
        };
        let extra: Vec<String> = base
            .far
            .map(|_| "base.far".to_owned())
            .into_iter()
            .chain(top.right.map(|_| "top.right".to_owned()))
            .chain(top.far.map(|_| "top.far".to_owned()))
            .collect();
        if !extra.is_empty() {
            return Err(MetrologyError::InvalidField {
                field: field.clone(),
                reason: format!(
                    "object {name:?} gives {}, which the {method} method does not read: {advice}",
                    extra.join(" and ")
                ),
            });
        }
        if top.near.is_none() && top.left.is_some() {
            return Err(MetrologyError::InvalidField {
                field: format!("{field}.top"),
                reason: format!(
                    "object {name:?} gives `top.left` without `top.near`, which the {method} method needs: {advice}"
                ),
            });
        }
        Ok(Some(ThesisBox {
            near,
            right,
            left,
            top_near: top.near,
            top_left: top.left,
        }))
    }
}

/// Largest magnitude of an annotated image coordinate, pixels: points are clicked in (or near)
/// the photo.
pub const MAX_POINT_PX: f64 = 1e7;
/// Largest magnitude of a vanishing point's coordinate, pixels (nearly parallel edges put it
/// far away; beyond this it is at infinity for any real camera).
pub const MAX_VANISHING_POINT_PX: f64 = 1e12;
/// Largest known length in a `scale`, metres.
pub const MAX_SCALE_M: f64 = 1e6;

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

/// The fields of a scene file that vpmap does not read (often typos such as `scael`), as
/// paths like `"scael"`, `objects[0]."heigth"` or `scale."meter"`; empty when `value` is not
/// an object.
///
/// # Example
/// ```
/// use vpmap_metrology::scene::unknown_fields;
/// let v = serde_json::json!({"version": 1, "scael": {}, "objects": [{"name": "a", "heigth": 2}]});
/// assert_eq!(unknown_fields(&v), ["\"scael\"", "objects[0].\"heigth\""]);
/// ```
#[must_use]
pub fn unknown_fields(value: &serde_json::Value) -> Vec<String> {
    const TOP: [&str; 9] = [
        "version",
        "image",
        "vanishing_points",
        "principal_point",
        "focal_px",
        "objects",
        "floor",
        "scale",
        "perspective",
    ];
    const OBJECT: [&str; 5] = ["name", "base", "footprint", "top", "own_yaw"];
    const SCALE: [&str; 6] = [
        "camera_height_m",
        "object",
        "dimension",
        "edge",
        "meters",
        "floor_distance",
    ];
    let Some(top) = value.as_object() else {
        return Vec::new();
    };
    let mut out: Vec<String> = top
        .keys()
        .filter(|k| !TOP.contains(&k.as_str()))
        .map(|k| format!("{k:?}"))
        .collect();
    if let Some(objects) = top.get("objects").and_then(serde_json::Value::as_array) {
        for (i, o) in objects.iter().enumerate() {
            if let Some(o) = o.as_object() {
                out.extend(
                    o.keys()
                        .filter(|k| !OBJECT.contains(&k.as_str()))
                        .map(|k| format!("objects[{i}].{k:?}")),
                );
                for (part, extra) in [("base", &[][..]), ("top", &["above", "point"][..])] {
                    if let Some(corners) = o.get(part).and_then(serde_json::Value::as_object) {
                        out.extend(
                            corners
                                .keys()
                                .filter(|k| {
                                    !BoxCorner::ALL.iter().any(|c| c.name() == k.as_str())
                                        && !extra.contains(&k.as_str())
                                })
                                .map(|k| format!("objects[{i}].{part}.{k:?}")),
                        );
                    }
                }
            }
        }
    }
    if let Some(scale) = top.get("scale").and_then(serde_json::Value::as_object) {
        out.extend(
            scale
                .keys()
                .filter(|k| !SCALE.contains(&k.as_str()))
                .map(|k| format!("scale.{k:?}")),
        );
    }
    out
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
    pub fn from_json_str(text: &str) -> Result<Self> {
        let scene: Scene =
            serde_json::from_str(text).map_err(|e| MetrologyError::Json(e.to_string()))?;
        scene.validate()?;
        Ok(scene)
    }

    /// The scene as pretty-printed JSON.
    #[must_use]
    pub fn to_json_string(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_default()
    }

    /// Check everything that does not need the camera: version, finiteness, object shapes,
    /// unique names, the scale's form.
    ///
    /// # Errors
    /// The first problem found, naming the field and the value.
    pub fn validate(&self) -> Result<()> {
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
        let n = self.vanishing_points.len();
        if !(2..=3).contains(&n) {
            return Err(MetrologyError::VanishingPointCount(n));
        }
        self.check_sizes()?;
        if let Some(p) = self.perspective {
            let expected = match p {
                crate::calibration::Perspective::TwoPoint => 2,
                crate::calibration::Perspective::ThreePoint => 3,
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
        }
        if let Some(p) = self.principal_point {
            check_point("principal_point", p)?;
        }
        if let Some(f) = self.focal_px {
            check_positive("focal_px", f)?;
        }
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

    /// Whether the vanishing points' order was set by a tool that names each one: some are
    /// given only by segments (drawn on the page under their names, or written by
    /// `vpmap detect`). Vanishing points all given as points or directions may come in any
    /// data set's order ([`crate::calibration::reading`]).
    #[must_use]
    pub fn vanishing_points_labelled(&self) -> bool {
        self.vanishing_points
            .iter()
            .any(|v| v.point.is_none() && v.direction.is_none())
    }

    /// The vanishing points in homogeneous pixel coordinates `(x, y, w)`, in the order given:
    /// a given point as `(x, y, 1)`, a direction as `(dx, dy, 0)`, segments by their
    /// least-squares intersection ([`intersect_segments`]) as `(x, y, 1)`. Which one is
    /// vertical is decided by [`crate::calibration::vertical_index`].
    ///
    /// # Errors
    /// [`MetrologyError::ParallelLines`] when a set of segments meets at infinity.
    pub fn resolve_vanishing_points(&self) -> Result<Vec<Vector3<f64>>> {
        let n = self.vanishing_points.len();
        self.vanishing_points
            .iter()
            .enumerate()
            .map(|(i, vp)| {
                if let Some(d) = vp.direction {
                    return Ok(Vector3::new(d[0], d[1], 0.0));
                }
                if let Some(p) = vp.point {
                    return Ok(Vector3::new(p[0], p[1], 1.0));
                }
                intersect_segments(&vp.lines, self.image)
                    .map(|p| Vector3::new(p.x, p.y, 1.0))
                    .map_err(|fit| match fit {
                    SegmentFit::Parallel => MetrologyError::ParallelLines {
                        index: i + 1,
                        hint: if n == 3 {
                            "; for a level camera (vertical edges parallel in the photo) give the vertical vanishing point as a `direction`, or only the two horizontal ones".to_owned()
                        } else {
                            String::new()
                        },
                    },
                    SegmentFit::Collinear => MetrologyError::InvalidField {
                        field: format!("vanishing_points[{i}].lines"),
                        reason: "the segments lie on one line, so they do not fix a point: click edges on different lines that run to the vanishing point".to_owned(),
                    },
                    SegmentFit::Overflow => MetrologyError::InvalidField {
                        field: format!("vanishing_points[{i}].lines"),
                        reason: "the segments' coordinates are too large for their intersection to be computed: give them in pixels of the image".to_owned(),
                    },
                })
            })
            .collect()
    }
}

/// The least-squares intersection of the lines through two or more segments.
///
/// Each segment `[x1, y1, x2, y2]` gives a homogeneous line, normalised so that its value at a
/// point is the point's distance to it; the intersection minimises the sum of squared
/// distances in homogeneous form (smallest eigenvector of the 3x3 normal matrix), computed in
/// coordinates centred on the image and scaled by its diagonal for conditioning.
///
/// # Errors
/// [`SegmentFit::Parallel`] when the lines meet at infinity (further than 1e7 image diagonals
/// away), [`SegmentFit::Collinear`] when they all lie on one line (no single point).
///
/// # Example
/// ```
/// use vpmap_metrology::scene::{intersect_segments, ImageSize};
/// let image = ImageSize { width: 100, height: 100 };
/// let vp = intersect_segments(&[[0.0, 0.0, 1.0, 1.0], [10.0, 0.0, 9.0, 1.0]], image).unwrap();
/// assert!((vp.x - 5.0).abs() < 1e-9 && (vp.y - 5.0).abs() < 1e-9);
/// ```
pub fn intersect_segments(
    segments: &[[f64; 4]],
    image: ImageSize,
) -> std::result::Result<Vector2<f64>, SegmentFit> {
    let c = image.centre();
    let s = image.diagonal();
    let mut m = Matrix3::<f64>::zeros();
    for seg in segments {
        let a = Vector3::new((seg[0] - c.x) / s, (seg[1] - c.y) / s, 1.0);
        let b = Vector3::new((seg[2] - c.x) / s, (seg[3] - c.y) / s, 1.0);
        let l = a.cross(&b);
        let norm = l.x.hypot(l.y);
        if norm <= f64::EPSILON {
            continue;
        }
        let l = l / norm;
        m += l * l.transpose();
    }
    let eig = crate::linalg::symmetric_eigen(m).ok_or(SegmentFit::Overflow)?;
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| eig.eigenvalues[a].total_cmp(&eig.eigenvalues[b]));
    // Two vanishing eigenvalues: every line is the same line.
    if eig.eigenvalues[order[1]] <= 1e-12 * eig.eigenvalues.sum().max(f64::MIN_POSITIVE) {
        return Err(SegmentFit::Collinear);
    }
    let v = eig.eigenvectors.column(order[0]);
    if v.z.abs() < 1e-7 * v.x.hypot(v.y) {
        return Err(SegmentFit::Parallel);
    }
    Ok(Vector2::new(v.x / v.z * s + c.x, v.y / v.z * s + c.y))
}

/// Why a set of segments fixes no vanishing point.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SegmentFit {
    /// The lines are parallel: they meet only at infinity.
    Parallel,
    /// The segments all lie on one line.
    Collinear,
    /// The lines' coordinates are so large that their intersection overflows.
    Overflow,
}

//! The scene file's types: what a user annotates on one photo, field by field, and the
//! validated shapes of its objects ([`ObjectShape`], [`ThesisBox`]).

use nalgebra::Vector2;
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
    /// The uncertainty of `point` or `direction`, degrees squared: a 2 x 2 covariance of the
    /// vanishing direction seen from the scene's reference camera (its `focal_px`, else the
    /// image diagonal, and its `principal_point`, else the image centre), in the basis
    /// *across* (perpendicular to the line from the principal point to the vanishing point)
    /// and *radial* (along it) ([`crate::scene::VpChart`]). With it the fit weighs the point
    /// by this covariance (and not its `lines`, which stay as evidence a person can check);
    /// `vpmap detect` writes it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub covariance_deg2: Option<[[f64; 2]; 2]>,
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

/// Two- or three-point perspective.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Perspective {
    /// Two horizontal vanishing points: the camera's pitch is 0.
    #[serde(rename = "2pp")]
    TwoPoint,
    /// Two horizontal and one vertical vanishing point.
    #[serde(rename = "3pp")]
    ThreePoint,
}

impl Perspective {
    /// The scene file's spelling: `"2pp"` or `"3pp"` (as serialised).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::TwoPoint => "2pp",
            Self::ThreePoint => "3pp",
        }
    }

    /// In words: `"two-point"` or `"three-point"` (as summaries print it).
    #[must_use]
    pub fn words(self) -> &'static str {
        match self {
            Self::TwoPoint => "two-point",
            Self::ThreePoint => "three-point",
        }
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
    /// The standard deviation of `focal_px`, pixels: with it `focal_px` is a prior the joint
    /// fit weighs with the rest of the evidence (a focal length from EXIF, say), not only a
    /// starting value.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub focal_sd_px: Option<f64>,
    /// The standard deviation of `principal_point` (each coordinate), pixels: with it the
    /// principal point is a prior the joint fit refines (`vpmap detect` writes the image
    /// centre with the spread of real cameras' principal points); without it a given
    /// principal point is held as known.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub principal_point_sd_px: Option<f64>,
    /// The lens's distortion (the division model, [`super::LensDistortion`]): with it every
    /// click and vanishing-point segment is in the photo's pixels and is undistorted before
    /// the fit; without it the photo is taken as a pinhole camera's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lens_distortion: Option<super::LensDistortion>,
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
    pub perspective: Option<Perspective>,
    /// Per click, its 2 x 2 covariance in px^2, keyed by the click's field path
    /// (`objects[0].base.near`, `objects[i].top.<corner>`, `objects[i].footprint[k]`,
    /// `objects[i].top.point`, `floor[k]`, `scale.floor_distance.from`/`.to`), as `vpmap snap`
    /// writes it: the fit weights each such click by its own covariance.
    #[serde(default, skip_serializing_if = "std::collections::BTreeMap::is_empty")]
    pub click_covariances_px2: std::collections::BTreeMap<String, [[f64; 2]; 2]>,
    /// In a room file, this photo's placement pinned: its quarter turn against photo 1's
    /// room directions, degrees (0, 90, 180 or 270), as a map's `alternatives` give it
    /// (`placement_turn_deg`). The room fit then places the photo only so turned; without it
    /// the fit chooses. Photos 2..n only.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub placement_turn_deg: Option<i64>,
    /// The room's other photos: a room file (`{"version": 1, "photos": [SCENE, ...]}`) is
    /// read into its first photo, this scene, with photos 2..n here, each a single-photo
    /// scene. Empty for a single-photo scene file; not a field of the file.
    #[serde(skip)]
    pub other_photos: Vec<Scene>,
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

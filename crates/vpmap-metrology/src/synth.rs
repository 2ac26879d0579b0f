//! A synthetic pinhole camera: Manhattan scenes with known truth.
//!
//! This is the test oracle of the reconstruction (and the evaluation's data source). It shares
//! nothing with the reconstruction code but the scene and map types: it projects known 3D
//! points through a textbook pinhole camera (`u = o + f [x/z, y/z]` in a camera frame with `x`
//! right, `y` down, `z` forward), so an error in the reconstruction's geometry shows up as a
//! mismatch against [`Truth`].
//!
//! World frame = map frame: origin at the station point, `x` right, `y` forward (the camera's
//! horizontal viewing direction), `z` up; lengths in metres. The camera stands at
//! `(0, 0, height_m)`, pitched down by `pitch` about `x`, then rolled by `roll` about its
//! viewing direction (positive roll makes the horizon fall to the right in the image, as in
//! `../shared/data/synthetic-scenes`).

use nalgebra::{Vector2, Vector3};
use rand::{Rng, RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use serde::{Deserialize, Serialize};

use crate::error::{MetrologyError, Result};
use crate::scene::{
    BoxCorner, BoxCorners, ImageSize, ObjectSpec, PixelPoint, ScaleSpec, Scene, TopSpec,
    VanishingPointSpec,
};

/// A pinhole camera above a flat floor.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PinholeCamera {
    /// Image size.
    pub image: ImageSize,
    /// Focal length, pixels.
    pub focal_px: f64,
    /// Principal point, pixels.
    pub principal_point_px: Vector2<f64>,
    /// Height above the floor, metres.
    pub height_m: f64,
    /// Pitch, radians, positive looking down.
    pub pitch_rad: f64,
    /// Roll, radians.
    pub roll_rad: f64,
}

impl PinholeCamera {
    /// The camera axes in the world: `(right, down, forward)`.
    #[must_use]
    pub fn axes(&self) -> (Vector3<f64>, Vector3<f64>, Vector3<f64>) {
        let (s, c) = self.pitch_rad.sin_cos();
        let forward = Vector3::new(0.0, c, -s);
        let right0 = Vector3::new(1.0, 0.0, 0.0);
        let down0 = Vector3::new(0.0, -s, -c);
        let (sr, cr) = (-self.roll_rad).sin_cos();
        let right = right0 * cr + down0 * sr;
        let down = -right0 * sr + down0 * cr;
        (right, down, forward)
    }

    /// Depth of a world point along the viewing direction (positive in front).
    #[must_use]
    pub fn depth(&self, world: Vector3<f64>) -> f64 {
        let (_, _, f) = self.axes();
        (world - self.centre()).dot(&f)
    }

    /// The camera centre in the world.
    #[must_use]
    pub fn centre(&self) -> Vector3<f64> {
        Vector3::new(0.0, 0.0, self.height_m)
    }

    /// Project a world point to pixels (`None` behind the camera).
    #[must_use]
    pub fn project(&self, world: Vector3<f64>) -> Option<Vector2<f64>> {
        let (r, d, f) = self.axes();
        let v = world - self.centre();
        let z = v.dot(&f);
        if z <= 1e-12 {
            return None;
        }
        Some(self.principal_point_px + Vector2::new(v.dot(&r), v.dot(&d)) * (self.focal_px / z))
    }

    /// Vanishing point of a world direction (`None` when parallel to the image plane).
    #[must_use]
    pub fn vanishing_point(&self, direction: Vector3<f64>) -> Option<Vector2<f64>> {
        let (r, d, f) = self.axes();
        let z = direction.dot(&f);
        if z.abs() <= 1e-12 {
            return None;
        }
        Some(
            self.principal_point_px
                + Vector2::new(direction.dot(&r), direction.dot(&d)) * (self.focal_px / z),
        )
    }

    /// The floor point seen at a pixel (`None` at or above the horizon).
    #[must_use]
    pub fn floor_point(&self, pixel: Vector2<f64>) -> Option<Vector2<f64>> {
        let (r, d, f) = self.axes();
        let q = (pixel - self.principal_point_px) / self.focal_px;
        let ray = r * q.x + d * q.y + f;
        if ray.z >= -1e-12 {
            return None;
        }
        let t = -self.height_m / ray.z;
        Some(Vector2::new(ray.x * t, ray.y * t))
    }

    /// Whether a pixel lies inside the image.
    #[must_use]
    pub fn in_image(&self, p: Vector2<f64>) -> bool {
        p.x >= 0.0
            && p.y >= 0.0
            && p.x <= f64::from(self.image.width)
            && p.y <= f64::from(self.image.height)
    }
}

/// A box standing on the floor.
#[derive(Debug, Clone, PartialEq)]
pub struct SynthBox {
    /// Name.
    pub name: String,
    /// One base corner, metres.
    pub corner: Vector2<f64>,
    /// First edge from `corner` (along one room axis), metres.
    pub edge_a: Vector2<f64>,
    /// Second edge from `corner` (along the other room axis), metres.
    pub edge_b: Vector2<f64>,
    /// Height, metres.
    pub height_m: f64,
}

impl SynthBox {
    /// The four base corners in order around the box.
    #[must_use]
    pub fn corners(&self) -> [Vector2<f64>; 4] {
        [
            self.corner,
            self.corner + self.edge_a,
            self.corner + self.edge_a + self.edge_b,
            self.corner + self.edge_b,
        ]
    }
}

/// A prism with a polygonal footprint standing on the floor (the thesis's chair).
#[derive(Debug, Clone, PartialEq)]
pub struct SynthPrism {
    /// Name.
    pub name: String,
    /// Footprint vertices in order, metres.
    pub footprint: Vec<Vector2<f64>>,
    /// Height, metres.
    pub height_m: f64,
}

/// The truth of a synthetic scene, in the map frame (metres).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Truth {
    /// The camera.
    pub camera: TruthCamera,
    /// Objects in scene order: a box's footprint is near, right, far, left.
    pub objects: Vec<TruthObject>,
    /// Floor outline in scene order.
    pub floor: Vec<[f64; 2]>,
}

/// The true camera.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TruthCamera {
    /// Focal length, pixels.
    pub focal_px: f64,
    /// Principal point, pixels (absent: the image centre).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub principal_point: Option<[f64; 2]>,
    /// Pitch, degrees, positive looking down.
    pub pitch_deg: f64,
    /// Roll, degrees.
    pub roll_deg: f64,
    /// Height, metres.
    pub height: f64,
}

impl TruthCamera {
    /// The pinhole camera this truth describes, for an image of the given size (principal
    /// point: the image centre when absent).
    #[must_use]
    pub fn pinhole(&self, image: ImageSize) -> PinholeCamera {
        PinholeCamera {
            image,
            focal_px: self.focal_px,
            principal_point_px: self
                .principal_point
                .map_or_else(|| image.centre(), |p| Vector2::new(p[0], p[1])),
            height_m: self.height,
            pitch_rad: self.pitch_deg.to_radians(),
            roll_rad: self.roll_deg.to_radians(),
        }
    }
}

/// One true object.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TruthObject {
    /// Name.
    pub name: String,
    /// Footprint corners, metres.
    pub footprint: Vec<[f64; 2]>,
    /// Height, metres.
    pub height: f64,
}

/// How the vanishing points are written into the scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum VanishingPointForm {
    /// As exact points.
    #[default]
    Points,
    /// As the (possibly noisy) annotated box edges that meet there, as a user would click them.
    Lines,
}

/// What the synthetic user clicks on each box, and whether the boxes keep to the room's axes:
/// the views real photos show ([`synthesize`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Annotation {
    /// The thesis's annotation: corner view, base `near`, `right`, `left`, top `near` and
    /// `left`; boxes along the room's axes, some taller than the camera.
    #[default]
    Thesis,
    /// Boxes seen nearly face-on: the room (and every box with it) turned 3-10 degrees either
    /// way from square to the camera's viewing direction, boxes lower than the camera, each
    /// annotated in the face view by base `front_left`, `front_right` and all four top corners
    /// (`front_left`, `front_right`, `back_left`, `back_right`).
    FaceOn,
    /// Hidden base corners: corner view with only base `near` and the four top corners
    /// (`near`, `right`, `left`, `far`); boxes lower than the camera.
    HiddenBase,
    /// Objects with their own yaw: every second box (the 2nd, 4th, ...) turned from the
    /// room's axes by its own angle, 15-40 degrees either way, and marked `own_yaw`;
    /// annotated as [`Annotation::Thesis`].
    OwnYaw,
}

/// Options of [`synthesize`].
#[derive(Debug, Clone, PartialEq)]
pub struct SynthOptions {
    /// Random seed (the scene is a pure function of the options).
    pub seed: u64,
    /// Image size.
    pub image: ImageSize,
    /// Focal length, pixels.
    pub focal_px: f64,
    /// Camera height, metres.
    pub height_m: f64,
    /// Pitch, degrees (0 gives a two-point-perspective scene).
    pub pitch_deg: f64,
    /// Roll, degrees.
    pub roll_deg: f64,
    /// Number of boxes.
    pub boxes: usize,
    /// Number of pentagonal prisms.
    pub prisms: usize,
    /// Gaussian noise on every annotated point, pixels (standard deviation).
    pub noise_px: f64,
    /// How vanishing points are given.
    pub vanishing_points: VanishingPointForm,
    /// Write `scale.camera_height_m` into the scene.
    pub with_scale: bool,
    /// Give the principal point in the scene (else the reader's default applies).
    pub with_principal_point: bool,
    /// What is clicked on each box and how boxes are turned ([`Annotation::Thesis`] by
    /// default, which draws exactly the scenes drawn before the other views existed).
    pub annotation: Annotation,
}

impl Default for SynthOptions {
    fn default() -> Self {
        Self {
            seed: 0,
            image: ImageSize {
                width: 1600,
                height: 1200,
            },
            focal_px: 1100.0,
            height_m: 1.5,
            pitch_deg: 20.0,
            roll_deg: 3.0,
            boxes: 4,
            prisms: 1,
            noise_px: 0.0,
            vanishing_points: VanishingPointForm::Points,
            with_scale: true,
            with_principal_point: false,
            annotation: Annotation::Thesis,
        }
    }
}

fn arr(p: Vector2<f64>) -> PixelPoint {
    [p.x, p.y]
}

/// The corners a synthetic user clicks on one box ([`render_annotated`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum BoxClicks {
    /// Corner view: base `near`, `right`, `left`; top `near`, `left` (the thesis's).
    #[default]
    Thesis,
    /// Face view: base `front_left`, `front_right`; top `front_left`, `front_right`,
    /// `back_left`, `back_right`. The front face is the one whose outward normal points most
    /// against the camera's horizontal viewing direction.
    FaceOn,
    /// Corner view: base `near` only; top `near`, `right`, `left`, `far`.
    HiddenBase,
}

/// How one box is annotated ([`render_annotated`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct BoxAnnotation {
    /// The corners clicked.
    pub clicks: BoxClicks,
    /// Mark the box `own_yaw` (turned by its own angle rather than along the room's axes).
    pub own_yaw: bool,
}

/// Render boxes, prisms and a floor outline through a camera into a scene and its truth.
///
/// Box annotations follow the scene format: the base corner nearest the station point, its
/// neighbours at the image-right and image-left ends, the top above the near corner and the
/// top above the left corner. Returns `None` when an annotated point falls behind the camera.
/// [`render_annotated`] with the thesis's annotation for every box.
#[must_use]
pub fn render_scene(
    camera: &PinholeCamera,
    room_axes: [Vector3<f64>; 2],
    boxes: &[SynthBox],
    prisms: &[SynthPrism],
    floor: &[Vector2<f64>],
) -> Option<(Scene, Truth)> {
    render_annotated(camera, room_axes, boxes, &[], prisms, floor)
}

/// A box's base corners in the order `(0, 0), (1, 0), (1, 1), (0, 1)` of
/// [`BoxCorner::grid_index`] for the view its clicks use: corner view near, right, far, left;
/// face view front left, front right, back right, back left. `None` when a corner is behind
/// the camera.
fn grid_corners(camera: &PinholeCamera, b: &SynthBox, clicks: BoxClicks) -> Option<[usize; 4]> {
    let c = b.corners();
    let image_x = |i: usize| {
        camera
            .project(Vector3::new(c[i].x, c[i].y, 0.0))
            .map(|p| p.x)
    };
    let (first, n1, n3) = match clicks {
        BoxClicks::Thesis | BoxClicks::HiddenBase => {
            let near = (0..4).min_by(|&i, &j| c[i].norm().total_cmp(&c[j].norm()))?;
            (near, (near + 1) % 4, (near + 3) % 4)
        }
        BoxClicks::FaceOn => {
            // The front face: the base edge whose outward normal points most towards -y
            // (against the camera's horizontal viewing direction).
            let centre = (c[0] + c[1] + c[2] + c[3]) / 4.0;
            let facing = |k: usize| {
                let (p, q) = (c[k], c[(k + 1) % 4]);
                let e = q - p;
                let mut n = Vector2::new(e.y, -e.x);
                if n.dot(&((p + q) / 2.0 - centre)) < 0.0 {
                    n = -n;
                }
                -n.y / n.norm()
            };
            let k = (0..4).max_by(|&i, &j| facing(i).total_cmp(&facing(j)))?;
            let (p, q) = (k, (k + 1) % 4);
            // front left: the end further left in the image; its other neighbour is back left.
            let (fl, fr) = if image_x(p)? <= image_x(q)? {
                (p, q)
            } else {
                (q, p)
            };
            let bl = if (fl + 1) % 4 == fr {
                (fl + 3) % 4
            } else {
                (fl + 1) % 4
            };
            return Some([fl, fr, (fl + 2) % 4, bl]);
        }
    };
    let (right, left) = if image_x(n1)? >= image_x(n3)? {
        (n1, n3)
    } else {
        (n3, n1)
    };
    Some([first, right, (first + 2) % 4, left])
}

/// [`render_scene`] with each box annotated as `annotations` says (boxes beyond its end: the
/// thesis's annotation, along the room's axes). The truth's footprint of a box lists its
/// corners in the order of [`BoxCorner::grid_index`] for the view used: `(0, 0)`, `(1, 0)`,
/// `(1, 1)`, `(0, 1)`, i.e. near, right, far, left or front left, front right, back right,
/// back left, the order the map reports them in.
#[must_use]
pub fn render_annotated(
    camera: &PinholeCamera,
    room_axes: [Vector3<f64>; 2],
    boxes: &[SynthBox],
    annotations: &[BoxAnnotation],
    prisms: &[SynthPrism],
    floor: &[Vector2<f64>],
) -> Option<(Scene, Truth)> {
    let floor3 = |p: Vector2<f64>| Vector3::new(p.x, p.y, 0.0);
    let up = |p: Vector2<f64>, h: f64| Vector3::new(p.x, p.y, h);
    let mut objects = Vec::new();
    let mut truth_objects = Vec::new();
    for (k, b) in boxes.iter().enumerate() {
        let annotation = annotations.get(k).copied().unwrap_or_default();
        let c = b.corners();
        let grid = grid_corners(camera, b, annotation.clicks)?;
        let at_base = |g: usize| camera.project(floor3(c[grid[g]])).map(arr);
        let at_top = |g: usize| camera.project(up(c[grid[g]], b.height_m)).map(arr);
        // grid[0] = (0, 0), grid[1] = (1, 0), grid[2] = (1, 1), grid[3] = (0, 1).
        let (base, top) = match annotation.clicks {
            BoxClicks::Thesis => (
                BoxCorners {
                    near: Some(at_base(0)?),
                    right: Some(at_base(1)?),
                    left: Some(at_base(3)?),
                    ..BoxCorners::default()
                },
                BoxCorners {
                    near: Some(at_top(0)?),
                    left: Some(at_top(3)?),
                    ..BoxCorners::default()
                },
            ),
            BoxClicks::HiddenBase => (
                BoxCorners {
                    near: Some(at_base(0)?),
                    ..BoxCorners::default()
                },
                BoxCorners {
                    near: Some(at_top(0)?),
                    right: Some(at_top(1)?),
                    far: Some(at_top(2)?),
                    left: Some(at_top(3)?),
                    ..BoxCorners::default()
                },
            ),
            BoxClicks::FaceOn => (
                BoxCorners {
                    front_left: Some(at_base(0)?),
                    front_right: Some(at_base(1)?),
                    ..BoxCorners::default()
                },
                BoxCorners {
                    front_left: Some(at_top(0)?),
                    front_right: Some(at_top(1)?),
                    back_right: Some(at_top(2)?),
                    back_left: Some(at_top(3)?),
                    ..BoxCorners::default()
                },
            ),
        };
        objects.push(ObjectSpec {
            name: b.name.clone(),
            base: Some(base),
            footprint: None,
            top: Some(TopSpec {
                corners: top,
                above: None,
                point: None,
            }),
            own_yaw: annotation.own_yaw,
        });
        truth_objects.push(TruthObject {
            name: b.name.clone(),
            footprint: grid.iter().map(|&i| arr(c[i])).collect(),
            height: b.height_m,
        });
    }
    for p in prisms {
        let pts = p
            .footprint
            .iter()
            .map(|v| camera.project(floor3(*v)).map(arr))
            .collect::<Option<Vec<_>>>()?;
        objects.push(ObjectSpec {
            name: p.name.clone(),
            base: None,
            footprint: Some(pts),
            top: Some(TopSpec {
                corners: BoxCorners::default(),
                above: Some(0),
                point: Some(arr(camera.project(up(p.footprint[0], p.height_m))?)),
            }),
            own_yaw: false,
        });
        truth_objects.push(TruthObject {
            name: p.name.clone(),
            footprint: p.footprint.iter().map(|v| arr(*v)).collect(),
            height: p.height_m,
        });
    }
    let floor_px = floor
        .iter()
        .map(|p| camera.project(floor3(*p)).map(arr))
        .collect::<Option<Vec<_>>>()?;
    let mut vps = vec![
        VanishingPointSpec {
            point: Some(arr(camera.vanishing_point(room_axes[0])?)),
            lines: Vec::new(),
            direction: None,
        },
        VanishingPointSpec {
            point: Some(arr(camera.vanishing_point(room_axes[1])?)),
            lines: Vec::new(),
            direction: None,
        },
    ];
    if camera.pitch_rad.abs() > 1e-12 {
        vps.push(VanishingPointSpec {
            point: Some(arr(camera.vanishing_point(Vector3::new(0.0, 0.0, 1.0))?)),
            lines: Vec::new(),
            direction: None,
        });
    }
    let scene = Scene {
        version: 1,
        image: camera.image,
        vanishing_points: vps,
        principal_point: None,
        focal_px: None,
        objects,
        floor: floor_px,
        scale: None,
        perspective: None,
    };
    let truth = Truth {
        camera: TruthCamera {
            focal_px: camera.focal_px,
            principal_point: Some(arr(camera.principal_point_px)),
            pitch_deg: camera.pitch_rad.to_degrees(),
            roll_deg: camera.roll_rad.to_degrees(),
            height: camera.height_m,
        },
        objects: truth_objects,
        floor: floor.iter().map(|p| arr(*p)).collect(),
    };
    Some((scene, truth))
}

/// Rewrite the vanishing points of a scene as the box edges that meet there (two or more per
/// vanishing point), as a user clicking edges would give them. Uses the scene's (possibly
/// noisy) annotated corners, so noise reaches the vanishing points the way it would in use.
/// Only the vertical edges of a box marked `own_yaw` are used (its horizontal edges run to
/// its own vanishing points, not the room's). A vanishing point with fewer than two edges is
/// left as it was.
pub fn vanishing_points_as_lines(scene: &mut Scene) {
    let mut lines: Vec<Vec<[f64; 4]>> = vec![Vec::new(); scene.vanishing_points.len()];
    let points: Vec<Vector2<f64>> = scene
        .vanishing_points
        .iter()
        .map(|v| {
            v.point
                .map_or(Vector2::zeros(), |p| Vector2::new(p[0], p[1]))
        })
        .collect();
    let seg = |a: PixelPoint, b: PixelPoint| [a[0], a[1], b[0], b[1]];
    // How far a segment's line misses a vanishing point: the sine of the angle between the
    // segment and the direction from its first end to the point.
    let miss = |l: &[f64; 4], v: Vector2<f64>| {
        let a = Vector2::new(l[2] - l[0], l[3] - l[1]);
        let b = v - Vector2::new(l[0], l[1]);
        (a.x * b.y - a.y * b.x).abs() / (a.norm() * b.norm()).max(1e-300)
    };
    for obj in &scene.objects {
        let Some(base) = obj.base else { continue };
        let top = obj.top.map(|t| t.corners).unwrap_or_default();
        // The box's edges between given corners, by the axis they run along.
        let mut along: [Vec<[f64; 4]>; 3] = [Vec::new(), Vec::new(), Vec::new()];
        let levels = [base, top];
        // A box with its own yaw: its horizontal edges do not run to the room's vanishing
        // points (its vertical edges do).
        let horizontal_axes = if obj.own_yaw { 0 } else { 2 };
        for (axis, edges) in along.iter_mut().enumerate().take(horizontal_axes) {
            for corners in &levels {
                for (c, p) in corners.given() {
                    let (i, j) = c.grid_index();
                    if (if axis == 0 { i } else { j }) != 0 {
                        continue;
                    }
                    let other = if axis == 0 {
                        BoxCorner::at(c.view(), 1, j)
                    } else {
                        BoxCorner::at(c.view(), i, 1)
                    };
                    if let Some(q) = corners.get(other) {
                        edges.push(seg(p, q));
                    }
                }
            }
        }
        for (c, p) in base.given() {
            if let Some(q) = top.get(c) {
                along[2].push(seg(p, q));
            }
        }
        // Which horizontal vanishing point each floor axis runs to: the assignment whose
        // edges point at them best.
        let cost =
            |axis: usize, k: usize| along[axis].iter().map(|l| miss(l, points[k])).sum::<f64>();
        let (k0, k1) = if cost(0, 0) + cost(1, 1) <= cost(0, 1) + cost(1, 0) {
            (0, 1)
        } else {
            (1, 0)
        };
        let [a0, a1, vertical] = along;
        lines[k0].extend(a0);
        lines[k1].extend(a1);
        if lines.len() > 2 {
            lines[2].extend(vertical);
        }
    }
    for (vp, l) in scene.vanishing_points.iter_mut().zip(lines) {
        if l.len() >= 2 {
            vp.point = None;
            vp.lines = l;
        }
    }
}

/// How [`long_edges`] draws the edges a user would click to locate the vanishing points on a
/// real photo: the room's long straight lines (floor-wall and wall-ceiling junctions, wall
/// corners, door and window frames) rather than the objects' own short edges.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LongEdgeOptions {
    /// Length of every edge in the image, pixels.
    pub length_px: f64,
    /// Edges per vanishing point (at least 2).
    pub per_vanishing_point: usize,
    /// Margin kept from the image borders, as a fraction of the image's width and height.
    pub inset: f64,
}

impl Default for LongEdgeOptions {
    /// Three edges of 600 px per vanishing point, 2 % inside the image.
    fn default() -> Self {
        Self {
            length_px: 600.0,
            per_vanishing_point: 3,
            inset: 0.02,
        }
    }
}

/// Attempts per edge before [`long_edges`] gives up.
const LONG_EDGE_ATTEMPTS: usize = 2000;

/// Long straight edges running to each of the given world directions' vanishing points, as
/// segments `[x1, y1, x2, y2]` (one list per direction, in order), each the exact image of a
/// segment of a 3D line in that direction lying in front of the camera.
///
/// Per edge: a pixel `c` is drawn uniformly from the image less `inset`; the 3D line in
/// `direction` through the point one camera height along `c`'s viewing ray is the line a user
/// would click there (where along the ray does not change the line's image). The
/// part of that line in front of the camera images onto the ray from the vanishing point
/// through `c` (the whole line when the direction is parallel to the image plane). A
/// `length_px` stretch of that ray inside the inset image, at a uniform position, is taken;
/// its end points are pulled back onto the 3D line and projected through the camera, so they
/// are projections of 3D points (equal to the drawn pixels to rounding). A `c` whose ray has
/// too short a stretch inside the image is drawn again.
///
/// # Errors
/// [`MetrologyError::InvalidField`] for a non-positive or non-finite length, fewer than 2
/// edges, an inset outside `[0, 0.25]` or a zero direction; [`MetrologyError::Degenerate`]
/// when no edge of that length fits in the image for a direction (ask for shorter edges).
///
/// # Example
/// ```
/// use nalgebra::{Vector2, Vector3};
/// use rand::SeedableRng;
/// use vpmap_metrology::scene::{intersect_segments, ImageSize};
/// use vpmap_metrology::synth::{LongEdgeOptions, PinholeCamera, long_edges};
/// let image = ImageSize { width: 1600, height: 1200 };
/// let camera = PinholeCamera {
///     image, focal_px: 1000.0, principal_point_px: image.centre(), height_m: 1.5,
///     pitch_rad: 0.3, roll_rad: 0.05,
/// };
/// let direction = Vector3::new(0.6, 0.8, 0.0);
/// let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
/// let edges = long_edges(&camera, &[direction], &LongEdgeOptions::default(), &mut rng).unwrap();
/// assert_eq!(edges[0].len(), 3);
/// let vp = camera.vanishing_point(direction).unwrap();
/// let fitted = intersect_segments(&edges[0], image).unwrap();
/// assert!((fitted - vp).norm() < 1e-6 * vp.norm());
/// ```
pub fn long_edges(
    camera: &PinholeCamera,
    directions: &[Vector3<f64>],
    options: &LongEdgeOptions,
    rng: &mut impl Rng,
) -> Result<Vec<Vec<[f64; 4]>>> {
    let invalid = |field: &str, reason: String| MetrologyError::InvalidField {
        field: format!("long_edges.{field}"),
        reason,
    };
    let length = options.length_px;
    if !(length.is_finite() && length > 0.0) {
        return Err(invalid(
            "length_px",
            format!("must be a positive number of pixels, got {length}"),
        ));
    }
    if options.per_vanishing_point < 2 {
        return Err(invalid(
            "per_vanishing_point",
            format!(
                "at least 2 edges fix a vanishing point, got {}",
                options.per_vanishing_point
            ),
        ));
    }
    if !(0.0..=0.25).contains(&options.inset) {
        return Err(invalid(
            "inset",
            format!("must lie in [0, 0.25], got {}", options.inset),
        ));
    }
    let w = f64::from(camera.image.width);
    let h = f64::from(camera.image.height);
    let (x0, x1) = (options.inset * w, (1.0 - options.inset) * w);
    let (y0, y1) = (options.inset * h, (1.0 - options.inset) * h);
    let (right, down, forward) = camera.axes();
    let f = camera.focal_px;
    let pp = camera.principal_point_px;
    let ray = |pixel: Vector2<f64>| {
        let q = (pixel - pp) / f;
        right * q.x + down * q.y + forward
    };
    let mut out = Vec::with_capacity(directions.len());
    for (k, &dir) in directions.iter().enumerate() {
        let norm = dir.norm();
        if !(norm.is_finite() && norm > 0.0) {
            return Err(invalid(
                "directions",
                format!("direction {} is not a non-zero vector", k + 1),
            ));
        }
        let u = dir / norm;
        // The vanishing point in homogeneous pixels: (vxy, w), at infinity when w = 0.
        let w_h = u.dot(&forward);
        let v_xy = Vector2::new(u.dot(&right), u.dot(&down)) * f + pp * w_h;
        let mut edges = Vec::with_capacity(options.per_vanishing_point);
        let mut attempts = 0;
        while edges.len() < options.per_vanishing_point {
            attempts += 1;
            if attempts > LONG_EDGE_ATTEMPTS * options.per_vanishing_point {
                return Err(MetrologyError::Degenerate {
                    field: "long_edges.length_px".to_owned(),
                    reason: format!(
                        "no line through vanishing point {} has {length} px inside the image ({} x {} less {} %) in {} attempts; ask for shorter edges",
                        k + 1,
                        camera.image.width,
                        camera.image.height,
                        options.inset * 100.0,
                        LONG_EDGE_ATTEMPTS * options.per_vanishing_point
                    ),
                });
            }
            let c = Vector2::new(rng.random_range(x0..=x1), rng.random_range(y0..=y1));
            // Direction along the image line, pointing away from the vanishing point.
            let away = c * w_h - v_xy;
            let away = if w_h < 0.0 { -away } else { away };
            let e_norm = away.norm();
            if !(e_norm.is_finite() && e_norm > 1e-9 * f) {
                continue; // c is the vanishing point itself
            }
            let e = away / e_norm;
            // The stretch c + s e inside the inset image ...
            let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
            for (from, to, at, step) in [(x0, x1, c.x, e.x), (y0, y1, c.y, e.y)] {
                if step.abs() <= f64::EPSILON {
                    continue;
                }
                let (a, b) = ((from - at) / step, (to - at) / step);
                lo = lo.max(a.min(b));
                hi = hi.min(a.max(b));
            }
            // ... and on the vanishing point's far side (in front of the camera), a pixel
            // clear of it.
            if w_h != 0.0 {
                let v = v_xy / w_h;
                lo = lo.max((v - c).dot(&e) + 1.0);
            }
            // (`hi - length < lo` also when `hi - lo` rounds to `length`: an empty range.)
            let last_start = hi - length;
            if hi - lo < length || last_start < lo {
                continue;
            }
            let start = rng.random_range(lo..=last_start);
            // The 3D line through the point one camera height along c's ray.
            let eye = camera.centre();
            let through = eye + ray(c) * camera.height_m;
            let on_line = |pixel: Vector2<f64>| {
                let r = ray(pixel);
                let ur = u.cross(&r);
                let t = -(through - eye).cross(&r).dot(&ur) / ur.norm_squared();
                camera.project(through + u * t)
            };
            let (Some(a), Some(b)) = (on_line(c + e * start), on_line(c + e * (start + length)))
            else {
                continue;
            };
            edges.push([a.x, a.y, b.x, b.y]);
        }
        out.push(edges);
    }
    Ok(out)
}

/// Add Gaussian noise of standard deviation `sigma_px` to every clicked point of a scene: box
/// corners and tops, footprint vertices, floor corners, and the end points of vanishing-point
/// lines. A vanishing point given as a point is left alone: it is not clicked but computed, often
/// far outside the image, where a pixel of error means nothing; its error comes from the lines
/// it is fitted to. The clicked points are jittered in that order, so a scene's object and floor
/// noise does not depend on whether it carries vanishing-point lines.
pub fn add_noise(scene: &mut Scene, sigma_px: f64, rng: &mut impl Rng) {
    if sigma_px <= 0.0 {
        return;
    }
    let Ok(normal) = Normal::new(0.0, sigma_px) else {
        return;
    };
    let mut jitter = |p: &mut [f64]| {
        for v in p {
            *v += normal.sample(rng);
        }
    };
    for o in &mut scene.objects {
        if let Some(b) = &mut o.base {
            for p in b.points_mut() {
                jitter(p);
            }
        }
        if let Some(f) = &mut o.footprint {
            for p in f {
                jitter(p);
            }
        }
        if let Some(t) = &mut o.top {
            for p in t.corners.points_mut() {
                jitter(p);
            }
            if let Some(p) = &mut t.point {
                jitter(p);
            }
        }
    }
    for p in &mut scene.floor {
        jitter(p);
    }
    for vp in &mut scene.vanishing_points {
        for l in &mut vp.lines {
            jitter(l);
        }
    }
}

/// A random Manhattan room seen by a camera as set in the options: boxes of random size and
/// height (some taller than the camera, so their tops lie above the horizon), pentagonal
/// prisms, and the room's floor outline cut at the nearest floor line the image shows. Every
/// object base corner lies inside the image; floor corners may lie outside it (a user would
/// extrapolate them), but always in front of the camera.
///
/// The scene is a pure function of the options.
///
/// # Errors
/// [`MetrologyError::InvalidField`] for options out of range, and
/// [`MetrologyError::Degenerate`] when the objects cannot be placed apart from each other in
/// the camera's view (too many, or a camera that sees too little floor) within 200 attempts.
pub fn synthesize(options: &SynthOptions) -> Result<(Scene, Truth)> {
    let bad = |field: &str, reason: String| {
        Err(MetrologyError::InvalidField {
            field: field.to_owned(),
            reason,
        })
    };
    for (field, v) in [
        ("focal_px", options.focal_px),
        ("height_m", options.height_m),
    ] {
        if !(v.is_finite() && v > 0.0) {
            return bad(field, format!("must be positive, got {v}"));
        }
    }
    if !(options.pitch_deg.is_finite() && options.pitch_deg.abs() < 80.0) {
        return bad(
            "pitch_deg",
            format!("must lie in (-80, 80) degrees, got {}", options.pitch_deg),
        );
    }
    if !(options.roll_deg.is_finite() && options.roll_deg.abs() < 45.0) {
        return bad(
            "roll_deg",
            format!("must lie in (-45, 45) degrees, got {}", options.roll_deg),
        );
    }
    if !(options.noise_px.is_finite() && options.noise_px >= 0.0) {
        return bad(
            "noise_px",
            format!("must be a non-negative number, got {}", options.noise_px),
        );
    }
    let mut rng = ChaCha8Rng::seed_from_u64(options.seed);
    for _ in 0..200 {
        if let Some(out) = try_synthesize(options, &mut rng) {
            return Ok(out);
        }
    }
    Err(MetrologyError::Degenerate {
        field: "synth".to_owned(),
        reason: format!(
            "could not place {} boxes and {} prisms apart from each other in the camera's view in 200 attempts: ask for fewer objects, or a camera that sees more floor (looking down, not up)",
            options.boxes, options.prisms
        ),
    })
}

fn try_synthesize(options: &SynthOptions, rng: &mut ChaCha8Rng) -> Option<(Scene, Truth)> {
    let camera = PinholeCamera {
        image: options.image,
        focal_px: options.focal_px,
        principal_point_px: options.image.centre()
            + if options.with_principal_point {
                Vector2::new(rng.random_range(-20.0..20.0), rng.random_range(-20.0..20.0))
            } else {
                Vector2::zeros()
            },
        height_m: options.height_m,
        pitch_rad: options.pitch_deg.to_radians(),
        roll_rad: options.roll_deg.to_radians(),
    };
    let yaw = if options.annotation == Annotation::FaceOn {
        // Nearly square to the viewing direction, never exactly: a two-point camera's focal
        // length is fixed by its horizontal vanishing points only while both are finite.
        let turn = rng.random_range(3f64..10.0);
        (if rng.random_bool(0.5) { turn } else { -turn }).to_radians()
    } else {
        rng.random_range(20f64..70.0).to_radians()
    };
    let a = Vector2::new(yaw.cos(), yaw.sin());
    let b = Vector2::new(-yaw.sin(), yaw.cos());
    let axes = [Vector3::new(a.x, a.y, 0.0), Vector3::new(b.x, b.y, 0.0)];
    let w = f64::from(options.image.width);
    let h = f64::from(options.image.height);
    // The floor region the image shows: the horizon's image row, clamped into the image.
    // The horizon's row straight ahead of the camera.
    let horizon_y = camera
        .vanishing_point(Vector3::new(0.0, 1.0, 0.0))
        .map_or(0.0, |v| v.y)
        .clamp(0.0, 0.9 * h);
    let sample_floor = |rng: &mut ChaCha8Rng| -> Option<Vector2<f64>> {
        let top = horizon_y + 0.25 * (h - horizon_y);
        let px = Vector2::new(
            rng.random_range(0.1 * w..0.9 * w),
            rng.random_range(top..0.95 * h),
        );
        camera.floor_point(px)
    };
    let inside = |p: Vector2<f64>| {
        camera
            .project(Vector3::new(p.x, p.y, 0.0))
            .is_some_and(|q| camera.in_image(q))
    };
    let mut boxes: Vec<SynthBox> = Vec::new();
    let mut tries = 0;
    while boxes.len() < options.boxes {
        tries += 1;
        if tries > 2000 {
            return None;
        }
        let c = sample_floor(rng)?;
        let s = options.height_m;
        let (side_a, side_b) = (
            rng.random_range(0.15 * s..0.8 * s),
            rng.random_range(0.15 * s..0.8 * s),
        );
        // Views that show the top face need boxes lower than the camera.
        let tallest = match options.annotation {
            Annotation::Thesis | Annotation::OwnYaw => 1.4,
            Annotation::FaceOn | Annotation::HiddenBase => 0.8,
        };
        let height_m = rng.random_range(0.1 * s..tallest * s);
        let (ea, eb) = if options.annotation == Annotation::OwnYaw && boxes.len() % 2 == 1 {
            let turn = rng.random_range(15f64..40.0).to_radians();
            let turn = if rng.random_bool(0.5) { turn } else { -turn };
            let (sin, cos) = turn.sin_cos();
            let rotate =
                |v: Vector2<f64>| Vector2::new(cos * v.x - sin * v.y, sin * v.x + cos * v.y);
            (rotate(a), rotate(b))
        } else {
            (a, b)
        };
        let bx = SynthBox {
            name: format!("box{}", boxes.len()),
            corner: c,
            edge_a: ea * side_a,
            edge_b: eb * side_b,
            height_m,
        };
        if bx.corners().iter().all(|p| inside(*p))
            && clear_of(&bx.corners(), &boxes, &[], 0.1 * s)
            && bx
                .corners()
                .iter()
                .all(|p| camera.depth(Vector3::new(p.x, p.y, bx.height_m)) > 0.05 * s)
        {
            boxes.push(bx);
        }
    }
    let mut prisms: Vec<SynthPrism> = Vec::new();
    tries = 0;
    while prisms.len() < options.prisms {
        tries += 1;
        if tries > 2000 {
            return None;
        }
        let c = sample_floor(rng)?;
        let s = options.height_m;
        let radius = rng.random_range(0.1 * s..0.35 * s);
        let turn = rng.random_range(0.0..std::f64::consts::TAU);
        let mut footprint: Vec<Vector2<f64>> = (0..5)
            .map(|k| {
                let t = turn + f64::from(k) * std::f64::consts::TAU / 5.0;
                c + Vector2::new(t.cos(), t.sin()) * radius
            })
            .collect();
        // Start at the vertex nearest the camera, as a user would.
        let near = (0..5).min_by(|&i, &j| footprint[i].norm().total_cmp(&footprint[j].norm()))?;
        footprint.rotate_left(near);
        let prism = SynthPrism {
            name: format!("chair{}", prisms.len()),
            footprint,
            height_m: rng.random_range(0.3 * s..0.9 * s),
        };
        if prism.footprint.iter().all(|p| inside(*p))
            && clear_of(&prism.footprint, &boxes, &prisms, 0.1 * s)
        {
            prisms.push(prism);
        }
    }
    // Floor: the room rectangle around every object, cut at the image's bottom row.
    let all: Vec<Vector2<f64>> = boxes
        .iter()
        .flat_map(SynthBox::corners)
        .chain(prisms.iter().flat_map(|p| p.footprint.clone()))
        .collect();
    let (mut lo_a, mut hi_a, mut lo_b, mut hi_b) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for p in &all {
        lo_a = lo_a.min(p.dot(&a));
        hi_a = hi_a.max(p.dot(&a));
        lo_b = lo_b.min(p.dot(&b));
        hi_b = hi_b.max(p.dot(&b));
    }
    let margin = rng.random_range(0.3..1.0) * options.height_m;
    let rect = [
        a * (lo_a - margin) + b * (lo_b - margin),
        a * (hi_a + margin) + b * (lo_b - margin),
        a * (hi_a + margin) + b * (hi_b + margin),
        a * (lo_a - margin) + b * (hi_b + margin),
    ];
    // ... cut to the floor the image shows (2 % inside its borders), as a user would click it.
    let floor = clip_to_view(&camera, &rect, 0.02);
    if floor.len() < 3 {
        return None;
    }
    let annotations: Vec<BoxAnnotation> = (0..boxes.len())
        .map(|k| match options.annotation {
            Annotation::Thesis => BoxAnnotation::default(),
            Annotation::FaceOn => BoxAnnotation {
                clicks: BoxClicks::FaceOn,
                own_yaw: false,
            },
            Annotation::HiddenBase => BoxAnnotation {
                clicks: BoxClicks::HiddenBase,
                own_yaw: false,
            },
            Annotation::OwnYaw => BoxAnnotation {
                clicks: BoxClicks::Thesis,
                own_yaw: k % 2 == 1,
            },
        })
        .collect();
    let (mut scene, truth) =
        render_annotated(&camera, axes, &boxes, &annotations, &prisms, &floor)?;
    if options.with_principal_point {
        scene.principal_point = Some(arr(camera.principal_point_px));
    }
    if options.with_scale {
        scene.scale = Some(ScaleSpec {
            camera_height_m: Some(options.height_m),
            ..ScaleSpec::default()
        });
    }
    add_noise(&mut scene, options.noise_px, rng);
    if options.vanishing_points == VanishingPointForm::Lines {
        vanishing_points_as_lines(&mut scene);
    }
    Some((scene, truth))
}

/// Whether a footprint keeps at least `gap` from every box and prism placed so far.
fn clear_of(
    footprint: &[Vector2<f64>],
    boxes: &[SynthBox],
    prisms: &[SynthPrism],
    gap: f64,
) -> bool {
    use geo::{Distance, Euclidean, LineString, Polygon};
    let poly = |pts: &[Vector2<f64>]| {
        Polygon::new(
            LineString::from(pts.iter().map(|p| (p.x, p.y)).collect::<Vec<_>>()),
            vec![],
        )
    };
    let me = poly(footprint);
    boxes
        .iter()
        .map(|b| poly(&b.corners()))
        .chain(prisms.iter().map(|p| poly(&p.footprint)))
        .all(|other| Euclidean.distance(&me, &other) > gap)
}

/// Clip a convex polygon to the half-plane on `inside`'s side of the line through `a`, `b`.
fn clip_halfplane(
    poly: &[Vector2<f64>],
    a: Vector2<f64>,
    b: Vector2<f64>,
    inside: Vector2<f64>,
) -> Vec<Vector2<f64>> {
    let side = |p: Vector2<f64>| {
        let (d, e) = (b - a, p - a);
        d.x * e.y - d.y * e.x
    };
    let sign = side(inside).signum();
    let mut out = Vec::new();
    for i in 0..poly.len() {
        let p = poly[i];
        let q = poly[(i + 1) % poly.len()];
        let (sp, sq) = (side(p) * sign, side(q) * sign);
        if sp >= 0.0 {
            out.push(p);
        }
        if (sp >= 0.0) != (sq >= 0.0) {
            out.push(p + (q - p) * (sp / (sp - sq)));
        }
    }
    out
}

/// Clip a convex floor polygon to the floor the camera's image shows, `inset` (a fraction of
/// the image size) inside its borders: each border is a line on the floor (through the floor
/// points of two of its pixels below the horizon).
fn clip_to_view(camera: &PinholeCamera, poly: &[Vector2<f64>], inset: f64) -> Vec<Vector2<f64>> {
    let w = f64::from(camera.image.width);
    let h = f64::from(camera.image.height);
    let (x0, x1, y0, y1) = (inset * w, (1.0 - inset) * w, inset * h, (1.0 - inset) * h);
    let Some(inside) = camera.floor_point(Vector2::new(w / 2.0, 0.9 * h)) else {
        return poly.to_vec();
    };
    let borders = [
        (Vector2::new(x0, y0), Vector2::new(x0, y1)),
        (Vector2::new(x1, y0), Vector2::new(x1, y1)),
        (Vector2::new(x0, y0), Vector2::new(x1, y0)),
        (Vector2::new(x0, y1), Vector2::new(x1, y1)),
    ];
    let mut out = poly.to_vec();
    for (from, to) in borders {
        let on_floor: Vec<Vector2<f64>> = (0..=64)
            .filter_map(|k| camera.floor_point(from + (to - from) * (f64::from(k) / 64.0)))
            .collect();
        if let (Some(a), Some(b)) = (on_floor.first(), on_floor.last())
            && on_floor.len() >= 2
        {
            out = clip_halfplane(&out, *a, *b, inside);
        }
    }
    out
}

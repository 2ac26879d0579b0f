//! The joint model of a room's photos: every photo's camera (its own focal length, pitch,
//! roll, room yaw, principal point where fitted, and for photos after the first its place and
//! height on the floor) in one camera block, and every object once, in the first photo's map
//! frame, seen by one or more photos.
//!
//! Frame: the first photo's map frame ([`crate::fit`]'s: station point at the origin, `+y`
//! the first camera's horizontal viewing direction, `+z` up, unit the first camera's
//! height). Photo `p` stands at `position_p` (its station point) with height `h_p` (held at
//! the ratio of the two when photo `p` and the first both give their camera height in metres);
//! its own
//! map frame is turned by its heading `theta_p` from the first's. The room's directions are
//! one pair for all photos, so the heading is not a parameter of its own: photo `p`'s first
//! room direction is the first photo's turned by `quarter_p` quarter turns, which gives
//! `theta_p = yaw_1 + quarter_p pi/2 - yaw_p` from the photos' room yaws.

use nalgebra::{Matrix2, Vector2, Vector3};

use crate::fit::model::{BoxAxes, Camera, Part, VpEvidence, vp_residual_count, vp_residuals};
use crate::fit::solve::Model;
use crate::interrupt::Interrupt;

/// One photo's camera parameters in the camera block.
#[derive(Debug, Clone)]
pub(crate) struct PhotoBlock {
    /// Start of its parameters in the camera block.
    pub offset: usize,
    /// Its own camera's parameter count (4, or 6 with the principal point).
    pub camera_len: usize,
    /// The principal point when it is held.
    pub fixed_pp: Option<Vector2<f64>>,
    /// The pitch is held (two-point perspective: a level camera).
    pub fixed_pitch: bool,
    /// Photos after the first: its station point `x, y` and height follow its camera.
    pub posed: bool,
    /// A posed photo's height held at this many first camera heights (when both its photo and
    /// the first give their camera height in metres), instead of fitted.
    pub fixed_height: Option<f64>,
    /// Quarter turns from the first photo's first room direction to this photo's.
    pub quarter: u8,
    /// Its vanishing points' evidence, in its fit's order (horizontal, horizontal, up).
    pub vps: Vec<VpEvidence>,
}

impl PhotoBlock {
    /// Number of parameters.
    pub fn len(&self) -> usize {
        self.camera_len
            + match (self.posed, self.fixed_height) {
                (false, _) => 0,
                (true, Some(_)) => 2,
                (true, None) => 3,
            }
    }
}

/// A photo's camera placed in the room.
#[derive(Debug, Clone, Copy)]
pub(crate) struct View {
    /// The camera in its own map frame (unit: its own height).
    pub cam: Camera,
    /// Its station point in the room frame.
    pub position: Vector2<f64>,
    /// Its height above the floor, room units.
    pub height: f64,
    /// Its heading: the angle from the room frame's axes to its own map frame's, radians.
    pub heading_rad: f64,
    /// The heading's sine and cosine.
    heading_sin_cos: (f64, f64),
}

impl View {
    fn new(cam: Camera, position: Vector2<f64>, height: f64, heading_rad: f64) -> Self {
        Self {
            cam,
            position,
            height,
            heading_rad,
            heading_sin_cos: heading_rad.sin_cos(),
        }
    }

    /// A room-frame point in the photo's own map frame (unit: its own height).
    pub fn own_from_room(self, world: Vector3<f64>) -> Vector3<f64> {
        let d = Vector2::new(world.x, world.y) - self.position;
        let (s, c) = self.heading_sin_cos;
        let local = Vector2::new(c * d.x + s * d.y, -s * d.x + c * d.y);
        Vector3::new(local.x, local.y, world.z) / self.height
    }

    /// An own-frame floor point of the photo in the room frame.
    pub fn room_from_own(self, own: Vector2<f64>) -> Vector2<f64> {
        let (s, c) = self.heading_sin_cos;
        let p = own * self.height;
        self.position + Vector2::new(c * p.x - s * p.y, s * p.x + c * p.y)
    }

    /// The pixel a room-frame point projects to, or `None` behind the camera.
    pub fn project(&self, world: Vector3<f64>) -> Option<Vector2<f64>> {
        self.cam.project(self.own_from_room(world))
    }
}

/// Where on an object a clicked point lies.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Place {
    /// A box corner `(i, j, k)` on the room-frame box's axes and level.
    Corner(u8, u8, u8),
    /// A footprint vertex (room-frame index).
    Vertex(usize),
    /// The top point above a footprint vertex.
    Top(usize),
    /// A floor point.
    Point,
}

/// One clicked point of an object in one photo.
#[derive(Debug, Clone)]
pub(crate) struct Sighting {
    /// The photo, from 0.
    pub photo: usize,
    /// Which point of the object.
    pub place: Place,
    /// The clicked pixel.
    pub pixel: Vector2<f64>,
    /// The scene field of the click, e.g. `photos[1].objects[0].base.near`.
    pub field: String,
    /// The whitening of the click's covariance, when its photo gives one.
    pub weight: Option<Matrix2<f64>>,
}

/// An object's shape in the room frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Shape {
    /// A box: parameters origin corner `x, y`, sides `a, b`, then `h` when a top is
    /// clicked in some photo, then its own yaw when it has one (as [`Part::Box`]).
    Box {
        axes: BoxAxes,
        has_top: bool,
        own_yaw: bool,
    },
    /// A footprint prism of `n` vertices: parameters `x, y` per vertex, then `h` when a top
    /// is clicked.
    Footprint { n: usize, has_top: bool },
    /// A floor point: `x, y`.
    Point,
}

/// An object of the room: its shape and every photo's clicks of it.
#[derive(Debug, Clone)]
pub(crate) struct RoomPart {
    pub shape: Shape,
    pub sightings: Vec<Sighting>,
}

impl RoomPart {
    /// Number of parameters.
    pub fn len(&self) -> usize {
        match self.shape {
            Shape::Box {
                has_top, own_yaw, ..
            } => 4 + usize::from(has_top) + usize::from(own_yaw),
            Shape::Footprint { n, has_top } => 2 * n + usize::from(has_top),
            Shape::Point => 2,
        }
    }

    /// The room-frame point of `place` for parameters `p`; `room` is a camera whose room
    /// yaw is the room frame's (the first photo's own camera).
    pub fn point(&self, room: &Camera, p: &[f64], place: Place) -> Vector3<f64> {
        match (self.shape, place) {
            (
                Shape::Box {
                    axes,
                    has_top,
                    own_yaw,
                },
                Place::Corner(i, j, k),
            ) => Part::box_corner(room, axes, own_yaw, has_top, p, (i, j, k)),
            (Shape::Footprint { .. }, Place::Vertex(v)) => {
                Vector3::new(p[2 * v], p[2 * v + 1], 0.0)
            }
            (Shape::Footprint { n, .. }, Place::Top(v)) => {
                Vector3::new(p[2 * v], p[2 * v + 1], p[2 * n])
            }
            _ => Vector3::new(p[0], p[1], 0.0),
        }
    }
}

/// The least-squares problem of a room.
#[derive(Debug, Clone)]
pub(crate) struct RoomProblem {
    /// Each photo's block, in photo order.
    pub photos: Vec<PhotoBlock>,
    /// Size of the camera block.
    pub camera_len: usize,
    /// The objects and floor points.
    pub parts: Vec<RoomPart>,
    /// Start of each part's parameters.
    pub offsets: Vec<usize>,
    /// Camera groups: `(photo, vanishing point)`.
    pub groups: Vec<(usize, usize)>,
    /// Stops the fit: once it fires, every evaluation fails (no cameras), so that
    /// the minimiser (`fit::solve::minimise`) returns at its next step.
    pub interrupt: Interrupt,
}

impl RoomProblem {
    /// Assemble from the photos' blocks (offsets are set here) and the parts.
    pub fn new(mut photos: Vec<PhotoBlock>, parts: Vec<RoomPart>) -> Self {
        let mut at = 0;
        for b in &mut photos {
            b.offset = at;
            at += b.len();
        }
        let camera_len = at;
        let mut offsets = Vec::with_capacity(parts.len());
        for p in &parts {
            offsets.push(at);
            at += p.len();
        }
        let groups = photos
            .iter()
            .enumerate()
            .flat_map(|(k, b)| (0..b.vps.len()).map(move |g| (k, g)))
            .collect();
        Self {
            photos,
            camera_len,
            parts,
            offsets,
            groups,
            interrupt: Interrupt::default(),
        }
    }

    /// Photo `k`'s own camera for camera block `c`.
    pub fn camera(&self, c: &[f64], k: usize) -> Camera {
        let b = &self.photos[k];
        Camera::from_params(&c[b.offset..b.offset + b.camera_len], b.fixed_pp)
    }

    /// Every photo placed in the room, for camera block `c`.
    pub fn views(&self, c: &[f64]) -> Vec<View> {
        (0..self.photos.len()).map(|k| self.view(c, k)).collect()
    }

    /// Photo `k` placed in the room, for camera block `c`.
    pub fn view(&self, c: &[f64], k: usize) -> View {
        let b = &self.photos[k];
        let cam = self.camera(c, k);
        if !b.posed {
            return View::new(cam, Vector2::zeros(), 1.0, 0.0);
        }
        let at = b.offset + b.camera_len;
        // The first photo's room yaw (its camera's fourth parameter).
        let first_yaw = c[self.photos[0].offset + 3];
        View::new(
            cam,
            Vector2::new(c[at], c[at + 1]),
            b.fixed_height.unwrap_or_else(|| c[at + 2]),
            first_yaw + f64::from(b.quarter) * std::f64::consts::FRAC_PI_2 - cam.room_yaw_rad,
        )
    }

    /// The photo whose camera block holds parameter `c`.
    fn photo_of(&self, c: usize) -> usize {
        self.photos.iter().rposition(|b| b.offset <= c).unwrap_or(0)
    }

    /// Part `i`'s parameters in `x`.
    pub fn part_params<'a>(&self, x: &'a [f64], i: usize) -> &'a [f64] {
        &x[self.offsets[i]..self.offsets[i] + self.parts[i].len()]
    }
}

impl Model for RoomProblem {
    fn camera_len(&self) -> usize {
        self.camera_len
    }

    fn camera_fixed(&self, c: usize) -> bool {
        self.photos
            .iter()
            .any(|b| b.fixed_pitch && c == b.offset + 1)
    }

    fn part_count(&self) -> usize {
        self.parts.len()
    }

    fn part_offset(&self, i: usize) -> usize {
        self.offsets[i]
    }

    fn part_len(&self, i: usize) -> usize {
        self.parts[i].len()
    }

    fn part_residual_count(&self, i: usize) -> usize {
        2 * self.parts[i].sightings.len()
    }

    fn camera_group_count(&self) -> usize {
        self.groups.len()
    }

    fn camera_group_len(&self, g: usize) -> usize {
        let (k, v) = self.groups[g];
        vp_residual_count(&self.photos[k].vps[v])
    }

    fn camera_group_residuals(&self, g: usize, c: &[f64], out: &mut [f64]) {
        let (k, v) = self.groups[g];
        vp_residuals(&self.camera(c, k), v, &self.photos[k].vps[v], out);
    }

    fn has_click_covariances(&self) -> bool {
        self.parts
            .iter()
            .any(|p| p.sightings.iter().any(|s| s.weight.is_some()))
    }

    fn part_uses_camera(&self, i: usize, c: usize) -> bool {
        let photo = self.photo_of(c);
        let seen = |k: usize| self.parts[i].sightings.iter().any(|s| s.photo == k);
        // The first photo's room yaw sets the room's directions (a box's axes, every
        // heading); the rest of its camera only what the first photo shows.
        seen(photo) || (photo == 0 && c == self.photos[0].offset + 3)
    }

    type Cameras = Vec<View>;

    fn cameras(&self, c: &[f64]) -> Vec<View> {
        // No cameras: every part's residuals fail, and the minimiser stops.
        if self.interrupt.check().is_some() {
            return Vec::new();
        }
        self.views(c)
    }

    fn part_residuals_with(&self, i: usize, views: &Vec<View>, p: &[f64], out: &mut [f64]) -> bool {
        let part = &self.parts[i];
        let Some(room) = views.first().map(|v| v.cam) else {
            return false;
        };
        for (n, s) in part.sightings.iter().enumerate() {
            let Some(v) = views.get(s.photo) else {
                return false;
            };
            let Some(q) = v.project(part.point(&room, p, s.place)) else {
                return false;
            };
            let r = Vector2::new(q.x - s.pixel.x, q.y - s.pixel.y);
            let r = s.weight.map_or(r, |w| w * r);
            out[2 * n] = r.x;
            out[2 * n + 1] = r.y;
        }
        true
    }
}

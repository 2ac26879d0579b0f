//! A random room photographed several times: [`synthesize_room`] places a rectangular room
//! aligned with its Manhattan axes, boxes aligned with the room, and up to eight cameras standing
//! near the room's corners looking in (two a corner at most), and annotates each photo as a single-photo scene through
//! the same independent pinhole camera as [`synthesize`](super::synthesize).
//!
//! # Frames
//! The room is drawn in its own frame (`x`, `y` along its walls, corner at the origin). Each
//! camera stands at `position` on the floor with `heading` (radians counter-clockwise from the
//! room's `+y`); a photo is rendered by moving the room into the camera's plan frame (origin on
//! the floor under the camera, `x` right, `y` forward), where [`PinholeCamera`] stands. The truth
//! ([`RoomTruth`]) is written in the first photo's plan frame, the frame of the room's map;
//! headings in it turn counter-clockwise from `+y`, as the map's `cameras[].heading_deg`.
//!
//! # The room
//! 4-7 m a side (times `sqrt(boxes / 6)` for more than six boxes); boxes 0.3-1.2 m a side and 0.2-1.0 m high (furniture lower than every
//! camera: tables, beds, cabinets), at least 0.3 m apart, inside the middle 60 % of the room
//! on each axis. Cameras 0.3-0.9 m from two walls near a corner (the first at a random
//! corner, the second at the opposite one, then the other two; photos 5-8 go round the corners
//! again in the same order, each from its own spot, height, pitch and focal length), looking at
//! the room's centre turned by up to 12 degrees, at least 15 degrees off both room axes. A room
//! of one to four photos is the same room whatever the most photos allowed (the random draws of
//! photos 5-8 come after theirs).
//!
//! # What each photo shows
//! A box is listed in a photo when its four base corners lie inside the image (2 % margin) and
//! its top is in front of the camera; it is clicked in the thesis's corner view (base near,
//! right, left; top near, left), named as that photo shows it. The floor outline is the room's
//! rectangle clipped to the floor the image shows. The first photo lists at least two, and every later photo shares at least two boxes with
//! the photos before it, so the joint fit is tied. A box no photo lists is left out of the
//! truth. Boxes do not hide each other (no occlusion is simulated: a box behind another is
//! still clicked). Only the first photo carries the scale
//! (`camera_height_m`) unless [`RoomSynthOptions::scale_every_photo`].

use nalgebra::{Vector2, Vector3};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use super::annotate::{BoxAnnotation, render_annotated};
use super::camera::PinholeCamera;
use super::noise::add_noise;
use super::random_scene::{VanishingPointForm, clip_to_view};
use super::truth::{SynthBox, Truth};
use super::vp_edges::vanishing_points_as_lines;
use crate::error::{MetrologyError, Result};
use crate::scene::{ImageSize, ScaleSpec, Scene};

/// Most photos of a synthetic room (two per corner of the room).
pub const MAX_ROOM_PHOTOS: usize = 8;

/// Attempts at drawing a room before [`synthesize_room`] gives up.
const ROOM_ATTEMPTS: usize = 500;

/// How far inside the image's borders a photo's floor outline runs, as a fraction of the
/// image's size (the floor outline is the room clipped to that part of the image).
pub const FLOOR_OUTLINE_INSET: f64 = 0.02;

/// Fewest boxes a later photo shares with the photos before it (and the first photo shows).
const MIN_SHARED_BOXES: usize = 2;

/// Smallest angle, degrees, between a camera's viewing direction and either room axis (modulo
/// 90): both horizontal vanishing points stay at a finite, well-conditioned place.
const MIN_AXIS_ANGLE_DEG: f64 = 15.0;

/// Options of [`synthesize_room`].
#[derive(Debug, Clone, PartialEq)]
pub struct RoomSynthOptions {
    /// Random seed (the room is a pure function of the options).
    pub seed: u64,
    /// Number of photos, 1 to [`MAX_ROOM_PHOTOS`] (one: the room as its first camera sees it,
    /// not [`synthesize`](super::synthesize)'s scene).
    pub photos: usize,
    /// Number of boxes in the room.
    pub boxes: usize,
    /// Gaussian noise on every annotated point of every photo, pixels (standard deviation).
    pub noise_px: f64,
    /// How vanishing points are given in every photo.
    pub vanishing_points: VanishingPointForm,
    /// Write `scale.camera_height_m` into every photo, not only the first.
    pub scale_every_photo: bool,
    /// Image size of every photo.
    pub image: ImageSize,
}

impl Default for RoomSynthOptions {
    fn default() -> Self {
        Self {
            seed: 0,
            photos: 3,
            boxes: 6,
            noise_px: 0.0,
            vanishing_points: VanishingPointForm::Points,
            scale_every_photo: false,
            image: ImageSize {
                width: 1600,
                height: 1200,
            },
        }
    }
}

/// The truth of a synthetic room, in the first photo's plan frame (metres).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RoomTruth {
    /// What the frame is.
    pub frame: String,
    /// The room's floor rectangle, four corners in order.
    pub room: Vec<[f64; 2]>,
    /// Every box once.
    pub objects: Vec<RoomTruthObject>,
    /// Every camera, in photo order.
    pub cameras: Vec<RoomTruthCamera>,
    /// Each photo's own truth, in that photo's plan frame (what a map of that photo alone
    /// should show; its objects in the order of that photo's scene).
    pub photos: Vec<Truth>,
}

/// One true box of a room.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RoomTruthObject {
    /// Name (the same in every photo that lists it).
    pub name: String,
    /// The four base corners in order around the box, metres.
    pub footprint: Vec<[f64; 2]>,
    /// Height, metres.
    pub height: f64,
    /// The two sides, shorter first, metres.
    pub size: [f64; 2],
    /// The photos (0-based) that list it.
    pub photos: Vec<usize>,
}

/// One true camera of a room.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RoomTruthCamera {
    /// The station point (the floor under the camera), metres.
    pub position: [f64; 2],
    /// Height above the floor, metres.
    pub height: f64,
    /// Viewing direction on the floor, degrees counter-clockwise from `+y`.
    pub heading_deg: f64,
    /// Focal length, pixels.
    pub focal_px: f64,
    /// Pitch, degrees, positive looking down.
    pub pitch_deg: f64,
    /// Roll, degrees.
    pub roll_deg: f64,
}

/// A camera standing in the room's frame.
struct Placed {
    camera: PinholeCamera,
    /// Station point in the room's frame.
    position: Vector2<f64>,
    /// Heading, radians counter-clockwise from the room's `+y`.
    heading: f64,
}

impl Placed {
    /// The camera's right and forward directions on the floor, in the room's frame.
    fn axes(&self) -> (Vector2<f64>, Vector2<f64>) {
        let (s, c) = self.heading.sin_cos();
        (Vector2::new(c, s), Vector2::new(-s, c))
    }

    /// A floor point of the room's frame in the camera's plan frame.
    fn to_plan(&self, p: Vector2<f64>) -> Vector2<f64> {
        let (right, forward) = self.axes();
        let d = p - self.position;
        Vector2::new(d.dot(&right), d.dot(&forward))
    }

    /// A direction of the room's frame in the camera's plan frame.
    fn direction_to_plan(&self, v: Vector2<f64>) -> Vector2<f64> {
        let (right, forward) = self.axes();
        Vector2::new(v.dot(&right), v.dot(&forward))
    }

    /// A box of the room's frame in the camera's plan frame.
    fn box_to_plan(&self, b: &SynthBox) -> SynthBox {
        SynthBox {
            name: b.name.clone(),
            corner: self.to_plan(b.corner),
            edge_a: self.direction_to_plan(b.edge_a),
            edge_b: self.direction_to_plan(b.edge_b),
            height_m: b.height_m,
        }
    }

    /// Whether the box, in the camera's plan frame, shows as the photo needs: every base
    /// corner inside the image (2 % margin) and well in front, its top in front.
    fn shows(&self, b: &SynthBox) -> bool {
        let cam = &self.camera;
        let (w, h) = (f64::from(cam.image.width), f64::from(cam.image.height));
        b.corners().iter().all(|c| {
            let base = Vector3::new(c.x, c.y, 0.0);
            cam.depth(base) > 0.3
                && cam.depth(Vector3::new(c.x, c.y, b.height_m)) > 0.3
                && cam.project(base).is_some_and(|p| {
                    p.x >= 0.02 * w && p.x <= 0.98 * w && p.y >= 0.02 * h && p.y <= 0.98 * h
                })
        })
    }
}

/// A random room photographed `photos` times (see the module's documentation): the room as a
/// scene (the first photo with the others in [`Scene::other_photos`], as
/// [`Scene::from_json_str`] reads a room file) and its truth.
///
/// # Errors
/// [`MetrologyError::InvalidField`] for options out of range, and
/// [`MetrologyError::Degenerate`] when no room with every box shown and every photo tied is
/// drawn in 500 attempts (too many boxes).
pub fn synthesize_room(options: &RoomSynthOptions) -> Result<(Scene, RoomTruth)> {
    if !(1..=MAX_ROOM_PHOTOS).contains(&options.photos) {
        return Err(MetrologyError::InvalidField {
            field: "photos".to_owned(),
            reason: format!(
                "must be from 1 to {MAX_ROOM_PHOTOS}, got {}",
                options.photos
            ),
        });
    }
    if !(options.noise_px.is_finite() && options.noise_px >= 0.0) {
        return Err(MetrologyError::InvalidField {
            field: "noise_px".to_owned(),
            reason: format!("must be a non-negative number, got {}", options.noise_px),
        });
    }
    if options.boxes < MIN_SHARED_BOXES {
        return Err(MetrologyError::InvalidField {
            field: "boxes".to_owned(),
            reason: format!(
                "a room needs at least {MIN_SHARED_BOXES} boxes (to tie its photos), got {}",
                options.boxes
            ),
        });
    }
    let mut rng = ChaCha8Rng::seed_from_u64(options.seed);
    for _ in 0..ROOM_ATTEMPTS {
        if let Some(out) = try_room(options, &mut rng) {
            return Ok(out);
        }
    }
    Err(MetrologyError::Degenerate {
        field: "synth".to_owned(),
        reason: format!(
            "could not draw a room of {} boxes seen by {} tied photos in {ROOM_ATTEMPTS} attempts: ask for fewer boxes",
            options.boxes, options.photos
        ),
    })
}

const FRAME: &str =
    "first photo's plan frame: origin on the floor under camera 1, x right, y forward (metres)";

/// The two sides of a footprint's first corner, shorter first (a polygon's two first edges).
fn sides(footprint: &[[f64; 2]]) -> [f64; 2] {
    let len = |i: usize, j: usize| match (footprint.get(i), footprint.get(j)) {
        (Some(a), Some(b)) => (a[0] - b[0]).hypot(a[1] - b[1]),
        _ => f64::NAN,
    };
    let (a, b) = (len(0, 1), len(1, 2));
    [a.min(b), a.max(b)]
}

fn try_room(options: &RoomSynthOptions, rng: &mut ChaCha8Rng) -> Option<(Scene, RoomTruth)> {
    // More than six boxes need a larger room: its sides grow with the square root of the count.
    let grow = (options.boxes as f64 / 6.0).sqrt().max(1.0);
    let room = Vector2::new(
        rng.random_range(4.0..7.0) * grow,
        rng.random_range(4.0..7.0) * grow,
    );
    // Boxes along the walls' axes, apart from each other and from the walls.
    let mut boxes: Vec<SynthBox> = Vec::new();
    let mut tries = 0;
    while boxes.len() < options.boxes {
        tries += 1;
        if tries > 2000 {
            return None;
        }
        let (a, b) = (rng.random_range(0.3..1.2), rng.random_range(0.3..1.2));
        let corner = Vector2::new(
            rng.random_range(0.2 * room.x..0.8 * room.x - a),
            rng.random_range(0.2 * room.y..0.8 * room.y - b),
        );
        let bx = SynthBox {
            name: format!("box{}", boxes.len()),
            corner,
            edge_a: Vector2::new(a, 0.0),
            edge_b: Vector2::new(0.0, b),
            height_m: rng.random_range(0.2..1.0),
        };
        let gap = 0.3;
        let apart = boxes.iter().all(|o| {
            let (lo, hi) = (o.corner, o.corner + o.edge_a + o.edge_b);
            let (me_lo, me_hi) = (bx.corner, bx.corner + bx.edge_a + bx.edge_b);
            me_lo.x > hi.x + gap
                || me_hi.x + gap < lo.x
                || me_lo.y > hi.y + gap
                || me_hi.y + gap < lo.y
        });
        if apart {
            boxes.push(bx);
        }
    }
    // Cameras near the room's corners, the first at a random one, the second at the opposite,
    // then the other two; each looks at the room's centre, turned a little.
    let first = rng.random_range(0..4usize);
    let corners = [first, (first + 2) % 4, (first + 1) % 4, (first + 3) % 4];
    let order = corners.iter().chain(&corners);
    let centre = room / 2.0;
    let mut placed = Vec::with_capacity(options.photos);
    for &corner in order.take(options.photos) {
        let inset = Vector2::new(rng.random_range(0.3..0.9), rng.random_range(0.3..0.9));
        let position = Vector2::new(
            if corner == 1 || corner == 2 {
                room.x - inset.x
            } else {
                inset.x
            },
            if corner >= 2 {
                room.y - inset.y
            } else {
                inset.y
            },
        );
        let to_centre = centre - position;
        let heading =
            (-to_centre.x).atan2(to_centre.y) + rng.random_range(-12f64..12.0).to_radians();
        let off_axis = heading.to_degrees().rem_euclid(90.0);
        if !(MIN_AXIS_ANGLE_DEG..=90.0 - MIN_AXIS_ANGLE_DEG).contains(&off_axis) {
            return None;
        }
        let camera = PinholeCamera {
            image: options.image,
            focal_px: rng.random_range(700.0..1300.0),
            principal_point_px: options.image.centre(),
            height_m: rng.random_range(1.1..1.7),
            pitch_rad: rng.random_range(8f64..35.0).to_radians(),
            roll_rad: rng.random_range(-4f64..4.0).to_radians(),
        };
        placed.push(Placed {
            camera,
            position,
            heading,
        });
    }
    // Which photo lists which box; every box listed, every photo tied.
    let shows: Vec<Vec<bool>> = placed
        .iter()
        .map(|p| boxes.iter().map(|b| p.shows(&p.box_to_plan(b))).collect())
        .collect();
    let mut seen = vec![false; boxes.len()];
    for (k, row) in shows.iter().enumerate() {
        let shared = row
            .iter()
            .zip(&seen)
            .filter(|(s, e)| **s && (**e || k == 0))
            .count();
        if shared < MIN_SHARED_BOXES {
            return None;
        }
        for (e, s) in seen.iter_mut().zip(row) {
            *e |= *s;
        }
    }
    // A box no photo lists is no part of the room's truth (nothing would map it).
    if seen.iter().filter(|s| **s).count() < MIN_SHARED_BOXES {
        return None;
    }
    let rect = [
        Vector2::new(0.0, 0.0),
        Vector2::new(room.x, 0.0),
        room,
        Vector2::new(0.0, room.y),
    ];
    let mut photos = Vec::with_capacity(placed.len());
    let mut truths = Vec::with_capacity(placed.len());
    for (k, p) in placed.iter().enumerate() {
        let listed: Vec<SynthBox> = boxes
            .iter()
            .zip(&shows[k])
            .filter(|(_, s)| **s)
            .map(|(b, _)| p.box_to_plan(b))
            .collect();
        let rect_in_plan: Vec<Vector2<f64>> = rect.iter().map(|c| p.to_plan(*c)).collect();
        let floor = clip_to_view(&p.camera, &rect_in_plan, FLOOR_OUTLINE_INSET);
        if floor.len() < 3 {
            return None;
        }
        let axes = [
            p.direction_to_plan(Vector2::new(1.0, 0.0)),
            p.direction_to_plan(Vector2::new(0.0, 1.0)),
        ]
        .map(|v| Vector3::new(v.x, v.y, 0.0));
        let annotations = vec![BoxAnnotation::default(); listed.len()];
        let (mut scene, truth) =
            render_annotated(&p.camera, axes, &listed, &annotations, &[], &floor)?;
        if k == 0 || options.scale_every_photo {
            scene.scale = Some(ScaleSpec {
                camera_height_m: Some(p.camera.height_m),
                ..ScaleSpec::default()
            });
        }
        photos.push(scene);
        truths.push(truth);
    }
    // The clicks' noise, photo after photo, once the room is drawn.
    for scene in &mut photos {
        add_noise(scene, options.noise_px, rng);
        if options.vanishing_points == VanishingPointForm::Lines {
            vanishing_points_as_lines(scene);
        }
    }
    // The truth in the first photo's plan frame.
    let one = placed.first()?;
    let arr = |v: Vector2<f64>| [v.x, v.y];
    let objects = boxes
        .iter()
        .enumerate()
        .filter(|(i, _)| seen[*i])
        .map(|(i, b)| {
            let footprint: Vec<[f64; 2]> =
                b.corners().iter().map(|c| arr(one.to_plan(*c))).collect();
            RoomTruthObject {
                name: b.name.clone(),
                size: sides(&footprint),
                footprint,
                height: b.height_m,
                photos: (0..placed.len()).filter(|&k| shows[k][i]).collect(),
            }
        })
        .collect();
    let cameras = placed
        .iter()
        .map(|p| RoomTruthCamera {
            position: arr(one.to_plan(p.position)),
            height: p.camera.height_m,
            heading_deg: (p.heading - one.heading).to_degrees().rem_euclid(360.0),
            focal_px: p.camera.focal_px,
            pitch_deg: p.camera.pitch_rad.to_degrees(),
            roll_deg: p.camera.roll_rad.to_degrees(),
        })
        .collect();
    let mut photos = photos.into_iter();
    let mut scene = photos.next()?;
    scene.other_photos = photos.collect();
    Some((
        scene,
        RoomTruth {
            frame: FRAME.to_owned(),
            room: rect.iter().map(|c| arr(one.to_plan(*c))).collect(),
            objects,
            cameras,
            photos: truths,
        },
    ))
}

//! The room fit's start: each photo fitted alone, then placed in the first photo's frame as a
//! whole-room hypothesis (`room/hypotheses.rs`) has it.
//!
//! Placing photo `p` is a similarity on the floor: its heading follows from the room
//! directions up to a quarter turn (`quarter` in 0..4, the room's 90-degree ambiguity
//! between photos, which also decides which of a box's corners in one photo is which in the
//! other), its scale and station point from the hypothesis's least-squares placement. Here:
//! the photos' objects in the room frame ([`place_objects`], a box seen by several photos
//! started at the weighted mean of their placements, [`average_boxes`]), the footprints'
//! vertex correspondences ([`candidate_poses`]), and each photo's clicks as sightings of the
//! room's objects ([`sightings`]).

use nalgebra::Vector2;

use super::model::{PhotoBlock, Place, RoomPart, Shape, Sighting};
use crate::error::{MetrologyError, Result};
use crate::fit::Fitted;
use crate::fit::model::{BoxAxes, Camera, Part};
use crate::scene::Scene;

/// A photo's fit alone, with its boxes' sides made positive.
pub(crate) struct PhotoFit {
    pub fitted: Fitted,
    /// Per scene object: its part, parameters (sides positive) and clicks.
    pub objects: Vec<PhotoObject>,
}

/// One object as a photo's own fit has it (own frame, own camera height).
#[derive(Debug, Clone)]
pub(crate) struct PhotoObject {
    pub name: String,
    pub part: Part,
    pub params: Vec<f64>,
    /// Index in its photo's scene.
    pub index: usize,
    /// Per clicked point (in its part's residuals' order), its covariance's whitening.
    pub weights: Vec<Option<nalgebra::Matrix2<f64>>>,
}

/// Quarter-turn indices of a box's two axes: room direction `k` is quarter `k`, its opposite
/// `k + 2`.
fn quarters(axes: BoxAxes) -> (u8, u8) {
    let q = |k: usize, sign: f64| (k as u8 + if sign < 0.0 { 2 } else { 0 }) % 4;
    (q(axes.first, axes.sign1), q(1 - axes.first, axes.sign2))
}

/// Box axes from quarter-turn indices.
fn axes_of(q1: u8, q2: u8) -> BoxAxes {
    BoxAxes {
        first: usize::from(q1 % 2),
        sign1: if q1 >= 2 { -1.0 } else { 1.0 },
        sign2: if q2 >= 2 { -1.0 } else { 1.0 },
    }
}

/// A photo's box axes turned into the room frame by `quarter`.
pub(crate) fn room_axes(axes: BoxAxes, quarter: u8) -> BoxAxes {
    let (q1, q2) = quarters(axes);
    axes_of((q1 + quarter) % 4, (q2 + quarter) % 4)
}

/// The room-frame corner `(I, J)` of corner `(i, j)` of a photo's box whose axes, turned
/// into the room frame, are `photo` and the room-frame box's are `room` (both boxes with
/// positive sides).
pub(crate) fn corner_in_room(photo: BoxAxes, room: BoxAxes, i: u8, j: u8) -> (u8, u8) {
    let (p1, p2) = quarters(photo);
    let (r1, r2) = quarters(room);
    let mut out = (0, 0);
    for (q, v) in [(p1, i), (p2, j)] {
        if q == r1 {
            out.0 = v;
        } else if q == (r1 + 2) % 4 {
            out.0 = 1 - v;
        } else if q == r2 {
            out.1 = v;
        } else {
            out.1 = 1 - v;
        }
    }
    out
}

impl PhotoFit {
    /// The photo's fit, its boxes turned so both sides are positive (a negative side is the
    /// same box with that axis the other way round).
    pub fn new(fitted: Fitted, scene: &Scene) -> Self {
        let mut objects = Vec::with_capacity(scene.objects.len());
        for (index, o) in scene.objects.iter().enumerate() {
            let k = fitted.object_parts[index];
            let off = fitted.problem.offsets[k];
            let mut part = fitted.problem.parts[k].clone();
            let mut params = fitted.x[off..off + part.len()].to_vec();
            if let Part::Box { axes, .. } = &mut part {
                // A side `s < 0` along axis `e` is the side `-s` along `-e` from the same
                // origin: every corner, and so every click's place, stays where it was.
                // (Moving the origin by `s e` as well, as this once did, mirrored the box
                // about its origin's edge.)
                if params[2] < 0.0 {
                    params[2] = -params[2];
                    axes.sign1 = -axes.sign1;
                }
                if params[3] < 0.0 {
                    params[3] = -params[3];
                    axes.sign2 = -axes.sign2;
                }
            }
            let weights = fitted.problem.weights.get(k).cloned().unwrap_or_default();
            objects.push(PhotoObject {
                name: o.name.clone(),
                part,
                params,
                index,
                weights,
            });
        }
        Self { fitted, objects }
    }

    /// The photo's own camera.
    pub fn camera(&self) -> Camera {
        self.fitted.problem.camera(&self.fitted.x)
    }
}

/// A placed object: its room-frame shape, parameters, and where it came from.
#[derive(Debug, Clone)]
pub(crate) struct Placed {
    pub name: String,
    pub shape: Shape,
    pub params: Vec<f64>,
    /// Footprints: for each photo that shows it, the room-frame index of each of its
    /// vertices.
    pub vertex_maps: Vec<(usize, Vec<usize>)>,
}

/// A photo placed in the room: the similarity's start values and the quarter turn.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Pose {
    pub quarter: u8,
    pub heading_rad: f64,
    pub scale: f64,
    pub position: Vector2<f64>,
}

impl Pose {
    fn apply(&self, p: Vector2<f64>) -> Vector2<f64> {
        let (s, c) = self.heading_rad.sin_cos();
        self.position + Vector2::new(c * p.x - s * p.y, s * p.x + c * p.y) * self.scale
    }
}

/// Corresponding floor points (own frame of the photo, room frame) and heights.
#[derive(Default)]
struct Pairs {
    points: Vec<(Vector2<f64>, Vector2<f64>)>,
    heights: Vec<(f64, f64)>,
}

/// An object's floor corners (own frame), and its height if fitted.
pub(crate) fn own_corners(cam: &Camera, o: &PhotoObject) -> (Vec<Vector2<f64>>, Option<f64>) {
    match &o.part {
        Part::Box {
            axes,
            has_top,
            own_yaw,
            ..
        } => {
            let c = |i, j| {
                let v = Part::box_corner(cam, *axes, *own_yaw, *has_top, &o.params, (i, j, 0));
                Vector2::new(v.x, v.y)
            };
            (
                vec![c(0, 0), c(1, 0), c(1, 1), c(0, 1)],
                has_top.then(|| o.params[4]),
            )
        }
        Part::Footprint { vertices, top } => (
            (0..vertices.len())
                .map(|k| Vector2::new(o.params[2 * k], o.params[2 * k + 1]))
                .collect(),
            top.map(|_| o.params[2 * vertices.len()]),
        ),
        Part::FloorPoint { .. } => (vec![Vector2::new(o.params[0], o.params[1])], None),
    }
}

/// A room-frame object's floor corners in the order of [`own_corners`] for a box
/// (`(0,0), (1,0), (1,1), (0,1)`), and its height.
fn room_corner(room: &Camera, placed: &Placed, i: u8, j: u8) -> Vector2<f64> {
    let part = RoomPart {
        shape: placed.shape,
        sightings: Vec::new(),
    };
    let v = part.point(room, &placed.params, Place::Corner(i, j, 0));
    Vector2::new(v.x, v.y)
}

fn room_height(placed: &Placed) -> Option<f64> {
    match placed.shape {
        Shape::Box { has_top: true, .. } => Some(placed.params[4]),
        Shape::Footprint { n, has_top: true } => Some(placed.params[2 * n]),
        _ => None,
    }
}

/// Scale and translation taking `a` (turned own-frame points) onto `b`, with heights, and the
/// RMS misfit relative to the points' spread.
fn similarity(pairs: &Pairs, heading: f64) -> Option<(f64, Vector2<f64>, f64)> {
    let n = pairs.points.len();
    if n == 0 {
        return None;
    }
    let (s, c) = heading.sin_cos();
    let turned: Vec<(Vector2<f64>, Vector2<f64>)> = pairs
        .points
        .iter()
        .map(|(a, b)| (Vector2::new(c * a.x - s * a.y, s * a.x + c * a.y), *b))
        .collect();
    let ma = turned.iter().map(|p| p.0).sum::<Vector2<f64>>() / n as f64;
    let mb = turned.iter().map(|p| p.1).sum::<Vector2<f64>>() / n as f64;
    let mut num = 0.0;
    let mut den = 0.0;
    for (a, b) in &turned {
        num += (a - ma).dot(&(b - mb));
        den += (a - ma).norm_squared();
    }
    for (ha, hb) in &pairs.heights {
        num += ha * hb;
        den += ha * ha;
    }
    if den <= 0.0 {
        return None;
    }
    let k = num / den;
    if !(k.is_finite() && k > 0.0) {
        return None;
    }
    let t = mb - ma * k;
    let mut err = 0.0;
    let mut spread = 0.0;
    for (a, b) in &turned {
        err += (a * k + t - b).norm_squared();
        spread += (b - mb).norm_squared();
    }
    for (ha, hb) in &pairs.heights {
        err += (ha * k - hb).powi(2);
        spread += hb * hb;
    }
    Some((k, t, (err / spread.max(f64::MIN_POSITIVE)).sqrt()))
}

/// The best cyclic correspondence of a footprint's vertices to the room-frame ones: for each
/// own vertex, the room vertex index.
pub(crate) fn footprint_map(
    own: &[Vector2<f64>],
    room: &[Vector2<f64>],
    heading: f64,
) -> Option<(Vec<usize>, f64)> {
    let n = own.len();
    if n != room.len() || n == 0 {
        return None;
    }
    let mut best: Option<(Vec<usize>, f64)> = None;
    for shift in 0..n {
        for backwards in [false, true] {
            let map: Vec<usize> = (0..n)
                .map(|v| {
                    if backwards {
                        (shift + n - v) % n
                    } else {
                        (shift + v) % n
                    }
                })
                .collect();
            let pairs = Pairs {
                points: (0..n).map(|v| (own[v], room[map[v]])).collect(),
                heights: Vec::new(),
            };
            if let Some((_, _, r)) = similarity(&pairs, heading)
                && best.as_ref().is_none_or(|(_, b)| r < *b)
            {
                best = Some((map, r));
            }
        }
    }
    best
}

/// The photo's heading for a quarter turn.
pub(crate) fn heading(first_yaw: f64, own_yaw: f64, quarter: u8) -> f64 {
    first_yaw + f64::from(quarter) * std::f64::consts::FRAC_PI_2 - own_yaw
}

/// A pose for one quarter turn, its misfit, and the footprints' vertex maps under it.
pub(crate) type Candidate = (Pose, f64, Vec<(String, Vec<usize>)>);

/// Score every quarter turn of photo `fit` (or only `only`) against the placed objects:
/// `(quarter, pose, misfit)`, best first; and for each the footprints' vertex maps.
pub(crate) fn candidate_poses(
    fit: &PhotoFit,
    first_yaw: f64,
    room_cam: &Camera,
    placed: &[Placed],
    only: Option<u8>,
) -> Vec<Candidate> {
    let cam = fit.camera();
    let mut out = Vec::new();
    for quarter in (0..4u8).filter(|q| only.is_none_or(|o| o == *q)) {
        let th = heading(first_yaw, cam.room_yaw_rad, quarter);
        let mut pairs = Pairs::default();
        let mut maps = Vec::new();
        for o in &fit.objects {
            let Some(w) = placed.iter().find(|p| p.name == o.name) else {
                continue;
            };
            let (corners, h) = own_corners(&cam, o);
            match (&o.part, w.shape) {
                (Part::Box { axes, .. }, Shape::Box { axes: waxes, .. }) => {
                    let turned = room_axes(*axes, quarter);
                    for (k, (i, j)) in [(0u8, 0u8), (1, 0), (1, 1), (0, 1)].iter().enumerate() {
                        let (ii, jj) = corner_in_room(turned, waxes, *i, *j);
                        pairs
                            .points
                            .push((corners[k], room_corner(room_cam, w, ii, jj)));
                    }
                }
                (Part::Footprint { .. }, Shape::Footprint { n, .. }) => {
                    let room: Vec<Vector2<f64>> = (0..n)
                        .map(|v| Vector2::new(w.params[2 * v], w.params[2 * v + 1]))
                        .collect();
                    if let Some((map, _)) = footprint_map(&corners, &room, th) {
                        for (v, &r) in map.iter().enumerate() {
                            pairs.points.push((corners[v], room[r]));
                        }
                        maps.push((o.name.clone(), map));
                    }
                }
                _ => continue,
            }
            if let (Some(a), Some(b)) = (h, room_height(w)) {
                pairs.heights.push((a, b));
            }
        }
        if let Some((scale, position, misfit)) = similarity(&pairs, th) {
            out.push((
                Pose {
                    quarter,
                    heading_rad: th,
                    scale,
                    position,
                },
                misfit,
                maps,
            ));
        }
    }
    out.sort_by(|a, b| a.1.total_cmp(&b.1));
    out
}

/// Place a photo's objects not yet in the room (and add its estimates of heights and yaws
/// the room's objects lack).
pub(crate) fn place_objects(fit: &PhotoFit, pose: &Pose, placed: &mut Vec<Placed>, photo: usize) {
    let cam = fit.camera();
    for o in &fit.objects {
        let existing = placed.iter().position(|p| p.name == o.name);
        match (&o.part, existing) {
            (
                Part::Box {
                    axes,
                    has_top,
                    own_yaw,
                    ..
                },
                None,
            ) => {
                let origin = pose.apply(Vector2::new(o.params[0], o.params[1]));
                let mut params = vec![
                    origin.x,
                    origin.y,
                    o.params[2] * pose.scale,
                    o.params[3] * pose.scale,
                ];
                if *has_top {
                    params.push(o.params[4] * pose.scale);
                }
                if *own_yaw {
                    params.push(o.params[4 + usize::from(*has_top)]);
                }
                placed.push(Placed {
                    name: o.name.clone(),
                    shape: Shape::Box {
                        axes: room_axes(*axes, pose.quarter),
                        has_top: *has_top,
                        own_yaw: *own_yaw,
                    },
                    params,
                    vertex_maps: Vec::new(),
                });
            }
            (
                Part::Box {
                    has_top, own_yaw, ..
                },
                Some(k),
            ) => {
                // A top or an own yaw that only this photo shows.
                let w = &mut placed[k];
                if let Shape::Box {
                    has_top: wt,
                    own_yaw: wy,
                    ..
                } = &mut w.shape
                {
                    if *has_top && !*wt {
                        w.params.insert(4, o.params[4] * pose.scale);
                        *wt = true;
                    }
                    if *own_yaw && !*wy {
                        w.params.push(o.params[4 + usize::from(*has_top)]);
                        *wy = true;
                    }
                }
            }
            (Part::Footprint { vertices, top }, None) => {
                let (corners, h) = own_corners(&cam, o);
                let mut params = Vec::with_capacity(2 * vertices.len() + 1);
                for c in &corners {
                    let q = pose.apply(*c);
                    params.extend([q.x, q.y]);
                }
                if let Some(h) = h {
                    params.push(h * pose.scale);
                }
                placed.push(Placed {
                    name: o.name.clone(),
                    shape: Shape::Footprint {
                        n: vertices.len(),
                        has_top: top.is_some(),
                    },
                    params,
                    vertex_maps: vec![(photo, (0..vertices.len()).collect())],
                });
            }
            (
                Part::Footprint {
                    top: Some(_),
                    vertices,
                },
                Some(k),
            ) => {
                let w = &mut placed[k];
                if let Shape::Footprint { has_top, n } = &mut w.shape
                    && !*has_top
                {
                    w.params.push(o.params[2 * vertices.len()] * pose.scale);
                    *has_top = true;
                    let _ = n;
                }
            }
            _ => {}
        }
    }
}

/// The sightings of photo `photo`'s clicks of one placed object.
pub(crate) fn sightings(
    photo: usize,
    o: &PhotoObject,
    quarter: u8,
    placed: &Placed,
) -> Vec<Sighting> {
    let field = |name: &str| format!("photos[{photo}].objects[{}].{name}", o.index);
    let weight = |n: usize| o.weights.get(n).copied().flatten();
    match (&o.part, placed.shape) {
        (Part::Box { axes, clicks, .. }, Shape::Box { axes: waxes, .. }) => {
            let turned = room_axes(*axes, quarter);
            clicks
                .iter()
                .enumerate()
                .map(|(n, c)| {
                    let (i, j) = corner_in_room(turned, waxes, c.place.0, c.place.1);
                    Sighting {
                        photo,
                        place: Place::Corner(i, j, c.place.2),
                        pixel: c.pixel,
                        field: field(&c.name),
                        weight: weight(n),
                    }
                })
                .collect()
        }
        (Part::Footprint { vertices, top }, Shape::Footprint { .. }) => {
            let identity: Vec<usize> = (0..vertices.len()).collect();
            let map = placed
                .vertex_maps
                .iter()
                .find(|(p, _)| *p == photo)
                .map_or(&identity, |(_, m)| m);
            let mut out: Vec<Sighting> = vertices
                .iter()
                .enumerate()
                .map(|(v, px)| Sighting {
                    photo,
                    place: Place::Vertex(map[v]),
                    pixel: *px,
                    field: field(&format!("footprint[{v}]")),
                    weight: weight(v),
                })
                .collect();
            if let Some((above, px)) = top {
                out.push(Sighting {
                    photo,
                    place: Place::Top(map[*above]),
                    pixel: *px,
                    field: field("top.point"),
                    weight: weight(vertices.len()),
                });
            }
            out
        }
        _ => Vec::new(),
    }
}

/// Photo `k`'s camera block from its own fit, and its start values; `fixed_height` holds a
/// posed photo's height (first camera heights).
pub(crate) fn photo_block(
    fit: &PhotoFit,
    pose: Option<&Pose>,
    fixed_height: Option<f64>,
) -> (PhotoBlock, Vec<f64>) {
    let problem = &fit.fitted.problem;
    let mut x = fit.fitted.x[..problem.camera_len].to_vec();
    let fixed_height = pose.and(fixed_height);
    if let Some(p) = pose {
        x.extend([p.position.x, p.position.y]);
        if fixed_height.is_none() {
            x.push(p.scale);
        }
    }
    (
        PhotoBlock {
            offset: 0,
            camera_len: problem.camera_len,
            fixed_pp: problem.fixed_pp,
            fixed_pitch: problem.fixed_pitch,
            posed: pose.is_some(),
            fixed_height,
            quarter: pose.map_or(0, |p| p.quarter),
            vps: problem.vps.clone(),
        },
        x,
    )
}

/// An error of photo `k`'s own fit, naming the photo.
pub(crate) fn in_photo(k: usize, error: MetrologyError) -> MetrologyError {
    MetrologyError::InPhoto {
        photo: k,
        error: Box::new(error),
    }
}

/// The footprint vertex maps found for a photo, recorded on the placed objects.
pub(crate) fn record_maps(placed: &mut [Placed], photo: usize, maps: &[(String, Vec<usize>)]) {
    for (name, map) in maps {
        if let Some(p) = placed.iter_mut().find(|p| &p.name == name) {
            p.vertex_maps.push((photo, map.clone()));
        }
    }
}

/// `Result` helper for a placed object lookup.
pub(crate) fn placed_index(placed: &[Placed], name: &str) -> Result<usize> {
    placed
        .iter()
        .position(|p| p.name == name)
        .ok_or_else(|| MetrologyError::Degenerate {
            field: "photos".to_owned(),
            reason: format!("object {name:?} was not placed in the room"),
        })
}

/// The start of every room-aligned box seen by several photos: the weighted mean of its
/// corners as each placed photo sees them (each corner weighted by the inverse of its
/// depth's variance, `f^2 / (d^2 (1 + d^2) + 1)`), and of its height; a box placed from one
/// photo alone can start far off when that photo sees it from afar or with noisy clicks, and
/// the joint fit then runs into a point behind a camera or a poorer minimum.
pub(crate) fn average_boxes(fits: &[PhotoFit], poses: &[Option<Pose>], placed: &mut [Placed]) {
    let Some(room_cam) = fits.first().map(PhotoFit::camera) else {
        return;
    };
    for w in placed.iter_mut() {
        let Shape::Box {
            axes: waxes,
            has_top,
            own_yaw: false,
        } = w.shape
        else {
            continue;
        };
        // Per room-frame corner (i + 2 j): weighted sum and weight; the height likewise.
        let mut sums = [(Vector2::zeros(), 0.0); 4];
        let mut height = (0.0, 0.0);
        let mut seen = 0;
        for (k, fit) in fits.iter().enumerate() {
            let pose = match (k, poses.get(k).copied().flatten()) {
                (0, _) => Pose {
                    quarter: 0,
                    heading_rad: 0.0,
                    scale: 1.0,
                    position: Vector2::zeros(),
                },
                (_, Some(p)) => p,
                _ => continue,
            };
            let Some(o) = fit.objects.iter().find(|o| o.name == w.name) else {
                continue;
            };
            let Part::Box { axes, .. } = &o.part else {
                continue;
            };
            let cam = fit.camera();
            let (corners, h) = own_corners(&cam, o);
            let turned = room_axes(*axes, pose.quarter);
            let mut d_sum = 0.0;
            for (c, (i, j)) in corners.iter().zip([(0u8, 0u8), (1, 0), (1, 1), (0, 1)]) {
                let (ii, jj) = corner_in_room(turned, waxes, i, j);
                let d = c.norm();
                d_sum += d;
                let weight = cam.focal_px.powi(2) / (d * d * (1.0 + d * d) + 1.0);
                if let Some(s) = sums.get_mut(usize::from(ii) + 2 * usize::from(jj)) {
                    s.0 += pose.apply(*c) * weight;
                    s.1 += weight;
                }
            }
            if let Some(h) = h {
                let d = d_sum / 4.0;
                let weight = cam.focal_px.powi(2) / (d * d + 1.0);
                height.0 += h * pose.scale * weight;
                height.1 += weight;
            }
            seen += 1;
        }
        if seen < 2 || sums.iter().any(|s| s.1 <= 0.0) {
            continue;
        }
        let c: Vec<Vector2<f64>> = sums.iter().map(|s| s.0 / s.1).collect();
        let (e1, e2) = Part::box_axes(&room_cam, waxes, 0.0);
        let a = 0.5 * ((c[1] - c[0]).dot(&e1) + (c[3] - c[2]).dot(&e1));
        let b = 0.5 * ((c[2] - c[0]).dot(&e2) + (c[3] - c[1]).dot(&e2));
        if !(a > 0.0 && b > 0.0) {
            continue;
        }
        let origin = (c[0] + (c[1] - e1 * a) + (c[2] - e2 * b) + (c[3] - e1 * a - e2 * b)) / 4.0;
        if let Some(p) = w.params.get_mut(..4) {
            p.copy_from_slice(&[origin.x, origin.y, a, b]);
        }
        if has_top
            && height.1 > 0.0
            && let Some(p) = w.params.get_mut(4)
        {
            *p = height.0 / height.1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fit::{FitOptions, fit_scene};
    use crate::synth::{SynthOptions, synthesize};

    /// Each corner of each box of `fit`, in its own frame, keyed by the clicks' grid places:
    /// the point of every clicked base corner.
    fn clicked_corners(fit: &PhotoFit) -> Vec<Vector2<f64>> {
        let cam = fit.camera();
        let mut out = Vec::new();
        for o in &fit.objects {
            if let Part::Box {
                axes,
                clicks,
                own_yaw,
                has_top,
                ..
            } = &o.part
            {
                for c in clicks {
                    let v = Part::box_corner(&cam, *axes, *own_yaw, *has_top, &o.params, c.place);
                    out.push(Vector2::new(v.x, v.y));
                }
            }
        }
        out
    }

    #[test]
    fn a_fitted_box_with_a_negative_side_is_the_same_box_with_positive_sides() {
        // A fit may end with a box's side negative: side `-s` along axis `-e` is the same
        // box as side `s` along `e` from the same origin. Its photo's boxes are made positive
        // for the room fit, and every clicked corner must stay where the fit put it. Checked
        // against the same fit with the side positive, written the other way round by hand
        // (the part's axis sign and the side both negated; the clicks as they were).
        let scene = synthesize(&SynthOptions {
            seed: 3,
            ..SynthOptions::default()
        })
        .map_or_else(|e| panic!("{e}"), |(scene, _)| scene);
        let fitted = fit_scene(&scene, &FitOptions::default()).unwrap_or_else(|e| panic!("{e}"));
        let plain = PhotoFit::new(fitted.clone(), &scene);
        let mut flipped = fitted;
        let mut changed = 0;
        for k in 0..flipped.problem.parts.len() {
            let off = flipped.problem.offsets[k];
            let Part::Box { axes, .. } = &mut flipped.problem.parts[k] else {
                continue;
            };
            // The first box: its first side negative; the second: both.
            axes.sign1 = -axes.sign1;
            flipped.x[off + 2] = -flipped.x[off + 2];
            if changed == 1 {
                axes.sign2 = -axes.sign2;
                flipped.x[off + 3] = -flipped.x[off + 3];
            }
            changed += 1;
            if changed == 2 {
                break;
            }
        }
        assert_eq!(changed, 2, "the scene has two boxes");
        let turned = PhotoFit::new(flipped, &scene);
        let (a, b) = (clicked_corners(&plain), clicked_corners(&turned));
        assert_eq!(a.len(), b.len());
        assert!(!a.is_empty());
        for (p, q) in a.iter().zip(&b) {
            assert!((p - q).norm() < 1e-9, "{p} moved to {q}");
        }
        for o in &turned.objects {
            assert!(
                o.params
                    .get(2..4)
                    .is_none_or(|s| s.iter().all(|v| *v >= 0.0))
            );
        }
    }
}

//! What a synthetic user clicks: known boxes, prisms and a floor outline rendered through the
//! camera into a scene, each box annotated in one of the views ([`BoxClicks`]), with its truth.

use nalgebra::{Vector2, Vector3};

use super::camera::PinholeCamera;
use super::truth::{SynthBox, SynthPrism, Truth, TruthCamera, TruthObject};
use crate::scene::{BoxCorners, ObjectSpec, PixelPoint, Scene, TopSpec, VanishingPointSpec};

/// `[x, y]` of a vector: a pixel of the scene, or a floor point of the truth.
pub(super) fn arr(p: Vector2<f64>) -> PixelPoint {
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
/// [`BoxCorner::grid_index`](crate::scene::BoxCorner::grid_index) for the view its clicks
/// use: corner view near, right, far, left; face view front left, front right, back right,
/// back left. `None` when a corner is behind the camera.
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
/// corners in the order of [`BoxCorner::grid_index`](crate::scene::BoxCorner::grid_index)
/// for the view used: `(0, 0)`, `(1, 0)`, `(1, 1)`, `(0, 1)`, i.e. near, right, far, left or
/// front left, front right, back right, back left, the order the map reports them in.
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
            covariance_deg2: None,
        },
        VanishingPointSpec {
            point: Some(arr(camera.vanishing_point(room_axes[1])?)),
            lines: Vec::new(),
            direction: None,
            covariance_deg2: None,
        },
    ];
    if camera.pitch_rad.abs() > 1e-12 {
        vps.push(VanishingPointSpec {
            point: Some(arr(camera.vanishing_point(Vector3::new(0.0, 0.0, 1.0))?)),
            lines: Vec::new(),
            direction: None,
            covariance_deg2: None,
        });
    }
    let scene = Scene {
        version: 1,
        image: camera.image,
        vanishing_points: vps,
        principal_point: None,
        focal_px: None,
        focal_sd_px: None,
        principal_point_sd_px: None,
        lens_distortion: None,
        objects,
        floor: floor_px,
        scale: None,
        perspective: None,
        click_covariances_px2: std::collections::BTreeMap::new(),
        placement_turn_deg: None,
        other_photos: Vec::new(),
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

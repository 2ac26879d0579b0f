//! The random Manhattan room: its options ([`SynthOptions`], [`Annotation`]) and
//! [`synthesize`], which places boxes, prisms and the floor outline in the camera's view and
//! renders, jitters and annotates them.

use nalgebra::{Vector2, Vector3};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::Serialize;

use super::annotate::{BoxAnnotation, BoxClicks, arr, render_annotated};
use super::camera::PinholeCamera;
use super::noise::add_noise;
use super::truth::{SynthBox, SynthPrism, Truth};
use super::vp_edges::vanishing_points_as_lines;
use crate::error::{MetrologyError, Result};
use crate::scene::{ImageSize, ScaleSpec, Scene};

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
pub(super) fn clip_to_view(
    camera: &PinholeCamera,
    poly: &[Vector2<f64>],
    inset: f64,
) -> Vec<Vector2<f64>> {
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

//! Synthetic test photos with a known camera: a tiled floor and a few boxes.
//!
//! [`render_manhattan_scene`] ray-casts a Manhattan scene through a pinhole camera and returns
//! the picture with the truth: intrinsics, the three vanishing directions and points.
//!
//! # Scene and camera
//! World frame: `x` right, `y` forward (the camera's horizontal viewing direction), `z` up,
//! metres; the floor is `z = 0`. The camera stands at `(0, 0, camera_height_m)`, pitched down
//! by `pitch_rad` about `x`, then rolled by `roll_rad` about its viewing direction (positive
//! roll makes the horizon fall to the right in the image), the conventions of
//! `vpmap_metrology::synth`. The *room* — floor tiles and boxes — is turned by `yaw_rad` about
//! the vertical: its axes are `a = (cos yaw, sin yaw, 0)`, `b = (-sin yaw, cos yaw, 0)` and
//! `up = (0, 0, 1)`, which are the three vanishing directions. With `yaw = 0` the room's `b`
//! axis is parallel to the viewing direction and `a` to the image plane (one-point
//! perspective when the pitch is zero too); the default yaw of 30 degrees gives two finite
//! horizontal vanishing points.
//!
//! A pixel `(u, v)` (origin at the top-left corner of the image, pixel centres at `i + 0.5`)
//! sees the ray `right (u - c_x) / f + down (v - c_y) / f + forward`.
//!
//! # Pictures
//! The floor is a checkerboard of square tiles (two tones, faded towards a mean colour with
//! distance so the far floor does not alias); boxes stand on it, axis-aligned with the room,
//! placed at random (seeded) where the camera sees the floor; each face is shaded by its
//! orientation (`0.55 + 0.45 n . light`, with a light direction that gives all five visible
//! face orientations different shades); the sky is a smooth gradient. Pixels where the
//! surface changes are supersampled 4 x 4 (anti-aliasing); seeded Gaussian noise is added.

pub mod photo;
mod realism;

use image::{DynamicImage, GrayImage, Luma, Rgb, RgbImage};
use nalgebra::Vector3;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

use crate::detection::Intrinsics;
use vpmap_metrology::calibration::Perspective;

/// How to render a scene. `Default` gives a 640 x 480 colour photo at 25 degrees pitch.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneRenderOptions {
    /// Image width, pixels.
    pub width_px: u32,
    /// Image height, pixels.
    pub height_px: u32,
    /// Focal length, pixels.
    pub focal_px: f64,
    /// Principal point, pixels (default: the image centre).
    pub principal_point_px: Option<[f64; 2]>,
    /// Pitch, radians, positive looking down (0: two-point perspective).
    pub pitch_rad: f64,
    /// Roll, radians, positive makes the horizon fall to the right.
    pub roll_rad: f64,
    /// The room's turn about the vertical, radians (see the module doc).
    pub yaw_rad: f64,
    /// Camera height above the floor, metres.
    pub camera_height_m: f64,
    /// Floor tile side, metres.
    pub tile_size_m: f64,
    /// Number of boxes (fewer when they do not fit).
    pub boxes: usize,
    /// Colour (RGB) or grey picture.
    pub colour: bool,
    /// Standard deviation of the added noise, grey levels (0 to 255 scale).
    pub noise_sigma: f64,
    /// Seed of the box placement, colours and noise.
    pub seed: u64,
}

impl Default for SceneRenderOptions {
    fn default() -> Self {
        Self {
            width_px: 640,
            height_px: 480,
            focal_px: 600.0,
            principal_point_px: None,
            pitch_rad: 25f64.to_radians(),
            roll_rad: 0.0,
            yaw_rad: 30f64.to_radians(),
            camera_height_m: 1.6,
            tile_size_m: 0.5,
            boxes: 5,
            colour: true,
            noise_sigma: 1.5,
            seed: 0,
        }
    }
}

/// A rendered scene and its truth.
#[derive(Clone, Debug)]
pub struct RenderedScene {
    /// The picture (`ImageRgb8`, or `ImageLuma8` when not in colour).
    pub image: DynamicImage,
    /// The camera's true intrinsics.
    pub intrinsics: Intrinsics,
    /// The room's axes `a`, `b` and `up` in the camera frame (`x` right, `y` down, `z`
    /// forward), unit vectors: two horizontal directions, then the vertical.
    pub directions_camera: [[f64; 3]; 3],
    /// Their vanishing points, pixels (`None` at infinity).
    pub vanishing_points_px: [Option<[f64; 2]>; 3],
    /// Two-point perspective exactly when the pitch is zero (a small non-zero pitch is
    /// three-point here; [`crate::detect`] calls it two-point within its tolerance: compare
    /// [`RenderedScene::vertical_tilt_deg`] with the tolerance for that).
    pub perspective: Perspective,
    /// Angle between the vertical and the image plane, degrees (`|pitch|`).
    pub vertical_tilt_deg: f64,
    /// Boxes actually placed.
    pub boxes: usize,
}

/// Sub-samples per pixel side where the surface changes.
const SUB: usize = 4;
/// Distance over which the floor's tile contrast falls by `e`, metres.
const FLOOR_FADE_M: f64 = 12.0;
/// Beyond this distance the floor is uniform, metres.
const FLOOR_UNIFORM_BEYOND_M: f64 = 36.0;

/// A box in room coordinates (`u` along `a`, `v` along `b`, `z` up).
#[derive(Clone, Copy, Debug)]
struct SceneBox {
    lo: [f64; 3],
    hi: [f64; 3],
    albedo: [f64; 3],
}

/// What a ray hit.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Hit {
    Sky,
    /// Floor tile with its parity.
    Floor(bool),
    /// Box index and face (0..6).
    Face(usize, usize),
}

/// The camera and the room, ready to trace.
struct Tracer {
    right: Vector3<f64>,
    down: Vector3<f64>,
    forward: Vector3<f64>,
    centre: Vector3<f64>,
    focal: f64,
    pp: [f64; 2],
    a: Vector3<f64>,
    b: Vector3<f64>,
    tile: f64,
    boxes: Vec<SceneBox>,
    light: [f64; 3],
    floor_colours: [[f64; 3]; 2],
}

impl Tracer {
    fn new(opts: &SceneRenderOptions) -> Self {
        let (s, c) = opts.pitch_rad.sin_cos();
        let forward = Vector3::new(0.0, c, -s);
        let right0 = Vector3::new(1.0, 0.0, 0.0);
        let down0 = Vector3::new(0.0, -s, -c);
        let (sr, cr) = (-opts.roll_rad).sin_cos();
        let right = right0 * cr + down0 * sr;
        let down = -right0 * sr + down0 * cr;
        let (sy, cy) = opts.yaw_rad.sin_cos();
        let pp = opts.principal_point_px.unwrap_or([
            0.5 * f64::from(opts.width_px),
            0.5 * f64::from(opts.height_px),
        ]);
        let light = Vector3::new(0.6, -0.35, 0.72).normalize();
        Self {
            right,
            down,
            forward,
            centre: Vector3::new(0.0, 0.0, opts.camera_height_m),
            focal: opts.focal_px,
            pp,
            a: Vector3::new(cy, sy, 0.0),
            b: Vector3::new(-sy, cy, 0.0),
            tile: opts.tile_size_m.max(1e-3),
            boxes: Vec::new(),
            light: [light.x, light.y, light.z],
            floor_colours: if opts.colour {
                [[0.78, 0.70, 0.55], [0.42, 0.33, 0.25]]
            } else {
                [[0.72; 3], [0.36; 3]]
            },
        }
    }

    /// World ray direction through pixel position `(u, v)`.
    fn ray(&self, u: f64, v: f64) -> Vector3<f64> {
        self.right * ((u - self.pp[0]) / self.focal)
            + self.down * ((v - self.pp[1]) / self.focal)
            + self.forward
    }

    /// Camera-frame coordinates of a world direction.
    fn to_camera(&self, w: &Vector3<f64>) -> [f64; 3] {
        [w.dot(&self.right), w.dot(&self.down), w.dot(&self.forward)]
    }

    /// The nearest hit along the ray and its distance.
    fn trace(&self, dir: &Vector3<f64>) -> (Hit, f64) {
        let mut best = (Hit::Sky, f64::INFINITY);
        if dir.z < -1e-12 {
            let t = -self.centre.z / dir.z;
            let p = self.centre + dir * t;
            let (u, v) = (p.dot(&self.a) / self.tile, p.dot(&self.b) / self.tile);
            // Beyond the fade distance the tiles are one colour (nothing to anti-alias).
            let parity = t * dir.norm() < FLOOR_UNIFORM_BEYOND_M
                && (u.floor() + v.floor()).rem_euclid(2.0) >= 1.0;
            best = (Hit::Floor(parity), t);
        }
        // Room coordinates of the ray.
        let o = [
            self.centre.dot(&self.a),
            self.centre.dot(&self.b),
            self.centre.z,
        ];
        let d = [dir.dot(&self.a), dir.dot(&self.b), dir.z];
        for (i, bx) in self.boxes.iter().enumerate() {
            if let Some((t, face)) = slab(&o, &d, bx)
                && t < best.1
            {
                best = (Hit::Face(i, face), t);
            }
        }
        best
    }

    /// Linear RGB (0-1) of a hit.
    fn shade(&self, hit: Hit, dist: f64, dir: &Vector3<f64>) -> [f64; 3] {
        match hit {
            Hit::Sky => {
                let elevation = (dir.z / dir.norm()).clamp(-1.0, 1.0);
                let t = elevation.max(0.0).sqrt();
                [0.80 - 0.25 * t, 0.86 - 0.18 * t, 0.95 - 0.05 * t]
            }
            Hit::Floor(parity) => {
                let [light, dark] = self.floor_colours;
                let c = if parity { dark } else { light };
                // Contrast fades with distance: no aliasing at the horizon.
                let keep = if dist < FLOOR_UNIFORM_BEYOND_M {
                    (-dist / FLOOR_FADE_M).exp()
                } else {
                    0.0
                };
                let mut out = c;
                for ((o, l), d) in out.iter_mut().zip(light).zip(dark) {
                    let mean = 0.5 * (l + d);
                    *o = mean + (*o - mean) * keep;
                }
                out
            }
            Hit::Face(i, face) => {
                let normal = match face {
                    0 => [-1.0, 0.0, 0.0],
                    1 => [1.0, 0.0, 0.0],
                    2 => [0.0, -1.0, 0.0],
                    3 => [0.0, 1.0, 0.0],
                    4 => [0.0, 0.0, -1.0],
                    _ => [0.0, 0.0, 1.0],
                };
                let lambert = normal[0] * self.light[0]
                    + normal[1] * self.light[1]
                    + normal[2] * self.light[2];
                let albedo = self.boxes.get(i).map_or([0.5; 3], |b| b.albedo);
                albedo.map(|x| x * (0.55 + 0.45 * lambert))
            }
        }
    }

    fn sample(&self, u: f64, v: f64) -> (Hit, [f64; 3]) {
        let dir = self.ray(u, v);
        let (hit, t) = self.trace(&dir);
        (hit, self.shade(hit, t * dir.norm(), &dir))
    }

    /// Place up to `count` boxes where the camera sees the floor.
    fn place_boxes(&mut self, opts: &SceneRenderOptions, rng: &mut ChaCha8Rng) {
        let (w, h) = (f64::from(opts.width_px), f64::from(opts.height_px));
        let mut attempts = 0;
        while self.boxes.len() < opts.boxes && attempts < 400 {
            attempts += 1;
            let u = rng.random_range(0.1..0.9) * w;
            let v = rng.random_range(0.3..0.95) * h;
            let dir = self.ray(u, v);
            if dir.z >= -1e-9 {
                continue;
            }
            let t = -self.centre.z / dir.z;
            let p = self.centre + dir * t;
            let ground = (p.x.powi(2) + p.y.powi(2)).sqrt();
            if !(1.5..=10.0).contains(&ground) {
                continue;
            }
            let scale = (ground / 4.0).clamp(0.5, 1.5);
            let half_u = rng.random_range(0.2..0.6) * scale;
            let half_v = rng.random_range(0.2..0.6) * scale;
            let height = rng.random_range(0.3..1.3) * scale;
            let (cu, cv) = (p.dot(&self.a), p.dot(&self.b));
            let candidate = SceneBox {
                lo: [cu - half_u, cv - half_v, 0.0],
                hi: [cu + half_u, cv + half_v, height],
                albedo: if opts.colour {
                    [
                        rng.random_range(0.15..0.95),
                        rng.random_range(0.15..0.95),
                        rng.random_range(0.15..0.95),
                    ]
                } else {
                    [rng.random_range(0.2..0.95); 3]
                },
            };
            // Keep boxes apart, and away from the camera.
            let clear = self.boxes.iter().all(|o| {
                candidate.lo[0] > o.hi[0] + 0.2
                    || candidate.hi[0] < o.lo[0] - 0.2
                    || candidate.lo[1] > o.hi[1] + 0.2
                    || candidate.hi[1] < o.lo[1] - 0.2
            });
            let o = [self.centre.dot(&self.a), self.centre.dot(&self.b)];
            let contains_camera = (candidate.lo[0] - 0.5..=candidate.hi[0] + 0.5).contains(&o[0])
                && (candidate.lo[1] - 0.5..=candidate.hi[1] + 0.5).contains(&o[1]);
            if clear && !contains_camera {
                self.boxes.push(candidate);
            }
        }
    }
}

/// Ray-box intersection (slab method) in room coordinates: entry distance and face.
fn slab(o: &[f64; 3], d: &[f64; 3], bx: &SceneBox) -> Option<(f64, usize)> {
    let mut t_near = f64::NEG_INFINITY;
    let mut t_far = f64::INFINITY;
    let mut face = 0;
    for (k, (((&ok, &dk), &lo), &hi)) in o.iter().zip(d).zip(&bx.lo).zip(&bx.hi).enumerate() {
        if dk.abs() < 1e-15 {
            if ok < lo || ok > hi {
                return None;
            }
            continue;
        }
        let (t0, t1) = ((lo - ok) / dk, (hi - ok) / dk);
        let (tn, tf, f) = if t0 < t1 {
            (t0, t1, 2 * k)
        } else {
            (t1, t0, 2 * k + 1)
        };
        if tn > t_near {
            t_near = tn;
            face = f;
        }
        t_far = t_far.min(tf);
    }
    (t_near <= t_far && t_near > 1e-9).then_some((t_near, face))
}

/// Render a Manhattan scene (tiled floor, boxes) seen from a known camera.
///
/// # Example
/// ```
/// use vpmap_vision::synthetic::{render_manhattan_scene, SceneRenderOptions};
/// let scene = render_manhattan_scene(&SceneRenderOptions {
///     width_px: 160,
///     height_px: 120,
///     focal_px: 150.0,
///     pitch_rad: 0.0,
///     colour: false,
///     ..SceneRenderOptions::default()
/// });
/// assert_eq!(scene.image.width(), 160);
/// assert!(scene.vanishing_points_px[2].is_none()); // vertical at infinity: 2PP
/// ```
#[must_use]
pub fn render_manhattan_scene(opts: &SceneRenderOptions) -> RenderedScene {
    let mut rng = ChaCha8Rng::seed_from_u64(opts.seed);
    let mut tracer = Tracer::new(opts);
    tracer.place_boxes(opts, &mut rng);
    let (w, h) = (opts.width_px as usize, opts.height_px as usize);
    // First pass: one sample per pixel.
    let mut hits = Vec::with_capacity(w * h);
    let mut colours = Vec::with_capacity(w * h);
    for y in 0..h {
        for x in 0..w {
            let (hit, c) = tracer.sample(x as f64 + 0.5, y as f64 + 0.5);
            hits.push(hit);
            colours.push(c);
        }
    }
    // Second pass: supersample where the surface changes.
    let hit_at = |x: usize, y: usize| hits.get(y * w + x).copied();
    let mut out = colours.clone();
    for y in 0..h {
        for x in 0..w {
            let here = hit_at(x, y);
            let edge = [
                (x.wrapping_sub(1), y),
                (x + 1, y),
                (x, y.wrapping_sub(1)),
                (x, y + 1),
            ]
            .iter()
            .any(|&(nx, ny)| nx < w && ny < h && hit_at(nx, ny) != here);
            if !edge {
                continue;
            }
            let mut sum = [0.0; 3];
            for sy in 0..SUB {
                for sx in 0..SUB {
                    let u = x as f64 + (sx as f64 + 0.5) / SUB as f64;
                    let v = y as f64 + (sy as f64 + 0.5) / SUB as f64;
                    let (_, c) = tracer.sample(u, v);
                    for (s, v) in sum.iter_mut().zip(c) {
                        *s += v;
                    }
                }
            }
            if let Some(slot) = out.get_mut(y * w + x) {
                *slot = sum.map(|s| s / (SUB * SUB) as f64);
            }
        }
    }
    let noise = Normal::new(0.0, opts.noise_sigma.max(0.0)).ok();
    let quantise = |v: f64, rng: &mut ChaCha8Rng| -> u8 {
        let n = noise.map_or(0.0, |d| d.sample(rng));
        (v * 255.0 + n).round().clamp(0.0, 255.0) as u8
    };
    let image = if opts.colour {
        let mut img = RgbImage::new(opts.width_px, opts.height_px);
        for (p, c) in img.pixels_mut().zip(&out) {
            *p = Rgb(c.map(|v| quantise(v, &mut rng)));
        }
        DynamicImage::ImageRgb8(img)
    } else {
        let mut img = GrayImage::new(opts.width_px, opts.height_px);
        for (p, c) in img.pixels_mut().zip(&out) {
            *p = Luma([quantise((c[0] + c[1] + c[2]) / 3.0, &mut rng)]);
        }
        DynamicImage::ImageLuma8(img)
    };
    let axes = [tracer.a, tracer.b, Vector3::z()];
    let directions_camera = axes.map(|w| tracer.to_camera(&w));
    let vanishing_points_px = directions_camera.map(|d| {
        (d[2].abs() > 1e-12).then(|| {
            [
                tracer.pp[0] + tracer.focal * d[0] / d[2],
                tracer.pp[1] + tracer.focal * d[1] / d[2],
            ]
        })
    });
    let tilt = opts.pitch_rad.abs().to_degrees();
    RenderedScene {
        image,
        intrinsics: Intrinsics {
            focal_px: opts.focal_px,
            principal_point_px: tracer.pp,
        },
        directions_camera,
        vanishing_points_px,
        perspective: if opts.pitch_rad == 0.0 {
            Perspective::TwoPoint
        } else {
            Perspective::ThreePoint
        },
        vertical_tilt_deg: tilt,
        boxes: tracer.boxes.len(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_ray_through_a_vanishing_point_runs_along_its_direction() {
        let opts = SceneRenderOptions {
            roll_rad: 0.1,
            yaw_rad: 0.4,
            ..SceneRenderOptions::default()
        };
        let tracer = Tracer::new(&opts);
        let cam = tracer.to_camera(&tracer.a);
        let vp = [
            tracer.pp[0] + tracer.focal * cam[0] / cam[2],
            tracer.pp[1] + tracer.focal * cam[1] / cam[2],
        ];
        let ray = tracer.ray(vp[0], vp[1]).normalize();
        let dir = if cam[2] > 0.0 { tracer.a } else { -tracer.a };
        assert!((ray - dir).norm() < 1e-12);
    }

    #[test]
    fn slab_hits_the_near_face() {
        let bx = SceneBox {
            lo: [-1.0, 2.0, 0.0],
            hi: [1.0, 3.0, 1.0],
            albedo: [0.5; 3],
        };
        let hit = slab(&[0.0, 0.0, 0.5], &[0.0, 1.0, 0.0], &bx);
        assert_eq!(hit, Some((2.0, 2)));
        assert_eq!(slab(&[0.0, 0.0, 1.5], &[0.0, 1.0, 0.0], &bx), None);
    }
}

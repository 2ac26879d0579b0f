//! Photos of a synthetic scene, good enough to measure snapping: shaded, textured faces,
//! blur, noise and a JPEG round trip, with the true corner of every click.
//!
//! [`render_photo`] takes a scene and its truth from `vpmap_metrology::synth` (a pinhole
//! camera over a floor with boxes and prisms) and ray-casts it through the truth's camera:
//!
//! * **surfaces**: the floor (`z = 0`, everywhere), walls standing on the floor outline's
//!   edges that run along the room's two directions (the room's far sides; the outline's
//!   other edges are where the view cut it), every object as a prism (a box's four corners or
//!   a footprint polygon, extruded to its height); above the walls a plain ceiling colour;
//! * **shading**: albedo times `ambient + diffuse * max(0, n . light)`, so faces of
//!   different orientation differ; each surface carries a procedural texture (value noise at
//!   three scales, in metres on the surface, [`PhotoOptions::texture_contrast`]);
//! * **anti-aliasing**: pixels whose neighbours see another surface are averaged over
//!   [`PhotoOptions::supersample`]^2 sub-samples;
//! * then a Gaussian blur ([`PhotoOptions::blur_sigma_px`], the lens), Gaussian noise
//!   ([`PhotoOptions::noise_sigma`], grey levels) and a JPEG round trip
//!   ([`PhotoOptions::jpeg_quality`]);
//! * optionally what real photos have and these renders lack (all off by default, and then
//!   the photo is byte for byte what it was): lens distortion
//!   ([`PhotoOptions::distortion_k`], a one-parameter division model about the principal
//!   point), clutter strokes near the corners and off the room's axes
//!   ([`PhotoOptions::clutter_per_corner`]), thin occluders in front of the scene making
//!   T junctions ([`PhotoOptions::occluders`]) and blur growing towards the photo's corners
//!   ([`PhotoOptions::blur_growth`]); [`PhotoOptions::cluttered`] turns them all on with JPEG
//!   at phone quality (85).
//!
//! Every click of the scene comes back as a [`TrueCorner`]: its exact projection (the scene
//! must hold the exact clicks, as `synthesize` writes them with no noise), whether the camera
//! sees it (nothing in front of it, itself included) and what kind of image point it is.

use image::{DynamicImage, Rgb, RgbImage};
use nalgebra::{Vector2, Vector3};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use vpmap_metrology::scene::Scene;
use vpmap_metrology::synth::{PinholeCamera, Truth};

use super::realism::{
    Lens, draw_clutter, draw_occluders, gaussian_blur, jpeg_round_trip, varying_blur,
};
use crate::clicks::{ClickPlace, scene_clicks};
use crate::error::{Result, VisionError};

/// How to render a photo. `Default`: a photo like a phone's, slightly soft, a little noisy,
/// JPEG at quality 90.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhotoOptions {
    /// Standard deviation of the Gaussian blur, pixels (0: none).
    pub blur_sigma_px: f64,
    /// Standard deviation of the added noise, grey levels (0 to 255 scale).
    pub noise_sigma: f64,
    /// JPEG quality 1-100 of the round trip (`None`: no JPEG).
    pub jpeg_quality: Option<u8>,
    /// Relative amplitude of the surfaces' texture (0: flat colours).
    pub texture_contrast: f64,
    /// Sub-samples per pixel side where the surface changes.
    pub supersample: usize,
    /// Wall height in camera heights.
    pub wall_height: f64,
    /// Seed of the colours, textures and noise.
    pub seed: u64,
    /// Lens distortion, the division model's `k` (0: a pinhole photo). For a photo pixel
    /// `p_d`, with `c` the principal point and `r = |p_d - c| / h` (`h` half the image
    /// diagonal, pixels), the pinhole pixel is `p_u = c + (p_d - c) / (1 + k r^2)`; barrel
    /// distortion has `k < 0`, phones about `-0.12` to 0. The true corners come back
    /// distorted, and [`RenderedPhoto::distortion_k`] holds it.
    pub distortion_k: f64,
    /// Clutter strokes drawn near each visible corner (0: none): short, thin, any direction.
    pub clutter_per_corner: usize,
    /// Thin bars across the photo in front of everything (0: none); a corner under one is not
    /// visible.
    pub occluders: usize,
    /// Blur growth towards the photo's corners: there the blur is
    /// `blur_sigma_px (1 + blur_growth)`, mixed in by the squared distance from the centre
    /// (0: the same blur everywhere).
    pub blur_growth: f64,
}

impl Default for PhotoOptions {
    fn default() -> Self {
        Self {
            blur_sigma_px: 0.7,
            noise_sigma: 2.0,
            jpeg_quality: Some(90),
            texture_contrast: 0.08,
            supersample: 5,
            wall_height: 1.8,
            seed: 0,
            distortion_k: 0.0,
            clutter_per_corner: 0,
            occluders: 0,
            blur_growth: 0.0,
        }
    }
}

impl PhotoOptions {
    /// A photo closer to a phone's: the default with three clutter strokes a corner, two
    /// occluding bars, blur twice as wide at the photo's corners, JPEG at quality 85 and
    /// barrel distortion `k = -0.06` (mid-range for phones).
    #[must_use]
    pub fn cluttered(seed: u64) -> Self {
        Self {
            seed,
            jpeg_quality: Some(85),
            distortion_k: -0.06,
            clutter_per_corner: 3,
            occluders: 2,
            blur_growth: 1.0,
            ..Self::default()
        }
    }
}

/// What kind of image point a click is, for measuring snapping per kind.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum CornerKind {
    /// A box corner: its edges run along the room's directions (towards the vanishing points).
    BoxCorner,
    /// A corner of the room where two walls meet the floor.
    RoomCorner,
    /// A footprint object's vertex or top: its floor edges run along no vanishing point.
    FootprintCorner,
    /// A floor outline point where the view cut the outline: on one edge at most, no corner.
    NoCorner,
}

impl CornerKind {
    /// A name for tables: `box`, `room`, `footprint`, `no corner`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::BoxCorner => "box corner",
            Self::RoomCorner => "room corner",
            Self::FootprintCorner => "footprint vertex",
            Self::NoCorner => "no corner",
        }
    }
}

/// The truth of one click of the scene.
#[derive(Clone, Debug, PartialEq)]
pub struct TrueCorner {
    /// Where the click sits in the scene.
    pub place: ClickPlace,
    /// The exact projection, pixels.
    pub point_px: [f64; 2],
    /// Nothing stands between the camera and the point (the object itself included), and it
    /// lies in the image.
    pub visible: bool,
    /// What kind of image point it is.
    pub kind: CornerKind,
}

/// A rendered photo and the truth of its clicks.
#[derive(Clone, Debug)]
pub struct RenderedPhoto {
    /// The photo (`ImageRgb8`, after the JPEG round trip when asked).
    pub image: DynamicImage,
    /// Per click of the scene, in [`crate::clicks::scene_clicks`] order (in the distorted
    /// photo when [`PhotoOptions::distortion_k`] is not 0).
    pub corners: Vec<TrueCorner>,
    /// The lens distortion rendered, the division model's `k` ([`PhotoOptions::distortion_k`]).
    pub distortion_k: f64,
}

/// A surface a ray can hit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Surface {
    None,
    Floor,
    Wall(usize),
    /// Object, face: `0..n` the sides, `n` the top, `n + 1` the bottom.
    Face(usize, usize),
}

/// An object as a convex prism.
struct Prism {
    /// Footprint, counter-clockwise seen from above.
    footprint: Vec<Vector2<f64>>,
    height: f64,
    albedo: [f64; 3],
}

/// A wall: a vertical rectangle over a floor segment.
struct Wall {
    from: Vector2<f64>,
    to: Vector2<f64>,
    normal: Vector2<f64>,
    albedo: [f64; 3],
}

struct World {
    centre: Vector3<f64>,
    right: Vector3<f64>,
    down: Vector3<f64>,
    forward: Vector3<f64>,
    focal: f64,
    pp: Vector2<f64>,
    prisms: Vec<Prism>,
    walls: Vec<Wall>,
    wall_height: f64,
    floor_albedo: [f64; 3],
    ceiling: [f64; 3],
    light: Vector3<f64>,
    texture_contrast: f64,
    seed: u64,
}

/// Counter-clockwise order of a polygon (seen from above, `z` up).
fn counter_clockwise(mut p: Vec<Vector2<f64>>) -> Vec<Vector2<f64>> {
    let area: f64 = (0..p.len())
        .map(|i| {
            let (a, b) = (p[i], p[(i + 1) % p.len()]);
            a.x * b.y - a.y * b.x
        })
        .sum();
    if area < 0.0 {
        p.reverse();
    }
    p
}

fn luminance(c: [f64; 3]) -> f64 {
    0.299 * c[0] + 0.587 * c[1] + 0.114 * c[2]
}

impl World {
    fn new(scene: &Scene, truth: &Truth, camera: &PinholeCamera, opts: &PhotoOptions) -> Self {
        let mut rng = ChaCha8Rng::seed_from_u64(opts.seed ^ 0x5eed_f00d);
        let (right, down, forward) = camera.axes();
        let floor_albedo = [0.62, 0.50, 0.38];
        let floor_lum = luminance(floor_albedo);
        let wall_albedo = [0.86, 0.84, 0.78];
        let albedo = |rng: &mut ChaCha8Rng| loop {
            let c = [
                rng.random_range(0.08..0.95),
                rng.random_range(0.08..0.95),
                rng.random_range(0.08..0.95),
            ];
            let l = luminance(c);
            if (l - floor_lum).abs() > 0.12 && (l - luminance(wall_albedo)).abs() > 0.08 {
                break c;
            }
        };
        let prisms = truth
            .objects
            .iter()
            .map(|o| Prism {
                footprint: counter_clockwise(
                    o.footprint
                        .iter()
                        .map(|p| Vector2::new(p[0], p[1]))
                        .collect(),
                ),
                height: o.height,
                albedo: albedo(&mut rng),
            })
            .collect();
        // The room's directions: the first vanishing point's ray, made horizontal.
        let room_a = scene
            .vanishing_points
            .first()
            .and_then(|v| v.point)
            .map(|v| {
                let q = (Vector2::new(v[0], v[1]) - camera.principal_point_px) / camera.focal_px;
                let ray = right * q.x + down * q.y + forward;
                Vector2::new(ray.x, ray.y)
            })
            .filter(|a| a.norm() > 1e-9)
            .map_or(Vector2::new(1.0, 0.0), |a| a.normalize());
        let floor = counter_clockwise(
            truth
                .floor
                .iter()
                .map(|p| Vector2::new(p[0], p[1]))
                .collect(),
        );
        let n = floor.len();
        let along = |i: usize| {
            let e = floor[(i + 1) % n] - floor[i];
            let len = e.norm();
            len > 1e-9
                && ((e.x * room_a.y - e.y * room_a.x).abs() / len < 1e-6
                    || e.dot(&room_a).abs() / len < 1e-6)
        };
        let mut walls = Vec::new();
        for i in 0..n {
            if !along(i) {
                continue;
            }
            let (p, q) = (floor[i], floor[(i + 1) % n]);
            let e = (q - p).normalize();
            // Where the view cut the outline the wall goes on (out of the picture); at a room
            // corner it meets the next wall.
            let far = 1e3 * camera.height_m;
            let from = if along((i + n - 1) % n) {
                p
            } else {
                p - e * far
            };
            let to = if along((i + 1) % n) { q } else { q + e * far };
            // Outward normal of a counter-clockwise polygon: the edge turned clockwise.
            walls.push(Wall {
                from,
                to,
                normal: Vector2::new(e.y, -e.x),
                albedo: wall_albedo,
            });
        }
        let tallest = truth.objects.iter().map(|o| o.height).fold(0.0, f64::max);
        Self {
            centre: camera.centre(),
            right,
            down,
            forward,
            focal: camera.focal_px,
            pp: camera.principal_point_px,
            prisms,
            walls,
            wall_height: (opts.wall_height * camera.height_m).max(1.2 * tallest),
            floor_albedo,
            ceiling: [0.93, 0.93, 0.95],
            light: Vector3::new(0.45, -0.62, 0.64).normalize(),
            texture_contrast: opts.texture_contrast,
            seed: opts.seed,
        }
    }

    fn ray(&self, u: f64, v: f64) -> Vector3<f64> {
        self.right * ((u - self.pp.x) / self.focal)
            + self.down * ((v - self.pp.y) / self.focal)
            + self.forward
    }

    /// Entry distance and face of a ray into a convex prism.
    fn prism_entry(o: &Vector3<f64>, d: &Vector3<f64>, p: &Prism) -> Option<(f64, usize)> {
        let n = p.footprint.len();
        let mut t_near = f64::NEG_INFINITY;
        let mut t_far = f64::INFINITY;
        let mut face = 0;
        // Planes: sides (outward normal, offset), top, bottom.
        let mut clip = |num: f64, den: f64, f: usize| -> bool {
            // Inside when num + den t <= 0.
            if den.abs() < 1e-15 {
                return num <= 0.0;
            }
            let t = -num / den;
            if den < 0.0 {
                if t > t_near {
                    t_near = t;
                    face = f;
                }
            } else {
                t_far = t_far.min(t);
            }
            true
        };
        for i in 0..n {
            let (a, b) = (p.footprint[i], p.footprint[(i + 1) % n]);
            let e = b - a;
            let nn = Vector2::new(e.y, -e.x);
            let num = (o.x - a.x) * nn.x + (o.y - a.y) * nn.y;
            let den = d.x * nn.x + d.y * nn.y;
            if !clip(num, den, i) {
                return None;
            }
        }
        if !clip(o.z - p.height, d.z, n) || !clip(-o.z, -d.z, n + 1) {
            return None;
        }
        (t_near <= t_far && t_near > 1e-9).then_some((t_near, face))
    }

    fn trace(&self, d: &Vector3<f64>) -> (Surface, f64) {
        let o = &self.centre;
        let mut best = (Surface::None, f64::INFINITY);
        if d.z < -1e-12 {
            best = (Surface::Floor, -o.z / d.z);
        }
        for (k, w) in self.walls.iter().enumerate() {
            let den = d.x * w.normal.x + d.y * w.normal.y;
            if den <= 1e-15 {
                continue; // seen from behind or edge-on
            }
            let num = (w.from.x - o.x) * w.normal.x + (w.from.y - o.y) * w.normal.y;
            let t = num / den;
            if !(t > 1e-9 && t < best.1) {
                continue;
            }
            let p = o + d * t;
            let e = w.to - w.from;
            let s = ((p.x - w.from.x) * e.x + (p.y - w.from.y) * e.y) / e.norm_squared();
            if (0.0..=1.0).contains(&s) && p.z >= 0.0 && p.z <= self.wall_height {
                best = (Surface::Wall(k), t);
            }
        }
        for (k, p) in self.prisms.iter().enumerate() {
            if let Some((t, f)) = Self::prism_entry(o, d, p)
                && t < best.1
            {
                best = (Surface::Face(k, f), t);
            }
        }
        best
    }

    /// Texture factor of a surface point (surface coordinates in metres).
    fn texture(&self, u: f64, v: f64, surface_seed: u64) -> f64 {
        let s = self
            .seed
            .wrapping_mul(0x9E37_79B9)
            .wrapping_add(surface_seed);
        let n = 0.6 * value_noise(u * 3.0, v * 3.0, s)
            + 0.3 * value_noise(u * 11.0, v * 11.0, s ^ 0xA5A5)
            + 0.1 * value_noise(u * 31.0, v * 31.0, s ^ 0x5A5A);
        1.0 + self.texture_contrast * n
    }

    fn shade(&self, surface: Surface, t: f64, d: &Vector3<f64>) -> [f64; 3] {
        let p = self.centre + d * t;
        let lit = |n: Vector3<f64>| 0.5 + 0.5 * n.dot(&self.light).max(0.0);
        let (albedo, normal, tex) = match surface {
            Surface::None => return self.ceiling,
            Surface::Floor => (self.floor_albedo, Vector3::z(), self.texture(p.x, p.y, 1)),
            Surface::Wall(k) => {
                let Some(w) = self.walls.get(k) else {
                    return self.ceiling;
                };
                let along = (p.xy() - w.from).norm();
                (
                    w.albedo,
                    Vector3::new(-w.normal.x, -w.normal.y, 0.0),
                    self.texture(along, p.z, 10 + k as u64),
                )
            }
            Surface::Face(k, f) => {
                let Some(prism) = self.prisms.get(k) else {
                    return self.ceiling;
                };
                let n = prism.footprint.len();
                let seed = 100 + 16 * k as u64 + f as u64;
                if f >= n {
                    let normal = if f == n { Vector3::z() } else { -Vector3::z() };
                    (prism.albedo, normal, self.texture(p.x, p.y, seed))
                } else {
                    let a = prism.footprint[f];
                    let e = prism.footprint[(f + 1) % n] - a;
                    let out = Vector2::new(e.y, -e.x).normalize();
                    let along = (p.xy() - a).norm();
                    (
                        prism.albedo,
                        Vector3::new(out.x, out.y, 0.0),
                        self.texture(along, p.z, seed),
                    )
                }
            }
        };
        let k = lit(normal) * tex;
        albedo.map(|a| a * k)
    }

    fn sample(&self, u: f64, v: f64) -> (Surface, [f64; 3]) {
        let d = self.ray(u, v);
        let (s, t) = self.trace(&d);
        (s, self.shade(s, t, &d))
    }

    /// Whether the camera sees a world point: no surface in front of it.
    fn sees(&self, world: Vector3<f64>) -> bool {
        let d = world - self.centre;
        let o = &self.centre;
        let margin = 1e-6;
        let blocks = |t: f64| t > 1e-9 && t < 1.0 - margin;
        if self
            .prisms
            .iter()
            .any(|p| Self::prism_entry(o, &d, p).is_some_and(|(t, _)| blocks(t)))
        {
            return false;
        }
        // Walls only hide what is behind them (outside the room).
        !self.walls.iter().any(|w| {
            let den = d.x * w.normal.x + d.y * w.normal.y;
            if den <= 1e-15 {
                return false;
            }
            let t = ((w.from.x - o.x) * w.normal.x + (w.from.y - o.y) * w.normal.y) / den;
            if !blocks(t) {
                return false;
            }
            let p = o + d * t;
            let e = w.to - w.from;
            let s = ((p.x - w.from.x) * e.x + (p.y - w.from.y) * e.y) / e.norm_squared();
            (0.0..=1.0).contains(&s) && p.z >= 0.0 && p.z <= self.wall_height
        })
    }
}

/// SplitMix64 of a lattice point and seed, to `[0, 1)`.
fn lattice(ix: i64, iy: i64, seed: u64) -> f64 {
    let mut z = seed
        ^ (ix as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
        ^ (iy as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 53) as f64
}

/// Value noise in `[-1, 1]`: smoothstep interpolation of random lattice values.
fn value_noise(x: f64, y: f64, seed: u64) -> f64 {
    let (fx, fy) = (x.floor(), y.floor());
    let (ix, iy) = (fx as i64, fy as i64);
    let (tx, ty) = (x - fx, y - fy);
    let (sx, sy) = (tx * tx * (3.0 - 2.0 * tx), ty * ty * (3.0 - 2.0 * ty));
    let v00 = lattice(ix, iy, seed);
    let v10 = lattice(ix + 1, iy, seed);
    let v01 = lattice(ix, iy + 1, seed);
    let v11 = lattice(ix + 1, iy + 1, seed);
    let top = v00 + (v10 - v00) * sx;
    let bottom = v01 + (v11 - v01) * sx;
    2.0 * (top + (bottom - top) * sy) - 1.0
}

/// Render a photo of a synthetic scene (`vpmap_metrology::synth::synthesize` with no noise)
/// and the truth of its clicks. Deterministic for the same inputs.
///
/// # Errors
/// [`VisionError::InvalidParameter`] for options out of range; [`VisionError::Decode`] when
/// the JPEG round trip fails.
///
/// # Example
/// ```
/// use vpmap_metrology::scene::ImageSize;
/// use vpmap_metrology::synth::{synthesize, SynthOptions};
/// use vpmap_vision::synthetic::photo::{render_photo, PhotoOptions};
/// let (scene, truth) = synthesize(&SynthOptions {
///     image: ImageSize { width: 200, height: 150 },
///     focal_px: 140.0,
///     ..SynthOptions::default()
/// }).unwrap();
/// let photo = render_photo(&scene, &truth, &PhotoOptions::default())?;
/// assert_eq!(photo.image.width(), 200);
/// assert!(photo.corners.iter().any(|c| c.visible));
/// # Ok::<(), vpmap_vision::VisionError>(())
/// ```
pub fn render_photo(scene: &Scene, truth: &Truth, opts: &PhotoOptions) -> Result<RenderedPhoto> {
    check_options(opts)?;
    let camera = truth.camera.pinhole(scene.image);
    let world = World::new(scene, truth, &camera, opts);
    let (w, h) = (scene.image.width as usize, scene.image.height as usize);
    let lens = Lens {
        centre: [camera.principal_point_px.x, camera.principal_point_px.y],
        half_diagonal: 0.5 * (w as f64).hypot(h as f64),
        k: opts.distortion_k,
    };
    // A photo pixel shows the pinhole pixel `undistort(p)` (itself without distortion).
    let sample = |u: f64, v: f64| {
        if opts.distortion_k == 0.0 {
            world.sample(u, v)
        } else {
            let p = lens.undistort([u, v]);
            world.sample(p[0], p[1])
        }
    };
    let mut surfaces = Vec::with_capacity(w * h);
    let mut colours = Vec::with_capacity(w * h);
    for y in 0..h {
        for x in 0..w {
            let (s, c) = sample(x as f64 + 0.5, y as f64 + 0.5);
            surfaces.push(s);
            colours.push(c);
        }
    }
    let sub = opts.supersample.max(1);
    let surface_at = |x: usize, y: usize| surfaces.get(y * w + x).copied();
    let mut out = colours;
    for y in 0..h {
        for x in 0..w {
            let here = surface_at(x, y);
            let edge = [
                (x.wrapping_sub(1), y),
                (x + 1, y),
                (x, y.wrapping_sub(1)),
                (x, y + 1),
            ]
            .iter()
            .any(|&(nx, ny)| nx < w && ny < h && surface_at(nx, ny) != here);
            if !edge || sub == 1 {
                continue;
            }
            let mut sum = [0.0; 3];
            for sy in 0..sub {
                for sx in 0..sub {
                    let u = x as f64 + (sx as f64 + 0.5) / sub as f64;
                    let v = y as f64 + (sy as f64 + 0.5) / sub as f64;
                    let (_, c) = sample(u, v);
                    for (s, v) in sum.iter_mut().zip(c) {
                        *s += v;
                    }
                }
            }
            if let Some(slot) = out.get_mut(y * w + x) {
                *slot = sum.map(|s| s / (sub * sub) as f64);
            }
        }
    }
    let mut corners = true_corners(scene, truth, &world, &camera);
    if opts.distortion_k != 0.0 {
        for c in &mut corners {
            match lens.distort(c.point_px) {
                Some(p) => c.point_px = p,
                None => c.visible = false,
            }
        }
    }
    if opts.clutter_per_corner > 0 || opts.occluders > 0 {
        let mut clutter_rng = ChaCha8Rng::seed_from_u64(opts.seed ^ 0xC1A7_7E2D);
        let visible: Vec<[f64; 2]> = corners
            .iter()
            .filter(|c| c.visible)
            .map(|c| c.point_px)
            .collect();
        draw_clutter(
            &mut out,
            w,
            h,
            &visible,
            opts.clutter_per_corner,
            &mut clutter_rng,
        );
        let bars = draw_occluders(&mut out, w, h, opts.occluders, &lens, &mut clutter_rng);
        for c in &mut corners {
            let pinhole = lens.undistort(c.point_px);
            if bars.iter().any(|b| b.covers(pinhole, 1.0)) {
                c.visible = false;
            }
        }
    }
    let mut rng = ChaCha8Rng::seed_from_u64(opts.seed);
    let noise = Normal::new(0.0, opts.noise_sigma.max(0.0)).ok();
    let mut planes: Vec<Vec<f64>> = (0..3)
        .map(|c| out.iter().map(|p| p[c] * 255.0).collect())
        .collect();
    for plane in &mut planes {
        if opts.blur_growth > 0.0 {
            varying_blur(plane, w, h, opts.blur_sigma_px, opts.blur_growth);
        } else {
            gaussian_blur(plane, w, h, opts.blur_sigma_px);
        }
    }
    let mut img = RgbImage::new(scene.image.width, scene.image.height);
    for (i, px) in img.pixels_mut().enumerate() {
        let mut c = [0u8; 3];
        for (ch, plane) in c.iter_mut().zip(&planes) {
            let n = noise.map_or(0.0, |d| d.sample(&mut rng));
            *ch = (plane.get(i).copied().unwrap_or(0.0) + n)
                .round()
                .clamp(0.0, 255.0) as u8;
        }
        *px = Rgb(c);
    }
    let image = match opts.jpeg_quality {
        Some(q) => jpeg_round_trip(&img, q)?,
        None => DynamicImage::ImageRgb8(img),
    };
    Ok(RenderedPhoto {
        image,
        corners,
        distortion_k: opts.distortion_k,
    })
}

fn check_options(opts: &PhotoOptions) -> Result<()> {
    let bad = |field: &'static str, value: f64, requirement: &'static str| {
        Err(VisionError::InvalidParameter {
            field,
            value,
            requirement,
        })
    };
    if !(opts.blur_sigma_px.is_finite() && (0.0..=10.0).contains(&opts.blur_sigma_px)) {
        return bad("blur_sigma_px", opts.blur_sigma_px, "must lie in 0..=10");
    }
    if !(opts.noise_sigma.is_finite() && (0.0..=100.0).contains(&opts.noise_sigma)) {
        return bad("noise_sigma", opts.noise_sigma, "must lie in 0..=100");
    }
    if !(opts.texture_contrast.is_finite() && (0.0..=1.0).contains(&opts.texture_contrast)) {
        return bad(
            "texture_contrast",
            opts.texture_contrast,
            "must lie in 0..=1",
        );
    }
    if !(1..=16).contains(&opts.supersample) {
        return bad("supersample", opts.supersample as f64, "must lie in 1..=16");
    }
    if let Some(q) = opts.jpeg_quality
        && !(1..=100).contains(&q)
    {
        return bad("jpeg_quality", f64::from(q), "must lie in 1..=100");
    }
    if !(opts.wall_height.is_finite() && opts.wall_height > 0.0) {
        return bad("wall_height", opts.wall_height, "must be positive");
    }
    if !(opts.distortion_k.is_finite() && (-0.5..=0.5).contains(&opts.distortion_k)) {
        return bad("distortion_k", opts.distortion_k, "must lie in -0.5..=0.5");
    }
    if !(opts.blur_growth.is_finite() && (0.0..=10.0).contains(&opts.blur_growth)) {
        return bad("blur_growth", opts.blur_growth, "must lie in 0..=10");
    }
    if opts.clutter_per_corner > 100 || opts.occluders > 100 {
        return bad(
            "clutter_per_corner",
            opts.clutter_per_corner.max(opts.occluders) as f64,
            "clutter_per_corner and occluders must be at most 100",
        );
    }
    Ok(())
}

/// The world point of each click and whether the camera sees it.
fn true_corners(
    scene: &Scene,
    truth: &Truth,
    world: &World,
    camera: &PinholeCamera,
) -> Vec<TrueCorner> {
    let floor3 = |p: [f64; 2], z: f64| Vector3::new(p[0], p[1], z);
    let floor_wall = |k: usize| -> bool {
        // A floor corner is a room corner when both outline edges at it carry a wall.
        let n = truth.floor.len();
        let on_wall = |a: usize, b: usize| {
            let (Some(pa), Some(pb)) = (truth.floor.get(a), truth.floor.get(b)) else {
                return false;
            };
            let (p, q) = (Vector2::new(pa[0], pa[1]), Vector2::new(pb[0], pb[1]));
            // The edge lies on a wall's line.
            world.walls.iter().any(|w| {
                let d = |x: Vector2<f64>| ((x - w.from).dot(&w.normal)).abs();
                d(p) < 1e-9 && d(q) < 1e-9
            })
        };
        n >= 3 && on_wall((k + n - 1) % n, k) && on_wall(k, (k + 1) % n)
    };
    scene_clicks(scene)
        .into_iter()
        .map(|c| {
            let (point, kind) = match c.place {
                ClickPlace::BoxCorner {
                    object,
                    corner,
                    top,
                } => {
                    let o = truth.objects.get(object);
                    let (i, j) = corner.grid_index();
                    let index = match (i, j) {
                        (0, 0) => 0,
                        (1, 0) => 1,
                        (1, 1) => 2,
                        _ => 3,
                    };
                    let p = o.and_then(|o| o.footprint.get(index).copied());
                    let z = if top {
                        o.map_or(0.0, |o| o.height)
                    } else {
                        0.0
                    };
                    (p.map(|p| floor3(p, z)), CornerKind::BoxCorner)
                }
                ClickPlace::FootprintVertex { object, vertex } => {
                    let p = truth
                        .objects
                        .get(object)
                        .and_then(|o| o.footprint.get(vertex).copied());
                    (p.map(|p| floor3(p, 0.0)), CornerKind::FootprintCorner)
                }
                ClickPlace::FootprintTop { object, above } => {
                    let o = truth.objects.get(object);
                    let p = o.and_then(|o| o.footprint.get(above).copied());
                    (
                        p.map(|p| floor3(p, o.map_or(0.0, |o| o.height))),
                        CornerKind::FootprintCorner,
                    )
                }
                ClickPlace::Floor { index } => {
                    let p = truth.floor.get(index).copied();
                    let kind = if floor_wall(index) {
                        CornerKind::RoomCorner
                    } else {
                        CornerKind::NoCorner
                    };
                    (p.map(|p| floor3(p, 0.0)), kind)
                }
            };
            let projected = point.and_then(|p| camera.project(p));
            let visible = point.is_some_and(|p| world.sees(p))
                && projected.is_some_and(|q| camera.in_image(q));
            TrueCorner {
                place: c.place,
                point_px: c.point_px,
                visible,
                kind,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use vpmap_metrology::scene::ImageSize;
    use vpmap_metrology::synth::{SynthOptions, synthesize};

    #[test]
    fn value_noise_is_continuous_and_bounded() {
        for k in 0..200 {
            let x = f64::from(k) * 0.173;
            let a = value_noise(x, 0.3 * x, 7);
            let b = value_noise(x + 1e-6, 0.3 * x, 7);
            assert!((-1.0..=1.0).contains(&a));
            assert!((a - b).abs() < 1e-4);
        }
    }

    #[test]
    fn a_prism_is_entered_through_its_near_side() {
        let p = Prism {
            footprint: counter_clockwise(vec![
                Vector2::new(-1.0, 2.0),
                Vector2::new(1.0, 2.0),
                Vector2::new(1.0, 3.0),
                Vector2::new(-1.0, 3.0),
            ]),
            height: 1.0,
            albedo: [0.5; 3],
        };
        let hit = World::prism_entry(&Vector3::new(0.0, 0.0, 0.5), &Vector3::y(), &p);
        assert!(hit.is_some_and(|(t, _)| (t - 2.0).abs() < 1e-12), "{hit:?}");
        let over = World::prism_entry(&Vector3::new(0.0, 0.0, 1.5), &Vector3::y(), &p);
        assert!(over.is_none());
    }

    #[test]
    fn a_rendered_box_corner_lies_on_a_brightness_change() {
        let Ok((scene, truth)) = synthesize(&SynthOptions {
            image: ImageSize {
                width: 320,
                height: 240,
            },
            focal_px: 220.0,
            seed: 3,
            ..SynthOptions::default()
        }) else {
            panic!("synthesize failed");
        };
        let photo = render_photo(&scene, &truth, &PhotoOptions::default());
        let Ok(photo) = photo else {
            panic!("{photo:?}");
        };
        let grey = photo.image.to_luma8();
        let visible: Vec<&TrueCorner> = photo
            .corners
            .iter()
            .filter(|c| c.visible && c.kind == CornerKind::BoxCorner)
            .collect();
        assert!(visible.len() >= 6, "{visible:?}");
        // Around most visible box corners the picture is not flat (a face may happen to
        // match its background's brightness).
        let mut flat = Vec::new();
        for c in &visible {
            let (x, y) = (c.point_px[0] as i64, c.point_px[1] as i64);
            let mut values = Vec::new();
            for dy in -3..=3 {
                for dx in -3..=3 {
                    let (px, py) = (x + dx, y + dy);
                    if px >= 0 && py >= 0 && px < 320 && py < 240 {
                        values.push(f64::from(grey.get_pixel(px as u32, py as u32)[0]));
                    }
                }
            }
            let lo = values.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            if hi - lo <= 12.0 {
                flat.push(c.place.field());
            }
        }
        assert!(5 * flat.len() <= visible.len(), "flat: {flat:?}");
    }
}

//! The camera's part of a rendered photo, for [`super::photo::render_photo`]: Gaussian blur
//! and the JPEG round trip, and what real photos have and the plain renders lack:
//! lens distortion (a one-parameter division model), clutter strokes near the corners and off
//! the room's axes, thin occluders in front of the scene (T-junctions where they cross an
//! edge), and blur that grows towards the photo's corners. Every part is off by default, and
//! then nothing here runs (the plain renders stay byte for byte what they were).
//!
//! **Distortion** (division model, one parameter `k`): for a pixel `p_d` of the distorted
//! photo, with `c` the principal point and `r = |p_d - c| / h` (`h` half the image diagonal,
//! pixels), the undistorted (pinhole) pixel is `p_u = c + (p_d - c) / (1 + k r^2)`. Barrel
//! distortion has `k < 0`; phones lie in about `[-0.12, 0]`. The renderer samples the pinhole
//! scene at `p_u` for every photo pixel `p_d`, and the true corners it returns are distorted
//! ([`distort`], the model's exact inverse).
//!
//! Fitzgibbon, "Simultaneous linear estimation of multiple view geometry and lens
//! distortion", CVPR 2001 (the division model).

use image::codecs::jpeg::{JpegDecoder, JpegEncoder};
use image::{DynamicImage, RgbImage};
use rand::RngExt as _;
use rand_chacha::ChaCha8Rng;

use crate::error::{Result, VisionError};

/// The lens of a rendered photo: the division model's `k` about the principal point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Lens {
    /// Principal point, pixels.
    pub(crate) centre: [f64; 2],
    /// Half the image diagonal, pixels.
    pub(crate) half_diagonal: f64,
    /// The division model's parameter.
    pub(crate) k: f64,
}

impl Lens {
    /// The pinhole pixel a photo pixel shows: `c + (p_d - c) / (1 + k r^2)`.
    pub(crate) fn undistort(&self, p: [f64; 2]) -> [f64; 2] {
        let d = [p[0] - self.centre[0], p[1] - self.centre[1]];
        let r2 = (d[0] * d[0] + d[1] * d[1]) / (self.half_diagonal * self.half_diagonal);
        let s = 1.0 + self.k * r2;
        [self.centre[0] + d[0] / s, self.centre[1] + d[1] / s]
    }

    /// The photo pixel showing a pinhole pixel (the inverse of [`Lens::undistort`]): with
    /// `u = |p_u - c| / h`, `r` solves `r / (1 + k r^2) = u`, the root nearest `u`:
    /// `r = 2 u / (1 + sqrt(1 - 4 k u^2))`. `None` beyond the model's reach
    /// (`1 - 4 k u^2 < 0`, `k > 0` only).
    pub(crate) fn distort(&self, p: [f64; 2]) -> Option<[f64; 2]> {
        let d = [p[0] - self.centre[0], p[1] - self.centre[1]];
        let u = d[0].hypot(d[1]) / self.half_diagonal;
        let disc = 1.0 - 4.0 * self.k * u * u;
        if disc < 0.0 {
            return None;
        }
        // r / u = 2 / (1 + sqrt(disc)), finite at u = 0.
        let ratio = 2.0 / (1.0 + disc.sqrt());
        Some([self.centre[0] + d[0] * ratio, self.centre[1] + d[1] * ratio])
    }
}

/// A thin bar in front of the scene, from image border to image border: straight in the
/// pinhole image, so bowed by the lens like every other straight edge of the photo.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Bar {
    from: [f64; 2],
    to: [f64; 2],
    half_width: f64,
    colour: [f64; 3],
}

impl Bar {
    /// Whether a pinhole pixel lies under the bar (or within `margin` pixels of it).
    pub(crate) fn covers(&self, p: [f64; 2], margin: f64) -> bool {
        segment_distance(p, self.from, self.to) <= self.half_width + margin
    }
}

/// Distance from `p` to the segment `a`-`b`.
fn segment_distance(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let e = [b[0] - a[0], b[1] - a[1]];
    let len2 = e[0] * e[0] + e[1] * e[1];
    let t = if len2 > 0.0 {
        (((p[0] - a[0]) * e[0] + (p[1] - a[1]) * e[1]) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p[0] - a[0] - t * e[0]).hypot(p[1] - a[1] - t * e[1])
}

/// Paint a stroke (a segment `half_width` wide, anti-aliased by its distance from the pixel
/// centre) blending towards `colour` by `opacity`.
/// With a `lens`, the stroke is straight in the pinhole image: each photo pixel's centre is
/// undistorted before its distance is taken (and every pixel of the photo is tried).
fn paint(
    colours: &mut [[f64; 3]],
    width: usize,
    height: usize,
    stroke: ([f64; 2], [f64; 2], f64),
    colour: [f64; 3],
    opacity: f64,
    lens: Option<&Lens>,
) {
    let (a, b, half) = stroke;
    let reach = half + 1.0;
    let (x0, y0, x1, y1) = if lens.is_some() {
        (0, 0, width, height)
    } else {
        (
            (a[0].min(b[0]) - reach).floor().max(0.0) as usize,
            (a[1].min(b[1]) - reach).floor().max(0.0) as usize,
            ((a[0].max(b[0]) + reach).ceil().max(0.0) as usize).min(width),
            ((a[1].max(b[1]) + reach).ceil().max(0.0) as usize).min(height),
        )
    };
    for y in y0..y1 {
        for x in x0..x1 {
            let mut p = [x as f64 + 0.5, y as f64 + 0.5];
            if let Some(lens) = lens {
                p = lens.undistort(p);
            }
            let cover = (half + 0.5 - segment_distance(p, a, b)).clamp(0.0, 1.0) * opacity;
            if cover <= 0.0 {
                continue;
            }
            if let Some(px) = colours.get_mut(y * width + x) {
                for (v, c) in px.iter_mut().zip(colour) {
                    *v += cover * (c - *v);
                }
            }
        }
    }
}

/// Clutter near each corner: `per_corner` short strokes (3 to 25 px long, 0.5 to 1.5 px wide,
/// any direction, a few % to 30 % darker or lighter than the surface) starting within 15 px
/// of the corner: texture, cracks, cables, the edges of posters, none along the room's axes
/// but by chance.
pub(crate) fn draw_clutter(
    colours: &mut [[f64; 3]],
    width: usize,
    height: usize,
    corners: &[[f64; 2]],
    per_corner: usize,
    rng: &mut ChaCha8Rng,
) {
    for c in corners {
        for _ in 0..per_corner {
            let start = [
                c[0] + rng.random_range(-15.0..15.0),
                c[1] + rng.random_range(-15.0..15.0),
            ];
            let angle = rng.random_range(0.0..std::f64::consts::PI);
            let length = rng.random_range(3.0..25.0);
            let end = [
                start[0] + length * angle.cos(),
                start[1] + length * angle.sin(),
            ];
            let half = rng.random_range(0.25..0.75);
            let shade = if rng.random::<bool>() {
                rng.random_range(0.0..0.3)
            } else {
                rng.random_range(0.6..1.0)
            };
            let opacity = rng.random_range(0.1..0.5);
            paint(
                colours,
                width,
                height,
                (start, end, half),
                [shade; 3],
                opacity,
                None,
            );
        }
    }
}

/// `count` thin bars (1.5 to 4 px wide, a uniform grey) across the photo in front of
/// everything, each through a random point of the photo at a random angle: where one crosses
/// an edge of the scene it makes a T junction. Each is straight in the pinhole image and seen
/// through the `lens` (when it has a `k`), as a pole or a cable in front of a real camera.
pub(crate) fn draw_occluders(
    colours: &mut [[f64; 3]],
    width: usize,
    height: usize,
    count: usize,
    lens: &Lens,
    rng: &mut ChaCha8Rng,
) -> Vec<Bar> {
    let diagonal = (width as f64).hypot(height as f64);
    (0..count)
        .map(|_| {
            let through = [
                rng.random_range(0.0..width as f64),
                rng.random_range(0.0..height as f64),
            ];
            let angle = rng.random_range(0.0..std::f64::consts::PI);
            let d = [diagonal * angle.cos(), diagonal * angle.sin()];
            let bar = Bar {
                from: [through[0] - d[0], through[1] - d[1]],
                to: [through[0] + d[0], through[1] + d[1]],
                half_width: rng.random_range(0.75..2.0),
                colour: [rng.random_range(0.05..0.9); 3],
            };
            paint(
                colours,
                width,
                height,
                (bar.from, bar.to, bar.half_width),
                bar.colour,
                1.0,
                (lens.k != 0.0).then_some(lens),
            );
            bar
        })
        .collect()
}

/// Blur that grows towards the photo's corners: the plane blurred with `sigma` and with
/// `sigma (1 + growth)`, mixed by `r^2` (`r` the distance from the centre over half the
/// diagonal), as a lens is softer off its axis.
pub(crate) fn varying_blur(
    plane: &mut [f64],
    width: usize,
    height: usize,
    sigma: f64,
    growth: f64,
) {
    let mut soft = plane.to_vec();
    gaussian_blur(plane, width, height, sigma);
    gaussian_blur(&mut soft, width, height, sigma * (1.0 + growth));
    let (cx, cy) = (0.5 * width as f64, 0.5 * height as f64);
    let h2 = cx * cx + cy * cy;
    for (i, (p, s)) in plane.iter_mut().zip(&soft).enumerate() {
        let (x, y) = ((i % width) as f64 + 0.5 - cx, (i / width) as f64 + 0.5 - cy);
        let t = ((x * x + y * y) / h2).min(1.0);
        *p += t * (s - *p);
    }
}

/// A separable Gaussian blur of a planar float image, mirrored at the borders.
pub(crate) fn gaussian_blur(pixels: &mut [f64], width: usize, height: usize, sigma: f64) {
    if sigma <= 0.0 || width == 0 || height == 0 {
        return;
    }
    let half = (3.0 * sigma).ceil() as isize;
    let kernel: Vec<f64> = (-half..=half)
        .map(|k| (-0.5 * (k as f64 / sigma).powi(2)).exp())
        .collect();
    let total: f64 = kernel.iter().sum();
    let kernel: Vec<f64> = kernel.iter().map(|k| k / total).collect();
    let mirror = |i: isize, n: usize| -> usize {
        let n = n as isize;
        let mut i = i;
        if i < 0 {
            i = -i - 1;
        }
        if i >= n {
            i = 2 * n - i - 1;
        }
        i.clamp(0, n - 1) as usize
    };
    let mut tmp = vec![0.0; pixels.len()];
    for y in 0..height {
        for x in 0..width {
            let mut s = 0.0;
            for (k, w) in kernel.iter().enumerate() {
                let xi = mirror(x as isize + k as isize - half, width);
                s += w * pixels.get(y * width + xi).copied().unwrap_or(0.0);
            }
            if let Some(t) = tmp.get_mut(y * width + x) {
                *t = s;
            }
        }
    }
    for y in 0..height {
        for x in 0..width {
            let mut s = 0.0;
            for (k, w) in kernel.iter().enumerate() {
                let yi = mirror(y as isize + k as isize - half, height);
                s += w * tmp.get(yi * width + x).copied().unwrap_or(0.0);
            }
            if let Some(p) = pixels.get_mut(y * width + x) {
                *p = s;
            }
        }
    }
}

pub(crate) fn jpeg_round_trip(img: &RgbImage, quality: u8) -> Result<DynamicImage> {
    let decode_error = |e: image::ImageError| VisionError::Decode {
        format: "JPEG",
        message: e.to_string(),
    };
    let mut bytes = Vec::new();
    JpegEncoder::new_with_quality(&mut bytes, quality)
        .encode_image(img)
        .map_err(decode_error)?;
    let decoder = JpegDecoder::new(std::io::Cursor::new(bytes)).map_err(decode_error)?;
    DynamicImage::from_decoder(decoder)
        .map(|d| DynamicImage::ImageRgb8(d.to_rgb8()))
        .map_err(decode_error)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distorting_then_undistorting_gives_the_point_back() {
        let lens = Lens {
            centre: [800.0, 600.0],
            half_diagonal: 1000.0,
            k: -0.1,
        };
        for p in [[0.0, 0.0], [1600.0, 1200.0], [812.0, 590.0], [800.0, 600.0]] {
            let Some(d) = lens.distort(p) else {
                panic!("no distorted point");
            };
            let back = lens.undistort(d);
            assert!((back[0] - p[0]).abs() < 1e-9 && (back[1] - p[1]).abs() < 1e-9);
        }
        // Barrel: a corner of the pinhole image moves towards the centre... in the photo the
        // pinhole corner at r_u = 1 is shown at r_d < 1.
        let Some(d) = lens.distort([1600.0, 1200.0]) else {
            panic!("no distorted point");
        };
        assert!(d[0] < 1600.0 && d[1] < 1200.0);
        // The convention: r = |p_d - c| / h, p_u = c + (p_d - c) / (1 + k r^2).
        let u = lens.undistort([1800.0, 600.0]);
        assert!((u[0] - (800.0 + 1000.0 / (1.0 - 0.1))).abs() < 1e-9);
    }
}

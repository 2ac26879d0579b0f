//! The photo as snapping reads it: grey levels, and around one click a smoothed patch with its
//! gradient, sampled bilinearly at sub-pixel positions.

use image::DynamicImage;

/// A photo ready for snapping: its 8-bit pixels (grey, or RGB whose grey level, Rec. 601
/// luma on the 0 to 255 scale, is computed where a patch reads it), row-major. Making one
/// copies the pixels once (no conversion of the whole photo).
#[derive(Clone, Debug)]
pub struct SnapImage {
    width: u32,
    height: u32,
    channels: usize,
    pixels: Vec<u8>,
}

impl SnapImage {
    /// The pixels of a photo (8-bit grey or RGB as they are; other types converted to RGB).
    #[must_use]
    pub fn new(image: &DynamicImage) -> Self {
        let (channels, pixels) = match image {
            DynamicImage::ImageLuma8(g) => (1, g.as_raw().clone()),
            DynamicImage::ImageRgb8(c) => (3, c.as_raw().clone()),
            other => (3, other.to_rgb8().into_raw()),
        };
        Self {
            width: image.width(),
            height: image.height(),
            channels,
            pixels,
        }
    }

    /// Bytes its pixels take (1 a pixel for grey, 3 for RGB).
    #[must_use]
    pub fn pixel_bytes(&self) -> usize {
        self.pixels.len()
    }

    /// Width, pixels.
    #[must_use]
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height, pixels.
    #[must_use]
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The grey level of a pixel (borders clamped).
    fn at(&self, x: i64, y: i64) -> f64 {
        let x = x.clamp(0, i64::from(self.width) - 1) as usize;
        let y = y.clamp(0, i64::from(self.height) - 1) as usize;
        let k = (y * self.width as usize + x) * self.channels;
        match self.pixels.get(k..k + self.channels) {
            Some([g]) => f64::from(*g),
            Some([r, g, b]) => {
                0.299 * f64::from(*r) + 0.587 * f64::from(*g) + 0.114 * f64::from(*b)
            }
            _ => 0.0,
        }
    }
}

/// A square patch around a point: the gradient of the Gaussian-smoothed grey levels at pixel
/// centres (central differences), grey levels per pixel.
pub(crate) struct Patch {
    /// Image column and row of the patch's first pixel.
    x0: i64,
    y0: i64,
    size: usize,
    gx: Vec<f64>,
    gy: Vec<f64>,
}

impl Patch {
    /// The patch of `half` pixels on each side of `centre`, smoothed with `sigma` pixels.
    pub(crate) fn new(image: &SnapImage, centre: [f64; 2], half: usize, sigma: f64) -> Self {
        let margin = (3.0 * sigma).ceil() as usize + 1;
        let size = 2 * half + 1;
        let big = size + 2 * margin;
        let x0 = centre[0].floor() as i64 - half as i64;
        let y0 = centre[1].floor() as i64 - half as i64;
        let (bx, by) = (x0 - margin as i64, y0 - margin as i64);
        let mut grey: Vec<f64> = (0..big * big)
            .map(|k| image.at(bx + (k % big) as i64, by + (k / big) as i64))
            .collect();
        smooth(&mut grey, big, sigma);
        let at = |x: usize, y: usize| grey.get(y * big + x).copied().unwrap_or(0.0);
        let mut gx = vec![0.0; size * size];
        let mut gy = vec![0.0; size * size];
        for y in 0..size {
            for x in 0..size {
                let (sx, sy) = (x + margin, y + margin);
                let k = y * size + x;
                if let (Some(a), Some(b)) = (gx.get_mut(k), gy.get_mut(k)) {
                    *a = 0.5 * (at(sx + 1, sy) - at(sx - 1, sy));
                    *b = 0.5 * (at(sx, sy + 1) - at(sx, sy - 1));
                }
            }
        }
        Self {
            x0,
            y0,
            size,
            gx,
            gy,
        }
    }

    /// Every pixel of the patch: its centre in image pixels and its gradient.
    pub(crate) fn pixels(&self) -> impl Iterator<Item = ([f64; 2], [f64; 2])> + '_ {
        (0..self.size * self.size).map(move |k| {
            let (x, y) = (k % self.size, k / self.size);
            (
                [
                    (self.x0 + x as i64) as f64 + 0.5,
                    (self.y0 + y as i64) as f64 + 0.5,
                ],
                [
                    self.gx.get(k).copied().unwrap_or(0.0),
                    self.gy.get(k).copied().unwrap_or(0.0),
                ],
            )
        })
    }

    /// The gradient at an image position (bilinear between pixel centres; `None` outside the
    /// patch).
    pub(crate) fn gradient(&self, p: [f64; 2]) -> Option<[f64; 2]> {
        let fx = p[0] - self.x0 as f64 - 0.5;
        let fy = p[1] - self.y0 as f64 - 0.5;
        if !(fx >= 0.0 && fy >= 0.0) {
            return None;
        }
        let (ix, iy) = (fx.floor() as usize, fy.floor() as usize);
        if ix + 1 >= self.size || iy + 1 >= self.size {
            return None;
        }
        let (tx, ty) = (fx - ix as f64, fy - iy as f64);
        let k = iy * self.size + ix;
        let lerp = |g: &[f64]| -> Option<f64> {
            let a = *g.get(k)?;
            let b = *g.get(k + 1)?;
            let c = *g.get(k + self.size)?;
            let d = *g.get(k + self.size + 1)?;
            Some((a * (1.0 - tx) + b * tx) * (1.0 - ty) + (c * (1.0 - tx) + d * tx) * ty)
        };
        Some([lerp(&self.gx)?, lerp(&self.gy)?])
    }
}

/// Separable Gaussian smoothing of a square image in place (borders clamped).
fn smooth(pixels: &mut [f64], size: usize, sigma: f64) {
    if sigma <= 0.0 || size == 0 {
        return;
    }
    let half = (3.0 * sigma).ceil() as isize;
    let kernel: Vec<f64> = (-half..=half)
        .map(|k| (-0.5 * (k as f64 / sigma).powi(2)).exp())
        .collect();
    let total: f64 = kernel.iter().sum();
    let n = size as isize;
    let mut tmp = vec![0.0; pixels.len()];
    for y in 0..n {
        for x in 0..n {
            let s: f64 = kernel
                .iter()
                .enumerate()
                .map(|(k, w)| {
                    let xi = (x + k as isize - half).clamp(0, n - 1);
                    w * pixels.get((y * n + xi) as usize).copied().unwrap_or(0.0)
                })
                .sum();
            if let Some(t) = tmp.get_mut((y * n + x) as usize) {
                *t = s / total;
            }
        }
    }
    for y in 0..n {
        for x in 0..n {
            let s: f64 = kernel
                .iter()
                .enumerate()
                .map(|(k, w)| {
                    let yi = (y + k as isize - half).clamp(0, n - 1);
                    w * tmp.get((yi * n + x) as usize).copied().unwrap_or(0.0)
                })
                .sum();
            if let Some(p) = pixels.get_mut((y * n + x) as usize) {
                *p = s / total;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::{GrayImage, Luma};

    #[test]
    fn the_gradient_of_a_step_peaks_at_the_step() {
        // Step at x = 20 (corner coordinates): columns 0..19 dark, 20.. bright.
        let img = GrayImage::from_fn(40, 40, |x, _| Luma([if x < 20 { 50 } else { 150 }]));
        let snap = SnapImage::new(&DynamicImage::ImageLuma8(img));
        let patch = Patch::new(&snap, [20.0, 20.0], 8, 1.0);
        let g = |x: f64| patch.gradient([x, 20.0]).map_or(0.0, |g| g[0]);
        assert!(g(20.0) > g(19.0) && g(20.0) > g(21.0));
        assert!((g(19.5) - g(20.5)).abs() < 1e-9, "symmetric about the step");
        assert!(
            patch
                .gradient([20.0, 20.0])
                .is_some_and(|g| g[1].abs() < 1e-9)
        );
        assert!(patch.gradient([50.0, 20.0]).is_none());
    }
}

//! Where York Urban's labelled lines lie against the photo's own edges: the photo's gradient
//! and, at a labelled corner, each labelled line's offset from the edge the photo shows beside
//! it. [`super::yud`] measures the labels' own error from these offsets (module docs there).

use super::yud::dist;
use crate::stats::median;

/// The photo's grey levels smoothed by a Gaussian of 1 px and their gradient, for locating
/// edges across the labelled lines.
pub(super) struct Gradient {
    width: usize,
    height: usize,
    gx: Vec<f64>,
    gy: Vec<f64>,
}

impl Gradient {
    pub(super) fn new(image: &image::DynamicImage) -> Self {
        let grey = image.to_luma8();
        let (width, height) = (grey.width() as usize, grey.height() as usize);
        let raw: Vec<f64> = grey.as_raw().iter().map(|&v| f64::from(v)).collect();
        let kernel: Vec<f64> = (-3i32..=3)
            .map(|k| (-0.5 * f64::from(k * k)).exp())
            .collect();
        let total: f64 = kernel.iter().sum();
        let pass = |src: &[f64], horizontal: bool| -> Vec<f64> {
            let mut out = vec![0.0; src.len()];
            for y in 0..height {
                for x in 0..width {
                    let mut s = 0.0;
                    for (k, w) in kernel.iter().enumerate() {
                        let o = k as i64 - 3;
                        let (xx, yy) = if horizontal {
                            ((x as i64 + o).clamp(0, width as i64 - 1) as usize, y)
                        } else {
                            (x, (y as i64 + o).clamp(0, height as i64 - 1) as usize)
                        };
                        s += w * src.get(yy * width + xx).copied().unwrap_or(0.0);
                    }
                    if let Some(v) = out.get_mut(y * width + x) {
                        *v = s / total;
                    }
                }
            }
            out
        };
        let smooth = pass(&pass(&raw, true), false);
        let at = |x: usize, y: usize| smooth.get(y * width + x).copied().unwrap_or(0.0);
        let mut gx = vec![0.0; raw.len()];
        let mut gy = vec![0.0; raw.len()];
        for y in 1..height.saturating_sub(1) {
            for x in 1..width.saturating_sub(1) {
                let k = y * width + x;
                if let (Some(a), Some(b)) = (gx.get_mut(k), gy.get_mut(k)) {
                    *a = 0.5 * (at(x + 1, y) - at(x - 1, y));
                    *b = 0.5 * (at(x, y + 1) - at(x, y - 1));
                }
            }
        }
        Self {
            width,
            height,
            gx,
            gy,
        }
    }

    /// The gradient at an image position (pixel centres at `k + 0.5`), bilinear.
    fn at(&self, p: [f64; 2]) -> Option<[f64; 2]> {
        let (fx, fy) = (p[0] - 0.5, p[1] - 0.5);
        if !(fx >= 1.0 && fy >= 1.0) {
            return None;
        }
        let (ix, iy) = (fx.floor() as usize, fy.floor() as usize);
        if ix + 2 >= self.width || iy + 2 >= self.height {
            return None;
        }
        let (tx, ty) = (fx - ix as f64, fy - iy as f64);
        let k = iy * self.width + ix;
        let lerp = |g: &[f64]| -> Option<f64> {
            let (a, b) = (*g.get(k)?, *g.get(k + 1)?);
            let (c, d) = (*g.get(k + self.width)?, *g.get(k + self.width + 1)?);
            Some((a * (1.0 - tx) + b * tx) * (1.0 - ty) + (c * (1.0 - tx) + d * tx) * ty)
        };
        Some([lerp(&self.gx)?, lerp(&self.gy)?])
    }
}

/// Profile step across a labelled line, pixels.
const STEP: f64 = 0.25;
/// Profile samples on each side of a labelled line (3 px).
const HALF: i32 = 12;

/// The offset of the photo's edge from a labelled line at a corner, along the line's normal,
/// pixels: the median over the points 3 to 12 px from the corner along the segment of the
/// sub-pixel gradient maximum across the line (`None` with fewer than 5 such points).
pub(super) fn label_offset(
    grad: &Gradient,
    corner: [f64; 2],
    segment: &[f64; 4],
    normal: [f64; 2],
) -> Option<f64> {
    // Along the segment, away from the corner.
    let (p, q) = ([segment[0], segment[1]], [segment[2], segment[3]]);
    let far = if dist(p, corner) > dist(q, corner) {
        p
    } else {
        q
    };
    let len = dist(far, corner);
    if len < 1e-9 {
        return None;
    }
    let u = [(far[0] - corner[0]) / len, (far[1] - corner[1]) / len];
    let n = normal;
    let profiles: Vec<Vec<f64>> = (3..=12)
        .map(f64::from)
        .filter(|&t| t <= len)
        .map(|t| {
            (-HALF..=HALF)
                .map(|k| {
                    let s = f64::from(k) * STEP;
                    let x = [
                        corner[0] + t * u[0] + s * n[0],
                        corner[1] + t * u[1] + s * n[1],
                    ];
                    grad.at(x).map_or(f64::NAN, |g| g[0] * n[0] + g[1] * n[1])
                })
                .collect()
        })
        .collect();
    // One polarity per segment: the sign of the summed gradient across it.
    let total: f64 = profiles.iter().flatten().filter(|v| v.is_finite()).sum();
    let sign = if total >= 0.0 { 1.0 } else { -1.0 };
    let mut offsets: Vec<f64> = Vec::new();
    for prof in &profiles {
        let best = prof
            .iter()
            .enumerate()
            .filter(|(_, v)| v.is_finite())
            .max_by(|a, b| (sign * a.1).total_cmp(&(sign * b.1)));
        let Some((i, &g)) = best else { continue };
        if i == 0 || i + 1 == prof.len() || sign * g < 2.0 {
            continue;
        }
        let (a, c) = (sign * prof[i - 1], sign * prof[i + 1]);
        let b = sign * g;
        let den = a - 2.0 * b + c;
        let off = if den < -1e-12 {
            (0.5 * (a - c) / den).clamp(-0.5, 0.5)
        } else {
            0.0
        };
        offsets.push((f64::from(i as i32 - HALF) + off) * STEP);
    }
    (offsets.len() >= 5).then(|| median(&offsets)).flatten()
}

//! Input checks and the working image: grey levels, downscaled by area averaging.
//!
//! The working image is the input converted to grey (Rec. 709 luma as `image` computes it,
//! 0-255 scale, whatever the input's depth) and, when its longer side exceeds
//! [`DetectOptions::max_side_px`], shrunk by the factor `s = max_side_px / max(width, height)`
//! with an exact area average (every working pixel is the mean of the input area it covers).
//! Coordinates map exactly between the two with the pixel-corner origin:
//! `x_input = x_working / s`.

use image::DynamicImage;

use crate::detection::DetectOptions;
use crate::error::{Result, VisionError};

/// The smallest image side accepted, pixels.
pub const MIN_SIDE_PX: u32 = 16;
/// The largest image side accepted, pixels.
pub const MAX_SIDE_PX: u32 = 32_768;
/// The smallest [`DetectOptions::max_side_px`] accepted.
pub const MIN_WORKING_SIDE_PX: u32 = 64;
/// The largest two-point tolerance accepted, degrees.
pub const MAX_TWO_POINT_TOLERANCE_DEG: f64 = 45.0;

/// The grey working image.
pub(crate) struct WorkingImage {
    /// Grey levels, 0-255, row-major.
    pub pixels: Vec<f64>,
    /// Width, pixels.
    pub width: usize,
    /// Height, pixels.
    pub height: usize,
    /// Working pixels per input pixel (1 when not downscaled).
    pub scale: f64,
}

/// Check the image size against [`MIN_SIDE_PX`] and [`MAX_SIDE_PX`].
pub(crate) fn check_size(width: u32, height: u32) -> Result<()> {
    let ok = |side: u32| (MIN_SIDE_PX..=MAX_SIDE_PX).contains(&side);
    if ok(width) && ok(height) {
        Ok(())
    } else {
        Err(VisionError::BadImageSize {
            width,
            height,
            max: MAX_SIDE_PX,
        })
    }
}

/// Check every option of [`DetectOptions`].
pub(crate) fn check_options(opts: &DetectOptions) -> Result<()> {
    if let Some(f) = opts.focal_px
        && !(f.is_finite() && f > 0.0 && f < 1e9)
    {
        return Err(VisionError::InvalidParameter {
            field: "focal_px",
            value: f,
            requirement: "must be a positive, finite number of pixels below 1e9",
        });
    }
    if let Some(pp) = opts.principal_point_px {
        for (value, field) in [
            (pp[0], "principal_point_px[0]"),
            (pp[1], "principal_point_px[1]"),
        ] {
            if !(value.is_finite() && value.abs() < 1e9) {
                return Err(VisionError::InvalidParameter {
                    field,
                    value,
                    requirement: "must be a finite number of pixels within +-1e9",
                });
            }
        }
    }
    if let crate::detection::LensOption::Known(k) = opts.lens
        && !(k.is_finite() && k.abs() <= vpmap_metrology::scene::MAX_DIVISION_K)
    {
        return Err(VisionError::InvalidParameter {
            field: "lens",
            value: k,
            requirement: "a known division-model k must lie within -1 to 1",
        });
    }
    if !(MIN_WORKING_SIDE_PX..=MAX_SIDE_PX).contains(&opts.max_side_px) {
        return Err(VisionError::InvalidParameter {
            field: "max_side_px",
            value: f64::from(opts.max_side_px),
            requirement: "must be between 64 and 32768 pixels",
        });
    }
    let tol = opts.two_point_tolerance_deg;
    if !(tol.is_finite() && (0.0..=MAX_TWO_POINT_TOLERANCE_DEG).contains(&tol)) {
        return Err(VisionError::InvalidParameter {
            field: "two_point_tolerance_deg",
            value: tol,
            requirement: "must be between 0 and 45 degrees",
        });
    }
    Ok(())
}

/// Working pixels per input pixel for an image whose longer side is `longer_side` pixels.
pub(crate) fn working_scale(longer_side: u32, max_side_px: u32) -> f64 {
    if longer_side > max_side_px {
        f64::from(max_side_px) / f64::from(longer_side)
    } else {
        1.0
    }
}

/// Rec. 709 luma weights (those of `image`'s own conversion).
const LUMA: [f64; 3] = [0.2126, 0.7152, 0.0722];

/// Grey levels (0-255 scale) of row `y` of `image` into `out` (one value per column).
fn grey_row(image: &DynamicImage, y: u32, out: &mut [f64]) {
    let w = image.width() as usize;
    let luma = |r: f64, g: f64, b: f64| LUMA[0] * r + LUMA[1] * g + LUMA[2] * b;
    match image {
        DynamicImage::ImageLuma8(img) => {
            let row = img
                .as_raw()
                .chunks_exact(w)
                .nth(y as usize)
                .unwrap_or_default();
            for (o, &v) in out.iter_mut().zip(row) {
                *o = f64::from(v);
            }
        }
        DynamicImage::ImageRgb8(img) => {
            let row = img
                .as_raw()
                .chunks_exact(3 * w)
                .nth(y as usize)
                .unwrap_or_default();
            for (o, p) in out.iter_mut().zip(row.chunks_exact(3)) {
                if let [r, g, b] = p {
                    *o = luma(f64::from(*r), f64::from(*g), f64::from(*b));
                }
            }
        }
        DynamicImage::ImageRgba8(img) => {
            let row = img
                .as_raw()
                .chunks_exact(4 * w)
                .nth(y as usize)
                .unwrap_or_default();
            for (o, p) in out.iter_mut().zip(row.chunks_exact(4)) {
                if let [r, g, b, _] = p {
                    *o = luma(f64::from(*r), f64::from(*g), f64::from(*b));
                }
            }
        }
        other => {
            // Rarer layouts (16-bit, float, grey with alpha): per pixel, through `image`.
            use image::{GenericImageView, Pixel};
            for (x, o) in (0..other.width()).zip(out.iter_mut()) {
                let [r, g, b, _] = other.get_pixel(x, y).to_rgba().0;
                *o = luma(f64::from(r), f64::from(g), f64::from(b));
            }
        }
    }
}

/// The grey, possibly downscaled, working image. Streams the input row by row, so a large
/// input costs no more memory than the working image.
pub(crate) fn working_image(image: &DynamicImage, max_side_px: u32) -> WorkingImage {
    let (width, height) = (image.width(), image.height());
    let scale = working_scale(width.max(height), max_side_px);
    let (width, height) = (width as usize, height as usize);
    let mut row = vec![0.0f64; width];
    if scale >= 1.0 {
        let mut pixels = vec![0.0f64; width * height];
        for (y, out) in (0..).zip(pixels.chunks_exact_mut(width)) {
            grey_row(image, y, out);
        }
        return WorkingImage {
            pixels,
            width,
            height,
            scale: 1.0,
        };
    }
    let out_w = ((width as f64 * scale).round() as usize).max(1);
    let out_h = ((height as f64 * scale).round() as usize).max(1);
    // One common scale keeps the pixel grid square; the last row and column absorb the
    // rounding (under one working pixel).
    let columns = area_spans(width, out_w, scale);
    let rows = area_spans(height, out_h, scale);
    // For each input row, the output rows it contributes to, with weights.
    let mut row_targets: Vec<Vec<(usize, f64)>> = vec![Vec::new(); height];
    for (o, span) in rows.iter().enumerate() {
        for &(i, w) in &span.taps {
            if let Some(t) = row_targets.get_mut(i) {
                t.push((o, w));
            }
        }
    }
    let mut pixels = vec![0.0f64; out_w * out_h];
    let mut reduced = vec![0.0f64; out_w];
    for (y, targets) in (0..).zip(&row_targets) {
        grey_row(image, y, &mut row);
        for (slot, span) in reduced.iter_mut().zip(&columns) {
            *slot = span
                .taps
                .iter()
                .map(|&(i, w)| w * row.get(i).copied().unwrap_or(0.0))
                .sum();
        }
        for &(o, w) in targets {
            if let Some(dst) = pixels.get_mut(o * out_w..(o + 1) * out_w) {
                for (d, v) in dst.iter_mut().zip(&reduced) {
                    *d += w * v;
                }
            }
        }
    }
    WorkingImage {
        pixels,
        width: out_w,
        height: out_h,
        scale,
    }
}

/// The input samples (index, weight) one output sample averages.
struct AreaSpan {
    taps: Vec<(usize, f64)>,
}

/// Area-average spans: output sample `o` covers input `[o / scale, (o + 1) / scale)`, clipped
/// to the input; weights are the overlap lengths, normalised.
fn area_spans(len_in: usize, len_out: usize, scale: f64) -> Vec<AreaSpan> {
    (0..len_out)
        .map(|o| {
            let start = (o as f64 / scale).min(len_in as f64);
            let end = if o + 1 == len_out {
                len_in as f64
            } else {
                ((o + 1) as f64 / scale).min(len_in as f64)
            };
            let first = start.floor() as usize;
            let last = (end.ceil() as usize).min(len_in);
            let mut taps: Vec<(usize, f64)> = (first..last)
                .map(|i| {
                    let lo = (i as f64).max(start);
                    let hi = ((i + 1) as f64).min(end);
                    (i, (hi - lo).max(0.0))
                })
                .filter(|&(_, w)| w > 0.0)
                .collect();
            let total: f64 = taps.iter().map(|&(_, w)| w).sum();
            if total > 0.0 {
                for tap in &mut taps {
                    tap.1 /= total;
                }
            } else {
                taps = vec![(first.min(len_in.saturating_sub(1)), 1.0)];
            }
            AreaSpan { taps }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::{GrayImage, Luma};

    #[test]
    fn area_spans_cover_the_input_once() {
        let spans = area_spans(2000, 640, 640.0 / 2000.0);
        let mut coverage = vec![0.0; 2000];
        for span in &spans {
            let total: f64 = span.taps.iter().map(|t| t.1).sum();
            assert!((total - 1.0).abs() < 1e-12);
            for &(i, w) in &span.taps {
                coverage[i] += w * 2000.0 / 640.0;
            }
        }
        assert!(coverage.iter().all(|&c| (c - 1.0).abs() < 1e-9));
    }

    #[test]
    fn downscaling_keeps_a_flat_image_flat_and_the_step_in_place() {
        let image = GrayImage::from_fn(1000, 500, |x, _| Luma([if x < 500 { 10 } else { 200 }]));
        let work = working_image(&DynamicImage::ImageLuma8(image), 250);
        assert_eq!((work.width, work.height), (250, 125));
        assert!((work.scale - 0.25).abs() < 1e-12);
        let row = &work.pixels[..250];
        assert!((row[0] - 10.0).abs() < 1e-9 && (row[249] - 200.0).abs() < 1e-9);
        assert!((row[124] - 10.0).abs() < 1e-9 && (row[125] - 200.0).abs() < 1e-9);
    }

    #[test]
    fn sizes_and_options_are_checked() {
        assert!(check_size(15, 100).is_err());
        assert!(check_size(100, 40_000).is_err());
        assert!(check_size(16, 32_768).is_ok());
        let bad = DetectOptions {
            focal_px: Some(f64::NAN),
            ..DetectOptions::default()
        };
        assert!(check_options(&bad).is_err());
        let bad = DetectOptions {
            two_point_tolerance_deg: -1.0,
            ..DetectOptions::default()
        };
        assert!(check_options(&bad).is_err());
        let bad = DetectOptions {
            max_side_px: 10,
            ..DetectOptions::default()
        };
        assert!(check_options(&bad).is_err());
        assert!(check_options(&DetectOptions::default()).is_ok());
    }
}

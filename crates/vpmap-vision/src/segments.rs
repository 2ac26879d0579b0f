//! Line segments: LSD (Grompone von Gioi et al.) through the `lsdetect` crate.
//!
//! The working image (see [`DetectOptions::max_side_px`]) is sub-sampled at LSD's standard
//! scale 0.8 (a Gaussian of `sigma = 0.6 / 0.8` pixels, which removes JPEG blocking and
//! staircase edges; done here, as the article does it) and goes to [`lsdetect::detect`]:
//! gradient-magnitude ordering, region growing with a 22.5 degree tolerance, rectangle
//! approximation and the a-contrario validation `NFA <= 1`. No parameter is tuned: LSD's
//! defaults are the ones its authors derive.
//!
//! Coordinates: `lsdetect` reports pixel *centres* at integer coordinates; every
//! [`Segment`] here is in *input-image* pixels with the origin at the top-left corner of the
//! top-left pixel (pixel centres at `i + 0.5`), the convention of `docs/scene-format.md`.

use image::DynamicImage;

use crate::detection::{DetectOptions, Segment};
use crate::error::Result;
use crate::prepare::{self, WorkingImage};

/// LSD's standard working scale (the article's `S = 0.8`).
pub const LSD_SCALE: f64 = 0.8;

/// Find the line segments of `image` with LSD, longest first, in input-image pixels.
///
/// Only [`DetectOptions::max_side_px`] matters here.
///
/// # Errors
/// [`crate::VisionError::BadImageSize`] for an image outside 16..=32768 pixels a side,
/// [`crate::VisionError::InvalidParameter`] for invalid options.
///
/// # Example
/// ```
/// use image::{DynamicImage, GrayImage, Luma};
/// // A dark square on a light background: four edges.
/// let img = GrayImage::from_fn(120, 100, |x, y| {
///     Luma([if (30..90).contains(&x) && (20..80).contains(&y) { 40 } else { 210 }])
/// });
/// let segments = vpmap_vision::detect_segments(
///     &DynamicImage::ImageLuma8(img),
///     &vpmap_vision::DetectOptions::default(),
/// )?;
/// assert!(segments.len() >= 4);
/// assert!(segments[0].length_px() > 40.0);
/// # Ok::<(), vpmap_vision::VisionError>(())
/// ```
pub fn detect_segments(image: &DynamicImage, opts: &DetectOptions) -> Result<Vec<Segment>> {
    prepare::check_size(image.width(), image.height())?;
    prepare::check_options(opts)?;
    let work = prepare::working_image(image, opts.max_side_px);
    Ok(segments_of(&work))
}

/// LSD on the working image, mapped back to input pixels.
pub(crate) fn segments_of(work: &WorkingImage) -> Vec<Segment> {
    let (small, w, h) = gaussian_sampling(&work.pixels, work.width, work.height, LSD_SCALE);
    // Scale 1: the sub-sampling above is LSD's own, done here (faster than lsdetect's, and
    // with the article's sub-pixel kernel centres).
    let Ok(found) = lsdetect::detect(&small, w, h, 1.0) else {
        return Vec::new();
    };
    // lsdetect's coordinates: sub-sampled image, pixel centres at integers. Working image,
    // centres at integers: `q / LSD_SCALE`; corner origin: `+ 0.5`; input: `/ work.scale`.
    let to_input = |q: f64| (q / LSD_SCALE + 0.5) / work.scale;
    let mut segments: Vec<Segment> = found
        .iter()
        .map(|s| Segment {
            start_px: [to_input(s.x1), to_input(s.y1)],
            end_px: [to_input(s.x2), to_input(s.y2)],
            // lsdetect's `log_nfa` holds -log10(NFA) (positive for a valid segment), as its
            // code computes it, whatever its field doc says.
            strength: s.log_nfa,
        })
        .filter(|s| s.start_px.iter().chain(&s.end_px).all(|v| v.is_finite()))
        .collect();
    segments.sort_by(|a, b| b.length_px().total_cmp(&a.length_px()));
    segments
}

/// LSD's Gaussian sub-sampling (the article's `gaussian_sampling`): output pixel `x` (centre
/// at integer coordinates) is the Gaussian-weighted mean around input position `x / scale`,
/// `sigma = 0.6 / scale`, kernel half-width `ceil(sigma sqrt(4 ln 10))`, mirrored at the
/// borders. Output size `ceil(width scale) x ceil(height scale)`.
fn gaussian_sampling(
    image: &[f64],
    width: usize,
    height: usize,
    scale: f64,
) -> (Vec<f64>, usize, usize) {
    let out_w = ((width as f64 * scale).ceil() as usize).max(1);
    let out_h = ((height as f64 * scale).ceil() as usize).max(1);
    let sigma = LSD_SIGMA_SCALE / scale;
    let half = (sigma * (4.0 * std::f64::consts::LN_10).sqrt()).ceil() as usize;
    let columns = kernels(width, out_w, scale, sigma, half);
    let rows = kernels(height, out_h, scale, sigma, half);
    let mut horizontal = vec![0.0; out_w * height];
    for (src, dst) in image
        .chunks_exact(width)
        .zip(horizontal.chunks_exact_mut(out_w))
    {
        for (d, taps) in dst.iter_mut().zip(&columns) {
            *d = taps
                .iter()
                .map(|&(i, k)| k * src.get(i).copied().unwrap_or(0.0))
                .sum();
        }
    }
    let mut out = vec![0.0; out_w * out_h];
    for (dst, taps) in out.chunks_exact_mut(out_w).zip(&rows) {
        for &(i, k) in taps {
            if let Some(src) = horizontal.get(i * out_w..(i + 1) * out_w) {
                for (d, v) in dst.iter_mut().zip(src) {
                    *d += k * v;
                }
            }
        }
    }
    (out, out_w, out_h)
}

/// LSD's `sigma_scale`.
const LSD_SIGMA_SCALE: f64 = 0.6;

/// Per output sample: the input samples and normalised Gaussian weights (mirrored borders).
fn kernels(
    len_in: usize,
    len_out: usize,
    scale: f64,
    sigma: f64,
    half: usize,
) -> Vec<Vec<(usize, f64)>> {
    let period = 2 * len_in;
    (0..len_out)
        .map(|o| {
            let centre = o as f64 / scale;
            let nearest = (centre + 0.5).floor() as isize;
            let mut taps: Vec<(usize, f64)> = (-(half as isize)..=half as isize)
                .map(|k| {
                    let j = nearest + k;
                    let d = j as f64 - centre;
                    let mut m = j.rem_euclid(period as isize) as usize;
                    if m >= len_in {
                        m = period - 1 - m;
                    }
                    (m, (-0.5 * d * d / (sigma * sigma)).exp())
                })
                .collect();
            let total: f64 = taps.iter().map(|t| t.1).sum();
            for t in &mut taps {
                t.1 /= total;
            }
            taps
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::{GrayImage, Luma};

    #[test]
    fn a_vertical_step_gives_a_long_vertical_segment_at_the_edge() {
        // Edge between columns 59 and 60: x = 60 in corner coordinates.
        let img = GrayImage::from_fn(120, 100, |x, _| Luma([if x < 60 { 50 } else { 200 }]));
        let segs = detect_segments(&DynamicImage::ImageLuma8(img), &DetectOptions::default())
            .unwrap_or_default();
        let s = segs.first().copied().unwrap_or(Segment {
            start_px: [0.0; 2],
            end_px: [0.0; 2],
            strength: 0.0,
        });
        assert!(s.length_px() > 80.0, "{s:?}");
        let x = 0.5 * (s.start_px[0] + s.end_px[0]);
        assert!((x - 60.0).abs() < 0.75, "edge at x = {x}");
        assert!(s.strength > 0.0);
    }

    #[test]
    fn a_flat_image_has_no_segment() {
        let img = GrayImage::from_pixel(64, 64, Luma([128]));
        let segs = detect_segments(&DynamicImage::ImageLuma8(img), &DetectOptions::default());
        assert!(segs.is_ok_and(|s| s.is_empty()));
    }
}

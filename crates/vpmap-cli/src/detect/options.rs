//! The detector's options shared by `vpmap detect` and `vpmap eval-detect`: their defaults,
//! and the checks of `--max-side` and `--two-point-tolerance`.

use anyhow::{Result, bail};
use vpmap_pipeline::num;
use vpmap_vision::DetectOptions;

/// Accepted `--max-side` values, pixels.
const MAX_SIDE_RANGE: std::ops::RangeInclusive<u32> = 64..=8192;
/// Accepted `--two-point-tolerance` values, degrees.
const TOLERANCE_RANGE_DEG: std::ops::RangeInclusive<f64> = 0.0..=30.0;

/// The detector's defaults.
pub fn default_options() -> DetectOptions {
    DetectOptions::default()
}

/// `--two-point-tolerance` must be within [`TOLERANCE_RANGE_DEG`].
pub fn check_two_point_tolerance(tolerance_deg: f64) -> Result<()> {
    if !(tolerance_deg.is_finite() && TOLERANCE_RANGE_DEG.contains(&tolerance_deg)) {
        bail!(
            "--two-point-tolerance must be from {} to {} degrees, got {}",
            TOLERANCE_RANGE_DEG.start(),
            TOLERANCE_RANGE_DEG.end(),
            num(tolerance_deg)
        );
    }
    Ok(())
}

/// `--max-side` must be within [`MAX_SIDE_RANGE`].
pub fn check_max_side(max_side: u32) -> Result<()> {
    if !MAX_SIDE_RANGE.contains(&max_side) {
        bail!(
            "--max-side must be from {} to {} pixels, got {max_side}",
            MAX_SIDE_RANGE.start(),
            MAX_SIDE_RANGE.end(),
        );
    }
    Ok(())
}

/// `--lens`: `estimate`, `none` or a known division-model `k`.
///
/// # Errors
/// Anything else, or a `k` outside -1..1, named.
pub fn parse_lens(text: &str) -> Result<vpmap_vision::LensOption> {
    use vpmap_vision::LensOption;
    match text.trim() {
        "estimate" => Ok(LensOption::Estimate),
        "none" => Ok(LensOption::Pinhole),
        other => match other.parse::<f64>() {
            Ok(k) if k.is_finite() && k.abs() <= vpmap_metrology::scene::MAX_DIVISION_K => {
                Ok(LensOption::Known(k + 0.0))
            }
            _ => bail!(
                "--lens {text:?} is not `estimate`, `none` or a division-model k within -1 to 1 (barrel lenses about -0.15 to 0)"
            ),
        },
    }
}

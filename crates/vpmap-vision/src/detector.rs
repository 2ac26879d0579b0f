//! The detector: a photo to its segments, Manhattan vanishing points and camera ([`detect`]),
//! or segments found elsewhere to the vanishing points and camera
//! ([`detect_from_segments`]).

use nalgebra::Vector2;
use vpmap_metrology::scene::{DivisionModel, ImageSize, VpChart};

use crate::detection::{DetectOptions, Detection, LensOption, Segment, VanishingPoint};
use crate::distortion::{LensEstimate, estimate_division_k};
use crate::error::Result;
use crate::{manhattan, prepare, segments};
use vpmap_metrology::calibration::Perspective;

/// Rounds of lens estimation and detection again ([`LensOption::Estimate`]): a second one
/// moved York Urban's AUC by at most 0.3 points and its focal figures not at all, at twice
/// the cost.
const LENS_ROUNDS: usize = 1;

/// Find line segments, the three Manhattan vanishing points and the camera in `image`.
///
/// The image is converted to grey and, when its longer side exceeds
/// [`DetectOptions::max_side_px`], downscaled by area averaging; segments come from LSD
/// ([`segments`](crate::segments)), the vanishing points and the camera from [`manhattan`](crate::manhattan). All results are in
/// input-image pixels.
///
/// Without [`DetectOptions::focal_px`] the focal length is estimated together with the
/// vanishing points. Without [`DetectOptions::principal_point_px`] the principal point is
/// estimated only in clear three-point perspective (the vertical direction tilted by at least
/// [`manhattan::PRINCIPAL_POINT_MIN_TILT_DEG`](crate::manhattan::PRINCIPAL_POINT_MIN_TILT_DEG)); otherwise the vanishing points do not fix it
/// (in two-point perspective it may slide along the horizon, and near it its distance from the
/// horizon trades off against the pitch), and the image centre is used
/// ([`Detection::principal_point_estimated`] tells which).
///
/// # Errors
/// * [`VisionError::BadImageSize`](crate::VisionError::BadImageSize) when a side is below [`MIN_SIDE_PX`](crate::MIN_SIDE_PX) or above
///   [`MAX_SIDE_PX`](crate::MAX_SIDE_PX);
/// * [`VisionError::InvalidParameter`](crate::VisionError::InvalidParameter) for an invalid option;
/// * [`VisionError::NotEnoughLines`](crate::VisionError::NotEnoughLines) when the image has too few straight edges to fix the
///   vanishing points (blank, noise, blurred);
/// * [`VisionError::NoOrthogonalDirections`](crate::VisionError::NoOrthogonalDirections) when its edges do not point along two or more
///   orthogonal directions (all parallel, say).
///
/// # Complexity
/// Linear in the number of pixels of the working image (LSD), plus about
/// `6 x 40 x N` segment tests for `N <= 350` segments when the focal length is searched.
/// About 30 ms for a 640 x 480 photo on one core.
pub fn detect(image: &image::DynamicImage, opts: &DetectOptions) -> Result<Detection> {
    prepare::check_size(image.width(), image.height())?;
    prepare::check_options(opts)?;
    let work = prepare::working_image(image, opts.max_side_px);
    let segments = segments::segments_of(&work);
    detect_from_segments(segments, [image.width(), image.height()], opts)
}

/// The vanishing points and the camera from segments found elsewhere (another detector, or
/// hand-labelled ones), for an image of `image_size_px` = `[width, height]` pixels.
///
/// The segments are in input-image pixels; thresholds are applied at the scale
/// [`detect`] would analyse this image at (see [`DetectOptions::max_side_px`]).
///
/// # Errors
/// As [`detect`].
pub fn detect_from_segments(
    segments: Vec<Segment>,
    image_size_px: [u32; 2],
    opts: &DetectOptions,
) -> Result<Detection> {
    prepare::check_size(image_size_px[0], image_size_px[1])?;
    prepare::check_options(opts)?;
    let scale = prepare::working_scale(image_size_px[0].max(image_size_px[1]), opts.max_side_px);
    let find = |segments: &[Segment]| {
        manhattan::estimate(
            segments,
            image_size_px,
            scale,
            opts.focal_px,
            opts.principal_point_px,
            opts.focal_prior,
            opts.seed,
        )
    };
    let first = find(&segments)?;
    let image = ImageSize {
        width: image_size_px[0],
        height: image_size_px[1],
    };
    let centre = opts.principal_point_px.unwrap_or([
        0.5 * f64::from(image_size_px[0]),
        0.5 * f64::from(image_size_px[1]),
    ]);
    let (estimate, lens) = match opts.lens {
        LensOption::Pinhole => (first, None),
        LensOption::Known(k) => {
            let lens = LensEstimate {
                model: DivisionModel::new(k, image, Some(centre)),
                estimated_k: k,
                k_sd: 0.0,
                segments_k_sd: None,
                segments: 0,
            };
            let pinhole: Vec<Segment> = segments.iter().map(|s| lens.undistort(s)).collect();
            (find(&pinhole)?, Some(lens))
        }
        LensOption::Estimate => {
            // Estimate k on the pinhole frame's support, then find the frame again from the
            // segments undistorted by it (LENS_ROUNDS times).
            let mut current = first;
            let mut lens = None;
            for _ in 0..LENS_ROUNDS {
                let chart = VpChart {
                    focal_px: current.intrinsics.focal_px,
                    centre_px: Vector2::from(current.intrinsics.principal_point_px),
                };
                let Some(found) = estimate_division_k(
                    &segments,
                    &current.support,
                    &current.directions,
                    &chart,
                    image,
                    centre,
                ) else {
                    break;
                };
                if found.k() == 0.0 {
                    // Not clearly a lens: the pinhole frame stands.
                    lens = Some(found);
                    break;
                }
                let pinhole: Vec<Segment> = segments.iter().map(|s| found.undistort(s)).collect();
                match find(&pinhole) {
                    Ok(next) => {
                        current = next;
                        lens = Some(found);
                    }
                    Err(_) => break,
                }
            }
            (current, lens)
        }
    };
    let k = estimate.intrinsics;
    let vanishing_points: Vec<VanishingPoint> = estimate
        .directions
        .iter()
        .zip(estimate.support)
        .enumerate()
        .map(|(i, (d, support))| VanishingPoint {
            point_px: (d[2].abs() > 1e-12).then(|| {
                [
                    k.focal_px * d[0] / d[2] + k.principal_point_px[0],
                    k.focal_px * d[1] / d[2] + k.principal_point_px[1],
                ]
            }),
            direction_camera: *d,
            segments: support,
            vertical: i == 2,
        })
        .collect();
    let tilt_deg = estimate.directions[2][2].abs().min(1.0).asin().to_degrees();
    Ok(Detection {
        image_size_px,
        segments,
        vanishing_points,
        intrinsics: k,
        focal_estimated: opts.focal_px.is_none(),
        principal_point_estimated: estimate.principal_point_estimated,
        principal_point_given: opts.principal_point_px.is_some(),
        focal_prior: opts.focal_prior.filter(|_| opts.focal_px.is_none()),
        perspective: if tilt_deg < opts.two_point_tolerance_deg {
            Perspective::TwoPoint
        } else {
            Perspective::ThreePoint
        },
        vertical_tilt_deg: tilt_deg,
        lens,
    })
}

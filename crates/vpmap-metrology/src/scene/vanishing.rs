//! Resolving a scene's vanishing points: given points, directions, or the least-squares
//! intersection of clicked segments.

use nalgebra::{Matrix3, Vector2, Vector3};

use super::types::{ImageSize, Scene};
use crate::error::{MetrologyError, Result};

impl Scene {
    /// Whether the vanishing points' order was set by a tool that names each one: some are
    /// given only by segments (drawn on the page under their names, or written by
    /// `vpmap eval`). Vanishing points all given as points or directions may come in any
    /// data set's order ([`crate::calibration::reading`]).
    #[must_use]
    pub fn vanishing_points_labelled(&self) -> bool {
        self.vanishing_points
            .iter()
            .any(|v| v.point.is_none() && v.direction.is_none())
    }

    /// The vanishing points in homogeneous pixel coordinates `(x, y, w)`, in the order given:
    /// a given point as `(x, y, 1)`, a direction as `(dx, dy, 0)`, segments by their
    /// least-squares intersection ([`intersect_segments`]) as `(x, y, 1)`. Which one is
    /// vertical is decided by [`crate::calibration::vertical_index`].
    ///
    /// # Errors
    /// [`MetrologyError::ParallelLines`] when a set of segments meets at infinity.
    pub fn resolve_vanishing_points(&self) -> Result<Vec<Vector3<f64>>> {
        let n = self.vanishing_points.len();
        self.vanishing_points
            .iter()
            .enumerate()
            .map(|(i, vp)| {
                if let Some(d) = vp.direction {
                    return Ok(Vector3::new(d[0], d[1], 0.0));
                }
                if let Some(p) = vp.point {
                    return Ok(Vector3::new(p[0], p[1], 1.0));
                }
                intersect_segments(&vp.lines, self.image)
                    .map(|p| Vector3::new(p.x, p.y, 1.0))
                    .map_err(|fit| match fit {
                    SegmentFit::Parallel => MetrologyError::ParallelLines {
                        index: i + 1,
                        hint: if n == 3 {
                            "; for a level camera (vertical edges parallel in the photo) give the vertical vanishing point as a `direction`, or only the two horizontal ones".to_owned()
                        } else {
                            String::new()
                        },
                    },
                    SegmentFit::Collinear => MetrologyError::InvalidField {
                        field: format!("vanishing_points[{i}].lines"),
                        reason: "the segments lie on one line, so they do not fix a point: click edges on different lines that run to the vanishing point".to_owned(),
                    },
                    SegmentFit::Overflow => MetrologyError::InvalidField {
                        field: format!("vanishing_points[{i}].lines"),
                        reason: "the segments' coordinates are too large for their intersection to be computed: give them in pixels of the image".to_owned(),
                    },
                })
            })
            .collect()
    }
}

/// The least-squares intersection of the lines through two or more segments.
///
/// Each segment `[x1, y1, x2, y2]` gives a homogeneous line, normalised so that its value at a
/// point is the point's distance to it; the intersection minimises the sum of squared
/// distances in homogeneous form (smallest eigenvector of the 3x3 normal matrix), computed in
/// coordinates centred on the image and scaled by its diagonal for conditioning.
///
/// # Errors
/// [`SegmentFit::Parallel`] when the lines meet at infinity (further than 1e7 image diagonals
/// away), [`SegmentFit::Collinear`] when they all lie on one line (no single point).
///
/// # Example
/// ```
/// use vpmap_metrology::scene::{intersect_segments, ImageSize};
/// let image = ImageSize { width: 100, height: 100 };
/// let vp = intersect_segments(&[[0.0, 0.0, 1.0, 1.0], [10.0, 0.0, 9.0, 1.0]], image).unwrap();
/// assert!((vp.x - 5.0).abs() < 1e-9 && (vp.y - 5.0).abs() < 1e-9);
/// ```
pub fn intersect_segments(
    segments: &[[f64; 4]],
    image: ImageSize,
) -> std::result::Result<Vector2<f64>, SegmentFit> {
    let c = image.centre();
    let s = image.diagonal();
    let mut m = Matrix3::<f64>::zeros();
    for seg in segments {
        let a = Vector3::new((seg[0] - c.x) / s, (seg[1] - c.y) / s, 1.0);
        let b = Vector3::new((seg[2] - c.x) / s, (seg[3] - c.y) / s, 1.0);
        let l = a.cross(&b);
        let norm = l.x.hypot(l.y);
        if norm <= f64::EPSILON {
            continue;
        }
        let l = l / norm;
        m += l * l.transpose();
    }
    let eig = crate::linalg::symmetric_eigen(m).ok_or(SegmentFit::Overflow)?;
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| eig.eigenvalues[a].total_cmp(&eig.eigenvalues[b]));
    // Two vanishing eigenvalues: every line is the same line.
    if eig.eigenvalues[order[1]] <= 1e-12 * eig.eigenvalues.sum().max(f64::MIN_POSITIVE) {
        return Err(SegmentFit::Collinear);
    }
    let v = eig.eigenvectors.column(order[0]);
    if v.z.abs() < 1e-7 * v.x.hypot(v.y) {
        return Err(SegmentFit::Parallel);
    }
    Ok(Vector2::new(v.x / v.z * s + c.x, v.y / v.z * s + c.y))
}

/// Why a set of segments fixes no vanishing point.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SegmentFit {
    /// The lines are parallel: they meet only at infinity.
    Parallel,
    /// The segments all lie on one line.
    Collinear,
    /// The lines' coordinates are so large that their intersection overflows.
    Overflow,
}

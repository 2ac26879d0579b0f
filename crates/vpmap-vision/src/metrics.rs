//! Accuracy figures for vanishing directions, as Lu et al. (2017) report them.
//!
//! * The error of a detected direction against a true one is the angle between the two
//!   *lines* (sign-free): `acos |a . b|`, degrees.
//! * The three detected directions are matched to the three true ones vertical to vertical,
//!   and the two horizontals by the assignment with the smaller sum of errors.
//!
//! The figures made from these errors (fractions within a threshold, the area under the
//! accuracy curve, medians) and the York Urban scorer are in `vpmap_eval::stats` and
//! `vpmap_eval::detection`.

/// The angle between the lines of two directions (sign-free), degrees. `NaN` when either is
/// zero.
#[must_use]
pub fn line_angle_deg(a: [f64; 3], b: [f64; 3]) -> f64 {
    let dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let na = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    let nb = (b[0] * b[0] + b[1] * b[1] + b[2] * b[2]).sqrt();
    (dot.abs() / (na * nb)).min(1.0).acos().to_degrees()
}

/// Errors of three detected directions against three true ones, degrees, in the order of
/// `truth`: the vertical ones (`detected_vertical`, `truth_vertical`: their indices) are
/// matched to each other, the horizontal ones by the assignment with the smaller sum.
///
/// # Example
/// ```
/// use vpmap_vision::metrics::manhattan_errors_deg;
/// let truth = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
/// // Horizontals swapped and signs flipped: no error.
/// let found = [[0.0, 0.0, -1.0], [-1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
/// let e = manhattan_errors_deg(&found, 2, &truth, 1);
/// assert!(e.iter().all(|&x| x < 1e-9));
/// ```
#[must_use]
pub fn manhattan_errors_deg(
    detected: &[[f64; 3]; 3],
    detected_vertical: usize,
    truth: &[[f64; 3]; 3],
    truth_vertical: usize,
) -> [f64; 3] {
    let dv = detected_vertical.min(2);
    let tv = truth_vertical.min(2);
    let dh: Vec<usize> = (0..3).filter(|&k| k != dv).collect();
    let th: Vec<usize> = (0..3).filter(|&k| k != tv).collect();
    let get = |set: &[[f64; 3]; 3], k: usize| set.get(k).copied().unwrap_or([0.0; 3]);
    let pick = |v: &[usize], k: usize| v.get(k).copied().unwrap_or(0);
    let err = |d: usize, t: usize| line_angle_deg(get(detected, d), get(truth, t));
    let straight = [
        err(pick(&dh, 0), pick(&th, 0)),
        err(pick(&dh, 1), pick(&th, 1)),
    ];
    let crossed = [
        err(pick(&dh, 1), pick(&th, 0)),
        err(pick(&dh, 0), pick(&th, 1)),
    ];
    let horizontal = if straight[0] + straight[1] <= crossed[0] + crossed[1] {
        straight
    } else {
        crossed
    };
    let mut out = [0.0; 3];
    out[tv] = err(dv, tv);
    for (slot, e) in th.iter().zip(horizontal) {
        if let Some(o) = out.get_mut(*slot) {
            *o = e;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn angles_are_sign_free() {
        assert!(line_angle_deg([1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]) < 1e-9);
        let e = line_angle_deg([1.0, 0.0, 0.0], [1.0, 1.0, 0.0]);
        assert!((e - 45.0).abs() < 1e-9);
    }

    #[test]
    fn the_horizontal_assignment_is_the_better_one() {
        let truth = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        let a = 2f64.to_radians();
        let found = [
            [0.0, a.sin(), a.cos()],
            [0.0, 1.0, 0.0],
            [a.cos(), 0.0, a.sin()],
        ];
        let e = manhattan_errors_deg(&found, 1, &truth, 1);
        assert!((e[0] - 2.0).abs() < 1e-9 && e[1] < 1e-9 && (e[2] - 2.0).abs() < 1e-9);
    }
}

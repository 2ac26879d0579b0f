//! A small Levenberg-Marquardt least-squares solver.
//!
//! We keep our own rather than the `levenberg-marquardt` crate: that one is a port of MINPACK
//! (trust region, QR, analytic Jacobian), whose iterates and so the detections would differ.

use nalgebra::{DMatrix, DVector};

/// Minimise `|r(x)|^2` by Levenberg-Marquardt with a forward-difference Jacobian.
pub(super) fn levenberg_marquardt(
    mut x: Vec<f64>,
    residuals: impl Fn(&[f64], &mut Vec<f64>),
    iterations: usize,
) -> Vec<f64> {
    let n = x.len();
    let mut r = Vec::new();
    residuals(&x, &mut r);
    let mut cost: f64 = r.iter().map(|v| v * v).sum();
    if !cost.is_finite() {
        return x;
    }
    let mut lambda = 1e-3;
    let mut probe = Vec::new();
    let mut trial_r = Vec::new();
    for _ in 0..iterations {
        let m = r.len();
        let mut columns = Vec::with_capacity(n);
        for j in 0..n {
            let h = 1e-7;
            probe.clone_from(&x);
            if let Some(p) = probe.get_mut(j) {
                *p += h;
            }
            residuals(&probe, &mut trial_r);
            if trial_r.len() != m {
                return x;
            }
            columns.push(DVector::from_iterator(
                m,
                trial_r.iter().zip(&r).map(|(a, b)| (a - b) / h),
            ));
        }
        let jac = DMatrix::from_columns(&columns);
        let jt = jac.transpose();
        let jtj = &jt * &jac;
        let jtr = &jt * DVector::from_column_slice(&r);
        let mut improved = false;
        for _ in 0..8 {
            let damping = jtj.diagonal().map(|d| lambda * (d + 1e-12));
            let a = &jtj + DMatrix::from_diagonal(&damping);
            let Some(chol) = a.cholesky() else {
                lambda *= 10.0;
                continue;
            };
            let step = chol.solve(&(-&jtr));
            let trial: Vec<f64> = x.iter().zip(step.iter()).map(|(a, b)| a + b).collect();
            residuals(&trial, &mut trial_r);
            let trial_cost: f64 = trial_r.iter().map(|v| v * v).sum();
            if trial_r.len() == m && trial_cost.is_finite() && trial_cost < cost {
                let gain = cost - trial_cost;
                x = trial;
                std::mem::swap(&mut r, &mut trial_r);
                cost = trial_cost;
                lambda = (lambda * 0.3).max(1e-9);
                improved = gain > 1e-12 * cost.max(1.0);
                break;
            }
            lambda *= 10.0;
        }
        if !improved {
            break;
        }
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn levenberg_marquardt_fits_a_line() {
        let pts = [(0.0, 1.0), (1.0, 3.1), (2.0, 4.9), (3.0, 7.0)];
        let x = levenberg_marquardt(
            vec![0.0, 0.0],
            |x, out| {
                out.clear();
                out.extend(pts.iter().map(|(t, y)| x[0] * t + x[1] - y));
            },
            20,
        );
        assert!(
            (x[0] - 1.98).abs() < 1e-3 && (x[1] - 1.03).abs() < 1e-3,
            "{x:?}"
        );
    }
}

//! Eigen and singular value decompositions that cannot panic or spin on what a user's input
//! makes of them.
//!
//! nalgebra's `SVD::new` panics ("Singular value was NaN") when its iteration produces a NaN,
//! which finite but extreme inputs do (a fit that ran towards a focal length of 1e159 gives
//! rays whose cross terms underflow), and its `symmetric_eigen` iterates without a limit, so a
//! NaN entry would never converge. These wrappers refuse non-finite input, bound the
//! iterations, and check the output, answering `None` where the callers already handle a
//! singular or degenerate system.

use nalgebra::{
    DMatrix, DefaultAllocator, Dim, DimSub, OMatrix, SVD, SymmetricEigen, U1, allocator::Allocator,
};

/// Iterations allowed before a decomposition is declared not to converge; nalgebra's
/// iterations converge in a few dozen sweeps on any well-scaled matrix of the sizes used here.
const MAX_ITERATIONS: usize = 10_000;

/// The symmetric eigendecomposition of `m`, or `None` when `m` has a non-finite entry, the
/// iteration does not converge, or the result is not finite.
#[must_use]
pub fn symmetric_eigen<D>(m: OMatrix<f64, D, D>) -> Option<SymmetricEigen<f64, D>>
where
    D: Dim + DimSub<U1>,
    DefaultAllocator: Allocator<D, D> + Allocator<D> + Allocator<<D as DimSub<U1>>::Output>,
{
    if !m.iter().all(|v| v.is_finite()) {
        return None;
    }
    let eig = SymmetricEigen::try_new(m, f64::EPSILON, MAX_ITERATIONS)?;
    (eig.eigenvalues.iter().all(|v| v.is_finite())
        && eig.eigenvectors.iter().all(|v| v.is_finite()))
    .then_some(eig)
}

/// The thin singular value decomposition of `a` (with U and V), singular values in no
/// particular order, or `None` when `a` has a non-finite entry, the iteration does not
/// converge, or a singular value is not finite.
#[must_use]
pub fn svd(a: DMatrix<f64>) -> Option<SVD<f64, nalgebra::Dyn, nalgebra::Dyn>> {
    if !a.iter().all(|v| v.is_finite()) {
        return None;
    }
    let svd = SVD::try_new_unordered(a, true, true, f64::EPSILON, MAX_ITERATIONS)?;
    svd.singular_values
        .iter()
        .all(|v| v.is_finite())
        .then_some(svd)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Matrix2;

    #[test]
    fn refuses_non_finite_input() {
        assert!(symmetric_eigen(Matrix2::new(1.0, f64::NAN, f64::NAN, 1.0)).is_none());
        assert!(symmetric_eigen(Matrix2::new(f64::INFINITY, 0.0, 0.0, 1.0)).is_none());
        assert!(svd(DMatrix::from_row_slice(2, 2, &[1.0, f64::NAN, 0.0, 1.0])).is_none());
    }

    #[test]
    fn agrees_with_a_known_decomposition() {
        // [[2, 1], [1, 2]] has eigenvalues 1 and 3.
        let eig = symmetric_eigen(Matrix2::new(2.0, 1.0, 1.0, 2.0)).unwrap();
        let mut e: Vec<f64> = eig.eigenvalues.iter().copied().collect();
        e.sort_by(f64::total_cmp);
        assert!((e[0] - 1.0).abs() < 1e-12 && (e[1] - 3.0).abs() < 1e-12);
        // diag(3, 4) scaled by a rotation keeps singular values 3 and 4.
        let (s, c) = 0.3f64.sin_cos();
        let r = DMatrix::from_row_slice(2, 2, &[c, -s, s, c]);
        let a = &r * DMatrix::from_row_slice(2, 2, &[3.0, 0.0, 0.0, 4.0]);
        let d = svd(a).unwrap();
        let mut sv: Vec<f64> = d.singular_values.iter().copied().collect();
        sv.sort_by(f64::total_cmp);
        assert!((sv[0] - 3.0).abs() < 1e-12 && (sv[1] - 4.0).abs() < 1e-12);
    }
}

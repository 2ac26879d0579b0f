//! The cells bugs stand on as signed integer pairs ([`Xy`]), their conversions and the
//! small arithmetic on them.

use crate::grid::CellXy;
use crate::los::{Passable, PassableGrid};

/// Cell coordinates as signed integers.
pub(super) type Xy = (i64, i64);

#[inline]
pub(super) fn to_i(c: CellXy) -> Xy {
    (c.x as i64, c.y as i64)
}

#[inline]
pub(super) fn to_u(c: Xy) -> CellXy {
    CellXy::new(c.0 as usize, c.1 as usize)
}

/// Whether a bug may stand on cell `c`.
#[inline]
pub(super) fn passable(grid: &PassableGrid, c: Xy) -> bool {
    grid.passable(c.0, c.1)
}

#[inline]
pub(super) fn add(a: Xy, b: Xy) -> Xy {
    (a.0 + b.0, a.1 + b.1)
}

#[inline]
pub(super) fn d2(a: Xy, b: Xy) -> i64 {
    (a.0 - b.0).pow(2) + (a.1 - b.1).pow(2)
}

#[inline]
pub(super) fn dist(a: Xy, b: Xy) -> f64 {
    ((a.0 - b.0) as f64).hypot((a.1 - b.1) as f64)
}

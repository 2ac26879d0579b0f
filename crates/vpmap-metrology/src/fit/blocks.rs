//! The block structure inside one part of the fit's normal matrix ([`super::solve`]): a
//! part's parameters in the groups no residual couples ([`PartBlock`]), its Jacobian's columns
//! in colours no residual spans ([`Coloring`]), and that Jacobian kept dense or sparse
//! ([`OwnJacobian`]). A footprint's vertices each fix only their own click, so with these its
//! step costs time linear in its vertices; a box is one dense group.

use nalgebra::{DMatrix, DVector};

/// A part's own Jacobian in [`super::solve::Model::normal`]: dense, or column by column its non-zero
/// entries (a coloured part's, [`super::solve::Model::coloured_jacobian`]), never stored densely (a footprint
/// of 1,000 vertices would be 2,002 x 2,001).
pub(super) enum OwnJacobian {
    Dense(DMatrix<f64>),
    Sparse(Vec<Vec<(usize, f64)>>),
}

/// Columns of a part's Jacobian in colours (Curtis, Powell & Reid, "On the estimation of sparse
/// Jacobian matrices", 1974): no residual depends on two columns of one colour, so one
/// central difference perturbs a whole colour and gives each column exactly the values it
/// would alone. A footprint of n vertices takes three colours (every x, every y, the height)
/// instead of 2n + 1 columns, each of which evaluates all 2n + 2 residuals.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Coloring {
    /// Each colour's columns (parameter indices within the part).
    pub colors: Vec<Vec<usize>>,
    /// Per colour, per residual, which of that colour's columns (an index into its list) the
    /// residual depends on, if any.
    pub owners: Vec<Vec<Option<usize>>>,
}

/// A part's block of `J^T J` (or of its inverse), split into the groups of the part's
/// parameters that no residual couples: a footprint's vertices each fix only their own click,
/// so its block is block diagonal after a permutation, and is built, inverted and applied
/// group by group (linear in the vertices, not cubic). A box, whose every parameter meets
/// every other in some residual, is one group, handled exactly as a dense block.
///
/// The groups come from the Jacobian's zero pattern at the point: two parameters share a
/// group when some residual depends on both, or through a chain of such residuals. Entries
/// of `J^T J` between groups are then exactly zero there, so nothing is approximated.
#[derive(Debug, Clone)]
pub(crate) struct PartBlock {
    /// The part's number of parameters.
    len: usize,
    /// Each group's parameter indices within the part, ascending; `None` for one group of
    /// every parameter in order (the dense case, kept free of gathers).
    pub(super) groups: Option<Vec<Vec<usize>>>,
    /// Each group's square block.
    pub(super) blocks: Vec<DMatrix<f64>>,
}

impl PartBlock {
    /// `jo^T jo` of a part's own Jacobian (`m` residuals by `k` parameters).
    pub(super) fn gram(jo: &DMatrix<f64>) -> Self {
        let (m, k) = jo.shape();
        if one_group(jo) {
            return Self {
                len: k,
                groups: None,
                blocks: vec![jo.transpose() * jo],
            };
        }
        // Column by column (the matrix is column-major).
        let ColumnGroups {
            groups,
            group_of_column,
            first_in_row,
        } = column_groups(
            m,
            k,
            (0..k).flat_map(|c| {
                (0..m)
                    .filter(move |&row| jo[(row, c)] != 0.0)
                    .map(move |row| (row, c))
            }),
        );
        if groups.len() <= 1 {
            return Self {
                len: k,
                groups: None,
                blocks: vec![jo.transpose() * jo],
            };
        }
        // Each row touches one group (or none): gather that group's rows and columns.
        let mut rows: Vec<Vec<usize>> = vec![Vec::new(); groups.len()];
        for (row, &c) in first_in_row.iter().enumerate() {
            if c != usize::MAX {
                rows[group_of_column[c]].push(row);
            }
        }
        let blocks = groups
            .iter()
            .zip(&rows)
            .map(|(cols, rows)| {
                let sub = DMatrix::from_fn(rows.len(), cols.len(), |i, j| jo[(rows[i], cols[j])]);
                sub.transpose() * &sub
            })
            .collect();
        Self {
            len: k,
            groups: Some(groups),
            blocks,
        }
    }

    /// [`PartBlock::gram`] of a Jacobian given column by column as its non-zero entries
    /// (`(row, value)`, rows ascending).
    pub(super) fn gram_sparse(m: usize, columns: &[Vec<(usize, f64)>]) -> Self {
        let k = columns.len();
        let ColumnGroups { groups, .. } = column_groups(
            m,
            k,
            columns
                .iter()
                .enumerate()
                .flat_map(|(c, column)| column.iter().map(move |&(row, _)| (row, c))),
        );
        // Each entry of a group's block: the dot product of two sparse columns.
        let dot = |a: &[(usize, f64)], b: &[(usize, f64)]| {
            let (mut i, mut j, mut sum) = (0, 0, 0.0);
            while i < a.len() && j < b.len() {
                match a[i].0.cmp(&b[j].0) {
                    std::cmp::Ordering::Less => i += 1,
                    std::cmp::Ordering::Greater => j += 1,
                    std::cmp::Ordering::Equal => {
                        sum += a[i].1 * b[j].1;
                        i += 1;
                        j += 1;
                    }
                }
            }
            sum
        };
        let blocks = groups
            .iter()
            .map(|cols| {
                let mut b = DMatrix::zeros(cols.len(), cols.len());
                for (x, &ca) in cols.iter().enumerate() {
                    for (y, &cb) in cols.iter().enumerate().skip(x) {
                        let v = dot(&columns[ca], &columns[cb]);
                        b[(x, y)] = v;
                        b[(y, x)] = v;
                    }
                }
                b
            })
            .collect();
        Self {
            len: k,
            groups: (groups.len() > 1).then_some(groups),
            blocks,
        }
    }

    /// The same groups with each block mapped by `f` (`None` when `f` fails on one).
    pub(super) fn map(&self, f: impl Fn(&DMatrix<f64>) -> Option<DMatrix<f64>>) -> Option<Self> {
        Some(Self {
            len: self.len,
            groups: self.groups.clone(),
            blocks: self.blocks.iter().map(f).collect::<Option<_>>()?,
        })
    }

    /// `self * v`.
    pub(super) fn mul_vec(&self, v: &DVector<f64>) -> DVector<f64> {
        let Some(groups) = &self.groups else {
            return &self.blocks[0] * v;
        };
        let mut out = DVector::zeros(self.len);
        for (cols, b) in groups.iter().zip(&self.blocks) {
            let sub = DVector::from_fn(cols.len(), |i, _| v[cols[i]]);
            for (&c, y) in cols.iter().zip((b * sub).iter()) {
                out[c] = *y;
            }
        }
        out
    }

    /// `a * self`, `a` with `len` columns.
    pub(super) fn left_mul(&self, a: &DMatrix<f64>) -> DMatrix<f64> {
        let Some(groups) = &self.groups else {
            return a * &self.blocks[0];
        };
        let mut out = DMatrix::zeros(a.nrows(), self.len);
        for (cols, b) in groups.iter().zip(&self.blocks) {
            let prod = a.select_columns(cols.iter()) * b;
            for (j, &c) in cols.iter().enumerate() {
                out.set_column(c, &prod.column(j));
            }
        }
        out
    }

    /// The smallest eigenvalue of the block scaled to unit diagonal (each group's, the least).
    pub(super) fn scaled_min_eigenvalue(&self) -> f64 {
        self.blocks
            .iter()
            .map(super::solve::scaled_min_eigenvalue)
            .fold(1.0, f64::min)
    }
}

/// The groups of a part's columns that no residual couples, from the non-zero entries of its
/// Jacobian (`(row, column)`, any order): union-find over the columns, each row joining its
/// columns to the first one it was seen with.
struct ColumnGroups {
    /// Each group's columns, ascending; groups in the order of their first column.
    groups: Vec<Vec<usize>>,
    /// Each column's group.
    group_of_column: Vec<usize>,
    /// Each row's first column seen (`usize::MAX` for a row of zeros).
    first_in_row: Vec<usize>,
}

fn column_groups(
    m: usize,
    k: usize,
    entries: impl Iterator<Item = (usize, usize)>,
) -> ColumnGroups {
    let mut parent: Vec<usize> = (0..k).collect();
    let mut first_in_row = vec![usize::MAX; m];
    for (row, c) in entries {
        if first_in_row[row] == usize::MAX {
            first_in_row[row] = c;
        } else {
            let (a, b) = (root(&mut parent, first_in_row[row]), root(&mut parent, c));
            parent[a.max(b)] = a.min(b);
        }
    }
    let mut group_of_root = vec![usize::MAX; k];
    let mut groups: Vec<Vec<usize>> = Vec::new();
    let group_of_column: Vec<usize> = (0..k)
        .map(|c| {
            let r = root(&mut parent, c);
            if group_of_root[r] == usize::MAX {
                group_of_root[r] = groups.len();
                groups.push(Vec::new());
            }
            groups[group_of_root[r]].push(c);
            group_of_root[r]
        })
        .collect();
    ColumnGroups {
        groups,
        group_of_column,
        first_in_row,
    }
}

/// The root of `a` in a union-find forest (halving the path on the way).
fn root(parent: &mut [usize], mut a: usize) -> usize {
    while parent[a] != a {
        parent[a] = parent[parent[a]];
        a = parent[a];
    }
    a
}

/// Whether a part of at most 64 parameters is one group, decided without allocating (the
/// common case, a box, on every step of the fit): the columns reachable from the first through
/// shared rows, as a bit mask, grown until it stops. `false` for more parameters (then
/// [`PartBlock::gram`] finds the groups in general).
fn one_group(jo: &DMatrix<f64>) -> bool {
    let (m, k) = jo.shape();
    if k == 0 || k > 64 {
        return k == 0;
    }
    let all = if k == 64 { u64::MAX } else { (1u64 << k) - 1 };
    let row_mask = |row: usize| {
        (0..k).fold(0u64, |acc, c| {
            if jo[(row, c)] == 0.0 {
                acc
            } else {
                acc | (1 << c)
            }
        })
    };
    let mut reached = 1u64;
    loop {
        let before = reached;
        for row in 0..m {
            let r = row_mask(row);
            if r & reached != 0 {
                reached |= r;
            }
        }
        if reached == all {
            return true;
        }
        if reached == before {
            return false;
        }
    }
}

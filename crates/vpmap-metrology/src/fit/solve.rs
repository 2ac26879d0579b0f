//! Sparse Levenberg-Marquardt for the fit (Hartley & Zisserman, appendix A6.3-A6.4).
//!
//! The normal matrix has the "arrowhead" shape of bundle adjustment: a small camera block
//! `U`, one block `V_o` per object (objects share only the camera), and the couplings `W_o`.
//! Each step is solved by the Schur complement `S = U - sum W_o V_o^-1 W_o^T`, so the work
//! grows linearly with the number of objects; the same solve gives `Sigma g` for the error
//! bars. Written here rather than taken from the `levenberg-marquardt` crate because that
//! crate solves the dense normal equations (cubic in the number of objects, over the 5 ms a
//! 20-object scene may take) and has no access to this structure.
//!
//! Jacobians are central differences (relative step 1e-6): every residual depends on the
//! camera and at most one object, so a column costs one object's residuals.

use nalgebra::{DMatrix, DVector, Matrix2, Vector2};

use super::blocks::{Coloring, OwnJacobian, PartBlock};
use super::model::{Camera, Part, VpEvidence, vp_residual_count, vp_residuals};
use crate::interrupt::Interrupt;

/// The least-squares problem: camera parameters first, then each part's.
#[derive(Debug, Clone)]
pub(crate) struct Problem {
    /// Number of camera parameters (4, or 6 with the principal point).
    pub camera_len: usize,
    /// The principal point when it is held fixed.
    pub fixed_pp: Option<Vector2<f64>>,
    /// The pitch is held at its starting value (0 in two-point perspective, where the scene
    /// format defines the camera as level).
    pub fixed_pitch: bool,
    /// The objects (and floor points).
    pub parts: Vec<Part>,
    /// Start of each part's parameters in the vector.
    pub offsets: Vec<usize>,
    /// Evidence per vanishing point, in scene order.
    pub vps: Vec<VpEvidence>,
    /// Per part, per clicked point, the whitening of its covariance when the scene gives one
    /// (empty when it gives none): the point's residual is `W r`.
    pub weights: Vec<Vec<Option<Matrix2<f64>>>>,
    /// Stops the minimiser early ([`minimise`] looks at it before every iteration).
    pub interrupt: Interrupt,
}

/// The blocks of `J^T J` and `J^T r` at one point.
#[derive(Debug, Clone)]
pub(crate) struct Normal {
    u: DMatrix<f64>,
    gc: DVector<f64>,
    v: Vec<PartBlock>,
    w: Vec<DMatrix<f64>>,
    go: Vec<DVector<f64>>,
}

/// Why a solve of the normal equations failed: which block is singular.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Singular {
    /// The camera block (after eliminating the objects).
    Camera,
    /// One part's block.
    Part(usize),
}

fn step_size(x: f64) -> f64 {
    1e-6 * x.abs().max(1.0)
}

/// A least-squares model in the fit's "arrowhead" shape: a camera block (every photo's camera
/// parameters) that every residual may depend on, then parts (objects, floor points) whose
/// residuals depend on the camera block and their own parameters only. [`minimise`], the
/// normal equations and the error bars work on any such model: one photo's [`Problem`] and a
/// room's several photos alike.
pub(crate) trait Model {
    /// Number of camera-block parameters.
    fn camera_len(&self) -> usize;
    /// Whether camera-block parameter `c` is held fixed.
    fn camera_fixed(&self, c: usize) -> bool;
    /// Number of parts.
    fn part_count(&self) -> usize;
    /// Start of part `i`'s parameters in the vector.
    fn part_offset(&self, i: usize) -> usize;
    /// Number of part `i`'s parameters.
    fn part_len(&self, i: usize) -> usize;
    /// Number of part `i`'s residuals.
    fn part_residual_count(&self, i: usize) -> usize;
    /// Number of groups of residuals that depend on the camera block only (one per vanishing
    /// point).
    fn camera_group_count(&self) -> usize;
    /// Number of residuals of camera group `g`.
    fn camera_group_len(&self, g: usize) -> usize;
    /// Residuals of camera group `g` for camera block `c` into `out`.
    fn camera_group_residuals(&self, g: usize, c: &[f64], out: &mut [f64]);
    /// What the parts' residuals need of a camera block (the cameras it makes), computed
    /// once for every part that uses it.
    type Cameras;
    /// The cameras of camera block `c`.
    fn cameras(&self, c: &[f64]) -> Self::Cameras;
    /// Residuals of part `i` for `cameras` and part parameters `p` into `out`; `false` when a
    /// point falls behind a camera.
    fn part_residuals_with(
        &self,
        i: usize,
        cameras: &Self::Cameras,
        p: &[f64],
        out: &mut [f64],
    ) -> bool;

    /// Whether the work must stop ([`minimise`] then returns where it is, not converged).
    fn stopped(&self) -> bool {
        false
    }

    /// Whether some clicks carry their own covariance (then the click noise of the error
    /// bars is 1 px unless given: the covariances are absolute).
    fn has_click_covariances(&self) -> bool {
        false
    }

    /// Whether part `i`'s residuals may depend on camera-block parameter `c` (a room's object
    /// does not depend on the cameras of photos that do not show it): the Jacobian's other
    /// columns are zero and are not computed.
    fn part_uses_camera(&self, _i: usize, _c: usize) -> bool {
        true
    }

    /// Part `i`'s own columns in groups that no residual spans ([`Coloring`]), for a part with
    /// many parameters each reaching few residuals (a footprint); `None` takes the columns one
    /// by one.
    fn part_coloring(&self, _i: usize) -> Option<Coloring> {
        None
    }

    /// Part `i`'s own Jacobian at `cameras` and parameters `own` by one central difference a
    /// colour of `coloring`, as its non-zero entries column by column (`(row, value)`, rows
    /// ascending); `None` where a residual fails.
    fn coloured_jacobian(
        &self,
        i: usize,
        cameras: &Self::Cameras,
        own: &[f64],
        coloring: &Coloring,
    ) -> Option<Vec<Vec<(usize, f64)>>> {
        let m = self.part_residual_count(i);
        let mut columns = vec![Vec::new(); own.len()];
        let (mut plus, mut minus) = (vec![0.0; m], vec![0.0; m]);
        let mut p = own.to_vec();
        // A colour's columns perturbed together: each residual moves with at most one of them,
        // by exactly what it would alone.
        for (colour, owner) in coloring.colors.iter().zip(&coloring.owners) {
            let h: Vec<f64> = colour.iter().map(|&c| step_size(own[c])).collect();
            for (&c, h) in colour.iter().zip(&h) {
                p[c] = own[c] + h;
            }
            let ok_p = self.part_residuals_with(i, cameras, &p, &mut plus);
            for (&c, h) in colour.iter().zip(&h) {
                p[c] = own[c] - h;
            }
            let ok_m = self.part_residuals_with(i, cameras, &p, &mut minus);
            for &c in colour {
                p[c] = own[c];
            }
            if !(ok_p && ok_m) {
                return None;
            }
            for (row, slot) in owner.iter().enumerate() {
                if let Some(j) = *slot {
                    let value = (plus[row] - minus[row]) / (2.0 * h[j]);
                    if value != 0.0 {
                        columns[colour[j]].push((row, value));
                    }
                }
            }
        }
        Some(columns)
    }

    /// Total number of parameters.
    fn len(&self) -> usize {
        self.camera_len()
            + (0..self.part_count())
                .map(|i| self.part_len(i))
                .sum::<usize>()
    }

    /// Total number of residuals.
    fn residual_count(&self) -> usize {
        (0..self.camera_group_count())
            .map(|g| self.camera_group_len(g))
            .sum::<usize>()
            + (0..self.part_count())
                .map(|i| self.part_residual_count(i))
                .sum::<usize>()
    }

    /// Every residual, camera groups first; `None` when a point falls behind a camera or a
    /// value is not finite.
    fn residuals(&self, x: &[f64]) -> Option<Vec<f64>> {
        let nc = self.camera_len();
        let mut out = vec![0.0; self.residual_count()];
        let mut at = 0;
        for g in 0..self.camera_group_count() {
            let n = self.camera_group_len(g);
            self.camera_group_residuals(g, &x[..nc], &mut out[at..at + n]);
            at += n;
        }
        let cameras = self.cameras(&x[..nc]);
        for i in 0..self.part_count() {
            let n = self.part_residual_count(i);
            let off = self.part_offset(i);
            let p = &x[off..off + self.part_len(i)];
            if !self.part_residuals_with(i, &cameras, p, &mut out[at..at + n]) {
                return None;
            }
            at += n;
        }
        out.iter().all(|v| v.is_finite()).then_some(out)
    }

    /// Sum of squared residuals, or infinity where [`Model::residuals`] fails.
    fn cost(&self, x: &[f64]) -> f64 {
        self.residuals(x)
            .map_or(f64::INFINITY, |r| r.iter().map(|v| v * v).sum())
    }

    /// The normal-equation blocks at `x` (`None` where the residuals fail).
    fn normal(&self, x: &[f64]) -> Option<Normal> {
        let nc = self.camera_len();
        let mut u = DMatrix::zeros(nc, nc);
        let mut gc = DVector::zeros(nc);
        let mut xs = x[..nc].to_vec();
        let free: Vec<usize> = (0..nc).filter(|&c| !self.camera_fixed(c)).collect();
        // Camera groups (vanishing points): camera only.
        for g in 0..self.camera_group_count() {
            let m = self.camera_group_len(g);
            let mut r = vec![0.0; m];
            self.camera_group_residuals(g, &x[..nc], &mut r);
            let mut j = DMatrix::zeros(m, nc);
            let (mut plus, mut minus) = (vec![0.0; m], vec![0.0; m]);
            for &c in &free {
                let h = step_size(x[c]);
                xs[c] = x[c] + h;
                self.camera_group_residuals(g, &xs, &mut plus);
                xs[c] = x[c] - h;
                self.camera_group_residuals(g, &xs, &mut minus);
                xs[c] = x[c];
                for row in 0..m {
                    j[(row, c)] = (plus[row] - minus[row]) / (2.0 * h);
                }
            }
            let r = DVector::from_vec(r);
            u += j.transpose() * &j;
            gc += j.transpose() * r;
        }
        // Parts: residuals and own columns at the cameras of `x`; their camera columns below,
        // each perturbed camera block's cameras made once for every part that uses it.
        let parts = self.part_count();
        let base = self.cameras(&x[..nc]);
        let mut rs = Vec::with_capacity(parts);
        let mut jos = Vec::with_capacity(parts);
        for i in 0..parts {
            let (m, k, off) = (
                self.part_residual_count(i),
                self.part_len(i),
                self.part_offset(i),
            );
            let own = &x[off..off + k];
            let mut r = vec![0.0; m];
            if !self.part_residuals_with(i, &base, own, &mut r) {
                return None;
            }
            if let Some(coloring) = self.part_coloring(i) {
                rs.push(r);
                jos.push(OwnJacobian::Sparse(
                    self.coloured_jacobian(i, &base, own, &coloring)?,
                ));
                continue;
            }
            let (mut plus, mut minus) = (vec![0.0; m], vec![0.0; m]);
            let mut jo = DMatrix::zeros(m, k);
            let mut p = own.to_vec();
            for c in 0..k {
                let h = step_size(p[c]);
                p[c] = x[off + c] + h;
                let ok_p = self.part_residuals_with(i, &base, &p, &mut plus);
                p[c] = x[off + c] - h;
                let ok_m = self.part_residuals_with(i, &base, &p, &mut minus);
                p[c] = x[off + c];
                if !(ok_p && ok_m) {
                    return None;
                }
                for row in 0..m {
                    jo[(row, c)] = (plus[row] - minus[row]) / (2.0 * h);
                }
            }
            rs.push(r);
            jos.push(OwnJacobian::Dense(jo));
        }
        let mut jcs: Vec<DMatrix<f64>> = (0..parts)
            .map(|i| DMatrix::zeros(self.part_residual_count(i), nc))
            .collect();
        let longest = (0..parts)
            .map(|i| self.part_residual_count(i))
            .max()
            .unwrap_or(0);
        let (mut plus, mut minus) = (vec![0.0; longest], vec![0.0; longest]);
        for &c in &free {
            let users: Vec<usize> = (0..parts)
                .filter(|&i| self.part_uses_camera(i, c))
                .collect();
            if users.is_empty() {
                continue;
            }
            let h = step_size(x[c]);
            xs[c] = x[c] + h;
            let cams_p = self.cameras(&xs);
            xs[c] = x[c] - h;
            let cams_m = self.cameras(&xs);
            xs[c] = x[c];
            for i in users {
                let (m, k, off) = (
                    self.part_residual_count(i),
                    self.part_len(i),
                    self.part_offset(i),
                );
                let own = &x[off..off + k];
                let ok_p = self.part_residuals_with(i, &cams_p, own, &mut plus[..m]);
                let ok_m = self.part_residuals_with(i, &cams_m, own, &mut minus[..m]);
                if !(ok_p && ok_m) {
                    return None;
                }
                for row in 0..m {
                    jcs[i][(row, c)] = (plus[row] - minus[row]) / (2.0 * h);
                }
            }
        }
        let mut v = Vec::with_capacity(parts);
        let mut w = Vec::with_capacity(parts);
        let mut go = Vec::with_capacity(parts);
        for ((r, jo), jc) in rs.into_iter().zip(jos).zip(jcs) {
            let r = DVector::from_vec(r);
            u += jc.transpose() * &jc;
            gc += jc.transpose() * &r;
            match jo {
                OwnJacobian::Dense(jo) => {
                    v.push(PartBlock::gram(&jo));
                    w.push(jc.transpose() * &jo);
                    go.push(jo.transpose() * r);
                }
                OwnJacobian::Sparse(columns) => {
                    v.push(PartBlock::gram_sparse(r.len(), &columns));
                    let mut wi = DMatrix::zeros(jc.ncols(), columns.len());
                    let mut gi = DVector::zeros(columns.len());
                    for (c, column) in columns.iter().enumerate() {
                        for &(row, value) in column {
                            for a in 0..jc.ncols() {
                                wi[(a, c)] += jc[(row, a)] * value;
                            }
                            gi[c] += value * r[row];
                        }
                    }
                    w.push(wi);
                    go.push(gi);
                }
            }
        }
        // A held parameter: a unit row and column, so its step is 0 and it carries no
        // variance into what is reported (the gradients skip it too).
        for c in (0..nc).filter(|&c| self.camera_fixed(c)) {
            u[(c, c)] = 1.0;
        }
        Some(Normal { u, gc, v, w, go })
    }
}

impl Model for Problem {
    fn camera_len(&self) -> usize {
        self.camera_len
    }

    fn camera_fixed(&self, c: usize) -> bool {
        c == 1 && self.fixed_pitch
    }

    fn part_count(&self) -> usize {
        self.parts.len()
    }

    fn part_offset(&self, i: usize) -> usize {
        self.offsets[i]
    }

    fn part_len(&self, i: usize) -> usize {
        self.parts[i].len()
    }

    fn part_residual_count(&self, i: usize) -> usize {
        self.parts[i].residual_count()
    }

    fn camera_group_count(&self) -> usize {
        self.vps.len()
    }

    fn camera_group_len(&self, g: usize) -> usize {
        vp_residual_count(&self.vps[g])
    }

    fn camera_group_residuals(&self, g: usize, c: &[f64], out: &mut [f64]) {
        vp_residuals(&self.camera(c), g, &self.vps[g], out);
    }

    type Cameras = Camera;

    fn cameras(&self, c: &[f64]) -> Camera {
        self.camera(c)
    }

    fn stopped(&self) -> bool {
        self.interrupt.check().is_some()
    }

    fn part_residuals_with(&self, i: usize, camera: &Camera, p: &[f64], out: &mut [f64]) -> bool {
        let ok = self.parts[i].residuals(camera, p, out);
        if let Some(ws) = self.weights.get(i) {
            whiten(ws, out);
        }
        ok
    }

    fn has_click_covariances(&self) -> bool {
        self.weights.iter().flatten().any(Option::is_some)
    }

    fn part_coloring(&self, i: usize) -> Option<Coloring> {
        self.parts[i].coloring()
    }
}

impl Problem {
    /// The camera for parameter vector `x` (or its camera block).
    pub fn camera(&self, x: &[f64]) -> Camera {
        Camera::from_params(&x[..self.camera_len], self.fixed_pp)
    }
}

/// Apply each clicked point's whitening (where it has one) to its two residuals.
pub(crate) fn whiten(weights: &[Option<Matrix2<f64>>], out: &mut [f64]) {
    for (n, w) in weights.iter().enumerate() {
        if let Some(w) = w
            && let Some(pair) = out.get_mut(2 * n..2 * n + 2)
        {
            let r = w * Vector2::new(pair[0], pair[1]);
            pair[0] = r.x;
            pair[1] = r.y;
        }
    }
}

/// Smallest eigenvalue of a symmetric matrix scaled to unit diagonal: 0 for a singular one.
pub(super) fn scaled_min_eigenvalue(a: &DMatrix<f64>) -> f64 {
    let n = a.nrows();
    if n == 0 {
        return 1.0;
    }
    let d: Vec<f64> = (0..n)
        .map(|i| a[(i, i)].max(f64::MIN_POSITIVE).sqrt())
        .collect();
    let s = DMatrix::from_fn(n, n, |i, j| a[(i, j)] / (d[i] * d[j]));
    // A matrix without a finite decomposition counts as singular.
    crate::linalg::symmetric_eigen(s).map_or(0.0, |e| e.eigenvalues.min())
}

/// Relative size under which a scaled block counts as singular.
const SINGULAR: f64 = 1e-10;

/// The normal matrix factored for repeated solves ([`Normal::factor`]).
#[derive(Debug, Clone)]
pub(crate) struct Factored {
    v_inv: Vec<PartBlock>,
    w: Vec<DMatrix<f64>>,
    wv: Vec<DMatrix<f64>>,
    s: nalgebra::Cholesky<f64, nalgebra::Dyn>,
}

impl Factored {
    /// [`Factored::solve`] for a `g` that is zero outside the camera and `parts`: the camera's
    /// block of `y` and its blocks of those parts (in their order), the others never formed.
    /// Work independent of the number of parts.
    pub fn solve_parts(
        &self,
        gc: &DVector<f64>,
        go: &[DVector<f64>],
        parts: &[usize],
    ) -> (DVector<f64>, Vec<DVector<f64>>) {
        let mut rhs = gc.clone();
        for &i in parts {
            rhs -= &self.wv[i] * &go[i];
        }
        let yc = self.s.solve(&rhs);
        let yo = parts
            .iter()
            .map(|&i| self.v_inv[i].mul_vec(&(&go[i] - self.w[i].transpose() * &yc)))
            .collect();
        (yc, yo)
    }

    /// Solve for `y` given `g = (g_c, g_o...)`.
    pub fn solve(
        &self,
        gc: &DVector<f64>,
        go: &[DVector<f64>],
    ) -> (DVector<f64>, Vec<DVector<f64>>) {
        let mut rhs = gc.clone();
        for (i, g) in go.iter().enumerate() {
            rhs -= &self.wv[i] * g;
        }
        let yc = self.s.solve(&rhs);
        let yo = self
            .v_inv
            .iter()
            .enumerate()
            .map(|(i, inv)| inv.mul_vec(&(&go[i] - self.w[i].transpose() * &yc)))
            .collect();
        (yc, yo)
    }
}

impl Normal {
    /// Factor `J^T J + lambda diag(J^T J)` by the Schur complement.
    pub fn factor(&self, lambda: f64) -> Result<Factored, Singular> {
        let damp = |m: &DMatrix<f64>| {
            let mut m = m.clone();
            for i in 0..m.nrows() {
                m[(i, i)] *= 1.0 + lambda;
            }
            m
        };
        let mut s = damp(&self.u);
        let mut v_inv = Vec::with_capacity(self.v.len());
        let mut wv = Vec::with_capacity(self.v.len());
        for (i, v) in self.v.iter().enumerate() {
            let inv = v
                .map(|b| damp(b).cholesky().map(|c| c.inverse()))
                .ok_or(Singular::Part(i))?;
            let m = inv.left_mul(&self.w[i]);
            s -= &m * self.w[i].transpose();
            v_inv.push(inv);
            wv.push(m);
        }
        let s = s.cholesky().ok_or(Singular::Camera)?;
        Ok(Factored {
            v_inv,
            w: self.w.clone(),
            wv,
            s,
        })
    }

    /// The first singular block of the undamped matrix, if any: a part whose parameters the
    /// clicks do not fix given the camera, or a camera the data do not fix.
    pub fn singular_block(&self) -> Option<Singular> {
        for (i, v) in self.v.iter().enumerate() {
            if v.scaled_min_eigenvalue() < SINGULAR {
                return Some(Singular::Part(i));
            }
        }
        let mut s = self.u.clone();
        for (i, v) in self.v.iter().enumerate() {
            let inv = v.map(|b| b.clone().cholesky().map(|c| c.inverse()))?;
            s -= inv.left_mul(&self.w[i]) * self.w[i].transpose();
        }
        (scaled_min_eigenvalue(&s) < SINGULAR).then_some(Singular::Camera)
    }

    /// `J^T r`, camera part and per part.
    pub fn gradient(&self) -> (&DVector<f64>, &[DVector<f64>]) {
        (&self.gc, &self.go)
    }
}

/// How a minimisation ended.
#[derive(Debug, Clone)]
pub(crate) struct Solution {
    /// The parameters.
    pub x: Vec<f64>,
    /// Sum of squared residuals, pixels squared.
    pub cost: f64,
    /// Iterations taken.
    pub iterations: usize,
    /// Whether it met the convergence test (else it ran out of iterations).
    pub converged: bool,
}

/// Most Levenberg-Marquardt iterations.
pub(crate) const MAX_ITERATIONS: usize = 200;

/// Minimise the problem's cost from `x0`.
pub(crate) fn minimise<M: Model + ?Sized>(problem: &M, x0: Vec<f64>) -> Option<Solution> {
    let mut x = x0;
    let mut cost = problem.cost(&x);
    if !cost.is_finite() {
        return None;
    }
    let mut lambda = 1e-3;
    let mut iterations = 0;
    let mut converged = false;
    while iterations < MAX_ITERATIONS {
        if problem.stopped() {
            break;
        }
        iterations += 1;
        let normal = problem.normal(&x)?;
        let (gc, go) = normal.gradient();
        let gc = -gc.clone();
        let go: Vec<DVector<f64>> = go.iter().map(|g| -g.clone()).collect();
        let mut improved = false;
        let mut small_step = false;
        while lambda < 1e16 {
            let Ok(factored) = normal.factor(lambda) else {
                lambda *= 10.0;
                continue;
            };
            let (dc, dob) = factored.solve(&gc, &go);
            let mut trial = x.clone();
            for (i, d) in dc.iter().enumerate() {
                trial[i] += d;
            }
            for (p, d) in dob.iter().enumerate() {
                let off = problem.part_offset(p);
                for (i, v) in d.iter().enumerate() {
                    trial[off + i] += v;
                }
            }
            let step: f64 = trial
                .iter()
                .zip(&x)
                .map(|(a, b)| ((a - b) / b.abs().max(1.0)).powi(2))
                .sum::<f64>()
                .sqrt();
            small_step = step < 1e-13;
            let new_cost = problem.cost(&trial);
            if new_cost < cost {
                let gain = cost - new_cost;
                x = trial;
                let old = cost;
                cost = new_cost;
                lambda = (lambda / 3.0).max(1e-12);
                improved = true;
                if gain <= 1e-14 * old || cost <= 1e-24 || small_step {
                    converged = true;
                }
                break;
            }
            if small_step {
                break;
            }
            lambda *= 4.0;
        }
        if converged {
            break;
        }
        if !improved {
            // No step lowers the cost: a minimum to working precision.
            converged = small_step || lambda >= 1e16;
            break;
        }
    }
    Some(Solution {
        x,
        cost,
        iterations,
        converged,
    })
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::fit::{FitOptions, fit_scene};
    use crate::synth::{SynthOptions, add_noise, synthesize};
    use rand::SeedableRng as _;

    /// A noisy synthetic scene's fit (four boxes and a pentagonal footprint with a top).
    pub(crate) fn fitted() -> (Problem, Vec<f64>) {
        let (mut scene, _) = synthesize(&SynthOptions {
            seed: 4,
            ..SynthOptions::default()
        })
        .unwrap();
        add_noise(
            &mut scene,
            1.0,
            &mut rand_chacha::ChaCha8Rng::seed_from_u64(4),
        );
        let fitted = fit_scene(&scene, &FitOptions::default()).unwrap();
        (fitted.problem, fitted.x)
    }

    #[test]
    fn a_footprints_vertices_are_groups_of_their_own() {
        let (problem, x) = fitted();
        let normal = problem.normal(&x).unwrap();
        let mut footprints = 0;
        for (i, part) in problem.parts.iter().enumerate() {
            let groups = normal.v[i].groups.clone();
            match part {
                Part::Footprint { vertices, top } => {
                    footprints += 1;
                    // Each vertex's x, y alone, the one under the top click with the height.
                    let mut want: Vec<Vec<usize>> = (0..vertices.len())
                        .map(|k| vec![2 * k, 2 * k + 1])
                        .collect();
                    let (above, _) = top.unwrap();
                    want[above].push(2 * vertices.len());
                    assert_eq!(groups, Some(want));
                }
                Part::Box { .. } => assert_eq!(groups, None, "a box is one dense group"),
                Part::FloorPoint { .. } => {}
            }
        }
        assert_eq!(footprints, 1);
    }

    #[test]
    fn a_footprints_coloured_differences_equal_its_columns_one_by_one() {
        // The footprint's own Jacobian by one central difference a column, against the three
        // colours `normal` perturbs at once: the same bits, and so the same `J^T J` blocks to
        // rounding (summed sparsely).
        let (problem, x) = fitted();
        let normal = problem.normal(&x).unwrap();
        let camera = problem.camera(&x);
        let i = problem
            .parts
            .iter()
            .position(|p| matches!(p, Part::Footprint { .. }))
            .unwrap();
        assert!(problem.part_coloring(i).is_some());
        let (m, k, off) = (
            problem.part_residual_count(i),
            problem.part_len(i),
            problem.part_offset(i),
        );
        let mut p = x[off..off + k].to_vec();
        let mut jo = DMatrix::zeros(m, k);
        let (mut plus, mut minus) = (vec![0.0; m], vec![0.0; m]);
        for c in 0..k {
            let h = step_size(p[c]);
            p[c] = x[off + c] + h;
            assert!(problem.part_residuals_with(i, &camera, &p, &mut plus));
            p[c] = x[off + c] - h;
            assert!(problem.part_residuals_with(i, &camera, &p, &mut minus));
            p[c] = x[off + c];
            for row in 0..m {
                jo[(row, c)] = (plus[row] - minus[row]) / (2.0 * h);
            }
        }
        // Every entry the same bits, and nothing else non-zero.
        let coloured = problem
            .coloured_jacobian(
                i,
                &camera,
                &x[off..off + k],
                &problem.part_coloring(i).unwrap(),
            )
            .unwrap();
        let mut sparse = DMatrix::zeros(m, k);
        for (c, column) in coloured.iter().enumerate() {
            for &(row, value) in column {
                sparse[(row, c)] = value;
            }
        }
        assert_eq!(sparse, jo);
        // Its blocks from the sparse columns, against the dense product of the same Jacobian.
        let dense = PartBlock::gram(&jo);
        assert_eq!(dense.groups, normal.v[i].groups);
        for (a, b) in dense.blocks.iter().zip(&normal.v[i].blocks) {
            assert!((a - b).amax() <= 1e-12 * a.amax(), "{a} vs {b}");
        }
    }

    #[test]
    fn the_grouped_solve_equals_a_dense_solve_of_the_whole_normal_matrix() {
        // Independent of the blocks: the whole Jacobian by central differences of every
        // residual, `J^T J` formed densely and solved by LU, against the Schur solve with
        // each part inverted group by group.
        let (problem, x) = fitted();
        let n = x.len();
        let r0 = problem.residuals(&x).unwrap();
        let mut j = DMatrix::zeros(r0.len(), n);
        let mut xs = x.clone();
        for c in 0..n {
            if c < problem.camera_len() && problem.camera_fixed(c) {
                continue;
            }
            let h = step_size(x[c]);
            xs[c] = x[c] + h;
            let plus = problem.residuals(&xs).unwrap();
            xs[c] = x[c] - h;
            let minus = problem.residuals(&xs).unwrap();
            xs[c] = x[c];
            for row in 0..r0.len() {
                j[(row, c)] = (plus[row] - minus[row]) / (2.0 * h);
            }
        }
        let mut jtj = j.transpose() * &j;
        for c in (0..problem.camera_len()).filter(|&c| problem.camera_fixed(c)) {
            jtj[(c, c)] = 1.0;
        }
        // A right-hand side with every entry non-zero (held camera entries zero).
        let g = DVector::from_fn(n, |i, _| {
            if i < problem.camera_len() && problem.camera_fixed(i) {
                0.0
            } else {
                1.0 + 0.37 * i as f64
            }
        });
        let dense = jtj.lu().solve(&g).unwrap();
        let nc = problem.camera_len();
        let gc = g.rows(0, nc).into_owned();
        let go: Vec<DVector<f64>> = (0..problem.part_count())
            .map(|p| {
                g.rows(problem.part_offset(p), problem.part_len(p))
                    .into_owned()
            })
            .collect();
        let (yc, yo) = problem
            .normal(&x)
            .unwrap()
            .factor(0.0)
            .unwrap()
            .solve(&gc, &go);
        let scale = dense.amax();
        for i in 0..nc {
            assert!(
                (yc[i] - dense[i]).abs() <= 1e-6 * scale,
                "camera {i}: {} vs {}",
                yc[i],
                dense[i]
            );
        }
        for (p, y) in yo.iter().enumerate() {
            for (k, v) in y.iter().enumerate() {
                let d = dense[problem.part_offset(p) + k];
                assert!((v - d).abs() <= 1e-6 * scale, "part {p}[{k}]: {v} vs {d}");
            }
        }
    }
}

//! The modes of the linearised motion with the largest real parts: a Cayley transform of the
//! companion form, iterated by faer's Krylov–Schur solver (module docs).
//!
//! With `z = [δ; δ̇]` the motion is `A z = λ B z`, `A = [[0, I], [K, C]]`, `B = diag(I, M)`.
//! The Cayley operator `T = (A − σB)⁻¹ (A + σB) = I + 2σ (A − σB)⁻¹ B` (σ > 0) has eigenvalues
//! `θ = (λ + σ)/(λ − σ)`: `|θ| > 1` exactly when `Re λ > 0`, so the iteration, which keeps the
//! eigenvalues of largest `|θ|`, finds every growing mode first, then the least damped
//! (Meerbergen & Roose 1996). One application solves `P(σ) w₁ = (C − σM) v₁ − M v₂` and sets
//! `w₂ = v₁ + σ w₁` (`P(σ) = σ²M − σC − K`, one LU factorisation for all of them).

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::solvers::Solve;
use faer::matrix_free::eigen::{partial_eigen, partial_eigen_scratch, PartialEigenParams};
use faer::matrix_free::LinOp;
use faer::sparse::linalg::solvers::Lu;
use faer::{c64, Col, Mat, MatMut, MatRef, Par};

use super::{Linearized, StabilityError};

/// How many modes to look for, and where.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModeOptions {
    /// Modes wanted (the rightmost in the Cayley sense; complex pairs count twice).
    pub count: usize,
    /// The Cayley shift σ (1/s): modes with `|λ|` of this order are resolved best. Of the
    /// order of the swing's angular frequency (a parachute's is 1–3 rad/s).
    pub shift: f64,
    /// Convergence of the Krylov–Schur iteration on `|θ|` (absolute; `θ` is O(1)).
    pub tolerance: f64,
    /// Modes solved worse than this backward error ([`Mode::backward_error`]) are left out:
    /// stiff structural modes (`|λ| ≫ σ`) sit at `|θ| ≈ 1`, where an error in `θ` grows by
    /// `|λ|²/2σ` in `λ`.
    pub max_backward_error: f64,
}

impl Default for ModeOptions {
    fn default() -> Self {
        Self {
            count: 12,
            shift: 2.0,
            tolerance: 1e-10,
            max_backward_error: 1e-8,
        }
    }
}

/// One mode `δ = φ e^{λt}` of the linearised motion.
#[derive(Debug, Clone, PartialEq)]
pub struct Mode {
    /// The eigenvalue λ (1/s): growth rate `Re λ`, angular frequency `Im λ`.
    pub eigenvalue: c64,
    /// The shape φ on every DOF of the model (fixed DOFs 0), scaled to a largest
    /// translational component of 1.
    pub shape: Vec<c64>,
    /// Backward error `‖P(λ)φ‖ / ((|λ|²‖M‖ + |λ|‖C‖ + ‖K‖) ‖φ‖)` (∞-norms): how exactly the
    /// mode solves the quadratic eigenproblem.
    pub backward_error: f64,
}

/// The Cayley operator of the companion form (module docs), on `2 n` vectors.
struct Cayley<'a> {
    lin: &'a Linearized,
    lu: Lu<usize, f64>,
    sigma: f64,
}

impl std::fmt::Debug for Cayley<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Cayley(σ = {})", self.sigma)
    }
}

impl Cayley<'_> {
    /// `w = T v` for one column.
    fn apply_one(&self, v: &[f64], w: &mut [f64]) {
        let n = self.lin.n_free;
        let (v1, v2) = v.split_at(n);
        let mut cv = vec![0.0; n];
        self.lin.mul(&self.lin.c, v1, &mut cv);
        let s = self.sigma;
        let mut w1 = Col::<f64>::from_fn(n, |i| {
            cv[i] - s * self.lin.mass[i] * v1[i] - self.lin.mass[i] * v2[i]
        });
        self.lu.solve_in_place(w1.as_mat_mut());
        for i in 0..n {
            let (a, b) = (w1[i], v1[i] + s * w1[i]);
            w[i] = v1[i] + 2.0 * s * a;
            w[n + i] = v2[i] + 2.0 * s * b;
        }
    }
}

impl LinOp<f64> for Cayley<'_> {
    fn apply_scratch(&self, _: usize, _: Par) -> StackReq {
        StackReq::EMPTY
    }
    fn nrows(&self) -> usize {
        2 * self.lin.n_free
    }
    fn ncols(&self) -> usize {
        2 * self.lin.n_free
    }
    fn apply(&self, mut out: MatMut<'_, f64>, rhs: MatRef<'_, f64>, _: Par, _: &mut MemStack) {
        let m = self.nrows();
        let (mut v, mut w) = (vec![0.0; m], vec![0.0; m]);
        for j in 0..rhs.ncols() {
            for i in 0..m {
                v[i] = rhs[(i, j)];
            }
            self.apply_one(&v, &mut w);
            for i in 0..m {
                out[(i, j)] = w[i];
            }
        }
    }
    fn conj_apply(&self, out: MatMut<'_, f64>, rhs: MatRef<'_, f64>, par: Par, st: &mut MemStack) {
        self.apply(out, rhs, par, st);
    }
}

/// The modes of `lin` with the largest real parts (module docs), sorted by decreasing
/// `Re λ`; only those the iteration converged on, to [`ModeOptions::max_backward_error`].
pub fn modes(lin: &Linearized, opts: &ModeOptions) -> Result<Vec<Mode>, StabilityError> {
    let n2 = 2 * lin.n_free;
    let count = opts.count.min(n2);
    if count == 0 {
        return Ok(Vec::new());
    }
    let sigma = opts.shift;
    let op = Cayley {
        lin,
        lu: lin.lu(&lin.pencil(sigma))?,
        sigma,
    };
    let params = PartialEigenParams {
        max_restarts: 200,
        ..Default::default()
    };
    let mut buf = MemBuffer::new(partial_eigen_scratch(&op, count, Par::Seq, params));
    let mut vecs = Mat::<c64>::zeros(n2, count);
    let mut vals = vec![c64::new(0.0, 0.0); count];
    // A fixed, generic start (no constant vector, which is a rigid-body motion).
    let v0 = Col::<f64>::from_fn(n2, |i| {
        ((i as f64 + 1.0) * 0.618_033_988_749_895).fract() - 0.5
    });
    let info = partial_eigen(
        vecs.as_mut(),
        &mut vals,
        &op,
        v0.as_ref(),
        opts.tolerance,
        Par::Seq,
        MemStack::new(&mut buf),
        params,
    );
    let norms = Norms::of(lin);
    let mut out: Vec<Mode> = (0..info.n_converged_eigen)
        .map(|j| {
            let theta = vals[j];
            let one = c64::new(1.0, 0.0);
            let lambda = (theta + one) / (theta - one) * sigma;
            let phi: Vec<c64> = (0..lin.n_free).map(|i| vecs[(i, j)]).collect();
            mode(lin, lambda, phi, &norms)
        })
        .filter(|m| m.backward_error <= opts.max_backward_error)
        .collect();
    out.sort_by(|a, b| b.eigenvalue.re.total_cmp(&a.eigenvalue.re));
    Ok(out)
}

/// ∞-norms of `M`, `C` and `K` (largest absolute row sum).
struct Norms {
    m: f64,
    c: f64,
    k: f64,
}

impl Norms {
    fn of(lin: &Linearized) -> Self {
        let row_sums = |a: &[f64]| {
            let mut s = vec![0.0; lin.n_free];
            for col in 0..lin.n_free {
                for k in lin.col_ptr[col]..lin.col_ptr[col + 1] {
                    s[lin.row_idx[k]] += a[k].abs();
                }
            }
            s.into_iter().fold(0.0, f64::max)
        };
        Self {
            m: lin.mass.iter().copied().fold(0.0, f64::max),
            c: row_sums(&lin.c),
            k: row_sums(&lin.k),
        }
    }
}

/// The mode of eigenvalue `lambda` and free-DOF shape `phi`: scaled, spread onto every DOF,
/// with its backward error.
fn mode(lin: &Linearized, lambda: c64, mut phi: Vec<c64>, n: &Norms) -> Mode {
    let (re, im): (Vec<f64>, Vec<f64>) = phi.iter().map(|z| (z.re, z.im)).unzip();
    let zeros = || vec![0.0; re.len()];
    let (mut kr, mut ki, mut cr, mut ci) = (zeros(), zeros(), zeros(), zeros());
    lin.mul(&lin.k, &re, &mut kr);
    lin.mul(&lin.k, &im, &mut ki);
    lin.mul(&lin.c, &re, &mut cr);
    lin.mul(&lin.c, &im, &mut ci);
    let l2 = lambda * lambda;
    let mut r_max: f64 = 0.0;
    for i in 0..phi.len() {
        let kphi = c64::new(kr[i], ki[i]);
        let cphi = c64::new(cr[i], ci[i]);
        let r = l2 * phi[i] * lin.mass[i] - lambda * cphi - kphi;
        r_max = r_max.max(r.norm());
    }
    let phi_max = phi.iter().map(|z| z.norm()).fold(0.0, f64::max);
    let scale = (lambda.norm_sqr() * n.m + lambda.norm() * n.c + n.k) * phi_max;
    let backward_error = if scale > 0.0 { r_max / scale } else { 0.0 };
    // Scale to a largest translational component of 1 (real and positive there).
    let n_pos = lin
        .dof_of
        .iter()
        .zip(&phi)
        .filter(|(&d, _)| d < lin.n_translational)
        .max_by(|a, b| a.1.norm().total_cmp(&b.1.norm()))
        .map(|(_, z)| *z);
    if let Some(z) = n_pos.filter(|z| z.norm() > 0.0) {
        let s = z.conj() / z.norm_sqr();
        phi.iter_mut().for_each(|p| *p *= s);
    }
    let mut shape = vec![c64::new(0.0, 0.0); lin.n_dofs];
    for (&d, p) in lin.dof_of.iter().zip(phi) {
        shape[d] = p;
    }
    Mode {
        eigenvalue: lambda,
        shape,
        backward_error,
    }
}

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
use faer::matrix_free::eigen::{partial_eigen, partial_eigen_scratch, PartialEigenParams};
use faer::matrix_free::LinOp;
use faer::{c64, Col, Mat, MatMut, MatRef, Par};

use super::linearize::PencilSolver;
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
    /// Companion forms up to this size (`2 ×` free DOFs) are solved densely; default
    /// [`DENSE_UP_TO`].
    pub dense_up_to: usize,
}

impl Default for ModeOptions {
    fn default() -> Self {
        Self {
            count: 12,
            shift: 2.0,
            tolerance: 1e-10,
            max_backward_error: 1e-8,
            dense_up_to: DENSE_UP_TO,
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

/// A spectral transformation of the companion form (module docs), on `2 n` vectors.
struct Cayley<'a> {
    lin: &'a Linearized,
    lu: PencilSolver,
    sigma: f64,
    /// The Cayley operator `I + 2σ S` (the rightmost modes) or the shift-invert `S` itself
    /// (the modes nearest σ).
    cayley: bool,
}

impl std::fmt::Debug for Cayley<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Spectral(σ = {}, Cayley {})", self.sigma, self.cayley)
    }
}

impl Cayley<'_> {
    /// `w = T v` for one column.
    fn apply_one(&self, v: &[f64], w: &mut [f64]) {
        let n = self.lin.n_free;
        let (v1, v2) = v.split_at(n);
        let mut cv = vec![0.0; n];
        self.lin.mul_c(v1, &mut cv);
        let s = self.sigma;
        let mut w1 = Col::<f64>::from_fn(n, |i| {
            cv[i] - s * self.lin.mass[i] * v1[i] - self.lin.mass[i] * v2[i]
        });
        self.lu.solve_in_place(&mut w1);
        let c = if self.cayley { 2.0 * s } else { 1.0 };
        for i in 0..n {
            let (a, b) = (w1[i], v1[i] + s * w1[i]);
            w[i] = c * a;
            w[n + i] = c * b;
            if self.cayley {
                w[i] += v1[i];
                w[n + i] += v2[i];
            }
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

/// Companion forms up to this size (`2 ×` free DOFs) are solved densely: every eigenvalue at
/// once, faster than the iteration on a small model whose many weakly damped structural modes
/// crowd `|θ| ≈ 1` (a rod canopy: 2 s iterating against milliseconds).
pub const DENSE_UP_TO: usize = 600;

/// A mode with `|λ|` below this (1/s: an e-folding in 1,000 s, longer than a descent from
/// 5 km) is neutral: a change of position or heading, or a slack fabric's wrinkle. Near-zero
/// eigenvalues of a slack cloth come out 10⁻⁵ /s from zero, so a finer line would call round-off
/// growth.
pub const NEUTRAL_RATE: f64 = 1e-3;

/// Neutral modes listed at most (after every growing mode and the others nearest σ): the
/// three positions and the heading.
pub const NEUTRAL_SHOWN: usize = 4;

/// The modes of `lin` with the largest real parts (module docs), sorted by decreasing
/// `Re λ`: the `count` of largest Cayley `|θ|`, solved to [`ModeOptions::max_backward_error`]
/// (densely up to [`ModeOptions::dense_up_to`], else by the iteration, which keeps those it
/// converged on).
pub fn modes(lin: &Linearized, opts: &ModeOptions) -> Result<Vec<Mode>, StabilityError> {
    let n2 = 2 * lin.n_free;
    let count = opts.count.min(n2);
    if count == 0 {
        return Ok(Vec::new());
    }
    let norms = Norms::of(lin);
    let candidates = if n2 <= opts.dense_up_to {
        dense(lin, opts.shift)?
    } else {
        // Twice the count: room for the neutral modes the selection passes over.
        let wanted = (2 * count).min(n2);
        let mut c = iterate(lin, opts, wanted, true)?;
        c.extend(iterate(lin, opts, wanted, false)?);
        c
    };
    let mut all: Vec<Mode> = Vec::new();
    for (lambda, phi) in candidates {
        let m = mode(lin, lambda, phi, &norms);
        // Both passes of the iteration may find a mode, or another combination of a multiple
        // eigenvalue's shapes; only shapes outside the span already found are kept.
        let seen = in_span(&all, &m);
        if m.backward_error <= opts.max_backward_error && !seen {
            all.push(m);
        }
    }
    // Every growing mode, then the nearest to σ (the slow modes of the whole body).
    // Every growing mode, then the others nearest σ (the slow modes of the whole body), then
    // a few neutral ones: a slack fabric has hundreds.
    let neutral = |m: &Mode| m.eigenvalue.norm() < NEUTRAL_RATE;
    let (neutrals, moving): (Vec<Mode>, Vec<Mode>) = all.into_iter().partition(neutral);
    let grows = |m: &Mode| m.eigenvalue.re > NEUTRAL_RATE;
    let (mut out, mut rest): (Vec<Mode>, Vec<Mode>) = moving.into_iter().partition(grows);
    let dist = |m: &Mode| (m.eigenvalue - opts.shift).norm();
    rest.sort_by(|a, b| dist(a).total_cmp(&dist(b)));
    let room = count.saturating_sub(out.len() + neutrals.len().min(NEUTRAL_SHOWN));
    out.extend(rest.into_iter().take(room));
    out.extend(neutrals.into_iter().take(NEUTRAL_SHOWN));
    out.sort_by(|a, b| b.eigenvalue.re.total_cmp(&a.eigenvalue.re));
    Ok(out)
}

/// Every eigenpair, from the shift-invert operator formed densely column by column (one
/// solve each). The companion matrix itself would be as small but badly scaled: rod twists
/// and stiff membranes put its norm at 10⁶ /s, and its eigenvalues near zero (the neutral
/// modes) come out 10⁻⁵ /s wrong; through `θ = 1/(λ − σ)` they are resolved to round-off.
fn dense(lin: &Linearized, sigma: f64) -> Result<Vec<(c64, Vec<c64>)>, StabilityError> {
    let n2 = 2 * lin.n_free;
    let op = spectral(lin, sigma, false)?;
    let mut t = Mat::<f64>::zeros(n2, n2);
    let (mut e, mut w) = (vec![0.0; n2], vec![0.0; n2]);
    for j in 0..n2 {
        e[j] = 1.0;
        op.apply_one(&e, &mut w);
        e[j] = 0.0;
        for i in 0..n2 {
            t[(i, j)] = w[i];
        }
    }
    let evd = t
        .eigen()
        .map_err(|e| StabilityError::Singular(format!("dense eigen-solve: {e:?}")))?;
    let (u, s) = (evd.U(), evd.S());
    Ok((0..n2)
        .filter(|&j| s[j].norm() > 0.0)
        .map(|j| {
            (
                to_lambda(s[j], sigma, false),
                (0..lin.n_free).map(|i| u[(i, j)]).collect(),
            )
        })
        .collect())
}

/// Whether `m`'s shape lies in the span of the shapes of the modes of `kept` with its λ
/// (Gram–Schmidt; within 1 % of its norm).
fn in_span(kept: &[Mode], m: &Mode) -> bool {
    let close =
        |a: &Mode| (a.eigenvalue - m.eigenvalue).norm() <= 1e-6 * (1.0 + m.eigenvalue.norm());
    let dot = |x: &[c64], y: &[c64]| -> c64 { x.iter().zip(y).map(|(a, b)| a.conj() * b).sum() };
    let mut basis: Vec<Vec<c64>> = Vec::new();
    for a in kept.iter().filter(|a| close(a)) {
        let mut v = a.shape.clone();
        for b in &basis {
            let c = dot(b, &v);
            v.iter_mut().zip(b).for_each(|(x, y)| *x -= c * y);
        }
        let n = dot(&v, &v).re.sqrt();
        if n > 0.0 {
            basis.push(v.into_iter().map(|x| x / n).collect());
        }
    }
    let mut r = m.shape.clone();
    for b in &basis {
        let c = dot(b, &r);
        r.iter_mut().zip(b).for_each(|(x, y)| *x -= c * y);
    }
    dot(&r, &r).re.sqrt() <= 0.01 * dot(&m.shape, &m.shape).re.sqrt()
}

/// λ of an eigenvalue θ of the Cayley operator, `σ (θ + 1)/(θ − 1)`, or of the shift-invert
/// one, `σ + 1/θ`.
fn to_lambda(theta: c64, sigma: f64, cayley: bool) -> c64 {
    let one = c64::new(1.0, 0.0);
    if cayley {
        (theta + one) / (theta - one) * sigma
    } else {
        one / theta + sigma
    }
}

/// The Cayley or shift-invert operator of `lin` with shift σ (one LU of `P(σ)`).
fn spectral(lin: &Linearized, sigma: f64, cayley: bool) -> Result<Cayley<'_>, StabilityError> {
    Ok(Cayley {
        lin,
        lu: lin.pencil_solver(sigma)?,
        sigma,
        cayley,
    })
}

/// The eigenpairs the Krylov–Schur iteration converged on: of the Cayley operator (the
/// rightmost modes) or of the shift-invert one (the nearest σ).
fn iterate(
    lin: &Linearized,
    opts: &ModeOptions,
    count: usize,
    cayley: bool,
) -> Result<Vec<(c64, Vec<c64>)>, StabilityError> {
    let n2 = 2 * lin.n_free;
    let op = spectral(lin, opts.shift, cayley)?;
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
    Ok((0..info.n_converged_eigen)
        .map(|j| {
            let lambda = to_lambda(vals[j], opts.shift, cayley);
            (lambda, (0..lin.n_free).map(|i| vecs[(i, j)]).collect())
        })
        .collect())
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
        // The low-rank part's ∞-norm is at most Σ_j ‖u_j‖∞ ‖w_j‖₁.
        let low = |w: fn(&super::linearize::Coupling) -> &Vec<f64>| -> f64 {
            lin.coupling
                .iter()
                .map(|c| {
                    let u = c.u.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
                    u * w(c).iter().map(|x| x.abs()).sum::<f64>()
                })
                .sum()
        };
        Self {
            m: lin.mass.iter().copied().fold(0.0, f64::max),
            c: row_sums(&lin.c) + low(|c| &c.wv),
            k: row_sums(&lin.k) + low(|c| &c.wq),
        }
    }
}

/// The mode of eigenvalue `lambda` and free-DOF shape `phi`: scaled, spread onto every DOF,
/// with its backward error.
fn mode(lin: &Linearized, lambda: c64, mut phi: Vec<c64>, n: &Norms) -> Mode {
    let (re, im): (Vec<f64>, Vec<f64>) = phi.iter().map(|z| (z.re, z.im)).unzip();
    let zeros = || vec![0.0; re.len()];
    let (mut kr, mut ki, mut cr, mut ci) = (zeros(), zeros(), zeros(), zeros());
    lin.mul_k(&re, &mut kr);
    lin.mul_k(&im, &mut ki);
    lin.mul_c(&re, &mut cr);
    lin.mul_c(&im, &mut ci);
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

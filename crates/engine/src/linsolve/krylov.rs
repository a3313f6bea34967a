//! Krylov correction of a solve with an approximate factorisation.
//!
//! Modified Newton factorises the symmetric part `J_s = ½ (J + Jᵀ)` of a non-symmetric
//! Jacobian (drag is the only skew part). When `J_s⁻¹` is too far from `J⁻¹` for the Newton
//! update to contract, the exact system `J Δ = −R` is solved by BiCGStab (faer's
//! `matrix_free::bicgstab`) with the held LLᵀ / LBLᵀ factors of `J_s` as right
//! preconditioner, starting from the approximate update `J_s⁻¹ (−R)`.
//!
//! Why not LU of `J`: LU needs its own symbolic analysis and factor storage, several times
//! the Cholesky factor's (≈ 2.5 GiB at 100k DOFs), and about twice its flops; the
//! preconditioned iteration needs ten `n`-vectors and converges in a few iterations because
//! `J_s⁻¹ J = I + J_s⁻¹ (J − J_s)` is a small perturbation of the identity.

use faer::dyn_stack::{MemStack, StackReq};
use faer::matrix_free::bicgstab::{bicgstab, bicgstab_scratch, BicgParams};
use faer::matrix_free::{InitialGuessStatus, LinOp, Precond};
use faer::reborrow::ReborrowMut;
use faer::sparse::SparseColMatRef;
use faer::{MatMut, MatRef, Par};

use super::{LinearSolver, LowRank};

/// The held factorisation of [`LinearSolver`] as a preconditioner `x ↦ A⁻¹ x`.
pub(super) struct HeldFactors<'a>(pub &'a LinearSolver);

impl std::fmt::Debug for HeldFactors<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("HeldFactors")
    }
}

impl LinOp<f64> for HeldFactors<'_> {
    fn apply_scratch(&self, rhs_ncols: usize, par: Par) -> StackReq {
        self.0.solve_scratch(rhs_ncols, par)
    }
    fn nrows(&self) -> usize {
        self.0.n
    }
    fn ncols(&self) -> usize {
        self.0.n
    }
    fn apply(&self, mut out: MatMut<'_, f64>, rhs: MatRef<'_, f64>, par: Par, st: &mut MemStack) {
        out.copy_from(rhs);
        self.0.solve_completed(out, par, st);
    }
    fn conj_apply(&self, out: MatMut<'_, f64>, rhs: MatRef<'_, f64>, par: Par, st: &mut MemStack) {
        self.apply(out, rhs, par, st);
    }
}

impl Precond<f64> for HeldFactors<'_> {
    fn apply_in_place_scratch(&self, rhs_ncols: usize, par: Par) -> StackReq {
        self.0.solve_scratch(rhs_ncols, par)
    }
    fn apply_in_place(&self, rhs: MatMut<'_, f64>, par: Par, st: &mut MemStack) {
        self.0.solve_completed(rhs, par, st);
    }
    fn conj_apply_in_place(&self, rhs: MatMut<'_, f64>, par: Par, st: &mut MemStack) {
        self.0.solve_completed(rhs, par, st);
    }
}

/// The full matrix: the sparse values and the low-rank part the factors are completed with.
#[derive(Debug)]
pub(super) struct Full<'a> {
    pub sparse: SparseColMatRef<'a, usize, f64>,
    pub low_rank: &'a LowRank,
}

impl LinOp<f64> for Full<'_> {
    fn apply_scratch(&self, rhs_ncols: usize, par: Par) -> StackReq {
        self.sparse.apply_scratch(rhs_ncols, par)
    }
    fn nrows(&self) -> usize {
        self.sparse.nrows()
    }
    fn ncols(&self) -> usize {
        self.sparse.ncols()
    }
    fn apply(&self, mut out: MatMut<'_, f64>, rhs: MatRef<'_, f64>, par: Par, st: &mut MemStack) {
        self.sparse.apply(out.rb_mut(), rhs, par, st);
        if self.low_rank.rank() == 0 {
            return;
        }
        for j in 0..rhs.ncols() {
            let x = rhs.col(j).try_as_col_major();
            let y = out.rb_mut().col_mut(j).try_as_col_major_mut();
            let contiguous = "products run on contiguous columns";
            self.low_rank.apply_add(
                x.expect(contiguous).as_slice(),
                y.expect(contiguous).as_slice_mut(),
            );
        }
    }
    fn conj_apply(&self, out: MatMut<'_, f64>, rhs: MatRef<'_, f64>, par: Par, st: &mut MemStack) {
        self.apply(out, rhs, par, st);
    }
}

/// Workspace size of [`corrected_solve`] for an `n × n` system.
pub(super) fn scratch(solver: &LinearSolver, a: &Full<'_>) -> StackReq {
    let ident = faer::matrix_free::IdentityPrecond { dim: solver.n };
    bicgstab_scratch(ident, HeldFactors(solver), a, 1, solver.par)
}

/// What a corrected solve achieved.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KrylovReport {
    /// BiCGStab iterations (each: two products with `A`, two preconditioner solves).
    pub iterations: usize,
    /// `‖b − A x‖₂ / ‖b‖₂` at exit.
    pub relative_residual: f64,
    /// Whether `relative_residual ≤ rel_tol` was reached within the iteration budget.
    pub converged: bool,
}

/// Solve `A x = b` by right-preconditioned BiCGStab with the held factors, from the initial
/// guess in `x` (overwritten). `rel_tol` is on `‖b − A x‖₂ / ‖b‖₂`.
pub(super) fn corrected_solve(
    solver: &LinearSolver,
    a: &Full<'_>,
    b: &[f64],
    x: &mut [f64],
    rel_tol: f64,
    max_iters: usize,
    stack: &mut MemStack,
) -> KrylovReport {
    let n = solver.n;
    let params = BicgParams {
        initial_guess: InitialGuessStatus::MaybeNonZero,
        abs_tolerance: 0.0,
        rel_tolerance: rel_tol,
        max_iters,
        ..Default::default()
    };
    let ident = faer::matrix_free::IdentityPrecond { dim: n };
    let out = MatMut::from_column_major_slice_mut(x, n, 1);
    let rhs = MatRef::from_column_major_slice(b, n, 1);
    let res = bicgstab(
        out,
        ident,
        HeldFactors(solver),
        a,
        rhs,
        params,
        |_| {},
        solver.par,
        stack,
    );
    match res {
        Ok(info) => KrylovReport {
            iterations: info.iter_count,
            relative_residual: info.rel_residual,
            converged: true,
        },
        Err(faer::matrix_free::bicgstab::BicgError::NoConvergence { rel_residual, .. }) => {
            KrylovReport {
                iterations: max_iters,
                relative_residual: rel_residual,
                converged: false,
            }
        }
    }
}

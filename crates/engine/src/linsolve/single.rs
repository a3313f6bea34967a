//! Single-precision Cholesky factors of the Newton matrix
//! ([`crate::NewtonOptions::single_precision`]): the matrix is rounded to `f32`, factorised
//! and solved with faer's `f32` kernels (twice the SIMD lanes, half the memory traffic);
//! right-hand sides and solutions stay `f64` at the interface.

use super::{Factorization, LinearSolver};
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::linalg::cholesky::{LltRef, SymbolicCholesky};
use faer::sparse::SparseColMatRef;
use faer::{Conj, MatMut, Par, Side};

impl LinearSolver {
    /// Factorise LLᵀ in single precision from now on (LBLᵀ, LU and a failed single LLᵀ stay
    /// in double). The factor's storage and bandwidth halve and faer's kernels process twice
    /// the lanes, so factorisations and triangular solves take about half the time; the
    /// solve's relative accuracy becomes about `cond(A) × 6e-8` instead of `cond(A) × 1e-16`,
    /// which a Newton iteration that evaluates its residual in double tolerates as an
    /// inexact linear solve (the caller checks it: [`LinearSolver::single_held`]). Allocates
    /// the single-precision copies once; no effect without LLᵀ (non-symmetric solver).
    pub fn enable_single(&mut self) {
        let Some((chol, _)) = self.llt.as_ref() else {
            return;
        };
        let (n, par) = (self.n, self.par);
        let req = chol
            .factorize_numeric_llt_scratch::<f32>(par, Default::default())
            .or(solve_scratch(chol, n, par));
        let a_len = self
            .lower
            .as_ref()
            .map_or(self.row_idx.len(), |lo| lo.row_idx.len());
        self.single = Some((vec![0.0; chol.len_val()], vec![0.0; a_len]));
        self.single_on = true;
        self.req = self.req.or(req);
        self.mem = MemBuffer::new(self.req.or(self.lu_scratch()));
        self.krylov_mem = None;
    }

    /// Make the next LLᵀ factorisations in single (`true`, once
    /// [`LinearSolver::enable_single`] has allocated for it, unless one broke down: then
    /// double for good) or double precision; the held factors stay until the next
    /// factorisation.
    pub fn set_single(&mut self, on: bool) {
        self.single_on = on && self.single_usable();
    }

    /// Whether single-precision factorisations are allocated and have not broken down.
    pub fn single_usable(&self) -> bool {
        self.single.is_some() && !self.single_broke
    }

    /// Whether the held factors are single-precision LLᵀ.
    pub fn single_held(&self) -> bool {
        self.valid && self.single_held && self.last == Factorization::Llt
    }
}

/// LLᵀ of `a` (rounded into `single.1`) into `single.0`; whether it is positive definite in
/// single precision.
pub(super) fn factor(
    chol: &SymbolicCholesky<usize>,
    single: &mut (Vec<f32>, Vec<f32>),
    a: SparseColMatRef<'_, usize, f64>,
    par: Par,
    stack: &mut MemStack,
) -> bool {
    let (l32, a32) = single;
    for (x, &v) in a32.iter_mut().zip(a.val()) {
        *x = v as f32;
    }
    let a = SparseColMatRef::new(a.symbolic(), &a32[..]);
    chol.factorize_numeric_llt::<f32>(
        l32,
        a,
        Side::Lower,
        LltRegularization::default(),
        par,
        stack,
        Default::default(),
    )
    .is_ok()
}

/// Solve in place with single-precision factors `l32`: each column of `x` is rounded to
/// `f32` in the workspace, solved, and written back.
pub(super) fn solve(
    chol: &SymbolicCholesky<usize>,
    l32: &[f32],
    mut x: MatMut<'_, f64>,
    par: Par,
    stack: &mut MemStack,
) {
    let n = x.nrows();
    for j in 0..x.ncols() {
        let (mut y, stack) = stack.make_with::<f32>(n, |i| x[(i, j)] as f32);
        let ym = MatMut::from_column_major_slice_mut(&mut y, n, 1);
        LltRef::new(chol, l32).solve_in_place_with_conj(Conj::No, ym, par, stack);
        for i in 0..n {
            x[(i, j)] = f64::from(y[i]);
        }
    }
}

/// Workspace of the single-precision solve of one column (`n` unknowns).
pub(super) fn solve_scratch(chol: &SymbolicCholesky<usize>, n: usize, par: Par) -> StackReq {
    chol.solve_in_place_scratch::<f32>(1, par)
        .and(StackReq::new::<f32>(n))
}

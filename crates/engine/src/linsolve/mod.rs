//! Sparse linear solves of the Newton system with faer.
//!
//! The symbolic analysis (fill-reducing ordering, elimination tree, supernodes) is done once
//! per pattern; each Newton iteration only refactorises numerically into preallocated
//! storage. Only symmetric matrices are factorised: a supernodal LLᵀ (Cholesky) is tried
//! first; if the matrix is not positive definite (e.g. a buckling rod or a compressed
//! membrane with a large time step) the same symbolic structure is factorised as LBLᵀ
//! (Bunch–Kaufman pivoting within supernodes), which needs no more memory. A non-symmetric
//! system is solved with the factors of its symmetric part as preconditioner
//! ([`LinearSolver::solve_corrected`], module [`krylov`]): LU would need its own symbolic
//! structure, several times the Cholesky factor's storage and about 8× its time on the
//! bundled shells (docs/performance.md).

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::reborrow::ReborrowMut;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, SymbolicCholesky, SymmetricOrdering,
};
use faer::sparse::linalg::{amd, SupernodalThreshold};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{MatMut, Par, Side};

use crate::error::{EngineError, SparseError};
use faer::sparse::FaerError;

mod krylov;
mod low_rank;
mod numeric;
pub use krylov::KrylovReport;
use low_rank::Woodbury;
pub use low_rank::{LowRank, MAX_RANK};
use numeric::Numeric;

/// The precision of the factors ([`numeric`] module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Precision {
    /// `f64` factors.
    #[default]
    Double,
    /// `f32` factors: half the storage and memory traffic, for factors that precondition an
    /// iteration whose residual is in double precision.
    Single,
}

/// The numeric factors in the chosen precision.
enum Factors {
    Double(Numeric<f64>),
    Single(Numeric<f32>),
}

/// The engine's name for a faer failure.
fn sparse_error(e: FaerError) -> SparseError {
    match e {
        FaerError::IndexOverflow => SparseError::IndexOverflow,
        _ => SparseError::OutOfMemory,
    }
}

/// Check that `(col_ptr, row_idx)` is an `n × n` CSC pattern: `col_ptr` of length `n + 1`,
/// starting at 0, non-decreasing, ending at `row_idx.len()`; row indices in range and strictly
/// increasing within each column. This is what faer's unchecked constructor requires.
fn check_pattern(n: usize, col_ptr: &[usize], row_idx: &[usize]) -> Result<(), SparseError> {
    let bad = |m| Err(SparseError::InvalidPattern(m));
    if col_ptr.len() != n + 1 || col_ptr[0] != 0 || col_ptr[n] != row_idx.len() {
        return bad("column pointers do not span the row indices");
    }
    for c in 0..n {
        let (a, b) = (col_ptr[c], col_ptr[c + 1]);
        if a > b {
            return bad("column pointers decrease");
        }
        let rows = &row_idx[a..b];
        if rows.iter().any(|&r| r >= n) {
            return bad("row index out of range");
        }
        if rows.windows(2).any(|w| w[0] >= w[1]) {
            return bad("row indices not strictly increasing within a column");
        }
    }
    Ok(())
}

/// The fill-reducing order faer's Cholesky would use for this pattern (AMD with its default
/// control; `fwd[i]` = old index of new row `i`), or `None` if it fails (too large). A
/// system numbered in this order is factorised with [`LinearSolver::new_ordered`].
pub fn amd_order(n: usize, col_ptr: &[usize], row_idx: &[usize]) -> Option<Vec<usize>> {
    check_pattern(n, col_ptr, row_idx).ok()?;
    // SAFETY: checked just above.
    let a = unsafe { SymbolicSparseColMatRef::new_unchecked(n, n, col_ptr, None, row_idx) };
    let (mut fwd, mut inv) = (vec![0usize; n], vec![0usize; n]);
    let mut mem =
        MemBuffer::try_new(amd::order_maybe_unsorted_scratch::<usize>(n, row_idx.len())).ok()?;
    amd::order_maybe_unsorted(
        &mut fwd,
        &mut inv,
        a,
        amd::Control::default(),
        MemStack::new(&mut mem),
    )
    .ok()?;
    Some(fwd)
}

/// When faer factorises supernodally rather than column by column: its default threshold
/// (factor flops per factor entry above 40) leaves the small shell systems (a few hundred
/// nodes, 3 DOFs each, hinge stencils coupling 4 nodes) simplicial, where the supernodal
/// kernel factorises them 2.5× faster; half the threshold (20 flops per entry) switches
/// those and keeps the banded rods simplicial, whose triangular solves the supernodes'
/// padding would double (docs/performance.md §Engine tuning).
const SUPERNODAL_THRESHOLD: SupernodalThreshold = SupernodalThreshold(0.5);

/// Which factorisation solved the last system.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Factorization {
    /// Supernodal Cholesky LLᵀ (symmetric positive definite).
    Llt,
    /// Symmetric indefinite LBLᵀ (Bunch–Kaufman within supernodes) on the LLᵀ structure.
    Lblt,
}

/// Reusable sparse solver for one fixed pattern.
pub struct LinearSolver {
    n: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    chol: SymbolicCholesky<usize>,
    factors: Factors,
    mem: MemBuffer,
    /// Scratch needed by the LLᵀ / LBLᵀ paths.
    req: StackReq,
    /// Workspace of the Krylov-corrected solve (allocated on its first use).
    krylov_mem: Option<MemBuffer>,
    /// Parallelism handed to faer.
    pub par: Par,
    /// Factorisation held (or used last).
    pub last: Factorization,
    valid: bool,
    /// Preordered systems: the lower triangle handed to the numeric LLᵀ / LBLᵀ (faer reads
    /// an unpermuted matrix as it is, and its simplicial kernel wants one triangle only).
    lower: Option<Lower>,
    /// The low-rank part that completes the held factors ([`LinearSolver::complete`]).
    woodbury: Woodbury,
}

/// The lower triangle of a pattern.
struct Lower {
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    /// Index in the full pattern's values of each lower entry.
    src: Vec<usize>,
}

impl Lower {
    fn new(n: usize, col_ptr: &[usize], row_idx: &[usize]) -> Self {
        let (mut cp, mut ri, mut src) = (vec![0], Vec::new(), Vec::new());
        for c in 0..n {
            for k in col_ptr[c]..col_ptr[c + 1] {
                if row_idx[k] >= c {
                    ri.push(row_idx[k]);
                    src.push(k);
                }
            }
            cp.push(ri.len());
        }
        Self {
            col_ptr: cp,
            row_idx: ri,
            src,
        }
    }
}

impl LinearSolver {
    /// Analyse the symmetric pattern (CSC, sorted rows, no duplicates, both triangles;
    /// checked, an invalid pattern is [`SparseError::InvalidPattern`]) with AMD ordering.
    pub fn new(n: usize, col_ptr: &[usize], row_idx: &[usize]) -> Result<Self, EngineError> {
        Self::with_ordering(
            n,
            col_ptr,
            row_idx,
            SymmetricOrdering::Amd,
            Precision::Double,
        )
    }

    /// [`LinearSolver::new`] for a system already numbered in its fill-reducing order
    /// ([`amd_order`]): LLᵀ / LBLᵀ factorise it as it is, with no permutation.
    pub fn new_ordered(
        n: usize,
        col_ptr: &[usize],
        row_idx: &[usize],
        precision: Precision,
    ) -> Result<Self, EngineError> {
        Self::with_ordering(n, col_ptr, row_idx, SymmetricOrdering::Identity, precision)
    }

    fn with_ordering(
        n: usize,
        col_ptr: &[usize],
        row_idx: &[usize],
        ordering: SymmetricOrdering<'_, usize>,
        precision: Precision,
    ) -> Result<Self, EngineError> {
        check_pattern(n, col_ptr, row_idx).map_err(EngineError::Symbolic)?;
        // faer's parallel sparse LLᵀ was measured slower than one thread on the bundled
        // shells (21 ms against 11 ms at 7,203 DOFs, docs/performance.md): only very large
        // systems use the pool.
        let par = if n > 20_000 { Par::rayon(0) } else { Par::Seq };
        // SAFETY: `check_pattern` verified the CSC invariants faer requires.
        let sym = unsafe { SymbolicSparseColMatRef::new_unchecked(n, n, col_ptr, None, row_idx) };
        // AMD (done by the caller with `new_ordered`). A nested dissection by BFS level
        // structures was tried (docs/performance.md): 20 % more fill and 9 % slower
        // factorisations than AMD at 16k–33k nodes.
        let chol = factorize_symbolic_cholesky(
            sym,
            Side::Lower,
            ordering,
            CholeskySymbolicParams {
                supernodal_flop_ratio_threshold: SUPERNODAL_THRESHOLD,
                ..Default::default()
            },
        )
        .map_err(|e| EngineError::Symbolic(sparse_error(e)))?;
        let req = chol
            .factorize_numeric_llt_scratch::<f64>(par, Default::default())
            .or(chol.factorize_numeric_intranode_lblt_scratch::<f64>(par, Default::default()))
            .or(chol.solve_in_place_scratch::<f64>(1, par))
            .or(chol.factorize_numeric_llt_scratch::<f32>(par, Default::default()))
            .or(chol.factorize_numeric_intranode_lblt_scratch::<f32>(par, Default::default()))
            .or(chol.solve_in_place_scratch::<f32>(1, par));
        let lower = matches!(ordering, SymmetricOrdering::Identity)
            .then(|| Lower::new(n, col_ptr, row_idx));
        let nnz = lower.as_ref().map_or(row_idx.len(), |lo| lo.row_idx.len());
        let factors = match precision {
            Precision::Double => Factors::Double(Numeric::new(&chol, n, nnz)),
            Precision::Single => Factors::Single(Numeric::new(&chol, n, nnz)),
        };
        Ok(Self {
            n,
            col_ptr: col_ptr.to_vec(),
            row_idx: row_idx.to_vec(),
            chol,
            factors,
            mem: MemBuffer::new(req),
            req,
            krylov_mem: None,
            par,
            last: Factorization::Llt,
            valid: false,
            lower,
            woodbury: Woodbury::default(),
        })
    }

    /// The precision the factors are computed in.
    pub fn precision(&self) -> Precision {
        match self.factors {
            Factors::Double(_) => Precision::Double,
            Factors::Single(_) => Precision::Single,
        }
    }

    /// Compute later factors in `precision` (allocates the new factors' storage once when it
    /// changes; the factors held are dropped, so the next call must be a
    /// [`LinearSolver::factor`]).
    pub fn set_precision(&mut self, precision: Precision) {
        if self.precision() == precision {
            return;
        }
        let nnz = self
            .lower
            .as_ref()
            .map_or(self.row_idx.len(), |lo| lo.row_idx.len());
        self.factors = match precision {
            Precision::Double => Factors::Double(Numeric::new(&self.chol, self.n, nnz)),
            Precision::Single => Factors::Single(Numeric::new(&self.chol, self.n, nnz)),
        };
        // The Krylov workspace was sized for the old precision's solves.
        self.krylov_mem = None;
        self.valid = false;
    }

    /// The pattern given to [`LinearSolver::new`], as a faer view.
    fn pattern(&self) -> SymbolicSparseColMatRef<'_, usize> {
        // SAFETY: `new` checked the pattern (`check_pattern`), and it is never modified.
        unsafe {
            SymbolicSparseColMatRef::new_unchecked(
                self.n,
                self.n,
                &self.col_ptr,
                None,
                &self.row_idx,
            )
        }
    }

    /// Factorise the symmetric matrix with values `spd` (in the pattern given to
    /// [`LinearSolver::new`]; only its lower triangle is read): LLᵀ, or LBLᵀ on the same
    /// structure if it is not positive definite. The factors are kept for any number of
    /// [`LinearSolver::solve`] calls.
    pub fn factor(&mut self, spd: &[f64]) -> Factorization {
        let n = self.n;
        self.valid = true;
        self.woodbury.clear();
        if n == 0 {
            return self.last;
        }
        let (pattern, src) = match &self.lower {
            // SAFETY: the lower triangle of a checked pattern is a valid pattern.
            Some(lo) => (
                unsafe {
                    SymbolicSparseColMatRef::new_unchecked(n, n, &lo.col_ptr, None, &lo.row_idx)
                },
                Some(&lo.src[..]),
            ),
            // SAFETY: the same valid pattern as in `new`.
            None => (
                unsafe {
                    SymbolicSparseColMatRef::new_unchecked(n, n, &self.col_ptr, None, &self.row_idx)
                },
                None,
            ),
        };
        let stack = MemStack::new(&mut self.mem);
        self.last = match &mut self.factors {
            Factors::Double(f) => f.factor(&self.chol, pattern, spd, src, self.par, stack),
            Factors::Single(f) => f.factor(&self.chol, pattern, spd, src, self.par, stack),
        };
        self.last
    }

    /// Memory held by the solver (bytes): `(factor values, scratch)`.
    pub fn memory_bytes(&self) -> (usize, usize) {
        let l = match &self.factors {
            Factors::Double(f) => f.factor_bytes(),
            Factors::Single(f) => f.factor_bytes(),
        };
        (l, self.req.unaligned_bytes_required())
    }

    /// Stored entries of the factor.
    pub fn factor_entries(&self) -> usize {
        match &self.factors {
            Factors::Double(f) => f.factor_entries(),
            Factors::Single(f) => f.factor_entries(),
        }
    }

    /// Forget the factors (e.g. after `dt` changed).
    pub fn invalidate(&mut self) {
        self.valid = false;
    }

    /// Complete the factors just computed of `A` with a low-rank part: later solves are with
    /// `A + U Γ Uᵀ` (module [`low_rank`]), and [`LinearSolver::solve_corrected`]'s matrix
    /// includes it. Costs one solve per term. Returns false where the completed matrix is
    /// singular: the solves then stay with `A`.
    pub fn complete(&mut self, part: &LowRank) -> bool {
        assert!(self.valid, "complete() without factors");
        let mut wb = std::mem::take(&mut self.woodbury);
        let ok = wb.set(part, |x| self.solve_factors(x));
        self.woodbury = wb;
        ok
    }

    /// Solve `A x = b` in place with the current factors and their low-rank completion
    /// (`rhs` holds `b` on entry, `x` on exit).
    pub fn solve(&mut self, rhs: &mut [f64]) {
        self.woodbury.correct_rhs(rhs);
        self.solve_factors(rhs);
    }

    /// [`LinearSolver::solve`] with the sparse factors alone.
    fn solve_factors(&mut self, rhs: &mut [f64]) {
        let n = self.n;
        assert!(self.valid, "solve() without factors");
        if n == 0 {
            return;
        }
        // The workspace is moved out for the call (`solve_with` borrows the factors); the
        // zero-size placeholder does not reach the allocator.
        let mut mem = std::mem::replace(&mut self.mem, MemBuffer::new(StackReq::EMPTY));
        let x = MatMut::from_column_major_slice_mut(rhs, n, 1);
        self.solve_with(x, self.par, MemStack::new(&mut mem));
        self.mem = mem;
    }

    /// Workspace of [`LinearSolver::solve_with`] for `ncols` right-hand sides.
    fn solve_scratch(&self, ncols: usize, par: Par) -> StackReq {
        match &self.factors {
            Factors::Double(_) => self.chol.solve_in_place_scratch::<f64>(ncols, par),
            Factors::Single(_) => self.chol.solve_in_place_scratch::<f32>(ncols, par),
        }
    }

    /// Solve in place with the held factors and the given workspace (without the low-rank
    /// completion, which [`LinearSolver::solve`] and the Krylov preconditioner add).
    fn solve_with(&self, x: MatMut<'_, f64>, par: Par, stack: &mut MemStack) {
        match &self.factors {
            Factors::Double(f) => f.solve(&self.chol, self.last, x, par, stack),
            Factors::Single(f) => f.solve_f64(&self.chol, self.last, x, par, stack),
        }
    }

    /// [`LinearSolver::solve_with`] and the low-rank completion, on every column of `x`.
    fn solve_completed(&self, mut x: MatMut<'_, f64>, par: Par, stack: &mut MemStack) {
        if !self.woodbury.is_empty() {
            for j in 0..x.ncols() {
                let col = x.rb_mut().col_mut(j).try_as_col_major_mut();
                let col = col.expect("solves run on contiguous columns");
                self.woodbury.correct_rhs(col.as_slice_mut());
            }
        }
        self.solve_with(x, par, stack);
    }

    /// Solve `A x = b` for the matrix `A` with values `full` (in this solver's pattern) by
    /// BiCGStab preconditioned with the held factors (of an approximation of `A`), starting
    /// from `x` (see [`krylov`]). The workspace is allocated on the first call only.
    pub fn solve_corrected(
        &mut self,
        full: &[f64],
        b: &[f64],
        x: &mut [f64],
        rel_tol: f64,
        max_iters: usize,
    ) -> KrylovReport {
        assert!(self.valid, "solve_corrected() without factors");
        let held = self.krylov_mem.take();
        let a = krylov::Full {
            sparse: SparseColMatRef::new(self.pattern(), full),
            low_rank: self.woodbury.part(),
        };
        let mut mem = held.unwrap_or_else(|| MemBuffer::new(krylov::scratch(self, &a)));
        let rep =
            krylov::corrected_solve(self, &a, b, x, rel_tol, max_iters, MemStack::new(&mut mem));
        self.krylov_mem = Some(mem);
        rep
    }
}

#[cfg(test)]
mod tests;

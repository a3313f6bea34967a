//! The numeric factors of one symbolic structure, in double or single precision.
//!
//! Single precision halves the factor's storage, and with it the memory traffic of every
//! triangular solve (a solve streams the whole factor twice) and most of a factorisation's
//! time. The factors then solve the system to a relative accuracy of about `ε₃₂ κ`; that is
//! enough where they only precondition an iteration whose residual is computed in double
//! precision (chord iterations, Krylov corrections), and the converged state meets the same
//! double-precision test.

use faer::dyn_stack::MemStack;
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{IntranodeLbltRef, LltRef, SymbolicCholesky};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::traits::{ComplexField, RealField};
use faer::{Conj, MatMut, Par, Side};

use super::Factorization;

/// A real type faer factorises, with the conversions from and to `f64`.
pub(super) trait Real:
    ComplexField<Real = Self> + RealField + Copy + Default + Send + Sync + 'static
{
    fn from_f64(x: f64) -> Self;
    fn to_f64(self) -> f64;
}

impl Real for f64 {
    fn from_f64(x: f64) -> Self {
        x
    }
    fn to_f64(self) -> f64 {
        self
    }
}

impl Real for f32 {
    fn from_f64(x: f64) -> Self {
        x as f32
    }
    fn to_f64(self) -> f64 {
        f64::from(self)
    }
}

/// Factor values of one precision: `L` (and `B`'s sub-diagonal and the pivots of LBLᵀ), and
/// the matrix's lower triangle converted to that precision.
pub(super) struct Numeric<T> {
    l: Vec<T>,
    sub: Vec<T>,
    fwd: Vec<usize>,
    inv: Vec<usize>,
    matrix: Vec<T>,
    /// A right-hand side in this precision (single precision converts through it; behind a
    /// lock because a preconditioner solves through a shared reference).
    rhs: std::sync::Mutex<Vec<T>>,
}

impl<T: Real> Numeric<T> {
    /// Storage for `chol`'s factor of an `n × n` matrix with `lower_nnz` stored entries in
    /// the triangle handed to the factorisation.
    pub fn new(chol: &SymbolicCholesky<usize>, n: usize, lower_nnz: usize) -> Self {
        Self {
            l: vec![T::default(); chol.len_val()],
            sub: vec![T::default(); n],
            fwd: vec![0; n],
            inv: vec![0; n],
            matrix: vec![T::default(); lower_nnz],
            rhs: std::sync::Mutex::new(vec![T::default(); n]),
        }
    }

    /// Bytes of the factor values.
    pub fn factor_bytes(&self) -> usize {
        self.l.len() * std::mem::size_of::<T>()
    }

    /// Entries of the factor.
    pub fn factor_entries(&self) -> usize {
        self.l.len()
    }

    /// Factorise the matrix whose stored values (in `pattern`, lower triangle read) are
    /// `values[src[k]]` for entry `k`: LLᵀ, or LBLᵀ where it is not positive definite.
    #[allow(clippy::too_many_arguments)]
    pub fn factor(
        &mut self,
        chol: &SymbolicCholesky<usize>,
        pattern: SymbolicSparseColMatRef<'_, usize>,
        values: &[f64],
        src: Option<&[usize]>,
        par: Par,
        stack: &mut MemStack,
    ) -> Factorization {
        match src {
            Some(src) => {
                for (v, &k) in self.matrix.iter_mut().zip(src) {
                    *v = T::from_f64(values[k]);
                }
            }
            None => {
                for (v, &x) in self.matrix.iter_mut().zip(values) {
                    *v = T::from_f64(x);
                }
            }
        }
        let a = SparseColMatRef::new(pattern, &self.matrix[..]);
        let ok = chol
            .factorize_numeric_llt::<T>(
                &mut self.l,
                a,
                Side::Lower,
                LltRegularization::default(),
                par,
                stack,
                Default::default(),
            )
            .is_ok();
        if ok {
            return Factorization::Llt;
        }
        chol.factorize_numeric_intranode_lblt::<T>(
            &mut self.l,
            &mut self.sub,
            &mut self.fwd,
            &mut self.inv,
            a,
            Side::Lower,
            par,
            stack,
            Default::default(),
        );
        Factorization::Lblt
    }

    /// Solve the double-precision columns of `x` in place, converting each through this
    /// precision.
    pub fn solve_f64(
        &self,
        chol: &SymbolicCholesky<usize>,
        last: Factorization,
        mut x: MatMut<'_, f64>,
        par: Par,
        stack: &mut MemStack,
    ) {
        let mut rhs = self.rhs.lock().expect("not poisoned: solves do not panic");
        let n = rhs.len();
        for j in 0..x.ncols() {
            for i in 0..n {
                rhs[i] = T::from_f64(x[(i, j)]);
            }
            let col = MatMut::from_column_major_slice_mut(&mut rhs[..], n, 1);
            self.solve(chol, last, col, par, stack);
            for i in 0..n {
                x[(i, j)] = rhs[i].to_f64();
            }
        }
    }

    /// Solve in place with the factors of kind `last`.
    pub fn solve(
        &self,
        chol: &SymbolicCholesky<usize>,
        last: Factorization,
        x: MatMut<'_, T>,
        par: Par,
        stack: &mut MemStack,
    ) {
        match last {
            Factorization::Llt => {
                LltRef::new(chol, &self.l).solve_in_place_with_conj(Conj::No, x, par, stack);
            }
            Factorization::Lblt => {
                let perm = PermRef::new_checked(&self.fwd, &self.inv, self.fwd.len());
                IntranodeLbltRef::new(chol, &self.l, &self.sub, perm).solve_in_place_with_conj(
                    Conj::No,
                    x,
                    par,
                    stack,
                );
            }
        }
    }
}

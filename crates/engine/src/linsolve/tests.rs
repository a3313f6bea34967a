//! `LinearSolver::solve_corrected`: BiCGStab on a non-symmetric `A`, preconditioned by the
//! Cholesky factors of its symmetric part, reaches the requested relative residual and
//! agrees with a dense LU solve of `A`.

use super::{Factorization, LinearSolver};
use nalgebra::{DMatrix, DVector};
use rand::{rngs::StdRng, Rng, SeedableRng};

/// A random sparse `n × n` pattern (banded plus random couplings, structurally symmetric)
/// with an SPD symmetric part (diagonally dominant) and a skew part of relative size `skew`.
fn system(n: usize, skew: f64, rng: &mut StdRng) -> (Vec<usize>, Vec<usize>, Vec<f64>) {
    let mut a = DMatrix::<f64>::zeros(n, n);
    for i in 0..n {
        for j in [i + 1, i + 7, (i * 13 + 5) % n] {
            if j < n && j != i {
                let s = rng.random_range(-1.0..1.0);
                let k = skew * rng.random_range(-1.0..1.0);
                a[(i, j)] += s + k;
                a[(j, i)] += s - k;
            }
        }
    }
    for i in 0..n {
        let off: f64 = (0..n).filter(|&j| j != i).map(|j| a[(i, j)].abs()).sum();
        a[(i, i)] = off + 1.0;
    }
    // CSC of every structurally nonzero entry (both triangles, diagonal included).
    let (mut col_ptr, mut row_idx, mut vals) = (vec![0], Vec::new(), Vec::new());
    for c in 0..n {
        for r in 0..n {
            if r == c || a[(r, c)] != 0.0 || a[(c, r)] != 0.0 {
                row_idx.push(r);
                vals.push(a[(r, c)]);
            }
        }
        col_ptr.push(row_idx.len());
    }
    (col_ptr, row_idx, vals)
}

/// The values of `(A + Aᵀ)/2` on the pattern `(col_ptr, row_idx)`, column by column.
fn symmetric_part(a: &DMatrix<f64>, col_ptr: &[usize], row_idx: &[usize]) -> Vec<f64> {
    let sym = 0.5 * (a + a.transpose());
    (0..col_ptr.len() - 1)
        .flat_map(|c| (col_ptr[c]..col_ptr[c + 1]).map(move |k| (row_idx[k], c)))
        .map(|ij| sym[ij])
        .collect()
}

fn dense(n: usize, col_ptr: &[usize], row_idx: &[usize], v: &[f64]) -> DMatrix<f64> {
    let mut a = DMatrix::zeros(n, n);
    for c in 0..n {
        for k in col_ptr[c]..col_ptr[c + 1] {
            a[(row_idx[k], c)] = v[k];
        }
    }
    a
}

#[test]
fn krylov_correction_solves_the_nonsymmetric_system() {
    let mut rng = StdRng::seed_from_u64(11);
    let n = 300;
    for skew in [0.3, 1.0, 3.0] {
        let (cp, ri, full) = system(n, skew, &mut rng);
        let a = dense(n, &cp, &ri, &full);
        let sym_vals = symmetric_part(&a, &cp, &ri);
        let mut solver = LinearSolver::new(n, &cp, &ri).unwrap();
        assert_eq!(solver.factor(&sym_vals), Factorization::Llt);
        let b: Vec<f64> = (0..n).map(|_| rng.random_range(-1.0..1.0)).collect();
        // Start from the approximate solution A_s⁻¹ b, as Newton does.
        let mut x = b.clone();
        solver.solve(&mut x);
        let bv = DVector::from_column_slice(&b);
        let rel = |x: &[f64]| (&a * DVector::from_column_slice(x) - &bv).norm() / bv.norm();
        let before = rel(&x);
        let rep = solver.solve_corrected(&full, &b, &mut x, 1e-10, 50);
        let after = rel(&x);
        eprintln!(
            "skew {skew}: {before:.2e} → {after:.2e} in {} it",
            rep.iterations
        );
        // The control: the symmetric factors alone leave a residual far above the target.
        assert!(before > 1e-3, "skew {skew}: approximation already exact");
        assert!(rep.converged);
        // BiCGStab's recurrence residual vs the true one: equal up to round-off (κ ε).
        assert!(after <= 1e-9, "skew {skew}: true residual {after:e}");
        let exact = a.clone().lu().solve(&bv).unwrap();
        let err = (DVector::from_column_slice(&x) - &exact).norm() / exact.norm();
        assert!(err <= 1e-8, "skew {skew}: differs from dense LU by {err:e}");
    }
}

/// `LinearSolver::new` checks the CSC invariants faer's unchecked constructor relies on.
#[test]
fn malformed_patterns_are_refused() {
    use crate::error::{EngineError, SparseError};
    let cases: [(&[usize], &[usize]); 5] = [
        (&[0, 2, 3], &[1, 0, 1]), // rows not increasing in column 0
        (&[0, 1, 1], &[0, 0]),    // last pointer short of the row indices
        (&[0, 2, 1], &[0, 1]),    // pointers decrease
        (&[0, 1, 2], &[0, 2]),    // row out of range
        (&[0, 1], &[0]),          // wrong number of pointers
    ];
    for (col_ptr, row_idx) in cases {
        let err = LinearSolver::new(2, col_ptr, row_idx).err();
        assert!(
            matches!(
                err,
                Some(EngineError::Symbolic(SparseError::InvalidPattern(_)))
            ),
            "{col_ptr:?} {row_idx:?}: {err:?}"
        );
    }
    assert!(LinearSolver::new(2, &[0, 2, 4], &[0, 1, 0, 1]).is_ok());
}

/// A system numbered in its AMD order and factorised without a permutation
/// (`new_ordered`) solves it as the AMD-permuting solver does, on a small system (faer's
/// simplicial kernel), a larger one (supernodal), and an indefinite one (LBLᵀ).
#[test]
fn preordered_system_solves_like_the_permuting_solver() {
    let mut rng = StdRng::seed_from_u64(5);
    for (n, shift) in [(12, 0.0), (400, 0.0), (400, -30.0)] {
        let (cp, ri, mut v) = system(n, 0.0, &mut rng);
        // Shift the diagonal (indefinite for the negative shift).
        for c in 0..n {
            let k = cp[c] + ri[cp[c]..cp[c + 1]].binary_search(&c).unwrap();
            v[k] += shift;
        }
        let fwd = super::amd_order(n, &cp, &ri).unwrap();
        let mut inv = vec![0; n];
        for (i, &o) in fwd.iter().enumerate() {
            inv[o] = i;
        }
        // P A Pᵀ in CSC: new (i, j) = old (fwd[i], fwd[j]).
        let a = dense(n, &cp, &ri, &v);
        let (mut pcp, mut pri, mut pv) = (vec![0], Vec::new(), Vec::new());
        for j in 0..n {
            for i in 0..n {
                if a[(fwd[i], fwd[j])] != 0.0 || i == j {
                    pri.push(i);
                    pv.push(a[(fwd[i], fwd[j])]);
                }
            }
            pcp.push(pri.len());
        }
        let mut plain = LinearSolver::new(n, &cp, &ri).unwrap();
        let mut ordered =
            LinearSolver::new_ordered(n, &pcp, &pri, super::Precision::Double).unwrap();
        let f1 = plain.factor(&v);
        let f2 = ordered.factor(&pv);
        assert_eq!(f1, f2, "n {n}, shift {shift}");
        assert_eq!(f1 == Factorization::Lblt, shift < 0.0, "n {n}");
        let b: Vec<f64> = (0..n).map(|_| rng.random_range(-1.0..1.0)).collect();
        let mut x = b.clone();
        plain.solve(&mut x);
        let mut y: Vec<f64> = (0..n).map(|i| b[fwd[i]]).collect();
        ordered.solve(&mut y);
        let err = (0..n).map(|o| (x[o] - y[inv[o]]).abs()).fold(0.0, f64::max);
        let scale = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        assert!(err <= 1e-10 * scale, "n {n}, shift {shift}: {err:e}");
    }
}

/// Factors switched from single to double precision after the Krylov workspace was sized for
/// single-precision solves: the next corrected solve sizes it again and reaches 1e-10 (only
/// double-precision factors can precondition that far on their own).
#[test]
fn precision_switch_resizes_the_krylov_workspace() {
    let mut rng = StdRng::seed_from_u64(3);
    let n = 300;
    let (cp, ri, full) = system(n, 1.0, &mut rng);
    let a = dense(n, &cp, &ri, &full);
    let sym_vals = symmetric_part(&a, &cp, &ri);
    let mut solver = LinearSolver::new_ordered(n, &cp, &ri, super::Precision::Single).unwrap();
    let b: Vec<f64> = (0..n).map(|_| rng.random_range(-1.0..1.0)).collect();
    let bv = DVector::from_column_slice(&b);
    let rel = |x: &[f64]| (&a * DVector::from_column_slice(x) - &bv).norm() / bv.norm();
    for precision in [super::Precision::Single, super::Precision::Double] {
        solver.set_precision(precision);
        assert_eq!(solver.precision(), precision);
        solver.factor(&sym_vals);
        let mut x = b.clone();
        solver.solve(&mut x);
        let rep = solver.solve_corrected(&full, &b, &mut x, 1e-10, 50);
        assert!(rep.converged, "{precision:?}");
        assert!(rel(&x) <= 1e-9, "{precision:?}: {:e}", rel(&x));
    }
}

//! A symmetric low-rank term beside the sparse matrix: `A_full = A + U Γ Uᵀ`, with `U` an
//! `n × k` dense matrix over the free DOFs and `Γ = diag(γ)`.
//!
//! A force that couples every node of a body through a few collective quantities (the air's
//! added mass on a canopy's mean motion) has a Jacobian that would fill the sparse pattern
//! with a dense block. Held as `U Γ Uᵀ`, it costs `k` extra solves per factorisation and `2k`
//! vector products per solve, by the Sherman–Morrison–Woodbury identity
//! `(A + U Γ Uᵀ)⁻¹ = A⁻¹ − Z S⁻¹ Zᵀ` with `Z = A⁻¹ U`, `S = Γ⁻¹ + Uᵀ Z` (Golub & Van Loan,
//! *Matrix Computations*, 4th ed., §2.1.4).

use nalgebra::SMatrix;

/// Most terms a model's low-rank part may have (the corrections keep their `k` products on
/// the stack).
pub const MAX_RANK: usize = 8;

/// The terms `γ_j u_j u_jᵀ` of a low-rank part (only the terms with `γ_j ≠ 0`).
#[derive(Debug, Clone, Default)]
pub struct LowRank {
    n: usize,
    /// The vectors `u_j`, one after another (`rank × n`).
    u: Vec<f64>,
    /// The weights `γ_j`.
    gamma: Vec<f64>,
}

impl LowRank {
    /// An empty part for `n` unknowns, with room for `capacity` terms (so that
    /// [`LowRank::push`] never allocates up to it).
    pub fn with_capacity(n: usize, capacity: usize) -> Self {
        Self {
            n,
            u: Vec::with_capacity(n * capacity),
            gamma: Vec::with_capacity(capacity),
        }
    }

    /// Number of terms.
    pub fn rank(&self) -> usize {
        self.gamma.len()
    }

    /// Remove every term (the storage is kept).
    pub fn clear(&mut self) {
        self.u.clear();
        self.gamma.clear();
    }

    /// Add the term `gamma u uᵀ` with `u` zero, to be filled through the returned slice.
    pub fn push(&mut self, gamma: f64) -> &mut [f64] {
        assert!(
            self.rank() < MAX_RANK,
            "a low-rank part of more than {MAX_RANK} terms"
        );
        self.gamma.push(gamma);
        let start = self.u.len();
        self.u.resize(start + self.n, 0.0);
        &mut self.u[start..]
    }

    /// The terms `(γ_j, u_j)`.
    pub fn terms(&self) -> impl Iterator<Item = (f64, &[f64])> {
        self.gamma.iter().copied().zip(self.u.chunks(self.n.max(1)))
    }

    /// `y += U Γ Uᵀ x`.
    pub fn apply_add(&self, x: &[f64], y: &mut [f64]) {
        for (g, u) in self.terms() {
            let s = g * dot(u, x);
            y.iter_mut().zip(u).for_each(|(y, u)| *y += s * u);
        }
    }

    fn copy_from(&mut self, other: &LowRank) {
        self.n = other.n;
        self.u.clear();
        self.u.extend_from_slice(&other.u);
        self.gamma.clear();
        self.gamma.extend_from_slice(&other.gamma);
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(a, b)| a * b).sum()
}

/// The Woodbury correction that turns solves with factors of `A` into solves with
/// `A + U Γ Uᵀ`: `W = Z S⁻¹` is kept, and a right-hand side corrected by
/// [`Woodbury::correct_rhs`] before the solve.
#[derive(Debug, Default)]
pub(super) struct Woodbury {
    /// The part the factors were completed with.
    part: LowRank,
    /// `W = A⁻¹ U S⁻¹` (`rank × n`, one column after another).
    w: Vec<f64>,
    /// `Z = A⁻¹ U` while `W` is formed.
    z: Vec<f64>,
}

impl Woodbury {
    /// Whether there is a correction to apply.
    pub fn is_empty(&self) -> bool {
        self.part.rank() == 0
    }

    /// The part the factors were completed with.
    pub fn part(&self) -> &LowRank {
        &self.part
    }

    /// Hold no correction (new factors, not yet completed).
    pub fn clear(&mut self) {
        self.part.clear();
    }

    /// Complete factors of `A` with `part`: `solve` applies `A⁻¹` in place. Returns false
    /// (and holds no correction) where `S` is singular: the factors then stand for `A` alone,
    /// which the Krylov correction against the full matrix makes up for.
    pub fn set(&mut self, part: &LowRank, mut solve: impl FnMut(&mut [f64])) -> bool {
        self.part.copy_from(part);
        let (n, k) = (part.n, part.rank());
        self.z.clear();
        self.z.extend_from_slice(&part.u);
        for z in self.z.chunks_mut(n.max(1)) {
            solve(z);
        }
        // S = Γ⁻¹ + Uᵀ Z (k × k, symmetric for symmetric A) in the leading block of a fixed
        // MAX_RANK² matrix whose other block is the identity: its inverse has S⁻¹ there, and
        // nothing is allocated per factorisation.
        let s = SMatrix::<f64, MAX_RANK, MAX_RANK>::from_fn(|i, j| match (i < k, j < k) {
            (true, true) => {
                let d = if i == j { 1.0 / part.gamma[i] } else { 0.0 };
                d + dot(&part.u[i * n..(i + 1) * n], &self.z[j * n..(j + 1) * n])
            }
            _ => f64::from(u8::from(i == j)),
        });
        let Some(s_inv) = s.try_inverse().filter(|m| m.iter().all(|x| x.is_finite())) else {
            self.part.clear();
            return false;
        };
        // W = Z S⁻¹: column j of W is Σ_i Z_i (S⁻¹)_ij.
        self.w.clear();
        self.w.resize(k * n, 0.0);
        let z = &self.z;
        for j in 0..k {
            let col = &mut self.w[j * n..(j + 1) * n];
            for i in 0..k {
                let c = s_inv[(i, j)];
                col.iter_mut()
                    .zip(&z[i * n..(i + 1) * n])
                    .for_each(|(w, z)| *w += c * z);
            }
        }
        true
    }

    /// `b ← b − U (Wᵀ b)`, so that `A⁻¹` of the result is `(A + U Γ Uᵀ)⁻¹ b`: since `S` is
    /// symmetric, `Z S⁻¹ Uᵀ A⁻¹ b = A⁻¹ U S⁻¹ Zᵀ b = A⁻¹ U Wᵀ b`. Corrected before the solve
    /// rather than after it (`x − W Uᵀ x`, the same in exact arithmetic), the solve's own
    /// rounding is relative to the solution sought: after it, a large component of `A⁻¹ b`
    /// along `Z` would be cancelled, and single-precision factors' error with it amplified
    /// by the ratio of the low-rank part to `A` in that direction.
    pub fn correct_rhs(&self, b: &mut [f64]) {
        let n = self.part.n;
        let mut y = [0.0; MAX_RANK];
        for (w, y) in self.w.chunks(n.max(1)).zip(&mut y) {
            *y = dot(w, b);
        }
        for (u, y) in self.part.u.chunks(n.max(1)).zip(y) {
            b.iter_mut().zip(u).for_each(|(b, u)| *b -= y * u);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `A = tridiag(−1, 4, −1)` applied and solved densely, with a rank-2 part.
    #[test]
    fn woodbury_solves_the_completed_matrix() {
        use nalgebra::DMatrix;
        let n = 7;
        let a = DMatrix::from_fn(n, n, |i, j| match i.abs_diff(j) {
            0 => 4.0,
            1 => -1.0,
            _ => 0.0,
        });
        let mut part = LowRank::with_capacity(n, 2);
        for (j, g) in [(0, 2.5), (1, 0.7)] {
            let u = part.push(g);
            u.iter_mut()
                .enumerate()
                .for_each(|(i, x)| *x = ((i + 1) * (j + 2)) as f64 % 5.0 - 1.5);
        }
        let lu = a.clone().lu();
        let mut wb = Woodbury::default();
        assert!(wb.set(&part, |x| {
            let sol = lu.solve(&nalgebra::DVector::from_column_slice(x)).unwrap();
            x.copy_from_slice(sol.as_slice());
        }));
        let b: Vec<f64> = (0..n).map(|i| (i as f64).sin() + 0.3).collect();
        let mut rhs = b.clone();
        wb.correct_rhs(&mut rhs);
        let x = lu
            .solve(&nalgebra::DVector::from_column_slice(&rhs))
            .unwrap()
            .as_slice()
            .to_vec();
        // Residual of the completed system.
        let mut r: Vec<f64> = (&a * nalgebra::DVector::from_column_slice(&x))
            .as_slice()
            .to_vec();
        part.apply_add(&x, &mut r);
        let err = r
            .iter()
            .zip(&b)
            .fold(0.0f64, |m, (r, b)| m.max((r - b).abs()));
        assert!(err < 1e-12, "residual {err:.3e}");
    }
}

//! Anderson mixing of a fixed-point iteration `x ← x + f(x)` (Anderson 1965; Walker & Ni,
//! "Anderson acceleration for fixed-point iterations", SIAM J. Numer. Anal. 49(4), 2011).
//!
//! With `f(x) = −A⁻¹ R(x)` (the chord update with held factors `A`) the next iterate is
//! `x + f − (ΔX + ΔF) γ`, where the columns of `ΔX`, `ΔF` are the differences of the last
//! `m` iterates and updates and `γ` minimises `‖f − ΔF γ‖` in the mass-weighted norm
//! `Σ m_i f_i²` (the kinetic-energy metric, so that positions and angles are weighed by their
//! inertia). On a linear problem this is GMRES on `A⁻¹ J` restarted every `m` steps (Walker
//! & Ni, Th. 2.2): it removes the few directions in which stale factors are far from the
//! Jacobian, where the chord iteration would crawl or diverge, at the cost of `m` dot
//! products per iteration. No allocation after construction.

/// The mixing state: the last `m` differences and the Gram system of the least squares.
pub(crate) struct Anderson {
    depth: usize,
    dx: Vec<Vec<f64>>,
    df: Vec<Vec<f64>>,
    /// Columns stored (≤ depth) and the slot of the next one.
    len: usize,
    next: usize,
    x_prev: Vec<f64>,
    f_prev: Vec<f64>,
    has_prev: bool,
    weight: Vec<f64>,
    gram: Vec<f64>,
    gamma: Vec<f64>,
}

impl Anderson {
    /// Mixing of depth `depth` over `n` unknowns weighed by `weight` (masses).
    pub fn new(depth: usize, weight: &[f64]) -> Self {
        let n = weight.len();
        Self {
            depth,
            dx: vec![vec![0.0; n]; depth],
            df: vec![vec![0.0; n]; depth],
            len: 0,
            next: 0,
            x_prev: vec![0.0; n],
            f_prev: vec![0.0; n],
            has_prev: false,
            weight: weight.to_vec(),
            gram: vec![0.0; depth * depth],
            gamma: vec![0.0; depth],
        }
    }

    /// Forget the history (new factors: the map `f` changed).
    pub fn reset(&mut self) {
        self.len = 0;
        self.next = 0;
        self.has_prev = false;
    }

    /// Slot of the `j`-th stored column, oldest first.
    fn slot(&self, j: usize) -> usize {
        (self.next + self.depth - self.len + j) % self.depth
    }

    /// The next iterate from `x` and its update `f` (both overwritten: `x` with the new
    /// iterate).
    pub fn mix(&mut self, x: &mut [f64], f: &[f64]) {
        if self.has_prev && self.depth > 0 {
            let s = self.next;
            for i in 0..x.len() {
                self.dx[s][i] = x[i] - self.x_prev[i];
                self.df[s][i] = f[i] - self.f_prev[i];
            }
            self.next = (self.next + 1) % self.depth;
            self.len = (self.len + 1).min(self.depth);
        }
        self.x_prev.copy_from_slice(x);
        self.f_prev.copy_from_slice(f);
        self.has_prev = true;
        if self.len == 0 || !self.solve_least_squares(f) {
            // A plain chord update (first iteration, or a degenerate history, forgotten).
            if self.len > 0 {
                self.reset();
                self.x_prev.copy_from_slice(x);
                self.f_prev.copy_from_slice(f);
                self.has_prev = true;
            }
            x.iter_mut().zip(f).for_each(|(x, f)| *x += f);
            return;
        }
        for (i, xi) in x.iter_mut().enumerate() {
            let mut s = *xi + f[i];
            for j in 0..self.len {
                let c = self.slot(j);
                s -= self.gamma[j] * (self.dx[c][i] + self.df[c][i]);
            }
            *xi = s;
        }
    }

    /// `γ = argmin ‖f − ΔF γ‖_W` by the normal equations (a depth of a few columns; a
    /// relative regularisation of 1e-12 keeps nearly dependent columns from blowing up);
    /// `false` if they are singular even so.
    fn solve_least_squares(&mut self, f: &[f64]) -> bool {
        let k = self.len;
        let w = &self.weight;
        for a in 0..k {
            let ca = &self.df[self.slot(a)];
            for b in 0..=a {
                let cb = &self.df[self.slot(b)];
                let s: f64 = (0..w.len()).map(|i| w[i] * ca[i] * cb[i]).sum();
                self.gram[a * k + b] = s;
                self.gram[b * k + a] = s;
            }
            self.gamma[a] = (0..w.len()).map(|i| w[i] * ca[i] * f[i]).sum();
        }
        let trace: f64 = (0..k).map(|a| self.gram[a * k + a]).sum();
        for a in 0..k {
            self.gram[a * k + a] += 1e-12 * trace / k as f64;
        }
        cholesky_solve(&mut self.gram[..k * k], k, &mut self.gamma[..k])
    }
}

/// Solve the `k × k` SPD system `a x = b` in place (`b` ← `x`); `false` if not positive
/// definite.
fn cholesky_solve(a: &mut [f64], k: usize, b: &mut [f64]) -> bool {
    for j in 0..k {
        let d = a[j * k + j] - (0..j).map(|p| a[j * k + p].powi(2)).sum::<f64>();
        if !(d > 0.0 && d.is_finite()) {
            return false;
        }
        let d = d.sqrt();
        a[j * k + j] = d;
        for i in j + 1..k {
            let s = a[i * k + j] - (0..j).map(|p| a[i * k + p] * a[j * k + p]).sum::<f64>();
            a[i * k + j] = s / d;
        }
    }
    for i in 0..k {
        b[i] = (b[i] - (0..i).map(|p| a[i * k + p] * b[p]).sum::<f64>()) / a[i * k + i];
    }
    for i in (0..k).rev() {
        b[i] = (b[i] - (i + 1..k).map(|p| a[p * k + i] * b[p]).sum::<f64>()) / a[i * k + i];
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    /// On a linear map `f(x) = −A⁻¹(B x − b)` with `A ≠ B` the plain iteration diverges
    /// (spectral radius of `I − A⁻¹B` above 1) while the mixed one converges, as GMRES does.
    #[test]
    fn mixing_converges_where_the_chord_iteration_diverges() {
        let n = 6;
        // B = diag(1..6), A = diag of ones: I − A⁻¹B has eigenvalues 0, −1, …, −5.
        let bdiag: Vec<f64> = (1..=n).map(|i| i as f64).collect();
        let rhs = vec![1.0; n];
        let upd = |x: &[f64], f: &mut [f64]| {
            for i in 0..n {
                f[i] = -(bdiag[i] * x[i] - rhs[i]);
            }
        };
        let run = |depth: usize| {
            let mut aa = Anderson::new(depth, &vec![1.0; n]);
            let (mut x, mut f) = (vec![0.0; n], vec![0.0; n]);
            for _ in 0..12 {
                upd(&x, &mut f);
                aa.mix(&mut x, &f);
            }
            upd(&x, &mut f);
            f.iter().fold(0.0f64, |m, v| m.max(v.abs()))
        };
        let plain = run(0);
        let mixed = run(n);
        assert!(plain > 1e3, "the chord iteration should diverge: {plain:e}");
        assert!(mixed < 1e-8, "Anderson mixing should converge: {mixed:e}");
    }

    #[test]
    fn cholesky_solves_a_small_spd_system() {
        let mut a = vec![4.0, 2.0, 2.0, 3.0];
        let mut b = vec![2.0, 1.0];
        assert!(cholesky_solve(&mut a, 2, &mut b));
        assert!((b[0] - 0.5).abs() < 1e-15 && b[1].abs() < 1e-15, "{b:?}");
        let mut singular = vec![1.0, 1.0, 1.0, 1.0];
        assert!(!cholesky_solve(&mut singular, 2, &mut [1.0, 0.0]));
    }
}

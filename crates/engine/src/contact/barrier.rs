//! The log barrier of Incremental Potential Contact (Li et al., SIGGRAPH 2020, eq. 6) on a
//! squared distance `d`, and the energy, gradient and Hessian of one contact pair.
//!
//! `b(d) = −κ (d − d̂)² ln(d / d̂)` for `0 < d < d̂`, zero beyond: `b`, `b′` and `b″` all vanish
//! at `d = d̂` (the pair enters and leaves the active set smoothly, C²), and `b → ∞` as
//! `d → 0`, so a step that keeps the energy finite never lets two surfaces touch. `d̂` is the
//! square of the activation distance and κ the stiffness (N·m⁻³ here: energy per m⁴ of
//! squared distance).

use super::ad::{variables, Real};
use super::distance::{of_pair, Pair};

/// The barrier's parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Barrier {
    /// `d̂`: the square of the distance below which a pair repels (m²).
    pub d_hat: f64,
    /// κ: the barrier's stiffness (J/m⁴).
    pub kappa: f64,
}

impl Barrier {
    /// `(b, b′, b″)` at squared distance `d` (zero at and beyond `d̂`; `d` must be positive).
    pub fn eval(&self, d: f64) -> [f64; 3] {
        let dh = self.d_hat;
        if d >= dh {
            return [0.0; 3];
        }
        let (u, l) = (d - dh, (d / dh).ln());
        let k = self.kappa;
        [
            -k * u * u * l,
            -k * (2.0 * u * l + u * u / d),
            -k * (2.0 * l + 4.0 * u / d - u * u / (d * d)),
        ]
    }
}

/// Energy, gradient (12) and Hessian (12 × 12, row-major) of one pair on the stencil
/// coordinates `x` (4 points): `E = b(d)`, `∇E = b′ ∇d`, `∇²E = b′ ∇²d + b″ ∇d ∇dᵀ`. `None`
/// when the pair is inactive (`d ≥ d̂`).
pub fn pair(barrier: &Barrier, kind: Pair, x: &[f64; 12]) -> Option<(f64, [f64; 12], [f64; 144])> {
    let d = of_pair(kind, &variables(x));
    if d.value() >= barrier.d_hat {
        return None;
    }
    let [b, b1, b2] = barrier.eval(d.v);
    let mut h = [0.0; 144];
    for i in 0..12 {
        for j in 0..12 {
            h[12 * i + j] = b1 * d.h[i][j] + b2 * d.g[i] * d.g[j];
        }
    }
    Some((b, d.g.map(|g| b1 * g), h))
}

/// Replace the symmetric 12 × 12 `h` by its nearest positive semi-definite matrix (negative
/// eigenvalues set to zero), as IPC does per pair so that Newton's system stays definite.
pub fn project_psd(h: &mut [f64; 144]) {
    let m = nalgebra::SMatrix::<f64, 12, 12>::from_row_slice(h);
    let eig = nalgebra::SymmetricEigen::new(m);
    if eig.eigenvalues.iter().all(|&l| l >= 0.0) {
        return;
    }
    let lam = eig.eigenvalues.map(|l| l.max(0.0));
    let p = eig.eigenvectors
        * nalgebra::SMatrix::<f64, 12, 12>::from_diagonal(&lam)
        * eig.eigenvectors.transpose();
    for i in 0..12 {
        for j in 0..12 {
            h[12 * i + j] = 0.5 * (p[(i, j)] + p[(j, i)]);
        }
    }
}

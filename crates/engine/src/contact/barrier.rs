//! The log barrier of Incremental Potential Contact (Li et al., SIGGRAPH 2020, eq. 6) on a
//! squared distance `d`, and the energy, gradient and Hessian of one contact pair.
//!
//! `b(d) = −κ (d − d̂)² ln(d / d̂)` for `0 < d < d̂`, zero beyond: `b`, `b′` and `b″` all vanish
//! at `d = d̂` (the pair enters and leaves the active set smoothly, C²), and `b → ∞` as
//! `d → 0`, so a step that keeps the energy finite never lets two surfaces touch. `d̂` is the
//! square of the activation distance and κ the stiffness (N·m⁻³ here: energy per m⁴ of
//! squared distance).

use super::ad::{cross, dot, sub, variables, D2};
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
/// coordinates `x` (4 points): `E = m b(d)`, its derivatives exact (forward AD). `None` when
/// the pair is inactive (`d ≥ d̂`).
///
/// `mollifier`: for an edge–edge pair, IPC's `εx` (§4.3; `1e-3 |ea|²|eb|²` at rest, m²·m²):
/// `m = (2 − c/εx) c/εx` for `c = |ea × eb|² < εx`, else 1, so that the energy stays C¹ where
/// nearly parallel edges switch between the line–line and endpoint formulas; such edges are
/// held apart by their endpoints' pairs. `None` (point–triangle): `m = 1`.
pub fn pair(
    barrier: &Barrier,
    kind: Pair,
    x: &[f64; 12],
    mollifier: Option<f64>,
) -> Option<(f64, [f64; 12], [f64; 144])> {
    let v = variables(x);
    let d = of_pair(kind, &v);
    if d.v >= barrier.d_hat {
        return None;
    }
    let [b, b1, b2] = barrier.eval(d.v);
    let mut e = d.chain(b, b1, b2);
    if let Some(eps) = mollifier {
        let n = cross(sub(v[1], v[0]), sub(v[3], v[2]));
        let c = dot(n, n);
        if c.v < eps {
            let r = c * (1.0 / eps);
            e = e * (r * (D2::constant(2.0) - r));
        }
    }
    let mut h = [0.0; 144];
    for i in 0..12 {
        h[12 * i..12 * i + 12].copy_from_slice(&e.h[i]);
    }
    Some((e.v, e.g, h))
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

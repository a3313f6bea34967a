//! Regularised speed `|u|_ε = √(|u|² + ε²)`.
//!
//! Quadratic drag `|u| u` has the Jacobian `|u| I + u uᵀ/|u|`, which is undefined at `u = 0`
//! (a body at rest, the first step of every run). Replacing `|u|` by `|u|_ε` makes the force
//! and its Jacobian smooth everywhere; the relative change of the force is `ε²/(2|u|²)`,
//! i.e. 5·10⁻¹³ at 1 mm/s with the default ε, far below any other error.

use crate::vec3::{outer, M3, V3};

/// Default regularisation speed ε (m/s).
pub const DEFAULT_EPSILON: f64 = 1e-6;

/// `|u|_ε = √(|u|² + ε²)` (m/s).
#[inline]
pub fn reg_norm(u: &V3, eps: f64) -> f64 {
    (u.norm_squared() + eps * eps).sqrt()
}

/// The regularised quadratic law `g(u) = |u|_ε u` (m²/s²) and its Jacobian
/// `∂g/∂u = |u|_ε I + u uᵀ / |u|_ε` (m/s), which is symmetric positive definite.
#[inline]
pub fn quadratic(u: &V3, eps: f64) -> (V3, M3) {
    let w = reg_norm(u, eps);
    (u * w, M3::identity() * w + outer(u, u) / w)
}

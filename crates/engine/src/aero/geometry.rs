//! Triangle geometry shared by the drag elements.

use crate::vec3::{skew, M3, V3};

/// Area vector `N = ½ (x₁ − x₀) × (x₂ − x₀)` (m²): `|N|` is the area, `N/|N|` the unit
/// normal (right-handed with the node order).
#[inline]
pub(crate) fn area_vector(x: &[V3; 3]) -> V3 {
    0.5 * (x[1] - x[0]).cross(&(x[2] - x[0]))
}

/// `∂N/∂x_b` for b = 0, 1, 2 (m): `½[x₂ − x₁]×`, `−½[x₂ − x₀]×`, `½[x₁ − x₀]×`.
#[inline]
pub(crate) fn area_vector_jacobians(x: &[V3; 3]) -> [M3; 3] {
    [
        0.5 * skew(&(x[2] - x[1])),
        -0.5 * skew(&(x[2] - x[0])),
        0.5 * skew(&(x[1] - x[0])),
    ]
}

/// Read node `i`'s 3-vector from a stencil slice of a global vector.
#[inline]
pub(crate) fn stencil_vec(g: &[f64], st: &[usize], i: usize) -> V3 {
    V3::new(g[st[3 * i]], g[st[3 * i + 1]], g[st[3 * i + 2]])
}

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

/// The three corners (in `q`) or corner velocities (in `v`) of the triangle of stencil `st`.
#[inline]
pub(crate) fn corners(g: &[f64], st: &[usize]) -> [V3; 3] {
    [0, 1, 2].map(|i| stencil_vec(g, st, i))
}

/// The height z (m) of the centroid of the triangle with corners `x`: where the air and the
/// wind acting on it are taken.
#[inline]
pub(crate) fn centroid_height(x: &[V3; 3]) -> f64 {
    (x[0].z + x[1].z + x[2].z) / 3.0
}

/// The mean of the triangle's corner velocities (its centroid's velocity).
#[inline]
pub(crate) fn centroid_velocity(v: &[f64], st: &[usize]) -> V3 {
    corners(v, st).iter().sum::<V3>() / 3.0
}

/// Write the same force `f` (N) on each of a triangle's three nodes (`out`: 9 entries).
#[inline]
pub(crate) fn same_force_on_nodes(f: &V3, out: &mut [f64]) {
    for i in 0..3 {
        out[3 * i..3 * i + 3].copy_from_slice(f.as_slice());
    }
}

/// Fill a triangle's 9 × 9 Jacobians when every node's force is the same: row block `i`,
/// column block `b` is `dq[b]` in `dfdq` and `dv` in `dfdv`, for every `i`.
#[inline]
pub(crate) fn same_rows(dq: &[M3; 3], dv: &M3, dfdq: &mut [f64], dfdv: &mut [f64]) {
    for (bn, dqb) in dq.iter().enumerate() {
        for i in 0..3 {
            for r in 0..3 {
                for c in 0..3 {
                    dfdq[(3 * i + r) * 9 + 3 * bn + c] = dqb[(r, c)];
                    dfdv[(3 * i + r) * 9 + 3 * bn + c] = dv[(r, c)];
                }
            }
        }
    }
}

//! Bending of Discrete Elastic Rods: material curvatures and their exact gradients.
//!
//! At a node between edges `e0` (into the node) and `e1` (out of it), with material frames
//! `(m1_k, m2_k)` and the curvature binormal `κb = 2 e0 × e1/(|e0||e1| + e0·e1)`:
//! - `κ1 = ½ (m2_0 + m2_1)·κb` — bending *about* `m2` (the tangent turns towards `m1`);
//! - `κ2 = −½ (m1_0 + m1_1)·κb` — bending *about* `m1` (Bergou et al. 2008's convention).
//!
//! Both are dimensionless (integrated curvatures); the energy (see `bend_twist`) is
//! `½ [EI2 (κ1 − κ̄1)² + EI1 (κ2 − κ̄2)²] / l̄` in J, with `EI1`, `EI2` the stiffnesses about
//! `d1 = m1` and `d2 = m2` (N·m²) and `l̄` the Voronoi length (m).
//!
//! Gradients (Bergou et al. 2010; DisMech), with `χ = 1 + t0·t1`, `t̃ = (t0 + t1)/χ`,
//! `m̃_j = (m_j0 + m_j1)/χ`, for frames that follow the edges *without twisting*:
//! `∂κ1/∂e0 = (−κ1 t̃ + t1 × m̃2)/|e0|`, `∂κ1/∂e1 = (−κ1 t̃ − t0 × m̃2)/|e1|`,
//! `∂κ2/∂e0 = (−κ2 t̃ − t1 × m̃1)/|e0|`, `∂κ2/∂e1 = (−κ2 t̃ + t0 × m̃1)/|e1|`,
//! `∂κ1/∂θ_k = −½ κb·m1_k`, `∂κ2/∂θ_k = −½ κb·m2_k`.
//! Reference frames time-parallel transported from the last accepted tangent `u_k` do twist
//! about `t_k` when `t_k ≠ u_k`, at the rate `∂ψ_k/∂e_k = g_k` (see `bend_twist::Local`), so
//! the exact gradient adds `(∂κ_j/∂θ_k) g_k` to `∂κ_j/∂e_k`.

use super::bend_twist::Local;
use super::scalar::{Real, G3};

/// Material curvatures `[κ1, κ2]` (dimensionless).
#[inline]
pub(crate) fn curvatures<T: Real>(l: &Local<T>) -> [T; 2] {
    let half = 0.5;
    [
        (l.m2[0] + l.m2[1]).dot(&l.kb) * half,
        -((l.m1[0] + l.m1[1]).dot(&l.kb) * half),
    ]
}

/// Exact gradients of the material curvatures.
pub(crate) struct CurvatureGrad<T> {
    /// `de[j][k] = ∂κ_j/∂e_k` (1/m), including the frame-transport twist.
    pub de: [[G3<T>; 2]; 2],
    /// `dth[j][k] = ∂κ_j/∂θ_k` (1/rad).
    pub dth: [[T; 2]; 2],
}

/// Gradients of `kappa = curvatures(l)` with respect to the edge vectors and twists.
pub(crate) fn curvature_gradients<T: Real>(l: &Local<T>, kappa: &[T; 2]) -> CurvatureGrad<T> {
    let inv_chi = T::cst(1.0) / l.chi;
    let tt = (l.t[0] + l.t[1]).scale(inv_chi);
    let md1 = (l.m1[0] + l.m1[1]).scale(inv_chi);
    let md2 = (l.m2[0] + l.m2[1]).scale(inv_chi);
    let inv = [T::cst(1.0) / l.n[0], T::cst(1.0) / l.n[1]];
    let dth = [
        [-(l.kb.dot(&l.m1[0]) * 0.5), -(l.kb.dot(&l.m1[1]) * 0.5)],
        [-(l.kb.dot(&l.m2[0]) * 0.5), -(l.kb.dot(&l.m2[1]) * 0.5)],
    ];
    let k1t = tt.scale(-kappa[0]);
    let k2t = tt.scale(-kappa[1]);
    let de = [
        [
            (k1t + l.t[1].cross(&md2)).scale(inv[0]),
            (k1t - l.t[0].cross(&md2)).scale(inv[1]),
        ],
        [
            (k2t - l.t[1].cross(&md1)).scale(inv[0]),
            (k2t + l.t[0].cross(&md1)).scale(inv[1]),
        ],
    ];
    let mut out = CurvatureGrad { de, dth };
    for j in 0..2 {
        for k in 0..2 {
            out.de[j][k] = out.de[j][k] + l.g[k].scale(dth[j][k]);
        }
    }
    out
}

//! Twisting of Discrete Elastic Rods: reference twist and its exact gradient.
//!
//! The twist at the node between edges `e0` and `e1` is `τ = θ1 − θ0 + m` (rad), where the
//! *reference twist* `m` is the signed angle about `t1` from `P(t0 → t1) a1_0` to `a1_1`
//! (the twist of the reference frames themselves). The energy (see `bend_twist`) is
//! `½ GJ (τ − τ̄)² / l̄` (J), `GJ` in N·m², `l̄` the Voronoi length (m).
//!
//! Gradient: for frames that follow the edges without twisting, `∂m/∂e_k = κb/(2|e_k|)`
//! (Bergou et al. 2010, the holonomy of parallel transport). Time-parallel transported
//! frames twist by `dψ_k = g_k·de_k` as well (see `bend_twist::Local`), and `m` measures
//! frame 1 against frame 0, so `∂m/∂e0 = κb/(2|e0|) − g_0`, `∂m/∂e1 = κb/(2|e1|) + g_1`.

use super::bend_twist::Local;
use super::frames::transport;
use super::scalar::{Real, G3};
use std::f64::consts::TAU;

/// Reference twist `m` (rad) on the 2π branch nearest `previous`.
#[inline]
pub(crate) fn reference_twist<T: Real>(l: &Local<T>, previous: f64) -> T {
    let p = transport(&l.r1[0], &l.t[0], &l.t[1]);
    let m = p.cross(&l.r1[1]).dot(&l.t[1]).atan2(p.dot(&l.r1[1]));
    let turns = ((m.val() - previous) / TAU).round();
    m + (-TAU * turns)
}

/// `[∂m/∂e0, ∂m/∂e1]` (rad/m).
#[inline]
pub(crate) fn reference_twist_gradient<T: Real>(l: &Local<T>) -> [G3<T>; 2] {
    let h0 = T::cst(0.5) / l.n[0];
    let h1 = T::cst(0.5) / l.n[1];
    [l.kb.scale(h0) - l.g[0], l.kb.scale(h1) + l.g[1]]
}

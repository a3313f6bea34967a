//! Continuous collision detection: how far a pair may move along a straight-line update before
//! its distance falls to a fraction of what it was. Additive CCD (Li, Kaufman & Jiang,
//! "Codimensional Incremental Potential Contact", SIGGRAPH 2021, Algorithm 1): with `l_p` a
//! bound on how fast the pair's distance can shrink per unit of step (the largest relative
//! displacement of its two sides), a step of `(d − s d₀)/l_p` cannot bring it below `s d₀`;
//! repeated from the distance reached, the steps add up to a time of impact from below. A
//! line search that never steps past the smallest of these keeps every pair apart.

use super::ad::V;
use super::distance::{edge_edge, point_edge, point_triangle};

/// The kind of a pair's stencil (the same four points as in [`super::distance`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stencil {
    /// `p, t0, t1, t2`.
    PointTriangle,
    /// `a0, a1, b0, b1`.
    EdgeEdge,
    /// `p, a, b` (the fourth point is not used).
    PointEdge,
}

/// Iterations at most: a pair that is not closing is passed in a handful of them.
const MAX_ITERATIONS: usize = 10_000;
/// A step below this fraction of the whole is a pair closing in on its gap: the search stops.
const STALL: f64 = 1e-6;

fn distance(kind: Stencil, x: &[V<f64>; 4]) -> f64 {
    match kind {
        Stencil::PointTriangle => point_triangle(x).1,
        Stencil::EdgeEdge => edge_edge(x).1,
        Stencil::PointEdge => point_edge(x).1,
    }
    .sqrt()
}

fn norm(v: V<f64>) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

/// The largest `t ≤ t_max` such that moving the pair's points `x` by `t dx` keeps its distance
/// at or above `s` times the present one (`0 < s < 1`; IPC uses 0.1 to 0.2). Returns `t_max`
/// when nothing in between comes closer, 0 for a pair already touching.
pub fn max_step(kind: Stencil, x: &[V<f64>; 4], dx: &[V<f64>; 4], s: f64, t_max: f64) -> f64 {
    // Only the relative motion matters: remove the mean displacement.
    let used = if kind == Stencil::PointEdge { 3 } else { 4 };
    let mean: V<f64> =
        std::array::from_fn(|k| dx[..used].iter().map(|p| p[k]).sum::<f64>() / used as f64);
    let p: [V<f64>; 4] = dx.map(|d| std::array::from_fn(|k| d[k] - mean[k]));
    let l_p = match kind {
        Stencil::PointTriangle => norm(p[0]) + norm(p[1]).max(norm(p[2])).max(norm(p[3])),
        Stencil::EdgeEdge => norm(p[0]).max(norm(p[1])) + norm(p[2]).max(norm(p[3])),
        Stencil::PointEdge => norm(p[0]) + norm(p[1]).max(norm(p[2])),
    };
    let d0 = distance(kind, x);
    if l_p == 0.0 {
        return t_max;
    }
    if d0 == 0.0 {
        return 0.0;
    }
    let gap = s * d0;
    // Each step is one the bound covers: over it the distance falls by at most l_p per unit,
    // so it stays above the gap all the way; the first closes (1 − s) of the distance, the
    // later ones 0.9 of what is left above the gap, measured afresh.
    let (mut t, mut step) = (0.0, (1.0 - s) * d0 / l_p);
    let mut y = *x;
    for _ in 0..MAX_ITERATIONS {
        if t + step >= t_max {
            return t_max;
        }
        t += step;
        for (yi, (xi, pi)) in y.iter_mut().zip(x.iter().zip(dx.iter())) {
            *yi = std::array::from_fn(|k| xi[k] + t * pi[k]);
        }
        step = 0.9 * (distance(kind, &y) - gap) / l_p;
        // Creeping towards the gap (a collision ahead): stop here.
        if step <= STALL * t_max {
            return t;
        }
    }
    t
}

//! The small dense algebra of the tension-field inner solve: the barrier's derivatives in
//! strain-Voigt form, a root-free `L D Lᵀ` for 3 × 3 SPD systems, and the scalar roots.

use super::super::membrane::{Voigt, Voigt3};

/// `det P` and its gradient for `P` in strain-Voigt form.
#[inline]
pub(super) fn det_grad(p: &Voigt) -> (f64, Voigt) {
    (p[0] * p[1] - 0.25 * p[2] * p[2], [p[1], p[0], -0.5 * p[2]])
}

/// Hessian `B` of `−μ ln det P` (strain-Voigt), from `det P` and its gradient.
#[inline]
pub(super) fn barrier_hessian_of(mu: f64, d: f64, g: &Voigt) -> Voigt3 {
    // (One division: this is the inner loop's latency chain.)
    let a = mu / d;
    let s = a / d;
    let mut b = [[0.0; 3]; 3];
    for r in 0..3 {
        for c in 0..3 {
            b[r][c] = s * g[r] * g[c];
        }
    }
    // −μ ∇²d / d with ∇²d = [[0, 1, 0], [1, 0, 0], [0, 0, −½]].
    b[0][1] -= a;
    b[1][0] -= a;
    b[2][2] += 0.5 * a;
    b
}

/// Hessian `B` of `−μ ln det P` (strain-Voigt).
#[inline]
pub(super) fn barrier_hessian(mu: f64, p: &Voigt) -> Voigt3 {
    let (d, g) = det_grad(p);
    barrier_hessian_of(mu, d, &g)
}

/// The `L D Lᵀ` factors (`L` unit lower triangular: `l₁₀, l₂₀, l₂₁`; the inverse pivots
/// `1/dᵢ`) of a symmetric positive-definite 3 × 3 `A`: three divisions and no square root,
/// where a Cholesky factor and its solve put three roots and nine divisions on the inner
/// solve's critical path. A pivot that is not positive makes every solve NaN.
#[derive(Clone, Copy)]
pub(super) struct Ldl3 {
    l: [f64; 3],
    inv: [f64; 3],
}

impl Ldl3 {
    #[inline]
    pub(super) fn new(a: &Voigt3) -> Self {
        let inverse = |d: f64| if d > 0.0 { 1.0 / d } else { f64::NAN };
        let i0 = inverse(a[0][0]);
        let (l10, l20) = (a[1][0] * i0, a[2][0] * i0);
        let i1 = inverse(a[1][1] - l10 * a[1][0]);
        let l21 = (a[2][1] - l20 * a[1][0]) * i1;
        let i2 = inverse(a[2][2] - l20 * a[2][0] - l21 * (a[2][1] - l20 * a[1][0]));
        Self {
            l: [l10, l20, l21],
            inv: [i0, i1, i2],
        }
    }

    /// `A⁻¹ r`.
    #[inline]
    pub(super) fn solve(&self, r: &Voigt) -> Voigt {
        let [l10, l20, l21] = self.l;
        let y1 = r[1] - l10 * r[0];
        let y2 = r[2] - l20 * r[0] - l21 * y1;
        let x2 = y2 * self.inv[2];
        let x1 = y1 * self.inv[1] - l21 * x2;
        let x0 = r[0] * self.inv[0] - l10 * x1 - l20 * x2;
        [x0, x1, x2]
    }
}

/// Solve `A x = r` for symmetric positive-definite 3 × 3 `A`.
#[inline]
pub(super) fn spd_solve(a: &Voigt3, r: &Voigt) -> Voigt {
    Ldl3::new(a).solve(r)
}

/// Positive root of `k p² + s p − μ = 0`, without cancellation.
#[inline]
pub(super) fn root(k: f64, s: f64, mu: f64) -> f64 {
    let disc = (s * s + 4.0 * k * mu).sqrt();
    if s > 0.0 {
        2.0 * mu / (s + disc)
    } else {
        (disc - s) / (2.0 * k)
    }
}

/// The inverse of a symmetric 2 × 2 tensor given as `(T₁₁, T₂₂, T₁₂)`, in the same form, if
/// it is positive definite.
#[inline]
pub(super) fn inverse_if_pd(t: &Voigt) -> Option<Voigt> {
    let det = t[0] * t[1] - t[2] * t[2];
    (t[0] > 0.0 && det > 0.0).then(|| [t[1] / det, t[0] / det, -t[2] / det])
}

/// `det[a, b, c]` of three column 3-vectors.
#[inline]
pub(super) fn det3(a: &Voigt, b: &Voigt, c: &Voigt) -> f64 {
    a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
        + a[2] * (b[0] * c[1] - b[1] * c[0])
}

/// A root of `f` in `[a, b]`, where `f(a) = fa` and `f(b) = fb` differ in sign, by the
/// Illinois variant of regula falsi (superlinear, and never leaves the bracket) to 1e-12
/// rad.
pub(super) fn bracketed_root(
    f: &impl Fn(f64) -> f64,
    mut a: f64,
    mut b: f64,
    mut fa: f64,
    mut fb: f64,
) -> f64 {
    let mut side = 0;
    for _ in 0..100 {
        if fa == fb || (b - a).abs() < 1e-12 {
            break;
        }
        let x = (a * fb - b * fa) / (fb - fa);
        let fx = f(x);
        if fx == 0.0 {
            return x;
        }
        if fx * fb < 0.0 {
            (a, fa) = (b, fb);
            side = 0;
        } else {
            // The same end kept twice: halve its value so the bracket shrinks on both sides.
            side += 1;
            if side > 1 {
                fa *= 0.5;
            }
        }
        (b, fb) = (x, fx);
    }
    0.5 * (a + b)
}

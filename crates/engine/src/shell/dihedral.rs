//! Signed dihedral angle of a hinge, with its exact gradient and Hessian.
//!
//! A hinge has the shared edge `x0 → x1` and the opposite vertices `x2` (face A =
//! `(x0, x1, x2)`) and `x3` (face B = `(x1, x0, x3)`), both faces counter-clockwise about
//! their normals. With `e = x1 − x0`, `a = x2 − x0`, `b = x3 − x0` and the area-weighted
//! normals `n_A = e × a`, `n_B = b × e`:
//!
//! `θ = atan2((n_A × n_B) · ê, n_A · n_B)`, in `(−π, π]` (rad).
//!
//! **Sign convention:** `θ = 0` for a flat hinge; `θ > 0` when the wings fold away from
//! the normal side (the surface is convex seen from its normals, like a sphere with outward
//! normals); `θ < 0` when they fold towards it. `atan2` keeps θ accurate near 0 and near
//! ±π; the branch cut at ±π (the two faces on top of each other) is not crossed by
//! physical motions of a shell with positive bending stiffness.
//!
//! **Gradient** (Bridson et al. 2003; Tamstorf & Grinspun 2013), with `L = |e|` and the
//! edge parameters of the feet of the wings `t_A = a·e/L²`, `t_B = b·e/L²`:
//! `∇₂θ = −L n_A/|n_A|²`, `∇₃θ = −L n_B/|n_B|²`,
//! `∇₁θ = −(t_A ∇₂θ + t_B ∇₃θ)`, `∇₀θ = −(∇₁θ + ∇₂θ + ∇₃θ)`.
//! The formula only degenerates for zero-area faces or a zero-length edge.
//!
//! **Hessian:** the exact derivative of these expressions, by the chain rule through
//! `L`, `n_A`, `n_B`, `t_A`, `t_B`, using `d(n/|n|²) = (I − 2 n̂ n̂ᵀ)/|n|² dn` and
//! `d(u × v) = −[v]× du + [u]× dv`. It is symmetrised (it is symmetric analytically).

use crate::vec3::{outer, skew, M3, V3};
use nalgebra::{SMatrix, SMatrixViewMut, SVector};

/// 12-vector: gradient with respect to `[x0, x1, x2, x3]`.
pub type Grad12 = SVector<f64, 12>;
/// 12×12 Hessian with respect to `[x0, x1, x2, x3]`.
pub type Hess12 = SMatrix<f64, 12, 12>;

/// Signed dihedral angle θ (rad) of the hinge `x` = `[x0, x1, x2, x3]`.
#[inline]
pub fn angle(x: &[V3; 4]) -> f64 {
    let e = x[1] - x[0];
    let na = e.cross(&(x[2] - x[0]));
    let nb = (x[3] - x[0]).cross(&e);
    let sin_part = na.cross(&nb).dot(&e) / e.norm();
    sin_part.atan2(na.dot(&nb))
}

/// Quantities shared by the gradient and the Hessian.
struct Frame {
    e: V3,
    a: V3,
    b: V3,
    len: f64,
    e_hat: V3,
    na: V3,
    nb: V3,
    ta: f64,
    tb: f64,
    g: [V3; 4],
}

impl Frame {
    /// θ from the frame's vectors: the very operations of [`angle`], without recomputing them.
    #[inline]
    fn angle(&self) -> f64 {
        let sin_part = self.na.cross(&self.nb).dot(&self.e) / self.len;
        sin_part.atan2(self.na.dot(&self.nb))
    }

    fn new(x: &[V3; 4]) -> Self {
        let e = x[1] - x[0];
        let a = x[2] - x[0];
        let b = x[3] - x[0];
        let len = e.norm();
        let na = e.cross(&a);
        let nb = b.cross(&e);
        let ta = a.dot(&e) / (len * len);
        let tb = b.dot(&e) / (len * len);
        let g2 = -len * na / na.norm_squared();
        let g3 = -len * nb / nb.norm_squared();
        let g1 = -(ta * g2 + tb * g3);
        let g0 = -(g1 + g2 + g3);
        Self {
            e,
            a,
            b,
            len,
            e_hat: e / len,
            na,
            nb,
            ta,
            tb,
            g: [g0, g1, g2, g3],
        }
    }
}

/// θ and its gradient `∂θ/∂x` (rad/m).
pub fn angle_grad(x: &[V3; 4]) -> (f64, Grad12) {
    let f = Frame::new(x);
    let mut g = Grad12::zeros();
    for k in 0..4 {
        g.fixed_rows_mut::<3>(3 * k).copy_from(&f.g[k]);
    }
    (f.angle(), g)
}

/// `d(n/|n|²)/dn = (I − 2 n̂ n̂ᵀ)/|n|²`.
#[inline]
fn inv_sq_jacobian(n: &V3) -> M3 {
    let n2 = n.norm_squared();
    (M3::identity() - outer(n, n) * (2.0 / n2)) / n2
}

/// θ, its gradient and its Hessian `∂²θ/∂x²` (rad/m²).
#[inline]
pub fn angle_grad_hess(x: &[V3; 4]) -> (f64, Grad12, Hess12) {
    let mut h = Hess12::zeros();
    let (theta, g) = angle_grad_hess_into(x, h.as_mut_slice());
    (theta, g, h)
}

/// θ and its gradient, with the Hessian written into `h` (the 144 entries of a [`Hess12`]
/// in nalgebra's column-major order, every one written; no temporaries).
///
/// # Panics
/// If `h` holds fewer than 144 entries.
pub fn angle_grad_hess_into(x: &[V3; 4], h: &mut [f64]) -> (f64, Grad12) {
    let mut h = SMatrixViewMut::<f64, 12, 12>::from_slice(h);
    let f = Frame::new(x);
    let (len, eh) = (f.len, f.e_hat);
    let z = M3::zeros();
    let zv = V3::zeros();
    // ∂L/∂x_k.
    let dl = [-eh, eh, zv, zv];
    // ∂n_A/∂x_k with n_A = e × a, e = x1 − x0, a = x2 − x0.
    let (se, sa, sb) = (skew(&f.e), skew(&f.a), skew(&f.b));
    let dna = [sa - se, -sa, se, z];
    // ∂n_B/∂x_k with n_B = b × e, b = x3 − x0.
    let dnb = [se - sb, sb, z, -se];
    // ∂t/∂x_k with t = c·e/L² (c = a or b).
    let l2 = len * len;
    let dt = |c: &V3, t: f64, k_c: usize| -> [V3; 4] {
        let mut d = [
            -(c + f.e) / l2 + eh * (2.0 * t / len),
            c / l2 - eh * (2.0 * t / len),
            zv,
            zv,
        ];
        d[k_c] += f.e / l2;
        d
    };
    let dta = dt(&f.a, f.ta, 2);
    let dtb = dt(&f.b, f.tb, 3);
    let (pa, pb) = (inv_sq_jacobian(&f.na), inv_sq_jacobian(&f.nb));
    let (ua, ub) = (f.na / f.na.norm_squared(), f.nb / f.nb.norm_squared());
    for k in 0..4 {
        let dg2 = -ua * dl[k].transpose() - pa * dna[k] * len;
        let dg3 = -ub * dl[k].transpose() - pb * dnb[k] * len;
        let dg1 =
            -(f.g[2] * dta[k].transpose() + dg2 * f.ta + f.g[3] * dtb[k].transpose() + dg3 * f.tb);
        let dg0 = -(dg1 + dg2 + dg3);
        for (i, blk) in [dg0, dg1, dg2, dg3].iter().enumerate() {
            h.fixed_view_mut::<3, 3>(3 * i, 3 * k).copy_from(blk);
        }
    }
    // Symmetrise in place.
    for r in 0..12 {
        for c in 0..r {
            let m = 0.5 * (h[(r, c)] + h[(c, r)]);
            h[(r, c)] = m;
            h[(c, r)] = m;
        }
    }
    let mut g = Grad12::zeros();
    for k in 0..4 {
        g.fixed_rows_mut::<3>(3 * k).copy_from(&f.g[k]);
    }
    (f.angle(), g)
}

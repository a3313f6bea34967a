//! Quadratic drag on shell triangles with normal and tangential coefficients, report §II.D.
//!
//! Per triangle with nodes x₀, x₁, x₂ and node velocities v₀, v₁, v₂:
//! - relative velocity `u = (v₀ + v₁ + v₂)/3 − U∞` (m/s);
//! - area vector `N = ½ (x₁ − x₀) × (x₂ − x₀)`, area `A = |N|` (m²), normal `n̂ = N/A`;
//! - `s = n̂·u`, normal part `u_n = s n̂`, tangential part `u_t = u − u_n`;
//! - normal drag `f_n = −½ ρ C_n A |n̂·û| |u_n| u_n = −½ ρ C_n A (s³/|u|_ε) n̂` (N): the
//!   projected area `A |n̂·û|` times the dynamic pressure of the normal flow, a cos³ law in
//!   the angle between flow and normal;
//! - tangential (skin-friction) drag `f_t = −½ ρ C_t A |u_t|_ε u_t` (N);
//! - each node receives `(f_n + f_t)/3`.
//!
//! Writing `f_n = −c_n (N·u)³ N / (A³ |u|_ε)` (`c_n = ½ρC_n`) shows that the force is smooth
//! in `N` and `u` for `A > 0`, including where the flow crosses the triangle's plane (s
//! changes sign). Jacobians are exact: `∂F/∂u` and `∂F/∂N` in closed form (see
//! `docs/aero.md`), then `∂f_a/∂v_b = (1/9) ∂F/∂u` and `∂f_a/∂x_b = (1/3) ∂F/∂N ∂N/∂x_b`.
//! Neither Jacobian is symmetric.

use super::fluid::Fluid;
use super::geometry::{area_vector, area_vector_jacobians, stencil_vec};
use super::regularize::{quadratic, reg_norm, DEFAULT_EPSILON};
use crate::element::{node_stencils, Element, Family};
use crate::force::{BlockMut, EvalInput, JacobianKind};
use crate::vec3::{outer, M3, V3};

/// The triangle-drag law: coefficients, wind and regularisation, shared by all triangles.
#[derive(Debug, Clone, Copy)]
pub struct TriangleDragLaw {
    /// `c_n = ½ ρ C_n` (kg/m³).
    c_n: f64,
    /// `c_t = ½ ρ C_t` (kg/m³).
    c_t: f64,
    wind: V3,
    epsilon: f64,
}

/// Normal + tangential quadratic drag on a family of triangles.
pub type TriangleDrag = Family<TriangleDragLaw>;

/// Drag on one triangle and its derivatives.
struct TriDrag {
    /// Total force `F = f_n + f_t` (N).
    f: V3,
    /// `∂F/∂u` (N·s/m).
    dfdu: M3,
    /// `∂F/∂N` (N/m²).
    dfdn: M3,
}

/// `F(N, u)` and its exact derivatives; zero for a degenerate (zero-area) triangle, which is
/// the continuous limit since `F = O(A)`.
fn triangle_drag(n: &V3, u: &V3, c_n: f64, c_t: f64, eps: f64) -> TriDrag {
    let a2 = n.norm_squared();
    if a2 < f64::MIN_POSITIVE {
        return TriDrag {
            f: V3::zeros(),
            dfdu: M3::zeros(),
            dfdn: M3::zeros(),
        };
    }
    let a = a2.sqrt();
    let id = M3::identity();
    let p = n.dot(u);
    let w = reg_norm(u, eps);
    let nn = outer(n, n);
    let nu = outer(n, u);
    // Normal part: f_n = −c_n p³ N / (A³ w).
    let k3 = c_n / (a2 * a * w);
    let f_n = -k3 * p.powi(3) * n;
    let dfn_du = -k3 * (3.0 * p * p * nn - p.powi(3) / (w * w) * nu);
    let dfn_dn = -k3 * (p.powi(3) * id + 3.0 * p * p * nu - 3.0 * p.powi(3) / a2 * nn);
    // Tangential part: f_t = −c_t A |u_t|_ε u_t, u_t = u − p N / A².
    let ut = u - (p / a2) * n;
    let (g, dg) = quadratic(&ut, eps);
    let proj = id - nn / a2;
    let dut_dn = -(nu + p * id) / a2 + (2.0 * p / (a2 * a2)) * nn;
    let f_t = -c_t * a * g;
    let dft_du = -c_t * a * dg * proj;
    let dft_dn = -c_t * (outer(&g, n) / a + a * dg * dut_dn);
    TriDrag {
        f: f_n + f_t,
        dfdu: dfn_du + dft_du,
        dfdn: dfn_dn + dft_dn,
    }
}

/// Drag on a triangle alone (no derivatives): the force path of [`triangle_drag`], used when
/// the Newton iteration reuses its Jacobian.
fn triangle_drag_force(n: &V3, u: &V3, c_n: f64, c_t: f64, eps: f64) -> V3 {
    let a2 = n.norm_squared();
    if a2 < f64::MIN_POSITIVE {
        return V3::zeros();
    }
    let a = a2.sqrt();
    let p = n.dot(u);
    let w = reg_norm(u, eps);
    let f_n = -(c_n / (a2 * a * w)) * p.powi(3) * n;
    let ut = u - (p / a2) * n;
    f_n - c_t * a * reg_norm(&ut, eps) * ut
}

impl TriangleDrag {
    /// Drag on `triangles` (node triples) with normal and tangential drag coefficients
    /// `cd_normal`, `cd_tangential` and the fluid's density and wind.
    pub fn new(
        triangles: &[[usize; 3]],
        cd_normal: f64,
        cd_tangential: f64,
        fluid: &Fluid,
    ) -> Self {
        let law = TriangleDragLaw {
            c_n: 0.5 * fluid.density * cd_normal,
            c_t: 0.5 * fluid.density * cd_tangential,
            wind: V3::from(fluid.wind),
            epsilon: DEFAULT_EPSILON,
        };
        let data = vec![(); triangles.len()];
        Family::from_elements("triangle-drag", law, node_stencils(triangles), data)
    }

    /// Use the regularisation speed `eps` (m/s) for `|u|` and `|u_t|` instead of
    /// [`DEFAULT_EPSILON`].
    pub fn with_epsilon(mut self, eps: f64) -> Self {
        self.law.epsilon = eps;
        self
    }

    /// Number of triangles.
    pub fn n_triangles(&self) -> usize {
        self.len()
    }

    /// Total drag `f_n + f_t` (N) of every triangle at `(q, v)` into `out` (one entry per
    /// triangle; each of its nodes carries a third). For output, not for the solver.
    pub fn triangle_forces(&self, q: &[f64], v: &[f64], out: &mut [[f64; 3]]) {
        assert_eq!(out.len(), self.n_triangles(), "one output per triangle");
        let l = &self.law;
        for (st, o) in self.stencils.chunks(9).zip(out.iter_mut()) {
            let (_, n, u) = l.kinematics(q, v, st);
            let d = triangle_drag(&n, &u, l.c_n, l.c_t, l.epsilon);
            *o = d.f.into();
        }
    }
}

impl TriangleDragLaw {
    /// Node positions, area vector and relative mean velocity of the triangle `st`.
    #[inline]
    fn kinematics(&self, q: &[f64], v: &[f64], st: &[usize]) -> ([V3; 3], V3, V3) {
        let x = [0, 1, 2].map(|i| stencil_vec(q, st, i));
        let u = (stencil_vec(v, st, 0) + stencil_vec(v, st, 1) + stencil_vec(v, st, 2)) / 3.0
            - self.wind;
        (x, area_vector(&x), u)
    }
}

impl Element for TriangleDragLaw {
    const STENCIL: usize = 9;
    const KIND: JacobianKind = JacobianKind::GENERAL;
    type Data = ();

    fn evaluate(&self, _: &(), st: &[usize], input: &EvalInput<'_>, b: BlockMut<'_>) {
        let (x, n, u) = self.kinematics(input.q, input.v, st);
        if b.dfdq.is_empty() {
            let f = triangle_drag_force(&n, &u, self.c_n, self.c_t, self.epsilon);
            for an in 0..3 {
                for r in 0..3 {
                    b.f[3 * an + r] = f[r] / 3.0;
                }
            }
            return;
        }
        let d = triangle_drag(&n, &u, self.c_n, self.c_t, self.epsilon);
        for an in 0..3 {
            for r in 0..3 {
                b.f[3 * an + r] = d.f[r] / 3.0;
            }
        }
        let dn = area_vector_jacobians(&x);
        let dv = d.dfdu / 9.0;
        for bn in 0..3 {
            let dq = d.dfdn * dn[bn] / 3.0;
            for an in 0..3 {
                for r in 0..3 {
                    for c in 0..3 {
                        let idx = (3 * an + r) * 9 + 3 * bn + c;
                        b.dfdq[idx] = dq[(r, c)];
                        b.dfdv[idx] = dv[(r, c)];
                    }
                }
            }
        }
    }
}

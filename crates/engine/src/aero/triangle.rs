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
//!
//! **Height-dependent fluid.** ρ (and μ) are taken at the triangle's centroid height
//! `z̄ = (z₀ + z₁ + z₂)/3`; the position Jacobian gains `∂F/∂z̄ · ∂z̄/∂z_b` with
//! `∂z̄/∂z_b = 1/3` (for the impermeable law `∂F/∂z̄ = (ρ′/ρ) F`).
//!
//! **Permeable fabric** ([`TriangleDrag::with_fabric`]): the normal pressure
//! `c w²` (`c = ½ ρ C_n |n̂·û|`, `w = |s|`) becomes `c (w − u_p)²` with the leakage speed
//! `u_p` of [`super::permeability`], and `f_n = −sign(s) Δp N`; the tangential part is
//! unchanged. Derivatives follow from [`leakage`]'s partials, with `c = κ w`,
//! `κ = ½ρC_n/|u|_ε`: `∂φ/∂s = Δp_w + κ Δp_c`, `∂φ/∂|u| = −sign(s) Δp_c κ w/|u|` for
//! `φ = sign(s) Δp`, so `∂f_n/∂u = −N (∂φ/∂s n̂ + ∂φ/∂|u| u/|u|)ᵀ`,
//! `∂f_n/∂N = −φ I − ∂φ/∂s N ((u − s n̂)/A)ᵀ`.

use super::fluid::{Fluid, LocalFluid};
use super::geometry::{
    area_vector, area_vector_jacobians, centroid_height, centroid_velocity, corners,
};
use super::permeability::{leakage, Fabric};
use super::regularize::{quadratic, reg_norm, DEFAULT_EPSILON};
use super::wind::{add_shear, LocalWind};
use crate::element::{node_stencils, Element, Family};
use crate::force::{BlockMut, EvalInput, JacobianKind};
use crate::vec3::{outer, M3, V3};

/// The triangle-drag law: coefficients, fluid, regularisation and optional fabric
/// permeability, shared by all triangles.
#[derive(Debug, Clone)]
pub struct TriangleDragLaw {
    /// Normal drag coefficient C_n.
    cd_n: f64,
    /// Tangential drag coefficient C_t.
    cd_t: f64,
    fluid: Fluid,
    epsilon: f64,
    fabric: Option<Fabric>,
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

impl TriDrag {
    fn zero() -> Self {
        Self {
            f: V3::zeros(),
            dfdu: M3::zeros(),
            dfdn: M3::zeros(),
        }
    }
}

/// `F(N, u)` and its exact derivatives; zero for a degenerate (zero-area) triangle, which is
/// the continuous limit since `F = O(A)`.
fn triangle_drag(n: &V3, u: &V3, c_n: f64, c_t: f64, eps: f64) -> TriDrag {
    let a2 = n.norm_squared();
    if a2 < f64::MIN_POSITIVE {
        return TriDrag::zero();
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
    let t = tangential(n, u, c_t, eps);
    TriDrag {
        f: f_n + t.f,
        dfdu: dfn_du + t.dfdu,
        dfdn: dfn_dn + t.dfdn,
    }
}

/// The tangential part `f_t = −c_t A |u_t|_ε u_t`, `u_t = u − p N / A²`, and its
/// derivatives, for `A > 0`.
fn tangential(n: &V3, u: &V3, c_t: f64, eps: f64) -> TriDrag {
    let a2 = n.norm_squared();
    let a = a2.sqrt();
    let id = M3::identity();
    let p = n.dot(u);
    let nn = outer(n, n);
    let nu = outer(n, u);
    let ut = u - (p / a2) * n;
    let (g, dg) = quadratic(&ut, eps);
    let proj = id - nn / a2;
    let dut_dn = -(nu + p * id) / a2 + (2.0 * p / (a2 * a2)) * nn;
    TriDrag {
        f: -c_t * a * g,
        dfdu: -c_t * a * dg * proj,
        dfdn: -c_t * (outer(&g, n) / a + a * dg * dut_dn),
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

/// The normal drag of a permeable triangle, `f_n = −sign(s) Δp N` (see the module docs),
/// with `∂f_n/∂u`, `∂f_n/∂N` (when `jac`) and `∂f_n/∂z̄` through ρ and μ; `A > 0`.
fn permeable_normal(
    n: &V3,
    u: &V3,
    air: &LocalFluid,
    cd_n: f64,
    fabric: &Fabric,
    eps: f64,
    jac: bool,
) -> (TriDrag, V3) {
    let area = n.norm();
    let nh = n / area;
    let s = nh.dot(u);
    let (w, sg) = (s.abs(), if s < 0.0 { -1.0 } else { 1.0 });
    let r = reg_norm(u, eps);
    let kappa = 0.5 * air.density * cd_n / r;
    let (darcy, inertial) = (fabric.darcy(), fabric.inertial());
    let l = leakage(w, kappa * w, air.viscosity * darcy, air.density * inertial);
    let phi = sg * l.pressure;
    let mut d = TriDrag::zero();
    d.f = -phi * n;
    if !jac {
        return (d, V3::zeros());
    }
    let dphi_ds = l.d_w + kappa * l.d_c;
    let dphi_dr = -sg * l.d_c * kappa * w / r;
    d.dfdu = -outer(n, &(dphi_ds * nh + (dphi_dr / r) * u));
    let ds_dn = (u - s * nh) / area;
    d.dfdn = -phi * M3::identity() - dphi_ds * outer(n, &ds_dn);
    // ρ enters c = κ w and b = ρ h C_F/√k; μ enters a = μ h/k.
    let dphi_drho = sg * (l.d_c * 0.5 * cd_n * w / r + l.d_b * inertial);
    let dphi_dmu = sg * l.d_a * darcy;
    let dphi_dz = dphi_drho * air.density_gradient + dphi_dmu * air.viscosity_gradient;
    (d, -dphi_dz * n)
}

impl TriangleDrag {
    /// Drag on `triangles` (node triples) with normal and tangential drag coefficients
    /// `cd_normal`, `cd_tangential` and the fluid's density (at each triangle's centroid
    /// height) and wind.
    pub fn new(
        triangles: &[[usize; 3]],
        cd_normal: f64,
        cd_tangential: f64,
        fluid: &Fluid,
    ) -> Self {
        let law = TriangleDragLaw {
            cd_n: cd_normal,
            cd_t: cd_tangential,
            fluid: fluid.clone(),
            epsilon: DEFAULT_EPSILON,
            fabric: None,
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

    /// Let air leak through the triangles: the normal drag sees only the flow around the
    /// fabric (see the module docs and [`super::permeability`]).
    pub fn with_fabric(mut self, fabric: Fabric) -> Self {
        self.law.fabric = Some(fabric);
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
            let (x, n, u, _) = l.kinematics(q, v, st);
            *o = l.drag(&x, &n, &u, false).0.f.into();
        }
    }
}

impl TriangleDragLaw {
    /// Node positions, area vector, relative mean velocity of the triangle `st` and the wind
    /// at its centroid.
    #[inline]
    fn kinematics(&self, q: &[f64], v: &[f64], st: &[usize]) -> ([V3; 3], V3, V3, LocalWind) {
        let x = corners(q, st);
        let wind = self.fluid.wind_at(centroid_height(&x));
        let u = centroid_velocity(v, st) - V3::from(wind.velocity);
        (x, area_vector(&x), u, wind)
    }

    /// The drag of one triangle in the fluid at its centroid: `F` and, when `jac`, `∂F/∂u`,
    /// `∂F/∂N` and `∂F/∂z̄` (zero in a uniform fluid).
    fn drag(&self, x: &[V3; 3], n: &V3, u: &V3, jac: bool) -> (TriDrag, V3) {
        let air = self.fluid.at(centroid_height(x));
        let c_n = 0.5 * air.density * self.cd_n;
        let c_t = 0.5 * air.density * self.cd_t;
        let eps = self.epsilon;
        let Some(fabric) = &self.fabric else {
            if !jac {
                let mut d = TriDrag::zero();
                d.f = triangle_drag_force(n, u, c_n, c_t, eps);
                return (d, V3::zeros());
            }
            let d = triangle_drag(n, u, c_n, c_t, eps);
            let dz = d.f * (air.density_gradient / air.density);
            return (d, dz);
        };
        if n.norm_squared() < f64::MIN_POSITIVE {
            return (TriDrag::zero(), V3::zeros());
        }
        let (mut d, mut dz) = permeable_normal(n, u, &air, self.cd_n, fabric, eps, jac);
        if !jac {
            let ut = u - (n.dot(u) / n.norm_squared()) * n;
            d.f -= c_t * n.norm() * reg_norm(&ut, eps) * ut;
            return (d, dz);
        }
        let t = tangential(n, u, c_t, eps);
        d.f += t.f;
        d.dfdu += t.dfdu;
        d.dfdn += t.dfdn;
        dz += t.f * (air.density_gradient / air.density);
        (d, dz)
    }
}

impl Element for TriangleDragLaw {
    const STENCIL: usize = 9;
    const KIND: JacobianKind = JacobianKind::GENERAL;
    type Data = ();

    fn evaluate(&self, _: &(), st: &[usize], input: &EvalInput<'_>, mut b: BlockMut<'_>) {
        let (x, n, u, wind) = self.kinematics(input.q, input.v, st);
        let jac = !b.dfdq.is_empty();
        let (d, dz) = self.drag(&x, &n, &u, jac);
        for an in 0..3 {
            for r in 0..3 {
                b.f[3 * an + r] = d.f[r] / 3.0;
            }
        }
        if !jac {
            return;
        }
        let dn = area_vector_jacobians(&x);
        let dv = d.dfdu / 9.0;
        let stratified = !self.fluid.is_uniform();
        for bn in 0..3 {
            let mut dq = d.dfdn * dn[bn] / 3.0;
            if stratified {
                // Each node carries F/3, and z̄ moves by 1/3 of z_b.
                for r in 0..3 {
                    dq[(r, 2)] += dz[r] / 9.0;
                }
            }
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
        add_shear(&mut b, 3, wind.shear);
    }
}

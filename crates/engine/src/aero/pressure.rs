//! Per-node pressure drag on triangles: the DisMech peer code's law, kept as a selectable
//! alternative to [`TriangleDrag`](super::TriangleDrag).
//!
//! For every triangle and each of its nodes i, with that node's relative velocity
//! `u_i = v_i − U∞` (m/s), the triangle's **current** unit normal `n̂ = N/|N|`,
//! `N = ½ (x₁ − x₀) × (x₂ − x₀)`, and its **undeformed** area `A₀` (m²):
//!
//! `f_i = −sign(s_i) ½ ρ C_D (A₀/3) s_i² n̂ = −k |s_i| s_i n̂` (N), `s_i = u_i·n̂`,
//! `k = ½ ρ C_D A₀/3` (kg/m).
//!
//! Only the normal component of the flow acts (no skin friction), with a cos² dependence on
//! the angle between flow and normal (TriangleDrag's normal part is cos³). `|s| s` is C¹, so
//! no regularisation is needed. Exact Jacobians:
//! - `∂f_i/∂v_i = −2k |s_i| n̂ n̂ᵀ` (symmetric; zero between different nodes);
//! - `∂f_i/∂n̂ = −k (|s_i| s_i I + 2 |s_i| n̂ u_iᵀ)`, `∂n̂/∂N = (I − n̂ n̂ᵀ)/|N|`, and
//!   `∂f_i/∂x_b = ∂f_i/∂n̂ ∂n̂/∂N ∂N/∂x_b` (not symmetric).
//!
//! The peer code's own Jacobian for this force is twice the exact derivative; that only slows
//! its Newton iteration, and is not reproduced here.
//!
//! **Height-dependent fluid.** ρ (and μ) are taken at the triangle's centroid height
//! `z̄ = (z₀ + z₁ + z₂)/3`, so every `f_i` gains `∂f_i/∂z_b = ⅓ ∂f_i/∂z̄` (`= ⅓ (ρ′/ρ) f_i`
//! for the impermeable law).
//!
//! **Permeable fabric** ([`PressureDrag::with_fabric`]): the node's normal pressure
//! `c s_i²` (`c = ½ ρ C_D`) becomes `c (|s_i| − u_p)²` with the leakage speed `u_p` of
//! [`super::permeability`]: `f_i = −(A₀/3) φ_i n̂`, `φ_i = sign(s_i) Δp(|s_i|)`, with
//! `∂f_i/∂v_i = −(A₀/3) Δp_w n̂ n̂ᵀ` and `∂f_i/∂n̂ = −(A₀/3) (φ_i I + Δp_w n̂ u_iᵀ)`.

use super::fluid::{Fluid, LocalFluid};
use super::geometry::{area_vector, area_vector_jacobians, centroid_height, corners, stencil_vec};
use super::permeability::{leakage_in, Fabric};
use super::wind::add_shear;
use crate::element::{node_stencils, Element, Family};
use crate::force::{BlockMut, EvalInput, JacobianKind};
use crate::vec3::{node, outer, M3, V3};

/// The pressure-drag law: drag coefficient, fluid and optional fabric permeability; each
/// triangle has its undeformed area `A₀` (m²).
#[derive(Debug, Clone)]
pub struct PressureDragLaw {
    cd: f64,
    fluid: Fluid,
    fabric: Option<Fabric>,
}

/// Per-node normal pressure drag on a family of triangles.
pub type PressureDrag = Family<PressureDragLaw>;

impl PressureDrag {
    /// Pressure drag on `triangles` with undeformed areas taken from `q_rest`, drag
    /// coefficient `cd`, and the fluid's density (at each triangle's centroid height) and
    /// wind.
    pub fn new(triangles: &[[usize; 3]], q_rest: &[f64], cd: f64, fluid: &Fluid) -> Self {
        let areas: Vec<f64> = triangles
            .iter()
            .map(|t| area_vector(&t.map(|i| node(q_rest, i))).norm())
            .collect();
        Self::with_rest_areas(triangles, &areas, cd, fluid)
    }

    /// Pressure drag with explicit undeformed areas `rest_areas` (m², one per triangle).
    pub fn with_rest_areas(
        triangles: &[[usize; 3]],
        rest_areas: &[f64],
        cd: f64,
        fluid: &Fluid,
    ) -> Self {
        assert_eq!(triangles.len(), rest_areas.len(), "one area per triangle");
        let law = PressureDragLaw {
            cd,
            fluid: fluid.clone(),
            fabric: None,
        };
        let data = rest_areas.to_vec();
        Family::from_elements("pressure-drag", law, node_stencils(triangles), data)
    }

    /// Let air leak through the triangles: each node's normal pressure sees only the flow
    /// around the fabric (see the module docs and [`super::permeability`]).
    pub fn with_fabric(mut self, fabric: Fabric) -> Self {
        self.law.fabric = Some(fabric);
        self
    }
}

/// One node's normal pressure term: `φ = sign(s) Δp` (Pa), `∂φ/∂s` (Pa·s/m) and `∂φ/∂z̄`
/// (Pa/m) for the normal speed `s` (m/s).
type NodePressure = (f64, f64, f64);

impl PressureDragLaw {
    /// `φ`, `∂φ/∂s`, `∂φ/∂z̄` of a node with normal speed `s` behind the fabric `fab`, in
    /// the fluid `air` at the centroid.
    #[inline]
    fn pressure(&self, s: f64, air: &LocalFluid, fab: &Fabric) -> NodePressure {
        let c = 0.5 * air.density * self.cd;
        let dc = 0.5 * air.density_gradient * self.cd;
        let (dp, dp_w, dp_z) = leakage_in(s.abs(), c, dc, air, fab);
        let sg = if s < 0.0 { -1.0 } else { 1.0 };
        (sg * dp, dp_w, sg * dp_z)
    }

    /// A node's share of the normal force per unit normal, `A₀/3 · φ` (N), with its
    /// derivatives in `s` and `z̄`, for either law (impermeable: `φ = ½ρC_D |s| s`): the one
    /// formula of the force-only and the Jacobian paths.
    #[inline]
    fn node_force(&self, s: f64, air: &LocalFluid, a0: f64) -> NodePressure {
        let share = a0 / 3.0;
        if let Some(fab) = &self.fabric {
            let (phi, dphi, dz) = self.pressure(s, air, fab);
            return (share * phi, share * dphi, share * dz);
        }
        // k = ½ρC_D A₀/3, evaluated as the impermeable law always was.
        let k = 0.5 * air.density * self.cd * a0 / 3.0;
        let phi = k * s.abs() * s;
        (
            phi,
            2.0 * k * s.abs(),
            phi * (air.density_gradient / air.density),
        )
    }
}

impl Element for PressureDragLaw {
    const STENCIL: usize = 9;
    const KIND: JacobianKind = JacobianKind::GENERAL;
    type Data = f64;

    fn evaluate(&self, &a0: &f64, st: &[usize], input: &EvalInput<'_>, mut b: BlockMut<'_>) {
        let (q, v) = (input.q, input.v);
        let x = corners(q, st);
        let nv = area_vector(&x);
        let a = nv.norm();
        b.dfdq.fill(0.0);
        b.dfdv.fill(0.0);
        let jac = !b.dfdq.is_empty();
        if a < f64::MIN_POSITIVE {
            // A collapsed triangle has no normal; it carries no drag.
            b.f.fill(0.0);
            return;
        }
        let zc = centroid_height(&x);
        let (air, wind) = (self.fluid.at(zc), self.fluid.wind_at(zc));
        let wind_v = V3::from(wind.velocity);
        let stratified = !self.fluid.is_uniform();
        let n = nv / a;
        if !jac {
            // The residual path of modified Newton: the forces alone, none of the Jacobian's
            // terms.
            for i in 0..3 {
                let s = n.dot(&(stencil_vec(v, st, i) - wind_v));
                let (phi, _, _) = self.node_force(s, &air, a0);
                for r in 0..3 {
                    b.f[3 * i + r] = -phi * n[r];
                }
            }
            return;
        }
        let dn_dn = (M3::identity() - outer(&n, &n)) / a;
        let dn = area_vector_jacobians(&x);
        let nn = outer(&n, &n);
        for i in 0..3 {
            let u = stencil_vec(v, st, i) - wind_v;
            let s = n.dot(&u);
            // f = −φ n̂: ∂f/∂v = −φ_s n̂ n̂ᵀ, ∂f/∂n̂ = −(φ I + φ_s n̂ uᵀ), ∂f/∂z̄ = −φ_z n̂.
            let (phi, dphi, dz) = self.node_force(s, &air, a0);
            let f = -phi * n;
            let dv = -dphi * nn;
            let df_dnhat = -(phi * M3::identity() + dphi * outer(&n, &u));
            let dfz = -dz * n;
            for r in 0..3 {
                b.f[3 * i + r] = f[r];
            }
            for r in 0..3 {
                for c in 0..3 {
                    b.dfdv[(3 * i + r) * 9 + 3 * i + c] = dv[(r, c)];
                }
            }
            let df_dnvec = df_dnhat * dn_dn;
            for bn in 0..3 {
                let mut dq = df_dnvec * dn[bn];
                if stratified {
                    for r in 0..3 {
                        dq[(r, 2)] += dfz[r] / 3.0;
                    }
                }
                for r in 0..3 {
                    for c in 0..3 {
                        b.dfdq[(3 * i + r) * 9 + 3 * bn + c] = dq[(r, c)];
                    }
                }
            }
        }
        add_shear(&mut b, 3, wind.shear);
    }
}

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

use super::fluid::Fluid;
use super::geometry::{area_vector, area_vector_jacobians, stencil_vec};
use crate::element::{node_stencils, Element, Family};
use crate::force::{BlockMut, EvalInput, JacobianKind};
use crate::vec3::{node, outer, M3, V3};

/// The pressure-drag law: the wind; each triangle has its `k = ½ ρ C_D A₀/3` (kg/m).
#[derive(Debug, Clone, Copy)]
pub struct PressureDragLaw {
    wind: V3,
}

/// Per-node normal pressure drag on a family of triangles.
pub type PressureDrag = Family<PressureDragLaw>;

impl PressureDrag {
    /// Pressure drag on `triangles` with undeformed areas taken from `q_rest`, drag
    /// coefficient `cd`, and the fluid's density and wind.
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
        let coeff = rest_areas
            .iter()
            .map(|&a| 0.5 * fluid.density * cd * a / 3.0)
            .collect();
        let law = PressureDragLaw {
            wind: V3::from(fluid.wind),
        };
        Family::from_elements("pressure-drag", law, node_stencils(triangles), coeff)
    }
}

impl Element for PressureDragLaw {
    const STENCIL: usize = 9;
    const KIND: JacobianKind = JacobianKind::GENERAL;
    type Data = f64;

    fn evaluate(&self, &k: &f64, st: &[usize], input: &EvalInput<'_>, b: BlockMut<'_>) {
        let (q, v) = (input.q, input.v);
        let x = [0, 1, 2].map(|i| stencil_vec(q, st, i));
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
        let n = nv / a;
        let dn_dn = (M3::identity() - outer(&n, &n)) / a;
        let dn = area_vector_jacobians(&x);
        let nn = outer(&n, &n);
        for i in 0..3 {
            let u = stencil_vec(v, st, i) - self.wind;
            let s = n.dot(&u);
            let f = -k * s.abs() * s * n;
            let dv = -2.0 * k * s.abs() * nn;
            let df_dnhat = -k * (s.abs() * s * M3::identity() + 2.0 * s.abs() * outer(&n, &u));
            let df_dnvec = df_dnhat * dn_dn;
            for r in 0..3 {
                b.f[3 * i + r] = f[r];
            }
            if !jac {
                continue;
            }
            for r in 0..3 {
                for c in 0..3 {
                    b.dfdv[(3 * i + r) * 9 + 3 * i + c] = dv[(r, c)];
                }
            }
            for bn in 0..3 {
                let dq = df_dnvec * dn[bn];
                for r in 0..3 {
                    for c in 0..3 {
                        b.dfdq[(3 * i + r) * 9 + 3 * bn + c] = dq[(r, c)];
                    }
                }
            }
        }
    }
}

//! Linear (low-Reynolds, Stokes-like) drag on nodes.
//!
//! Per node k: `f_k = −c_k (v_k − U∞)` (N) with a drag coefficient `c_k` (N·s/m), and
//! `∂f_k/∂v_k = −c_k I`. For creeping flow past a sphere of radius r, `c = 6π μ r`
//! ([`stokes_sphere`]); for other shapes the caller supplies `c_k`. Valid for Re ≲ 1
//! (see [`DragRegime`](super::DragRegime)).

use super::fluid::Fluid;
use super::wind::add_shear;
use crate::element::{node_stencils, Element, Family};
use crate::force::{BlockMut, EvalInput, JacobianKind};

/// Stokes drag coefficient of a sphere, `c = 6π μ r` (N·s/m), from the dynamic viscosity μ
/// (Pa·s) and the radius r (m).
pub fn stokes_sphere(viscosity: f64, radius: f64) -> f64 {
    6.0 * std::f64::consts::PI * viscosity * radius
}

/// The linear drag law: the wind; each node has its coefficient `c_k` (N·s/m).
#[derive(Debug, Clone)]
pub struct LinearDragLaw {
    fluid: Fluid,
}

/// Linear drag on a set of nodes.
pub type LinearDrag = Family<LinearDragLaw>;

impl LinearDrag {
    /// Drag `−c_k (v_k − U∞)` on `nodes` with coefficients `coeffs` (N·s/m, one per node);
    /// only the fluid's wind is used (the viscosity is already in `c_k`).
    pub fn new(nodes: &[usize], coeffs: &[f64], fluid: &Fluid) -> Self {
        assert_eq!(nodes.len(), coeffs.len(), "one coefficient per node");
        let nodes: Vec<[usize; 1]> = nodes.iter().map(|&i| [i]).collect();
        let law = LinearDragLaw {
            fluid: fluid.clone(),
        };
        Family::from_elements("linear-drag", law, node_stencils(&nodes), coeffs.to_vec())
    }

    /// Total coefficient `Σ c_k` (N·s/m).
    pub fn total_coefficient(&self) -> f64 {
        self.data.iter().sum()
    }
}

impl Element for LinearDragLaw {
    const STENCIL: usize = 3;
    const KIND: JacobianKind = JacobianKind::VISCOUS;
    type Data = f64;

    fn kind(&self) -> JacobianKind {
        if self.fluid.wind_profile.is_uniform() {
            Self::KIND
        } else {
            JacobianKind::GENERAL
        }
    }

    fn evaluate(&self, &c: &f64, st: &[usize], input: &EvalInput<'_>, mut b: BlockMut<'_>) {
        let wind = self.fluid.wind_at(input.q[st[2]]);
        for r in 0..3 {
            b.f[r] = -c * (input.v[st[r]] - wind.velocity[r]);
        }
        if b.dfdv.is_empty() {
            return;
        }
        for r in 0..3 {
            for s in 0..3 {
                b.dfdv[3 * r + s] = if r == s { -c } else { 0.0 };
            }
        }
        if b.dfdq.is_empty() {
            return;
        }
        // Only the wind depends on position, through z.
        b.dfdq.fill(0.0);
        add_shear(&mut b, 1, wind.shear);
    }
}

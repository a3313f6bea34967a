//! Linear (low-Reynolds, Stokes-like) drag on nodes.
//!
//! Per node k: `f_k = −c_k (v_k − U∞)` (N) with a drag coefficient `c_k` (N·s/m), and
//! `∂f_k/∂v_k = −c_k I`. For creeping flow past a sphere of radius r, `c = 6π μ r`
//! ([`stokes_sphere`]); for other shapes the caller supplies `c_k`. Valid for Re ≲ 1
//! (see [`DragRegime`](super::DragRegime)).

use super::fluid::Fluid;
use super::geometry::node_stencils;
use crate::force::{EvalInput, Force, JacobianKind, LocalBlocks};

/// Stokes drag coefficient of a sphere, `c = 6π μ r` (N·s/m), from the dynamic viscosity μ
/// (Pa·s) and the radius r (m).
pub fn stokes_sphere(viscosity: f64, radius: f64) -> f64 {
    6.0 * std::f64::consts::PI * viscosity * radius
}

/// Linear drag on a set of nodes.
#[derive(Debug, Clone)]
pub struct LinearDrag {
    stencils: Vec<usize>,
    /// `c_k` per node (N·s/m).
    coeff: Vec<f64>,
    wind: [f64; 3],
}

impl LinearDrag {
    /// Drag `−c_k (v_k − U∞)` on `nodes` with coefficients `coeffs` (N·s/m, one per node);
    /// only the fluid's wind is used (the viscosity is already in `c_k`).
    pub fn new(nodes: &[usize], coeffs: &[f64], fluid: &Fluid) -> Self {
        assert_eq!(nodes.len(), coeffs.len(), "one coefficient per node");
        Self {
            stencils: node_stencils(nodes),
            coeff: coeffs.to_vec(),
            wind: fluid.wind,
        }
    }

    /// Total coefficient `Σ c_k` (N·s/m).
    pub fn total_coefficient(&self) -> f64 {
        self.coeff.iter().sum()
    }
}

impl Force for LinearDrag {
    fn name(&self) -> &str {
        "linear-drag"
    }
    fn stencil_size(&self) -> usize {
        3
    }
    fn stencils(&self) -> &[usize] {
        &self.stencils
    }
    fn jacobian_kind(&self) -> JacobianKind {
        JacobianKind {
            dq: false,
            dv: true,
            symmetric: true,
        }
    }
    fn evaluate(&self, input: &EvalInput<'_>, out: &mut LocalBlocks) {
        let v = input.v;
        out.par_for_each(input.jacobian, |b| {
            let i = b.index;
            let c = self.coeff[i];
            for r in 0..3 {
                b.f[r] = -c * (v[self.stencils[3 * i + r]] - self.wind[r]);
            }
            if b.dfdv.is_empty() {
                return;
            }
            for r in 0..3 {
                for s in 0..3 {
                    b.dfdv[3 * r + s] = if r == s { -c } else { 0.0 };
                }
            }
        });
    }
}

//! Quadratic (high-Reynolds) drag on rod nodes, report §II.A.
//!
//! Per node k, with the relative velocity `u = v_k − U∞` (m/s):
//!
//! `f_k = −½ ρ C_D A_k |u|_ε u` (N), `∂f_k/∂v_k = −½ ρ C_D A_k (|u|_ε I + u uᵀ/|u|_ε)` (N·s/m).
//!
//! `A_k` (m²) is the node's projected area, for a rod `A_k = 2 r_d l̄_k` with the drag radius
//! `r_d` and the **rest** Voronoi length `l̄_k` (half the sum of the rest lengths of the
//! edges meeting at node k). Because the area is frozen at rest, the force in a uniform fluid
//! does not depend on positions and there is no `∂f/∂x`; a strongly stretched rod therefore under-counts its
//! area by the stretch ratio (negligible for the stiff strips this law is used for).
//! The Jacobian ∂f/∂v is block-diagonal and symmetric negative definite.
//!
//! In a fluid whose density varies with height ([`Fluid::at`]), ρ is taken at the node's
//! own height z_k, and the force gains `∂f_k/∂z_k = (ρ′/ρ) f_k`: the family then declares a
//! (non-symmetric) position Jacobian; in a uniform fluid it has none.

use super::fluid::Fluid;
use super::geometry::stencil_vec;
use super::regularize::{quadratic, DEFAULT_EPSILON};
use super::wind::add_shear;
use crate::element::{node_stencils, Element, Family};
use crate::force::{BlockMut, EvalInput, JacobianKind};
use crate::vec3::V3;

/// The node-drag law: drag coefficient, fluid and regularisation speed; each node has its
/// projected area `A_k` (m²).
#[derive(Debug, Clone)]
pub struct NodeDragLaw {
    cd: f64,
    fluid: Fluid,
    epsilon: f64,
}

/// Quadratic drag on a set of nodes, each with its own area.
pub type NodeDrag = Family<NodeDragLaw>;

impl NodeDrag {
    /// Drag on `nodes` with projected areas `areas` (m², one per node, computed from rest
    /// lengths, e.g. `2 r_d l̄_k`), drag coefficient `cd` and the fluid's density (at each
    /// node's height) and wind.
    pub fn new(nodes: &[usize], areas: &[f64], cd: f64, fluid: &Fluid) -> Self {
        assert_eq!(nodes.len(), areas.len(), "one area per node");
        let nodes: Vec<[usize; 1]> = nodes.iter().map(|&i| [i]).collect();
        let law = NodeDragLaw {
            cd,
            fluid: fluid.clone(),
            epsilon: DEFAULT_EPSILON,
        };
        Family::from_elements("node-drag", law, node_stencils(&nodes), areas.to_vec())
    }

    /// Use the regularisation speed `eps` (m/s) instead of
    /// [`DEFAULT_EPSILON`].
    pub fn with_epsilon(mut self, eps: f64) -> Self {
        self.law.epsilon = eps;
        self
    }
}

impl Element for NodeDragLaw {
    const STENCIL: usize = 3;
    const KIND: JacobianKind = JacobianKind::VISCOUS;
    type Data = f64;

    fn kind(&self) -> JacobianKind {
        if self.fluid.is_uniform() {
            Self::KIND
        } else {
            JacobianKind::GENERAL
        }
    }

    fn evaluate(&self, &area: &f64, st: &[usize], input: &EvalInput<'_>, mut b: BlockMut<'_>) {
        let z = input.q[st[2]];
        let (air, wind) = (self.fluid.at(z), self.fluid.wind_at(z));
        let c = 0.5 * air.density * self.cd * area;
        let u = stencil_vec(input.v, st, 0) - V3::from(wind.velocity);
        let (g, dg) = quadratic(&u, self.epsilon);
        for r in 0..3 {
            b.f[r] = -c * g[r];
        }
        if b.dfdv.is_empty() {
            return;
        }
        for r in 0..3 {
            for s in 0..3 {
                b.dfdv[3 * r + s] = -c * dg[(r, s)];
            }
        }
        if b.dfdq.is_empty() {
            return;
        }
        // Only the density depends on position, through z: column z of ∂f/∂x.
        let dc = 0.5 * air.density_gradient * self.cd * area;
        b.dfdq.fill(0.0);
        for r in 0..3 {
            b.dfdq[3 * r + 2] = -dc * g[r];
        }
        add_shear(&mut b, 1, wind.shear);
    }
}

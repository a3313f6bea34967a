//! External loads: gravity and constant point forces (both a [`ConstantForces`] family),
//! constant generalised forces on single DOFs and a planar end moment. All honour the load
//! scale used by the static solver's load stepping.
use crate::force::{EvalInput, Force, JacobianKind, LocalBlocks};

mod dof_forces;
mod edge_moment;

pub use dof_forces::DofForces;
pub use edge_moment::PlanarEdgeMoment;

/// Constant forces `f_j` (N) on nodes, scaled by the load factor `s`:
/// energy `E = −s Σ f_j · x_j`, force `s f_j`, no Jacobian.
pub struct ConstantForces {
    name: &'static str,
    stencils: Vec<usize>,
    forces: Vec<[f64; 3]>,
    scale: f64,
}

impl ConstantForces {
    /// Force `forces[j]` on node `nodes[j]`, named `name` in diagnostics.
    pub fn new(name: &'static str, nodes: &[usize], forces: &[[f64; 3]]) -> Self {
        assert_eq!(nodes.len(), forces.len());
        Self {
            name,
            stencils: nodes
                .iter()
                .flat_map(|&i| [3 * i, 3 * i + 1, 3 * i + 2])
                .collect(),
            forces: forces.to_vec(),
            scale: 1.0,
        }
    }
    /// Sum of the forces at full scale (N).
    pub fn total(&self) -> [f64; 3] {
        let mut t = [0.0; 3];
        for f in &self.forces {
            for k in 0..3 {
                t[k] += f[k];
            }
        }
        t
    }
}

/// Gravity `f_i = m_i g` on a set of nodes (g in m/s², e.g. `[0, 0, −9.81]`).
pub struct Gravity;

impl Gravity {
    /// Gravity on nodes `nodes` with masses `masses` (kg).
    #[allow(clippy::new_ret_no_self)]
    pub fn new(nodes: &[usize], masses: &[f64], g: [f64; 3]) -> ConstantForces {
        let weights: Vec<[f64; 3]> = masses.iter().map(|&m| g.map(|gk| m * gk)).collect();
        ConstantForces::new("gravity", nodes, &weights)
    }
}

/// Constant point forces (N) on nodes.
pub struct PointForces;

impl PointForces {
    /// Force `forces[j]` on node `nodes[j]`.
    #[allow(clippy::new_ret_no_self)]
    pub fn new(nodes: &[usize], forces: &[[f64; 3]]) -> ConstantForces {
        ConstantForces::new("point-forces", nodes, forces)
    }
}

impl Force for ConstantForces {
    fn name(&self) -> &str {
        self.name
    }
    fn stencil_size(&self) -> usize {
        3
    }
    fn stencils(&self) -> &[usize] {
        &self.stencils
    }
    fn jacobian_kind(&self) -> JacobianKind {
        JacobianKind::CONSTANT
    }
    fn evaluate(&self, _input: &EvalInput<'_>, out: &mut LocalBlocks) {
        for (f, w) in out.f.chunks_mut(3).zip(&self.forces) {
            for k in 0..3 {
                f[k] = self.scale * w[k];
            }
        }
    }
    fn conservative(&self) -> bool {
        true
    }
    fn energy(&self, q: &[f64]) -> Option<f64> {
        let mut e = 0.0;
        for (st, w) in self.stencils.chunks(3).zip(&self.forces) {
            for k in 0..3 {
                e -= self.scale * w[k] * q[st[k]];
            }
        }
        Some(e)
    }
    fn set_load_scale(&mut self, scale: f64) {
        self.scale = scale;
    }
}

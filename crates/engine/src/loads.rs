//! External loads: gravity, constant point forces, constant generalised forces on single
//! DOFs and a planar end moment. All honour the load scale used by the static solver's load
//! stepping.
use crate::force::{EvalInput, Force, JacobianKind, LocalBlocks};

mod dof_forces;
mod edge_moment;

pub use dof_forces::DofForces;
pub use edge_moment::PlanarEdgeMoment;

/// Gravity `f_i = m_i g` on a set of nodes (g in m/s², e.g. `[0, 0, −9.81]`).
pub struct Gravity {
    stencils: Vec<usize>,
    /// Weight vector `m_i g` per stencil (N).
    weights: Vec<[f64; 3]>,
    scale: f64,
}

impl Gravity {
    /// Gravity on nodes `nodes` with masses `masses` (kg).
    pub fn new(nodes: &[usize], masses: &[f64], g: [f64; 3]) -> Self {
        let stencils = nodes
            .iter()
            .flat_map(|&i| [3 * i, 3 * i + 1, 3 * i + 2])
            .collect();
        let weights = masses
            .iter()
            .map(|&m| [m * g[0], m * g[1], m * g[2]])
            .collect();
        Self {
            stencils,
            weights,
            scale: 1.0,
        }
    }
    /// Total weight vector (N) at full scale.
    pub fn total(&self) -> [f64; 3] {
        let mut t = [0.0; 3];
        for w in &self.weights {
            for k in 0..3 {
                t[k] += w[k];
            }
        }
        t
    }
}

impl Force for Gravity {
    fn name(&self) -> &str {
        "gravity"
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
        for (f, w) in out.f.chunks_mut(3).zip(&self.weights) {
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
        for (st, w) in self.stencils.chunks(3).zip(&self.weights) {
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

/// Constant point forces (N) on nodes.
pub struct PointForces {
    stencils: Vec<usize>,
    forces: Vec<[f64; 3]>,
    scale: f64,
}

impl PointForces {
    /// Force `forces[j]` on node `nodes[j]`.
    pub fn new(nodes: &[usize], forces: &[[f64; 3]]) -> Self {
        Self {
            stencils: nodes
                .iter()
                .flat_map(|&i| [3 * i, 3 * i + 1, 3 * i + 2])
                .collect(),
            forces: forces.to_vec(),
            scale: 1.0,
        }
    }
}

impl Force for PointForces {
    fn name(&self) -> &str {
        "point-forces"
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

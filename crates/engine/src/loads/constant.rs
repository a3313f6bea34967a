//! Constant forces on nodes: gravity and point loads.
use crate::element::{node_stencils, Element, Family};
use crate::force::{BlockMut, EvalInput, JacobianKind};

/// The constant-force law: the load scale `s`; each node has its force `f_j` (N).
#[derive(Debug, Clone, Copy)]
pub struct ConstantLoad {
    scale: f64,
}

/// Constant forces `f_j` (N) on nodes, scaled by the load factor `s`:
/// energy `E = −s Σ f_j · x_j`, force `s f_j`, no Jacobian.
pub type ConstantForces = Family<ConstantLoad>;

impl ConstantForces {
    /// Force `forces[j]` on node `nodes[j]`, named `name` in diagnostics.
    pub fn new(name: &str, nodes: &[usize], forces: &[[f64; 3]]) -> Self {
        assert_eq!(nodes.len(), forces.len());
        let nodes: Vec<[usize; 1]> = nodes.iter().map(|&i| [i]).collect();
        let law = ConstantLoad { scale: 1.0 };
        Family::from_elements(name, law, node_stencils(&nodes), forces.to_vec())
    }

    /// Sum of the forces at full scale (N).
    pub fn total(&self) -> [f64; 3] {
        let mut t = [0.0; 3];
        for f in &self.data {
            for k in 0..3 {
                t[k] += f[k];
            }
        }
        t
    }
}

impl Element for ConstantLoad {
    const STENCIL: usize = 3;
    const KIND: JacobianKind = JacobianKind::CONSTANT;
    type Data = [f64; 3];

    fn evaluate(&self, w: &[f64; 3], _: &[usize], _: &EvalInput<'_>, b: BlockMut<'_>) {
        for k in 0..3 {
            b.f[k] = self.scale * w[k];
        }
    }

    fn add_energy(&self, w: &[f64; 3], st: &[usize], q: &[f64], acc: &mut f64) {
        for k in 0..3 {
            *acc -= self.scale * w[k] * q[st[k]];
        }
    }

    fn set_load_scale(&mut self, scale: f64) {
        self.scale = scale;
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

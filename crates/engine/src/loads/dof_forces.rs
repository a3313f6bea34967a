//! Constant generalised forces on single DOFs (a torque on a twist angle, a force on one
//! coordinate), e.g. the end torque of a torsion test.
use crate::element::{Element, Family};
use crate::force::{BlockMut, EvalInput, JacobianKind};

/// The single-DOF load law: the load scale `s`; each DOF has its value (N or N·m).
#[derive(Debug, Clone, Copy)]
pub struct DofLoad {
    scale: f64,
}

/// Constant generalised forces on single DOFs (N or N·m), honouring the load scale:
/// energy `E = −s Σ f_j q_j`.
pub type DofForces = Family<DofLoad>;

impl DofForces {
    /// Force (or torque) `values[j]` (N or N·m) on global DOF `dofs[j]`.
    pub fn new(dofs: Vec<usize>, values: Vec<f64>) -> Self {
        Family::from_elements("dof-forces", DofLoad { scale: 1.0 }, dofs, values)
    }
}

impl Element for DofLoad {
    const STENCIL: usize = 1;
    const KIND: JacobianKind = JacobianKind::CONSTANT;
    type Data = f64;

    fn evaluate(&self, &value: &f64, _: &[usize], _: &EvalInput<'_>, b: BlockMut<'_>) {
        b.f[0] = self.scale * value;
    }

    fn add_energy(&self, &value: &f64, st: &[usize], q: &[f64], acc: &mut f64) {
        *acc -= self.scale * value * q[st[0]];
    }

    fn set_load_scale(&mut self, scale: f64) {
        self.scale = scale;
    }
}

//! Constant generalised forces on single DOFs (a torque on a twist angle, a force on one
//! coordinate), e.g. the end torque of a torsion test.
use crate::force::{EvalInput, Force, JacobianKind, LocalBlocks};

/// Constant generalised forces on single DOFs (N or N·m), honouring the load scale.
pub struct DofForces {
    dofs: Vec<usize>,
    values: Vec<f64>,
    scale: f64,
}

impl DofForces {
    /// Force (or torque) `values[j]` (N or N·m) on global DOF `dofs[j]`.
    pub fn new(dofs: Vec<usize>, values: Vec<f64>) -> Self {
        Self {
            dofs,
            values,
            scale: 1.0,
        }
    }
}

impl Force for DofForces {
    fn name(&self) -> &str {
        "dof-forces"
    }
    fn stencil_size(&self) -> usize {
        1
    }
    fn stencils(&self) -> &[usize] {
        &self.dofs
    }
    fn jacobian_kind(&self) -> JacobianKind {
        JacobianKind::CONSTANT
    }
    fn evaluate(&self, _input: &EvalInput<'_>, out: &mut LocalBlocks) {
        for (f, v) in out.f.iter_mut().zip(&self.values) {
            *f = self.scale * v;
        }
    }
    fn conservative(&self) -> bool {
        true
    }
    fn energy(&self, q: &[f64]) -> Option<f64> {
        Some(
            -self.scale
                * self
                    .dofs
                    .iter()
                    .zip(&self.values)
                    .map(|(&d, v)| v * q[d])
                    .sum::<f64>(),
        )
    }
    fn set_load_scale(&mut self, s: f64) {
        self.scale = s;
    }
}

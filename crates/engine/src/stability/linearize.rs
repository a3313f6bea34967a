//! The equations of motion linearised about a state: `K = ∂F/∂q`, `C = ∂F/∂v` and the lumped
//! masses on the free DOFs, in the step solver's sparse pattern.

use faer::sparse::linalg::solvers::{Lu, SymbolicLu};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};

use super::StabilityError;
use crate::assembly::{Assembler, Coefficients};
use crate::force::EvalInput;
use crate::model::Model;

/// `K`, `C` and `M` of a model at one state, on its free DOFs (compressed sparse columns,
/// one pattern for both Jacobians: every stencil couples all its DOFs).
pub struct Linearized {
    /// Free DOFs (the size of `K`, `C`, `M`).
    pub n_free: usize,
    /// `dof_of[r]`: the model DOF of row (and column) `r`.
    pub dof_of: Vec<usize>,
    /// Column pointers of the pattern.
    pub col_ptr: Vec<usize>,
    /// Row indices of the pattern (sorted within each column).
    pub row_idx: Vec<usize>,
    /// Position of each column's diagonal entry in the values.
    pub diag: Vec<usize>,
    /// Values of `K = ∂F/∂q` (N/m).
    pub k: Vec<f64>,
    /// Values of `C = ∂F/∂v` (N·s/m).
    pub c: Vec<f64>,
    /// Lumped masses of the free DOFs (kg).
    pub mass: Vec<f64>,
    /// The force at the state, every DOF of the model (N).
    pub force: Vec<f64>,
    /// DOFs of the model.
    pub n_dofs: usize,
    /// Translational DOFs of the model (`3 ×` nodes; they come first).
    pub n_translational: usize,
    /// The assembler, kept for [`Linearized::update`] (its pattern and AMD order are built
    /// once).
    asm: Assembler,
}

impl Linearized {
    /// The linearisation of `model` at positions `q`, velocities `v` and time `t`.
    pub fn at(model: &Model, q: &[f64], v: &[f64], t: f64) -> Self {
        let asm = Assembler::new(model);
        let mut lin = Self {
            n_free: asm.n_free,
            dof_of: asm.dof_of.clone(),
            col_ptr: asm.col_ptr.clone(),
            row_idx: asm.row_idx.clone(),
            diag: asm.diag.clone(),
            k: vec![0.0; asm.nnz()],
            c: vec![0.0; asm.nnz()],
            mass: asm.dof_of.iter().map(|&d| model.mass[d]).collect(),
            force: vec![0.0; model.n_dofs()],
            n_dofs: model.n_dofs(),
            n_translational: 3 * model.layout.n_nodes,
            asm,
        };
        lin.update(model, q, v, t);
        lin
    }

    /// The same model linearised at another state, in place (no new pattern, no allocation).
    pub fn update(&mut self, model: &Model, q: &[f64], v: &[f64], t: f64) {
        let input = EvalInput::outside_step(q, v, t, true);
        // J = c_m M − c_q K − c_v C (crate::assembly): K alone, then C alone.
        let only_k = Coefficients {
            c_m: 0.0,
            c_q: -1.0,
            c_v: 0.0,
        };
        let only_c = Coefficients {
            c_m: 0.0,
            c_q: 0.0,
            c_v: -1.0,
        };
        let asm = &mut self.asm;
        asm.assemble(model, &input, &mut self.force, Some((&mut self.k, only_k)));
        asm.assemble(model, &input, &mut self.force, Some((&mut self.c, only_c)));
    }

    /// The pattern as faer's symbolic matrix.
    pub fn pattern(&self) -> SymbolicSparseColMatRef<'_, usize> {
        SymbolicSparseColMatRef::new_checked(
            self.n_free,
            self.n_free,
            &self.col_ptr,
            None,
            &self.row_idx,
        )
    }

    /// Values of `P(σ) = σ² M − σ C − K` on the pattern.
    pub fn pencil(&self, sigma: f64) -> Vec<f64> {
        let mut p: Vec<f64> = self
            .k
            .iter()
            .zip(&self.c)
            .map(|(k, c)| -sigma * c - k)
            .collect();
        for (col, &d) in self.diag.iter().enumerate() {
            p[d] += sigma * sigma * self.mass[col];
        }
        p
    }

    /// `out = A x` for the values `a` on the pattern.
    pub fn mul(&self, a: &[f64], x: &[f64], out: &mut [f64]) {
        out.fill(0.0);
        for (col, &xc) in x.iter().enumerate() {
            for k in self.col_ptr[col]..self.col_ptr[col + 1] {
                out[self.row_idx[k]] += a[k] * xc;
            }
        }
    }

    /// The sparse LU factors of `values` on the pattern.
    pub fn lu(&self, values: &[f64]) -> Result<Lu<usize, f64>, StabilityError> {
        let symbolic = SymbolicLu::try_new(self.pattern())
            .map_err(|e| StabilityError::Singular(e.to_string()))?;
        let mat = SparseColMatRef::new(self.pattern(), values);
        Lu::try_new_with_symbolic(symbolic, mat)
            .map_err(|e| StabilityError::Singular(format!("{e:?}")))
    }
}

//! The equations of motion linearised about a state: `K = ∂F/∂q`, `C = ∂F/∂v` and the lumped
//! masses on the free DOFs, in the step solver's sparse pattern, plus the low-rank part of
//! forces that hold quantities standing for a function of the state
//! ([`Force::lag_coupling`](crate::force::Force::lag_coupling)), applied by
//! Sherman–Morrison–Woodbury.

use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::{Lu, SymbolicLu};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Col, Mat};

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
    /// The low-rank part `ΔK = Σ u_j wq_jᵀ`, `ΔC = Σ u_j wv_jᵀ` on the free DOFs (empty
    /// unless a force has a [`LagCoupling`](crate::force::LagCoupling) and it was asked for).
    pub coupling: Vec<Coupling>,
    /// Whether [`Linearized::update`] computes [`Linearized::coupling`].
    with_coupling: bool,
    /// The assembler, kept for [`Linearized::update`] (its pattern and AMD order are built
    /// once).
    asm: Assembler,
}

/// One term of the low-rank part, on the free DOFs.
#[derive(Debug, Clone, PartialEq)]
pub struct Coupling {
    /// `u_j` (N per unit of the held quantity).
    pub u: Vec<f64>,
    /// `∂h_j/∂q`.
    pub wq: Vec<f64>,
    /// `∂h_j/∂v`.
    pub wv: Vec<f64>,
}

/// `P(σ)⁻¹` with the low-rank part: `(P₀ − U Zᵀ)⁻¹ b = y + Y S⁻¹ Zᵀ y`, `y = P₀⁻¹ b`,
/// `Y = P₀⁻¹ U`, `S = I − Zᵀ Y`, `Z_j = σ wv_j + wq_j`.
pub struct PencilSolver {
    lu: Lu<usize, f64>,
    y: Mat<f64>,
    z: Mat<f64>,
    s: Option<faer::linalg::solvers::PartialPivLu<f64>>,
}

impl PencilSolver {
    /// Overwrite `b` with `P(σ)⁻¹ b`.
    pub fn solve_in_place(&self, b: &mut Col<f64>) {
        self.lu.solve_in_place(b.as_mat_mut());
        let Some(s) = &self.s else {
            return;
        };
        let mut c = self.z.transpose() * &*b;
        s.solve_in_place(c.as_mat_mut());
        *b += &self.y * &c;
    }
}

impl Linearized {
    /// The linearisation of `model` at positions `q`, velocities `v` and time `t`, with the
    /// forces' held quantities taken as functions of the state ([`Linearized::coupling`]).
    pub fn at(model: &Model, q: &[f64], v: &[f64], t: f64) -> Self {
        Self::build(model, q, v, t, true)
    }

    /// The forces' own Jacobians alone, the held quantities fixed (a Newton matrix).
    pub fn jacobians_at(model: &Model, q: &[f64], v: &[f64], t: f64) -> Self {
        Self::build(model, q, v, t, false)
    }

    fn build(model: &Model, q: &[f64], v: &[f64], t: f64, with_coupling: bool) -> Self {
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
            coupling: Vec::new(),
            with_coupling,
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
        if self.with_coupling {
            self.coupling = self.couplings(model, q, v);
        }
    }

    /// The forces' couplings through held quantities, on the free DOFs.
    fn couplings(&self, model: &Model, q: &[f64], v: &[f64]) -> Vec<Coupling> {
        let mut row = vec![usize::MAX; self.n_dofs];
        for (r, &d) in self.dof_of.iter().enumerate() {
            row[d] = r;
        }
        let mut out = Vec::new();
        for c in model.forces.iter().filter_map(|f| f.lag_coupling(q, v)) {
            let spread = |x: &[f64]| {
                let mut y = vec![0.0; self.n_free];
                for (&d, xi) in c.dofs.iter().zip(x) {
                    if row[d] != usize::MAX {
                        y[row[d]] = *xi;
                    }
                }
                y
            };
            for j in 0..c.u.len() {
                out.push(Coupling {
                    u: spread(&c.u[j]),
                    wq: spread(&c.wq[j]),
                    wv: spread(&c.wv[j]),
                });
            }
        }
        out
    }

    /// `out = K x` with the low-rank part.
    pub fn mul_k(&self, x: &[f64], out: &mut [f64]) {
        self.mul(&self.k, x, out);
        self.add_coupling(x, out, |c| &c.wq);
    }

    /// `out = C x` with the low-rank part.
    pub fn mul_c(&self, x: &[f64], out: &mut [f64]) {
        self.mul(&self.c, x, out);
        self.add_coupling(x, out, |c| &c.wv);
    }

    fn add_coupling(&self, x: &[f64], out: &mut [f64], w: impl Fn(&Coupling) -> &Vec<f64>) {
        for c in &self.coupling {
            let s: f64 = w(c).iter().zip(x).map(|(a, b)| a * b).sum();
            out.iter_mut().zip(&c.u).for_each(|(o, u)| *o += u * s);
        }
    }

    /// `P(σ)⁻¹` with the low-rank part (one sparse LU).
    pub fn pencil_solver(&self, sigma: f64) -> Result<PencilSolver, StabilityError> {
        let lu = self.lu(&self.pencil(sigma))?;
        let (n, r) = (self.n_free, self.coupling.len());
        if r == 0 {
            let empty = Mat::zeros(0, 0);
            return Ok(PencilSolver {
                lu,
                y: empty.clone(),
                z: empty,
                s: None,
            });
        }
        // P = P₀ − U Zᵀ: ΔP = −σ ΔC − ΔK.
        let mut y = Mat::from_fn(n, r, |i, j| self.coupling[j].u[i]);
        lu.solve_in_place(y.as_mut());
        let z = Mat::from_fn(n, r, |i, j| {
            sigma * self.coupling[j].wv[i] + self.coupling[j].wq[i]
        });
        let s = Mat::<f64>::identity(r, r) - z.transpose() * &y;
        Ok(PencilSolver {
            lu,
            y,
            z,
            s: Some(s.partial_piv_lu()),
        })
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

//! Newton–Raphson with a backtracking line search on the residual
//! `R(q) = c_m M (q − q̃) − F(q, c_v (q − q_n))` over the free DOFs.
//!
//! Implicit Euler uses `c_m = 1/dt²`, `q̃ = q_n + dt v_n`, `c_v = 1/dt`; statics uses
//! `c_m = c_v = 0`. The Jacobian is `J = c_m M − ∂F/∂q − c_v ∂F/∂v`.
//!
//! Convergence: `‖R‖∞ ≤ force_tol_abs + force_tol_rel · ‖R₀‖∞` (R₀ the residual at the
//! first iterate), or a Newton update with `‖Δq‖∞ ≤ step_tol` while `‖R‖∞` is within
//! `1e3 ×` the force tolerance (so a stalled iteration is not mistaken for convergence).

use crate::assembly::{Assembler, Coefficients};
use crate::error::{EngineError, StepError};
use crate::force::EvalInput;
use crate::linsolve::{Factorization, LinearSolver};
use crate::model::Model;

/// Newton–Raphson settings.
#[derive(Debug, Clone, Copy)]
pub struct NewtonOptions {
    /// Maximum Newton iterations per solve.
    pub max_iterations: usize,
    /// Absolute force tolerance on `‖R‖∞` (N). `None`: `1e-9 × (1 + Σm · 9.81)`.
    pub force_tol_abs: Option<f64>,
    /// Tolerance relative to the first residual.
    pub force_tol_rel: f64,
    /// Step-size tolerance on `‖Δq‖∞` (m or rad).
    pub step_tol: f64,
    /// Backtracking line search on `‖R‖₂`.
    pub line_search: bool,
    /// Maximum number of step halvings in the line search.
    pub max_backtracks: usize,
}

impl Default for NewtonOptions {
    fn default() -> Self {
        Self {
            max_iterations: 25,
            force_tol_abs: None,
            force_tol_rel: 1e-10,
            step_tol: 1e-12,
            line_search: true,
            max_backtracks: 8,
        }
    }
}

/// What one solve did.
#[derive(Debug, Clone, Copy, Default)]
pub struct StepReport {
    /// Newton iterations (linear solves) taken.
    pub iterations: usize,
    /// Final `‖R‖∞` (N).
    pub residual: f64,
    /// Line-search halvings, summed over iterations.
    pub backtracks: usize,
    /// Whether the last linear solve used Cholesky.
    pub used_cholesky: bool,
}

/// Shared Newton machinery and all its preallocated buffers.
pub(crate) struct NewtonCore {
    pub assembler: Assembler,
    solver: LinearSolver,
    pub opts: NewtonOptions,
    force_tol_abs: f64,
    values: Vec<f64>,
    force: Vec<f64>,
    residual: Vec<f64>,
    delta: Vec<f64>,
    q_trial: Vec<f64>,
    v: Vec<f64>,
    /// `‖R‖∞` of every iterate of the last solve, the starting guess first (diagnostics:
    /// convergence-order tests). Capacity `max_iterations + 1` is reserved up front, so
    /// recording never allocates.
    pub history: Vec<f64>,
}

/// The target of one Newton solve.
pub(crate) struct Target<'a> {
    pub c_m: f64,
    pub c_v: f64,
    pub q_tilde: &'a [f64],
    pub q_n: &'a [f64],
    pub t: f64,
}

impl NewtonCore {
    pub fn new(model: &Model, opts: NewtonOptions) -> Result<Self, EngineError> {
        let assembler = Assembler::new(model);
        let solver = LinearSolver::new(
            assembler.n_free,
            &assembler.col_ptr,
            &assembler.row_idx,
            assembler.symmetric,
        )?;
        let n = model.n_dofs();
        let force_tol_abs = opts
            .force_tol_abs
            .unwrap_or(1e-9 * (1.0 + model.total_mass() * 9.81));
        Ok(Self {
            values: vec![0.0; assembler.nnz()],
            force: vec![0.0; n],
            residual: vec![0.0; assembler.n_free],
            delta: vec![0.0; assembler.n_free],
            q_trial: vec![0.0; n],
            v: vec![0.0; n],
            history: Vec::with_capacity(opts.max_iterations + 1),
            assembler,
            solver,
            opts,
            force_tol_abs,
        })
    }

    /// Evaluate the residual at `q` into `self.residual`; return `‖R‖₂` and fill the
    /// Jacobian values when `with_jacobian`.
    fn residual_at(&mut self, model: &Model, q: &[f64], tg: &Target<'_>, jac: bool) -> f64 {
        for d in 0..q.len() {
            self.v[d] = tg.c_v * (q[d] - tg.q_n[d]);
        }
        let input = EvalInput {
            q,
            v: &self.v,
            t: tg.t,
        };
        let coeffs = Coefficients {
            c_m: tg.c_m,
            c_q: 1.0,
            c_v: tg.c_v,
        };
        let values = if jac {
            Some((&mut self.values[..], coeffs))
        } else {
            None
        };
        self.assembler
            .assemble(model, &input, &mut self.force, values);
        let mut norm2 = 0.0;
        for (r, &d) in self.assembler.dof_of.iter().enumerate() {
            let x = tg.c_m * model.mass[d] * (q[d] - tg.q_tilde[d]) - self.force[d];
            self.residual[r] = x;
            norm2 += x * x;
        }
        norm2.sqrt()
    }

    fn inf_norm(&self) -> (f64, usize) {
        let mut worst = (0.0, 0);
        for (r, &x) in self.residual.iter().enumerate() {
            // NaN compares false, so a NaN residual is always reported as the worst.
            if x.is_nan() || x.abs() > worst.0 {
                worst = (x.abs(), self.assembler.dof_of[r]);
            }
        }
        worst
    }

    /// Solve `R(q) = 0` starting from `q` (overwritten with the solution on success; left
    /// at an unspecified iterate on failure).
    pub fn solve(
        &mut self,
        model: &Model,
        q: &mut [f64],
        tg: &Target<'_>,
    ) -> Result<StepReport, StepError> {
        let mut report = StepReport::default();
        self.history.clear();
        let mut norm = self.residual_at(model, q, tg, true);
        let (r0, _) = self.inf_norm();
        let tol = self.force_tol_abs + self.opts.force_tol_rel * r0;
        loop {
            let (rinf, worst) = self.inf_norm();
            if !rinf.is_finite() {
                return Err(StepError::NonFinite {
                    what: "residual",
                    dof: worst,
                });
            }
            report.residual = rinf;
            self.history.push(rinf);
            if rinf <= tol {
                return Ok(report);
            }
            if report.iterations >= self.opts.max_iterations {
                return Err(StepError::NotConverged {
                    iterations: report.iterations,
                    residual: rinf,
                    tolerance: tol,
                    worst_dof: worst,
                });
            }
            for (d, r) in self.delta.iter_mut().zip(&self.residual) {
                *d = -r;
            }
            let fac = self.solver.solve(&self.values, &mut self.delta)?;
            report.used_cholesky = fac == Factorization::Llt;
            report.iterations += 1;
            let mut dmax = 0.0f64;
            for (r, &d) in self.delta.iter().enumerate() {
                if !d.is_finite() {
                    return Err(StepError::NonFinite {
                        what: "Newton update",
                        dof: self.assembler.dof_of[r],
                    });
                }
                dmax = dmax.max(d.abs());
            }
            let mut alpha = 1.0;
            let mut cuts = 0;
            // Trials are evaluated with the Jacobian: the first one is almost always accepted,
            // and then it is the next iteration's matrix.
            let trial = loop {
                self.q_trial.copy_from_slice(q);
                for (r, &d) in self.assembler.dof_of.iter().enumerate() {
                    self.q_trial[d] += alpha * self.delta[r];
                }
                let qt = std::mem::take(&mut self.q_trial);
                let trial = self.residual_at(model, &qt, tg, true);
                self.q_trial = qt;
                let accept = !self.opts.line_search
                    || (trial.is_finite() && trial <= (1.0 - 1e-4 * alpha) * norm)
                    || cuts >= self.opts.max_backtracks;
                if accept {
                    break trial;
                }
                alpha *= 0.5;
                cuts += 1;
            };
            report.backtracks += cuts;
            q.copy_from_slice(&self.q_trial);
            norm = trial;
            let (rinf, _) = self.inf_norm();
            if alpha * dmax <= self.opts.step_tol && rinf <= 1e3 * tol {
                report.residual = rinf;
                self.history.push(rinf);
                return Ok(report);
            }
        }
    }
}

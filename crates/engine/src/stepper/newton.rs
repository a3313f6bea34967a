//! Newton–Raphson with a backtracking line search on the residual
//! `R(q) = c_m M (q − q̃) − F(q, c_v (q − q_n))` over the free DOFs.
//!
//! Implicit Euler uses `c_m = 1/dt²`, `q̃ = q_n + dt v_n`, `c_v = 1/dt`; statics uses
//! `c_m = c_v = 0`. The Jacobian is `J = c_m M − ∂F/∂q − c_v ∂F/∂v`.
//!
//! Convergence: `‖R‖∞ ≤ force_tol_abs + force_tol_rel · ‖R₀‖∞` (R₀ the residual at the
//! first iterate), or a Newton update with `‖Δq‖∞ ≤ step_tol` while `‖R‖∞` is within
//! `1e3 ×` the force tolerance (so a stalled iteration is not mistaken for convergence), or
//! (time steps, `accuracy_fraction > 0`) the accuracy-based test of
//! [`NewtonOptions::accuracy_fraction`]: the residual left moves the state by at most a
//! fraction of backward Euler's local error.
//!
//! A failed solve on the reused or approximate path is retried once with exact Newton
//! ([`NewtonOptions::exact_retry`]) before the error reaches the caller.

use crate::assembly::{Assembler, Coefficients};
use crate::error::{EngineError, StepError};
use crate::force::EvalInput;
use crate::linsolve::{Factorization, LinearSolver};
use crate::model::Model;
use crate::stepper::options::{NewtonOptions, StepReport, Timings};
use crate::stepper::retry_ledger::RetryLedger;
use crate::stepper::start_policy::{StartPolicy, FACTOR_WORK};
use std::time::Instant;

mod continuation;
mod direction;
mod filter;
mod homotopy;
mod retry;
mod tolerance;
use tolerance::Verdict;

/// Largest `‖(J − J_s) Δ‖∞ / ‖R‖∞` accepted from the symmetric approximation `J_s`: the
/// iteration then contracts at least ~10× per step where exact Newton would converge
/// quadratically (3–4 extra iterations from 1 N to 1e-9 N at worst); above it, the updates
/// are corrected by preconditioned BiCGStab.
const SKEW_LIMIT: f64 = 0.1;

/// Shared Newton machinery and all its preallocated buffers.
pub(crate) struct NewtonCore {
    pub assembler: Assembler,
    pub(crate) solver: LinearSolver,
    pub opts: NewtonOptions,
    force_tol_abs: f64,
    values: Vec<f64>,
    /// `½ (J + Jᵀ)` for the symmetric approximation (empty when unused).
    sym_values: Vec<f64>,
    /// `(J − J_s) Δ` (free DOFs; empty when the approximation is unused).
    skew_product: Vec<f64>,
    force: Vec<f64>,
    residual: Vec<f64>,
    delta: Vec<f64>,
    q_trial: Vec<f64>,
    /// Iterate before an update with a reused factorisation (restored if it is rejected).
    q_prev: Vec<f64>,
    v: Vec<f64>,
    /// `(c_m, c_v)` of the held factorisation (reuse is only valid for the same pair).
    factored_for: (f64, f64),
    /// `‖R‖∞` after each iteration of the last solve (capacity reserved up front).
    pub history: Vec<f64>,
    /// Every force has an energy (and none depends on velocity): Φ is a valid merit.
    conservative: bool,
    /// Accumulated phase timings and counts.
    pub timings: Timings,
    /// The held factorisation is of the symmetric approximation `½ (J + Jᵀ)`.
    approx_held: bool,
    /// This solve corrects every update of the symmetric approximation by BiCGStab (its
    /// linearised residual was too large).
    corrected: bool,
    /// A correction failed in this solve: no more are attempted.
    krylov_off: bool,
    /// Stale or fresh start of the next solve (modified Newton).
    pub start: StartPolicy,
    /// Factorisations of failed and successful solves: whether a failure may be retried.
    pub ledger: RetryLedger,
    /// `−R` for the Krylov correction (empty when the approximation is unused).
    neg_residual: Vec<f64>,
    /// The approximate update `J_s⁻¹ (−R)`, kept in case the Krylov correction fails.
    delta_approx: Vec<f64>,
    /// `1 / m` per free DOF (the accuracy-based test).
    inv_mass: Vec<f64>,
    /// This solve is an exact retry (fresh Jacobian every iteration, updates of the
    /// symmetric approximation corrected into exact Newton updates), with the line search
    /// or without.
    exact: Option<bool>,
    /// This solve is the exact retry's pseudo-transient continuation (its own budget).
    continuing: bool,
    /// This stage of an exact retry factorises `J` by LU instead of correcting the symmetric
    /// approximation's updates by BiCGStab.
    retry_lu: bool,
    /// The step homotopy's sub-step `q̃` and last solution (all DOFs).
    homotopy_q_tilde: Vec<f64>,
    homotopy_done: Vec<f64>,
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
        let approx = opts.symmetric_approx && !assembler.symmetric;
        let new_solver = if assembler.ordered {
            LinearSolver::new_ordered
        } else {
            LinearSolver::new
        };
        let solver = new_solver(
            assembler.n_free,
            &assembler.col_ptr,
            &assembler.row_idx,
            assembler.symmetric || approx,
        )?;
        let n = model.n_dofs();
        let force_tol_abs = opts
            .force_tol_abs
            .unwrap_or(1e-9 * (1.0 + model.total_mass() * opts.reference_acceleration));
        Ok(Self {
            values: vec![0.0; assembler.nnz()],
            sym_values: if approx {
                vec![0.0; assembler.nnz()]
            } else {
                Vec::new()
            },
            skew_product: if approx {
                vec![0.0; assembler.n_free]
            } else {
                Vec::new()
            },
            neg_residual: if approx {
                vec![0.0; assembler.n_free]
            } else {
                Vec::new()
            },
            delta_approx: if approx {
                vec![0.0; assembler.n_free]
            } else {
                Vec::new()
            },
            inv_mass: assembler
                .dof_of
                .iter()
                .map(|&d| 1.0 / model.mass[d])
                .collect(),
            exact: None,
            continuing: false,
            retry_lu: false,
            homotopy_q_tilde: vec![0.0; n],
            homotopy_done: vec![0.0; n],
            force: vec![0.0; n],
            residual: vec![0.0; assembler.n_free],
            delta: vec![0.0; assembler.n_free],
            q_trial: vec![0.0; n],
            q_prev: vec![0.0; n],
            v: vec![0.0; n],
            assembler,
            solver,
            opts,
            force_tol_abs,
            factored_for: (f64::NAN, f64::NAN),
            conservative: model.forces.iter().all(|f| f.conservative()),
            history: Vec::with_capacity(2 * opts.max_iterations + 1),
            timings: Timings::default(),
            approx_held: false,
            corrected: false,
            krylov_off: false,
            start: StartPolicy::default(),
            ledger: RetryLedger::default(),
        })
    }

    /// Evaluate the residual at `q` into `self.residual` (and the Jacobian values when
    /// `jac`); return `‖R‖₂`.
    fn residual_at(&mut self, model: &Model, q: &[f64], tg: &Target<'_>, jac: bool) -> f64 {
        for d in 0..q.len() {
            self.v[d] = tg.c_v * (q[d] - tg.q_n[d]);
        }
        let input = EvalInput {
            q,
            v: &self.v,
            t: tg.t,
            jacobian: jac,
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
        let t0 = Instant::now();
        self.assembler
            .assemble(model, &input, &mut self.force, values);
        self.timings.assembly_s += t0.elapsed().as_secs_f64();
        self.timings.evaluations += 1;
        self.timings.jacobian_evaluations += u64::from(jac);
        let mut norm2 = 0.0;
        for (r, &d) in self.assembler.dof_of.iter().enumerate() {
            let x = tg.c_m * model.mass[d] * (q[d] - tg.q_tilde[d]) - self.force[d];
            self.residual[r] = x;
            norm2 += x * x;
        }
        norm2.sqrt()
    }

    /// Whether the held factorisation may be used for this target.
    fn can_reuse(&self, tg: &Target<'_>) -> bool {
        self.opts.reuse_jacobian
            && self.solver.has_factors()
            && self.factored_for == (tg.c_m, tg.c_v)
    }

    /// Iterations allowed in this solve: an exact retry has twice the budget (it replaces a
    /// halving of `dt`, which costs two solves), its continuation stage four times.
    fn budget(&self) -> usize {
        if self.continuing {
            4 * self.opts.max_iterations
        } else if self.exact.is_some() {
            2 * self.opts.max_iterations
        } else {
            self.opts.max_iterations
        }
    }

    /// Modified Newton is on for this solve (off in an exact retry).
    fn reusing(&self) -> bool {
        self.opts.reuse_jacobian && self.exact.is_none()
    }

    /// Solve `R(q) = 0` starting from `q` (overwritten with the solution on success; left
    /// at an unspecified iterate on failure). With `reuse_jacobian`, whether to start from
    /// the held factors is decided by the measured [`StartPolicy`].
    pub fn solve(
        &mut self,
        model: &Model,
        q: &mut [f64],
        tg: &Target<'_>,
    ) -> Result<StepReport, StepError> {
        let choice = self.can_reuse(tg);
        let fresh = !choice || self.start.fresh_next();
        let (e0, f0) = (self.timings.evaluations, self.timings.factorizations);
        let retry = self.opts.exact_retry && !self.is_exact_path();
        let mut res = self.solve_from(model, q, tg, fresh);
        if retry && res.is_err() {
            if self.ledger.allows_retry() {
                res = self.exact_retry(model, q, tg);
            } else {
                self.timings.exact_retries_skipped += 1;
            }
        }
        let facts = self.timings.factorizations - f0;
        self.ledger.record(res.is_ok(), facts);
        // Recorded after the retry: a stale start that fails is charged the retry it caused.
        if choice {
            let evals = (self.timings.evaluations - e0) as f64;
            self.start.record(fresh, evals + FACTOR_WORK * facts as f64);
        }
        res
    }

    /// Whether every solve already is exact Newton with a line search (a retry would repeat
    /// it).
    fn is_exact_path(&self) -> bool {
        !self.opts.reuse_jacobian && self.sym_values.is_empty() && self.opts.line_search
    }

    pub(super) fn solve_from(
        &mut self,
        model: &Model,
        q: &mut [f64],
        tg: &Target<'_>,
        fresh_start: bool,
    ) -> Result<StepReport, StepError> {
        let mut report = StepReport::default();
        self.history.clear();
        self.timings.solves += 1;
        // An exact retry corrects every update of the symmetric approximation.
        self.corrected = self.exact.is_some();
        self.krylov_off = false;
        let mut fresh = fresh_start;
        let mut norm = self.residual_at(model, q, tg, fresh);
        let (r0, _) = self.inf_norm();
        let tol =
            self.force_tol_abs + self.opts.force_tol_rel * r0 + self.roundoff_floor(model, q, tg);
        self.history.push(r0);
        loop {
            let rinf = match self.verdict(q, tg, r0, tol, &mut report)? {
                Verdict::Converged => return Ok(report),
                Verdict::Continue(rinf) => rinf,
            };
            if fresh {
                self.factor(tg, &mut report)?;
            } else {
                self.q_prev.copy_from_slice(q);
            }
            let (alpha, trial, dmax) = self.update(model, q, tg, norm, fresh, &mut report)?;
            let reused = !fresh;
            norm = trial;
            let (rinf_new, _) = self.inf_norm();
            self.history.push(rinf_new);
            // A stale-Jacobian step (taken in full, without line search) that lands on a
            // non-finite residual (e.g. a degenerate triangle) is undone and retried as a
            // fresh, line-searched Newton step from the previous iterate. A finite increase
            // is kept: for stiff membranes ‖R‖ routinely grows on the way to convergence.
            if reused && !rinf_new.is_finite() {
                q.copy_from_slice(&self.q_prev);
                norm = self.residual_at(model, q, tg, true);
                self.timings.rejected += 1;
                fresh = true;
                continue;
            }
            // A reused Jacobian that no longer contracts the residual fast is refreshed at the
            // new iterate (its values must then be assembled there).
            // Past half the iteration budget, fall back to full Newton: a stale Jacobian that
            // still contracts slowly would otherwise exhaust the budget.
            fresh = !self.reusing()
                || (reused && rinf_new > self.opts.reuse_contraction * rinf)
                || report.iterations >= self.opts.max_iterations / 2;
            // With reuse on, trial residuals are assembled without the Jacobian.
            if fresh && self.reusing() {
                norm = self.residual_at(model, q, tg, true);
            }
            if alpha * dmax <= self.opts.step_tol && rinf_new <= 1e3 * tol {
                report.residual = rinf_new;
                return Ok(report);
            }
        }
    }

    fn factor(&mut self, tg: &Target<'_>, report: &mut StepReport) -> Result<(), StepError> {
        let t0 = Instant::now();
        let approx = !self.sym_values.is_empty();
        let fac = if approx && self.exact.is_some() && self.retry_lu {
            // A later stage of an exact retry factorises J itself (LU): the symmetric
            // approximation with its Krylov correction is what may have failed.
            self.solver.factor_lu(&self.values)
        } else if approx {
            self.assembler
                .symmetric_part(&self.values, &mut self.sym_values);
            self.solver.factor_with(&self.sym_values, &self.values)
        } else {
            self.solver.factor(&self.values)
        };
        self.approx_held = approx && matches!(fac, Ok(Factorization::Llt | Factorization::Lblt));
        self.timings.factor_s += t0.elapsed().as_secs_f64();
        let fac = fac?;
        self.timings.factorizations += 1;
        self.timings.lu_factorizations += u64::from(fac == Factorization::Lu);
        self.timings.lblt_factorizations += u64::from(fac == Factorization::Lblt);
        self.factored_for = (tg.c_m, tg.c_v);
        report.used_cholesky = fac == Factorization::Llt;
        report.factorizations += 1;
        Ok(())
    }

    /// Incremental potential `Φ(q) = ½ c_m Σ m (q − q̃)² + Σ E(q)` (J); its gradient is `R`.
    fn merit(&mut self, model: &Model, q: &[f64], tg: &Target<'_>) -> f64 {
        let t0 = Instant::now();
        let inertia: f64 = self
            .assembler
            .dof_of
            .iter()
            .map(|&d| 0.5 * tg.c_m * model.mass[d] * (q[d] - tg.q_tilde[d]).powi(2))
            .sum();
        let phi = inertia + model.energy(q);
        self.timings.merit_s += t0.elapsed().as_secs_f64();
        phi
    }

    /// Evaluate the residual at `q + α Δq` into `q_trial` / `residual`; returns `‖R‖₂`.
    fn try_step(
        &mut self,
        model: &Model,
        q: &[f64],
        tg: &Target<'_>,
        alpha: f64,
        jac: bool,
    ) -> f64 {
        self.q_trial.copy_from_slice(q);
        for (r, &d) in self.assembler.dof_of.iter().enumerate() {
            self.q_trial[d] += alpha * self.delta[r];
        }
        let qt = std::mem::take(&mut self.q_trial);
        let norm = self.residual_at(model, &qt, tg, jac);
        self.q_trial = qt;
        norm
    }

    /// One Newton update with line search from `q`; returns `(α, ‖R‖₂ at the new q, ‖Δq‖∞)`.
    /// With a reused factorisation the full step is taken (the direction is not an exact
    /// Newton direction, so backtracking on it would only waste evaluations).
    fn update(
        &mut self,
        model: &Model,
        q: &mut [f64],
        tg: &Target<'_>,
        norm: f64,
        fresh: bool,
        report: &mut StepReport,
    ) -> Result<(f64, f64, f64), StepError> {
        let dmax = self.direction(fresh, report)?;
        let line_search = self.opts.line_search && fresh && self.exact != Some(false);
        // The Jacobian is assembled with trial residuals only when the next iteration will
        // need it (full Newton); the first trial is almost always accepted.
        let want_jac = !self.reusing();
        // Merit: the incremental potential Φ when every force is conservative (its gradient
        // is R, so Newton on a stiff rod or membrane that raises ‖R‖ still decreases Φ);
        // otherwise ½‖R‖². Directions along which Φ does not descend are taken in full.
        let energy_merit = line_search && self.conservative;
        let (phi0, slope) = if energy_merit {
            let slope: f64 = self
                .residual
                .iter()
                .zip(&self.delta)
                .map(|(r, d)| r * d)
                .sum();
            (self.merit(model, q, tg), slope)
        } else {
            (0.0, 0.0)
        };
        let mut alpha = 1.0;
        let mut cuts = 0;
        let trial = loop {
            let trial = self.try_step(model, q, tg, alpha, want_jac);
            let accept = !line_search
                || cuts >= self.opts.max_backtracks
                || if energy_merit {
                    slope >= 0.0 || {
                        let qt = std::mem::take(&mut self.q_trial);
                        let phi = self.merit(model, &qt, tg);
                        self.q_trial = qt;
                        phi.is_finite() && phi <= phi0 + 1e-4 * alpha * slope
                    }
                } else {
                    trial.is_finite() && trial <= (1.0 - 1e-4 * alpha) * norm
                };
            if accept {
                break trial;
            }
            alpha *= 0.5;
            cuts += 1;
        };
        report.backtracks += cuts;
        q.copy_from_slice(&self.q_trial);
        Ok((alpha, trial, dmax))
    }
}

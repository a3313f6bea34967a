//! Implicit (backward) Euler: `M (q_{n+1} − q_n − dt v_n)/dt² = F(q_{n+1}, v_{n+1})`,
//! `v_{n+1} = (q_{n+1} − q_n)/dt`, solved by Newton–Raphson.
//!
//! Backward Euler is first-order accurate and unconditionally stable; an undamped oscillator
//! of angular frequency ω loses amplitude by the factor `1/√(1 + (ω dt)²)` per step, which is
//! the numerical damping users see at large `dt` (tested exactly).

use super::error_control::raw_estimate;
use super::newton::{NewtonCore, Target};
use super::options::{NewtonOptions, StepReport, Timings};
use super::predictor::PredictorState;
use crate::error::{EngineError, StepError};
use crate::model::{Model, State};

/// Implicit-Euler stepper for one model (its sparsity pattern is fixed at construction).
pub struct ImplicitEuler {
    core: NewtonCore,
    q_tilde: Vec<f64>,
    q_new: Vec<f64>,
    /// `v_{n+1}` of the last solved step, held until it is committed (or discarded).
    v_new: Vec<f64>,
    /// The history behind the first Newton iterate.
    guess: PredictorState,
    /// The local error estimate of the last trial (every DOF; filtered when `filter`).
    err_est: Vec<f64>,
    /// Filter the estimate through the step's factors ([`ImplicitEuler::set_error_filter`]).
    filter: bool,
}

/// A solved but not yet committed backward-Euler step (from [`ImplicitEuler::try_step`]):
/// `q_{n+1}`, `v_{n+1}` and the step size, held in the stepper's buffers. The state it was
/// solved from and the forces' history are untouched until [`Trial::commit`]; dropping the
/// trial discards the step (e.g. when its local error is too large), with nothing to undo.
pub struct Trial<'a> {
    q: &'a [f64],
    v: &'a [f64],
    e: &'a [f64],
    filtered: bool,
    dt: f64,
    report: StepReport,
}

impl Trial<'_> {
    /// `q_{n+1}` (m, rad).
    pub fn q(&self) -> &[f64] {
        self.q
    }

    /// `v_{n+1} = (q_{n+1} − q_n)/dt` (m/s, rad/s; zero on fixed DOFs).
    pub fn v(&self) -> &[f64] {
        self.v
    }

    /// The local error estimate of the step (every DOF, m or rad; zero on fixed DOFs):
    /// `(h/2)(v_{n+1} − v_n)`, filtered through the step's Newton matrix when the filter is
    /// on and the step held its factors ([`super::error_control`] module docs).
    pub fn local_error(&self) -> &[f64] {
        self.e
    }

    /// Whether [`Trial::local_error`] is the filtered estimate.
    pub fn error_filtered(&self) -> bool {
        self.filtered
    }

    /// The step size (s).
    pub fn dt(&self) -> f64 {
        self.dt
    }

    /// What the Newton solve did.
    pub fn report(&self) -> StepReport {
        self.report
    }

    /// Accept the step: `state ← (q_{n+1}, v_{n+1}, t + dt)` and every force commits its
    /// history (DER reference frames) at `q_{n+1}`. `state` and `model` must be the ones the
    /// trial was solved from.
    pub fn commit(self, model: &mut Model, state: &mut State) {
        state.q.copy_from_slice(self.q);
        state.v.copy_from_slice(self.v);
        state.t += self.dt;
        for f in model.forces.iter_mut() {
            f.commit(&state.q);
        }
    }
}

impl ImplicitEuler {
    /// Analyse the model's pattern and allocate every buffer the steps will need.
    pub fn new(model: &Model, opts: NewtonOptions) -> Result<Self, EngineError> {
        model.validate(true)?;
        let n = model.n_dofs();
        Ok(Self {
            core: NewtonCore::new(model, opts)?,
            q_tilde: vec![0.0; n],
            q_new: vec![0.0; n],
            v_new: vec![0.0; n],
            guess: PredictorState::new(n),
            err_est: vec![0.0; n],
            filter: false,
        })
    }

    /// Filter every trial's local error estimate through the step's own factorisation
    /// (RADAU5-style; [`super::error_control`] module docs). Off by default: it costs a pair
    /// of triangular solves per step, which only error-controlled stepping needs.
    pub fn set_error_filter(&mut self, on: bool) {
        self.filter = on;
    }

    /// Number of free DOFs in the Newton system.
    pub fn n_free(&self) -> usize {
        self.core.assembler.n_free
    }

    /// Nonzeros of the Jacobian pattern.
    pub fn nnz(&self) -> usize {
        self.core.assembler.nnz()
    }

    /// Memory held by the linear solver (bytes): `(factor values, scratch)`.
    pub fn solver_memory_bytes(&self) -> (usize, usize) {
        self.core.solver.memory_bytes()
    }

    /// Newton options in force.
    pub fn options(&self) -> &NewtonOptions {
        &self.core.opts
    }

    /// Phase timings and counts accumulated since construction or the last
    /// [`ImplicitEuler::reset_timings`].
    pub fn timings(&self) -> &Timings {
        &self.core.timings
    }

    /// Zero the accumulated [`Timings`] (e.g. after a benchmark's warm-up).
    pub fn reset_timings(&mut self) {
        self.core.timings = Timings::default();
    }

    /// `‖R‖∞` (N) of every Newton iterate of the last step, the predictor first.
    pub fn residual_history(&self) -> &[f64] {
        &self.core.history
    }

    /// Drop the held factorisation so that the next step starts with a fresh Jacobian.
    ///
    /// With modified Newton (`reuse_jacobian`) the bits of a step depend on which Jacobian is
    /// held; a stepper built afresh (e.g. on resume from a checkpoint) holds none. Calling this
    /// at the same deterministic points in every run makes those runs bit-identical from there.
    /// The predictor's history, the stale/fresh start policy's measurements and the exact
    /// retry's ledger are dropped too, for the same reason.
    pub fn invalidate_factorization(&mut self) {
        self.core.solver.invalidate();
        self.core.start.reset();
        self.core.ledger.reset();
        self.guess.reset();
    }

    /// Advance `state` by `dt` ([`ImplicitEuler::try_step`] then [`Trial::commit`]). On error
    /// the state and the forces' history are unchanged, so the caller may retry with a
    /// smaller `dt`.
    pub fn step(
        &mut self,
        model: &mut Model,
        state: &mut State,
        dt: f64,
    ) -> Result<StepReport, StepError> {
        let trial = self.try_step(model, state, dt)?;
        let report = trial.report();
        trial.commit(model, state);
        Ok(report)
    }

    /// Solve the step of size `dt` from `state` without changing `state` or the model: the
    /// result is a [`Trial`] to inspect (e.g. for its local error,
    /// [`Trial::local_error`]) and then commit or drop. Nothing but the
    /// stepper's own buffers (and its held factorisation, which is keyed on `dt`) changes.
    pub fn try_step(
        &mut self,
        model: &Model,
        state: &State,
        dt: f64,
    ) -> Result<Trial<'_>, StepError> {
        let n = state.q.len();
        let predictor = self.core.opts.predictor;
        self.guess.guess(
            predictor,
            model,
            state,
            dt,
            &mut self.q_tilde,
            &mut self.q_new,
        );
        let target = Target {
            c_m: 1.0 / (dt * dt),
            c_v: 1.0 / dt,
            q_tilde: &self.q_tilde,
            q_n: &state.q,
            t: state.t + dt,
        };
        let report = self.core.solve(model, &mut self.q_new, &target)?;
        self.guess
            .judge(predictor, &self.q_new, &self.q_tilde, state.t, dt);
        for d in 0..n {
            self.v_new[d] = if model.fixed[d] {
                0.0
            } else {
                (self.q_new[d] - state.q[d]) / dt
            };
        }
        raw_estimate(model, &state.v, &self.v_new, dt, &mut self.err_est);
        let filtered = self.filter
            && self
                .core
                .filter_estimate(model, &mut self.err_est, 1.0 / (dt * dt), 1.0 / dt);
        Ok(Trial {
            q: &self.q_new,
            v: &self.v_new,
            e: &self.err_est,
            filtered,
            dt,
            report,
        })
    }
}

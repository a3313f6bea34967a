//! Implicit (backward) Euler: `M (q_{n+1} − q_n − dt v_n)/dt² = F(q_{n+1}, v_{n+1})`,
//! `v_{n+1} = (q_{n+1} − q_n)/dt`, solved by Newton–Raphson.
//!
//! Backward Euler is first-order accurate and unconditionally stable; an undamped oscillator
//! of angular frequency ω loses amplitude by the factor `1/√(1 + (ω dt)²)` per step, which is
//! the numerical damping users see at large `dt` (tested exactly).

use super::newton::{NewtonCore, NewtonOptions, Predictor, StepReport, Target, Timings};
use crate::error::{EngineError, StepError};
use crate::model::{Model, State};

/// Implicit-Euler stepper for one model (its sparsity pattern is fixed at construction).
pub struct ImplicitEuler {
    core: NewtonCore,
    q_tilde: Vec<f64>,
    q_new: Vec<f64>,
    /// `v_{n−1}` and `dt_{n−1}` of the last accepted step (for the extrapolating predictor);
    /// `None` on the first step and after a sync point.
    v_prev: Vec<f64>,
    dt_prev: Option<f64>,
    /// `dt² a_n` of the current step (the extrapolating predictor's correction).
    extrap: Vec<f64>,
    /// [`Predictor::Adaptive`]: the extrapolating guess was the closer one last step.
    accel_better: bool,
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
            v_prev: vec![0.0; n],
            dt_prev: None,
            extrap: vec![0.0; n],
            accel_better: true,
        })
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
    /// The extrapolating predictor's history and the stale/fresh start policy's measurements
    /// are dropped too, for the same reason.
    pub fn invalidate_factorization(&mut self) {
        self.core.solver.invalidate();
        self.core.start.reset();
        self.dt_prev = None;
        self.accel_better = true;
    }

    /// Advance `state` by `dt`. On error the state and the forces' history are unchanged,
    /// so the caller may retry with a smaller `dt`.
    pub fn step(
        &mut self,
        model: &mut Model,
        state: &mut State,
        dt: f64,
    ) -> Result<StepReport, StepError> {
        let n = state.q.len();
        let predictor = self.core.opts.predictor;
        let accel = match (predictor, self.dt_prev) {
            (Predictor::ConstantVelocity, _) | (_, None) => 0.0,
            (_, Some(h)) => dt * dt / h,
        };
        let use_accel = match predictor {
            Predictor::ConstantVelocity => false,
            Predictor::ConstantAcceleration => true,
            Predictor::Adaptive => self.accel_better,
        };
        for d in 0..n {
            let v = if model.fixed[d] { 0.0 } else { state.v[d] };
            self.q_tilde[d] = state.q[d] + dt * v;
            // dt² a_n with a_n = (v_n − v_{n−1}) / dt_{n−1}.
            self.extrap[d] = accel * (v - self.v_prev[d]);
            self.q_new[d] = self.q_tilde[d] + if use_accel { self.extrap[d] } else { 0.0 };
        }
        let target = Target {
            c_m: 1.0 / (dt * dt),
            c_v: 1.0 / dt,
            q_tilde: &self.q_tilde,
            q_n: &state.q,
            t: state.t + dt,
        };
        let report = self.core.solve(model, &mut self.q_new, &target)?;
        if predictor == Predictor::Adaptive && accel != 0.0 {
            // Which guess was closer to the solution (by 2× for extrapolation) decides the
            // next step's guess.
            let (mut e_cv, mut e_ca) = (0.0f64, 0.0f64);
            for d in 0..n {
                let r = self.q_new[d] - self.q_tilde[d];
                e_cv = e_cv.max(r.abs());
                e_ca = e_ca.max((r - self.extrap[d]).abs());
            }
            self.accel_better = e_ca < 0.5 * e_cv;
        }
        self.v_prev.copy_from_slice(&state.v);
        self.dt_prev = Some(dt);
        for d in 0..n {
            state.v[d] = if model.fixed[d] {
                0.0
            } else {
                (self.q_new[d] - state.q[d]) / dt
            };
        }
        state.q.copy_from_slice(&self.q_new);
        state.t += dt;
        for f in model.forces.iter_mut() {
            f.commit(&state.q);
        }
        Ok(report)
    }
}

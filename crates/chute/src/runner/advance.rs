//! One step under the run loop's step-size policy, without outputs: solve, judge the local
//! error, commit. The run loop records and writes around it; [`Driver`] repeats it to a
//! given time, which is how `chute bench` steps, so both recover from failed solves alike.

use engine::{ImplicitEuler, Model, State, StepError};

use super::dt_policy::{DtPolicy, Plan, Verdict};
use super::RunConfig;
use crate::build::Built;

/// The stepper of a run under `cfg`: its Newton options, and the local error estimate
/// filtered through each step's factors when the run is adaptive with `time.error_filter`.
pub fn new_stepper(model: &Model, cfg: &RunConfig) -> Result<ImplicitEuler, engine::EngineError> {
    let mut stepper = ImplicitEuler::new(model, cfg.newton)?;
    stepper.set_error_filter(cfg.adaptive.is_some_and(|a| a.error_filter));
    Ok(stepper)
}

/// What one attempt at a step did.
pub(super) enum Outcome {
    /// Accepted and committed: Newton iterations, and the local error norm (≤ 1 unless the
    /// step was already the smallest allowed; 0 for a fixed step).
    Accepted { iterations: usize, err: f64 },
    /// Rejected for its local error; the policy holds the smaller retry step.
    Rejected,
    /// Newton failed (state unchanged); the caller asks the policy to halve.
    Failed(StepError),
}

/// Attempt the step `plan` from `state`; on acceptance `state` is the new state, ending
/// exactly on the planned event, and the policy has recorded the step.
pub(super) fn attempt(
    dt: &mut DtPolicy,
    stepper: &mut ImplicitEuler,
    model: &mut Model,
    state: &mut State,
    plan: &Plan,
) -> Outcome {
    let trial = match stepper.try_step(model, state, plan.h) {
        Ok(trial) => trial,
        Err(e) => return Outcome::Failed(e),
    };
    let (next, err) = match dt.judge(model, trial.local_error(), plan) {
        Verdict::Accept { next, err } => (next, err),
        Verdict::Reject => return Outcome::Rejected,
    };
    let iterations = trial.report().iterations;
    trial.commit(model, state);
    if let Some(t) = plan.lands_at {
        // Exactly on the event (the sum t + h may be an ulp off).
        state.t = t;
    }
    dt.accepted(plan.h, next);
    Outcome::Accepted { iterations, err }
}

/// Advances a built model with the run loop's step-size policy and nothing else (no
/// outputs, sync points or checkpoints).
#[derive(Debug, Clone)]
pub struct Driver {
    dt: DtPolicy,
    trace: bool,
}

impl Driver {
    /// The policy of `cfg` at the start of a run.
    pub fn new(cfg: &RunConfig) -> Result<Self, engine::EngineError> {
        Ok(Self {
            dt: DtPolicy::new(cfg)?,
            trace: false,
        })
    }

    /// Print every attempt and its Newton residual history on stderr.
    pub fn with_trace(mut self, trace: bool) -> Self {
        self.trace = trace;
        self
    }

    /// Step `b` until time `t_end` (s): a failed Newton solve halves the step, which grows
    /// back after accepted steps, as in a run. The error is that of the solve that failed
    /// at the smallest step allowed.
    pub fn advance_to(
        &mut self,
        stepper: &mut ImplicitEuler,
        b: &mut Built,
        t_end: f64,
    ) -> Result<(), StepError> {
        while b.state.t < t_end - self.dt.time_tol {
            let plan = self.dt.plan(b.state.t, t_end);
            let outcome = attempt(&mut self.dt, stepper, &mut b.model, &mut b.state, &plan);
            if self.trace {
                let what = match &outcome {
                    Outcome::Accepted { iterations, .. } => format!("ok, {iterations} it"),
                    Outcome::Rejected => "rejected (local error)".into(),
                    Outcome::Failed(e) => format!("failed: {e}"),
                };
                let hist = stepper.residual_history();
                eprintln!("t={:.5} h={:.3e} {what} {hist:?}", b.state.t, plan.h);
            }
            if let Outcome::Failed(e) = outcome {
                if !self.dt.newton_failed(plan.h) {
                    return Err(e);
                }
            }
        }
        Ok(())
    }

    /// Steps whose Newton solve failed so far (each was retried with half the step).
    pub fn newton_failures(&self) -> u64 {
        self.dt.rejected_newton
    }
}

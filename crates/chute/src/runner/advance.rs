//! One step under the run's step-size policy, without outputs: the engine's
//! [`ImplicitEuler::attempt`] (solve by the ladder of stages, judge the local error, commit,
//! or halve after a failed solve) with the run's statistics. The run loop records and writes
//! around it; [`Driver`] repeats it to a given time, which is how `chute bench` steps, so
//! both recover from failed solves alike.

use engine::{Attempt, ImplicitEuler, Model, State, StepError, StepReport};

use super::dt_policy::DtPolicy;
use super::RunConfig;
use crate::build::Built;

/// The stepper of a run under `cfg`: its Newton options, and the local error estimate
/// filtered through each step's factors when the run is adaptive with `time.error_filter`.
pub fn new_stepper(model: &Model, cfg: &RunConfig) -> Result<ImplicitEuler, engine::EngineError> {
    let mut stepper = ImplicitEuler::new(model, cfg.newton)?;
    stepper.set_error_filter(cfg.stepping.adaptive.is_some_and(|a| a.error_filter));
    Ok(stepper)
}

/// What one attempt at a step did.
pub(super) enum Outcome {
    /// Accepted and committed: its size, what the solve did, and the local error norm (≤ 1
    /// unless the step was already the smallest allowed; 0 for a fixed step).
    Accepted {
        h: f64,
        report: StepReport,
        err: f64,
    },
    /// Rejected for its local error; the policy holds the smaller retry step.
    Rejected,
    /// The solve of a step of size `h` failed (state unchanged) and the step was halved.
    Halved(StepError, f64),
    /// The solve failed at the smallest step allowed: the run must stop.
    Failed(StepError),
}

/// Attempt the next step from `state`, ending at or before `event` (s); on acceptance
/// `state` is the new state (exactly on the event where the step was planned to end there)
/// and the step is in the policy's statistics.
pub(super) fn attempt(
    dt: &mut DtPolicy,
    stepper: &mut ImplicitEuler,
    model: &mut Model,
    state: &mut State,
    event: f64,
) -> Outcome {
    match stepper.attempt(&mut dt.sizes, model, state, event) {
        Attempt::Accepted { h, report, err } => {
            dt.used.record(h);
            Outcome::Accepted { h, report, err }
        }
        Attempt::Rejected { .. } => Outcome::Rejected,
        Attempt::Halved { h, error } => Outcome::Halved(error, h),
        Attempt::Failed { error, .. } => Outcome::Failed(error),
    }
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

    /// Print every attempt, the stage that solved it and its residual history on stderr.
    pub fn with_trace(mut self, trace: bool) -> Self {
        self.trace = trace;
        self
    }

    /// Step `b` until time `t_end` (s): a failed solve halves the step, which grows back
    /// after accepted steps, as in a run. The error is that of the solve that failed at the
    /// smallest step allowed.
    pub fn advance_to(
        &mut self,
        stepper: &mut ImplicitEuler,
        b: &mut Built,
        t_end: f64,
    ) -> Result<(), StepError> {
        while b.state.t < t_end - self.dt.time_tol {
            let t = b.state.t;
            let outcome = attempt(&mut self.dt, stepper, &mut b.model, &mut b.state, t_end);
            if self.trace {
                let what = match &outcome {
                    Outcome::Accepted { h, report, .. } => format!(
                        "h={h:.3e} ok by {:?}, {} it, {} factorisations",
                        report.stage, report.iterations, report.factorizations
                    ),
                    Outcome::Rejected => "rejected (local error)".into(),
                    Outcome::Halved(e, h) => format!("h={h:.3e} failed, halved: {e}"),
                    Outcome::Failed(e) => format!("failed: {e}"),
                };
                let c = stepper.counters();
                let hist = stepper.residual_history();
                crate::err_line!(
                    "t={t:.5} {what} F{} E{} {hist:?}",
                    c.factorizations,
                    c.evaluations
                );
            }
            if let Outcome::Failed(e) = outcome {
                return Err(e);
            }
        }
        Ok(())
    }

    /// Steps whose solve failed so far (each was retried with half the step).
    pub fn newton_failures(&self) -> u64 {
        self.dt.sizes.state.rejected_newton
    }
}

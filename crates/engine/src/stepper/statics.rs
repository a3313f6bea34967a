//! Static equilibrium `F(q) = 0` by the Newton stage (`stage/newton.rs`) with load stepping:
//! external loads (forces that honour [`crate::Force::set_load_scale`]) are ramped from `1/n`
//! to 1 in `n` increments, each solved from the previous equilibrium. Elements with history
//! (DER reference frames) are committed after every increment, like a quasi-static step.

use super::options::{NewtonOptions, StepReport};
use super::stage::{newton, Core};
use super::workspace::Target;
use crate::error::{EngineError, StepError};
use crate::model::{Model, State};

/// Static solver for one model.
pub struct StaticSolver {
    core: Core,
    zeros: Vec<f64>,
}

impl StaticSolver {
    /// Analyse the model's pattern. Masses are not needed.
    pub fn new(model: &Model, opts: NewtonOptions) -> Result<Self, EngineError> {
        model.validate(false)?;
        let history = opts.max_iterations + 1;
        Ok(Self {
            core: Core::new(model, opts, history)?,
            zeros: vec![0.0; model.n_dofs()],
        })
    }

    /// `‖R‖∞` (N) of every Newton iterate of the last load increment, the start first.
    pub fn residual_history(&self) -> &[f64] {
        &self.core.ws.history
    }

    /// Solve for equilibrium in `load_steps` increments, starting from `state.q`. Returns the
    /// reports of the increments. On failure `state` holds the last converged increment.
    pub fn solve(
        &mut self,
        model: &mut Model,
        state: &mut State,
        load_steps: usize,
    ) -> Result<Vec<StepReport>, StepError> {
        let steps = load_steps.max(1);
        let mut reports = Vec::with_capacity(steps);
        let mut q = state.q.clone();
        for i in 1..=steps {
            let s = i as f64 / steps as f64;
            for f in model.forces.iter_mut() {
                f.set_load_scale(s);
            }
            let tg = Target {
                c_m: 0.0,
                c_v: 0.0,
                q_tilde: &self.zeros,
                q_n: &self.zeros,
                t: state.t,
            };
            let budget = self.core.opts.max_iterations;
            let mut cx = self.core.begin_solve(model);
            reports.push(newton::run(&mut cx, &tg, &mut q, budget)?);
            state.q.copy_from_slice(&q);
            for f in model.forces.iter_mut() {
                f.commit(&state.q, &state.v);
            }
        }
        Ok(reports)
    }
}

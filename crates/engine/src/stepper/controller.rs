//! The step controller: one implicit-Euler step from guess to committed state, and what
//! happens when it fails. A reader follows a hard step from top to bottom here.
//!
//! **The ladder** ([`ImplicitEuler::try_step`]). The predictor guesses `q_{n+1}`; the stages
//! of `stepper/stage/` then try, cheapest first, until one converges:
//! 1. *held* — iterations on the factors held from earlier steps, Anderson-mixed (only if
//!    factors for this step size are held, and not right after the stage failed: after a
//!    failure it sits out 1, 2, 4 … 64 steps, doubling while it keeps failing);
//! 2. *Newton* — fresh Jacobians and factorisations, Galerkin line search, from the better of
//!    the predictor and the held stage's last iterate;
//! 3. *continuation* — pseudo-transient continuation from `q̃`;
//! 4. *homotopy* — the solution followed in the step size from half the step up.
//!
//! The last two can cost hundreds of factorisations when they fail, so they are only tried
//! while failed solves have not cost more factorisations than successful ones since the last
//! sync point (the retry ledger). When every stage fails, the error goes to the caller, and
//! [`ImplicitEuler::attempt`] halves the step (`stepper/step_size.rs`).
//!
//! **Sizes** ([`ImplicitEuler::attempt`]): the step size comes from the step-size policy
//! (fixed or error-controlled), shortened to end on the caller's next event; an accepted
//! step is judged by its local error (adaptive), committed, and the policy learns from it.

use super::error_control::raw_estimate;
use super::implicit_euler::{velocities, Trial};
use super::linearization::Linearization;
use super::options::{Counters, NewtonOptions, StepReport};
use super::predictor::PredictorState;
use super::retry_ledger::RetryLedger;
use super::stage::held;
use super::stage::homotopy::{self, HomotopyBuffers};
use super::stage::{continuation, newton, Core};
use super::step_size::StepSizes;
use super::workspace::{Target, Workspace, ITERATE_GAP, PATH_GAP};
use crate::error::{EngineError, StepError};
use crate::model::{Model, State};

/// Longest wait of the held stage after repeated failures (steps).
const HELD_MAX_WAIT: u32 = 64;

/// When the held stage may run: after a failure it waits `skip` steps, `skip` doubling
/// (1, 2, 4 … [`HELD_MAX_WAIT`]) while it keeps failing and reset by a success. Counted in
/// steps, never in time, so runs stay bit-reproducible.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
struct HeldBackoff {
    skip: u32,
    wait: u32,
}

impl HeldBackoff {
    /// Whether this step may try the held stage (a step spent waiting counts down).
    fn allows(&mut self) -> bool {
        if self.wait > 0 {
            self.wait -= 1;
            return false;
        }
        true
    }

    fn record(&mut self, ok: bool) {
        if ok {
            self.skip = 0;
        } else {
            self.skip = (2 * self.skip).clamp(1, HELD_MAX_WAIT);
            self.wait = self.skip;
        }
    }
}

/// What one attempt at a step did ([`ImplicitEuler::attempt`]).
#[derive(Debug, Clone)]
pub enum Attempt {
    /// Accepted and committed: its size (s), what the solve did, and the error norm (≤ 1
    /// unless the step was already the smallest allowed; 0 for a fixed step).
    Accepted {
        /// Step size (s).
        h: f64,
        /// What the solve did.
        report: StepReport,
        /// Error norm of the step.
        err: f64,
    },
    /// Rejected for its local error; the policy holds the smaller retry step.
    Rejected {
        /// Step size tried (s).
        h: f64,
    },
    /// The solve failed (state unchanged) and the step was halved for a retry.
    Halved {
        /// Step size tried (s).
        h: f64,
        /// Why the solve failed.
        error: StepError,
    },
    /// The solve failed and the halved step would be below the smallest allowed: the caller
    /// must stop.
    Failed {
        /// Step size tried (s).
        h: f64,
        /// Why the solve failed.
        error: StepError,
    },
}

/// Implicit-Euler stepper for one model (its sparsity pattern is fixed at construction):
/// the ladder of stages and the step-size policy.
pub struct ImplicitEuler {
    core: Core,
    homotopy: HomotopyBuffers,
    ledger: RetryLedger,
    backoff: HeldBackoff,
    predictor: PredictorState,
    q_tilde: Vec<f64>,
    /// The predictor's guess (kept: the Newton stage may restart from it).
    q_guess: Vec<f64>,
    q_new: Vec<f64>,
    v_new: Vec<f64>,
    err_est: Vec<f64>,
    /// Filter the local error estimate through the step's factors.
    filter: bool,
}

impl ImplicitEuler {
    /// Analyse the model's pattern and allocate every buffer the steps will need.
    pub fn new(model: &Model, opts: NewtonOptions) -> Result<Self, EngineError> {
        model.validate(true)?;
        let n = model.n_dofs();
        let history = 8 * opts.max_iterations + opts.held_iterations + 2;
        Ok(Self {
            core: Core::new(model, opts, history)?,
            homotopy: HomotopyBuffers::new(n),
            ledger: RetryLedger::default(),
            backoff: HeldBackoff::default(),
            predictor: PredictorState::new(n),
            q_tilde: vec![0.0; n],
            q_guess: vec![0.0; n],
            q_new: vec![0.0; n],
            v_new: vec![0.0; n],
            err_est: vec![0.0; n],
            filter: false,
        })
    }

    /// The workspace and the held factors (unit-cost measurements).
    pub(crate) fn parts(&mut self) -> (&mut Workspace, &mut Linearization) {
        (&mut self.core.ws, &mut self.core.lin)
    }

    /// Filter every trial's local error estimate through the step's own factorisation
    /// (RADAU5-style; [`super::error_control`] module docs). Off by default: it costs a pair
    /// of triangular solves per step, which only error-controlled stepping needs.
    pub fn set_error_filter(&mut self, on: bool) {
        self.filter = on;
    }

    /// Number of free DOFs in the Newton system.
    pub fn n_free(&self) -> usize {
        self.core.ws.n_free()
    }

    /// Nonzeros of the Jacobian pattern.
    pub fn nnz(&self) -> usize {
        self.core.ws.asm.nnz()
    }

    /// Memory held by the linear solver (bytes): `(factor values, scratch)`.
    pub fn solver_memory_bytes(&self) -> (usize, usize) {
        self.core.lin.memory_bytes()
    }

    /// Whether the factors are computed in single precision: as asked by
    /// [`NewtonOptions::single_precision_factors`], until a matrix too ill-conditioned for
    /// them switched the stepper to double precision (docs/engine.md §Precision).
    pub fn single_precision_factors(&self) -> bool {
        self.core.lin.single_precision()
    }

    /// The settings in force.
    pub fn options(&self) -> &NewtonOptions {
        &self.core.opts
    }

    /// What the solves did since construction or the last [`ImplicitEuler::reset_counters`].
    pub fn counters(&self) -> &Counters {
        &self.core.ws.counters
    }

    /// Zero the accumulated [`Counters`] (e.g. after a benchmark's warm-up).
    pub fn reset_counters(&mut self) {
        self.core.ws.counters = Counters::default();
    }

    /// `‖R‖∞` (N) of every iterate of the last step, over all the stages it went through.
    pub fn residual_history(&self) -> &[f64] {
        &self.core.ws.history
    }

    /// Drop the held factors so that the next step starts as a fresh stepper would.
    ///
    /// With held factors the bits of a step depend on which factors are held; a stepper built
    /// afresh (e.g. on resume from a checkpoint) holds none. Calling this at the same
    /// deterministic points in every run makes those runs bit-identical from there. The
    /// predictor's history, the held stage's back-off, the retry ledger and the measured
    /// round-off are dropped too, for the same reason.
    pub fn invalidate_factorization(&mut self) {
        self.core.lin.invalidate();
        self.core.ws.forget_noise();
        self.ledger.reset();
        self.backoff = HeldBackoff::default();
        self.predictor.reset();
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
        self.begin_step(model, state, dt)?;
        let trial = self.try_step(model, state, dt)?;
        let report = trial.report();
        trial.commit(model, state);
        Ok(report)
    }

    /// One attempt at the next step from `state` under the step-size policy `sizes`, ending
    /// at or before `event` (s; exactly on it where the policy shortens the step to it):
    /// solve by the ladder; on failure halve (module docs); else judge the local error
    /// (adaptive), commit, and let the policy propose the next size.
    pub fn attempt(
        &mut self,
        sizes: &mut StepSizes,
        model: &mut Model,
        state: &mut State,
        event: f64,
    ) -> Attempt {
        let plan = sizes.plan(state.t, event);
        let h = plan.h;
        if let Err(error) = self.begin_step(model, state, h) {
            return Attempt::Failed { h, error };
        }
        let trial = match self.try_step(model, state, h) {
            Ok(trial) => trial,
            Err(error) if sizes.solve_failed(h) => return Attempt::Halved { h, error },
            Err(error) => return Attempt::Failed { h, error },
        };
        let Ok((next, err)) = sizes.judge(model, trial.local_error(), &plan) else {
            return Attempt::Rejected { h };
        };
        let report = trial.report();
        trial.commit(model, state);
        if let Some(t) = plan.lands_at {
            // Exactly on the event (the sum t + h may be an ulp off).
            state.t = t;
        }
        sizes.accepted(h, next);
        Attempt::Accepted { h, report, err }
    }

    /// Let the forces take their step-dependent stencils (contact pairs) for a step of `dt`
    /// from `state` ([`Model::begin_step`]); where they changed, rebuild the sparsity pattern
    /// and its symbolic factorisation (the held factors are dropped, the counters kept).
    pub fn begin_step(
        &mut self,
        model: &mut Model,
        state: &State,
        dt: f64,
    ) -> Result<(), StepError> {
        if !model.begin_step(&state.q, &state.v, dt) {
            return Ok(());
        }
        let t0 = std::time::Instant::now();
        let counters = self.core.ws.counters;
        let history = self.core.ws.history.capacity();
        self.core = Core::new(model, self.core.opts, history)
            .map_err(|e| StepError::Pattern(e.to_string()))?;
        self.core.ws.counters = counters;
        self.core.ws.counters.pattern_rebuilds += 1;
        self.core.ws.counters.pattern_s += t0.elapsed().as_secs_f64();
        Ok(())
    }

    /// Solve the step of size `dt` from `state` by the ladder (module docs) without changing
    /// `state` or the model: the result is a [`Trial`] to inspect (e.g. for its local error)
    /// and then commit or drop. Nothing but the stepper's own buffers, its held factors and
    /// its counters change.
    pub fn try_step(
        &mut self,
        model: &Model,
        state: &State,
        dt: f64,
    ) -> Result<Trial<'_>, StepError> {
        let predictor = self.core.opts.predictor;
        self.predictor.guess(
            predictor,
            model,
            state,
            dt,
            &mut self.q_tilde,
            &mut self.q_guess,
        );
        // The guess on the near side of every surface (contact).
        (self.core.ws).bound_move(model, &state.q, &mut self.q_guess, ITERATE_GAP);
        let q_tilde = std::mem::take(&mut self.q_tilde);
        let tg = Target {
            c_m: 1.0 / (dt * dt),
            c_v: 1.0 / dt,
            q_tilde: &q_tilde,
            q_n: &state.q,
            t: state.t + dt,
        };
        let res = self
            .solve(model, &tg)
            .and_then(|r| self.check_path(model, state, r));
        let filtered = res.is_ok() && self.finish_step(model, state, &tg);
        self.q_tilde = q_tilde;
        let report = res?;
        self.predictor
            .judge(predictor, &self.q_new, &self.q_tilde, state.t, dt);
        Ok(Trial {
            q: &self.q_new,
            v: &self.v_new,
            e: &self.err_est,
            filtered,
            dt,
            report,
        })
    }

    /// The ladder (module docs) from the predictor's guess in `q_guess`; the solution in
    /// `q_new`.
    pub(crate) fn solve(
        &mut self,
        model: &Model,
        tg: &Target<'_>,
    ) -> Result<StepReport, StepError> {
        let f0 = self.core.ws.counters.factorizations;
        let mut q = std::mem::take(&mut self.q_new);
        q.copy_from_slice(&self.q_guess);
        let mut cx = self.core.begin_solve(model);
        let mut held_report = StepReport::default();
        let mut res = Err(StepError::NonFinite {
            what: "step (no stage ran)",
            dof: 0,
        });
        if cx.opts.hold_factors && cx.lin.held_for(tg) && self.backoff.allows() {
            let r = held::run(&mut cx, tg, &mut q);
            cx.ws.counters.held.record(r.is_ok());
            self.backoff.record(r.is_ok());
            match r {
                Ok(rep) => res = Ok(rep),
                Err(gave_up) => {
                    held_report.iterations = cx.ws.history.len() - 1;
                    // Newton starts from wherever is closer to the solution.
                    let progressed = gave_up.residual < gave_up.initial;
                    if !progressed {
                        q.copy_from_slice(&self.q_guess);
                    }
                    res = Err(gave_up.error);
                }
            }
        }
        // A residual that is not finite at the predictor (a force model blowing up at this
        // step size) leaves nothing for a later stage to start from: the step is halved.
        let start_finite = cx.ws.history.first().is_none_or(|r| r.is_finite());
        let budget = cx.opts.max_iterations;
        if res.is_err() && start_finite {
            res = newton::run(&mut cx, tg, &mut q, budget);
            cx.ws.counters.newton.record(res.is_ok());
        }
        let start_finite = start_finite && cx.ws.history.first().is_none_or(|r| r.is_finite());
        if res.is_err() && start_finite && cx.opts.continuation {
            if self.ledger.allows_retry() {
                res = continuation::run(&mut cx, tg, &mut q, 4 * budget);
                cx.ws.counters.continuation.record(res.is_ok());
            } else {
                cx.ws.counters.stages_skipped += 1;
            }
        }
        if res.is_err() && start_finite && cx.opts.step_homotopy {
            if self.ledger.allows_retry() {
                res = homotopy::run(&mut cx, tg, &mut q, budget, &mut self.homotopy);
                cx.ws.counters.homotopy.record(res.is_ok());
            } else {
                cx.ws.counters.stages_skipped += 1;
            }
        }
        let facts = self.core.ws.counters.factorizations - f0;
        self.ledger.record(res.is_ok(), facts);
        self.q_new = q;
        res.map(|mut rep| {
            rep.iterations += held_report.iterations;
            rep.factorizations = facts as usize;
            rep
        })
    }

    /// Refuse a solution whose straight path from the step's start brings two contact
    /// surfaces together (`Force::max_step` at [`PATH_GAP`]): whichever stage solved it, no
    /// surface passed through another during an accepted step.
    fn check_path(
        &mut self,
        model: &Model,
        state: &State,
        report: StepReport,
    ) -> Result<StepReport, StepError> {
        let mut end = std::mem::take(&mut self.v_new);
        end.copy_from_slice(&self.q_new);
        let fraction = self.core.ws.bound_move(model, &state.q, &mut end, PATH_GAP);
        self.v_new = end;
        if fraction < 1.0 {
            self.core.ws.counters.path_rejects += 1;
            return Err(StepError::Crossing { fraction });
        }
        Ok(report)
    }

    /// After a converged solve: `v_{n+1}`, the raw local error estimate, and (with the
    /// filter on) its filtered form when the factors held are of this step's matrix (the
    /// estimate is left raw, and the fallback counted, when they are not or the result is not
    /// finite). Whether the estimate is filtered.
    fn finish_step(&mut self, model: &Model, state: &State, tg: &Target<'_>) -> bool {
        let h = 1.0 / tg.c_v;
        velocities(model, &state.q, &self.q_new, h, &mut self.v_new);
        raw_estimate(model, &state.v, &self.v_new, h, &mut self.err_est);
        if !self.filter {
            return false;
        }
        if !self.core.lin.held_for(tg) {
            self.core.ws.counters.error_filter_fallbacks += 1;
            return false;
        }
        let mut x = std::mem::take(&mut self.core.ws.delta);
        for (r, &d) in self.core.ws.asm.dof_of.iter().enumerate() {
            x[r] = tg.c_m * self.core.ws.mass[r] * self.err_est[d];
        }
        self.core.lin.apply(&mut self.core.ws, &mut x);
        let ok = x.iter().all(|v| v.is_finite());
        if ok {
            for (r, &d) in self.core.ws.asm.dof_of.iter().enumerate() {
                self.err_est[d] = x[r];
            }
            self.core.ws.counters.error_filters += 1;
        } else {
            self.core.ws.counters.error_filter_fallbacks += 1;
        }
        self.core.ws.delta = x;
        ok
    }
}

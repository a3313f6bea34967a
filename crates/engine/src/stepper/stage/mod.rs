//! The stages of the step solver's ladder (`stepper/controller.rs`), each one strategy for
//! solving `R(q) = 0` with one `run` entry point, cheapest first:
//!
//! 1. [`held`]: iterations with the factors held from earlier steps, Anderson-mixed; no
//!    Jacobian, no factorisation. Gives up after a few iterations that do not contract.
//! 2. [`newton`]: Newton with fresh Jacobians (kept while they contract), the Krylov-corrected
//!    update of `linearization.rs` and a Galerkin line search.
//! 3. [`continuation`]: pseudo-transient continuation from `q̃` (an added inertia that
//!    shrinks as the residual falls).
//! 4. [`homotopy`]: the step's solution followed in the step size from half the step up.
//!
//! Every stage judges its iterates with the same [`Convergence`] test, so whichever
//! converges, the result is the implicit-Euler solution of the step to the same tolerance.

pub(crate) mod continuation;
pub(crate) mod held;
pub(crate) mod homotopy;
pub(crate) mod newton;

use super::anderson::Anderson;
use super::convergence::Convergence;
use super::convergence::Tolerance;
use super::linearization::Linearization;
use super::options::{NewtonOptions, Stage, StepReport};
use super::workspace::{Target, Workspace, ITERATE_GAP};
use crate::model::Model;

/// What every step solver owns for its stages (dynamics and statics alike): the options,
/// the buffers, the held factors, the convergence test and the mixing of chord iterations.
pub(crate) struct Core {
    pub opts: NewtonOptions,
    pub ws: Workspace,
    pub lin: Linearization,
    pub conv: Convergence,
    pub mix: Mixing,
}

impl Core {
    /// The parts for `model` under `opts`, with room for `history` residuals per solve.
    pub fn new(
        model: &Model,
        opts: NewtonOptions,
        history: usize,
    ) -> Result<Self, crate::error::EngineError> {
        let ws = Workspace::new(model, history);
        Ok(Self {
            lin: Linearization::new(&ws, super::linearization::precision(&opts))?,
            conv: Convergence::new(&opts, model.total_mass()),
            mix: Mixing::new(opts.anderson_depth, &ws.mass, model.n_dofs()),
            ws,
            opts,
        })
    }

    /// Start one solve on `model`: a fresh residual history, the solve counted, and the
    /// parts lent to the stages.
    pub fn begin_solve<'a>(&'a mut self, model: &'a Model) -> Ctx<'a> {
        self.ws.history.clear();
        self.ws.counters.solves += 1;
        Ctx {
            model,
            ws: &mut self.ws,
            lin: &mut self.lin,
            mix: &mut self.mix,
            conv: &self.conv,
            opts: &self.opts,
        }
    }
}

/// What a stage works with: the model, the buffers, the held factors, the Anderson mixing of
/// chord iterations, the convergence test and the options.
pub(crate) struct Ctx<'a> {
    pub model: &'a Model,
    pub ws: &'a mut Workspace,
    pub lin: &'a mut Linearization,
    pub mix: &'a mut Mixing,
    pub conv: &'a Convergence,
    pub opts: &'a NewtonOptions,
}

impl Ctx<'_> {
    /// A stage's start at `q`: its report, the residual there (with the Jacobian when `jac`)
    /// as the first entry of the residual history, the solve's tolerance, and `‖R‖₂`.
    pub fn begin(
        &mut self,
        stage: Stage,
        tg: &Target<'_>,
        q: &[f64],
        jac: bool,
    ) -> (StepReport, Tolerance, f64) {
        let norm = self.ws.evaluate(self.model, q, tg, jac);
        let tol = self.conv.start(self.ws);
        self.ws.history.push(tol.r0);
        let rep = StepReport {
            stage,
            ..StepReport::default()
        };
        (rep, tol, norm)
    }
}

/// Chord iterations `q ← q + Δ` (the update in the workspace), Anderson-mixed over the free
/// DOFs (`stepper/anderson.rs`); no allocation after construction.
pub(crate) struct Mixing {
    anderson: Anderson,
    x: Vec<f64>,
    f: Vec<f64>,
    /// The iterate before the last chord update (all DOFs), for [`Mixing::undo`].
    q_prev: Vec<f64>,
}

impl Mixing {
    /// Mixing of `depth` for a model of `n` DOFs whose free DOFs have these masses (the
    /// norm's weights).
    pub fn new(depth: usize, mass: &[f64], n: usize) -> Self {
        Self {
            anderson: Anderson::new(depth, mass),
            x: vec![0.0; mass.len()],
            f: vec![0.0; mass.len()],
            q_prev: vec![0.0; n],
        }
    }

    /// Start mixing from iterate `q` (new factors, or a new step: the fixed-point map
    /// changed). Keeping the differences of earlier steps with the same factors as secant
    /// information was tried: on the main job it tripled the factorisations (old secant pairs
    /// extrapolate wildly once the shape has moved; docs/performance.md).
    pub fn begin(&mut self, ws: &Workspace, q: &[f64]) {
        self.anderson.reset();
        ws.gather(q, &mut self.x);
    }

    /// Move `q` by the chord update in `ws.delta`, mixed with the earlier ones, no farther
    /// than the model's forces admit (contact: `Force::max_step`).
    pub fn step(&mut self, ws: &mut Workspace, model: &Model, q: &mut [f64]) {
        self.q_prev.copy_from_slice(q);
        self.f.copy_from_slice(&ws.delta);
        self.anderson.mix(&mut self.x, &self.f);
        ws.scatter(&self.x, q);
        if ws.bound_move(model, &self.q_prev, q, ITERATE_GAP) < 1.0 {
            // The iterate is no longer where the mixing put it: mixing restarts from here.
            self.anderson.reset();
            ws.gather(q, &mut self.x);
        }
    }

    /// Put `q` back where it was before the last [`Mixing::step`] (its residual must be
    /// evaluated again).
    pub fn undo(&self, q: &mut [f64]) {
        q.copy_from_slice(&self.q_prev);
    }
}

//! The held stage: a step solved with the factors held from earlier steps, without a new
//! Jacobian or factorisation.
//!
//! The chord update `Δ = −A⁻¹ R(q)` with held factors `A` is a fixed-point iteration whose
//! contraction is that of `I − A⁻¹ J`: fast while the canopy's shape (and so the orientation
//! of its stiff membrane directions) is close to where `A` was factorised, divergent once it
//! has rotated by more than about `1/√κ` (`κ` the ratio of membrane stiffness to `M/h²`,
//! ~4e4 for the report's Kevlar at h = 4 ms). Anderson mixing (`stepper/anderson.rs`)
//! removes the few directions that contract slowly, at a few dot products per iteration.
//!
//! The stage costs one residual and one pair of triangular solves per iteration, against a
//! Jacobian and a factorisation (20–30 such iterations on the bundled shells) for a Newton
//! iteration, so it is tried first; it gives up as soon as its iterates show that it will not
//! converge within [`NewtonOptions::held_iterations`]: the residual grew, or its mean
//! contraction is worse than [`NewtonOptions::reuse_contraction`] per iteration (the same
//! test as the Newton stage's chord iterations). The step then goes to the
//! Newton stage, starting from the better of the predictor and this stage's last iterate.

use super::Ctx;
use crate::error::StepError;
use crate::stepper::convergence::Verdict;
use crate::stepper::options::{Stage, StepReport};
use crate::stepper::workspace::Target;

/// Why the held stage gave up, and the residual of its last iterate.
#[derive(Debug)]
pub(crate) struct GaveUp {
    /// What ended it.
    pub error: StepError,
    /// `‖R‖∞` of the last iterate (N), or ∞ where it was not finite.
    pub residual: f64,
    /// `‖R‖∞` of the predictor (N).
    pub initial: f64,
}

/// Solve the step from `q` with the held factors (which must be for `tg`'s step size).
pub(crate) fn run(cx: &mut Ctx<'_>, tg: &Target<'_>, q: &mut [f64]) -> Result<StepReport, GaveUp> {
    let (mut rep, tol, _) = cx.begin(Stage::Held, tg, q, false);
    let budget = cx.opts.held_iterations.min(cx.opts.max_iterations);
    cx.mix.begin(cx.ws, q);
    let give_up = |error, residual| GaveUp {
        error,
        residual,
        initial: tol.r0,
    };
    let mut probed = false;
    loop {
        let rinf = match cx.conv.judge(cx.ws, q, tg, &tol, rep.iterations, budget) {
            Ok(Verdict::Converged) => break,
            Ok(Verdict::Continue(r)) => r,
            Err(e) => {
                let r = cx.ws.inf_norm().0;
                return Err(give_up(e, if r.is_finite() { r } else { f64::INFINITY }));
            }
        };
        let k = rep.iterations;
        let slow = k >= 2 && rinf > tol.r0 * cx.opts.reuse_contraction.powi(k as i32);
        if slow && rinf <= 1e3 * tol.tol && !probed {
            // Before giving up: stalled on the residual's round-off? (as in the Newton stage)
            probed = true;
            cx.ws.measure_noise(cx.model, q, tg);
            continue;
        }
        if k >= 1 && (rinf > tol.r0 || slow) {
            let (_, worst) = cx.ws.inf_norm();
            let error = StepError::NotConverged {
                iterations: k,
                residual: rinf,
                tolerance: tol.tol,
                worst_dof: worst,
            };
            return Err(give_up(error, rinf));
        }
        cx.lin.chord(cx.ws);
        rep.iterations += 1;
        cx.mix.step(cx.ws, cx.model, q);
        cx.ws.evaluate(cx.model, q, tg, false);
        let (r, _) = cx.ws.inf_norm();
        cx.ws.history.push(r);
    }
    rep.residual = cx.ws.inf_norm().0;
    Ok(rep)
}

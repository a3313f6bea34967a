//! The continuation stage: pseudo-transient continuation from `q̃`, for a step whose Newton
//! iteration wanders off.
//!
//! Each iteration solves `(J + (c_m/τ) M) Δ = −R` with a fresh Jacobian at the iterate. The
//! extra diagonal is an added inertia: with `τ` small the update is a short,
//! well-conditioned step along `−M⁻¹R` (a smaller pseudo time step), with `τ → ∞` it is
//! Newton's. An update that keeps `‖R‖₂` below [`GROWTH_LIMIT`] times its value is taken and
//! `τ` grows with the residual's fall (switched evolution relaxation, Mulder & van Leer 1985;
//! Kelley & Keyes 1998: `τ ← τ ‖R_{k−1}‖₂ / ‖R_k‖₂`), so the iteration ends quadratically;
//! one that does not is undone and `τ` is quartered (a trust region in the mass metric). The
//! diagonal only changes the path: convergence is judged on `R` itself, so the result is
//! the implicit-Euler solution of the step.

use super::Ctx;
use crate::error::StepError;
use crate::stepper::convergence::Verdict;
use crate::stepper::options::{Stage, StepReport};
use crate::stepper::workspace::{Target, ITERATE_GAP};

/// First `τ`: the extra diagonal is `10 W` (`W = max(c_m M, −diag J)`, `Linearization::refresh`:
/// the inertia 11×, a pseudo step ~h/3).
const TAU_START: f64 = 0.1;
/// An update that raises `‖R‖₂` by more than this factor is undone.
const GROWTH_LIMIT: f64 = 10.0;
/// Bounds of `τ` (past the upper one the extra diagonal is below round-off of `W`).
const TAU_MIN: f64 = 1e-8;
const TAU_MAX: f64 = 1e16;

/// Solve the step from `q̃` (into `q`) within `budget` iterations. The held factors are of a
/// shifted matrix afterwards (not reusable for the step).
pub(crate) fn run(
    cx: &mut Ctx<'_>,
    tg: &Target<'_>,
    q: &mut [f64],
    budget: usize,
) -> Result<StepReport, StepError> {
    q.copy_from_slice(tg.q_tilde);
    cx.ws.bound_move(cx.model, tg.q_n, q, ITERATE_GAP);
    let (mut rep, tol, mut norm) = cx.begin(Stage::Continuation, tg, q, true);
    let mut tau = TAU_START;
    loop {
        if let Verdict::Converged = cx.conv.judge(cx.ws, q, tg, &tol, rep.iterations, budget)? {
            break;
        }
        cx.lin.jacobian_changed();
        cx.lin.refresh(cx.ws, tg, 1.0 / tau);
        rep.factorizations += 1;
        cx.lin.newton(cx.ws, 1e-3);
        rep.iterations += 1;
        cx.ws.delta_max().map_err(|dof| StepError::NonFinite {
            what: "continuation update",
            dof,
        })?;
        let alpha = cx.ws.max_alpha(cx.model, q);
        let trial = cx.ws.try_update(cx.model, q, tg, alpha, true);
        if trial.is_finite() && trial < GROWTH_LIMIT * norm {
            q.copy_from_slice(&cx.ws.q_trial);
            tau = (tau * norm / trial.max(f64::MIN_POSITIVE)).clamp(TAU_MIN, TAU_MAX);
            norm = trial;
        } else {
            // Undone: the residual and Jacobian at q again, a shorter pseudo step.
            tau = (0.25 * tau).max(TAU_MIN);
            norm = cx.ws.evaluate(cx.model, q, tg, true);
            rep.backtracks += 1;
        }
        let (rinf, _) = cx.ws.inf_norm();
        cx.ws.history.push(rinf);
    }
    rep.residual = cx.ws.inf_norm().0;
    Ok(rep)
}

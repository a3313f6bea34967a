//! The Newton stage: Newton–Raphson with fresh Jacobians, a Galerkin line search, and
//! Anderson-mixed chord iterations on each new factorisation.
//!
//! **Iterations.** A *Newton iteration* assembles the Jacobian at the iterate, factorises its
//! symmetric part and takes the update of `Linearization::newton` along a line search. The
//! factors and that Jacobian are then kept for *chord iterations*, Anderson-mixed
//! (`stepper/anderson.rs`) as in the held stage, as long as they contract: a chord
//! iteration costs one residual and one pair of triangular solves (plus a few BiCGStab
//! iterations where `J` is not symmetric), a Newton iteration about 20 of those on the
//! bundled shells. Once the residual grows, or its mean contraction since the Newton
//! iteration is worse than [`NewtonOptions::reuse_contraction`] per iteration, the next
//! iteration is a Newton iteration again. `reuse_contraction = 0` is plain Newton.
//!
//! **Chord iterations** solve with the lagged Jacobian `J(q_k)` itself, not only with its
//! symmetric factors: `Linearization::newton` corrects the update by BiCGStab wherever the
//! skew part makes `J_s⁻¹` too far from `J⁻¹`. With follower loads (the inflation pressure) that
//! skew part is large, and the uncorrected iteration contracts at `‖I − J J_s⁻¹‖`, which
//! crawled from 1e-3 to 1e-5 N over 20 iterations on a 30-gore canopy's opening until the
//! stage failed; corrected, it contracts at the lag of `J`
//! (docs/notes/performance-2026-12-06.md §Floors and the large canopy). The held stage stays
//! uncorrected: its factors' Jacobian is of an earlier step, and correcting towards it was
//! measured worse.
//!
//! **Forcing.** Each update is solved to the relative linear residual `η` (Dembo, Eisenstat
//! & Steihaug 1982): the Newton iteration's `η = (‖R‖/‖R₀‖)²` for quadratic convergence, but
//! never below `0.1 tol/‖R‖`, which is all that reaching the tolerance in one update needs
//! (asking for less made BiCGStab fail its 20 iterations near the end of a solve, and the
//! uncorrected update then crawled), and within [1e-12, 1e-3].
//!
//! **Descent.** Where the symmetric part is indefinite (a membrane buckling within the step)
//! its LBLᵀ update may point uphill (`R · Δ ≥ 0`). The matrix is then shifted by `μ W`,
//! `W = max(c_m M, −diag J)` per DOF (μ = 1, 4, 16 …, at most [`MAX_SHIFT`]), and
//! refactorised until the update descends: a Levenberg–Marquardt step, shorter and towards
//! the nearest solution of the step instead of a saddle. The mass metric alone cannot shift
//! a DOF of negligible inertia whose energy is concave (mid-edge bending's edge angle in a
//! sharp fold); its own negative diagonal can. Statics (`c_m = 0`) has no shift.
//! Except where the unshifted update at least halves `‖R‖∞` (one trial residual): with
//! follower loads (the inflation pressure) the step's solution itself can have an indefinite
//! symmetric part, and there the shifted iteration `(J + μ W)⁻¹ J` has negative
//! eigenvalues along the soft modes and walks away from the solution that Newton converges
//! to quadratically (measured on the guided round canopy: residual 5e-3 N growing to 9e-2 N
//! over 12 shifted iterations).
//!
//! **Line search.** Along an update `Δ` the step's merit `φ(α)` has the slope
//! `φ'(α) = R(q + α Δ) · Δ`: for conservative forces `φ` is the incremental potential, and
//! with drag it is the path integral of the residual along the line, which needs no energy
//! (Crisfield, *Non-linear finite element analysis of solids and structures* vol. 1, §9.3).
//! The full update is kept when `φ'(1) ≤ 0.8 |φ'(0)|` (the merit still falls at its end, or
//! has nearly reached its minimum on the line); otherwise the step shrinks to the secant root
//! of `φ'` between 0 and the last trial (clamped to [0.1, 0.9] of it). The search starts
//! no farther than the forces' step bound admits (contact's CCD: no iterate passes through a
//! surface, Li et al. 2020 §5).

use super::Ctx;
use crate::error::StepError;
use crate::stepper::convergence::Verdict;
use crate::stepper::options::{Stage, StepReport};
use crate::stepper::workspace::Target;

/// Accept the update when `φ'(α) ≤ LINE_TOL |φ'(0)|` (Crisfield's 0.8).
const LINE_TOL: f64 = 0.8;
/// An uphill Newton update is taken unshifted when it reduces `‖R‖∞` at least this much
/// (module docs, §Descent).
const CONTRACTS: f64 = 0.5;
/// Largest `μ` of a descent shift (module docs).
const MAX_SHIFT: f64 = 1024.0;
/// Largest forcing term of a Newton update (`Linearization::newton`): with chord iterations
/// to follow, a contraction of 1e-3 per update is plenty.
const ETA_MAX: f64 = 1e-3;
/// Smallest forcing term (below it BiCGStab's own round-off dominates).
const ETA_MIN: f64 = 1e-12;
/// An update need not be solved more accurately than it takes to end the stage: its linear
/// residual may be this fraction of the tolerance (module docs, §Forcing).
const FORCING_MARGIN: f64 = 0.1;

/// The forcing term of an update from an iterate of residual `rinf`: `quadratic` (the
/// Newton iteration's `(‖R‖/‖R₀‖)²`, or 0 for a chord iteration), but never below what it
/// takes to reach the tolerance `tol` in one update (module docs, §Forcing).
fn forcing(quadratic: f64, rinf: f64, tol: f64) -> f64 {
    quadratic
        .max(FORCING_MARGIN * tol / rinf)
        .clamp(ETA_MIN, ETA_MAX)
}

/// Solve the step from `q` (overwritten with the solution on success, an unspecified
/// iterate on failure) within `budget` iterations.
pub(crate) fn run(
    cx: &mut Ctx<'_>,
    tg: &Target<'_>,
    q: &mut [f64],
    budget: usize,
) -> Result<StepReport, StepError> {
    // With the Jacobian at once: the stage runs because the held stage (or the predictor)
    // left a residual above the tolerance, so its first iteration needs it, and one element
    // pass gives both.
    let (mut rep, tol, _) = cx.begin(Stage::Newton, tg, q, true);
    let rate = cx.opts.reuse_contraction;
    // Plain Newton assembles the Jacobian with every trial point (the next iteration needs
    // it); with chord iterations only where it refactorises.
    let jac_at_trials = rate <= 0.0;
    let mut jac_at_q = true;
    // Chord iterations since the last Newton iteration, and the residual they started from
    // (`None`: the next iteration is a Newton iteration).
    let mut chord: Option<(usize, f64)> = None;
    // The residual of the iterate before, and whether this stage measured the round-off.
    let (mut prev, mut probed) = (f64::INFINITY, false);
    loop {
        let rinf = match cx.conv.judge(cx.ws, q, tg, &tol, rep.iterations, budget)? {
            Verdict::Converged => break,
            Verdict::Continue(r) => r,
        };
        if rinf > 0.5 * prev && rinf <= 1e3 * tol.tol && !probed {
            // Stalled near the tolerance: perhaps on the residual's round-off, which the
            // estimate of `convergence.rs` can miss; measured once, then judged again.
            probed = true;
            cx.ws.measure_noise(cx.model, q, tg);
            continue;
        }
        prev = rinf;
        if let Some((k, r_ref)) = chord {
            if k >= 1 && rinf > r_ref {
                // A chord update that raised the residual is undone: the factors no longer
                // describe the step here, and the next Newton iteration starts from where
                // they still did.
                cx.mix.undo(q);
                jac_at_q = false;
                chord = None;
            } else if (k >= 2 && rinf > r_ref * rate.powi(k as i32)) || rep.iterations >= budget / 2
            {
                chord = None;
            }
        }
        rep.iterations += 1;
        let Some((k, r_ref)) = chord else {
            if !jac_at_q {
                cx.ws.evaluate(cx.model, q, tg, true);
            }
            // Forcing term ∝ ‖R‖²: the last iterations of plain Newton (no chord iterations)
            // overshoot the tolerance quadratically, as with an exact solve.
            let quadratic = (rinf / tol.r0.max(f64::MIN_POSITIVE)).powi(2);
            let eta = forcing(quadratic, rinf, tol.tol);
            let alpha = newton_iteration(cx, tg, q, eta, jac_at_trials, &mut rep)?;
            let step = alpha * cx.ws.delta_max().unwrap_or(f64::INFINITY);
            jac_at_q = jac_at_trials;
            let (r, _) = cx.ws.inf_norm();
            cx.ws.history.push(r);
            // Chord iterations follow a full Newton update only: where the line search had
            // to shorten it, the factors are not a good model of the step beyond.
            if rate > 0.0 && alpha == 1.0 {
                chord = Some((0, r));
                cx.mix.begin(cx.ws, q);
            }
            if cx.conv.stalled_at_tolerance(step, r, &tol) {
                break;
            }
            continue;
        };
        // The lagged Jacobian's update, not only its symmetric part's (module docs, §Chord
        // iterations).
        cx.lin.newton(cx.ws, forcing(0.0, rinf, tol.tol));
        cx.ws.delta_max().map_err(|dof| StepError::NonFinite {
            what: "chord update",
            dof,
        })?;
        cx.mix.step(cx.ws, cx.model, q);
        cx.ws.evaluate(cx.model, q, tg, false);
        jac_at_q = false;
        let (r, _) = cx.ws.inf_norm();
        cx.ws.history.push(r);
        chord = Some((k + 1, r_ref));
    }
    rep.residual = cx.ws.inf_norm().0;
    Ok(rep)
}

/// One Newton iteration from `q`, whose Jacobian is in the workspace: factorise (shifted
/// until the update descends, module docs), update, line search; `q` moves to the accepted
/// point (its residual evaluated) and the step length `α` is returned.
fn newton_iteration(
    cx: &mut Ctx<'_>,
    tg: &Target<'_>,
    q: &mut [f64],
    eta: f64,
    jac_at_trials: bool,
    rep: &mut StepReport,
) -> Result<f64, StepError> {
    cx.lin.jacobian_changed();
    let mut shift = 0.0;
    loop {
        cx.lin.refresh(cx.ws, tg, shift);
        rep.factorizations += 1;
        cx.lin.newton(cx.ws, eta);
        cx.ws.delta_max().map_err(|dof| StepError::NonFinite {
            what: "Newton update",
            dof,
        })?;
        let descends = cx.ws.slope() < 0.0;
        if descends || !cx.opts.line_search || tg.c_m <= 0.0 || shift >= MAX_SHIFT {
            break;
        }
        let bounded = cx.ws.max_alpha(cx.model, q) < 1.0;
        if shift == 0.0 && !bounded && newton_contracts(cx, tg, q, jac_at_trials) {
            q.copy_from_slice(&cx.ws.q_trial);
            return Ok(1.0);
        }
        shift = if shift == 0.0 { 1.0 } else { 4.0 * shift };
    }
    let alpha = line_search(cx, tg, q, jac_at_trials, rep);
    q.copy_from_slice(&cx.ws.q_trial);
    Ok(alpha)
}

/// Whether the full Newton update from `q`, although uphill for the merit, at least halves
/// `‖R‖∞` (module docs, §Descent); if so its point is left in `ws.q_trial` with its residual
/// (and its Jacobian when `jac`), otherwise the residual at `q` is restored. One residual
/// evaluation.
fn newton_contracts(cx: &mut Ctx<'_>, tg: &Target<'_>, q: &[f64], jac: bool) -> bool {
    let r = cx.ws.inf_norm().0;
    cx.ws.save_residual();
    cx.ws.try_update(cx.model, q, tg, 1.0, false);
    let contracts = cx.ws.inf_norm().0 <= CONTRACTS * r;
    if !contracts {
        cx.ws.restore_residual();
    } else if jac {
        let qt = std::mem::take(&mut cx.ws.q_trial);
        cx.ws.evaluate(cx.model, &qt, tg, true);
        cx.ws.q_trial = qt;
    }
    contracts
}

/// The Galerkin line search along `ws.delta` from `q` (module docs): leaves the accepted
/// point in `ws.q_trial` with its residual evaluated, and returns its `α`.
fn line_search(
    cx: &mut Ctx<'_>,
    tg: &Target<'_>,
    q: &[f64],
    jac: bool,
    rep: &mut StepReport,
) -> f64 {
    let slope0 = cx.ws.slope();
    let search = cx.opts.line_search && slope0 < 0.0;
    // No farther than contact admits (`Force::max_step`): no iterate passes through.
    let mut alpha = cx.ws.max_alpha(cx.model, q);
    let mut points = 0;
    loop {
        cx.ws.try_update(cx.model, q, tg, alpha, jac);
        if !search || points >= cx.opts.max_backtracks {
            break;
        }
        let slope = cx.ws.slope();
        if slope.is_finite() && cx.ws.inf_norm().0.is_finite() && slope <= LINE_TOL * -slope0 {
            break;
        }
        // The secant root of φ' through (0, φ'(0)) and (α, φ'(α)); halving where φ'(α) is
        // not finite.
        let ratio = if slope.is_finite() {
            slope0 / (slope0 - slope)
        } else {
            0.5
        };
        alpha *= ratio.clamp(0.1, 0.9);
        points += 1;
    }
    rep.backtracks += points;
    cx.ws.counters.line_search_points += points as u64;
    alpha
}

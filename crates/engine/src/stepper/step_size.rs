//! The step-size policy of [`crate::ImplicitEuler::attempt`]: the size of the next step, what
//! an accepted step, a step rejected for its local error or a failed solve does to it, and
//! how a step is shortened to end exactly on the caller's next event.
//!
//! **Fixed step** ([`StepSizing::adaptive`] `None`): every step is the nominal `dt` except
//! where it must end on an event (shortened, or stretched by at most 0.1 % when the summed
//! time falls just short of it). A failed solve halves `dt` (retry from the same state);
//! after [`GROW_AFTER`] accepted steps in a row at a reduced `dt` it doubles back, up to the
//! nominal one; below [`StepSizing::min_dt`] the caller must stop.
//!
//! **Adaptive step**: after every accepted step the elementary controller
//! ([`ErrorController`]) proposes the next one from the step's local error estimate, and a
//! step whose error exceeds the tolerance is rejected and retried with the controller's
//! smaller step. Steps end exactly on events by shortening the step that would cross one;
//! when a full step would leave less than one more step before the event, the remaining time
//! is split into two equal steps instead of a full step and a sliver. The proposal itself is
//! remembered: a shortened step does not shrink the steps after it. After a step of the
//! proposed size, a new proposal within [1, [`HOLD_BAND`]] × that size keeps it, so that the
//! held factors (keyed on the step size) stay usable. A failed solve halves the step and caps
//! the proposals there, the cap doubling after every [`GROW_AFTER`] accepted steps.

use super::error_control::{error_norm, Decision, ErrorController};
use crate::error::EngineError;
use crate::model::Model;

/// Consecutive accepted steps before a reduced step (or, adaptive, the cap after a failed
/// solve) is doubled again.
pub const GROW_AFTER: u32 = 8;

/// Adaptive: after a step of the proposed size, a new proposal between that size and this
/// many times it keeps the size. Changing `h` changes `M/h²` in the Newton matrix and costs a
/// factorisation, which a slightly longer step does not repay (the 1.2 of Hairer & Wanner's
/// RADAU5, *Solving ODEs II* §IV.8). Shrinking is never held back.
pub const HOLD_BAND: f64 = 1.2;

/// How steps are sized.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepSizing {
    /// Nominal (fixed) or first (adaptive) step (s).
    pub dt: f64,
    /// Smallest step (s): a solve that fails at this size stops the run.
    pub min_dt: f64,
    /// Error control, or `None` for a fixed step.
    pub adaptive: Option<ErrorController>,
}

/// The policy's state: what a checkpoint must store to continue bit for bit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SizeState {
    /// Size the next step tries before it is shortened to an event (s): fixed, the current
    /// `dt`; adaptive, the controller's remembered proposal.
    pub h: f64,
    /// Adaptive: ceiling on the proposals after a failed solve (s; ∞ when none).
    pub cap: f64,
    /// Accepted steps since the last failure or regrowth.
    pub streak: u32,
    /// Steps rejected for their local error (adaptive).
    pub rejected_error: u64,
    /// Steps whose solve failed (each retried with half the step).
    pub rejected_newton: u64,
}

/// The next step: its size and, when it was shortened to end on an event, that event's time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plan {
    /// Step size (s).
    pub h: f64,
    /// The event time the step ends on, if it was planned to.
    pub lands_at: Option<f64>,
}

/// The step-size policy and its state.
#[derive(Debug, Clone)]
pub struct StepSizes {
    sizing: StepSizing,
    /// The state (public for checkpoints).
    pub state: SizeState,
}

impl StepSizes {
    /// The policy at the start of a run. Errors when a size is not positive and finite or
    /// `min_dt > dt`.
    pub fn new(sizing: StepSizing) -> Result<Self, EngineError> {
        let ok = |x: f64| x.is_finite() && x > 0.0;
        if !(ok(sizing.dt) && ok(sizing.min_dt) && sizing.min_dt <= sizing.dt) {
            return Err(crate::error::InvalidModel::StepSizing {
                dt: sizing.dt,
                min_dt: sizing.min_dt,
            }
            .into());
        }
        Ok(Self {
            sizing,
            state: SizeState {
                h: sizing.dt,
                cap: f64::INFINITY,
                streak: 0,
                rejected_error: 0,
                rejected_newton: 0,
            },
        })
    }

    /// The settings.
    pub fn sizing(&self) -> &StepSizing {
        &self.sizing
    }

    /// Whether the step is error-controlled.
    pub fn adaptive(&self) -> bool {
        self.sizing.adaptive.is_some()
    }

    /// The next step from time `t`, which must end at or before `event` (s) (module docs).
    pub fn plan(&self, t: f64, event: f64) -> Plan {
        let rest = event - t;
        let h = self.state.h;
        if !self.adaptive() {
            // `t` is a sum of steps, so after many steps it may fall short of the event by
            // more than round-off of one step: a last step within 0.1 % of `dt` is stretched
            // rather than followed by a sliver (whose velocity (q_{n+1} − q_n)/h would lose
            // digits).
            if rest <= h * (1.0 + 1e-3) {
                return Plan {
                    h: rest,
                    lands_at: Some(event),
                };
            }
            return Plan { h, lands_at: None };
        }
        if rest <= h * (1.0 + 1e-9) {
            // Within round-off of the proposal, keep it exactly (same factorisation).
            let h = if rest >= h * (1.0 - 1e-9) { h } else { rest };
            Plan {
                h,
                lands_at: Some(event),
            }
        } else if rest < 2.0 * h {
            Plan {
                h: 0.5 * rest,
                lands_at: None,
            }
        } else {
            Plan { h, lands_at: None }
        }
    }

    /// Judge a solved step by its local error estimate `e` (every DOF, m): `Ok((next, err))`
    /// to accept it with the controller's proposal `next` (s) and error norm `err`, `Err(())`
    /// to reject it (the policy then holds the retry size). Fixed steps are always accepted.
    #[allow(clippy::result_unit_err)]
    pub fn judge(&mut self, model: &Model, e: &[f64], plan: &Plan) -> Result<(f64, f64), ()> {
        let Some(ctrl) = &self.sizing.adaptive else {
            return Ok((self.state.h, 0.0));
        };
        let err = error_norm(model, e, ctrl.tol_m, ctrl.norm);
        match ctrl.propose_limited(plan.h, err, self.state.h) {
            Decision::Accept { next_h } => Ok((next_h, err)),
            Decision::Reject { retry_h } => {
                self.state.rejected_error += 1;
                self.state.h = retry_h;
                Err(())
            }
        }
    }

    /// Record an accepted step of size `h` with the controller's proposal `next`.
    pub fn accepted(&mut self, h: f64, next: f64) {
        let s = &mut self.state;
        // Holding only saves a factorisation when the step was the proposal itself (a step
        // shortened to an event was factorised for its own size anyway).
        let was_proposal = h == s.h;
        s.streak += 1;
        let Some(ctrl) = &self.sizing.adaptive else {
            if s.h < self.sizing.dt && s.streak >= GROW_AFTER {
                s.h = (2.0 * s.h).min(self.sizing.dt);
                s.streak = 0;
            }
            return;
        };
        if s.cap.is_finite() && s.streak >= GROW_AFTER {
            s.cap *= 2.0;
            s.streak = 0;
            if s.cap >= ctrl.h_max {
                s.cap = f64::INFINITY;
            }
        }
        let next = next.min(s.cap);
        if !(was_proposal && s.h <= next && next <= HOLD_BAND * s.h) {
            s.h = next;
        }
    }

    /// A step of size `h` failed to solve: halve (fixed: the current `dt`; adaptive: the
    /// failed step, which also becomes the cap). `false` when the new size is below the
    /// smallest allowed step (the caller must stop).
    pub fn solve_failed(&mut self, h: f64) -> bool {
        let adaptive = self.adaptive();
        let s = &mut self.state;
        s.streak = 0;
        s.rejected_newton += 1;
        if adaptive {
            s.h = 0.5 * h;
            s.cap = s.h;
        } else {
            s.h *= 0.5;
        }
        s.h >= self.sizing.min_dt
    }
}

#[cfg(test)]
mod tests;

//! The run loop's step-size policy: the size of the next step, where steps must end, and
//! what an accepted step, a step rejected for its local error or a failed Newton solve does
//! to the step size (docs/reliability.md §1, docs/engine.md §Adaptive time step).
//!
//! **Fixed step** (`time.adaptive = false`, the default): every step is `time.dt_s` except
//! the last, which ends exactly on `time.duration_s` (shortened, or stretched by at most
//! 0.1 % when the summed time falls just short of it). A failed Newton solve halves `dt`
//! (retry from the same state); after [`GROW_AFTER`] accepted steps in a row at a reduced `dt`
//! it doubles back, up to `time.dt_s`; below `dt_s/1024` the run stops.
//!
//! **Adaptive step** (`time.adaptive = true`): the first step is `time.dt_s`; after every
//! accepted step the elementary controller ([`engine::ErrorController`]) proposes the next
//! one from the step's local error estimate (filtered through the step's Newton matrix and
//! measured in `time.error_norm`, [`engine::stepper::error_control`]), and a step whose error
//! exceeds the tolerance is
//! rejected and retried with the controller's smaller step (counted, the state untouched).
//! Steps end exactly on the *events* — frame and snapshot times, sync points and the end —
//! by shortening the step that would cross one; when a full step would leave less than one
//! more step before the event, the remaining time is split into two equal steps instead of
//! a full step and a sliver. The proposal itself is remembered: a shortened step does not
//! shrink the steps after it. After a step of the proposed size, a new proposal within
//! [1, [`HOLD_BAND`]] × that size keeps it, so that the factorised Jacobian (keyed on the step
//! size) is reused. A failed Newton solve halves the step and caps the proposals there, the
//! cap doubling after every [`GROW_AFTER`] accepted steps, like the fixed-step policy.

use engine::stepper::error_control::{error_norm, Decision, ErrorController};
use engine::Model;

use super::RunConfig;
use crate::output::summary::Stepping;
use crate::output::timeseries::Sample;

/// Consecutive accepted steps before a reduced `dt` (or, adaptive, the cap after a Newton
/// failure) is doubled again.
pub const GROW_AFTER: u32 = 8;

/// Accepted steps' worth of nominal `dt` between *sync points*. At every sync point the run
/// loop drops the stepper's reused factorisation (modified Newton), so the next step starts
/// with a fresh Jacobian exactly as a resumed run does: checkpoints are only taken at sync
/// points, which makes a resumed run bit-identical to an uninterrupted one. One extra
/// factorisation every 64 steps costs ~1 % at most.
pub const SYNC_STEPS: f64 = 64.0;

/// Adaptive: after a step of the proposed size, a new proposal between that size and this
/// many times it keeps the size. Changing `h` changes `M/h²` in the Newton Jacobian and costs
/// a factorisation, which a slightly longer step does not repay (the 1.2 of Hairer & Wanner's
/// RADAU5, *Solving ODEs II* §IV.8). Shrinking is never held back.
pub const HOLD_BAND: f64 = 1.2;

/// The next step: its size and, when it was shortened to end on an event, that event's time
/// (the state's time is set to it exactly after the step).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Plan {
    /// Step size (s).
    pub h: f64,
    /// The event time the step ends on, if it was planned to.
    pub lands_at: Option<f64>,
}

/// The local-error verdict on a solved step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Verdict {
    /// Keep it; `next` is the controller's proposal (s), `err` the error norm.
    Accept { next: f64, err: f64 },
    /// Discard it and retry (the policy already holds the smaller step).
    Reject,
}

/// Sizes of the accepted steps (s): min, max and their sum in step order.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct DtStats {
    pub min: f64,
    pub max: f64,
    pub sum: f64,
    pub count: u64,
}

impl Default for DtStats {
    fn default() -> Self {
        Self {
            min: f64::INFINITY,
            max: 0.0,
            sum: 0.0,
            count: 0,
        }
    }
}

impl DtStats {
    fn record(&mut self, h: f64) {
        self.min = self.min.min(h);
        self.max = self.max.max(h);
        self.sum += h;
        self.count += 1;
    }

    /// The statistics of the steps in `rows` of `timeseries.csv` (the first row is the
    /// initial state, not a step): a resumed run rebuilds them bit for bit, in the same order.
    pub fn from_rows(rows: &[Sample]) -> Self {
        let mut s = Self::default();
        rows.iter().skip(1).for_each(|r| s.record(r.dt_s));
        s
    }

    /// `(min, mean, max)` (s), or `None` before the first step.
    pub fn summary(&self) -> Option<(f64, f64, f64)> {
        (self.count > 0).then(|| (self.min, self.sum / self.count as f64, self.max))
    }
}

/// The step-size policy and its state (what a checkpoint stores of it: `h`, `streak`,
/// `cap`, the rejection counters).
#[derive(Debug, Clone)]
pub(super) struct DtPolicy {
    nominal: f64,
    min_dt: f64,
    ctrl: Option<ErrorController>,
    /// Size the next step tries before it is shortened to an event (s): fixed, the current
    /// `dt`; adaptive, the controller's remembered proposal.
    pub h: f64,
    /// Adaptive: ceiling on the proposals after a failed Newton solve (s; ∞ when none).
    pub cap: f64,
    /// Accepted steps since the last failure or regrowth.
    pub streak: u32,
    /// Steps rejected for their local error (adaptive).
    pub rejected_error: u64,
    /// Steps rejected because Newton failed.
    pub rejected_newton: u64,
    /// Accepted step sizes.
    pub used: DtStats,
    /// Time tolerance (s): events closer than this count as reached, and the run ends within
    /// it of the duration.
    pub time_tol: f64,
    /// An output is written when the time is within this of its time (s): half a step with a
    /// fixed step (the nearest step), `time_tol` when steps end on the output times.
    pub due_tol: f64,
    /// Simulated time between sync points (s).
    pub sync_dt: f64,
}

impl DtPolicy {
    /// The policy of `cfg` at the start of a run.
    pub fn new(cfg: &RunConfig) -> Result<Self, engine::EngineError> {
        let (ctrl, min_dt, time_tol, due_tol, sync_dt) = match cfg.adaptive {
            None => {
                let tol = 1e-9 * cfg.dt_s;
                (
                    None,
                    cfg.min_dt_s,
                    tol,
                    0.5 * cfg.dt_s,
                    SYNC_STEPS * cfg.dt_s,
                )
            }
            Some(a) => {
                let mut ctrl = ErrorController::new(a.error_tolerance_m, a.dt_min_s, a.dt_max_s)?;
                ctrl.norm = a.error_norm;
                // Far below any step, far above the round-off of times up to the duration.
                let tol = (1e-3 * a.dt_min_s).max(64.0 * f64::EPSILON * cfg.duration_s);
                (
                    Some(ctrl),
                    a.dt_min_s,
                    tol,
                    tol,
                    adaptive_sync_interval(cfg, a.dt_max_s),
                )
            }
        };
        Ok(Self {
            nominal: cfg.dt_s,
            min_dt,
            ctrl,
            h: cfg.dt_s,
            cap: f64::INFINITY,
            streak: 0,
            rejected_error: 0,
            rejected_newton: 0,
            used: DtStats::default(),
            time_tol,
            due_tol,
            sync_dt,
        })
    }

    /// Whether the step is error-controlled.
    pub fn adaptive(&self) -> bool {
        self.ctrl.is_some()
    }

    /// The frame time after `prev` with frame interval `iv` (s). Adaptive runs end steps on
    /// frame times, so these must match the sync times `k · sync_dt` to round-off: they are
    /// computed as multiples of `iv`, not accumulated.
    pub fn next_frame_after(&self, prev: f64, iv: f64) -> f64 {
        if self.adaptive() {
            ((prev / iv).round() + 1.0) * iv
        } else {
            prev + iv
        }
    }

    /// The next step from time `t`, which must end at or before `event` (s): the end of the
    /// run with a fixed step; the first event after `t` when adaptive (module docs).
    pub fn plan(&self, t: f64, event: f64) -> Plan {
        let rest = event - t;
        if !self.adaptive() {
            // The last step ends exactly on the end time. `t` is a sum of steps, so after many
            // steps it may fall short of the end by more than round-off of one step: a last
            // step within 0.1 % of `dt` is stretched rather than followed by a sliver step
            // (whose velocity (q_{n+1} − q_n)/h would lose digits).
            if rest <= self.h * (1.0 + 1e-3) {
                return Plan {
                    h: rest,
                    lands_at: Some(event),
                };
            }
            return Plan {
                h: self.h,
                lands_at: None,
            };
        }
        let h = self.h;
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

    /// Judge a solved step by its local error estimate `e` (every DOF, m; the trial's
    /// [`engine::Trial::local_error`]); on a rejection the policy holds the retry size. Fixed
    /// steps are always accepted.
    pub fn judge(&mut self, model: &Model, e: &[f64], plan: &Plan) -> Verdict {
        let Some(ctrl) = &self.ctrl else {
            return Verdict::Accept {
                next: self.h,
                err: 0.0,
            };
        };
        let err = error_norm(model, e, ctrl.tol_m, ctrl.norm);
        match ctrl.propose_limited(plan.h, err, self.h) {
            Decision::Accept { next_h } => Verdict::Accept { next: next_h, err },
            Decision::Reject { retry_h } => {
                self.rejected_error += 1;
                self.h = retry_h;
                Verdict::Reject
            }
        }
    }

    /// Record an accepted step of size `h` with the controller's proposal `next`.
    pub fn accepted(&mut self, h: f64, next: f64) {
        // Holding only saves a factorisation when the step was the proposal itself (a step
        // shortened to an event was factorised for its own size anyway).
        let was_proposal = h == self.h;
        self.used.record(h);
        self.streak += 1;
        let Some(ctrl) = &self.ctrl else {
            if self.h < self.nominal && self.streak >= GROW_AFTER {
                self.h = (2.0 * self.h).min(self.nominal);
                self.streak = 0;
            }
            return;
        };
        if self.cap.is_finite() && self.streak >= GROW_AFTER {
            self.cap *= 2.0;
            self.streak = 0;
            if self.cap >= ctrl.h_max {
                self.cap = f64::INFINITY;
            }
        }
        let next = next.min(self.cap);
        if !(was_proposal && self.h <= next && next <= HOLD_BAND * self.h) {
            self.h = next;
        }
    }

    /// The time-stepping settings of `cfg` and the statistics so far, for the summary.
    pub fn stepping(&self, cfg: &RunConfig) -> Stepping {
        let used = self.used.summary();
        Stepping {
            dt_s: cfg.dt_s,
            adaptive: cfg.adaptive.is_some(),
            error_tolerance_m: cfg.adaptive.map(|a| a.error_tolerance_m),
            dt_min_s: self.min_dt,
            dt_max_s: self.ctrl.map_or(self.nominal, |c| c.h_max),
            rejected_steps_error: self.rejected_error,
            rejected_steps_newton: self.rejected_newton,
            dt_used_min_s: used.map(|u| u.0),
            dt_used_mean_s: used.map(|u| u.1),
            dt_used_max_s: used.map(|u| u.2),
        }
    }

    /// A step of size `h` failed in Newton: halve (fixed: the current `dt`; adaptive: the
    /// failed step, which also becomes the cap). `false` when the new size is below the
    /// smallest allowed step (the run must stop).
    pub fn newton_failed(&mut self, h: f64) -> bool {
        self.streak = 0;
        self.rejected_newton += 1;
        if self.adaptive() {
            self.h = 0.5 * h;
            self.cap = self.h;
        } else {
            self.h *= 0.5;
        }
        self.h >= self.min_dt
    }
}

/// Adaptive sync interval (s): at least [`SYNC_STEPS`] first steps and at least one longest
/// step, rounded up to whole frame intervals so that sync points fall on frame times (steps
/// end on both; sync points between frames would cut one more step per interval).
fn adaptive_sync_interval(cfg: &RunConfig, dt_max: f64) -> f64 {
    let base = (SYNC_STEPS * cfg.dt_s).max(dt_max);
    let iv = cfg.frame_interval_s;
    if iv > 0.0 {
        (base / iv - 1e-9).ceil().max(1.0) * iv
    } else {
        base
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenario::AdaptiveSettings;

    fn cfg(adaptive: bool) -> RunConfig {
        RunConfig {
            name: "t".into(),
            guidance: None,
            dt_s: 1e-3,
            min_dt_s: 1e-3 / 1024.0,
            adaptive: adaptive.then_some(AdaptiveSettings {
                error_tolerance_m: 1e-5,
                dt_min_s: 1e-5,
                dt_max_s: 0.05,
                error_norm: engine::ErrorNorm::MassRms,
                error_filter: true,
            }),
            duration_s: 10.0,
            frame_interval_s: 0.05,
            snapshots_s: vec![],
            newton: engine::NewtonOptions::default(),
            air_density: 1.225,
            air_viscosity: 1.81e-5,
            quadratic_drag: true,
            air: engine::aero::Fluid::air(),
            altitude_m: 0.0,
            ground_z_m: None,
            gravity_mps2: 9.81,
            scenario_warnings: Vec::new(),
            progress: false,
        }
    }

    #[test]
    fn fixed_last_step_lands_exactly_on_the_end() {
        let p = DtPolicy::new(&cfg(false)).unwrap();
        // A summed time 1e-10 s short of a whole step: stretched, not followed by a sliver.
        let t = 10.0 - 1e-3 - 1e-10;
        let plan = p.plan(t, 10.0);
        assert_eq!(plan.lands_at, Some(10.0));
        assert_eq!(plan.h, 10.0 - t);
        // A partial last step is shortened; an ordinary one is dt.
        assert_eq!(p.plan(10.0 - 4e-4, 10.0).lands_at, Some(10.0));
        assert_eq!(
            p.plan(9.9, 10.0),
            Plan {
                h: 1e-3,
                lands_at: None
            }
        );
        assert_eq!(p.sync_dt, 0.064);
        assert_eq!(p.due_tol, 0.5e-3);
    }

    #[test]
    fn adaptive_steps_end_on_events_without_slivers() {
        let mut p = DtPolicy::new(&cfg(true)).unwrap();
        p.h = 0.01;
        // Shortened to the event.
        assert_eq!(
            p.plan(1.0, 1.005),
            Plan {
                h: 1.005 - 1.0,
                lands_at: Some(1.005)
            }
        );
        // Less than two steps left: two equal steps, not a step and a 5 ms sliver.
        assert_eq!(p.plan(1.0, 1.015).h, 0.5 * (1.015 - 1.0));
        assert_eq!(p.plan(1.0, 1.015).lands_at, None);
        assert_eq!(p.plan(1.0, 1.03).h, 0.01);
        // Within round-off of the proposal: the proposal itself (same factorisation).
        let plan = p.plan(1.0, 1.0 + 0.01 * (1.0 + 1e-12));
        assert_eq!(plan.h.to_bits(), 0.01f64.to_bits());
        assert!(plan.lands_at.is_some());
        // Sync points fall on frames: max(64 dt, dt_max) = 0.064 s → 2 frames of 0.05 s.
        assert!((p.sync_dt - 0.1).abs() < 1e-15);
        assert_eq!(p.due_tol, p.time_tol);
        assert!(p.time_tol > 0.0 && p.time_tol <= 1e-3 * 1e-5);
    }

    #[test]
    fn adaptive_hold_band_and_shortened_steps() {
        let mut p = DtPolicy::new(&cfg(true)).unwrap();
        p.h = 0.01;
        // After a step of the proposed size: +10 % is held, +30 % and −10 % are taken.
        p.accepted(0.01, 0.011);
        assert_eq!(p.h, 0.01);
        p.accepted(0.01, 0.013);
        assert_eq!(p.h, 0.013);
        p.accepted(0.013, 0.0117);
        assert_eq!(p.h, 0.0117);
        // After a shortened step the proposal is taken as is (nothing to reuse).
        p.accepted(0.004, 0.0125);
        assert_eq!(p.h, 0.0125);
        assert_eq!(p.used.count, 4);
        assert_eq!((p.used.min, p.used.max), (0.004, 0.013));
    }

    #[test]
    fn adaptive_newton_failure_halves_and_caps() {
        let mut p = DtPolicy::new(&cfg(true)).unwrap();
        p.h = 0.008;
        assert!(p.newton_failed(0.008));
        assert_eq!((p.h, p.cap, p.rejected_newton), (0.004, 0.004, 1));
        // The controller would grow; the cap holds for GROW_AFTER steps, then doubles.
        for _ in 0..GROW_AFTER - 1 {
            p.accepted(p.h, 1.0);
            assert_eq!(p.h, 0.004);
        }
        p.accepted(p.h, 1.0);
        assert_eq!((p.cap, p.h), (0.008, 0.008));
        // Once the cap reaches dt_max it is lifted.
        for _ in 0..3 * GROW_AFTER {
            p.accepted(p.h, 1.0);
        }
        assert_eq!(p.cap, f64::INFINITY);
        // Below dt_min the run must stop.
        p.h = 1.5e-5;
        assert!(!p.newton_failed(1.5e-5));
    }

    #[test]
    fn judge_rejects_and_holds_the_retry() {
        use engine::{DofLayout, Model};
        let mut p = DtPolicy::new(&cfg(true)).unwrap();
        p.h = 0.01;
        let mut model = Model::new(DofLayout::new(1, 0));
        model.add_node_mass(0, 1.0);
        let plan = Plan {
            h: 0.01,
            lands_at: None,
        };
        // e = 8e-5 m = 8 tol → reject, retry 0.9/√8 h.
        let v = p.judge(&model, &[0.0, 0.0, -8e-5], &plan);
        assert_eq!(v, Verdict::Reject);
        assert_eq!(p.rejected_error, 1);
        assert!((p.h - 0.01 * 0.9 / 8f64.sqrt()).abs() < 1e-12);
        // Within tolerance: accepted with the controller's proposal.
        let plan = Plan { h: p.h, ..plan };
        match p.judge(&model, &[0.0, 0.0, -5e-7], &plan) {
            Verdict::Accept { err, next } => assert!(err < 1.0 && next > plan.h),
            v => panic!("{v:?}"),
        }
        // A fixed step is never judged.
        let mut f = DtPolicy::new(&cfg(false)).unwrap();
        let v = f.judge(&model, &[0.0, 0.0, -1e3], &plan);
        assert!(matches!(v, Verdict::Accept { .. }));
    }
}

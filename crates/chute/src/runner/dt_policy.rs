//! The run loop's side of step sizes: the engine's step-size policy
//! ([`engine::StepSizes`]: fixed or error-controlled steps, halving after a failed solve,
//! regrowth, events; docs/engine.md §Step sizes) with the run's events — frame and snapshot
//! times, sync points and the end — and the statistics of the steps taken
//! (docs/reliability.md §1).

use engine::{ErrorController, StepSizes, StepSizing};

use super::RunConfig;
use crate::output::summary::Stepping;
use crate::output::timeseries::Sample;

/// Accepted steps' worth of nominal `dt` between *sync points*. At every sync point the run
/// loop drops the stepper's reused factorisation (modified Newton), so the next step starts
/// with a fresh Jacobian exactly as a resumed run does: checkpoints are only taken at sync
/// points, which makes a resumed run bit-identical to an uninterrupted one. One extra
/// factorisation every 64 steps costs ~1 % at most.
pub const SYNC_STEPS: f64 = 64.0;

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
    pub fn record(&mut self, h: f64) {
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

/// The step-size policy of a run (what a checkpoint stores of it: the engine policy's
/// [`engine::stepper::SizeState`]) and the run's time tolerances.
#[derive(Debug, Clone)]
pub(super) struct DtPolicy {
    /// The engine's step-size policy and its state.
    pub sizes: StepSizes,
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
        let (ctrl, min_dt, time_tol, due_tol, sync_dt) = match cfg.stepping.adaptive {
            None => {
                let tol = 1e-9 * cfg.stepping.dt_s;
                (
                    None,
                    cfg.stepping.min_dt_s,
                    tol,
                    0.5 * cfg.stepping.dt_s,
                    SYNC_STEPS * cfg.stepping.dt_s,
                )
            }
            Some(a) => {
                let mut ctrl = ErrorController::new(a.error_tolerance_m, a.dt_min_s, a.dt_max_s)?;
                ctrl.norm = a.error_norm;
                // Far below any step, far above the round-off of times up to the duration.
                let tol = (1e-3 * a.dt_min_s).max(64.0 * f64::EPSILON * cfg.stepping.duration_s);
                (
                    Some(ctrl),
                    a.dt_min_s,
                    tol,
                    tol,
                    adaptive_sync_interval(cfg, a.dt_max_s),
                )
            }
        };
        let sizes = StepSizes::new(StepSizing {
            dt: cfg.stepping.dt_s,
            min_dt: min_dt.min(cfg.stepping.dt_s),
            adaptive: ctrl,
        })?;
        Ok(Self {
            sizes,
            used: DtStats::default(),
            time_tol,
            due_tol,
            sync_dt,
        })
    }

    /// The time of sync point `k` (s): [`multiple`] of `sync_dt`.
    pub fn sync_time(&self, k: u64) -> f64 {
        multiple(k as f64, self.sync_dt)
    }

    /// Whether the step is error-controlled.
    pub fn adaptive(&self) -> bool {
        self.sizes.adaptive()
    }

    /// The frame time after `prev` with frame interval `iv` (s). Adaptive runs end steps on
    /// frame times, so these must match the sync times ([`DtPolicy::sync_time`]) to
    /// round-off: they are computed as multiples of `iv` ([`multiple`]), not accumulated.
    pub fn next_frame_after(&self, prev: f64, iv: f64) -> f64 {
        if self.adaptive() {
            multiple((prev / iv).round() + 1.0, iv)
        } else {
            prev + iv
        }
    }

    /// The time-stepping settings of `cfg` and the statistics so far, for the summary.
    pub fn stepping(&self, cfg: &RunConfig) -> Stepping {
        let used = self.used.summary();
        let sizing = self.sizes.sizing();
        let st = &self.sizes.state;
        Stepping {
            dt_s: cfg.stepping.dt_s,
            adaptive: cfg.stepping.adaptive.is_some(),
            error_tolerance_m: cfg.stepping.adaptive.map(|a| a.error_tolerance_m),
            dt_min_s: sizing.min_dt,
            dt_max_s: sizing.adaptive.map_or(sizing.dt, |c| c.h_max),
            rejected_steps_error: st.rejected_error,
            rejected_steps_newton: st.rejected_newton,
            dt_used_min_s: used.map(|u| u.0),
            dt_used_mean_s: used.map(|u| u.1),
            dt_used_max_s: used.map(|u| u.2),
        }
    }
}

/// Adaptive sync interval (s): at least [`SYNC_STEPS`] first steps and at least one longest
/// step, rounded up to whole frame intervals so that sync points fall on frame times (steps
/// end on both; sync points between frames would cut one more step per interval).
fn adaptive_sync_interval(cfg: &RunConfig, dt_max: f64) -> f64 {
    let base = (SYNC_STEPS * cfg.stepping.dt_s).max(dt_max);
    let iv = cfg.outputs.frame_interval_s;
    if iv > 0.0 {
        (base / iv - 1e-9).ceil().max(1.0) * iv
    } else {
        base
    }
}

/// `k · step`, computed as `k / n` when `step` is `1/n` for a whole `n` (0.1, 0.05, 0.02 …):
/// then 3 × 0.1 is the `0.3` a duration written as `0.3` is, not 0.30000000000000004, so a
/// run that ends there and one that passes through it take the same steps (a resumed
/// extension stays bit-identical to the longer run).
pub(super) fn multiple(k: f64, step: f64) -> f64 {
    let n = (1.0 / step).round();
    if n >= 1.0 && (1.0 / n - step).abs() <= 4.0 * f64::EPSILON * step {
        k / n
    } else {
        k * step
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
            triggers: None,
            stepping: crate::runner::Stepping {
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
            },
            outputs: crate::runner::Outputs {
                frame_interval_s: 0.05,
                snapshots_s: vec![],
            },
            newton: engine::NewtonOptions::default(),
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
    fn fixed_step_tolerances_and_sync_interval() {
        let p = DtPolicy::new(&cfg(false)).unwrap();
        assert_eq!(p.sync_dt, 0.064);
        assert_eq!(p.due_tol, 0.5e-3);
        assert!(!p.adaptive());
    }

    #[test]
    fn adaptive_sync_points_fall_on_frames() {
        let p = DtPolicy::new(&cfg(true)).unwrap();
        // Sync points fall on frames: max(64 dt, dt_max) = 0.064 s → 2 frames of 0.05 s.
        assert!((p.sync_dt - 0.1).abs() < 1e-15);
        assert_eq!(p.due_tol, p.time_tol);
        assert!(p.time_tol > 0.0 && p.time_tol <= 1e-3 * 1e-5);
        // Frame times are multiples of the interval, not sums.
        assert_eq!(p.next_frame_after(0.15000000000000002, 0.05), 0.2);
    }
}

//! A run in flight, without its files: the step-size policy, the counters and warnings, the
//! output and sync times it must stop on, the observed series and the ground watch.
//!
//! The run loop ([`super::simulate_with`]) writes its outputs around a [`Flight`]; a
//! [`super::Session`] (the Python `Simulation`) drives one and writes nothing. Both therefore
//! take the same steps, book them alike and stop at the same ground, and a session stepped to
//! the end has the run's state bit for bit and its summary but for the wall times (the
//! solver counts are equal too).

use engine::{ImplicitEuler, StepError};

use super::advance::{self, Outcome};
use super::dt_policy::DtPolicy;
use super::observe::Observer;
use super::{failure_message, recovery, RunConfig, RunError};
use crate::build::Built;
use crate::metrics::landing::{GroundWatch, Landing};
use crate::metrics::{self, Metrics};
use crate::output::summary::{RunInfo, SolverCounters, Summary};
use crate::output::timeseries::{DecimatedSeries, Sample};

/// At most this many step warnings (rejections, accepted over-tolerance steps) are kept.
const MAX_STEP_WARNINGS: usize = 20;

/// The bookkeeping of a run between its start and its summary.
pub(super) struct Flight {
    /// The step-size policy (fixed or adaptive) and its statistics.
    pub dt: DtPolicy,
    /// Accepted steps.
    pub steps: u64,
    /// Newton iterations over the accepted steps.
    pub newton_total: u64,
    /// The scenario's warnings, then the step warnings.
    pub warnings: Vec<String>,
    /// The next frame time (s).
    pub next_frame: f64,
    /// Snapshot times, sorted (s).
    pub snaps: Vec<f64>,
    /// Index of the next snapshot due in `snaps`.
    pub snap_idx: usize,
    /// Whether the flight draws its snapshots (a run does; a [`super::session::Session`]
    /// only ends its steps on their times, and so never warns of one not drawn).
    pub draws_snapshots: bool,
    /// Index of the next sync point (its time is `dt.sync_time(next_sync)`).
    pub next_sync: u64,
    /// Observation buffers.
    pub obs: Observer,
    /// The decimated series the metrics are computed from.
    pub dec: DecimatedSeries,
    ground: Option<GroundWatch>,
    guidance: Option<crate::control::Controller>,
    triggers: Option<crate::control::Triggers>,
    /// The touchdown, once the landing body has reached the ground.
    pub landing: Option<Landing>,
    /// The Newton solves' counters before this flight's stepper was made: zero at the
    /// start, a checkpoint's on resume; `None` when unknown (resumed from a checkpoint that
    /// did not record them), and then the summary reports none.
    pub solver_before: Option<SolverCounters>,
}

/// The warning of a summary without solver counters.
pub(super) const SOLVER_UNKNOWN: &str = "solver counters not reported (\"solver\": null): the run was resumed from a checkpoint without counters of this step solver (checkpoint format < 7), so the solves before it are unknown";

/// What one attempt at a step did.
pub(super) enum Attempt {
    /// Accepted, committed and booked: its Newton iterations and its sample.
    Accepted(usize, Sample),
    /// Rejected for its local error; retry with the policy's smaller step.
    Rejected,
    /// The solve failed at the smallest step allowed: the run stops for this reason (state
    /// unchanged).
    Failed(String),
}

/// The outputs due at the current time (the flight has moved past them).
pub(super) struct Due {
    /// A VTK frame.
    pub frame: bool,
    /// These snapshot times.
    pub snaps: Vec<f64>,
}

impl Flight {
    /// The bookkeeping at the start of a run of `built` under `cfg`, before any sample.
    pub fn new(built: &Built, cfg: &RunConfig) -> Result<Self, RunError> {
        let mut snaps = cfg.outputs.snapshots_s.clone();
        snaps.sort_by(f64::total_cmp);
        Ok(Self {
            dt: DtPolicy::new(cfg)?,
            steps: 0,
            newton_total: 0,
            warnings: cfg.scenario_warnings.clone(),
            next_frame: 0.0,
            snaps,
            snap_idx: 0,
            draws_snapshots: true,
            next_sync: 1,
            obs: Observer::new(built),
            dec: DecimatedSeries::default(),
            ground: cfg.ground_z_m.map(GroundWatch::new),
            guidance: cfg.guidance.clone(),
            triggers: cfg.triggers.clone(),
            landing: None,
            solver_before: Some(SolverCounters::default()),
        })
    }

    /// Start the payload's acceleration and the ground watch from `built.state` (a fresh or
    /// resumed start).
    pub fn start_watches(&mut self, built: &mut Built) {
        let s = &built.state;
        self.obs.start(built, s);
        self.obs.load(&s.q, &s.v);
        if let Some(g) = &mut self.ground {
            self.landing = g.observe(self.obs.ground_body(built, s.t));
        }
        if let (Some(tr), Some(lines)) = (&mut self.triggers, &built.lines) {
            let body = self.obs.ground_body(built, built.state.t);
            tr.start(&body, lines, &mut built.model);
        }
    }

    /// The first event after time `t` where an adaptive step must end: the end of the run,
    /// the next frame, snapshot and sync point. A fixed step only ends on the end.
    pub fn next_event(&self, t: f64, cfg: &RunConfig) -> f64 {
        if !self.dt.adaptive() {
            return cfg.stepping.duration_s;
        }
        let after = t + self.dt.time_tol;
        let frame = if cfg.outputs.frame_interval_s > 0.0 {
            self.next_frame
        } else {
            f64::INFINITY
        };
        let snap = self.snaps.get(self.snap_idx).copied();
        let sync = self.dt.sync_time(self.next_sync);
        [frame, snap.unwrap_or(f64::INFINITY), sync]
            .into_iter()
            .filter(|&e| e > after)
            .fold(cfg.stepping.duration_s, f64::min)
    }

    /// Attempt the next step from `built.state` (ending on the next event), judge its local
    /// error, and commit and book it (counters, sample, ground) or leave the state unchanged.
    pub fn attempt(
        &mut self,
        stepper: &mut ImplicitEuler,
        built: &mut Built,
        cfg: &RunConfig,
    ) -> Attempt {
        let event = self.next_event(built.state.t, cfg);
        let b = &mut *built;
        let (h, iterations, err) =
            match advance::attempt(&mut self.dt, stepper, &mut b.model, &mut b.state, event) {
                Outcome::Accepted { h, report, err } => (h, report.iterations, err),
                Outcome::Rejected => return Attempt::Rejected,
                Outcome::Halved(e, h) => {
                    self.halved(built, &e, h);
                    return Attempt::Rejected;
                }
                Outcome::Failed(e) => {
                    let t = built.state.t;
                    return Attempt::Failed(failure_message(built, &e, t, self.dt.sizes.state.h));
                }
            };
        let t = built.state.t;
        if err > 1.0 && self.warnings.len() < MAX_STEP_WARNINGS {
            // Accepted only because the step is already the smallest allowed.
            self.warnings.push(format!(
                "local error {err:.3} × the tolerance accepted at t = {t:.6} s: dt = {h:.3e} s is the smallest step allowed"
            ));
        }
        self.steps += 1;
        self.newton_total += iterations as u64;
        let s = self.obs.sample(built, &built.state, iterations as u32, h);
        self.dec.push(&s);
        if let Some(g) = &mut self.ground {
            self.landing = g.observe(self.obs.ground_body(built, t));
        }
        if let (Some(tr), Some(lines)) = (&mut self.triggers, &built.lines) {
            // Between steps, like guidance: the next step sees the firing.
            let body = self.obs.ground_body(built, t);
            tr.after_step(&body, lines, &mut built.model);
        }
        if let Some(c) = &self.guidance {
            // Between steps: the next step sees the new commands (docs/control.md).
            c.after_step(built);
        }
        Attempt::Accepted(iterations, s)
    }

    /// The warning of a step of size `h` whose solve failed and was halved.
    fn halved(&mut self, built: &Built, e: &StepError, h: f64) {
        let t = built.state.t;
        if self.warnings.len() < MAX_STEP_WARNINGS {
            self.warnings.push(format!(
                "step rejected at t = {t:.6} s ({e}); dt {h:.3e} s halved to {:.3e} s",
                self.dt.sizes.state.h
            ));
        }
    }

    /// The frame and snapshots due at time `t`, moving past them.
    pub fn take_due(&mut self, t: f64, cfg: &RunConfig) -> Due {
        let half = self.dt.due_tol;
        let iv = cfg.outputs.frame_interval_s;
        let frame = iv > 0.0 && t >= self.next_frame - half;
        if frame {
            while self.next_frame <= t + half {
                self.next_frame = self.dt.next_frame_after(self.next_frame, iv);
            }
        }
        let first = self.snap_idx;
        while self.snap_idx < self.snaps.len() && t >= self.snaps[self.snap_idx] - half {
            self.snap_idx += 1;
        }
        Due {
            frame,
            snaps: self.snaps[first..self.snap_idx].to_vec(),
        }
    }

    /// Whether time `t` is at or past the next sync point; if so, the next one is set. The
    /// caller drops the stepper's factorisation there (and may checkpoint).
    pub fn passed_sync(&mut self, t: f64) -> bool {
        let (sync_dt, tol) = (self.dt.sync_dt, self.dt.time_tol);
        if t < self.dt.sync_time(self.next_sync) - tol {
            return false;
        }
        self.next_sync = ((t + tol) / sync_dt).floor() as u64 + 1;
        true
    }

    /// The warnings of a run that ended at time `t`: the step warnings and one for all
    /// snapshots not drawn.
    pub fn final_warnings(&self, t: f64) -> Vec<String> {
        let mut warnings = self.warnings.clone();
        let missed = &self.snaps[self.snap_idx..];
        if self.draws_snapshots && !missed.is_empty() {
            // One warning for all of them: a short run with the default snapshot times would
            // otherwise repeat the same sentence.
            let times: Vec<String> = missed.iter().map(|t| format!("{t} s")).collect();
            warnings.push(format!(
                "snapshot{} at {} not drawn: the run ended at {t:.6} s",
                if missed.len() > 1 { "s" } else { "" },
                times.join(", "),
            ));
        }
        warnings
    }

    /// The summary of the flight so far (`info` says how it ended) and, when they could be
    /// computed, the descent metrics.
    pub fn summary(
        &self,
        built: &Built,
        cfg: &RunConfig,
        info: RunInfo,
    ) -> (Summary, Option<Metrics>) {
        let (rho, mu) = recovery::window_air(&self.dec, cfg);
        let params = metrics::Params {
            total_weight_n: built.total_weight_n,
            air_density_kg_m3: rho,
            air_viscosity_pa_s: mu,
            reference_length_m: built.reference_length_m,
            quadratic_drag: cfg.quadratic_drag,
            wind_mps: cfg.air.wind,
        };
        match metrics::compute(&self.dec.series(), &params) {
            Ok(m) => {
                let recovery = metrics::descent::compute(
                    &self.dec.recovery_series(),
                    &recovery::params(built, cfg),
                    m.terminal_velocity_mps,
                    m.drag_area_m2,
                    self.landing,
                );
                let recovery = match (&self.guidance, self.landing) {
                    (Some(c), Some(l)) => crate::metrics::descent::Recovery {
                        landing_miss_m: Some(c.miss_m(l.point_m)),
                        ..recovery
                    },
                    _ => recovery,
                };
                let triggers = self.trigger_records(built);
                let s = Summary::new(info, &m).with_recovery(recovery);
                (s.with_triggers(triggers), Some(m))
            }
            Err(e) => {
                let mut info = info;
                info.warnings.push(format!("metrics unavailable: {e}"));
                let undefined = Metrics::undefined(built.total_weight_n);
                let s = Summary::new(info, &undefined);
                (s.with_triggers(self.trigger_records(built)), None)
            }
        }
    }

    /// The record of every sensor-started pull (empty without one).
    pub fn trigger_records(&self, built: &Built) -> Vec<crate::control::TriggerRecord> {
        match (&self.triggers, &built.lines) {
            (Some(tr), Some(lines)) => tr.records(lines, &built.model),
            _ => Vec::new(),
        }
    }

    /// The solver counters of the whole run so far, the stepper's `counters` (since the
    /// flight's start or resume) included; `None` when the part before a resume is unknown.
    pub fn solver(&self, counters: &SolverCounters) -> Option<SolverCounters> {
        self.solver_before.map(|before| before.merge(counters))
    }

    /// The run record of the summary: how it ended and what it cost.
    pub fn info(&self, built: &Built, cfg: &RunConfig, end: End) -> RunInfo {
        let solver = self.solver(&end.counters);
        let mut warnings = if end.ended {
            let t = built.state.t;
            let records = self.trigger_records(built);
            let idle = match &self.triggers {
                Some(tr) => tr.warnings(&records, t),
                None => Vec::new(),
            };
            self.final_warnings(t).into_iter().chain(idle).collect()
        } else {
            self.warnings.clone()
        };
        match &solver {
            None => warnings.push(SOLVER_UNKNOWN.to_string()),
            Some(c) => warnings.extend(wasted_work(
                c,
                self.newton_total,
                self.dt.sizes.state.rejected_newton,
            )),
        }
        RunInfo {
            scenario_name: cfg.name.clone(),
            complete: end.complete,
            stop_reason: end.stop_reason,
            simulated_time_s: built.state.t,
            steps: self.steps,
            newton_iterations: self.newton_total,
            wall_time_s: end.wall_time_s,
            dofs: built.model.n_dofs(),
            stepping: self.dt.stepping(cfg),
            solver,
            warnings,
            canopy_weight_n: Some(built.canopy_weight_n),
        }
    }
}

/// The share of Newton iterations spent on attempts that were not accepted above which a run
/// that also halved steps warns.
pub const WASTED_WORK_WARN: f64 = 0.5;

/// A warning when most iterations went into attempts that did not give the accepted steps
/// (failed solves, and the halvings after them): the run then spends its time crossing a
/// region where the step is hard to solve, whatever its progress bar says (docs/outputs.md
/// §solver).
fn wasted_work(c: &SolverCounters, accepted_iterations: u64, halvings: u64) -> Option<String> {
    let wasted = c.iterations.saturating_sub(accepted_iterations);
    if halvings == 0 || (wasted as f64) <= WASTED_WORK_WARN * c.iterations as f64 {
        return None;
    }
    let failed = |s: engine::StageCounts| s.runs - s.converged;
    Some(format!(
        "{:.0} % of the {} iterations went into attempts that were not accepted \
         ({halvings} halved steps; {} failed continuation and {} failed homotopy stages): the \
         run crossed a region where the step is hard to solve (docs/outputs.md §solver)",
        100.0 * wasted as f64 / c.iterations as f64,
        c.iterations,
        failed(c.continuation),
        failed(c.homotopy),
    ))
}

/// How a flight ended, for its summary.
pub(super) struct End {
    /// The flight is over (a summary before the end does not warn of snapshots to come).
    pub ended: bool,
    /// The requested duration was simulated, or the run reached the ground.
    pub complete: bool,
    /// Why it stopped before the duration.
    pub stop_reason: Option<String>,
    /// Wall time spent (s).
    pub wall_time_s: f64,
    /// The stepper's counters since the flight started or resumed.
    pub counters: SolverCounters,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn counters(iterations: u64) -> SolverCounters {
        SolverCounters {
            iterations,
            continuation: engine::StageCounts {
                runs: 7,
                converged: 4,
            },
            ..SolverCounters::default()
        }
    }

    #[test]
    fn wasted_work_warns_only_past_half_the_iterations_with_halvings() {
        // 600 of 1,000 iterations not accepted, 2 halvings: warned, with the counts.
        let w = wasted_work(&counters(1000), 400, 2).expect("60 % wasted");
        assert!(w.starts_with("60 % of the 1000 iterations"), "{w}");
        assert!(
            w.contains("2 halved steps; 3 failed continuation and 0 failed homotopy"),
            "{w}"
        );
        // Exactly half, or no halving, or every iteration accepted: quiet.
        assert_eq!(wasted_work(&counters(1000), 500, 2), None);
        assert_eq!(wasted_work(&counters(1000), 400, 0), None);
        assert_eq!(wasted_work(&counters(1000), 1000, 5), None);
    }
}

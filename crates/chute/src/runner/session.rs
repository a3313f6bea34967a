//! Stepping a run from outside, one accepted step at a time (the Python `Simulation`): the
//! physics of [`simulate`](super::simulate) without its outputs.
//!
//! A [`Session`] takes exactly the steps the run loop takes: the same step-size policy
//! ([`super::dt_policy`]), adaptive steps ending on the same events (frame and snapshot
//! times, sync points, the end), failed solves halved the same way, and the stepper's reused
//! factorisation dropped at the same sync points. Stepping to the end therefore gives the
//! run's final state bit for bit, and [`Session::summary`] at the end equals the run's
//! `summary.json` but for the wall time (`tests/physics/session.rs` holds both to it). It
//! writes nothing: the frame and snapshot times are only followed because adaptive steps end
//! on them.

use std::time::{Duration, Instant};

use engine::ImplicitEuler;

use super::advance::{self, Outcome};
use super::dt_policy::DtPolicy;
use super::observe::Observer;
use super::{failure_message, RunConfig, RunError};
use crate::build::Built;
use crate::metrics;
use crate::output::summary::{RunInfo, Summary};
use crate::output::timeseries::DecimatedSeries;

/// A run stepped by its caller.
pub struct Session {
    built: Built,
    cfg: RunConfig,
    stepper: ImplicitEuler,
    dt: DtPolicy,
    obs: Observer,
    dec: DecimatedSeries,
    steps: u64,
    newton_total: u64,
    warnings: Vec<String>,
    next_frame: f64,
    snaps: Vec<f64>,
    snap_idx: usize,
    next_sync: u64,
    stop_reason: Option<String>,
    wall: Duration,
}

/// One accepted step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepInfo {
    /// Its size (s).
    pub h: f64,
    /// Newton iterations it took.
    pub iterations: usize,
}

/// The session has stopped before `time.duration_s`: a step failed even at the smallest
/// step allowed. The message is the run's stop reason.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct Stopped(pub String);

impl Session {
    /// A session at the start of the run of `built` under `cfg` (`cfg.progress` is ignored).
    pub fn new(built: Built, cfg: RunConfig) -> Result<Self, RunError> {
        let stepper = ImplicitEuler::new(&built.model, cfg.newton)?;
        let mut snaps = cfg.snapshots_s.clone();
        snaps.sort_by(f64::total_cmp);
        let mut s = Self {
            dt: DtPolicy::new(&cfg)?,
            obs: Observer::new(&built),
            dec: DecimatedSeries::default(),
            steps: 0,
            newton_total: 0,
            warnings: Vec::new(),
            next_frame: 0.0,
            snaps,
            snap_idx: 0,
            next_sync: 1,
            stop_reason: None,
            wall: Duration::ZERO,
            built,
            cfg,
            stepper,
        };
        let s0 = s.obs.sample(&s.built, &s.built.state, 0, s.cfg.dt_s);
        s.dec.push(&s0);
        s.pass_output_times();
        Ok(s)
    }

    /// Take one accepted step (retrying rejected and failed attempts as the run loop does).
    /// `Ok(None)` once the end time is reached; after a failure every call returns the same
    /// [`Stopped`].
    pub fn step(&mut self) -> Result<Option<StepInfo>, Stopped> {
        if let Some(r) = &self.stop_reason {
            return Err(Stopped(r.clone()));
        }
        let start = Instant::now();
        let r = self.try_step();
        self.wall += start.elapsed();
        r
    }

    /// Step until the simulated time reaches `t` (s) or the end, whichever is first; a step
    /// is never shortened to land on `t`, so the last one may pass it. The number of steps.
    pub fn advance_to(&mut self, t: f64) -> Result<u64, Stopped> {
        let mut n = 0;
        while !self.reached(t) && self.step()?.is_some() {
            n += 1;
        }
        Ok(n)
    }

    fn try_step(&mut self) -> Result<Option<StepInfo>, Stopped> {
        loop {
            let t = self.built.state.t;
            if t >= self.cfg.duration_s - self.dt.time_tol {
                return Ok(None);
            }
            let plan = self.dt.plan(t, self.next_event());
            let b = &mut self.built;
            let outcome = advance::attempt(
                &mut self.dt,
                &mut self.stepper,
                &mut b.model,
                &mut b.state,
                &plan,
            );
            let (iterations, err) = match outcome {
                Outcome::Accepted { iterations, err } => (iterations, err),
                Outcome::Rejected => continue,
                Outcome::Failed(e) => {
                    if !self.dt.newton_failed(plan.h) {
                        let reason = failure_message(&self.built, &e, t, self.dt.h);
                        self.stop_reason = Some(reason.clone());
                        return Err(Stopped(reason));
                    }
                    if self.warnings.len() < 20 {
                        self.warnings.push(format!(
                            "step rejected at t = {t:.6} s ({e}); dt halved to {:.3e} s",
                            self.dt.h
                        ));
                    }
                    continue;
                }
            };
            self.record(iterations, err, plan.h);
            return Ok(Some(StepInfo {
                h: plan.h,
                iterations,
            }));
        }
    }

    /// Book an accepted step as the run loop does: warning, counters, sample, output times
    /// passed, sync point.
    fn record(&mut self, iterations: usize, err: f64, h: f64) {
        let t = self.built.state.t;
        if err > 1.0 && self.warnings.len() < 20 {
            self.warnings.push(format!(
                "local error {err:.3} × the tolerance accepted at t = {t:.6} s: dt = {h:.3e} s is the smallest step allowed"
            ));
        }
        self.steps += 1;
        self.newton_total += iterations as u64;
        let s = self
            .obs
            .sample(&self.built, &self.built.state, iterations as u32, h);
        self.dec.push(&s);
        self.pass_output_times();
        let (sync_dt, tol) = (self.dt.sync_dt, self.dt.time_tol);
        if t >= self.next_sync as f64 * sync_dt - tol {
            self.stepper.invalidate_factorization();
            self.next_sync = ((t + tol) / sync_dt).floor() as u64 + 1;
        }
    }

    /// Move past the frame and snapshot times due now (the run writes its outputs there).
    fn pass_output_times(&mut self) {
        let (t, half, iv) = (
            self.built.state.t,
            self.dt.due_tol,
            self.cfg.frame_interval_s,
        );
        if iv > 0.0 && t >= self.next_frame - half {
            while self.next_frame <= t + half {
                self.next_frame = self.dt.next_frame_after(self.next_frame, iv);
            }
        }
        while self.snap_idx < self.snaps.len() && t >= self.snaps[self.snap_idx] - half {
            self.snap_idx += 1;
        }
    }

    /// The first event after the current time where an adaptive step must end (the run
    /// loop's rule); the end of the run with a fixed step.
    fn next_event(&self) -> f64 {
        let end = self.cfg.duration_s;
        if !self.dt.adaptive() {
            return end;
        }
        let after = self.built.state.t + self.dt.time_tol;
        let frame = if self.cfg.frame_interval_s > 0.0 {
            self.next_frame
        } else {
            f64::INFINITY
        };
        let snap = self.snaps.get(self.snap_idx).copied();
        let sync = self.next_sync as f64 * self.dt.sync_dt;
        [frame, snap.unwrap_or(f64::INFINITY), sync]
            .into_iter()
            .filter(|&e| e > after)
            .fold(end, f64::min)
    }

    /// Simulated time (s).
    pub fn time(&self) -> f64 {
        self.built.state.t
    }

    /// The model, its current state (`built().state`) and what the observers know of it.
    pub fn built(&self) -> &Built {
        &self.built
    }

    /// The run's settings.
    pub fn config(&self) -> &RunConfig {
        &self.cfg
    }

    /// Whether the simulated time has reached `t` (s), to the run loop's time tolerance.
    pub fn reached(&self, t: f64) -> bool {
        self.time() >= t - self.dt.time_tol
    }

    /// Accepted steps so far.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// Whether the end time is reached or the session stopped.
    pub fn finished(&self) -> bool {
        self.stop_reason.is_some() || self.reached(self.cfg.duration_s)
    }

    /// Why the session stopped early, if it did.
    pub fn stop_reason(&self) -> Option<&str> {
        self.stop_reason.as_deref()
    }

    /// The summary so far: what the run would write to `summary.json` had it ended now
    /// (incomplete before the end time), with the wall time spent stepping.
    pub fn summary(&self) -> Summary {
        let complete = self.stop_reason.is_none() && self.finished();
        let mut warnings = self.warnings.clone();
        let missed = &self.snaps[self.snap_idx..];
        if self.finished() && !missed.is_empty() {
            let times: Vec<String> = missed.iter().map(|t| format!("{t} s")).collect();
            warnings.push(format!(
                "snapshot{} at {} not drawn: the run ended at {:.6} s",
                if missed.len() > 1 { "s" } else { "" },
                times.join(", "),
                self.time()
            ));
        }
        let b = &self.built;
        let (rho, mu) = super::recovery::window_air(&self.dec, &self.cfg);
        let params = metrics::Params {
            total_weight_n: b.total_weight_n,
            air_density_kg_m3: rho,
            air_viscosity_pa_s: mu,
            reference_length_m: b.reference_length_m,
            quadratic_drag: self.cfg.quadratic_drag,
        };
        let mut info = RunInfo {
            scenario_name: self.cfg.name.clone(),
            complete,
            stop_reason: self.stop_reason.clone(),
            simulated_time_s: self.time(),
            steps: self.steps,
            newton_iterations: self.newton_total,
            wall_time_s: self.wall.as_secs_f64(),
            dofs: b.model.n_dofs(),
            stepping: self.dt.stepping(&self.cfg),
            warnings,
        };
        match metrics::compute(&self.dec.series(), &params) {
            // A session does not watch for the ground yet (docs/python.md): no landing.
            Ok(m) => Summary::new(info, &m).with_recovery(metrics::descent::compute(
                &self.dec.recovery_series(),
                &super::recovery::params(b, &self.cfg),
                m.terminal_velocity_mps,
                m.drag_area_m2,
                None,
            )),
            Err(e) => {
                info.warnings.push(format!("metrics unavailable: {e}"));
                Summary::new(info, &metrics::Metrics::undefined(b.total_weight_n))
            }
        }
    }
}

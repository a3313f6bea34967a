//! Stepping a run from outside, one accepted step at a time (the Python `Simulation`): the
//! physics of [`simulate`](super::simulate) without its outputs.
//!
//! A [`Session`] drives the same [`Flight`] as the run loop: the same step-size policy
//! ([`super::dt_policy`]), adaptive steps ending on the same events (frame and snapshot
//! times, sync points, the end), failed solves halved the same way, the stepper's reused
//! factorisation dropped at the same sync points, and the same ground watch (it ends at the
//! ground, complete). Stepping to the end therefore gives the run's final state bit for bit,
//! and [`Session::summary`] at the end equals the run's `summary.json` but for the wall times
//! (`tests/physics/session.rs` holds both to it). It writes nothing: the frame and snapshot
//! times are only followed because adaptive steps end on them.

use std::time::{Duration, Instant};

use engine::ImplicitEuler;

use super::flight::{Attempt, End, Flight};
use super::{RunConfig, RunError, GROUND};
use crate::build::Built;
use crate::output::summary::Summary;

/// A run stepped by its caller.
pub struct Session {
    built: Built,
    cfg: RunConfig,
    stepper: ImplicitEuler,
    flight: Flight,
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
    pub fn new(mut built: Built, cfg: RunConfig) -> Result<Self, RunError> {
        let stepper = super::advance::new_stepper(&built.model, &cfg)?;
        let mut flight = Flight::new(&built, &cfg)?;
        flight.draws_snapshots = false;
        let s0 = flight
            .obs
            .sample(&built, &built.state, 0, cfg.stepping.dt_s);
        flight.dec.push(&s0);
        flight.take_due(built.state.t, &cfg);
        flight.start_watches(&mut built);
        Ok(Self {
            built,
            cfg,
            stepper,
            flight,
            stop_reason: None,
            wall: Duration::ZERO,
        })
    }

    /// Take one accepted step (retrying rejected and failed attempts as the run loop does).
    /// `Ok(None)` once the end time or the ground is reached; after a failure every call
    /// returns the same [`Stopped`].
    pub fn step(&mut self) -> Result<Option<StepInfo>, Stopped> {
        if let Some(r) = &self.stop_reason {
            return Err(Stopped(r.clone()));
        }
        let start = Instant::now();
        let r = self.try_step();
        self.wall += start.elapsed();
        r
    }

    /// Step until the simulated time reaches `t` (s), the end or the ground, whichever is
    /// first; a step is never shortened to land on `t`, so the last one may pass it. The
    /// number of steps.
    pub fn advance_to(&mut self, t: f64) -> Result<u64, Stopped> {
        let mut n = 0;
        while !self.reached(t) && self.step()?.is_some() {
            n += 1;
        }
        Ok(n)
    }

    fn try_step(&mut self) -> Result<Option<StepInfo>, Stopped> {
        loop {
            if self.finished() {
                return Ok(None);
            }
            match self
                .flight
                .attempt(&mut self.stepper, &mut self.built, &self.cfg)
            {
                Attempt::Accepted(iterations, sample) => {
                    let t = self.built.state.t;
                    self.flight.take_due(t, &self.cfg);
                    if self.flight.passed_sync(t) {
                        self.stepper.invalidate_factorization();
                    }
                    return Ok(Some(StepInfo {
                        h: sample.dt_s,
                        iterations,
                    }));
                }
                Attempt::Rejected => continue,
                Attempt::Failed(reason) => {
                    self.stop_reason = Some(reason.clone());
                    return Err(Stopped(reason));
                }
            }
        }
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
        self.time() >= t - self.flight.dt.time_tol
    }

    /// Accepted steps so far.
    pub fn steps(&self) -> u64 {
        self.flight.steps
    }

    /// Whether the end time or the ground is reached, or the session stopped.
    pub fn finished(&self) -> bool {
        self.stop_reason.is_some() || self.landed() || self.reached(self.cfg.stepping.duration_s)
    }

    /// Whether the landing body has reached the ground (`atmosphere.ground_altitude_m`); the
    /// session then ends there, complete, like the run.
    pub fn landed(&self) -> bool {
        self.flight.landing.is_some()
    }

    /// Why the session stopped early, if it did (`"ground"` once landed).
    pub fn stop_reason(&self) -> Option<&str> {
        match &self.stop_reason {
            Some(r) => Some(r),
            None if self.landed() => Some(GROUND),
            None => None,
        }
    }

    /// The summary so far: what the run would write to `summary.json` had it ended now
    /// (incomplete before the end time), with the wall time spent stepping.
    pub fn summary(&self) -> Summary {
        let end = End {
            ended: self.finished(),
            complete: self.stop_reason.is_none() && self.finished(),
            stop_reason: self.stop_reason().map(str::to_string),
            wall_time_s: self.wall.as_secs_f64(),
            counters: *self.stepper.counters(),
        };
        let info = self.flight.info(&self.built, &self.cfg, end);
        self.flight.summary(&self.built, &self.cfg, info).0
    }
}

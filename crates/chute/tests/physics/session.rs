//! `runner::Session` (the Python `Simulation`) steps exactly as the run loop: stepping to the
//! end gives the run's final state bit for bit and its summary but for the wall time, with a
//! fixed step (sync points), adaptive steps (events: frames, snapshots, sync points) and a
//! run that stops on a lasting failure.
use crate::common::*;

use chute::app::run_config;
use chute::build::{build, Built};
use chute::output::Summary;
use chute::runner::{simulate, RunResult, Session};
use chute::scenario::Scenario;
use std::sync::atomic::AtomicBool;

/// The summary as JSON without the wall times (the only things that may differ; the
/// solver counters must be equal).
fn comparable(s: &Summary) -> serde_json::Value {
    without_wall_times(serde_json::from_str(&s.to_json()).unwrap())
}

/// A run's summary as a session's would be: a session draws no snapshots, so it never warns
/// of one not drawn.
fn as_session(s: &Summary) -> serde_json::Value {
    let mut s = s.clone();
    s.warnings.retain(|w| !w.contains("not drawn"));
    comparable(&s)
}

fn run(mut built: Built, s: &Scenario) -> (Built, RunResult) {
    let dir = tempfile::tempdir().unwrap();
    let cfg = run_config(s, false);
    let r = simulate(&mut built, &cfg, dir.path(), &AtomicBool::new(false)).unwrap();
    (built, r)
}

/// Step a session of `built` to its end; the number of accepted steps it reported.
fn step_to_end(session: &mut Session) -> u64 {
    let mut n = 0;
    while let Ok(Some(_)) = session.step() {
        n += 1;
    }
    n
}

fn assert_same_as_run(s: &Scenario) {
    let (ran, r) = run(build(s).unwrap(), s);
    let mut session = Session::new(build(s).unwrap(), run_config(s, false)).unwrap();
    let n = step_to_end(&mut session);
    let st = &session.built().state;
    assert_eq!(st.t.to_bits(), ran.state.t.to_bits());
    assert!(st
        .q
        .iter()
        .zip(&ran.state.q)
        .all(|(a, b)| a.to_bits() == b.to_bits()));
    assert!(st
        .v
        .iter()
        .zip(&ran.state.v)
        .all(|(a, b)| a.to_bits() == b.to_bits()));
    assert_eq!(n, r.summary.steps);
    assert_eq!(comparable(&session.summary()), as_session(&r.summary));
    assert!(session.finished());
}

#[test]
fn fixed_step_session_equals_the_run() {
    // 200 steps: three sync points, and snapshots at 0.05 s and 0.3 s (one missed, which
    // the run warns of and the session, drawing none, does not).
    let s = rod(0.2, &[]);
    assert_same_as_run(&s);
    let mut session = Session::new(build(&s).unwrap(), run_config(&s, false)).unwrap();
    step_to_end(&mut session);
    assert!(!session
        .summary()
        .warnings
        .iter()
        .any(|w| w.contains("not drawn")));
}

#[test]
fn adaptive_session_equals_the_run() {
    // Adaptive steps end on the frames (every 0.05 s), the snapshot at 0.05 s and sync points.
    let s = rod(0.2, &["time.adaptive=true"]);
    assert_same_as_run(&s);
}

#[test]
fn a_session_stops_like_the_run_on_a_lasting_failure() {
    let s = rod(0.2, &[]);
    let with_blowup = || {
        let mut b = build(&s).unwrap();
        let mut trig = Trigger::new(2, 0.1);
        trig.nan_evals = usize::MAX;
        b.model.add_force(trig);
        b
    };
    let (ran, r) = run(with_blowup(), &s);
    assert!(!r.complete);
    let mut session = Session::new(with_blowup(), run_config(&s, false)).unwrap();
    step_to_end(&mut session);
    let stopped = session.step().unwrap_err();
    assert_eq!(Some(stopped.0.as_str()), r.stop_reason.as_deref());
    assert_eq!(session.stop_reason(), r.stop_reason.as_deref());
    assert_eq!(session.built().state.q, ran.state.q);
    assert_eq!(comparable(&session.summary()), as_session(&r.summary));
}

#[test]
fn advance_to_stops_at_the_first_step_past_the_time_and_the_summary_is_partial() {
    let s = rod(0.2, &[]);
    let mut session = Session::new(build(&s).unwrap(), run_config(&s, false)).unwrap();
    let n = session.advance_to(0.05).unwrap();
    assert_eq!(n, 50);
    assert!((session.time() - 0.05).abs() < 1e-12);
    let partial = session.summary();
    assert!(!partial.complete && !session.finished());
    assert_eq!(partial.steps, 50);
    assert!(partial
        .warnings
        .iter()
        .any(|w| w.contains("run incomplete")));
    // Past the end: stops at the end, then steps return None.
    session.advance_to(1.0).unwrap();
    assert!(session.finished());
    assert_eq!(session.step(), Ok(None));
    assert!(session.summary().complete);
}

/// With a ground the session ends where the run ends: at the first step on the ground,
/// complete with stop reason "ground", the same state and the same landing fields.
#[test]
fn a_session_lands_like_the_run() {
    // The rod canopy starts at z = 0 (altitude 1,000 m); the ground 0.5 m below is reached
    // in about half a second of free fall and deceleration.
    let s = rod(
        2.0,
        &[
            "atmosphere.model=\"isa1976\"",
            "atmosphere.altitude_m=1000",
            "atmosphere.ground_altitude_m=999.5",
        ],
    );
    let (ran, r) = run(build(&s).unwrap(), &s);
    assert!(r.complete && r.stop_reason.as_deref() == Some("ground"));
    let mut session = Session::new(build(&s).unwrap(), run_config(&s, false)).unwrap();
    let n = step_to_end(&mut session);
    assert!(session.landed() && session.finished());
    assert_eq!(session.step(), Ok(None));
    assert_eq!(session.stop_reason(), Some("ground"));
    assert_eq!(n, r.summary.steps);
    assert!(session.time() < 2.0);
    assert_eq!(session.built().state.q, ran.state.q);
    let summary = session.summary();
    assert!(summary.complete);
    assert_eq!(comparable(&summary), as_session(&r.summary));
}

//! Failed steps: a force that returns NaN from a given time makes the run loop reject the
//! step and halve dt; a short blow-up is recovered from (dt grows back), a lasting one stops
//! the run with a clear reason and valid partial outputs and a checkpoint of the last good
//! state.
use crate::common::*;

use chute::checkpoint::Checkpoint;
use chute::runner::{simulate, RunResult, GROW_AFTER};
use chute::scenario::Scenario;
use std::path::Path;
use std::sync::atomic::AtomicBool;

/// Run `s` into `dir` with a trigger whose first `nan_evals` evaluations from `at_s` on are NaN.
fn run_with_blowup(s: &Scenario, dir: &Path, at_s: f64, nan_evals: usize) -> RunResult {
    let mut built = chute::build::build(s).unwrap();
    let mut trig = Trigger::new(2, at_s);
    trig.nan_evals = nan_evals;
    built.model.add_force(trig);
    let stop = AtomicBool::new(false);
    std::fs::create_dir_all(dir).unwrap();
    simulate(&mut built, &chute::app::run_config(s, false), dir, &stop).unwrap()
}

#[test]
fn a_transient_blowup_is_recovered_by_halving_dt() {
    // A residual that is not finite at the predictor fails the step at once (no stage can
    // start from it), so each NaN evaluation reaches the run loop.
    let s = rod(0.2, &[]);
    let dt = s.time.dt_s;
    let tmp = tempfile::tempdir().unwrap();
    let clean = run_with_blowup(&s, &tmp.path().join("clean"), f64::INFINITY, 0);
    let dir = tmp.path().join("blowup");
    let r = run_with_blowup(&s, &dir, 0.1, 3);
    assert!(r.complete, "{:?}", r.stop_reason);
    let rejected: Vec<&String> = r
        .summary
        .warnings
        .iter()
        .filter(|w| w.contains("step rejected"))
        .collect();
    assert_eq!(rejected.len(), 3, "{:?}", r.summary.warnings);
    assert_eq!(r.summary.stepping.rejected_steps_newton, 3);
    assert_eq!(r.summary.stepping.rejected_steps_error, 0);
    assert_eq!(r.summary.stepping.dt_used_min_s, Some(dt / 8.0));
    assert_eq!(r.summary.stepping.dt_used_max_s, Some(dt));
    assert!(rejected[0].contains("t = 0.09"), "{}", rejected[0]);
    // The dt column: nominal, then dt/8 from the failure, doubling after every GROW_AFTER
    // accepted steps until nominal again.
    let rows = csv_rows(&dir.join("timeseries.csv"));
    let dts: Vec<f64> = rows[1..].iter().map(|r| r[12]).collect();
    let first_small = dts.iter().position(|&h| h < dt).unwrap();
    let expect: Vec<f64> = [8.0, 4.0, 2.0]
        .iter()
        .flat_map(|d| std::iter::repeat_n(dt / d, GROW_AFTER as usize))
        .collect();
    assert_eq!(&dts[first_small..first_small + expect.len()], &expect[..]);
    // Back to nominal (the last step ends exactly on the end time: cut short, or stretched by
    // the round-off of the summed time, at most 0.1 %).
    let (last, rest) = dts[first_small + expect.len()..].split_last().unwrap();
    assert!(rest.iter().all(|&h| h == dt) && *last <= dt * 1.001 && rest.len() > 50);
    assert_eq!(rows.last().unwrap()[0], 0.2);
    // The detour changes the trajectory only by the change in time-discretisation error
    // over the 24 reduced steps: backward Euler's relative error is ~dt·λ per unit λt, with
    // λ ≲ 10/s the drag relaxation rate here, so over the 1.05e-2 s detour the final state
    // moves by ≲ (dt λ)(1.05e-2 s · λ) ≈ 1e-3 relative (measured: 5.7e-6).
    let (a, b) = (clean.summary.simulated_time_s, r.summary.simulated_time_s);
    assert_eq!(a, b);
    let vz = |d: &Path| {
        *csv_rows(&d.join("timeseries.csv"))
            .last()
            .unwrap()
            .get(2)
            .unwrap()
    };
    let (v0, v1) = (vz(&tmp.path().join("clean")), vz(&dir));
    println!(
        "final vz: clean {v0}, after the detour {v1}, relative {:.2e}",
        (v1 - v0).abs() / v0.abs()
    );
    assert!(
        (v1 - v0).abs() < 1e-3 * v0.abs(),
        "final vz {v1} vs clean {v0}"
    );
}

#[test]
fn a_lasting_blowup_stops_with_reason_and_valid_partial_outputs() {
    let s = rod(0.2, &[]);
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let r = run_with_blowup(&s, dir, 0.1, usize::MAX);
    assert!(!r.complete);
    let why = r.stop_reason.unwrap();
    // Why (non-finite), when (the last good time) and where (DOF 2 = node 0, z).
    assert!(why.contains("step failed at t = 0.099"), "{why}");
    assert!(why.contains("non-finite") || why.contains("NaN"), "{why}");
    assert!(why.contains("node 0 z"), "{why}");
    // Ten halvings: dt/1024 is the last size tried.
    assert!(
        why.contains(&format!("{:.3e}", s.time.dt_s / 1024.0)),
        "{why}"
    );

    let summary = read_json(dir.join("summary.json"));
    assert_eq!(summary["complete"], false);
    assert!(summary["stop_reason"]
        .as_str()
        .unwrap()
        .contains("node 0 z"));
    let c = Checkpoint::read(dir).unwrap();
    assert!(!c.synced);
    let rows = csv_rows(&dir.join("timeseries.csv"));
    assert_eq!(rows.len() as u64, c.ts_rows);
    assert_eq!(rows.last().unwrap()[0], c.t);
    assert!(c.q.iter().chain(&c.v).all(|x| x.is_finite()));
    assert!((c.t - 0.099).abs() < 1e-9, "{}", c.t);
    assert!(dir.join("canopy.pvd").exists() && dir.join("shape.png").exists());
}

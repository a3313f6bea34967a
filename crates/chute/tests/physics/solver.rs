//! The `solver` object of `summary.json` (docs/outputs.md §solver): the stepper's counters
//! over a whole run, consistent with the run's own step and iteration counts. (Resumed runs:
//! `resume.rs`.)
use std::path::Path;
use std::sync::atomic::AtomicBool;

use chute::app::run_config;
use chute::build::build;
use chute::output::summary::SolverCounters;
use chute::output::Summary;
use chute::runner::simulate;
use chute::scenario::Scenario;

use crate::common::*;

/// Run `s` into `dir`; the summary returned, its counters checked against the file's (the
/// counts exactly; the times to an ulp, serde_json's parser being only that accurate without
/// its `float_roundtrip` feature).
fn run(s: &Scenario, dir: &Path) -> Summary {
    let mut b = build(s).unwrap();
    let r = simulate(&mut b, &run_config(s, false), dir, &AtomicBool::new(false)).unwrap();
    assert!(r.complete, "{:?}", r.stop_reason);
    let file: Summary =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    let (ours, theirs) = (r.summary.solver.unwrap(), file.solver.unwrap());
    let times = |c: &SolverCounters| [c.assembly_s, c.factor_s, c.solve_s];
    for (a, b) in times(&ours).into_iter().zip(times(&theirs)) {
        assert!((a - b).abs() <= 1e-15 * a.abs(), "{a} vs {b}");
    }
    let counts_only = |c: &SolverCounters| SolverCounters {
        assembly_s: 0.0,
        factor_s: 0.0,
        solve_s: 0.0,
        ..*c
    };
    assert_eq!(counts_only(&ours), counts_only(&theirs));
    r.summary
}

/// The relations every run's counters satisfy.
fn assert_consistent(s: &Summary) -> SolverCounters {
    let c = s.solver.expect("a fresh run knows its solver counters");
    assert!(c.factorizations >= c.indefinite_factorizations, "{c:?}");
    assert!(
        c.solves >= s.steps && c.iterations >= s.newton_iterations,
        "{c:?}"
    );
    assert!(c.evaluations >= c.iterations && c.jacobian_evaluations <= c.evaluations);
    // Each stage runs only after the one before it failed, and every solve ends in one
    // converged stage or a halving.
    let stages = [c.held, c.newton, c.continuation, c.homotopy];
    for st in stages {
        assert!(st.converged <= st.runs, "{c:?}");
    }
    // Newton → continuation → homotopy (the held stage falls through to Newton on its own).
    for w in stages[1..].windows(2) {
        assert!(w[1].runs <= w[0].runs - w[0].converged, "{c:?}");
    }
    let converged: u64 = stages.iter().map(|st| st.converged).sum();
    assert_eq!(
        converged + s.stepping.rejected_steps_newton,
        c.solves - s.stepping.rejected_steps_error,
        "{c:?}"
    );
    assert!(
        c.assembly_s > 0.0 && c.factor_s > 0.0 && c.solve_s > 0.0,
        "{c:?}"
    );
    c
}

#[test]
fn rod_run_counters_match_its_steps_and_iterations() {
    let dir = tempfile::tempdir().unwrap();
    let s = run(&rod(0.1, &[]), dir.path());
    let c = assert_consistent(&s);
    // No step was rejected or retried, so every solve is one accepted step and every
    // iteration one of `newton_iterations`.
    assert_eq!(
        (
            s.stepping.rejected_steps_newton,
            s.stepping.rejected_steps_error,
            c.continuation.runs
        ),
        (0, 0, 0)
    );
    assert_eq!(c.iterations, s.newton_iterations);
    assert_eq!(c.solves, s.steps);
    // Held factors and chord iterations reuse factors: fewer factorisations than iterations.
    assert!(c.factorizations < c.iterations, "{c:?}");
}

#[test]
fn springs_shell_at_the_report_settings_needs_no_rescue_stage() {
    // The report's springs + hinges at its ~0.25 m mesh and dt = 1 ms (975 DOFs, 300 steps,
    // < 1 s): the held and Newton stages carry every solve, so a continuation here is a
    // regression.
    let mut sets: Vec<String> = chute::scenario::REPORT_SHELL_MODEL
        .iter()
        .map(|s| s.to_string())
        .collect();
    sets.extend(
        [
            "canopy.edge_length_m=0.25",
            "time.duration_s=0.3",
            "output.snapshots_s=[]",
        ]
        .map(String::from),
    );
    let sc = Scenario::load(&repo().join("scenarios/report-shell-4-sites.toml"), &sets).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let s = run(&sc, dir.path());
    let c = assert_consistent(&s);
    assert_eq!((c.continuation.runs, c.homotopy.runs), (0, 0), "{c:?}");
    assert_eq!(c.iterations, s.newton_iterations);
}

/// The run warns when most of its Newton work was thrown away (docs/outputs.md §solver): the
/// warning is there exactly when the counters say so, with their numbers. One Newton
/// iteration per step under a 3 kN load makes steps fail their first stages, and some halve.
#[test]
fn wasted_newton_work_is_warned_as_the_counters_say() {
    use chute::runner::WASTED_WORK_WARN;
    let warned = |s: &Summary| {
        s.warnings
            .iter()
            .find(|w| w.contains("iterations went into attempts that were not accepted"))
            .cloned()
    };
    let dir = tempfile::tempdir().unwrap();
    let clean = run(&rod(0.1, &[]), dir.path());
    assert_eq!(warned(&clean), None);
    let hard = [
        "time.newton_max_iterations=1",
        "time.newton_tolerance_n=1e-3",
        "load.weight_n=3e3",
    ];
    let dir = tempfile::tempdir().unwrap();
    let s = run(&rod(0.3, &hard), dir.path());
    let c = assert_consistent(&s);
    let halvings = s.stepping.rejected_steps_newton;
    assert!(halvings > 0 && c.continuation.runs > 0, "{c:?}");
    let wasted = c.iterations - s.newton_iterations;
    let expect = wasted as f64 > WASTED_WORK_WARN * c.iterations as f64;
    match warned(&s) {
        Some(w) => {
            assert!(expect, "warned at {wasted} of {}: {w}", c.iterations);
            let pct = format!("{:.0} %", 100.0 * wasted as f64 / c.iterations as f64);
            assert!(w.starts_with(&pct), "{w} (expected {pct})");
            assert!(w.contains(&format!("{halvings} halved steps")), "{w}");
        }
        None => assert!(!expect, "{wasted} of {} not warned", c.iterations),
    }
}

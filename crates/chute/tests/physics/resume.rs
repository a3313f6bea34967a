//! Checkpoint and resume: a run stopped part-way and resumed from its checkpoint writes the
//! same files, bit for bit, as the uninterrupted run (wall times aside; the solver counters
//! too), for the rod model (whose DER frames are history) and the shell model; a checkpoint
//! of the format before the solver counters still resumes, and its summary says they are
//! unknown.
use crate::common::*;

use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

use chute::checkpoint::Checkpoint;
use chute::runner::{simulate_with, RunControl, RunResult};
use chute::scenario::Scenario;

/// Run `s` into `dir` with a trigger force on DOF 2 that, when `stop_at` is given, requests
/// a stop once the run reaches that time. The trigger is in every run (it adds exact zeros),
/// so all runs have the same force list.
fn run(
    s: &Scenario,
    dir: &Path,
    stop_at: Option<f64>,
    every: Option<f64>,
    resume: bool,
) -> RunResult {
    let mut built = chute::build::build(s).unwrap();
    let mut trig = Trigger::new(2, stop_at.unwrap_or(f64::INFINITY));
    trig.set_stop = stop_at.is_some();
    let stop = trig.stop.clone();
    built.model.add_force(trig);
    std::fs::create_dir_all(dir).unwrap();
    let resume = resume.then(|| Checkpoint::read(dir).unwrap());
    let ctl = RunControl {
        stop: &stop,
        checkpoint_every_s: every,
        resume,
        scenario_toml: s.to_toml(),
        sim_time: None,
    };
    simulate_with(&mut built, &chute::app::run_config(s, false), dir, &ctl).unwrap()
}

pub(crate) fn stop_and_resume(s: &Scenario, stop_at: f64, every: Option<f64>) {
    let tmp = tempfile::tempdir().unwrap();
    let (full, part) = (tmp.path().join("full"), tmp.path().join("part"));
    // The uninterrupted run writes no checkpoints: sync points do not depend on them.
    let r = run(s, &full, None, None, false);
    assert!(r.complete);

    let r = run(s, &part, Some(stop_at), every, false);
    assert!(!r.complete);
    assert!(r.stop_reason.as_deref().unwrap().contains("interrupted"));
    let summary = read_json(part.join("summary.json"));
    assert_eq!(summary["complete"], false);
    let c = Checkpoint::read(&part).unwrap();
    assert!(
        c.synced && c.t > 0.0 && c.t <= stop_at,
        "checkpoint at {}",
        c.t
    );
    // The partial series runs past the checkpoint (to the stop); resume cuts it back.
    let rows = csv_rows(&part.join("timeseries.csv"));
    assert!(rows.len() as u64 > c.ts_rows);
    // The stop is requested by the trial that reaches stop_at (accepted or not).
    let longest = s.time.dt_max_s.unwrap_or(s.time.dt_s);
    assert!(rows.last().unwrap()[0] >= stop_at - longest);

    let before = c
        .solver
        .expect("the checkpoint records the solver counters");
    assert!(before.solves > 0);
    let r = run(s, &part, None, every, true);
    assert!(r.complete, "{:?}", r.stop_reason);
    assert_same_outputs(&full, &part);
    // The summaries' solver counts (so the whole summaries but for wall times) are equal.
    let summary = |d: &Path| -> serde_json::Value { read_json(d.join("summary.json")) };
    let (a, b) = (
        without_wall_times(summary(&full)),
        without_wall_times(summary(&part)),
    );
    assert!(a["solver"]["solves"].as_u64().unwrap() > before.solves);
    assert_eq!(a["solver"], b["solver"]);
    assert_eq!(a, b);
}

/// Bytes of the solver counters before the checksum (flag, JSON length, JSON).
fn solver_bytes(c: &Checkpoint) -> usize {
    16 + serde_json::to_string(&c.solver.unwrap_or_default())
        .unwrap()
        .len()
}

/// Rewrite `dir/checkpoint.bin` as the format-3 file an earlier chute wrote: the same bytes
/// without the solver counters, version 3, checksum (FNV-1a-64) recomputed.
fn downgrade_to_version_3(dir: &Path) {
    let path = dir.join(chute::checkpoint::FILE_NAME);
    let bytes = std::fs::read(&path).unwrap();
    assert_eq!(
        bytes[8..12],
        chute::checkpoint::FORMAT_VERSION.to_le_bytes()
    );
    let solver = solver_bytes(&Checkpoint::read(dir).unwrap());
    let mut body = bytes[..bytes.len() - 8 - solver].to_vec();
    body[8..12].copy_from_slice(&3u32.to_le_bytes());
    let sum = body.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    });
    body.extend_from_slice(&sum.to_le_bytes());
    std::fs::write(&path, body).unwrap();
}

/// In a new temporary directory: `long`, 0.3 s of the rod, and `ext`, its first 0.2 s with
/// checkpoints every 0.1 s (which must complete), to be extended to 0.3 s.
fn long_and_extendable_rod_runs() -> (tempfile::TempDir, PathBuf, PathBuf) {
    let tmp = tempfile::tempdir().unwrap();
    let (long, ext) = (tmp.path().join("long"), tmp.path().join("ext"));
    run(&rod(0.3, &[]), &long, None, None, false);
    assert!(run(&rod(0.2, &[]), &ext, None, Some(0.1), false).complete);
    (tmp, long, ext)
}

#[test]
fn version_3_checkpoint_resumes_with_the_solver_counters_marked_unknown() {
    let (_tmp, long, ext) = long_and_extendable_rod_runs();
    downgrade_to_version_3(&ext);
    let c = Checkpoint::read(&ext).unwrap();
    assert_eq!(c.solver, None);
    let r = run(&rod(0.3, &[]), &ext, None, Some(0.1), true);
    assert!(r.complete, "{:?}", r.stop_reason);
    // The physics resumes bit for bit; only the summary differs: no counters, a warning.
    for f in ["timeseries.csv", "canopy.pvd"] {
        assert_eq!(
            std::fs::read(long.join(f)).unwrap(),
            std::fs::read(ext.join(f)).unwrap(),
            "{f}"
        );
    }
    let s = read_json(ext.join("summary.json"));
    assert!(s["solver"].is_null(), "{}", s["solver"]);
    assert!(r.summary.solver.is_none());
    let warned = |w: &serde_json::Value| {
        w.as_str()
            .unwrap()
            .starts_with("solver counters not reported")
            && w.as_str().unwrap().contains("checkpoint format < 7")
    };
    assert_eq!(
        s["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|w| warned(w))
            .count(),
        1
    );
    assert_eq!(s["steps"], 300);
    // Its own (version-4) checkpoints keep the counters unknown, so a second resume does not
    // report the part after the first as the whole run; the warning is not repeated.
    let c = Checkpoint::read(&ext).unwrap();
    assert!(c.t > 0.25 && c.solver.is_none(), "t = {}", c.t);
    let r = run(&rod(0.35, &[]), &ext, None, Some(0.1), true);
    assert!(r.complete && r.summary.solver.is_none());
    let n = r
        .summary
        .warnings
        .iter()
        .filter(|w| w.starts_with("solver counters not reported"))
        .count();
    assert_eq!(n, 1, "{:?}", r.summary.warnings);
}

#[test]
fn rod_resumed_after_stop_equals_uninterrupted() {
    // 0.3 s: sync points every 64 ms; stop at 0.21 s → checkpoint at 0.192 s.
    stop_and_resume(&rod(0.3, &[]), 0.21, Some(0.05));
}

#[test]
fn rod_resumed_without_periodic_checkpoints_equals_uninterrupted() {
    // The stop alone writes the last sync point's checkpoint.
    stop_and_resume(&rod(0.25, &[]), 0.15, None);
}

#[test]
fn adaptive_rod_resumed_after_stop_equals_uninterrupted() {
    // Adaptive: sync points every 0.1 s (2 frames); stop at 0.21 s → checkpoint at 0.2 s. The
    // step-size proposal, cap and counters are in the checkpoint, the dt statistics are
    // rebuilt from the rows.
    let s = rod(0.3, &["time.adaptive=true"]);
    stop_and_resume(&s, 0.21, Some(0.05));
    stop_and_resume(&s, 0.13, None);
}

#[test]
fn adaptive_resume_can_extend_a_finished_run() {
    let tmp = tempfile::tempdir().unwrap();
    let (long, ext) = (tmp.path().join("long"), tmp.path().join("ext"));
    let a = |d: f64| rod(d, &["time.adaptive=true"]);
    run(&a(0.3), &long, None, None, false);
    assert!(run(&a(0.2), &ext, None, Some(0.1), false).complete);
    assert!(run(&a(0.3), &ext, None, Some(0.1), true).complete);
    assert_same_outputs(&long, &ext);
}

#[test]
fn shell_resumed_after_stop_equals_uninterrupted() {
    stop_and_resume(&shell(0.2), 0.14, Some(0.1));
}

/// The air's added mass keeps history (each panel's air momentum, the lagged mass per area):
/// the checkpoint carries it, so the resumed run is the uninterrupted one bit for bit.
#[test]
fn shell_with_added_mass_resumed_after_stop_equals_uninterrupted() {
    let mut s = shell(0.2);
    s.fluid.added_mass = Some(true);
    stop_and_resume(&s, 0.14, Some(0.1));
}

#[test]
fn resume_can_extend_a_finished_run() {
    // A finished run's last periodic checkpoint continues to a longer duration exactly as a
    // longer uninterrupted run.
    let (_tmp, long, ext) = long_and_extendable_rod_runs();
    assert!(run(&rod(0.3, &[]), &ext, None, Some(0.1), true).complete);
    assert_same_outputs(&long, &ext);
}

#[test]
fn checkpoint_corruption_is_detected() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    run(&rod(0.1, &[]), dir, None, Some(0.05), false);
    let path = dir.join(chute::checkpoint::FILE_NAME);
    let bytes = std::fs::read(&path).unwrap();
    let c = Checkpoint::decode(&bytes).unwrap();
    assert_eq!(Checkpoint::decode(&c.encode()).unwrap(), c);
    for cut in [0, 7, 20, bytes.len() / 2, bytes.len() - 1] {
        assert!(Checkpoint::decode(&bytes[..cut]).is_err(), "cut at {cut}");
    }
    let mut flipped = bytes.clone();
    flipped[bytes.len() / 3] ^= 0x10;
    let e = Checkpoint::decode(&flipped).unwrap_err();
    assert!(e.contains("checksum"), "{e}");
}

#[test]
fn resume_rejects_a_different_scenario_and_a_missing_checkpoint() {
    use chute::app::{run as app_run, RunOptions};
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().to_path_buf();
    let opts = |resume: bool| RunOptions {
        out_dir: dir.clone(),
        force: true,
        progress: false,
        checkpoint_every_s: Some(0.05),
        resume: resume.then(|| dir.clone()),
        viewer: false,
        case_of: None,
    };
    // Each refusal is bad input (exit 2) saying what differs.
    let refused = |e: chute::app::AppError, want: &str| {
        assert_eq!(e.exit_code(), 2);
        assert!(e.to_string().contains(want), "{e}");
    };
    refused(
        app_run(&rod(0.1, &[]), &opts(true)).unwrap_err(),
        "checkpoint.bin",
    );
    app_run(&rod(0.1, &[]), &opts(false)).unwrap();
    // The key is named with its section.
    refused(
        app_run(&rod(0.1, &["load.weight_n=20"]), &opts(true)).unwrap_err(),
        "`load.weight_n` = 200.0 (checkpoint) vs 20.0 (now)",
    );
    // A shorter duration is refused, naming both.
    refused(
        app_run(&rod(0.05, &[]), &opts(true)).unwrap_err(),
        "0.05 s is shorter than the recorded run's 0.1 s",
    );
    // A longer duration is allowed.
    let o = app_run(&rod(0.15, &[]), &opts(true)).unwrap();
    assert!(o.complete);
    let _ = AtomicBool::new(false);
}

#[test]
fn guided_run_resumed_after_stop_equals_uninterrupted() {
    // Guidance decides every 0.25 s from the state and the commands in the lines' history
    // (checkpointed): sync points every 0.64 s; stop at 1.5 s → checkpoint at 1.28 s, between
    // decisions. lines.csv and track.csv are cut back and continued.
    let set: Vec<String> = SQUARE_ON_CORNERS
        .iter()
        .chain(&[
            "fluid.shell_drag=\"report\"",
            "guidance.pull_side=towards",
            "guidance.update_s=0.25",
            "guidance.target_m=[5, 12]",
            "atmosphere.altitude_m=30",
            "time.duration_s=2",
            "output.frame_interval_s=0.1",
        ])
        .map(|s| s.to_string())
        .collect();
    let s = Scenario::load(&repo().join("scenarios/control-guidance.toml"), &set).unwrap();
    stop_and_resume(&s, 1.5, None);
}

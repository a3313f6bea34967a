//! Reliability through the binary: exit code 3 with valid partial outputs, SIGTERM leaving a
//! checkpoint that resumes to the uninterrupted result, and bit-identical outputs for the
//! same inputs whatever `--jobs` is.
use crate::common::*;

use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use chute::checkpoint::Checkpoint;

const COARSE: [&str; 4] = [
    "--set",
    "canopy.nodes=21",
    "--set",
    "output.snapshots_s=[0.05]",
];

fn run_args<'a>(out: &'a str, duration: &'a str, extra: &[&'a str]) -> Vec<String> {
    let mut a: Vec<String> = [
        "run",
        &rod_file(),
        "--quiet",
        "--out",
        out,
        "--set",
        duration,
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    a.extend(COARSE.iter().chain(extra).map(|s| s.to_string()));
    a
}

fn run(cwd: &Path, args: &[String]) -> Output {
    let a: Vec<&str> = args.iter().map(String::as_str).collect();
    chute(cwd, &a)
}

#[test]
fn a_failing_run_exits_3_with_reason_and_valid_partial_outputs() {
    let tmp = tempfile::tempdir().unwrap();
    // The round parachute of FAILING_PULL_SETS: its lines jump shorter at t = 0.2 s, and no
    // step after that is solved at any size.
    let round = round_file();
    let mut args: Vec<String> = ["run", round.as_str(), "--quiet", "--out", "f", "--set"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    args.push("time.duration_s=0.4".into());
    args.extend(FAILING_PULL_SETS.iter().map(|s| s.to_string()));
    let o = run(tmp.path(), &args);
    let err = stderr(&o);
    assert_exit(&o, 3);
    for want in [
        "step failed at t = ",
        "residual",
        "worst at node",
        "resuming would repeat the failure",
    ] {
        assert!(err.contains(want), "want `{want}` in {err}");
    }
    // A failed step's checkpoint is the last good state, not a point to continue from.
    assert!(!err.contains("chute resume"), "{err}");
    let dir = tmp.path().join("f");
    let summary = read_json(dir.join("summary.json"));
    assert_eq!(summary["complete"], false);
    let c = Checkpoint::read(&dir).unwrap();
    let rows = csv_rows(&dir.join("timeseries.csv"));
    assert!(
        rows.len() > 10 && c.t > 0.0,
        "{} rows, t = {}",
        rows.len(),
        c.t
    );
    assert_eq!(rows.len() as u64, c.ts_rows);
    assert_eq!(rows.last().unwrap()[0], c.t);
    assert_eq!(summary["simulated_time_s"].as_f64().unwrap(), c.t);
}

#[cfg(unix)]
#[test]
fn sigterm_leaves_a_checkpoint_and_the_resumed_run_equals_the_uninterrupted_one() {
    let tmp = tempfile::tempdir().unwrap();
    let dur = "time.duration_s=1";
    let o = run(tmp.path(), &run_args("full", dur, &[]));
    assert_exit(&o, 0);

    let args = run_args("part", dur, &["--checkpoint-every", "0.1"]);
    // Signal once the run is under way (its fifth frame, t = 0.2 s, is written).
    let o = term_once_written(tmp.path(), &args, "part/frames/frame_000004.vtu");
    assert_exit_says(&o, 3, &["interrupted"]);
    let dir = tmp.path().join("part");
    let summary = read_json(dir.join("summary.json"));
    assert_eq!(summary["complete"], false);
    let c = Checkpoint::read(&dir).unwrap();
    assert!(c.synced);
    assert!(csv_rows(&dir.join("timeseries.csv")).len() as u64 >= c.ts_rows);

    // The directory alone: its record holds the scenario and the --set options (among them
    // the duration, 1 s, where the file says 10 s).
    chute_ok(tmp.path(), &["resume", "part", "--quiet"]);
    assert_same_outputs(&tmp.path().join("full"), &dir);
}

#[test]
fn same_inputs_give_identical_files_whatever_the_jobs() {
    let tmp = tempfile::tempdir().unwrap();
    let study = format!(
        "name = \"det\"\nbase = \"{}\"\n[grid]\n\"load.weight_n\" = [20, 200, 2000]\n",
        rod_file()
    );
    std::fs::write(tmp.path().join("det.toml"), study).unwrap();
    let sets = [
        "--set",
        "canopy.nodes=21",
        "--set",
        "time.duration_s=0.15",
        "--set",
        "output.snapshots_s=[0.05]",
    ];
    for (out, jobs) in [("j1", "1"), ("j3", "3")] {
        let mut a = vec!["study", "det.toml", "--out", out, "--jobs", jobs];
        a.extend(sets);
        chute_ok(tmp.path(), &a);
    }
    for case in ["weight_n-20", "weight_n-200", "weight_n-2000"] {
        assert_same_outputs(
            &tmp.path().join("j1").join(case),
            &tmp.path().join("j3").join(case),
        );
    }
    // A single run of the same case, twice, in other directories (without viewer.html, which
    // study cases do not write).
    for out in ["a", "b"] {
        let o = run(
            tmp.path(),
            &run_args(
                out,
                "time.duration_s=0.15",
                &[
                    "--no-viewer",
                    "--set",
                    "load.weight_n=200",
                    "--set",
                    "name=\"det-weight_n-200\"",
                ],
            ),
        );
        assert_exit(&o, 0);
    }
    assert_same_outputs(&tmp.path().join("a"), &tmp.path().join("b"));
    assert_same_outputs(&tmp.path().join("a"), &tmp.path().join("j3/weight_n-200"));
}

#[cfg(target_os = "linux")]
#[test]
fn an_unwritable_directory_is_refused_before_the_run_even_for_root() {
    // /proc/self is a directory nobody, root included, can create files in.
    let tmp = tempfile::tempdir().unwrap();
    let a = run_args("/proc/self", "time.duration_s=0.01", &["--force"]);
    let o = run(tmp.path(), &a);
    assert_exit_says(&o, 2, &["is not writable"]);
}

#[test]
fn resume_without_a_checkpoint_is_an_input_error() {
    let tmp = tempfile::tempdir().unwrap();
    let o = run(tmp.path(), &run_args("r", "time.duration_s=0.01", &[]));
    assert_exit(&o, 0);
    // No --checkpoint-every: a completed run keeps no checkpoint.
    let o = chute(tmp.path(), &["resume", "r"]);
    // It says what to do instead: run again, longer.
    let want = [
        "kept no checkpoint",
        "--checkpoint-every",
        "chute run r/scenario.resolved.toml --out r --force --set time.duration_s=T",
    ];
    assert_exit_says(&o, 2, &want);
}

#[test]
fn parallel_element_loops_give_identical_files_whatever_the_threads() {
    // A shell canopy fine enough (edge 0.1 m: ~4000 triangles, ~6000 hinges) that its element
    // loops run in parallel chunks; each element writes its own block, so the thread count
    // must not change a bit.
    let tmp = tempfile::tempdir().unwrap();
    let shell = repo().join("scenarios/report-shell-4-sites.toml");
    for (out, threads) in [("t1", "1"), ("t4", "4")] {
        let o = chute_command()
            .args(["run", shell.to_str().unwrap(), "--quiet", "--out", out])
            .args(["--set", "canopy.edge_length_m=0.1"])
            .args(["--set", "time.duration_s=0.003"])
            .args(["--set", "time.dt_s=0.001"])
            .args(["--set", "output.frame_interval_s=0.001"])
            .args(["--set", "output.snapshots_s=[0.002]"])
            .env("RAYON_NUM_THREADS", threads)
            .current_dir(tmp.path())
            .output()
            .unwrap();
        assert_exit(&o, 0);
    }
    let dofs = std::fs::read_to_string(tmp.path().join("t1/summary.json")).unwrap();
    assert!(dofs.contains("\"dofs\": "), "{dofs}");
    assert_same_outputs(&tmp.path().join("t1"), &tmp.path().join("t4"));
}

/// SIGTERM while a study's first case runs: that case is interrupted, the cases after it are
/// "not run" and get no directory (they never began), and the study exits 3.
#[cfg(unix)]
#[test]
fn a_stopped_study_does_not_begin_its_remaining_cases() {
    let tmp = tempfile::tempdir().unwrap();
    let study = repo().join("studies/table1.toml").display().to_string();
    let args: Vec<String> = ["study", &study, "--out", "s", "--jobs", "1"]
        .iter()
        .chain(&["--set", "time.duration_s=20"])
        .map(|s| s.to_string())
        .collect();
    let o = term_once_written(tmp.path(), &args, "s/20N/frames/frame_000002.vtu");
    let err = stderr(&o);
    assert_exit_says(&o, 3, &["not run: the study was stopped"]);
    for later in ["200N", "2000N"] {
        assert!(!tmp.path().join("s").join(later).exists(), "{later}: {err}");
    }
}

/// Run chute with `args` in `cwd`, send it SIGTERM once `file` (relative to `cwd`) exists, and
/// wait for it.
#[cfg(unix)]
fn term_once_written(cwd: &Path, args: &[String], file: &str) -> Output {
    let child = chute_command()
        .args(args)
        .current_dir(cwd)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let file = cwd.join(file);
    let start = Instant::now();
    while !file.exists() {
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "never started: no {file:?}"
        );
        std::thread::sleep(Duration::from_millis(5));
    }
    // Twice at once, as a group's signal forwarded by a parent (`timeout`) arrives: still one
    // stop with a checkpoint, not the deliberate second signal's abort.
    for sig in ["-TERM", "-INT"] {
        let kill = Command::new("kill")
            .args([sig, &child.id().to_string()])
            .status()
            .unwrap();
        assert!(kill.success());
    }
    child.wait_with_output().unwrap()
}

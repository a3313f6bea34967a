//! Run records through the binary: `chute resume DIR` continues from the directory alone,
//! only ever longer; `--force` replaces an earlier run entirely (or leaves it whole when the
//! new one cannot start) and never touches a directory chute did not write.
use crate::common::*;

use std::path::Path;
use std::process::Output;

/// `chute run` of the coarse rod into `out` with `extra` arguments.
fn run(cwd: &Path, out: &str, extra: &[&str]) -> Output {
    let f = rod_file();
    let mut a = vec![
        "run",
        &f,
        "--quiet",
        "--out",
        out,
        "--set",
        "canopy.nodes=21",
        "--set",
        "output.snapshots_s=[0.05]",
    ];
    a.extend(extra);
    chute(cwd, &a)
}

/// A 0.1 s run with checkpoints every 0.05 s and no viewer.
const CHECKPOINTED: [&str; 5] = [
    "--set",
    "time.duration_s=0.1",
    "--checkpoint-every",
    "0.05",
    "--no-viewer",
];

fn ok(o: &Output) {
    assert_eq!(o.status.code(), Some(0), "{}", stderr(o));
}

/// A new temporary directory holding `r`, a [`CHECKPOINTED`] run (which must succeed), and the
/// path of `r`.
fn checkpointed_in_tmp() -> (tempfile::TempDir, std::path::PathBuf) {
    let tmp = tempfile::tempdir().unwrap();
    ok(&run(tmp.path(), "r", &CHECKPOINTED));
    let r = tmp.path().join("r");
    (tmp, r)
}

/// A run with `extra` arguments into `out` of `cwd` is refused saying `want`, and every file of
/// `out` is left as it was.
fn refused_leaving_whole(cwd: &Path, out: &str, extra: &[&str], want: &str) {
    assert_untouched(&cwd.join(out), || {
        assert_refused(&run(cwd, out, extra), &[want]);
    });
}

#[test]
fn resume_with_no_arguments_continues_the_recorded_run() {
    let tmp = tempfile::tempdir().unwrap();
    let weight = ["--set", "load.weight_n=500"];
    let mut full = weight.to_vec();
    full.extend(["--set", "time.duration_s=0.35"]);
    ok(&run(tmp.path(), "full", &full));
    let mut part = weight.to_vec();
    part.extend(["--set", "time.duration_s=0.2", "--checkpoint-every", "0.1"]);
    ok(&run(tmp.path(), "part", &part));
    // Nothing but the directory and the longer duration: the load override, the mesh and
    // the checkpoint interval come from the run's record.
    ok(&chute(
        tmp.path(),
        &["resume", "part", "-q", "--set", "time.duration_s=0.35"],
    ));
    assert_same_outputs(&tmp.path().join("full"), &tmp.path().join("part"));
    let c = chute::checkpoint::Checkpoint::read(&tmp.path().join("part")).unwrap();
    assert_eq!(c.checkpoint_every_s, Some(0.1));
    assert!(
        c.t > 0.25,
        "the resumed run kept checkpointing: last at {} s",
        c.t
    );
}

#[test]
fn shorter_duration_resume_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let args = ["--set", "time.duration_s=0.2", "--checkpoint-every", "0.1"];
    ok(&run(tmp.path(), "r", &args));
    let want = [
        "time.duration_s = 0.1 s",
        "recorded run's 0.2 s",
        "extended",
    ];
    assert_untouched(&tmp.path().join("r"), || {
        let o = chute(tmp.path(), &["resume", "r", "--set", "time.duration_s=0.1"]);
        assert_refused(&o, &want);
    });
}

#[test]
fn resume_refuses_overrides_other_than_the_duration() {
    let tmp = tempfile::tempdir().unwrap();
    ok(&run(
        tmp.path(),
        "r",
        &["--set", "time.duration_s=0.15", "--checkpoint-every", "0.1"],
    ));
    assert_refused(
        &chute(tmp.path(), &["resume", "r", "--set", "load.weight_n=20"]),
        &["only time.duration_s may change", "chute run"],
    );
    assert_refused(
        &chute(tmp.path(), &["resume", "r", "--checkpoint-every", "-1"]),
        &["--checkpoint-every -1: must be a positive number"],
    );
    assert_refused(
        &chute(tmp.path(), &["resume", "r", "--checkpoint-every", "-inf"]),
        &["--checkpoint-every -inf: must be a positive number"],
    );
    assert_refused(
        &chute(tmp.path(), &["resume", "nowhere"]),
        &["not a directory"],
    );
    assert_refused(
        &chute(tmp.path(), &["run", &rod_file(), "--resume", "r"]),
        &["retired", "chute resume r"],
    );
}

#[test]
fn force_leaves_nothing_old() {
    let tmp = tempfile::tempdir().unwrap();
    // An earlier run with 7 frames, a snapshot, plots, a checkpoint and the viewer.
    let long = ["--set", "time.duration_s=0.3", "--checkpoint-every", "0.1"];
    ok(&run(tmp.path(), "d", &long));
    // A run that fails after its first frames (exit 3; FAILING_PULL_SETS), once fresh and
    // once over the earlier one: the two directories hold the same files.
    let round = round_file();
    let failing = |out: &'static str, force: bool| {
        let mut a = vec![
            "run",
            round.as_str(),
            "--quiet",
            "--out",
            out,
            "--no-viewer",
        ];
        a.extend(["--set", "time.duration_s=0.4"]);
        a.extend(FAILING_PULL_SETS);
        if force {
            a.push("--force");
        }
        chute(tmp.path(), &a)
    };
    let o = failing("fresh", false);
    assert_exit(&o, 3);
    let o = failing("d", true);
    assert_exit(&o, 3);
    assert_same_outputs(&tmp.path().join("fresh"), &tmp.path().join("d"));
    // A run that cannot start (an input error) leaves the earlier run whole.
    let bad = ["--set", "lines.length_m=1", "--set", "load.mode=payload"];
    assert_untouched(&tmp.path().join("d"), || {
        assert_exit(&run(tmp.path(), "d", &[&["--force"][..], &bad].concat()), 2);
    });
}

#[test]
fn force_never_deletes_files_chute_did_not_write() {
    let tmp = tempfile::tempdir().unwrap();
    let short = ["--set", "time.duration_s=0.05", "--force"];
    // Not a run directory: refused, untouched.
    std::fs::create_dir(tmp.path().join("mine")).unwrap();
    std::fs::write(tmp.path().join("mine/notes.txt"), "keep").unwrap();
    assert_refused(
        &run(tmp.path(), "mine", &short),
        &["not a chute run directory"],
    );
    assert_eq!(files(&tmp.path().join("mine")).len(), 1);
    // A run directory with a file of the user's: replaced, the file kept.
    ok(&run(tmp.path(), "r", &short));
    std::fs::write(tmp.path().join("r/notes.txt"), "keep").unwrap();
    std::fs::write(tmp.path().join("r/frames/mine.vtu"), "keep").unwrap();
    ok(&run(tmp.path(), "r", &short));
    let after = files(&tmp.path().join("r"));
    assert_eq!(after["notes.txt"], b"keep");
    assert_eq!(after["frames/mine.vtu"], b"keep");
}

/// A resumed run writes its files in place: a run file replaced by a link (to a file of the
/// user's elsewhere) is refused before anything is written, and the linked file is untouched.
#[test]
fn resume_refuses_a_run_file_that_is_a_link() {
    let (tmp, _) = checkpointed_in_tmp();
    let ts = tmp.path().join("r/timeseries.csv");
    let outside = tmp.path().join("elsewhere.csv");
    std::fs::rename(&ts, &outside).unwrap();
    std::os::unix::fs::symlink(&outside, &ts).unwrap();
    let before = std::fs::read(&outside).unwrap();
    let o = chute(tmp.path(), &["resume", "r", "--set", "time.duration_s=0.2"]);
    assert_refused(&o, &["timeseries.csv", "symbolic link"]);
    assert!(
        std::fs::read(&outside).unwrap() == before,
        "the linked file changed"
    );
}

/// A directory with a checkpoint but without the run's scenario is not a whole run: resume
/// refuses it as bad input (status 2) saying what is missing.
#[test]
fn resume_without_the_resolved_scenario_is_bad_input() {
    let (tmp, _) = checkpointed_in_tmp();
    std::fs::remove_file(tmp.path().join("r/scenario.resolved.toml")).unwrap();
    let o = chute(tmp.path(), &["resume", "r"]);
    assert_refused(&o, &["scenario.resolved.toml"]);
}

/// A run that ends before its first sync point (64 steps) writes no checkpoint whatever
/// `--checkpoint-every` asks: its summary says so instead of leaving it to a failed resume.
#[test]
fn a_run_too_short_for_a_checkpoint_says_so() {
    let tmp = tempfile::tempdir().unwrap();
    ok(&run(
        tmp.path(),
        "r",
        &[
            "--set",
            "time.duration_s=0.05",
            "--checkpoint-every",
            "0.01",
            "--no-viewer",
        ],
    ));
    let summary = std::fs::read_to_string(tmp.path().join("r/summary.json")).unwrap();
    assert!(summary.contains("no checkpoint was written"), "{summary}");
    assert!(!tmp.path().join("r/checkpoint.bin").exists());
}

/// A directory copied with hard links (`cp -al`) shares its files with the original: resuming
/// the copy, or running again into it with `--force`, gives the copy new files and leaves
/// every byte of the original as it was.
#[test]
fn a_hard_linked_copy_is_resumed_and_rerun_without_changing_the_original() {
    let (tmp, _) = checkpointed_in_tmp();
    let cp = |to: &str| {
        tool(
            tmp.path(),
            "cp",
            &["-al".as_ref(), "r".as_ref(), to.as_ref()],
        )
    };
    cp("linked");
    cp("linked2");
    let before = files(&tmp.path().join("r"));
    ok(&chute(
        tmp.path(),
        &["resume", "linked", "-q", "--set", "time.duration_s=0.15"],
    ));
    ok(&run(
        tmp.path(),
        "linked2",
        &["--set", "time.duration_s=0.05", "--force", "--no-viewer"],
    ));
    assert!(
        before == files(&tmp.path().join("r")),
        "the original directory changed"
    );
    let resumed = csv_rows(&tmp.path().join("linked/timeseries.csv"));
    assert!(resumed.len() > csv_rows(&tmp.path().join("r/timeseries.csv")).len());
}

/// Every check of a resume is made before anything changes: a directory standing where the
/// stopped run's later frame was (which the resume would have to remove), or a kept frame
/// replaced by a link, is refused and the directory is left exactly as it was.
#[test]
fn resume_refuses_frames_it_could_not_keep_or_remove_before_touching_anything() {
    let (tmp, r) = checkpointed_in_tmp();
    let later = r.join("frames/frame_000099.vtu");
    std::fs::create_dir(&later).unwrap();
    std::fs::write(later.join("inside"), "x").unwrap();
    assert_untouched(&r, || {
        let o = chute(tmp.path(), &["resume", "r", "--set", "time.duration_s=0.2"]);
        assert_refused(&o, &["frame_000099.vtu", "is a directory"]);
    });
    std::fs::remove_dir_all(&later).unwrap();

    let kept = r.join("frames/frame_000000.vtu");
    let outside = tmp.path().join("frame.vtu");
    std::fs::rename(&kept, &outside).unwrap();
    std::os::unix::fs::symlink(&outside, &kept).unwrap();
    let o = chute(tmp.path(), &["resume", "r", "--set", "time.duration_s=0.2"]);
    assert_refused(&o, &["frame_000000.vtu", "symbolic link"]);
}

/// A run that failed before it wrote its scenario (a full disk) leaves only its record: resume
/// and view say so with the record's reason, and resume advises running the scenario file
/// again, not a file the directory does not have.
#[test]
fn a_directory_with_only_a_failed_record_says_why_on_resume_and_view() {
    let tmp = tempfile::tempdir().unwrap();
    let r = tmp.path().join("r");
    std::fs::create_dir(&r).unwrap();
    let record = r#"{"status": "failed", "reason": "writing r/x: No space left on device (os error 28)", "inputs": [], "viewer": true}"#;
    std::fs::write(r.join("run.json"), record).unwrap();
    let o = chute(tmp.path(), &["resume", "r"]);
    assert_refused(
        &o,
        &[
            "no scenario.resolved.toml",
            "No space left on device",
            "chute run SCENARIO --out r --force",
        ],
    );
    let o = chute(tmp.path(), &["view", "r"]);
    assert_refused(&o, &["its run did not finish", "No space left on device"]);
}

/// `--force` replaces only what is chute's: a user's pictures named like a snapshot but
/// without its time (`snapshot_of_the_bags.png`) stay, and a directory whose `run.json` is
/// another tool's is not a chute run, so `--force` refuses it (status 2) and changes nothing.
#[test]
fn force_replaces_only_chute_files_and_runs() {
    let (tmp, r) = checkpointed_in_tmp();
    for name in ["snapshot_of_the_bags.png", "snapshot_v2s.png"] {
        std::fs::write(r.join(name), "the user's").unwrap();
    }
    ok(&run(tmp.path(), "r", &["--force", "--no-viewer"]));
    for name in ["snapshot_of_the_bags.png", "snapshot_v2s.png"] {
        assert!(r.join(name).is_file(), "{name} was removed");
    }
    let other = tmp.path().join("other");
    std::fs::create_dir(&other).unwrap();
    std::fs::write(other.join("run.json"), r#"{"my": "config"}"#).unwrap();
    std::fs::write(other.join("summary.json"), r#"{"mine": 1}"#).unwrap();
    refused_leaving_whole(
        tmp.path(),
        "other",
        &["--force"],
        "not a chute run directory",
    );
}

/// A directory copied with hard links shares the original's lock and reserve files: the
/// copy's writer gets files of its own, so the original's lock (another process's, or a
/// dead one's description) keeps its bytes and never blocks the copy.
#[test]
fn a_hard_linked_copy_gets_its_own_lock() {
    let (tmp, _) = checkpointed_in_tmp();
    let lock = tmp.path().join("r/.chute.lock");
    std::fs::write(&lock, "pid=1\nhost=elsewhere\n").unwrap();
    tool(
        tmp.path(),
        "cp",
        &["-al".as_ref(), "r".as_ref(), "copy".as_ref()],
    );
    // The original's lock file held by a process of its own (as a live run would).
    let held = std::fs::File::open(&lock).unwrap();
    held.lock().unwrap();
    ok(&run(tmp.path(), "copy", &["--force", "--no-viewer"]));
    assert_eq!(
        std::fs::read_to_string(&lock).unwrap(),
        "pid=1\nhost=elsewhere\n"
    );
}

/// A `frames` that is a file where a run would write its frames is refused (status 2) before
/// `--force` clears the earlier run, which is left whole.
#[test]
fn force_over_a_frames_file_is_refused_before_clearing() {
    let (tmp, r) = checkpointed_in_tmp();
    std::fs::remove_dir_all(r.join("frames")).unwrap();
    std::fs::write(r.join("frames"), "not a directory").unwrap();
    refused_leaving_whole(
        tmp.path(),
        "r",
        &["--force"],
        "`r/frames` is not a directory",
    );
}

/// A directory where a run writes one of its files (`canopy.pvd/`, a frame's name) is refused
/// (status 2) before `--force` clears the earlier run or a resume cuts it back: it is left whole.
#[test]
fn force_over_a_directory_named_like_a_run_file_is_refused_before_clearing() {
    let (tmp, r) = checkpointed_in_tmp();
    for taken in ["canopy.pvd", "frames/frame_000001.vtu"] {
        let path = r.join(taken);
        let kept = std::fs::read(&path).unwrap();
        std::fs::remove_file(&path).unwrap();
        std::fs::create_dir(&path).unwrap();
        let before = std::fs::read_dir(&r).unwrap().count();
        let o = run(tmp.path(), "r", &["--force"]);
        assert_refused(
            &o,
            &[&format!(
                "`r/{taken}` is a directory: a run writes a file of that name"
            )],
        );
        assert_eq!(
            before,
            std::fs::read_dir(&r).unwrap().count(),
            "the earlier run was changed"
        );
        assert!(r.join("summary.json").is_file());
        // Nor does a resume cut its time series back first.
        let series = std::fs::read(r.join("timeseries.csv")).unwrap();
        let o = chute(tmp.path(), &["resume", "r", "--quiet"]);
        assert_refused(&o, &[&format!("`r/{taken}` is a directory")]);
        assert_eq!(series, std::fs::read(r.join("timeseries.csv")).unwrap());
        std::fs::remove_dir(&path).unwrap();
        std::fs::write(&path, kept).unwrap();
    }
}

/// A clearing killed after it moved the earlier run's files aside leaves only chute's
/// `.chute.old`: the directory is still chute's, and `--force` clears it and runs.
#[test]
fn a_killed_clearing_leaves_a_directory_force_can_still_replace() {
    let tmp = tempfile::tempdir().unwrap();
    let r = tmp.path().join("r");
    std::fs::create_dir_all(r.join(".chute.old")).unwrap();
    std::fs::create_dir_all(r.join("frames")).unwrap();
    std::fs::write(r.join(".chute.old/0"), "the earlier run.json").unwrap();
    ok(&run(tmp.path(), "r", &["--force", "--no-viewer"]));
    assert!(!r.join(".chute.old").exists());
    assert!(r.join("summary.json").is_file());
    // A `.chute.old` of the user's is in the way: bad input (status 2), the run kept whole.
    ok(&run(
        tmp.path(),
        "r",
        &[&CHECKPOINTED[..], &["--force"]].concat(),
    ));
    std::fs::create_dir(r.join(".chute.old")).unwrap();
    std::fs::write(r.join(".chute.old/notes.txt"), "mine").unwrap();
    let held = "`r/.chute.old` holds files chute did not put there";
    refused_leaving_whole(tmp.path(), "r", &["--force", "--no-viewer"], held);
    // Nor does a resume touch the run (its record included).
    assert_untouched(&r, || {
        assert_refused(&chute(tmp.path(), &["resume", "r", "--quiet"]), &[held]);
    });
}

/// A directory whose `--force` clearing was killed after its record was moved aside is not
/// a complete run: `view` notes an unfinished run, and resume does not call it complete.
#[test]
fn a_half_cleared_run_is_not_described_as_complete() {
    let (tmp, r) = checkpointed_in_tmp();
    std::fs::create_dir(r.join(".chute.old")).unwrap();
    std::fs::rename(r.join("run.json"), r.join(".chute.old/0")).unwrap();
    std::fs::remove_file(r.join("checkpoint.bin")).unwrap();
    let o = chute(tmp.path(), &["view", "r"]);
    assert_exit_says(&o, 0, &["unfinished run"]);
    let o = chute(tmp.path(), &["resume", "r"]);
    assert_exit(&o, 2);
    assert_stderr_lacks(&o, &["the run is complete"]);
}

/// A run whose record was deleted, beside a checkpoint of a chute that always writes one, is
/// not resumed on trust: nothing could check its input files against the run's.
#[test]
fn a_resume_without_the_record_its_checkpoint_implies_is_refused() {
    let (tmp, _) = checkpointed_in_tmp();
    std::fs::remove_file(tmp.path().join("r/run.json")).unwrap();
    let o = chute(tmp.path(), &["resume", "r", "--set", "time.duration_s=0.2"]);
    assert_refused(&o, &["run.json", "is missing", "chute run"]);
}

/// A frame its run listed that is gone (a resume killed while it moved later frames aside)
/// is the run's state: `view` says which file is missing (status 2), not a bare I/O error.
#[test]
fn view_names_a_missing_frame_of_its_run() {
    let (tmp, _) = checkpointed_in_tmp();
    let frame = tmp.path().join("r/frames/frame_000001.vtu");
    std::fs::remove_file(&frame).unwrap();
    let o = chute(tmp.path(), &["view", "r"]);
    assert_refused(&o, &["frame_000001.vtu", "a file of its run, is missing"]);
}

/// A run with pulled lines is not resumed without its `lines.csv` (its rows up to the
/// checkpoint would be lost for good): refused, status 2, naming the file.
#[test]
fn a_pulled_run_without_its_lines_file_is_not_resumed() {
    let tmp = tempfile::tempdir().unwrap();
    let steer = repo().join("scenarios/control-steer.toml");
    let steer = steer.to_str().unwrap();
    let set = ["--set", "time.duration_s=0.1", "--checkpoint-every", "0.05"];
    let o = chute(
        tmp.path(),
        &[&["run", steer, "-q", "--no-viewer", "--out", "r"][..], &set].concat(),
    );
    ok(&o);
    let resume = ["resume", "r", "--set", "time.duration_s=0.15"];
    // One row of the checkpoint's last frame (t = 0.05 s: frames and checkpoints every
    // 0.05 s, the run ended at 0.1 s) cut out: that frame's rows are not whole.
    let lines = tmp.path().join("r/lines.csv");
    let text = std::fs::read_to_string(&lines).unwrap();
    let gone = text.lines().position(|l| l.starts_with("0.05")).unwrap();
    let kept: Vec<&str> = text
        .lines()
        .enumerate()
        .filter(|&(i, _)| i != gone)
        .map(|(_, l)| l)
        .collect();
    std::fs::write(&lines, kept.join("\n") + "\n").unwrap();
    assert_refused(
        &chute(tmp.path(), &resume),
        &["lines.csv", "run the scenario again"],
    );
    std::fs::remove_file(&lines).unwrap();
    assert_refused(
        &chute(tmp.path(), &resume),
        &["lines.csv", "run the scenario again"],
    );
}

/// A resume that writes no viewer removes the earlier one, which showed the run as it stood
/// when it stopped.
#[test]
fn a_resume_without_a_viewer_leaves_no_stale_one() {
    let tmp = tempfile::tempdir().unwrap();
    ok(&run(tmp.path(), "r", &CHECKPOINTED[..4]));
    assert!(tmp.path().join("r/viewer.html").is_file());
    let args = ["resume", "r", "--no-viewer", "--set", "time.duration_s=0.2"];
    ok(&chute(tmp.path(), &args));
    assert!(!tmp.path().join("r/viewer.html").exists());
    // Recorded, so that a later resume does as this one was told.
    let record = std::fs::read_to_string(tmp.path().join("r/run.json")).unwrap();
    assert!(record.contains("\"viewer\": false"), "{record}");
}

/// A picture that cannot take its place (a directory of its name) is warned of and leaves no
/// temporary behind.
#[test]
fn a_picture_that_cannot_be_renamed_leaves_no_temporary() {
    let (tmp, r) = checkpointed_in_tmp();
    std::fs::remove_file(r.join("velocity.png")).unwrap();
    std::fs::create_dir(r.join("velocity.png")).unwrap();
    std::fs::write(r.join("velocity.png/mine"), "x").unwrap();
    ok(&run(tmp.path(), "r", &["--force", "--no-viewer"]));
    let summary = std::fs::read_to_string(r.join("summary.json")).unwrap();
    assert!(
        summary.contains("velocity.png was not written"),
        "{summary}"
    );
    let left: Vec<String> = std::fs::read_dir(&r)
        .unwrap()
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .filter(|n| n.ends_with(".tmp.png"))
        .collect();
    assert!(left.is_empty(), "{left:?}");
}

//! Runs and studies on a full file system (docs/reliability.md §5), in a 1 MiB tmpfs of a
//! private mount namespace (root only; `CHUTE_NO_TMPFS=1` skips these tests): whole rows, a
//! record of why naming the file, nothing left by what did not run, and no output missing
//! without a word.
use crate::common::*;
use crate::integrity::rod_run;

use std::path::{Path, PathBuf};

/// A temporary directory for a test of a full tmpfs, or `None` (skip the test) when
/// `CHUTE_NO_TMPFS` is set.
fn tmpfs_test_dir() -> Option<tempfile::TempDir> {
    if std::env::var_os("CHUTE_NO_TMPFS").is_some() {
        return None;
    }
    Some(tempfile::tempdir().unwrap())
}

/// [`in_small_tmpfs`], then what the script wrote to `out/code` (its command's exit status,
/// which must be there) and to `out/err` (its stderr).
fn code_and_err_in_small_tmpfs(cwd: &Path, script: &str) -> (String, String) {
    let o = in_small_tmpfs(cwd, script);
    let code = std::fs::read_to_string(cwd.join("out/code"))
        .unwrap_or_else(|_| panic!("no tmpfs run: {}", stderr(&o)));
    let err = std::fs::read_to_string(cwd.join("out/err")).unwrap();
    (code, err)
}

/// The test's tmpfs: `sh -c SCRIPT` in a private mount namespace (root only).
fn in_small_tmpfs(cwd: &Path, script: &str) -> std::process::Output {
    let o = std::process::Command::new("unshare")
        .args(["-m", "sh", "-c", script])
        .current_dir(cwd)
        .output()
        .expect("unshare runs");
    assert!(
        !String::from_utf8_lossy(&o.stderr).contains("unshare failed"),
        "this test needs root (a private mount namespace and a tmpfs); set CHUTE_NO_TMPFS=1 to skip it: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    o
}

#[test]
fn a_full_file_system_leaves_whole_rows_and_a_record_of_why() {
    let Some(tmp) = tmpfs_test_dir() else {
        return;
    };
    let bin = PathBuf::from(env!("CARGO_BIN_EXE_chute"));
    let quote = |args: Vec<String>| {
        let q: Vec<String> = args.iter().map(|a| format!("'{a}'")).collect();
        q.join(" ")
    };
    // 1 MiB: the time series and frames fill it within seconds of simulated time. With the
    // rest filled up too, a second run into a new directory is refused (status 1, an I/O
    // failure: it cannot set its reserve aside) and leaves neither its lock file nor the
    // directory it created.
    let script = format!(
        "mkdir -p small out && mount -t tmpfs -o size=1m tmpfs small && {bin} {}; echo $? > out/code; \
         cp -r small/d out/d; dd if=/dev/zero of=small/fill bs=4096 2>/dev/null; \
         {bin} {}; echo $? > out/code2; if [ -e small/new ]; then ls -a small/new > out/new; fi",
        quote(rod_run("600", "small/d", &["--no-viewer"])),
        quote(rod_run("600", "small/new", &["--no-viewer"])),
        bin = bin.display(),
    );
    let o = in_small_tmpfs(tmp.path(), &script);
    let code = std::fs::read_to_string(tmp.path().join("out/code")).unwrap_or_else(|_| {
        panic!(
            "the run in a 1 MiB tmpfs did not happen (this test needs root for a private mount namespace; CHUTE_NO_TMPFS=1 skips it): {}",
            String::from_utf8_lossy(&o.stderr)
        )
    });
    assert_eq!(
        code.trim(),
        "1",
        "an I/O error: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    let code2 = std::fs::read_to_string(tmp.path().join("out/code2")).unwrap();
    assert_eq!(
        code2.trim(),
        "1",
        "a run on a full disk is refused as an I/O failure, not as bad input"
    );
    let left = std::fs::read_to_string(tmp.path().join("out/new")).unwrap_or_default();
    assert!(
        left.is_empty(),
        "the refused run left its directory: {left}"
    );
    let dir = tmp.path().join("out/d");
    // Whole rows only, every one of them numbers.
    let rows = csv_rows(&dir.join("timeseries.csv"));
    assert!(rows.len() > 100 && rows.iter().all(|r| r.len() == 17));
    let record = read_json(dir.join("run.json"));
    assert_eq!(record["status"], "failed", "{record}");
    // Naming the file that could not be written (a frame, the collection, the time series),
    // not only the directory.
    let reason = record["reason"].as_str().unwrap();
    assert!(
        reason.contains("No space left") && reason.contains("small/d/"),
        "{record}"
    );
    // What was written can still be read.
    let o = chute(tmp.path(), &["view", "out/d"]);
    assert_exit_says(&o, 0, &["the run failed: "]);
}

/// A study on a full file system: a case whose directory cannot take its lock and reserve is
/// "not run" and the study goes on to the others and to the table, instead of stopping at
/// the first case as if the input were bad (status 2).
#[test]
fn a_study_on_a_full_file_system_goes_through_every_case() {
    let Some(tmp) = tmpfs_test_dir() else {
        return;
    };
    let bin = PathBuf::from(env!("CARGO_BIN_EXE_chute"));
    let study = repo().join("studies/table1.toml").display().to_string();
    let script = format!(
        "mkdir -p small out && mount -t tmpfs -o size=1m tmpfs small && \
         dd if=/dev/zero of=small/fill bs=4096 2>/dev/null; \
         {bin} study '{study}' --out small/S --set time.duration_s=0.02 2> out/err; echo $? > out/code; \
         ls -A small/S > out/left 2>/dev/null; \
         {bin} study '{study}' --out out/T --set time.duration_s=0.02 2>/dev/null; \
         {bin} collect out/T --out small/C 2>/dev/null; echo $? > out/ccode; \
         if [ -e small/C ]; then echo left > out/cleft; fi",
        bin = bin.display()
    );
    let (code, err) = code_and_err_in_small_tmpfs(tmp.path(), &script);
    // The table cannot be written either: an I/O error (1), not bad input (2).
    assert_eq!(code.trim(), "1", "{err}");
    for case in ["20N", "200N", "2000N"] {
        let not_run = format!("case {case}: not run: ");
        assert!(err.contains(&not_run), "{case} not reported: {err}");
    }
    // Cases that did not run leave no directories that look like cases.
    let left = std::fs::read_to_string(tmp.path().join("out/left")).unwrap_or_default();
    for case in ["20N", "200N", "2000N"] {
        assert!(
            !left.lines().any(|l| l == case),
            "{case}'s directory is left: {left}"
        );
    }
    // A table that cannot be written: an I/O error, and the directory made for it is gone.
    let ccode = std::fs::read_to_string(tmp.path().join("out/ccode")).unwrap();
    assert_eq!(ccode.trim(), "1");
    assert!(
        !tmp.path().join("out/cleft").exists(),
        "collect left its --out"
    );
}

/// A run that fits on the disk but whose pictures do not: each missing picture is named in a
/// warning of `summary.json` (and so on the console), never silently absent.
#[test]
fn a_picture_that_cannot_be_written_is_named_in_a_warning() {
    let Some(tmp) = tmpfs_test_dir() else {
        return;
    };
    let run = quoted_rod_run("small/r", "0.05", &[]);
    let script = format!(
        "mkdir -p small out && mount -t tmpfs -o size=1m tmpfs small && \
         head -c 850K /dev/zero > small/filler && {run} 2> out/err; echo $? > out/code; \
         cp small/r/summary.json out/ 2>/dev/null; ls small/r > out/files"
    );
    let (code, err) = code_and_err_in_small_tmpfs(tmp.path(), &script);
    assert_eq!(code.trim(), "0", "{err}");
    let files = std::fs::read_to_string(tmp.path().join("out/files")).unwrap();
    let summary: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(tmp.path().join("out/summary.json")).unwrap(),
    )
    .unwrap();
    let warnings = summary["warnings"].to_string();
    let mut missing = 0;
    for png in ["shape.png", "velocity.png", "height.png"] {
        if !files.lines().any(|l| l == png) {
            missing += 1;
            assert!(
                warnings.contains(&format!("{png} was not written: plot I/O: No space left")),
                "{png} missing without a plain warning: {warnings}"
            );
        }
    }
    assert!(
        missing > 0,
        "the disk held every picture: the test tests nothing ({files})"
    );
}

/// Whatever the disk can still take, a run that ended never leaves a record saying
/// `running`: at every fill level from 880 KiB to 1 MiB of a 1 MiB tmpfs, the run either
/// is refused before it starts (no record) or records how it ended; and its time series
/// reaches as far as the last frame it wrote.
#[test]
fn no_fill_level_leaves_a_record_saying_running() {
    let Some(tmp) = tmpfs_test_dir() else {
        return;
    };
    // A frame every 0.01 s: the disk fills between frames as often as at the end.
    let run = quoted_rod_run("small/r", "0.2", &["--set", "output.frame_interval_s=0.01"]);
    let mut script = String::from("mkdir -p small out && mount -t tmpfs -o size=1m tmpfs small");
    for k in (880..=1024).step_by(8) {
        script.push_str(&format!(
            " && rm -rf small/r small/filler; head -c {k}K /dev/zero > small/filler 2>/dev/null; \
             {run} 2>/dev/null; cat small/r/run.json > out/{k}.json 2>/dev/null; \
             cp small/r/timeseries.csv out/{k}.csv 2>/dev/null; cp small/r/canopy.pvd out/{k}.pvd 2>/dev/null; true"
        ));
    }
    let o = in_small_tmpfs(tmp.path(), &script);
    let mut seen = 0;
    for k in (880..=1024).step_by(8) {
        let Ok(text) = std::fs::read_to_string(tmp.path().join(format!("out/{k}.json"))) else {
            continue;
        };
        if text.trim().is_empty() {
            continue;
        }
        seen += 1;
        let record: serde_json::Value = serde_json::from_str(&text)
            .unwrap_or_else(|e| panic!("{k} KiB filler: run.json unreadable ({e}): {text}"));
        assert_ne!(record["status"], "running", "{k} KiB filler: {record}");
        // The rows reach the disk before each frame: every frame the collection lists has
        // the time series up to its time beside it.
        let last_frame = std::fs::read_to_string(tmp.path().join(format!("out/{k}.pvd")))
            .unwrap_or_default()
            .split("timestep=\"")
            .skip(1)
            .filter_map(|t| t.split('"').next()?.parse::<f64>().ok())
            .fold(f64::NEG_INFINITY, f64::max);
        let csv = tmp.path().join(format!("out/{k}.csv"));
        let rows = if csv.is_file() {
            csv_rows(&csv)
        } else {
            Vec::new()
        };
        let last_row = rows.last().map_or(f64::NEG_INFINITY, |r| r[0]);
        assert!(
            last_row >= last_frame || last_frame == 0.0,
            "{k} KiB filler: the time series ends at {last_row} s, its last frame is at {last_frame} s"
        );
    }
    assert!(
        seen > 0,
        "no run got a record at any fill level: {}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// The shell command of a coarse-rod run of `duration` s into `out`, without the viewer,
/// with `extra` arguments.
fn quoted_rod_run(out: &str, duration: &str, extra: &[&str]) -> String {
    let bin = PathBuf::from(env!("CARGO_BIN_EXE_chute"));
    let extra = [&["--no-viewer"][..], extra].concat();
    let args: Vec<String> = rod_run(duration, out, &extra)
        .iter()
        .map(|a| format!("'{a}'"))
        .collect();
    format!("{} {}", bin.display(), args.join(" "))
}

/// A resume that finds too little room to cut its time series back fails as an I/O failure
/// (status 1) without changing the run's data: the time series, the frames, the collection
/// and the summary are byte for byte the stopped run's (the record says the resume failed,
/// and the resolved scenario holds the duration it was asked for).
#[test]
fn a_resume_without_room_changes_nothing_and_exits_1() {
    let Some(tmp) = tmpfs_test_dir() else {
        return;
    };
    let run = quoted_rod_run(
        "small/r",
        "0.5",
        &[
            "--set",
            "output.snapshots_s=[]",
            "--checkpoint-every",
            "0.1",
        ],
    );
    let bin = PathBuf::from(env!("CARGO_BIN_EXE_chute"));
    // Room for the reserve (64 KiB) but not for a copy of the time series beside it.
    let script = format!(
        "mkdir -p small out && mount -t tmpfs -o size=2m tmpfs small && {run} && \
         cp -r small/r out/before && \
         dd if=/dev/zero of=small/fill bs=1k count=$(( $(df -k --output=avail small | tail -1) - 80 )) 2>/dev/null; \
         {bin} resume small/r --quiet --set time.duration_s=1 2> out/err; echo $? > out/code; \
         cp -r small/r out/after",
        bin = bin.display()
    );
    let (code, err) = code_and_err_in_small_tmpfs(tmp.path(), &script);
    assert_eq!(code.trim(), "1", "{err}");
    assert!(
        err.contains("No space left") && !err.contains(" at path "),
        "{err}"
    );
    let (before, after) = (
        files(&tmp.path().join("out/before")),
        files(&tmp.path().join("out/after")),
    );
    for (name, bytes) in &before {
        if name == "run.json" || name == "scenario.resolved.toml" {
            continue;
        }
        assert!(after.get(name) == Some(bytes), "{name} changed: {err}");
    }
}

/// An earlier run one of whose files cannot be removed (its `frames/` on a read-only mount)
/// is left whole by `run --force` and by a resume that would remove its later frames: every
/// file keeps its bytes, each command fails naming a frame, and the run can still be viewed.
#[test]
fn a_run_with_a_file_that_cannot_be_removed_is_left_whole() {
    let Some(tmp) = tmpfs_test_dir() else {
        return;
    };
    // Its checkpoint is at the sync point t = 0.128 s (the first after 0.1 s), so the frames
    // at 0.15 and 0.2 s come after it: a resume removes them.
    let run = quoted_rod_run("r", "0.2", &["--checkpoint-every", "0.1"]);
    let force = quoted_rod_run("r", "0.1", &["--force"]);
    let bin = PathBuf::from(env!("CARGO_BIN_EXE_chute"));
    let script = format!(
        "{run} && cp -a r before && mount --bind r/frames r/frames && \
         mount -o remount,bind,ro r/frames && {force} 2> err; echo $? > code; \
         {bin} resume r --quiet --set time.duration_s=0.3 2> err2; echo $? > code2",
        bin = bin.display()
    );
    let o = in_small_tmpfs(tmp.path(), &script);
    for (code, err) in [("code", "err"), ("code2", "err2")] {
        let code = std::fs::read_to_string(tmp.path().join(code))
            .unwrap_or_else(|_| panic!("no run: {}", String::from_utf8_lossy(&o.stderr)));
        let err = std::fs::read_to_string(tmp.path().join(err)).unwrap();
        assert_eq!(code.trim(), "1", "{err}");
        assert!(err.contains("frames/frame_0000"), "{err}");
        let (before, after) = (
            files(&tmp.path().join("before")),
            files(&tmp.path().join("r")),
        );
        for (name, bytes) in &before {
            // The record says the last attempt failed, and with what.
            if name != "run.json" && name != "scenario.resolved.toml" {
                assert!(after.get(name) == Some(bytes), "{name} changed: {err}");
            }
        }
        assert_eq!(before.len(), after.len(), "{err}");
    }
    let o = chute(tmp.path(), &["view", "r"]);
    assert_exit(&o, 0);
}

/// `run --force` over an earlier run on a disk with room for the lock but not for the new
/// run's record or resolved scenario fails naming that file (status 1) and puts the earlier
/// run back whole: never an emptied directory. The room left is stepped across the sizes
/// where the record, then the resolved scenario, no longer fit (tmpfs pages); each run either
/// ran, or failed leaving the earlier run byte for byte.
#[test]
fn a_forced_run_that_cannot_write_its_record_leaves_the_earlier_run_whole() {
    let Some(tmp) = tmpfs_test_dir() else {
        return;
    };
    let lefts = [60, 64, 68, 72, 76, 80];
    let steps: Vec<String> = lefts
        .iter()
        .map(|left| {
            format!(
                "rm -rf small/r small/fill && cp -a before small/r && \
                 dd if=/dev/zero of=small/fill bs=1k count=$(( $(df -k --output=avail small | tail -1) - {left} )) 2>/dev/null; \
                 {force} 2> out/err{left}; echo $? > out/code{left}; rm -rf out/r{left}; cp -a small/r out/r{left}",
                force = quoted_rod_run("small/r", "0.1", &["--force", "--set", "load.weight_n=150"])
            )
        })
        .collect();
    let script = format!(
        "mkdir -p small out && mount -t tmpfs -o size=2m tmpfs small && {run} && cp -a small/r before && {steps}",
        run = quoted_rod_run("small/r", "0.1", &[]),
        steps = steps.join(" ; ")
    );
    let o = in_small_tmpfs(tmp.path(), &script);
    let before = files(&tmp.path().join("before"));
    let mut refused = Vec::new();
    for left in lefts {
        let code = std::fs::read_to_string(tmp.path().join(format!("out/code{left}")))
            .unwrap_or_else(|_| panic!("no run: {}", String::from_utf8_lossy(&o.stderr)));
        let err = std::fs::read_to_string(tmp.path().join(format!("out/err{left}"))).unwrap();
        let after = files(&tmp.path().join(format!("out/r{left}")));
        match code.trim() {
            "0" => assert_ne!(after, before, "{left} KiB: ran but left the earlier run"),
            "1" => {
                assert_eq!(after, before, "{left} KiB: {err}");
                for name in ["run.json", "scenario.resolved.toml"] {
                    if err.contains(&format!("small/r/{name}: No space left")) {
                        refused.push(name);
                    }
                }
            }
            c => panic!("{left} KiB: status {c}: {err}"),
        }
    }
    assert!(
        refused.contains(&"run.json") || refused.contains(&"scenario.resolved.toml"),
        "no step reached the record's write: {refused:?}"
    );
}

//! Run-directory integrity through the binary (docs/reliability.md §5): one writer per
//! directory, one run's files per directory, whole rows and a record that says why a run
//! ended, and a resume only over the same inputs.
use crate::common::*;

use std::path::Path;
use std::process::{Child, Stdio};
use std::time::{Duration, Instant};

use chute::output::run_files;

/// `chute run` of the coarse rod for `duration` s into `out`, with `extra` arguments.
pub(crate) fn rod_run(duration: &str, out: &str, extra: &[&str]) -> Vec<String> {
    let mut a: Vec<String> = ["run", &rod_file(), "--quiet", "--out", out]
        .iter()
        .map(|s| s.to_string())
        .collect();
    for s in ["canopy.nodes=21", &format!("time.duration_s={duration}")] {
        a.extend(["--set".to_string(), s.to_string()]);
    }
    a.extend(extra.iter().map(|s| s.to_string()));
    a
}

fn run(cwd: &Path, args: &[String]) -> std::process::Output {
    let a: Vec<&str> = args.iter().map(String::as_str).collect();
    chute(cwd, &a)
}

/// A new temporary directory holding `out`: 0.1 s of the coarse rod, checkpointed every
/// 0.05 s, without the viewer (the run must succeed).
fn checkpointed_rod_in_tmp(out: &str) -> tempfile::TempDir {
    let tmp = tempfile::tempdir().unwrap();
    let args = rod_run("0.1", out, &["--checkpoint-every", "0.05", "--no-viewer"]);
    assert_exit(&run(tmp.path(), &args), 0);
    tmp
}

/// A long run started in the background, once it holds `dir` (its record says `running`).
fn start_holding(cwd: &Path, dir: &str) -> Child {
    let child = chute_command()
        .args(rod_run("600", dir, &[]))
        .current_dir(cwd)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let record = cwd.join(dir).join(run_files::RUN_RECORD);
    let t0 = Instant::now();
    while !std::fs::read_to_string(&record).is_ok_and(|t| t.contains("\"running\"")) {
        assert!(
            t0.elapsed() < Duration::from_secs(60),
            "the run never started"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    child
}

#[test]
fn a_second_writer_is_refused_naming_the_holder_and_a_dead_holder_blocks_nobody() {
    let tmp = tempfile::tempdir().unwrap();
    let mut first = start_holding(tmp.path(), "d");
    let pid = first.id();
    let holder = format!("in use by process {pid} on host");
    let second = run(tmp.path(), &rod_run("0.05", "d", &["--force"]));
    let resume = chute(tmp.path(), &["resume", "d"]);
    let view = chute(tmp.path(), &["view", "d"]);
    for (what, o) in [
        ("run --force", &second),
        ("resume", &resume),
        ("view", &view),
    ] {
        assert_eq!(o.status.code(), Some(2), "{what}: {}", stderr(o));
        assert!(stderr(o).contains(&holder), "{what}: {}", stderr(o));
    }
    // Nothing of the refused commands reached the directory: the first run's files only.
    assert!(!tmp.path().join("d/viewer.html").exists());
    first.kill().unwrap();
    first.wait().unwrap();
    // The kernel released the dead process's lock; its stale lock file blocks nobody.
    assert!(tmp.path().join("d").join(run_files::LOCK).exists());
    let after = run(tmp.path(), &rod_run("0.05", "d", &["--force"]));
    assert_exit(&after, 0);
    let dir = tmp.path().join("d");
    assert!(!dir.join(run_files::LOCK).exists() && !dir.join(run_files::RESERVE).exists());
    let rows = csv_rows(&dir.join("timeseries.csv"));
    assert!((rows.last().unwrap()[0] - 0.05).abs() < 1e-12);
}

#[test]
fn a_killed_run_is_recorded_as_abandoned_and_view_says_so() {
    let tmp = tempfile::tempdir().unwrap();
    let mut first = start_holding(tmp.path(), "k");
    first.kill().unwrap();
    first.wait().unwrap();
    let o = chute(tmp.path(), &["view", "k"]);
    assert_exit_says(&o, 0, &["the run ended without finishing"]);
    let o = chute(tmp.path(), &["resume", "k"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("chute run k/scenario.resolved.toml --out k --force"),
        "{}",
        stderr(&o)
    );
}

/// The optional files [`every_file_run`] writes (a plain rod run writes none of them).
const OPTIONAL_FILES: [&str; 5] = [
    "lines.csv",
    "track.csv",
    "track.png",
    "wrinkles.png",
    "snapshot_0.05s.png",
];

/// Arguments of a square shell canopy with a line pull and a no-compression fabric, so that
/// the run writes every optional file: lines.csv, track.csv, track.png, wrinkles.png and a
/// snapshot.
fn every_file_run(out: &str) -> Vec<String> {
    let scenario = repo().join("scenarios/control-steer.toml");
    let mut a: Vec<String> = ["run", &scenario.to_string_lossy(), "--quiet", "--out", out]
        .iter()
        .map(|s| s.to_string())
        .collect();
    for s in [
        "time.duration_s=0.1",
        "canopy.edge_length_m=0.5",
        "output.snapshots_s=[0.05]",
        "shell.membrane=fabric",
        "material.no_compression=true",
        "material.warp_modulus_pa=1e9",
        "material.weft_modulus_pa=1e9",
        "material.shear_modulus_pa=1e8",
        "material.fabric_poisson_ratio=0.2",
    ] {
        a.extend(["--set".to_string(), s.to_string()]);
    }
    a
}

#[test]
fn every_file_a_run_writes_is_registered_and_force_clears_them_all() {
    let tmp = tempfile::tempdir().unwrap();
    let o = run(tmp.path(), &every_file_run("d"));
    assert_exit(&o, 0);
    let dir = tmp.path().join("d");
    let written: Vec<String> = files(&dir).into_keys().collect();
    for f in OPTIONAL_FILES.iter().chain(&["run.json"]) {
        assert!(
            written.iter().any(|w| w == f),
            "{f} not written: {written:?}"
        );
    }
    for f in &written {
        let top = f.strip_prefix("frames/").unwrap_or(f);
        assert!(
            run_files::is_run_file(f) || (f.starts_with("frames/") && top.starts_with("frame_")),
            "{f} is not in the registry"
        );
    }
    std::fs::write(dir.join("notes.txt"), "mine").unwrap();
    // A plain rod over it: nothing of the earlier run may stay.
    let o = run(
        tmp.path(),
        &rod_run("0.05", "d", &["--force", "--no-viewer"]),
    );
    assert_exit(&o, 0);
    let now: Vec<String> = files(&dir).into_keys().collect();
    for gone in OPTIONAL_FILES.iter().chain(&["viewer.html"]) {
        assert!(
            !now.iter().any(|w| w == gone),
            "{gone} left behind: {now:?}"
        );
    }
    assert_eq!(
        std::fs::read_to_string(dir.join("notes.txt")).unwrap(),
        "mine"
    );
}

#[test]
fn resume_cleans_the_temporaries_of_a_killed_writer() {
    let tmp = checkpointed_rod_in_tmp("r");
    let dir = tmp.path().join("r");
    let left = [
        dir.join("frames/.frame_000003.vtu.Ab12Cd.tmp"),
        dir.join(".summary.json.Zz99Yy.tmp"),
        dir.join(".velocity.png.4242.tmp.png"),
    ];
    for f in &left {
        std::fs::write(f, "half a file").unwrap();
    }
    chute_ok(tmp.path(), &["resume", "r", "--set", "time.duration_s=0.2"]);
    for f in &left {
        assert!(!f.exists(), "{f:?} left behind");
    }
}

/// A `frames` that is a symbolic link would make a run write and remove frames in the
/// directory it points to: `run --force` and `resume` refuse the directory (2), and the
/// user's files there are untouched.
#[cfg(unix)]
#[test]
fn a_linked_frames_directory_is_refused() {
    let tmp = checkpointed_rod_in_tmp("r");
    let ext = tmp.path().join("ext");
    std::fs::create_dir(&ext).unwrap();
    std::fs::write(ext.join("frame_000000.vtu"), "mine").unwrap();
    std::fs::remove_dir_all(tmp.path().join("r/frames")).unwrap();
    std::os::unix::fs::symlink(&ext, tmp.path().join("r/frames")).unwrap();
    let mut force = rod_run("0.1", "r", &["--no-viewer"]);
    force.push("--force".into());
    for o in [
        run(tmp.path(), &force),
        chute(tmp.path(), &["resume", "r", "--set", "time.duration_s=0.2"]),
    ] {
        assert_exit_says(&o, 2, &["is a symbolic link"]);
    }
    assert_eq!(
        std::fs::read_to_string(ext.join("frame_000000.vtu")).unwrap(),
        "mine"
    );
    assert_eq!(std::fs::read_dir(&ext).unwrap().count(), 1);
}

/// A run that cannot start removes every directory it created for `--out`, parents
/// included, and nothing that was there before.
#[test]
fn a_refused_run_removes_the_directories_it_created() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::create_dir(tmp.path().join("keep")).unwrap();
    let hex = repo()
        .join("scenarios/dismech-hex-n6.toml")
        .display()
        .to_string();
    for out in ["nest/a/b", "keep/a/b"] {
        let o = chute(
            tmp.path(),
            &[
                "run",
                &hex,
                "--out",
                out,
                "--set",
                "load.node=1000",
                "--quiet",
            ],
        );
        assert_exit(&o, 2);
    }
    assert!(!tmp.path().join("nest").exists());
    assert!(tmp.path().join("keep").is_dir() && !tmp.path().join("keep/a").exists());
}

/// Every file of the top of run directory `dir`, by name, with its bytes.
fn files_of(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut v: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_file())
        .map(|p| {
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            (name, std::fs::read(&p).unwrap())
        })
        .collect();
    v.sort();
    v
}

/// A run directory whose frames were deleted after the run stopped is not the run the
/// checkpoint describes: resume refuses it (2) naming the missing frame, and leaves every
/// file as it was (the time series is not cut back, the record not rewritten). The same for
/// another run's checkpoint copied in.
#[test]
fn a_refused_resume_leaves_the_run_directory_as_it_was() {
    let tmp = checkpointed_rod_in_tmp("r");
    std::fs::remove_file(tmp.path().join("r/frames/frame_000001.vtu")).unwrap();
    let before = files_of(&tmp.path().join("r"));
    let o = chute(tmp.path(), &["resume", "r", "--set", "time.duration_s=0.2"]);
    let err = stderr(&o);
    assert_exit(&o, 2);
    assert_contains(&err, &["frame_000001.vtu", "is missing"]);
    assert!(files_of(&tmp.path().join("r")) == before, "files changed");
    // Another model's checkpoint: refused for its shape, nothing changed either.
    let o = run(
        tmp.path(),
        &rod_run(
            "0.1",
            "r",
            &["--checkpoint-every", "0.05", "--no-viewer", "--force"],
        ),
    );
    assert_exit(&o, 0);
    let mut other = rod_run("0.1", "o", &["--checkpoint-every", "0.05", "--no-viewer"]);
    other.extend(["--set".into(), "canopy.nodes=31".into()]);
    assert_eq!(run(tmp.path(), &other).status.code(), Some(0));
    let ckpt = tmp.path().join("r/checkpoint.bin");
    std::fs::copy(tmp.path().join("o/checkpoint.bin"), &ckpt).unwrap();
    let before = files_of(&tmp.path().join("r"));
    let o = chute(tmp.path(), &["resume", "r", "--set", "time.duration_s=0.2"]);
    assert_exit(&o, 2);
    assert!(files_of(&tmp.path().join("r")) == before, "files changed");
    // Its scenario copied in too: the time series does not end at the checkpoint's state.
    let resolved = "scenario.resolved.toml";
    std::fs::copy(
        tmp.path().join("o").join(resolved),
        tmp.path().join("r").join(resolved),
    )
    .unwrap();
    let before = files_of(&tmp.path().join("r"));
    let o = chute(tmp.path(), &["resume", "r", "--set", "time.duration_s=0.2"]);
    assert_exit_says(&o, 2, &["not of one run"]);
    assert!(files_of(&tmp.path().join("r")) == before, "files changed");
}

#[test]
fn resume_keeps_no_viewer() {
    let tmp = checkpointed_rod_in_tmp("r");
    chute_ok(
        tmp.path(),
        &["resume", "r", "--set", "time.duration_s=0.15"],
    );
    assert!(!tmp.path().join("r/viewer.html").exists());
}

/// The bundled DisMech hexagon with every node coordinate × `scale`.
pub(crate) fn hex_mesh(scale: f64) -> String {
    let text =
        std::fs::read_to_string(repo().join("crates/chute/data/meshes/hexparachute_n6_python.txt"))
            .unwrap();
    let mut nodes = false;
    let mut out = String::new();
    for line in text.lines() {
        if line.starts_with('*') {
            nodes = line.eq_ignore_ascii_case("*Nodes");
            out.push_str(line);
        } else if nodes && !line.trim().is_empty() {
            let xs: Vec<String> = line
                .split(',')
                .map(|x| (x.trim().parse::<f64>().unwrap() * scale).to_string())
                .collect();
            out.push_str(&xs.join(", "));
        } else {
            out.push_str(line);
        }
        out.push('\n');
    }
    out
}

#[test]
fn resume_refuses_a_changed_mesh_naming_the_key_and_the_file() {
    let tmp = tempfile::tempdir().unwrap();
    let mesh = tmp.path().join("canopy.txt");
    std::fs::write(&mesh, hex_mesh(1.0)).unwrap();
    // dt = 10 ms: the first sync point, and checkpoint, is at 0.64 s.
    let scenario = repo().join("scenarios/dismech-hex-n6.toml");
    let args: Vec<String> = [
        "run",
        &scenario.to_string_lossy(),
        "--quiet",
        "--no-viewer",
        "--out",
        "m",
        "--checkpoint-every",
        "0.05",
        "--set",
        "time.duration_s=0.7",
        "--set",
        &format!("canopy.mesh_file={}", mesh.display()),
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    let o = run(tmp.path(), &args);
    assert_exit(&o, 0);
    let record = read_json(tmp.path().join("m/run.json"));
    assert_eq!(record["inputs"][0]["key"], "canopy.mesh_file", "{record}");
    // Every node × 1.2: the same name, other contents.
    std::fs::write(&mesh, hex_mesh(1.2)).unwrap();
    let o = chute(tmp.path(), &["resume", "m", "--set", "time.duration_s=0.8"]);
    let want = [
        "canopy.mesh_file",
        "canopy.txt",
        "has changed since the run started",
    ];
    assert_exit_says(&o, 2, &want);
    // A record edited to list no inputs cannot hide the change: the file it omits is named.
    let path = tmp.path().join("m/run.json");
    let mut without = record.clone();
    without["inputs"] = serde_json::json!([]);
    std::fs::write(&path, without.to_string()).unwrap();
    let o = chute(tmp.path(), &["resume", "m", "--set", "time.duration_s=0.8"]);
    assert_exit_says(&o, 2, &["does not list"]);
    std::fs::write(&path, record.to_string()).unwrap();
    // The run is untouched and resumes once the file is back.
    std::fs::write(&mesh, hex_mesh(1.0)).unwrap();
    chute_ok(tmp.path(), &["resume", "m", "--set", "time.duration_s=0.8"]);
}

#[test]
fn a_resumed_study_case_says_how_it_ended_in_its_marker() {
    let tmp = checkpointed_rod_in_tmp("s/c");
    // The marker of a case the study saw stop early.
    let done = tmp.path().join("s/c/done.json");
    let marker = serde_json::json!({
        "study": "s", "case": "c", "index": 0, "overrides": [], "status": "incomplete",
        "message": "interrupted at t = 0.1 s", "wall_time_s": 1.0, "inputs": "fnv1a64:0",
    });
    std::fs::write(&done, marker.to_string()).unwrap();
    chute_ok(
        tmp.path(),
        &["resume", "s/c", "--set", "time.duration_s=0.15"],
    );
    let after = read_json(&done);
    assert_eq!(after["status"], "complete", "{after}");
    assert!(after["message"].is_null(), "{after}");
    assert!(after["wall_time_s"].as_f64().unwrap() > 1.0, "{after}");
    // Extended from 0.1 to 0.15 s, the case is no longer the study's: inputs no study has,
    // so a study re-runs it and collect calls it changed.
    assert_eq!(
        after["inputs"], "extended by chute resume to time.duration_s = 0.15",
        "{after}"
    );
}

/// A path that is not UTF-8 (legal on Linux) is a path like any other: the run takes its lock
/// and runs, instead of panicking while describing the lock's holder.
#[test]
fn a_run_directory_named_in_bytes_that_are_not_utf8_runs() {
    use std::os::unix::ffi::OsStrExt;
    let tmp = tempfile::tempdir().unwrap();
    let name = std::ffi::OsStr::from_bytes(b"bad\xffname");
    let mut args: Vec<std::ffi::OsString> = rod_run("0.02", "x", &["--no-viewer"])
        .into_iter()
        .map(Into::into)
        .collect();
    let at = args.iter().position(|a| a == "x").unwrap();
    args[at] = name.to_os_string();
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_chute"))
        .args(&args)
        .current_dir(tmp.path())
        .output()
        .unwrap();
    assert_exit(&o, 0);
    assert!(tmp.path().join(name).join("summary.json").is_file());
}

/// `--jobs` above the number of cases starts no more workers than there are cases: a study
/// of three cases with `--jobs 1000000` runs like one with `--jobs 3` (before, it spawned a
/// million threads and did not finish).
#[test]
fn a_huge_jobs_count_starts_no_more_workers_than_cases() {
    let tmp = tempfile::tempdir().unwrap();
    let study = repo().join("studies/table1.toml").display().to_string();
    chute_ok(
        tmp.path(),
        &[
            "study",
            &study,
            "--out",
            "s",
            "--jobs",
            "1000000",
            "--set",
            "time.duration_s=0.02",
        ],
    );
    assert!(tmp.path().join("s/study.csv").is_file());
}

/// A `canopy.pvd` that is not a ParaView collection is named as such by `view` (status 2),
/// not read as a run of no frames.
#[test]
fn view_names_a_frame_collection_that_is_not_one() {
    let tmp = tempfile::tempdir().unwrap();
    let o = run(tmp.path(), &rod_run("0.02", "r", &["--no-viewer"]));
    assert_exit(&o, 0);
    std::fs::write(tmp.path().join("r/canopy.pvd"), "not xml at all\n").unwrap();
    let o = chute(tmp.path(), &["view", "r"]);
    assert_exit(&o, 2);
    assert!(
        stderr(&o).contains("canopy.pvd") && stderr(&o).contains("not a ParaView collection"),
        "{}",
        stderr(&o)
    );
}

/// chute's lock and reserve files are its own: a symbolic link named like one (to a file of
/// the user's) is refused as unwritable (status 2), and the file it points to is untouched.
#[test]
fn a_link_named_like_the_lock_or_the_reserve_is_not_written_through() {
    for name in [".chute.lock", ".chute.reserve"] {
        let tmp = tempfile::tempdir().unwrap();
        let precious = tmp.path().join("precious.txt");
        std::fs::write(&precious, "the user's data\n").unwrap();
        std::fs::create_dir(tmp.path().join("r")).unwrap();
        std::os::unix::fs::symlink(&precious, tmp.path().join("r").join(name)).unwrap();
        let o = run(
            tmp.path(),
            &rod_run("0.02", "r", &["--no-viewer", "--force"]),
        );
        assert_eq!(o.status.code(), Some(2), "{name}: {}", stderr(&o));
        assert!(stderr(&o).contains(name), "{name}: {}", stderr(&o));
        assert_eq!(
            std::fs::read_to_string(&precious).unwrap(),
            "the user's data\n",
            "{name}"
        );
        // The link is the user's too: refused, not removed.
        assert!(tmp.path().join("r").join(name).is_symlink(), "{name}");
        // A directory of that name is named, not reported as a bare "Is a directory".
        std::fs::remove_file(tmp.path().join("r").join(name)).unwrap();
        std::fs::create_dir(tmp.path().join("r").join(name)).unwrap();
        let o = run(
            tmp.path(),
            &rod_run("0.02", "r", &["--no-viewer", "--force"]),
        );
        assert_eq!(o.status.code(), Some(2), "{name}: {}", stderr(&o));
        assert!(stderr(&o).contains(name), "{name}: {}", stderr(&o));
    }
}

/// A reader that closes the pipe early ends chute by SIGPIPE, as it ends other tools, not
/// by a panic in its printing.
#[test]
fn a_closed_output_pipe_is_no_panic() {
    use std::os::unix::process::ExitStatusExt;
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_chute"))
        .args(["check", &rod_file()])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let o = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!err.contains("panicked"), "{err}");
    assert!(
        o.status.signal() == Some(13) || o.status.code() == Some(0),
        "{:?}: {err}",
        o.status
    );
}

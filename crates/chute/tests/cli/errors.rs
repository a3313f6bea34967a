//! The `chute` binary: exit codes, `error: …` messages on stderr, no panics, output-directory
//! safety, and argument parsing of every subcommand.

use std::path::Path;
use std::process::Output;

use crate::common::*;

/// Exit code `code` and a final `error: ` line; stderr contains every `want`.
fn assert_error(o: &Output, code: i32, want: &[&str]) {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(code), "stderr: {err}");
    // Progress lines may precede it; the error is the last line.
    assert!(
        err.trim_end()
            .lines()
            .last()
            .unwrap_or("")
            .starts_with("error: "),
        "{err}"
    );
    assert!(!err.contains("panicked"), "{err}");
    for w in want {
        assert!(err.contains(w), "want `{w}` in: {err}");
    }
}

/// Each `(args, code, wants)`: `chute ARGS` in `dir` exits with `code`, saying every want.
fn assert_errors(dir: &Path, cases: &[(&[&str], i32, &[&str])]) {
    for (args, code, want) in cases {
        assert_error(&chute(dir, args), *code, want);
    }
}

const HEAD: &str = "name = \"t\"\n[model]\nkind = \"shell\"\n";

#[test]
fn check_prints_derived_quantities() {
    let o = check_bundled("report-rod-200n.toml", &[]);
    assert_exit(&o, 0);
    let out = stdout(&o);
    assert_contains(&out, &["scenario `report-rod-200n`", "is valid"]);
    // Flat-plate terminal speed √(2 W /(ρ C_D A)) with W = 200 N + 51.84 kg · 9.81 = 708.6 N.
    assert_contains(&out, &["total weight", "708.6 N"]);
    assert_contains(&out, &["flat-canopy terminal speed", "6.060 m/s"]);
    let o = check_bundled("report-rod-200n.toml", &["load.weight_n=2000"]);
    assert!(stdout(&o).contains("2509 N"), "{}", stdout(&o));
}

#[test]
fn check_resolved_prints_a_scenario_that_resolves_to_itself() {
    let dir = tempfile::tempdir().unwrap();
    let args = ["--resolved", "--set", "load.weight_n=50"];
    let o = chute_bundled(dir.path(), "check", "round-parachute.toml", &args);
    assert_exit(&o, 0);
    let text = stdout(&o);
    assert_contains(&text, &["weight_n = 50.0", "rim_site_count = 12"]);
    std::fs::write(dir.path().join("r.toml"), &text).unwrap();
    let again = chute(dir.path(), &["check", "r.toml", "--resolved"]);
    assert_eq!(stdout(&again), text);
}

#[test]
fn every_scenario_error_class_exits_2_with_its_message() {
    let dir = tempfile::tempdir().unwrap();
    let cases: &[(&str, &[&str])] = &[
        (
            "[canopy]\nspan_m = = 1\n",
            &["s.toml:5:10: TOML syntax error"],
        ),
        (
            "[canopy]\nspam_m = 1\n",
            &["unknown key `canopy.spam_m` (s.toml:5); did you mean `canopy.span_m`?"],
        ),
        (
            "[canopy]\nspan_m = \"six\"\n",
            &["`canopy.span_m` (s.toml:5) must be a number, found the string \"six\""],
        ),
        (
            "[canopy]\nspan_m = -6\n",
            &["`canopy.span_m` (s.toml:5) = -6 is invalid: must be positive"],
        ),
        (
            "[canopy]\nspan_m = nan\n",
            &["`canopy.span_m` (s.toml:5)", "finite"],
        ),
        (
            "[fluid]\ndrag = \"cubic\"\n",
            &[
                "`fluid.drag` (s.toml:5) = \"cubic\" is not allowed",
                "\"quadratic\", \"linear\"",
            ],
        ),
        (
            "[load]\nsites = [[0, 9]]\n",
            &["`load.sites` (s.toml:5): load site 0 at (0, 9) m lies outside the canopy"],
        ),
        (
            "[canopy]\nshape = \"mesh\"\nmesh_file = \"m/none.txt\"\n",
            &[
                "`canopy.mesh_file` (s.toml:6): mesh file",
                "m/none.txt` does not exist",
            ],
        ),
    ];
    let f = dir.path().join("s.toml");
    for (body, want) in cases {
        std::fs::write(&f, format!("{HEAD}{body}")).unwrap();
        for cmd in ["check", "run"] {
            let o = chute(dir.path(), &[cmd, "s.toml"]);
            assert_error(&o, 2, want);
        }
    }
    assert!(
        !dir.path().join("runs").exists(),
        "no output directory for invalid input"
    );
}

#[test]
fn missing_file_and_bad_overrides_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    assert_error(
        &chute(dir.path(), &["check", "nope.toml"]),
        2,
        &["cannot read scenario file `nope.toml`"],
    );
    // A device as the scenario or the mesh is named as such, not read forever.
    assert_error(
        &chute(dir.path(), &["check", "/dev/zero"]),
        2,
        &["cannot read scenario file `/dev/zero`: it is a device, not a scenario file"],
    );
    let hex = repo().join("scenarios/dismech-hex-n6.toml");
    let mesh = "canopy.mesh_file=\"/dev/zero\"";
    assert_error(
        &chute(dir.path(), &["check", hex.to_str().unwrap(), "--set", mesh]),
        2,
        &["= \"/dev/zero\" is invalid: it is not a plain file"],
    );
    // A file far larger than any scenario or mesh is refused, not read into memory (sparse
    // files: they take no room).
    let big = std::fs::File::create(dir.path().join("big.toml")).unwrap();
    big.set_len(20 << 20).unwrap();
    assert_error(
        &chute(dir.path(), &["check", "big.toml"]),
        2,
        &["it is longer than 16777216 bytes, the most a scenario file may hold"],
    );
    let mesh = std::fs::File::create(dir.path().join("big.txt")).unwrap();
    mesh.set_len(2 << 30).unwrap();
    let set = format!(
        "canopy.mesh_file=\"{}\"",
        dir.path().join("big.txt").display()
    );
    assert_error(
        &chute(dir.path(), &["check", hex.to_str().unwrap(), "--set", &set]),
        2,
        &["the file is 2048 MiB; a mesh file is at most 256 MiB"],
    );
    std::fs::write(dir.path().join("s.toml"), HEAD).unwrap();
    assert_errors(
        dir.path(),
        &[
            (
                &["check", "s.toml", "--set", "fluid.wind_mps=[4,0]"],
                2,
                &["`fluid.wind_mps` (from `--set fluid.wind_mps=[4,0]`) must be an array of three numbers"],
            ),
            (
                &["check", "s.toml", "--set", "novalue"],
                2,
                &["invalid override `--set novalue`"],
            ),
            (
                &["check", "s.toml", "--set", "time.dtt_s=1"],
                2,
                &["unknown key `time.dtt_s` (from `--set time.dtt_s=1`); did you mean `time.dt_s`?"],
            ),
        ],
    );
    chute_ok(
        dir.path(),
        &[
            "check",
            "s.toml",
            "--set",
            "load.mode=force",
            "--set",
            "fluid.wind_mps=[4,0,0]",
        ],
    );
}

#[test]
fn run_refuses_to_overwrite_and_checks_writability() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("s.toml"), HEAD).unwrap();
    // An earlier run's directory (chute's resolved scenario marks it).
    std::fs::create_dir_all(dir.path().join("runs/t")).unwrap();
    std::fs::write(dir.path().join("runs/t/summary.json"), "{}").unwrap();
    std::fs::write(dir.path().join("runs/t/scenario.resolved.toml"), "").unwrap();
    assert_error(
        &chute(dir.path(), &["run", "s.toml"]),
        2,
        &[
            "output directory `runs/t` already exists and is not empty",
            "--force",
        ],
    );
    // With --force the run proceeds and replaces the old summary.
    let short = [
        "--set",
        "time.duration_s=0.004",
        "--set",
        "canopy.edge_length_m=1",
    ];
    let mut args = vec!["run", "s.toml", "--force", "--quiet"];
    args.extend(short);
    chute_ok(dir.path(), &args);
    let summary = std::fs::read_to_string(dir.path().join("runs/t/summary.json")).unwrap();
    assert!(summary.contains("terminal_velocity_mps"), "{summary}");
    // A fresh directory is created, and removed again when the run produced nothing (here the
    // builder rejects lines shorter than the distance from a corner to the payload).
    let o = chute(
        dir.path(),
        &[
            "run",
            "s.toml",
            "--out",
            "fresh",
            "--set",
            "load.mode=payload",
            "--set",
            "lines.length_m=1",
        ],
    );
    assert_error(&o, 2, &["lines.length_m"]);
    assert!(!dir.path().join("fresh").exists());
    // Not a directory / not creatable.
    std::fs::write(dir.path().join("afile"), "").unwrap();
    assert_errors(
        dir.path(),
        &[
            (
                &["run", "s.toml", "--out", "afile"],
                2,
                &["exists and is not a directory"],
            ),
            (
                &["run", "s.toml", "--out", "afile/sub"],
                2,
                &[
                    "cannot create output directory",
                    "`afile` is not a directory",
                ],
            ),
            (
                &["run", "s.toml", "--checkpoint-every", "0"],
                2,
                &["--checkpoint-every"],
            ),
            (
                &["run", "s.toml", "--resume", "nowhere"],
                2,
                &["retired", "chute resume nowhere"],
            ),
            (
                &["run", "--resume", "nowhere"],
                2,
                &["retired", "chute resume nowhere"],
            ),
        ],
    );
}

#[cfg(unix)]
#[test]
fn run_refuses_an_unwritable_directory() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("s.toml"), HEAD).unwrap();
    let ro = dir.path().join("ro");
    std::fs::create_dir(&ro).unwrap();
    std::fs::set_permissions(&ro, std::fs::Permissions::from_mode(0o555)).unwrap();
    // Root ignores permissions; only assert when the directory really is read-only.
    if tempfile::NamedTempFile::new_in(&ro).is_err() {
        assert_error(
            &chute(dir.path(), &["run", "s.toml", "--out", "ro"]),
            2,
            &["is not writable"],
        );
    }
    std::fs::set_permissions(&ro, std::fs::Permissions::from_mode(0o755)).unwrap();
}

#[test]
fn study_runs_cases_and_reports_failures_with_exit_3() {
    let dir = tempfile::tempdir().unwrap();
    // Short, coarse runs; case 30 N asks for lines shorter than the corner distance, so the
    // builder rejects it and the study reports one failed case.
    let base = format!(
        "{HEAD}[canopy]\nedge_length_m = 1.0\n[time]\nduration_s = 0.004\n[load]\nmode = \"payload\"\n[lines]\nlength_m = 4.0\n"
    );
    std::fs::write(dir.path().join("base.toml"), base).unwrap();
    std::fs::write(
        dir.path().join("st.toml"),
        "base = \"base.toml\"\n[[case]]\nname = \"weight_n-10\"\nset = [\"load.weight_n=10\"]\n[[case]]\nname = \"weight_n-20\"\nset = [\"load.weight_n=20\"]\n[[case]]\nname = \"weight_n-30\"\nset = [\"load.weight_n=30\", \"lines.length_m=1\"]\n",
    )
    .unwrap();
    let o = chute(
        dir.path(),
        &["study", "st.toml", "--jobs", "2", "--out", "o"],
    );
    assert_error(&o, 3, &["1 of 3 case(s) failed"]);
    let csv = std::fs::read_to_string(dir.path().join("o/study.csv")).unwrap();
    assert!(csv.starts_with("case,load.weight_n,"), "{csv}");
    assert_eq!(csv.lines().count(), 4, "{csv}");
    assert!(stdout(&o).contains("| weight_n-20 |"), "{}", stdout(&o));
    // Shard from SLURM variables: task 1 of 2 runs only case index 1.
    let o = chute_command()
        .args(["study", "st.toml", "--out", "slurm"])
        .current_dir(dir.path())
        .env("SLURM_ARRAY_TASK_ID", "1")
        .env("SLURM_ARRAY_TASK_COUNT", "2")
        .env_remove("SLURM_ARRAY_TASK_MIN")
        .output()
        .unwrap();
    assert_exit(&o, 0);
    let done: Vec<bool> = ["weight_n-10", "weight_n-20", "weight_n-30"]
        .iter()
        .map(|c| dir.path().join("slurm").join(c).join("done.json").exists())
        .collect();
    assert_eq!(done, [false, true, false]);
    // Input errors.
    assert_errors(
        dir.path(),
        &[
            (
                &["study", "st.toml", "--shard", "2/2"],
                2,
                &["invalid shard `2/2`"],
            ),
            (&["study", "st.toml", "--jobs", "0"], 2, &["--jobs"]),
        ],
    );
    assert_error(
        &chute(
            dir.path(),
            &["study", "st.toml", "--set", "canopy.span_m=-1"],
        ),
        2,
        &["case `weight_n-10`", "canopy.span_m", "must be positive"],
    );
    assert_error(
        &chute(dir.path(), &["study", "none.toml"]),
        2,
        &["cannot read study file `none.toml`"],
    );
    // Collect re-tabulates existing directories; a failed case fails it, named with why,
    // and the table is still written.
    let o = chute(dir.path(), &["collect", "o", "slurm", "--out", "merged"]);
    assert_error(
        &o,
        3,
        &[
            "the study is not complete: 2 of 3 case(s) found complete",
            "case `weight_n-30` failed: lines.length_m",
        ],
    );
    assert!(dir.path().join("merged/study.md").exists());
    assert_error(
        &chute(dir.path(), &["collect", "missing"]),
        2,
        &["`missing` is not a directory"],
    );
}

#[test]
fn validate_parses() {
    // `chute bench` is implemented; tests/bench_cli.rs covers it.
    let dir = tempfile::tempdir().unwrap();
    // A filter that selects no case is a mistake, not "0 passed, 0 failed": status 2, the
    // cases listed (the suite itself is exercised by tests/cli/validate.rs).
    let o = chute(
        dir.path(),
        &["validate", "--quick", "--json", "--case", "no-such-case"],
    );
    assert_error(
        &o,
        2,
        &["--case `no-such-case` matches no verification case with --quick; the cases are: "],
    );
    assert_eq!(stdout(&o).trim(), "");
}

#[test]
fn a_ground_above_the_payload_is_a_sentence_naming_the_key() {
    let o = check_bundled("round-parachute.toml", &["atmosphere.ground_altitude_m=-1"]);
    assert_error(
        &o,
        2,
        &["error: atmosphere.ground_altitude_m: the ground at -1.000 m is not below the payload, which starts at -2.598 m (2.598 m below atmosphere.altitude_m = 0 m); set the ground below -2.598 m, or raise atmosphere.altitude_m"],
    );
}

#[test]
fn usage_errors_exit_2_and_help_exits_0() {
    let dir = tempfile::tempdir().unwrap();
    let o = chute(dir.path(), &["frobnicate"]);
    assert_eq!(o.status.code(), Some(2));
    let o = chute(dir.path(), &["run"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("SCENARIO"), "{}", stderr(&o));
    let o = chute(dir.path(), &["--help"]);
    assert_eq!(o.status.code(), Some(0));
    for sub in ["run", "check", "study", "collect", "validate", "bench"] {
        assert!(stdout(&o).contains(sub), "{sub}");
    }
}

#[test]
fn every_out_naming_a_file_is_bad_input_saying_not_a_directory() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("afile"), "").unwrap();
    std::fs::create_dir(dir.path().join("empty")).unwrap();
    let study = repo().join("studies/table1.toml").display().to_string();
    let rod = repo()
        .join("scenarios/report-rod-200n.toml")
        .display()
        .to_string();
    let short = "time.duration_s=0.01";
    let cases: [&[&str]; 5] = [
        &["study", &study, "--out", "afile", "--set", short],
        &["study", &study, "--out", "afile/sub", "--set", short],
        &[
            "converge",
            &rod,
            "--vary",
            "canopy.nodes=11,21,41",
            "--out",
            "afile",
        ],
        &[
            "validate", "--quick", "--case", "elastica", "--out", "afile",
        ],
        &["view", "afile"],
    ];
    for args in cases {
        let o = chute(dir.path(), args);
        assert_error(&o, 2, &["not a directory"]);
        assert!(!stderr(&o).contains("os error"), "{args:?}: {}", stderr(&o));
    }
}

/// An existing output directory that takes no files (read-only) is bad input named before any
/// case runs, for a study as for a run: exit 2 and the operating system's reason.
#[test]
fn an_output_directory_that_takes_no_files_is_refused_before_any_work() {
    let tmp = tempfile::tempdir().unwrap();
    // Root writes through permissions; the kernel's own directories refuse it too.
    let locked = if unsafe { libc::geteuid() } == 0 {
        std::path::PathBuf::from("/sys/kernel")
    } else {
        let d = tmp.path().join("ro");
        std::fs::create_dir(&d).unwrap();
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&d, std::fs::Permissions::from_mode(0o555)).unwrap();
        d
    };
    assert!(locked.is_dir(), "{} is no directory", locked.display());
    let out = locked.to_str().unwrap();
    let study = repo().join("studies/table1.toml").display().to_string();
    let rod = repo()
        .join("scenarios/report-rod-20n.toml")
        .display()
        .to_string();
    for args in [["study", &study, "--out", out], ["run", &rod, "--out", out]] {
        let o = chute(tmp.path(), &args);
        assert_error(&o, 2, &["is not writable"]);
        assert_stderr_lacks(&o, &["case "]);
        // The probe's random name is no part of the reason.
        assert_stderr_lacks(&o, &[".chute-probe"]);
    }
}

/// A stdout or stderr on a full disk (`/dev/full`) is no panic: the run's files are written,
/// and results that could not reach stdout make the command exit 1 saying so; messages that
/// cannot reach stderr are dropped and the study still writes its table.
#[test]
fn a_full_stdout_or_stderr_is_no_panic() {
    use std::process::Stdio;
    let tmp = tempfile::tempdir().unwrap();
    let full = || {
        std::fs::OpenOptions::new()
            .write(true)
            .open("/dev/full")
            .unwrap()
    };
    let rod = repo().join("scenarios/report-rod-200n.toml");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_chute"))
        .current_dir(tmp.path())
        .args(["run", rod.to_str().unwrap(), "--out", "r", "--no-viewer"])
        .args(["--set", "time.duration_s=0.02", "--set", "canopy.nodes=21"])
        .stdout(full())
        .output()
        .unwrap();
    assert_exit_says(&o, 1, &["the results could not be written to stdout"]);
    assert!(tmp.path().join("r/summary.json").is_file());
    let study = repo().join("studies/table1.toml");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_chute"))
        .current_dir(tmp.path())
        .args(["study", study.to_str().unwrap(), "--out", "s"])
        .args(["--set", "time.duration_s=0.02"])
        .stdout(Stdio::null())
        .stderr(full())
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(0));
    assert!(tmp.path().join("s/study.csv").is_file());
}

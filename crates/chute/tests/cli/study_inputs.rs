//! Through the binary (docs/cli.md §Skipping finished cases): a study case whose inputs changed is re-run,
//! saying why, into a cleanly replaced directory; `chute collect` warns about a stale case and
//! refuses directories that hold no study (exit 2, nothing written).
use crate::common::*;

const SHORT: &str = "time.duration_s=0.05";

fn table1() -> String {
    repo().join("studies/table1.toml").display().to_string()
}

/// `chute study studies/table1.toml --out OUT` of [`SHORT`] flights in `dir`.
fn short_table1(dir: &std::path::Path, out: &str) -> std::process::Output {
    chute(dir, &["study", &table1(), "--out", out, "--set", SHORT])
}

/// A new temporary directory holding `o`, Table I's study of [`SHORT`] flights (which must
/// succeed).
fn short_table1_in_tmp() -> tempfile::TempDir {
    let tmp = tempfile::tempdir().unwrap();
    assert_exit(&short_table1(tmp.path(), "o"), 0);
    tmp
}

#[test]
fn changed_inputs_rerun_the_case_saying_why_into_a_replaced_directory() {
    let tmp = tempfile::tempdir().unwrap();
    let study = table1();
    let run = |set: &str| {
        chute(
            tmp.path(),
            &["study", &study, "--out", "o", "-j", "2", "--set", set],
        )
    };
    let o = run(SHORT);
    assert_exit(&o, 0);
    let case = tmp.path().join("o/20N");
    // A file the user put there and one an earlier (longer) run wrote and this one will not.
    std::fs::write(case.join("notes.txt"), "mine").unwrap();
    std::fs::write(case.join("snapshot_9s.png"), "old").unwrap();
    let o = run("time.duration_s=0.06");
    assert_exit_says(
        &o,
        0,
        &["case 20N: inputs changed since the recorded run; re-running"],
    );
    assert!(
        case.join("notes.txt").is_file(),
        "a file chute did not write is kept"
    );
    assert!(
        !case.join("snapshot_9s.png").exists(),
        "the earlier run's files are gone"
    );
    let resolved = std::fs::read_to_string(case.join("scenario.resolved.toml")).unwrap();
    assert!(resolved.contains("duration_s = 0.06"), "{resolved}");
    // The same inputs again: skipped.
    let o = run("time.duration_s=0.06");
    assert_eq!(
        stderr(&o).matches("already complete, skipped").count(),
        3,
        "{}",
        stderr(&o)
    );
}

#[test]
fn collect_warns_about_the_stale_case() {
    let tmp = tempfile::tempdir().unwrap();
    let base = std::fs::read_to_string(repo().join("scenarios/report-rod-200n.toml")).unwrap();
    std::fs::write(tmp.path().join("base.toml"), &base).unwrap();
    let study = "base = \"base.toml\"\n[[case]]\nname = \"light\"\nset = [\"load.weight_n=20\"]\n[[case]]\nname = \"heavy\"\nset = [\"load.weight_n=2000\"]\n";
    std::fs::write(tmp.path().join("s.toml"), study).unwrap();
    chute_ok(
        tmp.path(),
        &["study", "s.toml", "--out", "o", "--set", SHORT],
    );
    std::fs::write(tmp.path().join("s.toml"), study.replace("=2000", "=1000")).unwrap();
    let o = chute(tmp.path(), &["collect", "o"]);
    let err = stderr(&o);
    assert_exit_says(&o, 0, &["warning: case `heavy`: stale"]);
    assert!(!err.contains("case `light`"), "{err}");
    assert!(stdout(&o).contains("| true | changed |"), "{}", stdout(&o));
}

#[test]
fn collect_on_empty_and_run_directories_exits_2_writing_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::create_dir(tmp.path().join("empty")).unwrap();
    let o = chute(tmp.path(), &["collect", "empty"]);
    assert_exit_says(&o, 2, &["no cases found in `empty`"]);
    assert_eq!(
        std::fs::read_dir(tmp.path().join("empty")).unwrap().count(),
        0
    );
    let scenario = repo().join("scenarios/report-rod-200n.toml");
    chute_ok(
        tmp.path(),
        &[
            "run",
            &scenario.display().to_string(),
            "--out",
            "r",
            "-q",
            "--set",
            SHORT,
        ],
    );
    let before = files(&tmp.path().join("r"));
    let o = chute(tmp.path(), &["collect", "r"]);
    assert_exit_says(&o, 2, &["`r` is a run directory"]);
    assert!(
        files(&tmp.path().join("r")) == before,
        "nothing written into the run directory"
    );
    // A folder of plain runs (none a study's case) holds no cases either.
    std::fs::create_dir(tmp.path().join("runs")).unwrap();
    std::fs::rename(tmp.path().join("r"), tmp.path().join("runs/r")).unwrap();
    let o = chute(tmp.path(), &["collect", "runs"]);
    assert_exit_says(&o, 2, &["no cases found in `runs`"]);
    assert_eq!(
        std::fs::read_dir(tmp.path().join("runs")).unwrap().count(),
        1
    );
}

/// A mesh changed while a study ran reaches the cases that start later, whose recipe digest
/// was taken before: such a case's run records the bytes it read, and a case whose run read
/// other bytes than the file has now is neither skipped nor `current` (here its record says
/// it read other bytes, as a case started after the change would).
#[test]
fn a_case_whose_run_read_other_bytes_is_rerun_and_not_current() {
    let (tmp, p) = mesh_study_project();
    chute_ok(&p, &["study", "m.toml", "--out", "o"]);
    forge_input_digest(&p.join("o/a"));
    let o = chute(&p, &["collect", "o"]);
    let err = stderr(&o);
    assert!(err.contains("its run read canopy.mesh_file"), "{err}");
    let csv = std::fs::read_to_string(p.join("o/study.csv")).unwrap();
    assert!(csv.lines().nth(1).unwrap().ends_with(",changed"), "{csv}");
    // Moved too: the files are matched by key, so the move hides nothing.
    let p = tmp.path().join("moved");
    std::fs::rename(tmp.path().join("p"), &p).unwrap();
    let o = chute(&p, &["study", "m.toml", "--out", "o"]);
    let err = stderr(&o);
    assert_exit(&o, 0);
    let why = "its run's record does not show it read the input files as they are now";
    assert!(err.contains(why), "{err}");
    // A run of a mesh case whose record cannot be read: what it read cannot be checked, so
    // it is run again, not skipped.
    std::fs::write(p.join("o/a/run.json"), "{ not json").unwrap();
    let o = chute(&p, &["study", "m.toml", "--out", "o"]);
    assert!(stderr(&o).contains(why), "{}", stderr(&o));
}

/// A study that replaces a case first takes down the table that called it complete: killed
/// while the case runs again, its directory holds no table that says the old run is there.
#[test]
fn a_study_killed_while_replacing_a_case_leaves_no_stale_table() {
    let tmp = tempfile::tempdir().unwrap();
    let rod = repo().join("scenarios/report-rod-200n.toml");
    let study = |weight: u32, duration: &str| {
        format!(
            "name = \"k\"\nbase = \"{}\"\n[[case]]\nname = \"a\"\nset = [\"load.weight_n={weight}\", \"time.duration_s={duration}\"]\n",
            rod.display()
        )
    };
    std::fs::write(tmp.path().join("k.toml"), study(30, "0.02")).unwrap();
    let o = chute(tmp.path(), &["study", "k.toml", "--out", "o"]);
    assert_exit(&o, 0);
    assert!(tmp.path().join("o/study.csv").is_file());
    // Other inputs, a long run: started, then killed once its case is under way.
    std::fs::write(tmp.path().join("k.toml"), study(40, "60")).unwrap();
    let mut child = chute_command()
        .current_dir(tmp.path())
        .args(["study", "k.toml", "--out", "o"])
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let resolved = tmp.path().join("o/a/scenario.resolved.toml");
    let t0 = std::time::Instant::now();
    while !std::fs::read_to_string(&resolved).is_ok_and(|t| t.contains("weight_n = 40.0")) {
        assert!(t0.elapsed().as_secs() < 60, "the case never started");
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(!tmp.path().join("o/study.csv").exists());
    assert!(!tmp.path().join("o/study.md").exists());
}

/// A project moved elsewhere: the mesh its cases' runs recorded is no longer at its old path,
/// but the same bytes are at the new one, so the study skips its cases (content, not path).
#[test]
fn a_moved_project_with_a_mesh_keeps_its_cases() {
    let (tmp, p) = mesh_study_project();
    chute_ok(&p, &["study", "m.toml", "--out", "o"]);
    std::fs::rename(&p, tmp.path().join("moved")).unwrap();
    let o = chute(
        &tmp.path().join("moved"),
        &["study", "m.toml", "--out", "o"],
    );
    assert_exit_says(&o, 0, &["already complete, skipped"]);
}

/// A project `p` in a new temporary directory: [`hex_project`] and a one-case study `m.toml`
/// of a 0.02 s flight on it.
fn mesh_study_project() -> (tempfile::TempDir, std::path::PathBuf) {
    let tmp = tempfile::tempdir().unwrap();
    let p = tmp.path().join("p");
    std::fs::create_dir(&p).unwrap();
    hex_project(&p);
    let study = "name = \"m\"\nbase = \"hex.toml\"\n[[case]]\nname = \"a\"\nset = [\"time.duration_s=0.02\"]\n";
    std::fs::write(p.join("m.toml"), study).unwrap();
    (tmp, p)
}

/// A finished case whose `frames` or time series is a link (to another case's) holds no run
/// of its own: `collect` calls it unreadable (status 3) and a study does not skip it — a
/// linked `frames` makes it "not run" (status 3), a linked file is replaced by a run of its own.
#[test]
fn links_inside_a_finished_case_are_not_its_run() {
    let tmp = short_table1_in_tmp();
    let run = || short_table1(tmp.path(), "o");
    let o = tmp.path().join("o");
    std::fs::remove_dir_all(o.join("20N/frames")).unwrap();
    std::os::unix::fs::symlink("../200N/frames", o.join("20N/frames")).unwrap();
    let c = chute(tmp.path(), &["collect", "o"]);
    assert_exit_says(&c, 3, &["symbolic link"]);
    let r = run();
    let err = stderr(&r);
    assert_exit(&r, 3);
    assert_contains(&err, &["20N: not run", "symbolic link"]);
    // A linked time series instead: the case runs again, into files of its own.
    std::fs::remove_file(o.join("20N/frames")).unwrap();
    std::fs::remove_file(o.join("20N/timeseries.csv")).unwrap();
    std::os::unix::fs::symlink("../200N/timeseries.csv", o.join("20N/timeseries.csv")).unwrap();
    let r = run();
    assert_exit(&r, 0);
    let meta = std::fs::symlink_metadata(o.join("20N/timeseries.csv")).unwrap();
    assert!(meta.is_file(), "the time series is still a link");
    assert!(
        o.join("200N/timeseries.csv").is_file(),
        "the other case's file was touched"
    );
}

/// A directory holding only chute's run record (a run killed before it wrote more, or a run
/// starting up) is a run directory: no run nests in it and no study takes it as its OUT.
#[test]
fn a_directory_with_only_a_run_record_is_a_run_directory() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path().join("d");
    std::fs::create_dir(&d).unwrap();
    let record = r#"{"status": "running", "reason": null, "inputs": [], "viewer": true}"#;
    std::fs::write(d.join("run.json"), record).unwrap();
    let rod = repo().join("scenarios/report-rod-20n.toml");
    let rod = rod.to_str().unwrap();
    let o = chute(
        tmp.path(),
        &["run", rod, "--out", "d/sub", "--set", SHORT, "-q"],
    );
    assert_exit_says(&o, 2, &["lies inside the run directory"]);
    assert_exit(&short_table1(tmp.path(), "d"), 2);
    assert!(!d.join("sub").exists() && !d.join("20N").exists());
}

/// A finished case missing a file every finished run has (its time series), or with a frame
/// its `canopy.pvd` lists replaced by a link to another case's, is no finished case: collect
/// says so (status 3) and the study runs it again into files of its own.
#[test]
fn a_finished_case_missing_a_file_or_with_a_linked_frame_runs_again() {
    let tmp = short_table1_in_tmp();
    let run = || short_table1(tmp.path(), "o");
    let o = tmp.path().join("o");
    let frame = |case: &str| {
        let mut f: Vec<_> = std::fs::read_dir(o.join(case).join("frames"))
            .unwrap()
            .map(|e| e.unwrap().path())
            .collect();
        f.sort();
        f.last().unwrap().clone()
    };
    let (mine, theirs) = (frame("20N"), frame("200N"));
    std::fs::remove_file(&mine).unwrap();
    std::os::unix::fs::symlink(&theirs, &mine).unwrap();
    std::fs::remove_file(o.join("2000N/timeseries.csv")).unwrap();
    let c = chute(tmp.path(), &["collect", "o"]);
    let err = stderr(&c);
    assert_exit(&c, 3);
    assert_contains(&err, &["symbolic link", "timeseries.csv is missing"]);
    let r = run();
    assert_exit(&r, 0);
    assert!(
        std::fs::symlink_metadata(&mine).unwrap().is_file(),
        "the frame is still a link"
    );
    assert!(o.join("2000N/timeseries.csv").is_file());
    chute_ok(tmp.path(), &["collect", "o"]);
    // Its frame list gone, or listing another case's frame: no finished case.
    let pvd = o.join("20N/canopy.pvd");
    let text = std::fs::read_to_string(&pvd).unwrap();
    std::fs::write(&pvd, text.replacen("frames/", "../200N/frames/", 1)).unwrap();
    let c = chute(tmp.path(), &["collect", "o"]);
    assert_exit(&c, 3);
    std::fs::write(&pvd, text.replace("file=\"", "file='")).unwrap();
    let c = chute(tmp.path(), &["collect", "o"]);
    assert!(
        stderr(&c).contains("canopy.pvd cannot be read"),
        "{}",
        stderr(&c)
    );
    std::fs::remove_file(&pvd).unwrap();
    let c = chute(tmp.path(), &["collect", "o"]);
    assert!(
        stderr(&c).contains("canopy.pvd is missing"),
        "{}",
        stderr(&c)
    );
    // A time series of its header only.
    let ts = o.join("2000N/timeseries.csv");
    let header = std::fs::read_to_string(&ts)
        .unwrap()
        .lines()
        .next()
        .unwrap()
        .to_string();
    std::fs::write(&ts, header + "\n").unwrap();
    let c = chute(tmp.path(), &["collect", "o"]);
    assert!(stderr(&c).contains("holds no row"), "{}", stderr(&c));
    assert_eq!(run().status.code(), Some(0));
    // Its record deleted (this chute always writes one): no finished case either.
    std::fs::remove_file(o.join("200N/run.json")).unwrap();
    let c = chute(tmp.path(), &["collect", "o"]);
    assert_exit_says(&c, 3, &["run.json is missing"]);
    assert_eq!(run().status.code(), Some(0));
    assert!(o.join("200N/run.json").is_file());
}

/// A case holding another case's record (its files copied in) is not this case's run, and a
/// directory holding an interrupted run replacement (`.chute.old`) is a run's, never a
/// study's OUT.
#[test]
fn a_case_with_another_cases_record_is_not_its_run() {
    let tmp = short_table1_in_tmp();
    let run = |out: &str| short_table1(tmp.path(), out);
    let o = tmp.path().join("o");
    std::fs::copy(o.join("200N/run.json"), o.join("20N/run.json")).unwrap();
    let c = chute(tmp.path(), &["collect", "o"]);
    assert_exit_says(&c, 3, &["is of case `table1/200N`"]);
    assert_eq!(run("o").status.code(), Some(0));
    chute_ok(tmp.path(), &["collect", "o"]);
    // Its own record says the run did not complete: a marker saying so is not believed.
    let rec = o.join("20N/run.json");
    let text = std::fs::read_to_string(&rec).unwrap();
    std::fs::write(&rec, text.replace("\"complete\"", "\"incomplete\"")).unwrap();
    let c = chute(tmp.path(), &["collect", "o"]);
    assert_exit_says(&c, 3, &["did not complete"]);
    let t = tmp.path().join("t");
    std::fs::create_dir_all(t.join(".chute.old")).unwrap();
    std::fs::write(t.join(".chute.old/0"), "a moved run file").unwrap();
    let r = run("t");
    assert_exit_says(&r, 2, &["is a run directory"]);
}

//! A study's own directory (docs/reliability.md §5, docs/cli.md §`chute study`): each case is
//! judged under its lock and run only in a directory that is its own; a run the study did not
//! record is taken only when it is exactly the case's, and another study's directory is never
//! run into.
use crate::collect::{
    other_study_args, other_study_in_tmp, table1_study, table1_study_again, table1_study_in,
    write_other_study,
};
use crate::common::*;

/// A user's own short rod run into `out` of `dir` (`--force` over what is there), not a case
/// of any study.
fn users_run(dir: &std::path::Path, out: &str) {
    let rod = repo().join("scenarios/report-rod-200n.toml");
    let rod = rod.to_str().unwrap();
    let set = ["--set", "time.duration_s=0.01", "--set", "canopy.nodes=21"];
    let args = [
        &[
            "run",
            rod,
            "--quiet",
            "--no-viewer",
            "--force",
            "--out",
            out,
        ][..],
        &set,
    ]
    .concat();
    chute_ok(dir, &args);
}

/// `chute study` skips a case only when its summary reads too: a "complete" case whose
/// `summary.json` was removed is run again, not skipped into an `unreadable` row.
#[test]
fn a_study_reruns_a_complete_case_without_its_summary() {
    let tmp = table1_study_in("s");
    std::fs::remove_file(tmp.path().join("s/200N/summary.json")).unwrap();
    let err = table1_study_again(tmp.path());
    assert!(
        err.contains("case 200N: its summary.json is missing or unreadable; re-running"),
        "{err}"
    );
    assert!(tmp.path().join("s/200N/summary.json").is_file());
    chute_ok(tmp.path(), &["collect", "s", "--out", "m"]);
}

/// A case directory that is a link (to a run elsewhere) is not run through: the case is
/// "not run", and the run the link points to is untouched.
#[test]
fn a_study_does_not_write_through_a_linked_case_directory() {
    let tmp = tempfile::tempdir().unwrap();
    let elsewhere = tmp.path().join("elsewhere");
    std::fs::create_dir(&elsewhere).unwrap();
    std::fs::write(elsewhere.join("keep.txt"), "mine\n").unwrap();
    std::fs::create_dir(tmp.path().join("s")).unwrap();
    std::os::unix::fs::symlink(&elsewhere, tmp.path().join("s/200N")).unwrap();
    let o = table1_study(tmp.path(), "s");
    let err = stderr(&o);
    assert_ne!(o.status.code(), Some(0), "{err}");
    assert_contains(&err, &["200N", "symbolic link"]);
    let left: Vec<_> = std::fs::read_dir(&elsewhere).unwrap().collect();
    assert_eq!(left.len(), 1, "the linked directory was written to");
    // Linked to another study's finished case, the link is no case of this table either.
    let other = table1_study(tmp.path(), "t");
    assert_exit(&other, 0);
    std::fs::remove_file(tmp.path().join("s/200N")).unwrap();
    std::os::unix::fs::symlink(tmp.path().join("t/200N"), tmp.path().join("s/200N")).unwrap();
    let o = table1_study(tmp.path(), "s");
    let err = stderr(&o);
    assert!(err.contains("is a link, not a case directory"), "{err}");
    // Not "already complete" either, although the run behind the link is this case's: the
    // study is incomplete (status 3), as its table says.
    assert_eq!(o.status.code(), Some(3), "{err}");
    assert!(err.contains("case 200N: not run"), "{err}");
    let csv = std::fs::read_to_string(tmp.path().join("s/study.csv")).unwrap();
    let row = csv.lines().find(|l| l.starts_with("200N,")).unwrap();
    assert!(!row.contains(",complete,"), "{row}");
}

/// A study written into a directory that also holds other runs tables its own cases only.
#[test]
fn a_study_tables_only_its_own_cases() {
    let tmp = tempfile::tempdir().unwrap();
    users_run(tmp.path(), "s/other");

    let o = table1_study(tmp.path(), "s");
    assert_exit(&o, 0);
    let table = std::fs::read_to_string(tmp.path().join("s/study.csv")).unwrap();
    assert_eq!(table.lines().count(), 4, "{table}");
    assert!(!table.contains("other"), "{table}");
}

/// A case directory holding a run that ended without its study's record (a run the user put
/// there) is not replaced unless asked (`--force`); the study says so, runs the other cases,
/// and calls itself incomplete (status 3).
#[test]
fn a_study_replaces_a_run_it_did_not_record_only_when_forced() {
    let tmp = table1_study_in("s");
    // A run of the user's own (other inputs) where the case goes.
    users_run(tmp.path(), "s/20N");
    let summary = || std::fs::read(tmp.path().join("s/20N/summary.json")).unwrap();
    let users = summary();
    let study = repo().join("studies/table1.toml").display().to_string();
    let again = |force: &[&str]| {
        let args = [
            &[
                "study",
                &study,
                "--out",
                "s",
                "--set",
                "time.duration_s=0.02",
            ][..],
            force,
        ];
        chute(tmp.path(), &args.concat())
    };
    let o = again(&[]);
    assert_exit_says(&o, 3, &["case 20N: not run: `s/20N` holds a run that was not made for this case (no done.json, and its run.json names no case table1/20N); --force replaces it"]);
    assert_eq!(summary(), users, "the user's run was touched");
    // Nor when its record is damaged (or missing, from an older chute).
    let record = tmp.path().join("s/20N/run.json");
    std::fs::write(&record, "{").unwrap();
    let o = again(&[]);
    assert_exit(&o, 3);
    assert_eq!(summary(), users, "the user's run was touched");
    std::fs::remove_file(&record).unwrap();
    assert_eq!(again(&[]).status.code(), Some(3));
    assert_eq!(summary(), users, "the user's run was touched");
    let o = again(&["--force"]);
    assert_exit_says(
        &o,
        0,
        &["case 20N: `s/20N` holds a run this study did not record (no done.json); replacing it"],
    );
    assert_ne!(summary(), users);
}

/// A finished run of exactly a case's inputs that its study did not record (the case was
/// killed, then completed by `chute resume`) is recorded by the next study, not thrown away.
#[test]
fn a_finished_unrecorded_run_of_the_case_is_recorded_not_rerun() {
    let tmp = table1_study_in("s");
    let summary = std::fs::read(tmp.path().join("s/20N/summary.json")).unwrap();
    std::fs::remove_file(tmp.path().join("s/20N/done.json")).unwrap();
    let err = table1_study_again(tmp.path());
    assert!(
        err.contains("case 20N: its directory holds a finished run of it that the study had not recorded; recorded, skipped"),
        "{err}"
    );
    assert_eq!(
        std::fs::read(tmp.path().join("s/20N/summary.json")).unwrap(),
        summary
    );
    chute_ok(tmp.path(), &["collect", "s", "--out", "m"]);
}

/// A case whose directory cannot be used (a file in its place, a marker that is a
/// directory) is "not run", named with the reason, and the study goes on: the other cases
/// run and the table is written (status 3), instead of the whole study stopping.
#[test]
fn an_unusable_case_directory_does_not_stop_the_study() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::create_dir(tmp.path().join("s")).unwrap();
    std::fs::write(tmp.path().join("s/200N"), "a file of the user's").unwrap();
    std::fs::create_dir_all(tmp.path().join("s/2000N/done.json")).unwrap();
    let o = table1_study(tmp.path(), "s");
    assert_exit_says(
        &o,
        3,
        &[
            "case 20N: complete",
            "case 200N: not run: `s/200N` is a file, not a directory",
            "case 2000N: not run: its marker `s/2000N/done.json` cannot be removed",
        ],
    );
    assert!(tmp.path().join("s/study.csv").is_file());
    assert_eq!(
        std::fs::read_to_string(tmp.path().join("s/200N")).unwrap(),
        "a file of the user's"
    );
}

/// A study run into another study's directory would replace that study's cases of the same
/// names and its table: refused (status 2) before any case runs, the directory unchanged.
#[test]
fn a_study_never_runs_into_another_studys_directory() {
    let tmp = table1_study_in("s");
    write_other_study(tmp.path());
    let study_into_s = |file: &str| {
        chute(
            tmp.path(),
            &["study", file, "--out", "s", "--set", "time.duration_s=0.02"],
        )
    };
    let before = files(&tmp.path().join("s"));
    let o = study_into_s("other.toml");
    assert_exit_says(&o, 2, &["holds the cases of study `table1`"]);
    assert!(
        before == files(&tmp.path().join("s")),
        "the other study changed"
    );
    // The same name from another study file (two `table1.toml` in different folders) that
    // runs other inputs (one case's load).
    std::fs::create_dir(tmp.path().join("copy")).unwrap();
    let text = std::fs::read_to_string(repo().join("studies/table1.toml"))
        .unwrap()
        .replace(
            "../scenarios/",
            &format!("{}/", repo().join("scenarios").display()),
        )
        .replace("load.weight_n=2000\"", "load.weight_n=1500\"");
    std::fs::write(tmp.path().join("copy/table1.toml"), text).unwrap();
    let o = study_into_s("copy/table1.toml");
    assert_exit(&o, 2);
    assert!(
        before == files(&tmp.path().join("s")),
        "the other study changed"
    );
    // Nor when no case of it has finished yet (killed, or still running its first cases):
    // the directory's owner record says whose it is.
    for case in ["20N", "200N", "2000N"] {
        std::fs::remove_file(tmp.path().join("s").join(case).join("done.json")).unwrap();
    }
    assert!(tmp.path().join("s/.chute-study.json").is_file());
    let o = study_into_s("copy/table1.toml");
    assert_exit_says(&o, 2, &["(`s/.chute-study.json`)"]);
    // The same study file reached through a link is the same study.
    std::os::unix::fs::symlink(repo().join("studies"), tmp.path().join("linked")).unwrap();
    let o = study_into_s("linked/table1.toml");
    assert_exit(&o, 0);
}

/// An unrecorded run made for the case is taken as the case only when it is exactly the
/// case's: not when its summary is another case's (copied in), nor when the mesh it ran with
/// has changed since; it is then replaced.
#[test]
fn an_unrecorded_run_of_other_inputs_or_another_summary_is_not_taken() {
    let tmp = table1_study_in("s");
    let s = tmp.path().join("s");
    std::fs::remove_file(s.join("200N/done.json")).unwrap();
    std::fs::copy(s.join("2000N/summary.json"), s.join("200N/summary.json")).unwrap();
    // The run there was made for the case (its record says so): a study killed after it
    // removed the marker. Replaced, not refused.
    let err = table1_study_again(tmp.path());
    assert!(
        err.contains("case 200N: `s/200N` holds a run this study did not record (no done.json); replacing it"),
        "{err}"
    );
    // A mesh case: its run finished, its record lost, then the mesh file changed.
    let mesh = tmp.path().join("canopy.txt");
    std::fs::write(&mesh, crate::integrity::hex_mesh(1.0)).unwrap();
    let study = format!(
        "name = \"hex\"\nbase = \"{}\"\n[[case]]\nname = \"a\"\nset = [\"canopy.mesh_file={}\", \"time.duration_s=0.05\"]\n",
        repo().join("scenarios/dismech-hex-n6.toml").display(),
        mesh.display()
    );
    std::fs::write(tmp.path().join("hex.toml"), study).unwrap();
    let run = || chute(tmp.path(), &["study", "hex.toml", "--out", "h"]);
    assert_eq!(run().status.code(), Some(0));
    std::fs::remove_file(tmp.path().join("h/a/done.json")).unwrap();
    std::fs::write(&mesh, crate::integrity::hex_mesh(1.2)).unwrap();
    let o = run();
    let err = stderr(&o);
    assert!(
        err.contains("replacing it") && !err.contains("recorded, skipped"),
        "{err}"
    );
}

/// A run of its own beside a study's cases (its run.json names no case) is no case of the
/// study: `collect` neither lists it nor counts it.
#[test]
fn a_run_of_its_own_beside_the_cases_is_not_a_case() {
    let tmp = table1_study_in("s");
    users_run(tmp.path(), "s/myrun");
    let o = chute(tmp.path(), &["collect", "s", "--out", "m"]);
    assert_exit(&o, 0);
    // Nor a directory of the user's that holds no run record at all, nor a backup copy of a
    // case whose run had not finished (its record names the case `20N`, not `20N.bak`).
    std::fs::create_dir(tmp.path().join("s/notes")).unwrap();
    std::fs::write(tmp.path().join("s/notes/summary.json"), "{}").unwrap();
    std::fs::create_dir(tmp.path().join("s/20N.bak")).unwrap();
    let record = tmp.path().join("s/20N/run.json");
    std::fs::copy(&record, tmp.path().join("s/20N.bak/run.json")).unwrap();
    // Nor a run made for a case the study does not have.
    std::fs::create_dir(tmp.path().join("s/zzz")).unwrap();
    let other = std::fs::read_to_string(&record)
        .unwrap()
        .replace("table1/20N", "table1/zzz");
    assert!(other.contains("\"table1/zzz\""), "{other}");
    std::fs::write(tmp.path().join("s/zzz/run.json"), other).unwrap();
    let o = chute(tmp.path(), &["collect", "s", "--out", "m"]);
    let err = stderr(&o);
    assert_exit(&o, 0);
    let table = std::fs::read_to_string(tmp.path().join("m/study.csv")).unwrap();
    assert!(
        !table.contains("myrun") && !err.contains("myrun"),
        "{table}{err}"
    );
    for other in ["notes", "20N.bak", "zzz"] {
        assert!(
            !table.contains(other) && !err.contains(other),
            "{table}{err}"
        );
    }
    assert_eq!(table.lines().count(), 4, "{table}");
}

/// The directory's owner record knows its study file by bytes too: a same-name study from
/// another file is refused even once the first study's file was moved away, and that file,
/// moved (or copied byte for byte), is still the same study.
#[test]
fn a_moved_study_file_keeps_its_directory_and_no_namesake_takes_it() {
    let tmp = tempfile::tempdir().unwrap();
    let base = repo().join("scenarios/report-rod-200n.toml");
    let study = |weight: u32| {
        format!(
            "name = \"w\"\nbase = \"{}\"\n[[case]]\nname = \"a\"\nset = [\"load.weight_n={weight}\", \"time.duration_s=0.02\"]\n",
            base.display()
        )
    };
    for d in ["one", "two", "moved"] {
        std::fs::create_dir(tmp.path().join(d)).unwrap();
    }
    std::fs::write(tmp.path().join("one/w.toml"), study(20)).unwrap();
    std::fs::write(tmp.path().join("two/w.toml"), study(30)).unwrap();
    let run = |file: &str| chute(tmp.path(), &["study", file, "--out", "out"]);
    assert_eq!(run("one/w.toml").status.code(), Some(0));
    std::fs::rename(
        tmp.path().join("one/w.toml"),
        tmp.path().join("moved/w.toml"),
    )
    .unwrap();
    let o = run("two/w.toml");
    assert_exit_says(&o, 2, &["holds the cases of study `w`"]);
    let o = run("moved/w.toml");
    assert_exit_says(&o, 0, &["already complete, skipped"]);
    // A byte-identical study file whose relative base is another scenario runs other inputs:
    // another study.
    let rod = std::fs::read_to_string(&base).unwrap();
    let relative = "name = \"r\"\nbase = \"base.toml\"\n[[case]]\nname = \"a\"\nset = [\"time.duration_s=0.02\"]\n";
    for (d, weight) in [("r1", "200.0"), ("r2", "300.0")] {
        std::fs::create_dir(tmp.path().join(d)).unwrap();
        std::fs::write(tmp.path().join(d).join("r.toml"), relative).unwrap();
        let scenario = rod.replace("weight_n = 200.0", &format!("weight_n = {weight}"));
        std::fs::write(tmp.path().join(d).join("base.toml"), scenario).unwrap();
    }
    let run = |file: &str| chute(tmp.path(), &["study", file, "--out", "rout"]);
    assert_eq!(run("r1/r.toml").status.code(), Some(0));
    let o = run("r2/r.toml");
    assert_exit_says(&o, 2, &["holds the cases of study `r`"]);
    // The recorded study file is still there, so it was not moved: no advice to remove the
    // record (which would only meet the cases' own records).
    assert_stderr_lacks(&o, &["remove `.chute-study.json`"]);
}

/// A study read through `/dev/stdin` is the file it was redirected from: recorded as that
/// file, so that another file given the same way is another study (not "the same path").
#[test]
fn a_study_read_from_standard_input_is_the_file_it_came_from() {
    let tmp = tempfile::tempdir().unwrap();
    // A relative base, next to the study file (not next to `/dev/stdin`).
    let rod = repo().join("scenarios/report-rod-200n.toml");
    std::fs::copy(rod, tmp.path().join("base.toml")).unwrap();
    let study = |weight: u32| {
        format!(
            "name = \"w\"\nbase = \"base.toml\"\n[[case]]\nname = \"a\"\nset = [\"load.weight_n={weight}\", \"time.duration_s=0.02\"]\n"
        )
    };
    std::fs::write(tmp.path().join("w20.toml"), study(20)).unwrap();
    std::fs::write(tmp.path().join("w30.toml"), study(30)).unwrap();
    let run = |file: &str| {
        let stdin = std::fs::File::open(tmp.path().join(file)).unwrap();
        let cmd = chute_command()
            .current_dir(tmp.path())
            .args(["study", "/dev/stdin", "--out", "out"])
            .stdin(stdin)
            .output();
        cmd.unwrap()
    };
    assert_eq!(run("w20.toml").status.code(), Some(0));
    let owner = std::fs::read_to_string(tmp.path().join("out/.chute-study.json")).unwrap();
    assert!(
        owner.contains("w20.toml") && !owner.contains("/dev/stdin"),
        "{owner}"
    );
    let o = run("w30.toml");
    assert_exit(&o, 2);
    let done = std::fs::read_to_string(tmp.path().join("out/a/scenario.resolved.toml")).unwrap();
    assert!(done.contains("weight_n = 20.0"), "{done}");
}

/// A temporary of the owner record left by a killed study is removed by the next study there
/// once it is stale (a minute old); a fresh one (a live claim's) is left alone.
#[test]
fn a_killed_claims_temporary_is_removed_by_the_next_study() {
    let tmp = table1_study_in("s");
    let stale = tmp.path().join("s/..chute-study.json.AbC123.tmp");
    let fresh = tmp.path().join("s/..chute-study.json.XyZ789.tmp");
    // A table's temporary of a killed `collect` too.
    let table = tmp.path().join("s/.study.csv.QwE456.tmp");
    for f in [&stale, &fresh, &table] {
        std::fs::write(f, "{}").unwrap();
    }
    let touched = std::process::Command::new("touch")
        .args(["-d", "2 minutes ago"])
        .args([&stale, &table])
        .status()
        .unwrap();
    assert!(touched.success());
    table1_study_again(tmp.path());
    assert!(!stale.exists() && !table.exists() && fresh.exists());
}

/// A study and a ladder of the same name are two studies: neither runs into the other's
/// directory (the owner record says which kind made it).
#[test]
fn a_study_and_a_ladder_of_the_same_name_do_not_share_a_directory() {
    let tmp = tempfile::tempdir().unwrap();
    let rod = repo().join("scenarios/report-rod-200n.toml");
    let study = format!(
        "name = \"report-rod-200n-converge\"\nbase = \"{}\"\n[[case]]\nname = \"a\"\nset = [\"time.duration_s=0.02\"]\n",
        rod.display()
    );
    std::fs::write(tmp.path().join("s.toml"), study).unwrap();
    chute_ok(tmp.path(), &["study", "s.toml", "--out", "l"]);
    let vary = [
        "--vary",
        "time.dt_s=0.002,0.001",
        "--set",
        "time.duration_s=0.02",
    ];
    let args = [
        &["converge", rod.to_str().unwrap(), "--out", "l"][..],
        &vary,
    ]
    .concat();
    let o = chute(tmp.path(), &args);
    assert_exit_says(&o, 2, &["holds the cases of study"]);
    // Also when the owner record is gone (an older chute's directory): the cases' records say
    // which kind made them.
    std::fs::remove_file(tmp.path().join("l/.chute-study.json")).unwrap();
    let o = chute(tmp.path(), &args);
    assert_exit_says(&o, 2, &["l/a/done.json"]);
}

/// A `chute run` and a `chute study` started together on one new directory: the study
/// claims the directory under its run lock, so one of them has it wholly and the other is
/// refused; a study's cases never end up inside a run directory.
#[test]
fn a_run_and_a_study_started_together_never_share_a_directory() {
    let tmp = tempfile::tempdir().unwrap();
    write_other_study(tmp.path());
    let rod = repo().join("scenarios/report-rod-200n.toml");
    let short = ["--set", "time.duration_s=0.02", "--set", "canopy.nodes=21"];
    for i in 0..8 {
        let out = format!("d{i}");
        let spawn = |args: Vec<&str>| {
            chute_command()
                .current_dir(tmp.path())
                .args(args)
                .args(short)
                .stdout(std::process::Stdio::null())
                .stderr(std::process::Stdio::piped())
                .spawn()
                .unwrap()
        };
        let run = spawn(vec!["run", rod.to_str().unwrap(), "--out", &out, "--quiet"]);
        std::thread::sleep(std::time::Duration::from_millis(i as u64 * 3));
        let study = spawn(vec!["study", "other.toml", "--out", &out]);
        let (r, s) = (
            run.wait_with_output().unwrap(),
            study.wait_with_output().unwrap(),
        );
        let said = format!(
            "run {}: {}\nstudy {}: {}",
            r.status,
            String::from_utf8_lossy(&r.stderr),
            s.status,
            String::from_utf8_lossy(&s.stderr)
        );
        let dir = tmp.path().join(&out);
        let mixed = dir.join("run.json").exists() && dir.join("20N").exists();
        assert!(!mixed, "try {i}: both wrote `{out}`: {said}");
        assert!(r.status.success() != s.status.success(), "try {i}: {said}");
    }
}

/// A link planted at the lock's name in a study's output directory is refused as for a run
/// (status 2), not taken for a full disk and written through.
#[test]
fn a_linked_lock_file_in_a_studys_directory_is_refused() {
    let tmp = other_study_in_tmp();
    std::fs::write(tmp.path().join("victim"), "mine").unwrap();
    std::os::unix::fs::symlink("../victim", tmp.path().join("o/.chute.lock")).unwrap();
    let o = chute(tmp.path(), &other_study_args("o"));
    assert_exit(&o, 2);
    assert_eq!(
        std::fs::read_to_string(tmp.path().join("victim")).unwrap(),
        "mine"
    );
    assert!(!tmp.path().join("o/20N").exists());
}

/// A study waiting for another's table (its output directory's lock held by a `collect`)
/// stops on Ctrl-C at once, running nothing (status 3), instead of waiting the lock out.
#[test]
fn a_study_waiting_for_the_directorys_lock_stops_on_a_signal() {
    use std::io::Write;
    let tmp = other_study_in_tmp();
    // The lock as a run holds it, whatever its command line says: refused at once.
    let mut lock = std::fs::File::create(tmp.path().join("o/.chute.lock")).unwrap();
    lock.lock().unwrap();
    write!(
        lock,
        "pid=1\nhost=h\nstarted=0\ncommand=chute collect o\nholds=run\n"
    )
    .unwrap();
    let o = chute(tmp.path(), &other_study_args("o"));
    assert_exit(&o, 2);
    // As a collect of `o` holds it (this test process keeps it throughout).
    lock.set_len(0).unwrap();
    std::io::Seek::rewind(&mut lock).unwrap();
    write!(
        lock,
        "pid=1\nhost=h\nstarted=0\ncommand=chute collect o\nholds=table\n"
    )
    .unwrap();
    let mut child = chute_command()
        .current_dir(tmp.path())
        .args(other_study_args("o"))
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // Signalled once it says it is waiting (its stop handler is in place by then).
    let err = child.stderr.take().unwrap();
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        use std::io::BufRead;
        for line in std::io::BufReader::new(err).lines().map_while(Result::ok) {
            let _ = tx.send(line);
        }
    });
    let wait = std::time::Duration::from_secs(60);
    let waiting = rx.recv_timeout(wait).expect("no `waiting for` line");
    assert!(waiting.starts_with("waiting for `o`"), "{waiting}");
    let pid = child.id().to_string();
    assert!(std::process::Command::new("kill")
        .args(["-INT", &pid])
        .status()
        .unwrap()
        .success());
    // Waiting the lock out would take minutes: give up (and fail) long before that.
    let rest: Vec<String> = std::iter::from_fn(|| rx.recv_timeout(wait).ok()).collect();
    let t0 = std::time::Instant::now();
    let status = loop {
        match child.try_wait().unwrap() {
            Some(status) => break status,
            None if t0.elapsed() > wait => {
                child.kill().unwrap();
                panic!("the study did not stop while waiting for the lock: {rest:?}");
            }
            None => std::thread::sleep(std::time::Duration::from_millis(20)),
        }
    };
    let rest = rest.join("\n");
    assert_eq!(status.code(), Some(3), "{rest}");
    assert!(rest.contains("stopped while waiting for `o`"), "{rest}");
    assert!(!tmp.path().join("o/20N").exists());
}

/// A user's own `study.csv` (or `convergence.json`) where a study, a ladder or `collect`
/// would write its table is refused (status 2), never removed or replaced.
#[test]
fn a_users_file_named_like_a_table_is_never_replaced() {
    let tmp = other_study_in_tmp();
    // A user's case list: its header even starts like chute's.
    std::fs::write(tmp.path().join("o/study.csv"), "case,weight\n1,2\n").unwrap();
    let o = chute(tmp.path(), &other_study_args("o"));
    assert_exit_says(&o, 2, &["is not a table or report chute wrote"]);
    let kept = std::fs::read_to_string(tmp.path().join("o/study.csv")).unwrap();
    assert_eq!(kept, "case,weight\n1,2\n");
    // A study of its own elsewhere, collected into `o`: refused too.
    chute_ok(tmp.path(), &other_study_args("s"));
    let o = chute(tmp.path(), &["collect", "s", "--out", "o"]);
    assert_exit(&o, 2);
    let kept = std::fs::read_to_string(tmp.path().join("o/study.csv")).unwrap();
    assert_eq!(kept, "case,weight\n1,2\n");
}

//! Through the binary (docs/cli.md §Skipping finished cases): a study case whose inputs changed is re-run,
//! saying why, into a cleanly replaced directory; `chute collect` warns about a stale case and
//! refuses directories that hold no study (exit 2, nothing written).
use crate::common::*;

const SHORT: &str = "time.duration_s=0.05";

fn table1() -> String {
    repo().join("studies/table1.toml").display().to_string()
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
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let case = tmp.path().join("o/20N");
    // A file the user put there and one an earlier (longer) run wrote and this one will not.
    std::fs::write(case.join("notes.txt"), "mine").unwrap();
    std::fs::write(case.join("snapshot_9s.png"), "old").unwrap();
    let o = run("time.duration_s=0.06");
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(0), "{err}");
    assert!(
        err.contains("case 20N: inputs changed since the recorded run; re-running"),
        "{err}"
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
    let o = chute(
        tmp.path(),
        &["study", "s.toml", "--out", "o", "--set", SHORT],
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    std::fs::write(tmp.path().join("s.toml"), study.replace("=2000", "=1000")).unwrap();
    let o = chute(tmp.path(), &["collect", "o"]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(0), "{err}");
    assert!(err.contains("warning: case `heavy`: stale"), "{err}");
    assert!(!err.contains("case `light`"), "{err}");
    assert!(stdout(&o).contains("| true | changed |"), "{}", stdout(&o));
}

#[test]
fn collect_on_empty_and_run_directories_exits_2_writing_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::create_dir(tmp.path().join("empty")).unwrap();
    let o = chute(tmp.path(), &["collect", "empty"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("no cases found in `empty`"),
        "{}",
        stderr(&o)
    );
    assert_eq!(
        std::fs::read_dir(tmp.path().join("empty")).unwrap().count(),
        0
    );
    let scenario = repo().join("scenarios/report-rod-200n.toml");
    let o = chute(
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
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let before = files(&tmp.path().join("r"));
    let o = chute(tmp.path(), &["collect", "r"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("`r` is a run directory"),
        "{}",
        stderr(&o)
    );
    assert!(
        files(&tmp.path().join("r")) == before,
        "nothing written into the run directory"
    );
    // A folder of plain runs (none a study's case) holds no cases either.
    std::fs::create_dir(tmp.path().join("runs")).unwrap();
    std::fs::rename(tmp.path().join("r"), tmp.path().join("runs/r")).unwrap();
    let o = chute(tmp.path(), &["collect", "runs"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("no cases found in `runs`"),
        "{}",
        stderr(&o)
    );
    assert_eq!(
        std::fs::read_dir(tmp.path().join("runs")).unwrap().count(),
        1
    );
}

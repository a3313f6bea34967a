//! `chute collect` knows a study's full case list from the recipe its cases record
//! (docs/reliability.md §4): a missing, failed or incomplete case, or a list that cannot be
//! known, makes the table incomplete (status 3), and the message says which and why.
use crate::common::*;

/// `chute study studies/table1.toml --out OUT` of 0.02 s flights in `dir`, as it ended.
pub(crate) fn table1_study(dir: &std::path::Path, out: &str) -> std::process::Output {
    table1_study_of(dir, out, "0.02")
}

/// [`table1_study`] of flights of `duration` s.
fn table1_study_of(dir: &std::path::Path, out: &str, duration: &str) -> std::process::Output {
    let study = repo().join("studies/table1.toml").display().to_string();
    let set = format!("time.duration_s={duration}");
    chute(dir, &["study", &study, "--out", out, "--set", &set])
}

/// Write `dir/other.toml`: a study `other` whose one case is named `20N` like Table I's.
pub(crate) fn write_other_study(dir: &std::path::Path) {
    let base = repo().join("scenarios/report-rod-200n.toml");
    let other = format!(
        "name = \"other\"\nbase = \"{}\"\n[[case]]\nname = \"20N\"\nset = [\"load.weight_n=999\"]\n",
        base.display()
    );
    std::fs::write(dir.join("other.toml"), other).unwrap();
}

/// A new temporary directory holding the study of [`write_other_study`] and an empty
/// directory `o` for its output.
pub(crate) fn other_study_in_tmp() -> tempfile::TempDir {
    let tmp = tempfile::tempdir().unwrap();
    write_other_study(tmp.path());
    std::fs::create_dir(tmp.path().join("o")).unwrap();
    tmp
}

/// The arguments of `chute study other.toml --out OUT` of 0.02 s flights
/// ([`write_other_study`]).
pub(crate) fn other_study_args(out: &str) -> [&str; 6] {
    [
        "study",
        "other.toml",
        "--out",
        out,
        "--set",
        "time.duration_s=0.02",
    ]
}

/// The text of `studies/table1.toml` with the path of its base scenario made absolute, so that
/// a copy of it elsewhere runs the same cases.
fn table1_text_anywhere() -> String {
    let base = format!("base = \"{}\"", bundled("report-rod-200n.toml"));
    std::fs::read_to_string(repo().join("studies/table1.toml"))
        .unwrap()
        .replace("base = \"../scenarios/report-rod-200n.toml\"", &base)
}

/// Report Table I as a study of 0.02 s flights in `out` of a new temporary directory.
pub(crate) fn table1_study_in(out: &str) -> tempfile::TempDir {
    let tmp = tempfile::tempdir().unwrap();
    let study = repo().join("studies/table1.toml").display().to_string();
    let set = ["--set", "time.duration_s=0.02"];
    chute_ok(
        tmp.path(),
        &[&["study", &study, "--out", out][..], &set].concat(),
    );
    tmp
}

/// Table I's study again into `s` of `dir` (as [`table1_study_in`] ran it): its stderr, after
/// checking it succeeded.
pub(crate) fn table1_study_again(dir: &std::path::Path) -> String {
    let study = repo().join("studies/table1.toml").display().to_string();
    let set = ["--set", "time.duration_s=0.02"];
    let o = chute(dir, &[&["study", &study, "--out", "s"][..], &set].concat());
    let err = stderr(&o);
    assert_exit(&o, 0);
    err
}

/// `chute collect s --out m` in `dir`, which must call the table incomplete (status 3): its
/// stderr.
pub(crate) fn incomplete_collect(dir: &std::path::Path) -> String {
    let o = chute(dir, &["collect", "s", "--out", "m"]);
    let err = stderr(&o);
    assert_exit(&o, 3);
    err
}

/// Cases of an older chute record no recipe, so their study's full case list is unknown:
/// `collect` of them, one case deleted, cannot call the table complete (status 3).
#[test]
fn collect_of_cases_without_a_recipe_cannot_call_the_table_complete() {
    let tmp = table1_study_in("s");
    for case in ["20N", "200N", "2000N"] {
        let done = tmp.path().join("s").join(case).join("done.json");
        let mut j = read_json(&done);
        j.as_object_mut().unwrap().remove("recipe");
        std::fs::write(&done, j.to_string()).unwrap();
    }
    std::fs::remove_dir_all(tmp.path().join("s/20N")).unwrap();
    let err = incomplete_collect(tmp.path());
    assert!(err.contains("record no recipe"), "{err}");
}

/// A case whose directory is there but empty is missing, and said to be so as it is: the
/// directory exists but holds no record of the case.
#[test]
fn collect_names_an_empty_case_directory_as_such() {
    let tmp = table1_study_in("s");
    // Its run's files without the study's record: missing, and the others' recipes still
    // give the full case list.
    let case = tmp.path().join("s/200N");
    std::fs::remove_file(case.join("done.json")).unwrap();
    let err = incomplete_collect(tmp.path());
    assert!(err.contains("case `200N` is missing"), "{err}");
    assert!(!err.contains("no recipe"), "{err}");
    std::fs::remove_dir_all(&case).unwrap();
    std::fs::create_dir(&case).unwrap();
    let err = incomplete_collect(tmp.path());
    assert!(err.contains("exists but holds no record of it"), "{err}");
}

#[test]
fn collect_of_some_shards_names_the_missing_case_and_fails() {
    let tmp = tempfile::tempdir().unwrap();
    let study = repo().join("studies/table1.toml").display().to_string();
    for (out, shard) in [("a", "0/3"), ("b", "1/3")] {
        chute_ok(
            tmp.path(),
            &[
                "study",
                &study,
                "--out",
                out,
                "--shard",
                shard,
                "--set",
                "time.duration_s=0.02",
            ],
        );
    }
    let o = chute(tmp.path(), &["collect", "a", "b", "--out", "m"]);
    let err = stderr(&o);
    assert_exit(&o, 3);
    assert_contains(
        &err,
        &["2 of 3 case(s) found complete", "case `2000N` is missing"],
    );
    // The table is still written, with the missing case's row.
    let table = std::fs::read_to_string(tmp.path().join("m/study.csv")).unwrap();
    assert!(
        table
            .lines()
            .any(|l| l.starts_with("2000N,") && l.contains(",missing,false,")),
        "{table}"
    );
}

/// A case count in a `done.json` that disagrees with the study file (the file edited since
/// the cases ran, or the record edited) makes the full case list uncertain: not complete.
#[test]
fn collect_flags_a_recorded_case_count_that_disagrees_with_the_study() {
    let tmp = table1_study_in("s");
    let done = tmp.path().join("s/200N/done.json");
    let mut j = read_json(&done);
    assert_eq!(j["recipe"]["case_count"], 3, "{j}");
    j["recipe"]["case_count"] = 5.into();
    std::fs::write(&done, j.to_string()).unwrap();
    let err = incomplete_collect(tmp.path());
    assert!(
        err.contains("has 3 case(s) now, but its cases recorded 3 to 5"),
        "{err}"
    );
    // Every case recording the same wrong count: still flagged.
    for case in ["20N", "2000N"] {
        let done = tmp.path().join("s").join(case).join("done.json");
        let mut j = read_json(&done);
        j["recipe"]["case_count"] = 5.into();
        std::fs::write(&done, j.to_string()).unwrap();
    }
    let o = chute(tmp.path(), &["collect", "s", "--out", "m"]);
    assert_exit_says(&o, 3, &["recorded 5:"]);
}

/// A `done.json` that cannot be read (here a directory) makes its case unreadable, named, but
/// says nothing about the study's case list: the others' recipes still give it.
#[test]
fn an_unreadable_record_is_named_and_the_case_list_still_known() {
    let tmp = table1_study_in("s");
    let done = tmp.path().join("s/200N/done.json");
    std::fs::remove_file(&done).unwrap();
    std::fs::create_dir(&done).unwrap();
    let err = incomplete_collect(tmp.path());
    assert_contains(&err, &["200N", "done.json"]);
    assert!(
        !err.contains("unknown") && !err.contains("no recipe"),
        "{err}"
    );
}

/// A study file whose path is not UTF-8 runs its cases and writes its table (its recorded
/// path is lossy text), instead of panicking when each case records its recipe; `collect`
/// then knows the table is whole from the case names the cases recorded.
#[test]
fn a_study_file_at_a_path_that_is_not_utf8_runs() {
    use std::os::unix::ffi::OsStrExt;
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join(std::ffi::OsStr::from_bytes(b"st\xffudies"));
    std::fs::create_dir(&dir).unwrap();
    let text = table1_text_anywhere();
    std::fs::write(dir.join("t.toml"), text).unwrap();
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_chute"))
        .arg("study")
        .arg(dir.join("t.toml"))
        .args(["--out", "s", "--set", "time.duration_s=0.02"])
        .current_dir(tmp.path())
        .output()
        .unwrap();
    let err = stderr(&o);
    assert_exit(&o, 0);
    assert!(!err.contains("panicked"), "{err}");
    assert!(tmp.path().join("s/study.csv").is_file());
    // Its cases record their names: the table gathered again knows it is whole.
    chute_ok(tmp.path(), &["collect", "s", "--out", "m"]);
}

/// A case whose later run was killed (its `run.json` says `running` and no process holds
/// it: a `chute resume` of the case killed mid-way) is not complete, whatever its
/// `done.json` says: collect reports it (status 3) and a study runs it again.
#[test]
fn a_case_whose_later_run_was_killed_is_not_complete() {
    let tmp = table1_study_in("s");
    let record = tmp.path().join("s/200N/run.json");
    let mut j = read_json(&record);
    j["status"] = "running".into();
    std::fs::write(&record, j.to_string()).unwrap();
    let err = incomplete_collect(tmp.path());
    assert_contains(&err, &["200N", "killed"]);
    // Its status says what happened, not `missing` (which means no directory at all).
    let table = std::fs::read_to_string(tmp.path().join("m/study.csv")).unwrap();
    let row = table.lines().find(|l| l.starts_with("200N,")).unwrap();
    assert!(row.contains(",abandoned,"), "{row}");
    let err = table1_study_again(tmp.path());
    assert!(
        err.contains("case 200N: a run of it was killed; re-running"),
        "{err}"
    );
}

/// A SLURM task id that is not UTF-8 is a bad value (status 2), not an unset variable that
/// would make every task run every case.
#[test]
fn a_slurm_variable_that_is_not_utf8_is_refused() {
    use std::os::unix::ffi::OsStrExt;
    let tmp = tempfile::tempdir().unwrap();
    let study = repo().join("studies/table1.toml");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_chute"))
        .arg("study")
        .arg(&study)
        .args(["--out", "s", "--set", "time.duration_s=0.02"])
        .env("SLURM_ARRAY_TASK_ID", std::ffi::OsStr::from_bytes(b"1\xff"))
        .env("SLURM_ARRAY_TASK_COUNT", "3")
        .current_dir(tmp.path())
        .output()
        .unwrap();
    assert_exit_says(&o, 2, &["SLURM_ARRAY_TASK_ID"]);
}

/// A FIFO named like one of chute's files (a run's lock, a case's marker) is not one of them:
/// `collect` and `view` name it and go on or refuse, instead of waiting forever for a writer.
#[test]
fn a_fifo_named_like_a_run_file_is_named_not_waited_on() {
    let tmp = table1_study_in("s");
    let fifo = |p: &str| {
        let path = tmp.path().join(p);
        let _ = std::fs::remove_file(&path);
        tool(tmp.path(), "mkfifo", &[path.as_os_str()]);
    };
    fifo("s/20N/.chute.lock");
    fifo("s/200N/done.json");
    let o = chute_within(tmp.path(), &["collect", "s", "--out", "m"], 60);
    let err = stderr(&o);
    assert_exit(&o, 3);
    assert_contains(&err, &["200N/done.json", "not a plain file"]);
    let o = chute_within(tmp.path(), &["view", "s/20N"], 60);
    assert_exit_says(&o, 2, &[".chute.lock is not a plain file"]);
}

/// A study's tables and runs never go among a run's files: `collect --out`, `study --out` and
/// `run --out` inside a run directory (a case of the study, or its `frames`) are refused,
/// status 2, writing nothing.
#[test]
fn tables_are_never_written_inside_a_run_directory() {
    let tmp = table1_study_in("s");
    let study = repo().join("studies/table1.toml").display().to_string();
    let rod = repo()
        .join("scenarios/report-rod-20n.toml")
        .display()
        .to_string();
    for args in [
        &["collect", "s", "--out", "s/20N/frames"][..],
        &["study", &study, "--out", "s/20N/inner"],
        &["run", &rod, "--out", "s/20N/frames/x"],
    ] {
        let o = chute(tmp.path(), args);
        assert_exit_says(&o, 2, &["lies inside the run directory"]);
    }
    assert!(!tmp.path().join("s/20N/frames/study.csv").exists());
    assert!(!tmp.path().join("s/20N/inner").exists());
    assert!(!tmp.path().join("s/20N/frames/x").exists());
    // Nor through a link that leads into one.
    std::os::unix::fs::symlink(tmp.path().join("s/20N/frames"), tmp.path().join("lnk")).unwrap();
    let o = chute(tmp.path(), &["run", &rod, "--out", "lnk/x"]);
    assert_exit(&o, 2);
    assert!(stderr(&o).contains("lies inside the run directory"));
}

/// A case's `summary.json` replaced by another case's (or edited) is not read as its result:
/// each `done.json` records the digest of the summary its run wrote, so `collect` flags the
/// case (status 3) and a study runs it again, after which the table is whole.
#[test]
fn a_summary_swapped_between_cases_is_not_taken_as_the_case_result() {
    let tmp = table1_study_in("s");
    let s = tmp.path().join("s");
    std::fs::copy(s.join("2000N/summary.json"), s.join("20N/summary.json")).unwrap();
    let err = incomplete_collect(tmp.path());
    assert_contains(&err, &["20N", "is not the summary its run wrote"]);
    let err = table1_study_again(tmp.path());
    assert!(
        err.contains(
            "case 20N: its summary.json is not verifiably the one its run wrote; re-running"
        ),
        "{err}"
    );
    chute_ok(tmp.path(), &["collect", "s", "--out", "m"]);
    // A record without the digest (edited, or an older chute's) cannot vouch for its summary.
    let done = s.join("200N/done.json");
    let mut j = read_json(&done);
    j.as_object_mut().unwrap().remove("summary_digest");
    std::fs::write(&done, j.to_string()).unwrap();
    let err = incomplete_collect(tmp.path());
    assert!(err.contains("records no digest of its summary"), "{err}");
}

/// Two studies that share a case name are two cases one table cannot hold: `collect` of both
/// is refused (status 2) naming the case, both directories and both studies, instead of one
/// case silently replacing the other.
#[test]
fn two_studies_sharing_a_case_name_are_not_mixed() {
    let tmp = table1_study_in("s");
    write_other_study(tmp.path());
    chute_ok(tmp.path(), &other_study_args("o"));
    let o = chute(tmp.path(), &["collect", "s", "o", "--out", "m"]);
    let err = stderr(&o);
    assert_exit(&o, 2);
    for want in ["case `20N`", "s/20N", "o/20N", "table1.toml", "other.toml"] {
        assert!(err.contains(want), "want `{want}` in: {err}");
    }
    assert!(!tmp.path().join("m").exists());
}

/// Two studies of one name from different study files, with no case name in common, are
/// still two studies: refused (status 2), naming both files.
#[test]
fn two_studies_of_one_name_from_two_files_are_not_mixed() {
    let tmp = table1_study_in("s");
    let table1 = std::fs::read_to_string(repo().join("studies/table1.toml")).unwrap();
    let base = repo().join("scenarios/report-rod-200n.toml");
    let name = table1.lines().find(|l| l.starts_with("name")).unwrap();
    let other = format!(
        "{name}\nbase = \"{}\"\n[[case]]\nname = \"x\"\nset = [\"load.weight_n=30\"]\n",
        base.display()
    );
    std::fs::create_dir(tmp.path().join("b")).unwrap();
    std::fs::write(tmp.path().join("b/table1.toml"), other).unwrap();
    let set = ["--set", "time.duration_s=0.02"];
    chute_ok(
        tmp.path(),
        &[&["study", "b/table1.toml", "--out", "o"][..], &set].concat(),
    );
    let o = chute(tmp.path(), &["collect", "s", "o", "--out", "m"]);
    let err = stderr(&o);
    assert_exit(&o, 2);
    for want in ["studies/table1.toml", "b/table1.toml", "o/x"] {
        assert!(err.contains(want), "want `{want}` in: {err}");
    }
    assert!(!tmp.path().join("m").exists());
    // The same file name and the same case names, other contents: still another study
    // (one of its shards, the 2000N case, collected beside Table I).
    std::fs::create_dir(tmp.path().join("c")).unwrap();
    let edited = table1
        .replace("load.weight_n=2000", "load.weight_n=3000")
        .replace(
            "../scenarios/",
            &format!("{}/", repo().join("scenarios").display()),
        );
    std::fs::write(tmp.path().join("c/table1.toml"), edited).unwrap();
    let shard = ["--shard", "2/3"];
    chute_ok(
        tmp.path(),
        &[&["study", "c/table1.toml", "--out", "o3"][..], &set, &shard].concat(),
    );
    let o = chute(tmp.path(), &["collect", "s", "o3", "--out", "m"]);
    assert_exit_says(&o, 2, &["c/table1.toml"]);
    // Byte-identical study files whose relative base is another scenario: other inputs,
    // another study (each copy runs one shard).
    let rod = std::fs::read_to_string(repo().join("scenarios/report-rod-200n.toml")).unwrap();
    let copy = "name = \"k\"\nbase = \"base.toml\"\n[[case]]\nname = \"a\"\n[[case]]\nname = \"b\"\nset = [\"canopy.nodes=31\"]\n";
    for (d, shard, weight) in [("k1", "0/2", "200.0"), ("k2", "1/2", "77.0")] {
        std::fs::create_dir(tmp.path().join(d)).unwrap();
        std::fs::write(tmp.path().join(d).join("k.toml"), copy).unwrap();
        let base = rod.replace("weight_n = 200.0", &format!("weight_n = {weight}"));
        std::fs::write(tmp.path().join(d).join("base.toml"), base).unwrap();
        let (study, out) = (format!("{d}/k.toml"), format!("{d}/o"));
        let args = [
            &["study", &study, "--out", &out, "--shard", shard][..],
            &set,
        ]
        .concat();
        chute_ok(tmp.path(), &args);
    }
    let o = chute(tmp.path(), &["collect", "k1/o", "k2/o", "--out", "km"]);
    assert_exit(&o, 2);
}

/// A case found in two directories with other states or study-wide overrides is never
/// dropped without a word: the table shows one (the last complete) and a warning names
/// both places and which one the table shows.
#[test]
fn a_case_found_twice_with_other_inputs_is_named_with_the_one_shown() {
    let tmp = table1_study_in("s");
    let o = table1_study_of(tmp.path(), "t", "0.03");
    assert_exit(&o, 0);
    // The newer attempt of 20N stopped early.
    let done = tmp.path().join("t/20N/done.json");
    let mut j = read_json(&done);
    j["status"] = "incomplete".into();
    j["message"] = "interrupted".into();
    std::fs::write(&done, j.to_string()).unwrap();
    let o = chute(tmp.path(), &["collect", "s", "t", "--out", "m"]);
    let err = stderr(&o);
    let note = err
        .lines()
        .find(|l| l.contains("case found in `s/20N`"))
        .unwrap_or_else(|| panic!("no note on 20N: {err}"));
    assert!(
        note.contains("`t/20N` (incomplete") && note.ends_with("the table shows `s/20N`"),
        "{note}"
    );
}

/// The study file a case recorded, replaced by a FIFO since, is named, not waited on:
/// `collect` ends with the case's inputs `unknown` and the reason.
#[test]
fn a_recorded_study_file_that_became_a_fifo_is_named_not_waited_on() {
    let tmp = tempfile::tempdir().unwrap();
    let text = table1_text_anywhere();
    std::fs::write(tmp.path().join("t.toml"), text).unwrap();
    chute_ok(
        tmp.path(),
        &[
            "study",
            "t.toml",
            "--out",
            "s",
            "--set",
            "time.duration_s=0.02",
        ],
    );
    std::fs::remove_file(tmp.path().join("t.toml")).unwrap();
    tool(tmp.path(), "mkfifo", &["t.toml".as_ref()]);
    let o = chute_within(tmp.path(), &["collect", "s", "--out", "m"], 60);
    let err = stderr(&o);
    assert!(err.contains("t.toml` is not a plain file"), "{err}");
}

/// A copy of a case's directory under another name (`20N.old`, a backup) holds a record of
/// that case: it is left out of the table with a note, and never stands for the case.
#[test]
fn a_copy_of_a_case_under_another_name_does_not_stand_for_it() {
    let tmp = table1_study_in("s");
    let s = tmp.path().join("s");
    tool(
        &s,
        "cp",
        &["-a".as_ref(), "20N".as_ref(), "20N.old".as_ref()],
    );
    std::fs::write(s.join("20N.old/summary.json"), "{}").unwrap();
    let o = chute(tmp.path(), &["collect", "s", "--out", "m"]);
    assert_exit_says(
        &o,
        0,
        &["`s/20N.old` holds a record of case `20N` but is not named after it"],
    );
    let table = std::fs::read_to_string(tmp.path().join("m/study.csv")).unwrap();
    assert_eq!(table.lines().count(), 4, "{table}");
}

/// `collect A --out B` where B holds a study of its own would replace B's table with A's:
/// refused (status 2), B's table untouched.
#[test]
fn collect_never_replaces_another_studys_table() {
    let tmp = table1_study_in("s");
    let o = table1_study_of(tmp.path(), "b", "0.03");
    assert_exit(&o, 0);
    let before = std::fs::read(tmp.path().join("b/study.csv")).unwrap();
    let o = chute(tmp.path(), &["collect", "s", "--out", "b"]);
    assert_exit(&o, 2);
    assert!(stderr(&o).contains("holds the cases of a study of its own"));
    assert_eq!(
        std::fs::read(tmp.path().join("b/study.csv")).unwrap(),
        before
    );
    // Nor a study's directory that has no finished case yet, only its owner record.
    std::fs::create_dir(tmp.path().join("c")).unwrap();
    std::fs::copy(
        tmp.path().join("b/.chute-study.json"),
        tmp.path().join("c/.chute-study.json"),
    )
    .unwrap();
    let o = chute(tmp.path(), &["collect", "s", "--out", "c"]);
    assert_exit(&o, 2);
    assert!(!tmp.path().join("c/study.csv").exists());
}

/// Directories none of which has a readable record cannot say how many cases their study
/// has: `collect` says the list is unknown (status 3) instead of calling the directories
/// found the whole study.
#[test]
fn collect_of_cases_none_of_which_is_recorded_says_the_list_is_unknown() {
    let tmp = table1_study_in("s");
    for case in ["20N", "200N"] {
        std::fs::remove_file(tmp.path().join("s").join(case).join("done.json")).unwrap();
    }
    std::fs::remove_dir_all(tmp.path().join("s/2000N")).unwrap();
    let err = incomplete_collect(tmp.path());
    assert!(
        err.contains("no case found records its study's case list"),
        "{err}"
    );
}

//! The study machinery with a fake case runner: parallel cases, done markers, skipping,
//! failures, sharding (also via SLURM variables) and `collect`.

use crate::common::{assert_contains, read_json};
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

use chute::app::{AppError, RunOptions, RunOutcome};
use chute::scenario::Scenario;
use chute::study::{self, CaseStatus, Row, Shard, Study, StudyOptions, Table};

const BASE: &str = "[model]\nkind = \"rod\"\n[load]\nweight_n = 200\n";

pub(crate) fn setup(study_text: &str) -> (tempfile::TempDir, Study) {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(dir.path().join("scenarios")).unwrap();
    std::fs::create_dir_all(dir.path().join("studies")).unwrap();
    std::fs::write(dir.path().join("scenarios/base.toml"), BASE).unwrap();
    let file = dir.path().join("studies/s.toml");
    std::fs::write(&file, study_text).unwrap();
    let st = Study::load(&file).unwrap_or_else(|e| panic!("{e}"));
    (dir, st)
}

pub(crate) const LIST: &str = r#"
name = "loads"
base = "../scenarios/base.toml"
[[case]]
name = "20N"
set = ["load.weight_n=20"]
[[case]]
name = "200N"
set = ["load.weight_n=200"]
[[case]]
name = "2000N"
set = ["load.weight_n=2000", "load.sites=center"]
"#;

pub(crate) fn opts(out: &Path) -> StudyOptions {
    StudyOptions {
        out_dir: out.to_path_buf(),
        jobs: Some(2),
        set: vec![],
        shard: None,
        force: false,
        verbose: false,
    }
}

/// A fake simulation: terminal velocity −W/100, written as `summary.json` like `app::run`,
/// beside the other files every finished run has (its record with its inputs' digests, its
/// resolved scenario and a time series), so that a study takes it as a whole run.
pub(crate) fn fake(s: &Scenario, o: &RunOptions) -> Result<RunOutcome, AppError> {
    use chute::output::record::{InputFile, RunRecord, Status};
    let inputs = s
        .input_files()
        .into_iter()
        .map(|(key, path)| InputFile {
            key: key.to_string(),
            digest: study::inputs::file_digest(&path).unwrap(),
            path,
        })
        .collect();
    let record = RunRecord {
        status: Status::Complete,
        reason: None,
        inputs,
        viewer: false,
        case_of: o.case_of.clone(),
    };
    record.write(&o.out_dir).unwrap();
    std::fs::write(o.out_dir.join("scenario.resolved.toml"), s.to_toml()).unwrap();
    std::fs::write(o.out_dir.join("timeseries.csv"), "t_s\n0\n").unwrap();
    let summary = serde_json::json!({
        "terminal_velocity_mps": -s.load.weight_n / 100.0,
        "time_to_terminal_s": 1.5,
        "reached_terminal": true,
        "max_extended_height_m": 0.25,
        "force_balance_error": 0.001,
        "name": s.name,
    });
    std::fs::write(o.out_dir.join("summary.json"), summary.to_string()).unwrap();
    Ok(RunOutcome {
        summary,
        complete: true,
        message: None,
    })
}

/// Each row of `t` as its case and a word of it (`word`: its status, its inputs' state), in
/// one line: `20N complete, 200N missing`.
pub(crate) fn case_words(t: &Table, word: impl Fn(&Row) -> &'static str) -> String {
    let rows: Vec<String> = t
        .rows
        .iter()
        .map(|r| format!("{} {}", r.case, word(r)))
        .collect();
    rows.join(", ")
}

/// Assert that `lines` (a table's notes, say) is one line, starting with `start`.
pub(crate) fn assert_one_line_starting(lines: &[String], start: &str) {
    assert_eq!(lines.len(), 1, "{lines:?}");
    assert!(lines[0].starts_with(start), "{lines:?}");
}

pub(crate) fn csv(out: &Path) -> Vec<Vec<String>> {
    let mut r = csv::Reader::from_path(out.join("study.csv")).unwrap();
    let mut rows = vec![r.headers().unwrap().iter().map(str::to_string).collect()];
    rows.extend(
        r.records()
            .map(|x| x.unwrap().iter().map(str::to_string).collect()),
    );
    rows
}

#[test]
fn list_study_runs_every_case_and_tabulates() {
    let (dir, st) = setup(LIST);
    assert_eq!(st.base, dir.path().join("studies/../scenarios/base.toml"));
    let out = dir.path().join("out");
    let names = Mutex::new(Vec::new());
    let runner = |s: &Scenario, o: &RunOptions| {
        names
            .lock()
            .unwrap()
            .push((s.name.clone(), o.out_dir.clone(), o.force, o.progress));
        fake(s, o)
    };
    let rep = study::run_study_with(&st, &opts(&out), &runner).unwrap();
    assert_eq!(rep.failures(), 0);
    assert!(rep.cases.iter().all(|(_, s)| *s == CaseStatus::Complete));
    let mut names = names.into_inner().unwrap();
    names.sort();
    assert_eq!(
        names[0],
        ("loads-2000N".into(), out.join("2000N"), true, false)
    );
    let rows = csv(&out);
    assert_eq!(
        rows[0],
        [
            "case",
            "load.weight_n",
            "load.sites",
            "terminal_velocity_mps",
            "time_to_terminal_s",
            "reached_terminal",
            "max_extended_height_m",
            "force_balance_error",
            "status",
            "complete",
            "inputs"
        ]
    );
    assert_eq!(
        rows[1],
        ["20N", "20", "", "-0.2", "1.5", "true", "0.25", "0.001", "complete", "true", "current"]
    );
    assert_eq!(rows[3][..3], ["2000N", "2000", "center"]);
    assert_eq!(rows[3][3], "-20.0");
    let md = std::fs::read_to_string(out.join("study.md")).unwrap();
    assert!(
        md.contains(
            "| 2000N | 2000 | center | -20.00 | 1.500 | true | 0.2500 | 0.001000 | complete | true | current |"
        ),
        "{md}"
    );
    let done = read_json(out.join("20N/done.json"));
    assert_eq!(done["status"], "complete");
    assert_eq!(done["index"], 0);
    // Atomic writes leave no temporary files behind.
    let mut top: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    top.sort();
    assert_eq!(
        top,
        [
            ".chute-study.json",
            "2000N",
            "200N",
            "20N",
            "study.csv",
            "study.md"
        ]
    );
}

#[test]
fn complete_cases_are_skipped_unless_forced() {
    let (dir, st) = setup(LIST);
    let out = dir.path().join("out");
    let calls = AtomicUsize::new(0);
    let runner = |s: &Scenario, o: &RunOptions| {
        calls.fetch_add(1, Ordering::SeqCst);
        fake(s, o)
    };
    study::run_study_with(&st, &opts(&out), &runner).unwrap();
    let rep = study::run_study_with(&st, &opts(&out), &runner).unwrap();
    assert_eq!(calls.load(Ordering::SeqCst), 3);
    assert!(rep.cases.iter().all(|(_, s)| *s == CaseStatus::Skipped));
    assert_eq!(rep.table.rows.len(), 3);
    let forced = StudyOptions {
        force: true,
        ..opts(&out)
    };
    study::run_study_with(&st, &forced, &runner).unwrap();
    assert_eq!(calls.load(Ordering::SeqCst), 6);
}

#[test]
fn failures_and_early_stops_are_recorded_and_rerun() {
    let (dir, st) = setup(LIST);
    let out = dir.path().join("out");
    let runner = |s: &Scenario, o: &RunOptions| match s.load.weight_n as i64 {
        20 => Err(AppError::RunFailed("Newton diverged at t = 0.1 s".into())),
        200 => Ok(RunOutcome {
            complete: false,
            message: Some("wall-clock limit".into()),
            ..fake(s, o)?
        }),
        _ => fake(s, o),
    };
    let rep = study::run_study_with(&st, &opts(&out), &runner).unwrap();
    assert_eq!(rep.failures(), 2);
    assert!(matches!(&rep.cases[0].1, CaseStatus::Failed(m) if m.contains("Newton diverged")));
    let done = read_json(out.join("200N/done.json"));
    assert_eq!(
        (done["status"].as_str(), done["message"].as_str()),
        (Some("incomplete"), Some("wall-clock limit"))
    );
    let rows = csv(&out);
    assert_eq!(rows[1][0], "20N");
    assert_eq!(rows[1][3], "", "no summary, no metrics");
    let complete = rows[0].iter().position(|h| h == "complete").unwrap();
    assert_eq!(rows[1][complete], "false");
    assert_eq!(rows[2][complete], "false");
    assert_eq!(rows[3][complete], "true");
    // A re-run retries only what did not complete.
    let calls = AtomicUsize::new(0);
    let ok = |s: &Scenario, o: &RunOptions| {
        calls.fetch_add(1, Ordering::SeqCst);
        fake(s, o)
    };
    let rep = study::run_study_with(&st, &opts(&out), &ok).unwrap();
    assert_eq!(calls.load(Ordering::SeqCst), 2);
    assert_eq!(rep.failures(), 0);
    assert!(csv(&out)[1..].iter().all(|r| r[r.len() - 2] == "true"));
}

#[test]
fn input_errors_stop_the_study_before_any_case_runs() {
    let bad = LIST.replace("load.weight_n=200\"", "load.weight_n=-200\"");
    let (dir, st) = setup(&bad);
    let calls = AtomicUsize::new(0);
    let runner = |s: &Scenario, o: &RunOptions| {
        calls.fetch_add(1, Ordering::SeqCst);
        fake(s, o)
    };
    let e = study::run_study_with(&st, &opts(&dir.path().join("out")), &runner).unwrap_err();
    assert_eq!(e.exit_code(), 2);
    let msg = e.to_string();
    assert_contains(&msg, &["case `200N`", "load.weight_n", "must be positive"]);
    assert_eq!(calls.load(Ordering::SeqCst), 0);
}

#[test]
fn global_overrides_come_before_the_cases_own() {
    let (dir, st) = setup(LIST);
    let seen = Mutex::new(Vec::new());
    let runner = |s: &Scenario, o: &RunOptions| {
        seen.lock().unwrap().push((s.load.weight_n, s.time.dt_s));
        fake(s, o)
    };
    let o = StudyOptions {
        set: vec!["load.weight_n=1".into(), "time.dt_s=0.002".into()],
        ..opts(&dir.path().join("o"))
    };
    study::run_study_with(&st, &o, &runner).unwrap();
    let mut seen = seen.into_inner().unwrap();
    seen.sort_by(|a, b| a.0.total_cmp(&b.0));
    assert_eq!(seen, [(20.0, 0.002), (200.0, 0.002), (2000.0, 0.002)]);
}

const GRID: &str = r#"
base = "../scenarios/base.toml"
[grid]
"load.weight_n" = [20, 200]
load.sites = ["ends", "center"]
"#;

#[test]
fn grid_is_the_cartesian_product_with_value_names() {
    let (_dir, st) = setup(GRID);
    assert_eq!(st.name, "s", "name defaults to the file stem");
    let names: Vec<&str> = st.cases.iter().map(|c| c.name.as_str()).collect();
    // Keys in sorted order (load.sites, load.weight_n); the last varies fastest.
    assert_eq!(
        names,
        [
            "sites-ends_weight_n-20",
            "sites-ends_weight_n-200",
            "sites-center_weight_n-20",
            "sites-center_weight_n-200"
        ]
    );
    assert_eq!(
        st.cases[2].set,
        ["load.sites=\"center\"", "load.weight_n=20"]
    );
    for c in &st.cases {
        st.scenario(c, &[]).unwrap();
    }
}

#[test]
fn sharding_splits_cases_and_collect_merges_them() {
    let (dir, st) = setup(GRID);
    // Shards into one shared directory: each invocation tabulates everything finished so far.
    let out = dir.path().join("shared");
    let s0 = StudyOptions {
        shard: Some(Shard::parse("0/2").unwrap()),
        ..opts(&out)
    };
    let rep = study::run_study_with(&st, &s0, &fake).unwrap();
    let ran: Vec<&str> = rep.cases.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(
        ran,
        ["sites-ends_weight_n-20", "sites-center_weight_n-20"],
        "indices 0 and 2"
    );
    // The other shard's cases are listed as missing, not left out.
    let rows = csv(&out);
    let status = rows[0].iter().position(|h| h == "status").unwrap();
    let states: Vec<&str> = rows[1..].iter().map(|r| r[status].as_str()).collect();
    assert_eq!(states, ["complete", "missing", "complete", "missing"]);
    let s1 = StudyOptions {
        shard: Some(Shard::parse("1/2").unwrap()),
        ..opts(&out)
    };
    study::run_study_with(&st, &s1, &fake).unwrap();
    let rows = csv(&out);
    let order: Vec<&str> = rows[1..].iter().map(|r| r[0].as_str()).collect();
    assert_eq!(order, names(&st), "rows in case order");
    // Shards into separate directories, merged by collect.
    let (a, b, merged) = (
        dir.path().join("a"),
        dir.path().join("b"),
        dir.path().join("merged"),
    );
    let sa = StudyOptions {
        shard: Some(Shard { index: 0, count: 3 }),
        ..opts(&a)
    };
    let sb = StudyOptions {
        shard: Some(Shard { index: 1, count: 3 }),
        ..opts(&b)
    };
    let sc = StudyOptions {
        shard: Some(Shard { index: 2, count: 3 }),
        ..opts(&b)
    };
    for o in [&sa, &sb, &sc] {
        study::run_study_with(&st, o, &fake).unwrap();
    }
    let t = study::collect(&[a.clone(), b.clone()], &merged).unwrap();
    assert_eq!(
        t.rows.iter().map(|r| r.case.as_str()).collect::<Vec<_>>(),
        names(&st)
    );
    assert_eq!(t.override_keys, ["load.sites", "load.weight_n"]);
    assert_eq!(
        std::fs::read_to_string(merged.join("study.csv")).unwrap(),
        std::fs::read_to_string(out.join("study.csv")).unwrap()
    );
}

fn names(st: &Study) -> Vec<&str> {
    st.cases.iter().map(|c| c.name.as_str()).collect()
}

#[test]
fn shard_specs_and_slurm_variables() {
    assert_eq!(Shard::parse("2/4").unwrap(), Shard { index: 2, count: 4 });
    for bad in ["4/4", "1/0", "x/2", "1", "-1/2", ""] {
        let e = Shard::parse(bad).unwrap_err();
        assert_eq!(e.exit_code(), 2, "{bad}");
        assert!(e.to_string().contains("expected I/N"), "{e}");
    }
    let vars = |id: &'static str, count: &'static str, min: Option<&'static str>| {
        move |k: &str| match k {
            "SLURM_ARRAY_TASK_ID" => Some(id.to_string()),
            "SLURM_ARRAY_TASK_COUNT" => Some(count.to_string()),
            "SLURM_ARRAY_TASK_MIN" => min.map(str::to_string),
            _ => None,
        }
    };
    assert_eq!(
        Shard::from_slurm(vars("3", "4", None)).unwrap().unwrap(),
        Shard { index: 3, count: 4 }
    );
    // `--array=1-4`: ids 1..=4 map to shards 0..=3.
    assert_eq!(
        Shard::from_slurm(vars("4", "4", Some("1")))
            .unwrap()
            .unwrap(),
        Shard { index: 3, count: 4 }
    );
    assert!(Shard::from_slurm(vars("5", "4", None)).unwrap().is_err());
    assert!(Shard::from_slurm(vars("x", "4", None)).unwrap().is_err());
    assert!(Shard::from_slurm(|_| None).is_none());
    // A task id without the array's size: refused, not every case in every task.
    let lone = |k: &str| (k == "SLURM_ARRAY_TASK_ID").then(|| "2".to_string());
    let e = Shard::from_slurm(lone).unwrap().unwrap_err();
    assert!(
        e.to_string().contains("SLURM_ARRAY_TASK_COUNT is not"),
        "{e}"
    );
    // Arrays whose ids are not consecutive would leave shards unrun: refused in every task.
    let array = |id: &'static str, min: &'static str, max: &'static str, step: &'static str| {
        move |k: &str| {
            let v = match k {
                "SLURM_ARRAY_TASK_ID" => id,
                "SLURM_ARRAY_TASK_COUNT" => "3",
                "SLURM_ARRAY_TASK_MIN" => min,
                "SLURM_ARRAY_TASK_MAX" => max,
                "SLURM_ARRAY_TASK_STEP" => step,
                _ => return None,
            };
            Some(v.to_string())
        }
    };
    // `--array=1-5:2` (ids 1, 3, 5) and `--array=0,2,5`.
    for (id, min, max, step) in [
        ("1", "1", "5", "2"),
        ("3", "1", "5", "2"),
        ("0", "0", "5", "1"),
        ("2", "0", "5", "1"),
    ] {
        let e = Shard::from_slurm(array(id, min, max, step))
            .unwrap()
            .unwrap_err();
        assert_eq!(e.exit_code(), 2);
        assert!(e.to_string().contains("not consecutive"), "{e}");
    }
    // `--array=1-3` with every variable SLURM sets.
    assert_eq!(
        Shard::from_slurm(array("3", "1", "3", "1"))
            .unwrap()
            .unwrap(),
        Shard { index: 2, count: 3 }
    );
    let s = Shard { index: 1, count: 3 };
    assert_eq!(
        (0..7).filter(|i| s.contains(*i)).collect::<Vec<_>>(),
        [1, 4]
    );
}

#[test]
fn study_file_errors() {
    let dir = tempfile::tempdir().unwrap();
    let check = |text: &str, want: &str| {
        let e = Study::from_str(text, "st.toml", dir.path()).unwrap_err();
        assert_eq!(e.exit_code(), 2);
        assert!(e.to_string().contains(want), "want `{want}` in: {e}");
    };
    check("base = \"b.toml\"\n", "no cases");
    check(
        "base = \"b.toml\"\n[grid]\n\"load.weight_n\" = [1, 2]\nload = { weight_n = [3] }\n",
        "grid key `load.weight_n` is given twice",
    );
    check(
        "base = \"b.toml\"\n[grid]\n\"load.weight_n\" = [1, 2]\nload.\"weight_n \" = [3]\n",
        "is given twice",
    );
    check(
        "base = \"b.toml\"\n[grid]\n\"a.b\" = [1]\n[[case]]\nname = \"x\"\n",
        "give one of",
    );
    check(
        "base = \"b.toml\"\ncases = 3\n",
        "st.toml:2:1: unknown field `cases`",
    );
    check("[[case]]\nname = \"x\"\n", "missing field `base`");
    check(
        "base = \"b.toml\"\n[[case]]\nname = \"x\"\n[[case]]\nname = \"x\"\n",
        "two cases are named `x`",
    );
    check(
        "base = \"b.toml\"\n[[case]]\nname = \"a/b\"\n",
        "case name `a/b` is not a plain directory name",
    );
    check(
        "base = \"b.toml\"\n[[case]]\nname = \"\"\n",
        "a case name is empty",
    );
    // A case where the table goes, and study names that are no directory of their own.
    check(
        "base = \"b.toml\"\n[[case]]\nname = \"study.csv\"\n",
        "the name of the study's table",
    );
    for name in ["", " ", "a/b", "..", ".hidden"] {
        check(
            &format!("name = \"{name}\"\nbase = \"b.toml\"\n[[case]]\nname = \"x\"\n"),
            &format!("study name `{name}` is not a directory name"),
        );
    }
    check(
        "base = \"b.toml\"\n[grid]\n\"load.weight_n\" = 3\n",
        "non-empty array",
    );
    check(
        "base = \"b.toml\"\n[grid]\n\"load.weight_n\" = []\n",
        "non-empty array",
    );
    check(
        "base = \"b.toml\"\nminimise = \"|wall_time_s|\"\n[[case]]\nname = \"x\"\n",
        "st.toml: `minimise = \"|wall_time_s|\"`: not a numeric column",
    );
    let st = Study::from_str(
        "base = \"b.toml\"\nminimise = \"|landing_velocity_mps|\"\n[[case]]\nname = \"x\"\n",
        "st.toml",
        dir.path(),
    )
    .unwrap();
    assert_eq!(st.objective.unwrap().text(), "|landing_velocity_mps|");
    let e = Study::load(Path::new("/no/such/study.toml")).unwrap_err();
    assert!(e.to_string().contains("/no/such/study.toml"), "{e}");
}

#[test]
fn bundled_studies_parse_and_their_cases_validate() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../studies");
    for (file, cases) in [
        ("table1.toml", vec!["20N", "200N", "2000N"]),
        ("table2.toml", vec!["4-sites", "6-sites"]),
        ("table2-springs-hinges.toml", vec!["4-sites", "6-sites"]),
    ] {
        let st = Study::load(&root.join(file)).unwrap();
        assert_eq!(names(&st), cases);
        for c in &st.cases {
            let s = st.scenario(c, &[]).unwrap_or_else(|e| panic!("{e}"));
            assert_eq!(s.name, format!("{}-{}", st.name, c.name));
        }
    }
    let st = Study::load(&root.join("table1.toml")).unwrap();
    let w: Vec<f64> = st
        .cases
        .iter()
        .map(|c| st.scenario(c, &[]).unwrap().load.weight_n)
        .collect();
    assert_eq!(w, [20.0, 200.0, 2000.0]);
}

#[test]
fn collect_lists_every_missing_failed_and_unreadable_case() {
    let (dir, st) = setup(LIST);
    let (a, b) = (dir.path().join("a"), dir.path().join("b"));
    // Shards 0/3 and 1/3 only: case 2000N (index 2) never ran.
    for (out, index) in [(&a, 0), (&b, 1)] {
        let o = StudyOptions {
            shard: Some(Shard { index, count: 3 }),
            ..opts(out)
        };
        study::run_study_with(&st, &o, &fake).unwrap();
    }
    let merged = dir.path().join("merged");
    let t = study::collect(&[a.clone(), b.clone()], &merged).unwrap();
    let states = case_words(&t, |r| r.state.word());
    assert_eq!(states, "20N complete, 200N complete, 2000N missing");
    assert_one_line_starting(&t.unfinished(), "case `2000N` is missing: not run");
    // The missing row keeps its overrides and has no numbers.
    let r = &t.rows[2];
    assert_eq!(r.overrides["load.weight_n"], "2000");
    assert!(r.metrics.values().all(String::is_empty) && !r.complete);
    // A done.json that cannot be parsed: the case is named with the file, not dropped.
    std::fs::write(b.join("200N/done.json"), "{ \"status\": \"compl").unwrap();
    let t = study::collect(&[a.clone(), b.clone()], &merged).unwrap();
    let lines = t.unfinished();
    assert!(
        lines.iter().any(
            |l| l.starts_with("case `200N` cannot be read: cannot read `")
                && l.contains("200N/done.json")
        ),
        "{lines:?}"
    );
    // A summary that says nothing: a failed case's row has empty metrics, never 0.
    let fail = |s: &Scenario, o: &RunOptions| match s.load.weight_n as i64 {
        2000 => Err(AppError::RunFailed("step failed at t = 0".into())),
        _ => fake(s, o),
    };
    study::run_study_with(&st, &opts(&a), &fail).unwrap();
    let t = study::collect(std::slice::from_ref(&a), &merged).unwrap();
    let r = t.rows.iter().find(|r| r.case == "2000N").unwrap();
    assert_eq!(r.state.word(), "failed");
    assert!(r.metrics.values().all(String::is_empty), "{r:?}");
}

//! A finished study case is reused only for the inputs it ran (docs/cli.md): the
//! resolved scenario and the mesh file, hashed into `done.json`. With the fake case runner of
//! `study.rs`; `collect` on directories that hold no study.

use std::path::{Path, PathBuf};

use crate::common::read_json;
use std::sync::atomic::{AtomicUsize, Ordering};

use chute::app::{AppError, RunOptions, RunOutcome};
use chute::scenario::Scenario;
use chute::study::{self, CaseStatus, InputsState, Study, StudyOptions};

use super::study::{assert_one_line_starting, case_words, csv, fake, opts, setup, LIST};

/// A fake runner that counts its calls.
fn counting(
    calls: &AtomicUsize,
) -> impl Fn(&Scenario, &RunOptions) -> Result<RunOutcome, AppError> + Sync + '_ {
    move |s, o| {
        calls.fetch_add(1, Ordering::SeqCst);
        fake(s, o)
    }
}

/// A study of [`LIST`] in a new directory, run once into its `out` by a runner [`counting`]
/// its calls in `calls`.
fn study_run_once_counting(calls: &AtomicUsize) -> (tempfile::TempDir, Study, PathBuf) {
    let (dir, st) = setup(LIST);
    let out = dir.path().join("out");
    study::run_study_with(&st, &opts(&out), &counting(calls)).unwrap();
    (dir, st, out)
}

fn statuses(rep: &study::StudyReport) -> Vec<CaseStatus> {
    rep.cases.iter().map(|(_, s)| s.clone()).collect()
}

fn done(out: &Path, case: &str) -> serde_json::Value {
    read_json(out.join(case).join("done.json"))
}

#[test]
fn identical_inputs_are_skipped() {
    let calls = AtomicUsize::new(0);
    let (dir, st, out) = study_run_once_counting(&calls);
    let run = counting(&calls);
    assert!(done(&out, "20N")["inputs"]
        .as_str()
        .is_some_and(|d| d.starts_with("fnv1a64:")));
    // The base file rewritten with the same values spelled differently: the same inputs.
    std::fs::write(
        dir.path().join("scenarios/base.toml"),
        "# reformatted\n[model]\nkind = 'rod'\n\n[load]\nweight_n = 200.0\n",
    )
    .unwrap();
    let rep = study::run_study_with(&st, &opts(&out), &run).unwrap();
    assert_eq!(calls.load(Ordering::SeqCst), 3);
    assert_eq!(statuses(&rep), vec![CaseStatus::Skipped; 3]);
    assert!(rep
        .table
        .rows
        .iter()
        .all(|r| r.inputs == InputsState::Current));
}

#[test]
fn changed_duration_override_reruns_the_case() {
    let (dir, st) = setup(LIST);
    let out = dir.path().join("out");
    let calls = AtomicUsize::new(0);
    let run = counting(&calls);
    let with = |d: &str| StudyOptions {
        set: vec![format!("time.duration_s={d}")],
        ..opts(&out)
    };
    study::run_study_with(&st, &with("0.3"), &run).unwrap();
    let before = done(&out, "200N")["inputs"].clone();
    let rep = study::run_study_with(&st, &with("0.4"), &run).unwrap();
    assert_eq!(calls.load(Ordering::SeqCst), 6, "every case re-ran");
    assert_eq!(statuses(&rep), vec![CaseStatus::Complete; 3]);
    let after = done(&out, "200N");
    assert_ne!(after["inputs"], before);
    assert_eq!(after["recipe"]["set"][0], "time.duration_s=0.4");
    // And back to 0.3: re-run again, not mistaken for the 0.4 record.
    study::run_study_with(&st, &with("0.3"), &run).unwrap();
    assert_eq!(calls.load(Ordering::SeqCst), 9);
    assert_eq!(done(&out, "200N")["inputs"], before);
}

#[test]
fn edited_base_scenario_reruns_the_case() {
    let calls = AtomicUsize::new(0);
    let (dir, st, out) = study_run_once_counting(&calls);
    let run = counting(&calls);
    let base = dir.path().join("scenarios/base.toml");
    let text = std::fs::read_to_string(&base).unwrap();
    std::fs::write(&base, format!("{text}[time]\nduration_s = 2.0\n")).unwrap();
    let rep = study::run_study_with(&st, &opts(&out), &run).unwrap();
    assert_eq!(calls.load(Ordering::SeqCst), 6);
    assert_eq!(statuses(&rep), vec![CaseStatus::Complete; 3]);
}

/// A study of the bundled DisMech parachute with its mesh copied beside it.
fn mesh_study(dir: &Path) -> (Study, std::path::PathBuf) {
    let repo = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mesh = dir.join("canopy.txt");
    std::fs::copy(
        repo.join("crates/chute/data/meshes/hexparachute_n6_python.txt"),
        &mesh,
    )
    .unwrap();
    let scenario = std::fs::read_to_string(repo.join("scenarios/dismech-hex-n6.toml"))
        .unwrap()
        .replace(
            "../crates/chute/data/meshes/hexparachute_n6_python.txt",
            "canopy.txt",
        );
    std::fs::write(dir.join("hex.toml"), scenario).unwrap();
    let text = "base = \"hex.toml\"\n[[case]]\nname = \"a\"\n[[case]]\nname = \"b\"\nset = [\"load.weight_n=20\"]\n";
    std::fs::write(dir.join("s.toml"), text).unwrap();
    (Study::load(&dir.join("s.toml")).unwrap(), mesh)
}

#[test]
fn edited_mesh_file_reruns_the_case() {
    let dir = tempfile::tempdir().unwrap();
    let (st, mesh) = mesh_study(dir.path());
    let out = dir.path().join("out");
    let calls = AtomicUsize::new(0);
    let run = counting(&calls);
    study::run_study_with(&st, &opts(&out), &run).unwrap();
    study::run_study_with(&st, &opts(&out), &run).unwrap();
    assert_eq!(calls.load(Ordering::SeqCst), 2, "unchanged mesh: skipped");
    // One coordinate moved by a micrometre: the scenario text is the same, the mesh is not.
    let text = std::fs::read_to_string(&mesh).unwrap();
    let moved = text.replacen("0.090909, 0.000000", "0.090910, 0.000000", 1);
    assert_ne!(moved, text);
    std::fs::write(&mesh, moved).unwrap();
    let rep = study::run_study_with(&st, &opts(&out), &run).unwrap();
    assert_eq!(calls.load(Ordering::SeqCst), 4);
    assert_eq!(statuses(&rep), vec![CaseStatus::Complete; 2]);
}

#[test]
fn collect_flags_the_stale_case() {
    let (dir, st) = setup(LIST);
    let out = dir.path().join("out");
    study::run_study_with(&st, &opts(&out), &fake).unwrap();
    // The study file now gives case 200N another load.
    let file = dir.path().join("studies/s.toml");
    let text = std::fs::read_to_string(&file).unwrap();
    std::fs::write(
        &file,
        text.replace("load.weight_n=200\"", "load.weight_n=300\""),
    )
    .unwrap();
    let merged = dir.path().join("merged");
    let t = study::collect(std::slice::from_ref(&out), &merged).unwrap();
    let state = case_words(&t, |r| r.inputs.word());
    assert_eq!(state, "20N current, 200N changed, 2000N current");
    assert_one_line_starting(&t.input_warnings(), "case `200N`: stale");
    let rows = csv(&merged);
    assert_eq!(rows[0].last().unwrap(), "inputs");
    assert_eq!(rows[2][0], "200N");
    assert_eq!(rows[2].last().unwrap(), "changed");
    // A case the study file no longer has is stale too.
    std::fs::write(&file, text.replace("name = \"20N\"", "name = \"10N\"")).unwrap();
    let t = study::collect(std::slice::from_ref(&out), &merged).unwrap();
    let row = |name: &str| t.rows.iter().find(|r| r.case == name).unwrap();
    assert!(
        matches!(&row("20N").inputs, InputsState::Changed(why) if why.contains("no longer has"))
    );
    // And the case it has instead has not run.
    assert_eq!(row("10N").state.word(), "missing");
}

#[test]
fn collect_notes_cases_run_under_different_overrides() {
    let (dir, st) = setup(LIST);
    let out = dir.path().join("out");
    for (shard, d) in [(0, "0.3"), (1, "0.4"), (2, "0.4")] {
        let o = StudyOptions {
            set: vec![format!("time.duration_s={d}")],
            shard: Some(study::Shard {
                index: shard,
                count: 3,
            }),
            ..opts(&out)
        };
        study::run_study_with(&st, &o, &fake).unwrap();
    }
    let t = study::collect(std::slice::from_ref(&out), &out).unwrap();
    assert_eq!(t.notes.len(), 1, "{:?}", t.notes);
    assert!(
        t.notes[0].contains("20N with") && t.notes[0].contains("200N, 2000N with"),
        "{:?}",
        t.notes
    );
}

#[test]
fn collect_on_an_empty_directory_finds_no_cases() {
    let dir = tempfile::tempdir().unwrap();
    let empty = dir.path().join("empty");
    std::fs::create_dir_all(empty.join("not-a-case")).unwrap();
    let err = study::collect(std::slice::from_ref(&empty), &empty).unwrap_err();
    assert!(
        matches!(&err, AppError::Input(m) if m.contains("no cases found")),
        "{err}"
    );
    assert!(!empty.join("study.csv").exists() && !empty.join("study.md").exists());
}

#[test]
fn collect_refuses_a_run_directory() {
    let dir = tempfile::tempdir().unwrap();
    let run = dir.path().join("run");
    std::fs::create_dir_all(run.join("frames")).unwrap();
    std::fs::write(run.join("scenario.resolved.toml"), "name = \"x\"\n").unwrap();
    std::fs::write(run.join("summary.json"), "{}").unwrap();
    let before: Vec<_> = std::fs::read_dir(&run)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    let err = study::collect(std::slice::from_ref(&run), &run).unwrap_err();
    assert!(
        matches!(&err, AppError::Input(m) if m.contains("is a run directory")),
        "{err}"
    );
    let after: Vec<_> = std::fs::read_dir(&run)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(
        before.len(),
        after.len(),
        "nothing written into the run directory"
    );
    // A study may not write its table into one either.
    let (sdir, st) = setup(LIST);
    let err = study::run_study_with(&st, &opts(&run), &fake).unwrap_err();
    assert!(
        matches!(&err, AppError::Input(m) if m.contains("is a run directory")),
        "{err}"
    );
    drop(sdir);
}

//! One case of a study: skipped when current (its record then names this study), else run in
//! its own directory, which it holds (locks) from before its marker is removed until after
//! the new one is written (docs/cli.md §`chute study`). A case whose directory cannot be
//! used (a file in its place, a marker that is a directory, a linked `frames`, another
//! process holding it, a full disk) is "not run" with the reason, and the study goes on to
//! the other cases and the table.

use std::path::{Path, PathBuf};

use super::table::write_atomic;
use super::{expected, skip, split_override, summary_digest};
use super::{Case, CaseStatus, Runner, Study, StudyOptions, DONE_FILE};
use crate::app::{AppError, RunOptions};
use crate::output::lock::RunLock;
use crate::scenario::Scenario;

/// Run (or skip) `case` of `study` into `opts.out_dir/<case>`.
pub(super) fn run_case(
    study: &Study,
    case: &Case,
    scenario: &Scenario,
    digest: &str,
    opts: &StudyOptions,
    runner: &Runner,
) -> Result<CaseStatus, AppError> {
    let dir = opts.out_dir.join(&case.name);
    let done = dir.join(DONE_FILE);
    let (current, stale) = skip::recorded_run(&done, digest);
    let say = |what: &str| {
        if opts.verbose {
            eprintln!("case {}: {what}", case.name);
        }
    };
    if current && !opts.force {
        adopt(study, case, opts, &dir);
        say("already complete, skipped");
        return Ok(CaseStatus::Skipped);
    }
    if crate::runner::STOP.load(std::sync::atomic::Ordering::SeqCst) {
        // Stopped (Ctrl-C, SIGTERM) before this case began: it is not run, and gets no
        // directory that would show it as an interrupted run.
        let why = "not run: the study was stopped before this case began";
        say(why);
        return Ok(CaseStatus::Failed(why.into()));
    }
    let unrecorded = !done.exists() && crate::output::run_files::is_run_dir(&dir);
    let _lock = match claim(&dir) {
        Ok(lock) => lock,
        Err(why) => {
            let why = format!("not run: {why}");
            say(&why);
            return Ok(CaseStatus::Failed(why));
        }
    };
    if unrecorded && !opts.force && holds_finished_run(&dir, digest) {
        // A run of exactly this case that finished without its study recording it (a case
        // killed, then completed by `chute resume`): recorded, not thrown away.
        let m = marker(study, case, opts, digest, &dir, ("complete", None), None);
        write_atomic(&done, format!("{m:#}\n").as_bytes())?;
        say("its directory holds a finished run of it that the study had not recorded; recorded, skipped");
        return Ok(CaseStatus::Skipped);
    }
    match (stale, opts.force) {
        (Some(why), false) => say(&format!("{why}; re-running")),
        // Not silently: the run there may be one the user put there, not a case of this study.
        _ if unrecorded => say(&format!(
            "`{}` holds a run this study did not record (no {DONE_FILE}); replacing it",
            dir.display()
        )),
        _ => {}
    }
    let run_opts = RunOptions {
        out_dir: dir.clone(),
        force: true,
        progress: false,
        checkpoint_every_s: None,
        resume: None,
        viewer: false,
    };
    let started = std::time::Instant::now();
    let status = match runner(scenario, &run_opts) {
        Ok(o) if o.complete => CaseStatus::Complete,
        Ok(o) => CaseStatus::Incomplete(o.message.unwrap_or_else(|| "stopped early".into())),
        Err(e) => CaseStatus::Failed(e.to_string()),
    };
    let (word, message) = match &status {
        CaseStatus::Complete | CaseStatus::Skipped => ("complete", None),
        CaseStatus::Incomplete(m) => ("incomplete", Some(m.clone())),
        CaseStatus::Failed(m) => ("failed", Some(m.clone())),
    };
    let wall = Some(started.elapsed().as_secs_f64());
    let m = marker(
        study,
        case,
        opts,
        digest,
        &dir,
        (word, message.clone()),
        wall,
    );
    if let Err(e) = write_atomic(&done, format!("{m:#}\n").as_bytes()) {
        // The study goes on to the other cases and its table; this one is not recorded.
        let why = format!("ran ({word}) but its record could not be written: {e}");
        say(&why);
        return Ok(CaseStatus::Failed(why));
    }
    say(&format!(
        "{word}{}",
        message.map_or(String::new(), |m| format!(": {m}"))
    ));
    Ok(status)
}

/// The `done.json` of `case` run into `dir`: how it ended (`status`, its message), the wall
/// time (`None`: not known, for a run recorded after the fact), and what identifies it.
fn marker(
    study: &Study,
    case: &Case,
    opts: &StudyOptions,
    digest: &str,
    dir: &Path,
    (word, message): (&str, Option<String>),
    wall_time_s: Option<f64>,
) -> serde_json::Value {
    let overrides: Vec<[String; 2]> = case.set.iter().filter_map(|s| split_override(s)).collect();
    serde_json::json!({
        "study": study.name,
        "case": case.name,
        "index": case.index,
        "overrides": overrides,
        "status": word,
        "message": message,
        "wall_time_s": wall_time_s,
        "inputs": digest,
        "summary_digest": summary_digest(dir),
        "recipe": expected::recipe(study, &opts.set, case),
    })
}

/// Whether `dir` holds a complete run (its record says so and its summary reads) of exactly
/// the inputs `digest` (its resolved scenario, loaded again, has them).
fn holds_finished_run(dir: &Path, digest: &str) -> bool {
    use crate::output::record::{RunRecord, Status};
    use crate::output::run_files::{RESOLVED_SCENARIO, SUMMARY};
    let complete = matches!(RunRecord::read(dir), Ok(Some(r)) if r.status == Status::Complete);
    let summary = super::table::read_json(&dir.join(SUMMARY)).is_some();
    let same = || {
        let s = Scenario::load(&dir.join(RESOLVED_SCENARIO), &[]).ok()?;
        super::inputs::digest(&s).ok()
    };
    complete && summary && same().as_deref() == Some(digest)
}

/// Make `dir` the case's and hold it, with its earlier marker removed (so that a run stopped
/// from here on is never taken as complete; the runner then clears everything else the
/// earlier run wrote), or say why the case cannot be run there. A case that is not run
/// leaves no directory that looks like one.
fn claim(dir: &Path) -> Result<RunLock, String> {
    let d = dir.display();
    let meta = std::fs::symlink_metadata(dir);
    if meta.as_ref().is_ok_and(|m| m.file_type().is_symlink()) {
        // A link would make the case replace whatever run it points to, outside the study.
        return Err(format!(
            "`{d}` is a symbolic link; a study writes its cases in its own directory"
        ));
    }
    if meta.is_ok_and(|m| !m.is_dir()) {
        return Err(format!(
            "`{d}` is a file, not a directory; a study writes each case in a directory of its name"
        ));
    }
    let created = crate::app::out_dir::first_missing(dir);
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot create `{d}`: {e}"))?;
    let release = |why: String| {
        crate::app::out_dir::remove_created(dir, created.as_deref());
        why
    };
    // Held by another process (a re-queued array task), not writable (a full disk), a linked
    // `frames`: this case is not run and the study goes on.
    let lock = RunLock::acquire(dir).map_err(|e| release(e.to_string()))?;
    let done = dir.join(DONE_FILE);
    match std::fs::remove_file(&done) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(format!(
            "its marker `{}` cannot be removed: {e}",
            done.display()
        )),
        _ => Ok(lock),
    }
}

/// A skipped case is this study's now: its marker's recipe (the study's case list) and index
/// become this study's, so that `collect` knows every case of the study that ran last
/// (a ladder re-run into the same directory with other levels). Left as it is when another
/// process holds the directory or the marker cannot be rewritten: the case's result stands.
fn adopt(study: &Study, case: &Case, opts: &StudyOptions, dir: &Path) {
    let Ok(_lock) = RunLock::acquire(dir) else {
        return;
    };
    let done: PathBuf = dir.join(DONE_FILE);
    let Some(mut marker) = super::table::read_json(&done) else {
        return;
    };
    let recipe = expected::recipe(study, &opts.set, case);
    if marker["recipe"] == recipe && marker["index"] == case.index {
        return;
    }
    marker["recipe"] = recipe;
    marker["index"] = case.index.into();
    marker["study"] = study.name.clone().into();
    let _ = write_atomic(&done, format!("{marker:#}\n").as_bytes());
}

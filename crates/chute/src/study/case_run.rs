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
    let say = |what: &str| {
        if opts.verbose {
            crate::err_line!("case {}: {what}", case.name);
        }
    };
    let skipped = || {
        say("already complete, skipped");
        Ok(CaseStatus::Skipped)
    };
    // A first look, without the lock: a stop begins no case that is not already done.
    let files = scenario.input_files();
    let (current, _) = skip::recorded_run(&done, digest, &files);
    let current = current && !opts.force;
    if !current && crate::runner::STOP.load(std::sync::atomic::Ordering::SeqCst) {
        // Stopped (Ctrl-C, SIGTERM) before this case began: it is not run, and gets no
        // directory that would show it as an interrupted run.
        let why = "not run: the study was stopped before this case began";
        say(why);
        return Ok(CaseStatus::Failed(why.into()));
    }
    // A link is never the case's directory, whatever run is behind it (the table leaves it
    // out too).
    let linked = std::fs::symlink_metadata(&dir).is_ok_and(|m| m.file_type().is_symlink());
    let _lock = match hold(&dir) {
        Ok(lock) => lock,
        // Held by the process that is finishing it, say: its record stands.
        Err(_) if current && !linked => return skipped(),
        Err(why) => {
            let why = format!("not run: {why}");
            say(&why);
            return Ok(CaseStatus::Failed(why));
        }
    };
    // Judged again under the lock: another study may have finished the case meanwhile.
    let (current, stale) = skip::recorded_run(&done, digest, &files);
    if current && !opts.force {
        adopt(study, case, opts, &dir);
        return skipped();
    }
    let unrecorded = !done.exists() && crate::output::run_files::is_run_dir(&dir);
    if unrecorded && !opts.force && holds_finished_run(&dir, digest) {
        // A run of exactly this case that finished without its study recording it (a case
        // killed, then completed by `chute resume`): recorded, not thrown away.
        let m = marker(study, case, opts, digest, &dir, ("complete", None), None);
        return Ok(match write_atomic(&done, format!("{m:#}\n").as_bytes()) {
            Ok(()) => {
                say("its directory holds a finished run of it that the study had not recorded; recorded, skipped");
                CaseStatus::Skipped
            }
            Err(e) => CaseStatus::Failed(format!("its finished run could not be recorded: {e}")),
        });
    }
    if unrecorded && !opts.force && !made_for(&dir, &case_id(study, case)) {
        // A run not made for this case (its record names no case of this study, or there is
        // none) may be one the user put there: never replaced without being asked.
        let why = format!(
            "not run: `{}` holds a run that was not made for this case (no {DONE_FILE}, and its \
             run.json names no case {}); --force replaces it",
            dir.display(),
            case_id(study, case)
        );
        say(&why);
        return Ok(CaseStatus::Failed(why));
    }
    // The marker goes first, so that a run stopped from here on is never taken as complete;
    // the runner (force) then clears everything else the earlier run wrote.
    if let Err(e) = remove_marker(&done) {
        let why = format!("not run: {e}");
        say(&why);
        return Ok(CaseStatus::Failed(why));
    }
    match (stale, opts.force) {
        (Some(why), false) => say(&format!("{why}; re-running")),
        // Not silently: a run of this case that lost its marker, or any run under --force.
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
        case_of: Some(case_id(study, case)),
    };
    let earlier = summary_digest(&dir);
    let started = std::time::Instant::now();
    let outcome = runner(scenario, &run_opts);
    if let Ok(o) = &outcome {
        // A picture its run could not write (a full disk) is said here as `chute run` says
        // it, not only in the case's summary.json.
        let warnings = o.summary["warnings"].as_array().into_iter().flatten();
        for w in warnings.filter_map(|w| w.as_str()) {
            if w.contains(" was not written") {
                say(&format!("warning: {w}"));
            }
        }
    }
    let status = match outcome {
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
    let mut m = marker(
        study,
        case,
        opts,
        digest,
        &dir,
        (word, message.clone()),
        wall,
    );
    if word != "complete" && earlier.is_some() && summary_digest(&dir) == earlier {
        // The run failed before it replaced the earlier one: the summary there is not this
        // run's, and its numbers must not stand in this case's row.
        m["summary_digest"] = serde_json::Value::Null;
    }
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

/// Whether `dir` holds a complete run of exactly the inputs `digest`: its record says
/// complete, every input file it recorded still has the bytes it ran with, its resolved
/// scenario (loaded again) has the digest, and its summary is of that scenario.
fn holds_finished_run(dir: &Path, digest: &str) -> bool {
    use crate::output::record::{RunRecord, Status};
    use crate::output::run_files::{RESOLVED_SCENARIO, SUMMARY};
    let Ok(Some(record)) = RunRecord::read(dir) else {
        return false;
    };
    let inputs_kept = record
        .inputs
        .iter()
        .all(|f| super::inputs::file_digest(&f.path).is_ok_and(|now| now == f.digest));
    let Some(s) = Scenario::load(&dir.join(RESOLVED_SCENARIO), &[]).ok() else {
        return false;
    };
    let summary = super::table::read_json(&dir.join(SUMMARY));
    let of_it = summary.is_some_and(|j| j["scenario_name"] == s.name.as_str());
    let all_listed = s
        .input_files()
        .iter()
        .all(|(k, _)| record.inputs.iter().any(|r| r.key == *k));
    record.status == Status::Complete
        && inputs_kept
        && all_listed
        && of_it
        && super::inputs::digest(&s).is_ok_and(|d| d == digest)
}

/// How a case's runs name it in their record (`run.json`'s `case_of`): `study/case`.
fn case_id(study: &Study, case: &Case) -> String {
    format!("{}/{}", study.name, case.name)
}

/// Whether the run in `dir` was made for the case `id` (an earlier run of it whose marker
/// was lost: a study killed between removing the marker and writing the new one), or is
/// being replaced by a clearing that was killed (its record is then moved aside).
fn made_for(dir: &Path, id: &str) -> bool {
    use crate::output::record::RunRecord;
    let recorded = matches!(RunRecord::read(dir), Ok(Some(r)) if r.case_of.as_deref() == Some(id));
    recorded || crate::output::run_files::clearing_interrupted(dir)
}

/// Make `dir` the case's and hold it, or say why the case cannot be run there. A case that
/// is not run leaves no directory that looks like one.
fn hold(dir: &Path) -> Result<RunLock, String> {
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
    // Held by another process (a re-queued array task), not writable (a full disk), a linked
    // `frames`: this case is not run and the study goes on.
    RunLock::acquire(dir).map_err(|e| {
        crate::app::out_dir::remove_created(dir, created.as_deref());
        e.to_string()
    })
}

/// Remove the case's marker `done` (there may be none).
fn remove_marker(done: &Path) -> Result<(), String> {
    match std::fs::remove_file(done) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(format!(
            "its marker `{}` cannot be removed: {e}",
            done.display()
        )),
        _ => Ok(()),
    }
}

/// A skipped case is this study's now: its marker's recipe (the study's case list) and index
/// become this study's, so that `collect` knows every case of the study that ran last
/// (a ladder re-run into the same directory with other levels). The caller holds the
/// directory; a marker that cannot be rewritten is left as it is: the case's result stands.
fn adopt(study: &Study, case: &Case, opts: &StudyOptions, dir: &Path) {
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

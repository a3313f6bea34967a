//! Whether a study may skip a case: its directory holds a complete run of exactly the
//! inputs the study would run now, with a summary to read, and no killed run since.

use std::path::Path;

use super::table::read_json;
use crate::output::run_files::SUMMARY;

/// Whether a case directory holds a complete run of exactly these inputs, and if it holds a
/// complete run of others, why it is re-run.
/// `files` are the input files (key, path) the case reads now.
pub(super) fn recorded_run(
    done: &Path,
    digest: &str,
    files: &[(&'static str, std::path::PathBuf)],
) -> (bool, Option<&'static str>) {
    match read_json(done) {
        Some(d) if d["status"] == "complete" => match d["inputs"].as_str() {
            // Its table row comes from the summary: a case without a readable one is run
            // again rather than skipped into an `unreadable` row.
            Some(recorded) if recorded == digest => match done.parent() {
                Some(d) if abandoned(d) => (false, Some("a run of it was killed")),
                Some(dir) if !has_summary(dir) => {
                    (false, Some("its summary.json is missing or unreadable"))
                }
                Some(dir) if case_not_whole(dir, &d).is_some() => (
                    false,
                    Some("its run's files are not all its own (one missing, or a link)"),
                ),
                Some(dir) if super::table::summary_replaced(dir, &d).is_some() => (
                    false,
                    Some("its summary.json is not verifiably the one its run wrote"),
                ),
                Some(dir) if read_other_inputs(dir, files).is_some() => (
                    false,
                    Some("its run's record does not show it read the input files as they are now"),
                ),
                Some(_) => (true, None),
                None => (false, Some("its summary.json is missing or unreadable")),
            },
            Some(_) => (false, Some("inputs changed since the recorded run")),
            None => (
                false,
                Some("its record names no inputs (an older chute wrote it)"),
            ),
        },
        _ => (false, None),
    }
}

/// Whether `dir`'s record says a run is going that no process holds (killed). A study that
/// holds the directory itself (judging the case under its lock) is not that run.
fn abandoned(dir: &Path) -> bool {
    use crate::output::record::{DirState, RunRecord, Status};
    match DirState::of(dir) {
        Ok(DirState::Abandoned) => true,
        Ok(DirState::Running) if crate::output::lock::RunLock::held_here(dir) => {
            matches!(RunRecord::read(dir), Ok(Some(r)) if r.status == Status::Running)
        }
        _ => false,
    }
}

/// Whether `dir` holds a `summary.json` that parses.
fn has_summary(dir: &Path) -> bool {
    read_json(&dir.join(SUMMARY)).is_some()
}

/// Why the run recorded in `dir` is not of the input files the case reads now (`files`, key
/// and path, as its scenario resolves them now): its record's digest of a file it read
/// (taken when the run read it) differs from the bytes of the file of that key now, or that
/// file is not a plain file (a FIFO would be waited on). A file changed while a study ran
/// reaches the cases that start later, whose recipe digest was taken before. Files are
/// matched by key, not by the recorded path, so a moved project is judged by content. `None`
/// without a record (nothing to compare).
pub(crate) fn read_other_inputs(
    dir: &Path,
    files: &[(&'static str, std::path::PathBuf)],
) -> Option<String> {
    let record = match crate::output::record::RunRecord::read(dir) {
        Ok(Some(r)) => r,
        // A run of no input files has nothing to compare; a directory without a record is
        // an older chute's (or a runner's that keeps none).
        _ if files.is_empty() => return None,
        Ok(None) => return None,
        Err(e) => return Some(format!("its run's record cannot be read: {e}")),
    };
    record.inputs.iter().find_map(|recorded| {
        let now = files.iter().find(|(k, _)| *k == recorded.key);
        let r = crate::output::record::InputFile {
            path: now.map_or_else(|| recorded.path.clone(), |(_, p)| p.clone()),
            ..recorded.clone()
        };
        if std::fs::symlink_metadata(&r.path).is_err() {
            return Some(format!("{} `{}` is gone", r.key, r.path.display()));
        }
        if let Some(why) = crate::output::atomic::not_plain(&r.path, &r.key) {
            return Some(why);
        }
        match super::inputs::file_digest(&r.path) {
            Ok(now) if now == r.digest => None,
            Ok(now) => Some(format!(
                "its run read {} `{}` with digest {}, the file now has {now}",
                r.key,
                r.path.display(),
                r.digest
            )),
            Err(e) => Some(format!(
                "{} `{}` cannot be read: {e}",
                r.key,
                r.path.display()
            )),
        }
    })
}

/// Why the finished run in the case directory `dir` is not whole
/// ([`crate::output::run_files::run_not_whole`]), counting a missing `run.json` where the
/// case's record `done` shows it was written by a chute that always writes one (its recipe
/// records the study's `content`; an older chute's cases have no run.json to miss).
pub(super) fn case_not_whole(dir: &std::path::Path, done: &serde_json::Value) -> Option<String> {
    use crate::output::record::RunRecord;
    use crate::output::run_files::{run_not_whole, RESOLVED_SCENARIO, RUN_RECORD};
    // Whether its run pulled lines (and so wrote their files), as its resolved scenario says.
    let pulls = std::fs::read_to_string(dir.join(RESOLVED_SCENARIO))
        .ok()
        .and_then(|t| crate::scenario::Scenario::from_str_with_name(&t, "", &[]).ok())
        .is_some_and(|s| crate::resolve::ModelSpec::of(&s).pulled());
    run_not_whole(dir, pulls).or_else(|| {
        let record = dir.join(RUN_RECORD);
        let missing = !std::fs::symlink_metadata(&record).is_ok_and(|m| m.is_file());
        if done["recipe"]["content"].is_string() && missing {
            return Some(format!("its run's {RUN_RECORD} is missing"));
        }
        let record = RunRecord::read(dir).ok().flatten()?;
        // The run's own record outranks a marker edited to "complete".
        if record.status != crate::output::record::Status::Complete {
            return Some(format!(
                "its {RUN_RECORD} says the run did not complete ({:?})",
                record.status
            ));
        }
        // A record made for another case (its files copied in): not this case's run.
        let this = format!(
            "{}/{}",
            done["study"].as_str()?,
            done["case"].as_str()?
        );
        match record.case_of {
            Some(other) if other != this => Some(format!(
                "its {RUN_RECORD} is of case `{other}`, not `{this}` (files copied from another case?)"
            )),
            _ => None,
        }
    })
}

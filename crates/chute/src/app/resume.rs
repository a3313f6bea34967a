//! What `chute resume` checks before it continues a run in place: the checkpoint belongs
//! to this scenario (only `time.duration_s` may grow), and every input file the run read
//! still has the bytes it had (docs/reliability.md §2 and §5).

use std::path::Path;

use super::AppError;
use crate::output::record::RunRecord;
use crate::scenario::Scenario;

/// Refuse to resume `dir` when the model was built from input bytes other than its record's
/// ([`crate::build::Built::input_digests`]: what was parsed, whatever the file holds now).
pub(super) fn check_built_inputs(dir: &Path, built: &crate::build::Built) -> Result<(), AppError> {
    let Some(record) = RunRecord::read(dir).map_err(|e| cannot(dir, e))? else {
        return Ok(());
    };
    for (key, digest) in &built.input_digests {
        let Some(recorded) = record.inputs.iter().find(|r| r.key == *key) else {
            continue;
        };
        if *digest != recorded.digest {
            return Err(cannot(
                dir,
                format!(
                    "{key} `{}` changed while the run was resumed (recorded {}, read {digest}); the run cannot continue with other inputs: restore the file, or start a new run with `chute run … --force`",
                    recorded.path.display(),
                    recorded.digest
                ),
            ));
        }
    }
    Ok(())
}

/// Refuse to resume `dir` when an input file of its record has other bytes now (or cannot
/// be read): the run would continue from a state of one mesh with another. A record-less
/// directory (an older chute) cannot be checked and is accepted.
pub(super) fn check_inputs(dir: &Path, s: &Scenario) -> Result<(), AppError> {
    let record = RunRecord::read(dir).map_err(|e| cannot(dir, e))?;
    let Some(record) = record else {
        return Ok(());
    };
    let now = s.input_files();
    // Every file the scenario reads must be in the record: one missing from it (a record
    // edited, or written for another scenario) cannot be checked.
    if let Some((key, path)) = now
        .iter()
        .find(|(k, _)| !record.inputs.iter().any(|r| r.key == *k))
    {
        return Err(cannot(
            dir,
            format!(
                "the scenario reads {key} `{}`, which the run's record ({}) does not list, so its bytes cannot be checked against the run's: the record was edited or is another run's; start a new run with `chute run … --force`",
                path.display(),
                crate::output::run_files::RUN_RECORD
            ),
        ));
    }
    for recorded in &record.inputs {
        let path = now
            .iter()
            .find(|(k, _)| *k == recorded.key)
            .map_or(&recorded.path, |(_, p)| p);
        let digest = crate::study::inputs::file_digest(path).map_err(|e| {
            cannot(
                dir,
                format!("{} `{}` cannot be read: {e}", recorded.key, path.display()),
            )
        })?;
        if digest != recorded.digest {
            return Err(cannot(
                dir,
                format!(
                    "{} `{}` has changed since the run started (recorded {}, now {digest}); the run cannot continue with other inputs: restore the file, or start a new run with `chute run … --force`",
                    recorded.key,
                    path.display(),
                    recorded.digest
                ),
            ));
        }
    }
    Ok(())
}

fn cannot(dir: &Path, why: String) -> AppError {
    AppError::Input(format!("cannot resume `{}`: {why}", dir.display()))
}

/// Read the checkpoint of run directory `dir` and check it belongs to this scenario.
pub(super) fn load_checkpoint(
    dir: &std::path::Path,
    out_dir: &std::path::Path,
    scenario_toml: &str,
) -> Result<crate::checkpoint::Checkpoint, AppError> {
    let same_dir = match (dir.canonicalize(), out_dir.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    };
    if !same_dir {
        return Err(AppError::Input(format!(
            "resuming `{}` continues that run in place; the output directory `{}` must be the same directory",
            dir.display(),
            out_dir.display()
        )));
    }
    let c = crate::checkpoint::Checkpoint::read(dir)
        .map_err(|e| AppError::Input(format!("cannot resume from `{}`: {e}", dir.display())))?;
    let cannot = |why: String| AppError::Input(format!("cannot resume `{}`: {why}", dir.display()));
    if let Some(d) = scenario_difference(&c.scenario_toml, scenario_toml) {
        return Err(cannot(format!(
            "`{}` = {} (checkpoint) vs {} (now); only time.duration_s may change",
            d.key, d.was, d.now
        )));
    }
    let (was, now) = (
        resolved_value(&c.scenario_toml, DURATION_KEY).and_then(|v| v.parse::<f64>().ok()),
        resolved_value(scenario_toml, DURATION_KEY).and_then(|v| v.parse::<f64>().ok()),
    );
    if let (Some(was), Some(now)) = (was, now) {
        if now < was {
            return Err(cannot(format!(
                "time.duration_s = {now} s is shorter than the recorded run's {was} s (checkpoint at t = {} s); a resumed run can only be extended",
                crate::scenario::derived::sig4(c.t)
            )));
        }
    }
    Ok(c)
}

/// The one key a resumed run may change.
pub const DURATION_KEY: &str = "time.duration_s";

/// A key whose value differs between two resolved scenarios.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Difference {
    /// The dotted key (`load.weight_n`).
    pub key: String,
    /// Its value in the first text (`<absent>` when it has none).
    pub was: String,
    /// Its value in the second.
    pub now: String,
}

/// The `key = value` lines of a resolved scenario as (dotted key, value text), tracking the
/// `[section]` and `[[section]]` headers (entries of arrays of tables numbered from 0).
fn resolved_entries(text: &str) -> Vec<(String, String)> {
    let mut section = String::new();
    let mut counts: std::collections::BTreeMap<String, usize> = Default::default();
    let mut out = Vec::new();
    for line in text.lines().map(str::trim) {
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        if let Some(name) = line.strip_prefix("[[").and_then(|l| l.strip_suffix("]]")) {
            let n = counts.entry(name.to_string()).or_default();
            section = format!("{name}[{n}]");
            *n += 1;
        } else if let Some(name) = line.strip_prefix('[').and_then(|l| l.strip_suffix(']')) {
            section = name.to_string();
        } else if let Some((k, v)) = line.split_once('=') {
            let k = k.trim();
            let key = if section.is_empty() {
                k.to_string()
            } else {
                format!("{section}.{k}")
            };
            out.push((key, v.trim().to_string()));
        }
    }
    out
}

/// The value text of `key` in a resolved scenario.
pub fn resolved_value(text: &str, key: &str) -> Option<String> {
    resolved_entries(text)
        .into_iter()
        .find_map(|(k, v)| (k == key).then_some(v))
}

/// The first key (in the checkpoint's order, then keys only `now` has) whose value differs
/// between two resolved scenarios, ignoring `time.duration_s` (a resumed run may be
/// extended).
pub fn scenario_difference(was: &str, now: &str) -> Option<Difference> {
    let keep = |(k, _): &(String, String)| k != DURATION_KEY;
    let a: Vec<_> = resolved_entries(was).into_iter().filter(keep).collect();
    let b: Vec<_> = resolved_entries(now).into_iter().filter(keep).collect();
    let find = |list: &[(String, String)], key: &str| {
        list.iter()
            .find(|(k, _)| k == key)
            .map_or_else(|| "<absent>".to_string(), |(_, v)| v.clone())
    };
    a.iter()
        .chain(&b)
        .map(|(k, _)| Difference {
            key: k.clone(),
            was: find(&a, k),
            now: find(&b, k),
        })
        .find(|d| d.was != d.now)
}

/// Why `dir` cannot be resumed from its checkpoint (`e`: reading it failed), and what to do
/// instead: a directory that is no run, a complete run that kept no checkpoint, or a run
/// that stopped before its first one, are each started again with `chute run`.
pub fn unresumable(dir: &Path, e: &crate::checkpoint::CheckpointError) -> AppError {
    use crate::checkpoint::CheckpointError;
    use crate::output::record::{DirState, Status};
    use crate::output::run_files::{is_run_dir, RESOLVED_SCENARIO, SUMMARY};
    let d = dir.display();
    if !is_run_dir(dir) {
        return AppError::Input(format!(
            "cannot resume `{d}`: it is not a chute run directory (it has no {RESOLVED_SCENARIO}); give the directory `chute run` wrote"
        ));
    }
    if !dir.join(RESOLVED_SCENARIO).is_file() {
        // Only its record: the run ended (a full disk) before it wrote its scenario.
        // From the record alone: this process holds the lock now.
        let how = match crate::output::record::RunRecord::read(dir) {
            Ok(Some(r)) if r.status != Status::Running => DirState::Ended(r.status, r.reason),
            _ => DirState::Abandoned,
        };
        let how = how
            .unfinished()
            .unwrap_or_else(|| "it ended before writing it".into());
        return AppError::Input(format!(
            "cannot resume `{d}`: it has no {RESOLVED_SCENARIO} (the run's scenario) to continue: {how}; run your scenario file again: `chute run SCENARIO --out {d} --force`"
        ));
    }
    let again = format!("chute run {d}/{RESOLVED_SCENARIO} --out {d} --force");
    let missing = matches!(e, CheckpointError::Io { source, .. } if source.kind() == std::io::ErrorKind::NotFound);
    let half_cleared = crate::output::run_files::clearing_interrupted(dir);
    let recorded_complete = matches!(DirState::of(dir), Ok(DirState::Ended(Status::Complete, _)))
        || crate::output::atomic::read_own_string(&dir.join(SUMMARY))
            .ok()
            .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
            .is_some_and(|j| j["complete"] == true);
    // A `--force` killed while it moved the run aside left part of it: not complete.
    let complete = recorded_complete && !half_cleared;
    // A study case run again by hand is no longer its study's: say how to keep it one.
    let case = match dir.join(crate::study::DONE_FILE).is_file() {
        true => " (it is a study case: to keep it one, run its study again with the longer duration instead)",
        false => "",
    };
    let why = match (missing, complete) {
        (true, true) => format!(
            "the run is complete and kept no checkpoint (a run keeps one after it ends only when written with --checkpoint-every S, and only once it reached its first sync point, every {} steps); to run it longer, start it again with a longer duration: `{again} --set time.duration_s=T`{case}",
            crate::runner::SYNC_STEPS
        ),
        (true, false) => format!(
            "it has no checkpoint: the run stopped before writing one (a checkpoint is written on Ctrl-C or SIGTERM, at a failed step, and every --checkpoint-every S); start it again: `{again}`"
        ),
        (false, _) => format!("{e}; start the run again: `{again}`"),
    };
    AppError::Input(format!("cannot resume `{d}`: {why}"))
}

/// A run directory made ready to continue (`chute resume`): held, its checkpoint and recorded
/// scenario checked against each other, and the options to continue it with.
pub struct Resumable {
    /// The scenario to continue: the recorded one, `time.duration_s` possibly extended.
    pub scenario: Scenario,
    /// Options for [`super::run`] (no progress bar: the caller may turn it on).
    pub opts: super::RunOptions,
    /// The `time.duration_s` the run was stopped at (its checkpoint's scenario).
    pub stopped_at: Option<f64>,
    /// The directory has no `run.json` (an older chute's): its input files cannot be checked.
    pub unrecorded: bool,
    /// The directory's lock, held until dropped.
    pub lock: crate::output::lock::RunLock,
}

/// Make run directory `dir` ready to continue with `set` (only `time.duration_s` may change),
/// writing a checkpoint every `every` simulated seconds (`None`: as the run did) and the
/// viewer when `viewer` and the run did. Bad input (exit 2) names what is wrong and what to do.
pub fn prepare(
    dir: &Path,
    set: &[String],
    every: Option<f64>,
    viewer: bool,
) -> Result<Resumable, AppError> {
    use crate::output::run_files::RESOLVED_SCENARIO;
    if !dir.is_dir() {
        return Err(AppError::Input(format!(
            "`{}` is not a directory (give a run directory written by `chute run`)",
            dir.display()
        )));
    }
    for arg in set {
        let (key, _) = crate::scenario::overrides::parse(arg)?;
        if key != super::DURATION_KEY {
            return Err(AppError::Input(format!(
                "`--set {arg}`: a resumed run keeps its recorded scenario; only {} may change (to extend the run). Start a new run with `chute run` to change `{key}`",
                super::DURATION_KEY
            )));
        }
    }
    let lock = crate::output::lock::RunLock::acquire(dir)?;
    let (c, version) =
        crate::checkpoint::Checkpoint::read_versioned(dir).map_err(|e| unresumable(dir, &e))?;
    // The recorded scenario is the checkpoint's own copy; errors point at the directory's.
    let source = dir.join(RESOLVED_SCENARIO);
    // A checkpoint of another run (copied in) would continue that run over this one's files.
    let resolved = crate::output::atomic::read_own_string(&source).map_err(|e| match e.kind() {
        std::io::ErrorKind::NotFound => AppError::Input(format!(
            "cannot resume `{}`: it has a checkpoint but no {RESOLVED_SCENARIO} (the run's scenario): it is not a whole run directory; start the run again with `chute run`",
            dir.display()
        )),
        _ => AppError::io(&source, e),
    })?;
    if let Some(d) = scenario_difference(&resolved, &c.scenario_toml) {
        return Err(AppError::Input(format!(
            "cannot resume `{}`: its checkpoint is not of the run in the directory (`{}` = {} in {RESOLVED_SCENARIO}, {} in the checkpoint); start the run again with `chute run`",
            dir.display(),
            d.key,
            d.was,
            d.now
        )));
    }
    let scenario =
        Scenario::from_str_with_name(&c.scenario_toml, &source.display().to_string(), set)?;
    let stopped_at = Scenario::from_str_with_name(&c.scenario_toml, "", &[])
        .map(|r| r.time.duration_s)
        .ok();
    let recorded = RunRecord::read(dir).map_err(AppError::Input)?;
    if recorded.is_none() && version >= crate::checkpoint::FIRST_WITH_RECORD {
        // Written by a chute that always writes the record beside it: the record was
        // deleted, and nothing could check the run's input files.
        return Err(AppError::Input(format!(
            "cannot resume `{}`: its {} (the record of the run's input files) is missing, although the chute that wrote its checkpoint always writes one; the inputs cannot be checked against the run's: start a new run with `chute run … --force`",
            dir.display(),
            crate::output::run_files::RUN_RECORD
        )));
    }
    let opts = super::RunOptions {
        out_dir: dir.to_path_buf(),
        force: false,
        progress: false,
        checkpoint_every_s: every.or(c.checkpoint_every_s),
        resume: Some(dir.to_path_buf()),
        viewer: viewer && recorded.as_ref().is_none_or(|r| r.viewer),
        case_of: None,
    };
    Ok(Resumable {
        scenario,
        opts,
        stopped_at,
        unrecorded: recorded.is_none(),
        lock,
    })
}

//! `run.json`, a run directory's record: what state the run is in (and why it ended), the
//! input files it read, each by digest, and the options that `chute resume` keeps
//! (docs/outputs.md §run.json, docs/reliability.md §5).
//!
//! It is written atomically when a run starts (`running`) and when it ends, before anything
//! else after an I/O failure (the holder's reserve is freed for it, [`super::lock`]), so a
//! directory always says whether its run is complete, incomplete and why, or failed and why.
//! A directory whose record says `running` while no process holds its lock was left by a
//! process that was killed.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::run_files::{LOCK, RUN_RECORD};

/// The state of a run as its record says.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Status {
    /// A process is writing it (or was, until it was killed: see [`DirState`]).
    Running,
    /// It reached `time.duration_s` or the ground.
    Complete,
    /// It stopped early; `reason` says why (a failed step, a signal).
    Incomplete,
    /// It could not write its outputs; `reason` names the file and the error.
    Failed,
}

/// One input file of a run, by digest.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct InputFile {
    /// The scenario key that names it (`canopy.mesh_file`).
    pub key: String,
    /// The file, as the resolved scenario names it.
    pub path: PathBuf,
    /// `fnv1a64:<16 hex digits>` of its bytes.
    pub digest: String,
}

/// The contents of `run.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunRecord {
    /// Where the run is.
    pub status: Status,
    /// Why it ended early or failed; null otherwise.
    pub reason: Option<String>,
    /// Every file the scenario reads (meshes), by digest.
    pub inputs: Vec<InputFile>,
    /// Whether the run writes `viewer.html` (`--no-viewer` recorded for `chute resume`).
    pub viewer: bool,
    /// The study case it was made for (`study/case`); absent for a run of its own.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub case_of: Option<String>,
}

impl RunRecord {
    /// Write `dir/run.json` atomically.
    pub fn write(&self, dir: &Path) -> std::io::Result<()> {
        let text = serde_json::to_string_pretty(self).map_err(std::io::Error::other)?;
        super::write_atomic(&dir.join(RUN_RECORD), format!("{text}\n").as_bytes())
    }

    /// Read `dir/run.json`: `Ok(None)` when there is none (a run of an older chute), an
    /// error naming the file when it cannot be read.
    pub fn read(dir: &Path) -> Result<Option<RunRecord>, String> {
        let path = dir.join(RUN_RECORD);
        match super::atomic::read_own_string(&path) {
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
            Err(e) => Err(format!("{}: {e}", path.display())),
            Ok(text) => serde_json::from_str(&text)
                .map(Some)
                .map_err(|e| format!("{}: not a chute run record: {e}", path.display())),
        }
    }

    /// The same record in another state.
    pub fn with_status(&self, status: Status, reason: Option<String>) -> RunRecord {
        RunRecord {
            status,
            reason,
            ..self.clone()
        }
    }
}

/// What a run directory is, for the commands that read one.
#[derive(Debug, Clone, PartialEq)]
pub enum DirState {
    /// A process holds its lock now.
    Running,
    /// Its record says the run ended so.
    Ended(Status, Option<String>),
    /// Its record says `running`, but no process holds it: the writer was killed.
    Abandoned,
    /// It has no record (an older chute, or not a run).
    Unrecorded,
}

impl DirState {
    /// The state of `dir`.
    pub fn of(dir: &Path) -> Result<DirState, String> {
        if is_locked(dir) {
            return Ok(DirState::Running);
        }
        // Killed while replacing its earlier run: whatever its record says, part of that
        // run is gone.
        if super::run_files::clearing_interrupted(dir) {
            return Ok(DirState::Abandoned);
        }
        Ok(match RunRecord::read(dir)? {
            None => DirState::Unrecorded,
            Some(r) if r.status == Status::Running => DirState::Abandoned,
            Some(r) => DirState::Ended(r.status, r.reason),
        })
    }

    /// A sentence for a directory that does not hold a finished run, `None` for one that
    /// does (complete, or without a record).
    pub fn unfinished(&self) -> Option<String> {
        match self {
            DirState::Running => Some("a process is still writing it".into()),
            DirState::Ended(Status::Incomplete, r) => Some(format!(
                "the run stopped early: {}",
                r.as_deref().unwrap_or("no reason recorded")
            )),
            DirState::Ended(Status::Failed, r) => Some(format!(
                "the run failed: {}",
                r.as_deref().unwrap_or("no reason recorded")
            )),
            DirState::Abandoned => Some(
                "the run ended without finishing (its process was killed, or the machine stopped)"
                    .into(),
            ),
            DirState::Ended(..) | DirState::Unrecorded => None,
        }
    }
}

/// Whether a process holds `dir`'s lock now (read only: the lock file is not created).
fn is_locked(dir: &Path) -> bool {
    if super::lock::RunLock::held_here(dir) {
        return true;
    }
    let Ok(f) = super::atomic::open_own(&dir.join(LOCK)) else {
        return false;
    };
    match f.try_lock_shared() {
        Ok(()) => false,
        Err(std::fs::TryLockError::WouldBlock) => true,
        Err(std::fs::TryLockError::Error(_)) => false,
    }
}

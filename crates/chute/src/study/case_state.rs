//! Where a case of a study is, as its directory shows: the `status` column of the table.

/// Where a case of a study is, as its directory shows.
#[derive(Debug, Clone, PartialEq)]
pub enum CaseState {
    /// Ran to the end (`done.json` complete, `summary.json` present).
    Complete,
    /// Stopped early; why.
    Incomplete(String),
    /// Could not run, or could not write its outputs; why.
    Failed(String),
    /// A process is running it now.
    Running,
    /// A run of it was killed (its `run.json` says running and no process holds it); what
    /// the directory shows.
    Abandoned(String),
    /// Its directory has no finished run: not run yet (or by a shard whose directory was not
    /// given), or its process was killed; what the directory shows.
    Missing(String),
    /// A file of it cannot be read; the file and the error.
    Unreadable(String),
}

impl CaseState {
    /// The `status` cell.
    pub fn word(&self) -> &'static str {
        match self {
            CaseState::Complete => "complete",
            CaseState::Incomplete(_) => "incomplete",
            CaseState::Failed(_) => "failed",
            CaseState::Running => "running",
            CaseState::Abandoned(_) => "abandoned",
            CaseState::Missing(_) => "missing",
            CaseState::Unreadable(_) => "unreadable",
        }
    }

    /// What happened to it, as a verb phrase after its name.
    pub(super) fn phrase(&self) -> &'static str {
        match self {
            CaseState::Complete => "is complete",
            CaseState::Incomplete(_) => "stopped early",
            CaseState::Failed(_) => "failed",
            CaseState::Running => "is still running",
            CaseState::Abandoned(_) => "was abandoned",
            CaseState::Missing(_) => "is missing",
            CaseState::Unreadable(_) => "cannot be read",
        }
    }

    /// Why the case is not complete (`None` when it is).
    pub fn why(&self) -> Option<String> {
        match self {
            CaseState::Complete => None,
            CaseState::Running => Some("a process is running it now".into()),
            CaseState::Incomplete(m)
            | CaseState::Failed(m)
            | CaseState::Abandoned(m)
            | CaseState::Missing(m)
            | CaseState::Unreadable(m) => Some(m.clone()),
        }
    }
}

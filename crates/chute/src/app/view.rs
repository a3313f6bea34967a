//! `chute view`: a run directory's `viewer.html`, written while holding the directory like any
//! writer, with why its run did not finish when it did not.

use std::path::Path;

use super::AppError;
use crate::output::viewer::ViewerReport;

/// What [`view`] wrote, and why the run there did not finish (when it did not).
#[derive(Debug, Clone)]
pub struct Viewed {
    /// The viewer written.
    pub report: ViewerReport,
    /// Why the directory's run did not finish (`None`: it did, or it cannot tell).
    pub unfinished: Option<String>,
}

/// Write (or rewrite) `dir`'s `viewer.html`, holding `dir`'s lock meanwhile. A directory whose
/// frames cannot be shown is bad input (exit 2) saying why its run did not finish, when known.
pub fn view(dir: &Path) -> Result<Viewed, AppError> {
    use crate::output::run_dir::RunDirError;
    if !dir.is_dir() {
        return Err(AppError::Input(format!(
            "`{}` is not a directory (give a run directory written by `chute run`)",
            dir.display()
        )));
    }
    let unfinished = crate::output::record::DirState::of(dir)
        .ok()
        .and_then(|s| s.unfinished());
    // `view` writes into the directory: it waits its turn like any writer.
    let _lock = crate::output::lock::RunLock::acquire(dir)?;
    let because = |e: String| match &unfinished {
        Some(why) => format!("{e} (its run did not finish: {why})"),
        None => e,
    };
    let report = crate::output::viewer::write_viewer(dir).map_err(|e| match e {
        // A file of the run that is gone (a frame a killed resume was moving) is the run's
        // state, not an I/O failure: said with why the run did not finish.
        RunDirError::Io { path, source } if source.kind() == std::io::ErrorKind::NotFound => {
            AppError::Input(because(format!(
                "`{}`, a file of its run, is missing",
                path.display()
            )))
        }
        RunDirError::Io { path, source } => AppError::Io { path, source },
        e @ RunDirError::Format { .. } => AppError::Input(because(e.to_string())),
    })?;
    Ok(Viewed { report, unfinished })
}

//! `chute view`: write a run directory's `viewer.html`, holding the directory like any writer
//! and saying when the run there did not finish.

use super::ViewArgs;
use crate::app::AppError;

pub(super) fn cmd_view(a: &ViewArgs) -> Result<(), AppError> {
    use crate::output::run_dir::RunDirError;
    if !a.run_dir.is_dir() {
        return Err(AppError::Input(format!(
            "`{}` is not a directory (give a run directory written by `chute run`)",
            a.run_dir.display()
        )));
    }
    let unfinished = crate::output::record::DirState::of(&a.run_dir)
        .ok()
        .and_then(|s| s.unfinished());
    // `view` writes into the directory: it waits its turn like any writer.
    let _lock = crate::output::lock::RunLock::acquire(&a.run_dir)?;
    // A directory that cannot be shown says why its run did not finish, when it knows.
    let because = |e: String| match &unfinished {
        Some(why) => format!("{e} (its run did not finish: {why})"),
        None => e,
    };
    let r = crate::output::viewer::write_viewer(&a.run_dir).map_err(|e| match e {
        RunDirError::Io { path, source } => AppError::Io { path, source },
        e @ RunDirError::Format { .. } => AppError::Input(because(e.to_string())),
    })?;
    crate::out_line!(
        "wrote {} ({} bytes: {} of {} frames, {} triangles)",
        r.path.display(),
        r.bytes,
        r.frames_embedded,
        r.frames_total,
        r.triangles
    );
    if let Some(why) = unfinished {
        crate::err_line!(
            "note: `{}` holds an unfinished run: {why}",
            a.run_dir.display()
        );
    }
    Ok(())
}

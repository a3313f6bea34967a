//! The output directory of a run: made sure of before any simulation (a directory, created
//! when missing, writable, not somebody else's files, not another run's without `--force`),
//! and held by one process at a time ([`crate::output::lock`]). docs/cli.md §`chute run`,
//! docs/reliability.md §5.

use std::path::{Path, PathBuf};

use super::AppError;
use crate::output::lock::{LockError, RunLock};
use crate::output::run_files;

impl From<LockError> for AppError {
    fn from(e: LockError) -> Self {
        match e {
            // A full file system is an I/O failure (exit 1, docs/cli.md), not bad input.
            LockError::Unwritable { dir, source } if is_full(&source) => AppError::Io {
                path: dir,
                source: std::io::Error::new(
                    source.kind(),
                    format!("the directory cannot take a run's files: {source}"),
                ),
            },
            // The others are about the directory the user named: bad input (exit 2).
            e => AppError::Input(e.to_string()),
        }
    }
}

/// Whether `e` says the file system (or the user's quota) is full.
pub fn is_full(e: &std::io::Error) -> bool {
    matches!(e.raw_os_error(), Some(libc::ENOSPC) | Some(libc::EDQUOT))
}

/// A prepared output directory: held by this process until dropped.
#[derive(Debug)]
pub struct Prepared {
    /// The lock (and reserve) on the directory.
    pub lock: RunLock,
    /// The outermost directory created here (`dir` itself or one of its parents), when any
    /// was: removed again, with what lies between, if the run leaves it empty
    /// ([`Prepared::release`]).
    pub created: Option<PathBuf>,
}

impl Prepared {
    /// Release the directory; one created here that holds nothing is removed, so that it
    /// does not block the next attempt.
    pub fn release(self) {
        let dir = self.lock.dir().to_path_buf();
        drop(self.lock);
        if run_files::is_empty(&dir) {
            remove_created(&dir, self.created.as_deref());
        }
    }
}

/// The outermost of `dir` and its ancestors that does not exist yet (what creating `dir`
/// will create).
pub(crate) fn first_missing(dir: &Path) -> Option<PathBuf> {
    // `a/b/.` is `a/b`: its parents are those of `a/b` (components drop the `.`).
    let dir: PathBuf = dir.components().collect();
    let mut missing = None;
    let mut p = Some(dir.as_path());
    while let Some(d) = p.filter(|d| !d.as_os_str().is_empty() && !d.exists()) {
        missing = Some(d.to_path_buf());
        p = d.parent();
    }
    missing
}

/// Remove `dir` and its parents up to `top` (the outermost directory this command created),
/// each only while empty; nothing when `top` is `None`.
pub(crate) fn remove_created(dir: &Path, top: Option<&Path>) {
    let Some(top) = top else { return };
    let dir: PathBuf = dir.components().collect();
    let mut d = Some(dir.as_path());
    while let Some(cur) = d {
        if std::fs::remove_dir(cur).is_err() || cur == top {
            break;
        }
        d = cur.parent();
    }
}

/// Make sure `dir` can take a run's outputs and hold it: a directory (created when missing),
/// not held by another process, writable (the lock's reserve is real data, synced), and, when
/// it has files, an earlier chute run that `allow_existing` (`--force`, a resume) lets this
/// one replace.
pub fn prepare_out_dir(dir: &Path, allow_existing: bool) -> Result<Prepared, AppError> {
    refuse_inside_run(dir)?;
    let created = first_missing(dir);
    ensure_dir(dir)?;
    let lock = match RunLock::acquire(dir) {
        Ok(l) => l,
        Err(e) => {
            remove_created(dir, created.as_deref());
            return Err(e.into());
        }
    };
    let prepared = Prepared { lock, created };
    match check_fresh_dir(dir, allow_existing) {
        Ok(()) => Ok(prepared),
        Err(e) => {
            prepared.release();
            Err(e)
        }
    }
}

/// Create `dir` (and its parents) for a command's outputs (`run`, `study`, `converge`,
/// `collect --out`, `validate --out`): a path that is, or lies under, a file, or that cannot be
/// created or written in (read-only), is bad input (exit 2) saying so, before any work starts.
pub fn ensure_dir(dir: &Path) -> Result<(), AppError> {
    refuse_non_directory(dir)?;
    // `a/b/.` is `a/b` (create_dir_all would make `a` and then fail on `a/b/.`).
    let whole: PathBuf = dir.components().collect();
    std::fs::create_dir_all(&whole).map_err(|e| {
        AppError::Input(format!(
            "cannot create output directory `{}`: {e}",
            dir.display()
        ))
    })?;
    // A file created and removed at once: the only sure test that the directory takes files
    // (permissions, a read-only mount, ACLs).
    // A fresh random name, created exclusively (never through a link) and removed on drop.
    crate::output::atomic::signals_held(|| {
        tempfile::Builder::new()
            .prefix(crate::output::run_files::PROBE_PREFIX)
            .tempfile_in(dir)
            .map(drop)
    })
    .map_err(crate::output::atomic::without_temporary_name)
    .map_err(|e| {
        AppError::Input(format!(
            "output directory `{}` is not writable: {e}",
            dir.display()
        ))
    })
}

/// `dir`, or the first of its ancestors that exists, must be a directory: `--out file` or
/// `--out file/sub` is refused naming the file, not with the operating system's "File exists".
fn refuse_non_directory(dir: &Path) -> Result<(), AppError> {
    let existing = dir.ancestors().find(|a| a.exists() || a.is_symlink());
    match existing {
        Some(a) if !a.is_dir() && !a.as_os_str().is_empty() => {
            let what = if a == dir {
                format!(
                    "output path `{}` exists and is not a directory",
                    dir.display()
                )
            } else {
                format!(
                    "cannot create output directory `{}`: `{}` is not a directory",
                    dir.display(),
                    a.display()
                )
            };
            Err(AppError::Input(format!("{what}; choose another --out DIR")))
        }
        _ => Ok(()),
    }
}

/// A fresh run may write `dir` when it is empty, or, with `force`, when it holds an earlier
/// chute run (whose files are then cleared); never over files chute did not write.
pub fn check_fresh_dir(dir: &Path, force: bool) -> Result<(), AppError> {
    // Before anything is cleared: a run could not write its frames there.
    let frames = dir.join(crate::output::vtk::FRAMES_DIR);
    let kind = std::fs::symlink_metadata(&frames).map(|m| m.file_type());
    if kind.is_ok_and(|t| !t.is_dir() && !t.is_symlink()) {
        return Err(AppError::Input(format!(
            "`{}` is not a directory: a run writes its frames there; move it, or choose another --out DIR",
            frames.display()
        )));
    }
    refuse_directory_named_like_a_run_file(dir)?;
    if run_files::is_empty(dir) {
        return Ok(());
    }
    if !force {
        return Err(AppError::Input(format!(
            "output directory `{}` already exists and is not empty; pass --force to overwrite it, or --out DIR to choose another",
            dir.display()
        )));
    }
    if !run_files::is_run_dir(dir) {
        return Err(not_a_run_dir(dir));
    }
    refuse_users_trash(dir)
}

/// A `.chute.old` of the user's where chute sets an earlier run's files aside is refused
/// before anything in `dir` changes.
pub fn refuse_users_trash(dir: &Path) -> Result<(), AppError> {
    match crate::output::trash::users_trash(dir) {
        Some(trash) => Err(AppError::Input(format!(
            "`{}` holds files chute did not put there, where chute sets an earlier run's files aside; move it",
            trash.display()
        ))),
        None => Ok(()),
    }
}

/// A directory where a run (or a resume) would write one of its data files is refused
/// before anything in `dir` changes.
pub fn refuse_directory_named_like_a_run_file(dir: &Path) -> Result<(), AppError> {
    match run_files::directory_named_like_a_run_file(dir) {
        Some(taken) => Err(AppError::Input(format!(
            "`{}` is a directory: a run writes a file of that name; move it, or choose another --out DIR",
            taken.display()
        ))),
        None => Ok(()),
    }
}

/// `--force` is refused on a non-empty directory chute did not write: it would delete or
/// mix with someone else's files.
pub fn not_a_run_dir(dir: &Path) -> AppError {
    AppError::Input(format!(
        "output directory `{}` is not empty and is not a chute run directory (it has no {}); --force only replaces an earlier chute run: choose another --out DIR",
        dir.display(),
        run_files::RESOLVED_SCENARIO
    ))
}

/// The lock on `dir` for a run, unless this process holds it already (the command that
/// prepared it, or the study running the case).
pub(super) fn hold(dir: &Path) -> Result<Option<RunLock>, AppError> {
    if RunLock::held_here(dir) {
        return Ok(None);
    }
    Ok(Some(RunLock::acquire(dir)?))
}

/// Refuse an output directory that lies inside a run directory (`RUN/frames/x`, `RUN/sub`):
/// its files would sit among a run's, which `--force` and `resume` treat as the run's.
pub fn refuse_inside_run(out: &Path) -> Result<(), AppError> {
    // Through links: `link/x` with `link` pointing into a run is inside that run.
    let abs = resolved(out);
    let inside = abs
        .ancestors()
        .skip(1)
        .find(|a| run_files::run_evidence(a).is_some());
    match inside {
        Some(run) => Err(AppError::Input(format!(
            "`{}` lies inside the run directory `{}`: chute writes each run, study and table in a directory of its own",
            out.display(),
            run.display()
        ))),
        None => Ok(()),
    }
}

/// `path` with its existing part's links resolved (the rest need not exist yet).
fn resolved(path: &Path) -> PathBuf {
    let abs = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
    for base in abs.ancestors() {
        if let Ok(real) = base.canonicalize() {
            let rest = abs.strip_prefix(base).unwrap_or(Path::new(""));
            return real.join(rest);
        }
    }
    abs
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `a1/b1/.` names `a1/b1`: what a command created for it is removed again, `a1` too.
    #[test]
    fn created_directories_are_removed_whatever_the_spelling() {
        let tmp = tempfile::tempdir().unwrap();
        let out = tmp.path().join("a1/b1/.");
        let top = first_missing(&out);
        assert_eq!(top.as_deref(), Some(tmp.path().join("a1").as_path()));
        ensure_dir(&out).unwrap();
        assert!(tmp.path().join("a1/b1").is_dir());
        remove_created(&out, top.as_deref());
        assert!(!tmp.path().join("a1").exists());
    }
}

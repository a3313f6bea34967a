//! Removing an earlier run's files all or nothing: each is first moved (renamed) into a
//! hidden [`TRASH`] directory beside it (the run directory's, or `frames/`'s: a rename never
//! crosses a file system, and `frames/` may be a mount of its own), and only when every one
//! has moved are the trashes emptied. A file that cannot be moved (immutable, on a read-only
//! mount, a mount point) stops the clearing with every file moved so far put back, so the
//! earlier run stays whole and the error names that file (docs/reliability.md §5).

use std::io;
use std::path::{Path, PathBuf};

use super::run_files::TRASH;

/// Files moved aside from a run directory, until [`Trash::empty`] removes them or
/// [`Trash::restore`] puts them back.
#[derive(Debug)]
pub struct Trash {
    dirs: Vec<PathBuf>,
    moved: Vec<(PathBuf, PathBuf)>,
}

impl Trash {
    /// Move every one of `paths` (files of `run_dir` or of its `frames/`) aside, or none: on
    /// the first failure the moved ones go back and the error names the file.
    pub fn take_all(run_dir: &Path, paths: &[PathBuf]) -> io::Result<Trash> {
        // Ones left by a killed process: their files were the earlier run's, already judged
        // removable. Anything else of that name is the user's and stays.
        for dir in [
            run_dir.join(TRASH),
            run_dir.join(super::vtk::FRAMES_DIR).join(TRASH),
        ] {
            if std::fs::symlink_metadata(&dir).is_ok() {
                if !ours(&dir) {
                    return Err(named(
                        &dir,
                        io::Error::other("holds files chute did not put there; move it"),
                    ));
                }
                remove_all(&dir)?;
            }
        }
        let mut trash = Trash {
            dirs: Vec::new(),
            moved: Vec::new(),
        };
        for (i, p) in paths.iter().enumerate() {
            let dir = p.parent().unwrap_or(run_dir).join(TRASH);
            let made = match trash.dirs.contains(&dir) {
                true => Ok(()),
                false => std::fs::create_dir(&dir).map(|()| trash.dirs.push(dir.clone())),
            };
            let to = dir.join(i.to_string());
            if let Err(e) = made.and_then(|()| std::fs::rename(p, &to)) {
                trash.restore();
                return Err(named(p, e));
            }
            trash.moved.push((p.clone(), to));
        }
        Ok(trash)
    }

    /// Put every moved file back where it was (best effort: a file that cannot go back stays
    /// in a trash, which the next clearing of the directory empties).
    pub fn restore(mut self) {
        for (from, to) in self.moved.drain(..).rev() {
            let _ = std::fs::rename(&to, &from);
        }
        for dir in &self.dirs {
            let _ = std::fs::remove_dir(dir);
        }
    }

    /// Remove the moved files for good (best effort: what stays is hidden in a trash, which
    /// the next clearing empties).
    pub fn empty(self) {
        for dir in &self.dirs {
            let _ = remove_all(dir);
        }
    }
}

/// Whether `name` is that of a file [`Trash::take_all`] moved (they are numbered).
pub fn is_moved(name: &std::ffi::OsStr) -> bool {
    name.to_str().is_some_and(|n| n.parse::<usize>().is_ok())
}

/// A `.chute.old` in `run_dir` (or its `frames/`) that chute did not leave: the user's,
/// which clearing the directory would not touch (refused before anything changes).
pub fn users_trash(run_dir: &Path) -> Option<PathBuf> {
    [
        run_dir.join(TRASH),
        run_dir.join(super::vtk::FRAMES_DIR).join(TRASH),
    ]
    .into_iter()
    .find(|d| std::fs::symlink_metadata(d).is_ok() && !ours(d))
}

/// Whether `dir` is a trash chute left: a real directory holding only its numbered files.
fn ours(dir: &Path) -> bool {
    let real = std::fs::symlink_metadata(dir).is_ok_and(|m| m.is_dir());
    real && std::fs::read_dir(dir).is_ok_and(|it| {
        it.filter_map(Result::ok)
            .all(|e| e.file_type().is_ok_and(|t| t.is_file()) && is_moved(&e.file_name()))
    })
}

/// Remove `dir` and its files, not following links.
fn remove_all(dir: &Path) -> io::Result<()> {
    match std::fs::remove_dir_all(dir) {
        Err(e) if e.kind() != io::ErrorKind::NotFound => Err(named(dir, e)),
        _ => Ok(()),
    }
}

/// `e` with the file it concerns.
fn named(path: &Path, e: io::Error) -> io::Error {
    io::Error::new(e.kind(), format!("{}: {e}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn all_or_nothing() {
        let tmp = tempfile::tempdir().unwrap();
        let d = tmp.path();
        std::fs::write(d.join("a"), "a").unwrap();
        std::fs::write(d.join("b"), "b").unwrap();
        // The second path does not exist: nothing is moved, and the error names it.
        let e = Trash::take_all(d, &[d.join("a"), d.join("missing"), d.join("b")]).unwrap_err();
        assert!(e.to_string().contains("missing"), "{e}");
        assert!(d.join("a").is_file() && d.join("b").is_file());
        assert!(!d.join(TRASH).exists());
        let t = Trash::take_all(d, &[d.join("a"), d.join("b")]).unwrap();
        assert!(!d.join("a").exists() && !d.join("b").exists());
        t.restore();
        assert_eq!(std::fs::read_to_string(d.join("b")).unwrap(), "b");
        Trash::take_all(d, &[d.join("a"), d.join("b")])
            .unwrap()
            .empty();
        assert!(!d.join("a").exists() && !d.join(TRASH).exists());
        // A directory of that name that is not chute's is kept, and the clearing refused.
        std::fs::create_dir(d.join(TRASH)).unwrap();
        std::fs::write(d.join(TRASH).join("mine.txt"), "x").unwrap();
        std::fs::write(d.join("c"), "c").unwrap();
        let e = Trash::take_all(d, &[d.join("c")]).unwrap_err();
        assert!(e.to_string().contains("chute did not put there"), "{e}");
        assert!(d.join(TRASH).join("mine.txt").is_file() && d.join("c").is_file());
    }
}

//! The advisory lock of a run directory: one process writes a run directory at a time
//! (docs/reliability.md §5).
//!
//! The lock is the operating system's advisory file lock (`flock` on Unix, through the
//! standard library's `File::try_lock`) on `.chute.lock` inside the directory. The kernel
//! releases it when its holder ends, however it ends, so a lock left by a dead process blocks
//! nobody; the file only describes the last holder (process id, host, command, start), which
//! a second writer quotes when it is refused. The holder removes the file when it is done;
//! a process that locked a file another holder had just removed sees that the path no longer
//! names the file it holds and tries again, so two processes never both hold a directory.
//!
//! While it holds the directory the process also keeps [`RESERVE`], 64 KiB of written and
//! synced data: creating it proves the directory writable before any simulation (an empty
//! file can be created on a full file system, data cannot), and freeing it
//! ([`free_reserve`]) leaves room for the run's record when the file system fills up.

use std::collections::BTreeSet;
use std::fs::{File, OpenOptions};
use std::io::{self, Read, Write};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use super::run_files::{LOCK, RESERVE};

/// Bytes of the reserve.
const RESERVE_BYTES: usize = 64 * 1024;

/// Directories (canonical paths) this process holds.
static HELD: Mutex<BTreeSet<PathBuf>> = Mutex::new(BTreeSet::new());

/// Why a directory could not be locked.
#[derive(Debug, thiserror::Error)]
pub enum LockError {
    /// Another process (or another run of this one) holds it.
    #[error("run directory `{}` is in use by {holder}; wait for it to end, or choose another directory", dir.display())]
    Busy {
        /// The directory.
        dir: PathBuf,
        /// Who holds it, as its lock file describes it.
        holder: String,
        /// The holder holds it only to claim it or write a table ([`Hold::Table`]): it will
        /// let go within seconds.
        brief: bool,
    },
    /// The file system refused the lock itself.
    #[error("cannot lock run directory `{}`: {source} (chute needs a file system with advisory file locks, as local disks and NFS have)", dir.display())]
    Unsupported {
        /// The directory.
        dir: PathBuf,
        /// The operating system's error.
        source: io::Error,
    },
    /// The directory's `frames` is a symbolic link: chute would write and remove frames in
    /// the directory it points to, which is not the run's.
    #[error("`{}` is a symbolic link: chute writes a run's frames only inside its run directory; remove the link (or choose another directory)", dir.join(super::vtk::FRAMES_DIR).display())]
    LinkedFrames {
        /// The run directory.
        dir: PathBuf,
    },
    /// The lock or the reserve cannot be written.
    #[error("output directory `{}` is not writable: {source}", dir.display())]
    Unwritable {
        /// The directory.
        dir: PathBuf,
        /// The operating system's error.
        source: io::Error,
    },
}

/// A held run directory; dropping it frees the reserve, removes the lock file and releases
/// the lock.
#[derive(Debug)]
pub struct RunLock {
    dir: PathBuf,
    key: PathBuf,
    _file: File,
}

/// What a directory is locked for, recorded in its lock file for those who find it busy.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Hold {
    /// A run (or resume, view) writing or reading it, for as long as it lasts.
    Run,
    /// A study, ladder or collect claiming it or writing its table: seconds.
    Table,
}

impl Hold {
    fn word(self) -> &'static str {
        match self {
            Hold::Run => "run",
            Hold::Table => "table",
        }
    }
}

impl RunLock {
    /// Lock the existing directory `dir` for a run ([`RunLock::acquire_for`]).
    pub fn acquire(dir: &Path) -> Result<RunLock, LockError> {
        Self::acquire_for(dir, Hold::Run)
    }

    /// Lock the existing directory `dir` for this process, describe the holder (and what it
    /// holds the directory for) in the lock file and set the reserve aside.
    pub fn acquire_for(dir: &Path, hold: Hold) -> Result<RunLock, LockError> {
        let unwritable = |source| LockError::Unwritable {
            dir: dir.to_path_buf(),
            source,
        };
        let key = dir.canonicalize().map_err(unwritable)?;
        let frames = dir.join(super::vtk::FRAMES_DIR);
        if std::fs::symlink_metadata(&frames).is_ok_and(|m| m.file_type().is_symlink()) {
            return Err(LockError::LinkedFrames {
                dir: dir.to_path_buf(),
            });
        }
        let mut held = HELD.lock().unwrap_or_else(|e| e.into_inner());
        if held.contains(&key) {
            return Err(LockError::Busy {
                dir: dir.to_path_buf(),
                holder: "another run of this process".into(),
                brief: false,
            });
        }
        let mut file = lock_file(dir)?;
        if let Err(e) = describe_holder(&mut file, hold).and_then(|()| write_reserve(dir)) {
            // Nothing of ours stays behind (a full disk: the caller then removes the
            // directory it created).
            free_reserve(dir);
            let _ = std::fs::remove_file(dir.join(LOCK));
            return Err(unwritable(e));
        }
        held.insert(key.clone());
        Ok(RunLock {
            dir: dir.to_path_buf(),
            key,
            _file: file,
        })
    }

    /// Whether this process holds `dir`.
    pub fn held_here(dir: &Path) -> bool {
        let Ok(key) = dir.canonicalize() else {
            return false;
        };
        HELD.lock()
            .unwrap_or_else(|e| e.into_inner())
            .contains(&key)
    }

    /// The directory held.
    pub fn dir(&self) -> &Path {
        &self.dir
    }
}

impl Drop for RunLock {
    fn drop(&mut self) {
        free_reserve(&self.dir);
        // Removed while still locked: a process that opened it meanwhile finds, once it
        // holds it, that the path names no file or another one, and tries again.
        let _ = std::fs::remove_file(self.dir.join(LOCK));
        HELD.lock()
            .unwrap_or_else(|e| e.into_inner())
            .remove(&self.key);
    }
}

/// Free the reserve of a directory this process holds, so that the files written after an
/// I/O failure (the run's record, a study case's marker) find room.
pub fn free_reserve(dir: &Path) {
    // Only chute's own file: a link or anything else of that name is the user's.
    let path = dir.join(RESERVE);
    if std::fs::symlink_metadata(&path).is_ok_and(|m| m.file_type().is_file()) {
        let _ = std::fs::remove_file(path);
    }
}

/// Open and lock `dir/.chute.lock`, retrying while the path is replaced under us.
fn lock_file(dir: &Path) -> Result<File, LockError> {
    let path = dir.join(LOCK);
    let unwritable = |source| LockError::Unwritable {
        dir: dir.to_path_buf(),
        source,
    };
    for _ in 0..8 {
        let mut file = no_follow(OpenOptions::new().read(true).write(true).create(true))
            .truncate(false)
            .open(&path)
            .map_err(|e| not_followed(&path, e))
            .map_err(|e| named(&path, e))
            .map_err(unwritable)?;
        let meta = file.metadata().map_err(unwritable)?;
        if !meta.is_file() {
            return Err(unwritable(io::Error::other(format!(
                "{} is not a plain file (a FIFO, a device?): chute keeps its lock there",
                path.display()
            ))));
        }
        if shared(&meta) {
            // A hard link to another directory's lock (a `cp -al` copy): `flock` is per
            // file, so this directory gets a file of its own instead of that one's lock.
            drop(file);
            std::fs::remove_file(&path).map_err(unwritable)?;
            continue;
        }
        match try_lock_briefly(&file) {
            Ok(()) => {}
            Err(std::fs::TryLockError::WouldBlock) => {
                let (holder, brief) = read_holder(&mut file);
                return Err(LockError::Busy {
                    dir: dir.to_path_buf(),
                    holder,
                    brief,
                });
            }
            Err(std::fs::TryLockError::Error(source)) => {
                return Err(LockError::Unsupported {
                    dir: dir.to_path_buf(),
                    source,
                })
            }
        }
        if names_same_file(&file, &path) {
            return Ok(file);
        }
    }
    Err(LockError::Busy {
        dir: dir.to_path_buf(),
        holder: "other processes taking and releasing it repeatedly".into(),
        brief: false,
    })
}

/// Lock `file`, trying again for a moment while it is held: a reader asking whether the
/// directory is in use (`collect`, `view`: a shared lock taken and dropped at once) must not
/// make a writer starting at that instant give up.
fn try_lock_briefly(file: &File) -> Result<(), std::fs::TryLockError> {
    for _ in 0..10 {
        match file.try_lock() {
            Err(std::fs::TryLockError::WouldBlock) => {
                std::thread::sleep(std::time::Duration::from_millis(10))
            }
            other => return other,
        }
    }
    file.try_lock()
}

/// Whether the file has other names (hard links) besides this one.
#[cfg(unix)]
fn shared(meta: &std::fs::Metadata) -> bool {
    use std::os::unix::fs::MetadataExt;
    meta.nlink() > 1
}

#[cfg(not(unix))]
fn shared(_meta: &std::fs::Metadata) -> bool {
    false
}

#[cfg(unix)]
fn names_same_file(file: &File, path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (file.metadata(), std::fs::metadata(path)) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

#[cfg(not(unix))]
fn names_same_file(_file: &File, path: &Path) -> bool {
    path.exists()
}

/// Replace the lock file's text by this process's description.
fn describe_holder(file: &mut File, hold: Hold) -> io::Result<()> {
    use std::io::Seek;
    let started = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    let command: Vec<String> = std::env::args_os()
        .map(|a| a.to_string_lossy().into_owned())
        .collect();
    let text = format!(
        "pid={}\nhost={}\nstarted={started}\ncommand={}\nholds={}\n",
        std::process::id(),
        hostname(),
        command.join(" "),
        hold.word()
    );
    file.set_len(0)?;
    file.seek(io::SeekFrom::Start(0))?;
    file.write_all(text.as_bytes())?;
    file.flush()
}

/// "process 1234 on host `h` (`chute run …`, started 12 s ago)", from a lock file's text,
/// and whether it holds the directory only for a table ([`Hold::Table`]).
fn read_holder(file: &mut File) -> (String, bool) {
    let mut text = String::new();
    let _ = file.read_to_string(&mut text);
    let field = |k: &str| {
        text.lines()
            .find_map(|l| l.strip_prefix(k)?.strip_prefix('='))
            .map(str::to_string)
    };
    let brief = field("holds").as_deref() == Some(Hold::Table.word());
    let Some(pid) = field("pid") else {
        return (
            "another process (it has not described itself yet)".into(),
            false,
        );
    };
    let mut s = format!("process {pid}");
    if let Some(h) = field("host") {
        s.push_str(&format!(" on host `{h}`"));
    }
    let now = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    let ago = field("started")
        .and_then(|t| t.parse::<u64>().ok())
        .map(|t| now.saturating_sub(t));
    match (field("command"), ago) {
        (Some(c), Some(a)) => s.push_str(&format!(" (`{c}`, started {a} s ago)")),
        (Some(c), None) => s.push_str(&format!(" (`{c}`)")),
        _ => {}
    }
    (s, brief)
}

fn hostname() -> String {
    std::fs::read_to_string("/proc/sys/kernel/hostname")
        .ok()
        .or_else(|| std::env::var("HOSTNAME").ok())
        .map(|h| h.trim().to_string())
        .filter(|h| !h.is_empty())
        .unwrap_or_else(|| "unknown".into())
}

/// Write the reserve: real bytes, synced, so that a full file system refuses it.
/// `opts` that refuse to open a symbolic link (a link named like chute's file would make it
/// write wherever the link points) or to block on a FIFO.
fn no_follow(opts: &mut OpenOptions) -> &mut OpenOptions {
    use std::os::unix::fs::OpenOptionsExt;
    opts.custom_flags(libc::O_NOFOLLOW | libc::O_NONBLOCK)
}

/// The error of opening `path` without following links, said plainly when it is a link.
fn not_followed(path: &Path, e: io::Error) -> io::Error {
    if e.raw_os_error() == Some(libc::ELOOP) {
        io::Error::other(format!(
            "{} is a symbolic link: chute writes its own file there, never through a link",
            path.display()
        ))
    } else {
        e
    }
}

/// `e` with the path it concerns, unless it already says it (a directory named `.chute.lock`
/// fails with the bare "Is a directory").
fn named(path: &Path, e: io::Error) -> io::Error {
    match e.raw_os_error() {
        Some(_) => io::Error::new(e.kind(), format!("{}: {e}", path.display())),
        None => e,
    }
}

fn write_reserve(dir: &Path) -> io::Result<()> {
    let path = dir.join(RESERVE);
    if std::fs::symlink_metadata(&path).is_ok_and(|m| !m.file_type().is_file()) {
        return Err(io::Error::other(format!(
            "{} is not a plain file: chute writes its own file there, never through a link",
            path.display()
        )));
    }
    // A new file, never one truncated in place: it may be a hard link to another
    // directory's reserve.
    if std::fs::symlink_metadata(&path).is_ok() {
        std::fs::remove_file(&path)?;
    }
    let result = (|| {
        let mut f = no_follow(OpenOptions::new().write(true).create_new(true))
            .open(&path)
            .map_err(|e| not_followed(&path, e))?;
        f.write_all(&[0u8; RESERVE_BYTES])?;
        f.sync_all()
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&path);
    }
    result
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_directory_is_held_once_and_released_on_drop() {
        let dir = tempfile::tempdir().unwrap();
        let lock = RunLock::acquire(dir.path()).unwrap();
        assert!(RunLock::held_here(dir.path()));
        assert!(dir.path().join(RESERVE).is_file() && dir.path().join(LOCK).is_file());
        let again = RunLock::acquire(dir.path()).unwrap_err();
        assert!(matches!(again, LockError::Busy { .. }), "{again}");
        drop(lock);
        assert!(!RunLock::held_here(dir.path()));
        assert!(!dir.path().join(RESERVE).exists() && !dir.path().join(LOCK).exists());
        drop(RunLock::acquire(dir.path()).unwrap());
    }

    #[test]
    fn the_holder_is_described_by_pid_host_and_command() {
        let dir = tempfile::tempdir().unwrap();
        let lock = RunLock::acquire(dir.path()).unwrap();
        let mut f = File::open(dir.path().join(LOCK)).unwrap();
        let (who, brief) = read_holder(&mut f);
        assert!(
            who.starts_with(&format!("process {} on host `", std::process::id())),
            "{who}"
        );
        assert!(
            who.contains("started 0 s ago") || who.contains("s ago"),
            "{who}"
        );
        assert!(!brief, "a run holds its directory for its whole length");
        drop(lock);
        // A study's claim or table says it is brief, whatever its command line.
        let _table = RunLock::acquire_for(dir.path(), Hold::Table).unwrap();
        let mut f = File::open(dir.path().join(LOCK)).unwrap();
        assert!(read_holder(&mut f).1, "a table's hold is brief");
    }
}

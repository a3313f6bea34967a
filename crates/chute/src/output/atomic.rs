//! Atomic whole-file writes: readers see either the old file or the new one, never a mix.

use std::fs;
use std::io::{self, Write};
use std::path::{Path, PathBuf};

/// A file that could not be written (or read), and why: the error names the file, not only
/// its directory.
#[derive(Debug, thiserror::Error)]
#[error("{}: {source}", path.display())]
pub struct FileError {
    /// The file.
    pub path: PathBuf,
    /// The cause.
    #[source]
    pub source: io::Error,
}

/// `map_err` from an `io::Error` to a [`FileError`] naming `path`.
pub fn at(path: &Path) -> impl FnOnce(io::Error) -> FileError + '_ {
    move |source| FileError {
        path: path.to_path_buf(),
        source,
    }
}

/// Write `bytes` to `path` atomically.
///
/// The bytes go to a temporary file in the same directory (a rename is only atomic within one
/// file system), which is fsynced before being renamed over `path`; the directory is then
/// fsynced so the rename itself survives a power loss. On error the temporary file is removed.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> io::Result<()> {
    signals_held(|| write_atomic_now(path, bytes))
}

/// The stop signals a user sends (Ctrl-C, SIGTERM, SIGHUP).
#[cfg(unix)]
const STOP_SIGNALS: [libc::c_int; 3] = [libc::SIGINT, libc::SIGTERM, libc::SIGHUP];

/// Run `f` with the stop signals held back on this thread, then let them through: a command
/// without a handler (`collect`, `view`) that is stopped while it writes a file ends after
/// the rename instead of leaving the temporary behind. Writes are short, so a stop is late
/// by milliseconds at most.
pub fn signals_held<T>(f: impl FnOnce() -> T) -> T {
    #[cfg(unix)]
    // SAFETY: sigset_t is plain data initialised by sigemptyset; pthread_sigmask changes only
    // this thread's mask, and the old mask is restored below.
    unsafe {
        let mut set: libc::sigset_t = std::mem::zeroed();
        libc::sigemptyset(&mut set);
        for s in STOP_SIGNALS {
            libc::sigaddset(&mut set, s);
        }
        let mut old: libc::sigset_t = std::mem::zeroed();
        libc::pthread_sigmask(libc::SIG_BLOCK, &set, &mut old);
        let r = f();
        libc::pthread_sigmask(libc::SIG_SETMASK, &old, std::ptr::null_mut());
        r
    }
    #[cfg(not(unix))]
    f()
}

fn write_atomic_now(path: &Path, bytes: &[u8]) -> io::Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let name = path
        .file_name()
        .ok_or_else(|| io::Error::new(io::ErrorKind::InvalidInput, "path has no file name"))?;
    let mut tmp = temporary_beside(dir, name)?;
    tmp.as_file_mut().write_all(bytes)?;
    tmp.as_file().sync_all()?;
    tmp.persist(path).map_err(|e| e.error)?;
    sync_dir(dir);
    Ok(())
}

/// Best-effort fsync of a directory entry list; not every platform/file system supports
/// opening a directory, and the data itself is already durable, so failures are ignored.
fn sync_dir(dir: &Path) {
    if let Ok(d) = fs::File::open(dir) {
        let _ = d.sync_all();
    }
}

/// Append `bytes`, whole rows, to `file` (opened for appending), whose length is `*len`.
///
/// A write that fails part-way (a full file system) has put part of a row at the end; the
/// file is then cut back to `*len` (which needs no space), so a streamed CSV only ever ends
/// in a whole row, whatever happens. On success `*len` grows by the bytes written.
pub fn append_whole(file: &mut fs::File, len: &mut u64, bytes: &[u8]) -> io::Result<()> {
    match file.write_all(bytes).and_then(|()| file.flush()) {
        Ok(()) => {
            *len += bytes.len() as u64;
            Ok(())
        }
        Err(e) => {
            let _ = file.set_len(*len);
            Err(e)
        }
    }
}

/// Open a file chute wrote (a run's record, table, summary, checkpoint) for reading, refusing
/// anything but a plain file: a FIFO or a device named like one of chute's files would
/// otherwise make `view`, `collect` or a study wait forever on its first read.
pub fn open_own(path: &Path) -> io::Result<fs::File> {
    #[cfg(unix)]
    let file = {
        use std::os::unix::fs::OpenOptionsExt;
        fs::OpenOptions::new()
            .read(true)
            .custom_flags(libc::O_NONBLOCK)
            .open(path)?
    };
    #[cfg(not(unix))]
    let file = fs::File::open(path)?;
    if !file.metadata()?.is_file() {
        // The caller names the file.
        return Err(io::Error::other(
            "not a plain file (a FIFO, a device, a directory?): chute only reads its own files there",
        ));
    }
    Ok(file)
}

/// A sentence naming `path` (`what`: "study file") when something other than a plain file
/// is there: an input chute reads whole, where a FIFO would be waited on and a device read
/// forever. `None` for a plain file, or nothing at all (its reader says so).
pub fn not_plain(path: &Path, what: &str) -> Option<String> {
    std::fs::metadata(path)
        .is_ok_and(|m| !m.is_file())
        .then(|| {
            format!(
                "{what} `{}` is not a plain file (a FIFO, a device, a directory?)",
                path.display()
            )
        })
}

/// The bytes of a file chute wrote ([`open_own`]).
pub fn read_own(path: &Path) -> io::Result<Vec<u8>> {
    use std::io::Read;
    let mut bytes = Vec::new();
    open_own(path)?.read_to_end(&mut bytes)?;
    Ok(bytes)
}

/// The text of a file chute wrote ([`open_own`]); not UTF-8 is `InvalidData`.
pub fn read_own_string(path: &Path) -> io::Result<String> {
    String::from_utf8(read_own(path)?).map_err(|e| io::Error::new(io::ErrorKind::InvalidData, e))
}

/// Open `path`, which holds `rows` whole rows written by chute, for [`append_whole`]: with
/// its length, after cutting off a partial last row a killed writer may have left.
pub fn open_rows(path: &Path) -> io::Result<(fs::File, u64)> {
    let text = read_own(path)?;
    let whole = text.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
    let file = fs::OpenOptions::new().append(true).open(path)?;
    if whole < text.len() {
        file.set_len(whole as u64)?;
    }
    Ok((file, whole as u64))
}

/// A new temporary file in `dir` for a file named `name`: `.<name>.XXXXXX.tmp`, a random name
/// created exclusively (never through a link), removed when dropped, with the permissions of
/// a plain file under the umask.
pub fn temporary_beside(dir: &Path, name: &std::ffi::OsStr) -> io::Result<tempfile::NamedTempFile> {
    // A dot prefix hides the temporary from globs such as `frames/*.vtu`.
    let mut prefix = std::ffi::OsString::from(".");
    prefix.push(name);
    prefix.push(".");
    let mut builder = tempfile::Builder::new();
    builder.prefix(&prefix).suffix(".tmp");
    // tempfile creates 0600 files; ask for 0666 so the result honours the umask like any
    // other file the user creates (0644 with the usual 022).
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(fs::Permissions::from_mode(0o666));
    }
    // tempfile appends the temporary's random name to its errors; the caller names the
    // file it was writing, which is what a user can act on.
    builder.tempfile_in(dir).map_err(without_temporary_name)
}

/// `e` without the random temporary's name that tempfile appends (` at path "…"`).
pub(crate) fn without_temporary_name(e: io::Error) -> io::Error {
    let text = e.to_string();
    let plain = text.split(" at path ").next().unwrap_or(&text).to_string();
    io::Error::new(e.kind(), plain)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The mask of this thread has `sig` blocked.
    fn blocked(sig: libc::c_int) -> bool {
        // SAFETY: reading this thread's mask into a zeroed sigset_t.
        unsafe {
            let mut cur: libc::sigset_t = std::mem::zeroed();
            libc::pthread_sigmask(libc::SIG_BLOCK, std::ptr::null(), &mut cur);
            libc::sigismember(&cur, sig) == 1
        }
    }

    #[test]
    fn stop_signals_are_held_while_a_file_is_written_and_only_then() {
        assert!(STOP_SIGNALS.iter().all(|&s| !blocked(s)));
        let during = signals_held(|| STOP_SIGNALS.map(blocked));
        assert_eq!(during, [true; 3]);
        assert!(STOP_SIGNALS.iter().all(|&s| !blocked(s)));
    }
}

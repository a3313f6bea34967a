//! The files a run writes, by name: how a chute run directory is recognised, and how an
//! earlier run is cleared for `--force` so that a directory never holds parts of two runs
//! while files chute did not write are left alone (docs/outputs.md §Output directory).

use std::io;
use std::path::Path;

use super::vtk::{FRAMES_DIR, PVD_NAME};

/// The resolved scenario: written first by every run, so it marks a chute run directory.
pub const RESOLVED_SCENARIO: &str = "scenario.resolved.toml";

/// Files of fixed name a run (or a study case) writes at the top of its directory.
const FIXED: [&str; 10] = [
    RESOLVED_SCENARIO,
    "summary.json",
    "timeseries.csv",
    PVD_NAME,
    "velocity.png",
    "height.png",
    "shape.png",
    super::viewer::VIEWER_HTML,
    crate::checkpoint::FILE_NAME,
    "done.json",
];

/// A temporary of an atomic write (`.<name>.XXXXXX.tmp`, `.<name>.<pid>.tmp.png`), left
/// behind only by a crash.
fn is_temporary(name: &str) -> bool {
    name.starts_with('.') && (name.ends_with(".tmp") || name.ends_with(".tmp.png"))
}

/// Whether `name`, an entry at the top of a run directory, is a file chute writes there.
pub fn is_run_file(name: &str) -> bool {
    FIXED.contains(&name)
        || (name.starts_with("snapshot_") && name.ends_with("s.png"))
        || is_temporary(name)
}

/// Whether `name`, an entry of `frames/`, is a frame chute writes.
fn is_frame_file(name: &str) -> bool {
    let index = name
        .strip_prefix("frame_")
        .and_then(|n| n.strip_suffix(".vtu"));
    index.is_some_and(|i| !i.is_empty() && i.bytes().all(|b| b.is_ascii_digit()))
        || is_temporary(name)
}

/// Whether `dir` holds a chute run (its resolved scenario).
pub fn is_run_dir(dir: &Path) -> bool {
    dir.join(RESOLVED_SCENARIO).is_file()
}

/// Remove every file an earlier run wrote into `dir` (and `frames/` once it is empty);
/// anything else is kept.
pub fn clear(dir: &Path) -> io::Result<()> {
    for entry in std::fs::read_dir(dir)? {
        let entry = entry?;
        let name = entry.file_name();
        let Some(name) = name.to_str() else { continue };
        if entry.file_type()?.is_file() && is_run_file(name) {
            remove(&entry.path())?;
        }
    }
    let frames = dir.join(FRAMES_DIR);
    if frames.is_dir() {
        for entry in std::fs::read_dir(&frames)? {
            let entry = entry?;
            let name = entry.file_name();
            if entry.file_type()?.is_file() && name.to_str().is_some_and(is_frame_file) {
                remove(&entry.path())?;
            }
        }
        // Kept when it holds something chute did not write.
        let _ = std::fs::remove_dir(&frames);
    }
    Ok(())
}

fn remove(path: &Path) -> io::Result<()> {
    match std::fs::remove_file(path) {
        Err(e) if e.kind() != io::ErrorKind::NotFound => Err(e),
        _ => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_of_run_files() {
        for n in [
            "summary.json",
            "snapshot_2.5s.png",
            ".summary.json.a1B2c3.tmp",
            ".velocity.png.77.tmp.png",
        ] {
            assert!(is_run_file(n), "{n}");
        }
        for n in ["notes.txt", "summary.json.bak", "snapshot.png", "frames"] {
            assert!(!is_run_file(n), "{n}");
        }
        assert!(is_frame_file("frame_000012.vtu"));
        assert!(!is_frame_file("frame_.vtu") && !is_frame_file("mine.vtu"));
    }
}

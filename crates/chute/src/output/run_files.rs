//! The one registry of the files a run writes into its directory: how a chute run directory
//! is recognised, how an earlier run is cleared (for `--force`, a study's re-run, or a
//! fresh start over a directory chute wrote) so that a directory never holds parts of two
//! runs, and what docs/outputs.md §Output directory lists (a test compares the two). Files
//! chute did not write are left alone.

use std::io;
use std::path::Path;

use super::vtk::{FRAMES_DIR, PVD_NAME};

/// The resolved scenario: written first by every run, so it marks a chute run directory.
pub const RESOLVED_SCENARIO: &str = "scenario.resolved.toml";
/// The run's record: its status, input files by digest and the options a resume keeps
/// ([`super::record`]).
pub const RUN_RECORD: &str = "run.json";
/// The summary of a run that ended.
pub const SUMMARY: &str = "summary.json";
/// The streamed time series.
pub const TIMESERIES: &str = "timeseries.csv";
/// A study case's marker (docs/cli.md §study).
pub const DONE: &str = "done.json";
/// The advisory lock held by the process writing the directory ([`super::lock`]).
pub const LOCK: &str = ".chute.lock";
/// Space set aside while a run writes, freed so that its record can still be written when
/// the file system fills up ([`super::lock`]).
pub const RESERVE: &str = ".chute.reserve";
/// Where an earlier run's files wait while they are removed, all or none
/// ([`super::trash::Trash`]); only there while a process clears the directory.
pub const TRASH: &str = ".chute.old";

/// What a registered file is to the code that clears a directory.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Role {
    /// An output or record of one run: cleared before another run writes the directory.
    Run,
    /// Belongs to the process holding the directory, not to a run: never cleared by it.
    Holder,
}

/// One entry of the registry: how its name looks and what it is.
#[derive(Debug, Clone, Copy)]
pub struct RunFile {
    /// The name as docs/outputs.md writes it (`snapshot_<t>s.png`, `frames/frame_NNNNNN.vtu`).
    pub shown: &'static str,
    /// Matches a name at the top of the directory, or (`in_frames`) inside `frames/`.
    pattern: Pattern,
    /// Inside `frames/` rather than at the top.
    pub in_frames: bool,
    /// What clearing does with it.
    pub role: Role,
}

#[derive(Debug, Clone, Copy)]
enum Pattern {
    Exact(&'static str),
    /// `prefix`, a number, `suffix`.
    Numbered {
        prefix: &'static str,
        suffix: &'static str,
        number: Number,
    },
}

/// The number in a numbered file's name.
#[derive(Debug, Clone, Copy)]
enum Number {
    /// Digits only (`000012`).
    Index,
    /// Digits with at most one decimal point between digits (`2.5`, `10`): a time as
    /// [`super::plots::snapshot_file_name`] writes it, so that a user's
    /// `snapshot_of_the_bags.png` is not taken for one.
    Decimal,
}

impl Number {
    fn matches(self, m: &str) -> bool {
        let digits = |d: &str| !d.is_empty() && d.bytes().all(|b| b.is_ascii_digit());
        match (self, m.split_once('.')) {
            (Number::Index, _) => digits(m),
            (Number::Decimal, None) => digits(m),
            (Number::Decimal, Some((a, b))) => digits(a) && digits(b),
        }
    }
}

const fn exact(name: &'static str) -> RunFile {
    RunFile {
        shown: name,
        pattern: Pattern::Exact(name),
        in_frames: false,
        role: Role::Run,
    }
}

/// A run's numbered files `<prefix><number><suffix>`, shown in docs as `shown`.
const fn numbered(
    shown: &'static str,
    (prefix, suffix): (&'static str, &'static str),
    number: Number,
    in_frames: bool,
) -> RunFile {
    RunFile {
        shown,
        pattern: Pattern::Numbered {
            prefix,
            suffix,
            number,
        },
        in_frames,
        role: Role::Run,
    }
}

/// Every file a run (or a study case, or the process writing it) puts into its directory.
pub const RUN_FILES: &[RunFile] = &[
    exact(RESOLVED_SCENARIO),
    exact(RUN_RECORD),
    exact(TIMESERIES),
    exact(SUMMARY),
    exact(PVD_NAME),
    numbered(
        "frames/frame_NNNNNN.vtu",
        ("frame_", ".vtu"),
        Number::Index,
        true,
    ),
    exact(super::plots::VELOCITY_PNG),
    exact(super::plots::HEIGHT_PNG),
    exact(super::plots::SHAPE_PNG),
    numbered(
        "snapshot_<t>s.png",
        ("snapshot_", "s.png"),
        Number::Decimal,
        false,
    ),
    exact(super::plots::WRINKLES_PNG),
    exact(super::viewer::VIEWER_HTML),
    exact(super::control_files::LINES_CSV),
    exact(super::control_files::TRACK_CSV),
    exact(super::control_files::TRACK_PNG),
    exact(crate::checkpoint::FILE_NAME),
    exact(DONE),
    RunFile {
        role: Role::Holder,
        ..exact(LOCK)
    },
    RunFile {
        role: Role::Holder,
        ..exact(RESERVE)
    },
    RunFile {
        role: Role::Holder,
        ..exact(TRASH)
    },
];

impl RunFile {
    fn matches(&self, name: &str) -> bool {
        match self.pattern {
            Pattern::Exact(n) => n == name,
            Pattern::Numbered {
                prefix,
                suffix,
                number,
            } => name
                .strip_prefix(prefix)
                .and_then(|n| n.strip_suffix(suffix))
                .is_some_and(|m| number.matches(m)),
        }
    }
}

/// A temporary of an atomic write of a run file (`.<name>.XXXXXX.tmp`,
/// `.<name>.<pid>.tmp.png`, `<name>` one of the registry's), left behind only by a process
/// that was killed while writing. A user's `.notes.tmp` is not one.
fn is_temporary_of(name: &str, in_frames: bool) -> bool {
    let Some(inner) = name.strip_prefix('.').and_then(|n| {
        n.strip_suffix(".tmp.png")
            .or_else(|| n.strip_suffix(".tmp"))
    }) else {
        return false;
    };
    inner.rsplit_once('.').is_some_and(|(base, tag)| {
        !tag.is_empty()
            && tag.bytes().all(|b| b.is_ascii_alphanumeric())
            && RUN_FILES
                .iter()
                .any(|f| f.in_frames == in_frames && f.role != Role::Holder && f.matches(base))
    })
}

/// A temporary of a run file at the top of a run directory (`.<name>.XXXXXX.tmp` of a
/// registered `<name>`).
pub fn is_temporary(name: &str) -> bool {
    is_temporary_of(name, false)
}

/// A temporary of a frame in `frames/`.
fn is_frame_temporary(name: &str) -> bool {
    is_temporary_of(name, true)
}

/// The registry entry of `name`, an entry at the top of a run directory.
fn top_entry(name: &str) -> Option<&'static RunFile> {
    RUN_FILES.iter().find(|f| !f.in_frames && f.matches(name))
}

/// Whether `name`, an entry at the top of a run directory, is a file chute writes there
/// (temporaries included).
pub fn is_run_file(name: &str) -> bool {
    top_entry(name).is_some() || is_temporary(name)
}

/// Whether `name`, an entry of `frames/`, is a frame chute writes (or its temporary).
fn is_frame_file(name: &str) -> bool {
    RUN_FILES.iter().any(|f| f.in_frames && f.matches(name)) || is_frame_temporary(name)
}

/// The first directory in `dir` (or its `frames/`) named like a file a run writes there
/// (`canopy.pvd/`, `frames/frame_000001.vtu/`): the run could not write that file, so it is
/// refused before an earlier run is cleared (not for a picture or the viewer, whose failure
/// is a warning).
pub fn directory_named_like_a_run_file(dir: &Path) -> Option<std::path::PathBuf> {
    let dirs = |d: &Path, named: &dyn Fn(&str) -> bool| {
        std::fs::read_dir(d)
            .ok()?
            .filter_map(Result::ok)
            .find_map(|e| {
                let is_dir = e.file_type().is_ok_and(|t| t.is_dir());
                let name = e.file_name();
                (is_dir && name.to_str().is_some_and(named)).then(|| e.path())
            })
    };
    // Pictures and the viewer are optional: one that cannot be written is a warning.
    let optional = |n: &str| n.ends_with(".png") || n.ends_with(".html");
    let top = |n: &str| top_entry(n).is_some_and(|f| f.role != Role::Holder) && !optional(n);
    let frames = dir.join(FRAMES_DIR);
    let frame = |n: &str| RUN_FILES.iter().any(|f| f.in_frames && f.matches(n));
    dirs(dir, &top).or_else(|| {
        std::fs::symlink_metadata(&frames)
            .is_ok_and(|m| m.is_dir())
            .then(|| dirs(&frames, &frame))
            .flatten()
    })
}

/// Why the finished run in `dir` is not whole, or `None`: an entry named like a file a run
/// or study case writes (or `frames`, or a frame in it) that is a symbolic link — a run's
/// files are its own, never another run's seen through a link —, a file every finished run
/// has that is missing or holds no row (with `pulls`, the line-pull files too), or a frame
/// `canopy.pvd` lists that is not a plain file of its own `frames`. Such a
/// directory holds no finished run to skip or to table.
pub fn run_not_whole(dir: &Path, pulls: bool) -> Option<String> {
    let linked = |d: &Path, ours: &dyn Fn(&str) -> bool| {
        std::fs::read_dir(d)
            .ok()?
            .filter_map(Result::ok)
            .find_map(|e| {
                let name = e.file_name().to_str()?.to_string();
                (ours(&name) && e.file_type().is_ok_and(|t| t.is_symlink())).then(|| e.path())
            })
    };
    let top = |n: &str| {
        n == FRAMES_DIR || n == DONE || top_entry(n).is_some_and(|f| f.role != Role::Holder)
    };
    let frame = |n: &str| RUN_FILES.iter().any(|f| f.in_frames && f.matches(n));
    let link = linked(dir, &top).or_else(|| linked(&dir.join(FRAMES_DIR), &frame));
    if let Some(p) = link {
        return Some(format!(
            "`{}` is a symbolic link: a run's files are its own, not another's through a link",
            p.display()
        ));
    }
    let plain = |p: &Path| std::fs::symlink_metadata(p).is_ok_and(|m| m.is_file());
    if let Some(f) = [RESOLVED_SCENARIO, TIMESERIES, SUMMARY]
        .into_iter()
        .find(|f| !plain(&dir.join(f)))
    {
        return Some(format!("its run's {f} is missing"));
    }
    // Frames on disk are listed in `canopy.pvd`, and every frame it lists is a file of this
    // run's own `frames/` (not `../other/frames/…`).
    let frames = dir.join(FRAMES_DIR);
    let has_frames = std::fs::read_dir(&frames)
        .is_ok_and(|mut d| d.any(|e| e.is_ok_and(|e| e.file_name().to_str().is_some_and(frame))));
    if has_frames && !plain(&dir.join(PVD_NAME)) {
        return Some(format!("its run's {PVD_NAME} is missing"));
    }
    let listed = match plain(&dir.join(PVD_NAME)) {
        true => match super::run_dir::read_pvd(dir) {
            Ok(l) => l,
            Err(e) => return Some(format!("its run's {PVD_NAME} cannot be read: {e}")),
        },
        false => Vec::new(),
    };
    let own = |p: &Path| p.parent() == Some(frames.as_path()) && plain(p);
    if let Some((_, p)) = listed.iter().find(|(_, p)| !own(p)) {
        return Some(format!(
            "`{}`, a frame its run listed in {PVD_NAME}, is missing or not in its own {FRAMES_DIR}",
            p.display()
        ));
    }
    // A run whose lines are pulled (`pulls`) writes their files.
    let control = [
        super::control_files::LINES_CSV,
        super::control_files::TRACK_CSV,
    ];
    let mut rows = std::iter::once(TIMESERIES).chain(control.into_iter().filter(|_| pulls));
    rows.find(|f| !has_a_row(&dir.join(f)))
        .map(|f| format!("its run's {f} is missing or holds no row"))
}

/// Whether the CSV file `path` holds a whole row besides its header.
fn has_a_row(path: &Path) -> bool {
    use std::io::BufRead;
    let Ok(file) = super::atomic::open_own(path) else {
        return false;
    };
    let mut lines = std::io::BufReader::new(file).lines();
    let header = lines.next().is_some_and(|h| h.is_ok());
    header && lines.next().is_some_and(|r| r.is_ok_and(|r| !r.is_empty()))
}

/// The prefix of the file a command creates and removes at once to test that a directory
/// takes files ([`crate::app::ensure_dir`]).
pub const PROBE_PREFIX: &str = ".chute-probe.";

/// Whether `name` belongs to the process holding the directory rather than to a run; also
/// another process's passing probe, so that a command starting beside another is not
/// refused for a file that is gone a moment later.
pub fn is_holder_file(name: &str) -> bool {
    name.starts_with(PROBE_PREFIX) || top_entry(name).is_some_and(|f| f.role == Role::Holder)
}

/// The file (or trash) by which `dir` holds a single run, if it does: [`is_run_dir`]'s, or a
/// run's `summary.json`. Nothing else may be written into such a directory, or under it.
pub fn run_evidence(dir: &Path) -> Option<&'static str> {
    if dir.join(RESOLVED_SCENARIO).is_file() {
        return Some(RESOLVED_SCENARIO);
    }
    if dir.join(SUMMARY).is_file() {
        return Some(SUMMARY);
    }
    if super::record::RunRecord::read(dir).is_ok_and(|r| r.is_some()) {
        return Some(RUN_RECORD);
    }
    clearing_interrupted(dir).then_some(TRASH)
}

/// Whether `dir` holds a chute run: its resolved scenario, or a record that is chute's
/// (a `run.json` of another tool does not make a directory chute's to replace).
pub fn is_run_dir(dir: &Path) -> bool {
    dir.join(RESOLVED_SCENARIO).is_file()
        || super::record::RunRecord::read(dir).is_ok_and(|r| r.is_some())
        // A clearing that was killed: what is left is chute's.
        || clearing_interrupted(dir)
}

/// Whether a process replacing the run in `dir` (`--force`) was killed while it moved the
/// earlier run's files aside: `dir`'s trash holds some of them (they are numbered).
pub fn clearing_interrupted(dir: &Path) -> bool {
    std::fs::read_dir(dir.join(TRASH))
        .is_ok_and(|mut it| it.any(|e| e.is_ok_and(|e| super::trash::is_moved(&e.file_name()))))
}

/// Whether `dir` has nothing in it but the files of the process holding it (or does not
/// exist).
pub fn is_empty(dir: &Path) -> bool {
    std::fs::read_dir(dir).map_or(true, |it| {
        it.filter_map(Result::ok)
            .all(|e| e.file_name().to_str().is_some_and(is_holder_file))
    })
}

/// An earlier run's files moved aside by [`clear`]: removed for good by [`Cleared::commit`]
/// once the new run has its record, or put back by [`Cleared::restore`] when it cannot get
/// one, so that a run that cannot start leaves the earlier one as it was.
#[derive(Debug)]
pub struct Cleared {
    trash: super::trash::Trash,
    /// `frames/`, removed on commit when it is then empty.
    frames: Option<std::path::PathBuf>,
}

impl Cleared {
    /// Remove the earlier run's files (and `frames/` when nothing else is in it).
    pub fn commit(self) {
        self.trash.empty();
        if let Some(frames) = self.frames {
            // Kept when it holds something chute did not write.
            let _ = std::fs::remove_dir(&frames);
        }
    }

    /// Put the earlier run's files back.
    pub fn restore(self) {
        self.trash.restore();
    }
}

/// Move aside every file an earlier run wrote into `dir`, all or none; anything else, and
/// the holder's lock and reserve, is kept.
pub fn clear(dir: &Path) -> io::Result<Cleared> {
    let mut gone = matching(dir, |n| is_run_file(n) && !is_holder_file(n))?;
    let frames = dir.join(FRAMES_DIR);
    // Not through a symbolic link: the directory it points to is not the run's.
    let frames_dir = std::fs::symlink_metadata(&frames).is_ok_and(|m| m.is_dir());
    if frames_dir {
        gone.extend(matching(&frames, is_frame_file)?);
    }
    // The record first (a clearing killed part-way never leaves one saying `complete` over
    // a run missing files) and the resolved scenario last (what is left stays a chute run
    // directory, which `--force` may clear again).
    let rank = |p: &std::path::PathBuf| match p.file_name().and_then(|n| n.to_str()) {
        Some(RUN_RECORD) => 0,
        Some(RESOLVED_SCENARIO) => 2,
        _ => 1,
    };
    gone.sort_by_key(rank);
    // All or nothing: an earlier run stays whole when one of its files cannot be removed.
    Ok(Cleared {
        trash: super::trash::Trash::take_all(dir, &gone)?,
        frames: frames_dir.then_some(frames),
    })
}

/// The plain files of `dir` whose names satisfy `gone`.
fn matching(dir: &Path, gone: impl Fn(&str) -> bool) -> io::Result<Vec<std::path::PathBuf>> {
    let mut out = Vec::new();
    for entry in std::fs::read_dir(dir)? {
        let entry = entry?;
        let name = entry.file_name();
        let Some(name) = name.to_str() else { continue };
        if entry.file_type()?.is_file() && gone(name) {
            out.push(entry.path());
        }
    }
    Ok(out)
}

/// Remove the run files at the top of `dir` except `keep` (and the holder's): what a run
/// that has just created `keep` clears of an earlier one (frames are the frame writer's).
pub fn clear_top_except(dir: &Path, keep: &[&str]) -> io::Result<()> {
    remove_matching(dir, |n| {
        is_run_file(n) && !is_holder_file(n) && !keep.contains(&n)
    })
}

/// Remove the temporaries a killed writer left in `dir` and `frames/` (a resume's first
/// step: nothing else of the run is touched).
pub fn remove_temporaries(dir: &Path) -> io::Result<()> {
    clear_where(dir, is_temporary, is_frame_temporary)
}

/// Remove the files at the top of `dir` whose names satisfy `top` and those of `frames/`
/// that satisfy `frame`, then `frames/` itself when that left it empty.
fn clear_where(
    dir: &Path,
    top: impl Fn(&str) -> bool,
    frame: impl Fn(&str) -> bool,
) -> io::Result<()> {
    remove_matching(dir, top)?;
    let frames = dir.join(FRAMES_DIR);
    // Not through a symbolic link: the directory it points to is not the run's.
    if std::fs::symlink_metadata(&frames).is_ok_and(|m| m.is_dir()) {
        remove_matching(&frames, frame)?;
        // Kept when it holds something chute did not write.
        let _ = std::fs::remove_dir(&frames);
    }
    Ok(())
}

/// Remove the plain files of `dir` whose names satisfy `gone`.
fn remove_matching(dir: &Path, gone: impl Fn(&str) -> bool) -> io::Result<()> {
    for entry in std::fs::read_dir(dir)? {
        let entry = entry?;
        let name = entry.file_name();
        let Some(name) = name.to_str() else { continue };
        if entry.file_type()?.is_file() && gone(name) {
            remove(&entry.path())?;
        }
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
            "run.json",
            "lines.csv",
            "track.csv",
            "track.png",
            "wrinkles.png",
            "snapshot_2.5s.png",
            "snapshot_10s.png",
            ".summary.json.a1B2c3.tmp",
            ".velocity.png.77.tmp.png",
            ".chute.lock",
        ] {
            assert!(is_run_file(n), "{n}");
        }
        for n in [
            "notes.txt",
            "summary.json.bak",
            "snapshot.png",
            // A user's pictures that merely start and end like a snapshot's name.
            "snapshot_of_the_deployment_bags.png",
            "snapshot_v2s.png",
            "snapshot_1.2.3s.png",
            "snapshot_.5s.png",
            "frames",
            ".notes.tmp",
            ".x.y.tmp",
            ".my.file.tmp.png",
            ".data.csv.backup.tmp",
            ".chute.lock.abc123.tmp",
        ] {
            assert!(!is_run_file(n), "{n}");
        }
        assert!(is_frame_file(".frame_000012.vtu.Zq81xY.tmp"));
        assert!(!is_frame_file(".a.tmp") && !is_frame_file(".summary.json.a1B2c3.tmp"));
        assert!(is_frame_file("frame_000012.vtu"));
        assert!(!is_frame_file("frame_.vtu") && !is_frame_file("mine.vtu"));
        assert!(is_holder_file(LOCK) && is_holder_file(RESERVE));
        assert!(!is_holder_file(SUMMARY));
        // Another command's passing probe leaves a directory empty for a run (the two
        // started together would otherwise both be refused).
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join(format!("{PROBE_PREFIX}x1y2z3")), "").unwrap();
        assert!(is_holder_file(".chute-probe.x1y2z3") && is_empty(dir.path()));
    }

    /// `frames` as a symbolic link to a directory of the user's: clearing the run leaves that
    /// directory's frames alone (they are not the run's), and user files named like hidden
    /// temporaries survive too.
    #[cfg(unix)]
    #[test]
    fn clear_does_not_follow_a_linked_frames_directory() {
        let tmp = tempfile::tempdir().unwrap();
        let (run, other) = (tmp.path().join("run"), tmp.path().join("other"));
        std::fs::create_dir_all(&run).unwrap();
        std::fs::create_dir_all(&other).unwrap();
        for f in ["frame_000001.vtu", ".frame_000002.vtu.Ab12Cd.tmp"] {
            std::fs::write(other.join(f), "x").unwrap();
        }
        std::os::unix::fs::symlink(&other, run.join(FRAMES_DIR)).unwrap();
        for f in [SUMMARY, ".notes.tmp", ".summary.json.a1B2c3.tmp"] {
            std::fs::write(run.join(f), "x").unwrap();
        }
        clear(&run).unwrap();
        assert!(other.join("frame_000001.vtu").exists());
        assert!(other.join(".frame_000002.vtu.Ab12Cd.tmp").exists());
        assert!(run.join(".notes.tmp").exists());
        assert!(!run.join(SUMMARY).exists() && !run.join(".summary.json.a1B2c3.tmp").exists());
    }
}

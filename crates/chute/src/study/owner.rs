//! The study an output directory belongs to. A study's first run there records it in
//! `OUT/.chute-study.json` (its name, and its study file, or for a study made in code its base
//! scenario), created exclusively so that two studies started together cannot both take the
//! directory; every later study (or ladder) is refused there unless it is the same one, even
//! before any case has finished or after the first was killed. Directories of an older chute,
//! without the file, are judged by their cases' records (`done.json`).

use std::io::Write;
use std::path::Path;

use super::table::read_json;
use super::{Study, DONE_FILE};
use crate::app::AppError;

/// The owner record in a study's output directory.
pub(crate) const OWNER_FILE: &str = ".chute-study.json";

/// The file that identifies `study` (its study file, or for a study made in code its base
/// scenario) and the key under which it is recorded.
fn file_of(study: &Study) -> (&Path, &'static str) {
    match &study.file {
        Some(f) => (f, "study_file"),
        None => (&study.base, "base"),
    }
}

/// The digest of everything `study` runs under the study-wide overrides `set`: the inputs
/// digest of each of its cases (the scenario with the overrides, and every file it reads, by
/// bytes), so that a copy of the study file whose relative `base` or mesh resolves to other
/// files is another study.
pub(super) fn content_digest(study: &Study, set: &[String]) -> Option<String> {
    let mut parts = Vec::with_capacity(study.cases.len());
    for c in &study.cases {
        let s = study.scenario(c, set).ok()?;
        parts.push(format!("{}={}", c.name, super::inputs::digest(&s).ok()?));
    }
    Some(super::inputs::bytes_digest(parts.join("\n").as_bytes()))
}

/// The study `out` would be claimed for: its name, its file's path and the digest of what it
/// runs ([`content_digest`]).
fn identity(study: &Study, digest: Option<&str>) -> serde_json::Value {
    let (file, key) = file_of(study);
    // The file itself, not the name it was given: `/dev/stdin` (or any link) resolves to
    // whatever it names at this moment, so a later run through it must not match by name.
    // A pipe has no path; its record never matches one ([`another`]).
    let path = file.canonicalize().ok().filter(|p| p.is_file());
    let shown = path.map_or_else(
        || format!("{PIPE}{}", file.display()),
        |p| p.display().to_string(),
    );
    let names: Vec<&str> = study.cases.iter().map(|c| c.name.as_str()).collect();
    serde_json::json!({
        "study": study.name, key: shown, "digest": digest, "case_names": names,
    })
}

/// Prefix of a recorded study file that was not a file (a pipe): never the same path.
const PIPE: &str = "(not a file) ";

/// Whether a recorded identity is another study than `study`: another name, or the same name
/// from another file. The same study is the same path (through links: the file edited in
/// place), or the same content (a moved or copied project that runs the same inputs); a
/// recorded file that is gone, without a digest (an older record), is taken as this one.
fn another(recorded: &serde_json::Value, study: &Study, content: Option<&str>) -> bool {
    if recorded["study"].as_str() != Some(study.name.as_str()) {
        return true;
    }
    // A study records its study file, a ladder (a study made in code) only its base: a record
    // of the other kind is another study; one of neither (an older record) says nothing.
    let a_study = |r: &serde_json::Value| match (r["study_file"].is_string(), r["base"].is_string())
    {
        (true, _) => Some(true),
        (false, true) => Some(false),
        _ => None,
    };
    if a_study(recorded).is_some_and(|theirs| theirs != study.file.is_some()) {
        return true;
    }
    let (mine, key) = file_of(study);
    let Some(theirs) = recorded[key].as_str() else {
        return false;
    };
    // Recorded paths are resolved already (an older record's through links); a device path
    // (`/dev/stdin`) resolved again would follow to whatever this run reads.
    let device = ["/dev/", "/proc/", PIPE]
        .iter()
        .any(|p| theirs.starts_with(p));
    let same_path = !device
        && mine.canonicalize().is_ok_and(|b| {
            b.is_file()
                && (Path::new(theirs) == b
                    || Path::new(theirs).canonicalize().is_ok_and(|a| a == b))
        });
    let digest = recorded["digest"].as_str();
    let same_content = digest.is_some_and(|d| content == Some(d));
    let gone_unknown = digest.is_none() && Path::new(theirs).canonicalize().is_err();
    !(same_path || same_content || gone_unknown)
}

fn refused(out: &Path, recorded: &serde_json::Value, by: &Path, study: &Study) -> AppError {
    let other = recorded["study"].as_str().unwrap_or_default();
    let file = recorded["study_file"]
        .as_str()
        .or(recorded["base"].as_str());
    let from = file.map_or(String::new(), |f| format!(" of `{f}`"));
    AppError::Input(format!(
        "`{}` holds the cases of study `{other}`{from} (`{}`), which study `{}` would replace with its table: choose another --out{}",
        out.display(),
        by.display(),
        study.name,
        match by.ends_with(OWNER_FILE) && maybe_moved(recorded, study) {
            true => format!(" (or, if it is the same study moved and then edited or given other study-wide --set, remove `{OWNER_FILE}` there)"),
            false => String::new(),
        }
    ))
}

/// Whether the recorded study could be `study` moved: of the same kind (a study file, or a
/// ladder's base) and its recorded file no longer there. Otherwise removing the record only
/// leads to the cases' records refusing the study again.
fn maybe_moved(recorded: &serde_json::Value, study: &Study) -> bool {
    let (_, key) = file_of(study);
    recorded[key]
        .as_str()
        .is_some_and(|f| !f.starts_with(PIPE) && !Path::new(f).exists())
}

/// Refuse to run `study` into `out` when `out` holds cases another study recorded (their
/// `done.json`): this one would replace those of the same names and the directory's table.
pub(crate) fn refuse_other_studys_out(out: &Path, study: &Study) -> Result<(), AppError> {
    // A directory with its owner record is judged by it ([`claim`]), which knows the study
    // file's bytes too; the cases' records are for directories of an older chute.
    let Ok(entries) = std::fs::read_dir(out) else {
        return Ok(());
    };
    if std::fs::symlink_metadata(out.join(OWNER_FILE)).is_ok() {
        return Ok(());
    }
    for e in entries.filter_map(Result::ok) {
        let done = e.path().join(DONE_FILE);
        let Some(d) = read_json(&done) else { continue };
        let recipe = &d["recipe"];
        let recorded = serde_json::json!({
            "study": d["study"],
            "study_file": recipe["study_file"],
            "base": recipe["base"],
        });
        if another(&recorded, study, None) {
            return Err(refused(out, &recorded, &done, study));
        }
    }
    Ok(())
}

/// Take `out` (which exists) for `study`, or refuse it (exit 2) when another study holds it.
/// `study.content_digest` is what it runs ([`content_digest`]).
pub(crate) fn claim(out: &Path, study: &Study) -> Result<(), AppError> {
    let path = out.join(OWNER_FILE);
    remove_stale_temporaries(out);
    let content = study.content_digest.clone();
    let now = identity(study, content.as_deref());
    let mine = format!("{now:#}\n");
    match create_exclusive(out, &path, mine.as_bytes()) {
        Ok(()) => return Ok(()),
        Err(e) if e.kind() != std::io::ErrorKind::AlreadyExists => {
            // A full disk, say: the cases then say for themselves why they cannot run.
            crate::err_line!(
                "warning: {}: {e}: the directory is not recorded as this study's",
                path.display()
            );
            return Ok(());
        }
        Err(_) => {}
    }
    // Another process may be writing it this instant (the fallback without hard links).
    for _ in 0..20 {
        if let Some(recorded) = read_json(&path) {
            if another(&recorded, study, content.as_deref()) {
                return Err(refused(out, &recorded, &path, study));
            }
            // The same study, maybe moved or edited since: the record follows it, so that a
            // later move or edit is still recognised.
            if recorded != now {
                let _ = crate::output::atomic::write_atomic(&path, format!("{now:#}\n").as_bytes());
            }
            return Ok(());
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    Err(AppError::Input(format!(
        "`{}` cannot be read as the record of the study that owns `{}`; remove it if no study runs there",
        path.display(),
        out.display()
    )))
}

/// Mark as changed the rows of `rows` (cases of studies made in code, `recipes`) that are
/// no level of the ladder that ran last in any of `dirs` (its owner record's case names): a
/// directory reused by a second ladder of one scenario keeps the first one's levels, whose
/// inputs each still match their own recipe.
pub(crate) fn mark_earlier_ladders(
    dirs: &[std::path::PathBuf],
    rows: &mut [super::table::Row],
    recipes: &std::collections::BTreeMap<String, serde_json::Value>,
) {
    let levels: Vec<(&std::path::PathBuf, Vec<String>)> = dirs
        .iter()
        .filter_map(|d| {
            let r = read_json(&d.join(OWNER_FILE))?;
            let names = r["base"]
                .is_string()
                .then(|| r["case_names"].as_array().cloned())??;
            Some((
                d,
                names
                    .iter()
                    .filter_map(|n| Some(n.as_str()?.to_string()))
                    .collect(),
            ))
        })
        .collect();
    if levels.is_empty() {
        return;
    }
    for row in rows.iter_mut() {
        let ladder = recipes
            .get(&row.case)
            .is_some_and(|r| r["study_file"].is_null());
        if ladder && !levels.iter().any(|(_, names)| names.contains(&row.case)) {
            let (dir, names) = &levels[0];
            row.inputs = super::inputs::InputsState::Changed(format!(
                "a level of an earlier ladder: the ladder that ran last in `{}` has levels {}",
                dir.display(),
                names.join(", ")
            ));
        }
    }
}

/// Create `path` with `bytes`, failing with `AlreadyExists` when it exists: written beside
/// it and hard-linked into place (atomic and exclusive), or created exclusively and written
/// where the file system has no hard links.
fn create_exclusive(dir: &Path, path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    // The temporary: a fresh random name created exclusively (never through a link), removed
    // when dropped, so no other process can open it while it is linked into place.
    let written = crate::output::atomic::signals_held(|| {
        let mut tmp = crate::output::atomic::temporary_beside(dir, OWNER_FILE.as_ref())?;
        tmp.write_all(bytes)?;
        tmp.as_file().sync_all()?;
        std::fs::hard_link(tmp.path(), path)
    });
    match written {
        Err(e) if e.kind() != std::io::ErrorKind::AlreadyExists => {
            let mut f = std::fs::OpenOptions::new()
                .write(true)
                .create_new(true)
                .open(path)?;
            f.write_all(bytes).inspect_err(|_| {
                let _ = std::fs::remove_file(path);
            })
        }
        r => r,
    }
}

/// Remove temporaries of the owner record, the table or a ladder's reports that a killed
/// study, ladder or collect left (each is written within milliseconds: one older than a minute
/// is no live writer's).
fn remove_stale_temporaries(out: &Path) {
    // The owner record's, and the tables' and reports' (written under the directory's lock,
    // in milliseconds: one a minute old is a killed writer's).
    let names = [OWNER_FILE, "study.csv", "study.md"]
        .into_iter()
        .chain(crate::converge::REPORT_FILES);
    let prefixes: Vec<String> = names.map(|n| format!(".{n}.")).collect();
    let Ok(entries) = std::fs::read_dir(out) else {
        return;
    };
    for e in entries.filter_map(Result::ok) {
        let name = e.file_name();
        let ours = name
            .to_str()
            .is_some_and(|n| prefixes.iter().any(|p| n.starts_with(p)) && n.ends_with(".tmp"));
        let old = e
            .metadata()
            .ok()
            .and_then(|m| m.modified().ok())
            .is_some_and(|t| {
                t.elapsed()
                    .is_ok_and(|age| age > std::time::Duration::from_secs(60))
            });
        if ours && old && e.file_type().is_ok_and(|t| t.is_file()) {
            let _ = std::fs::remove_file(e.path());
        }
    }
}

/// Hold `out`'s run lock (as `chute run` holds the directory it writes) while a study claims it
/// or writes its table, so that a run started at the same moment takes the directory wholly
/// before (the study then sees its files) or after (the run then sees the study's record), and
/// a table is gathered and written by one process at a time. Studies, ladders and collect
/// hold it only while they claim or gather, so a lock busy with one of those is tried again
/// for up to [`HOLD_WAIT`]; a run holds it for its whole length, and the study is refused. `None` when this process holds it already.
///
/// `after` completes the message of a stop during the wait (what has, or has not, happened).
pub(crate) fn hold_out(
    out: &Path,
    after: &str,
) -> Result<Option<crate::output::lock::RunLock>, AppError> {
    use crate::output::lock::{Hold, LockError, RunLock};
    if RunLock::held_here(out) {
        return Ok(None);
    }
    let start = std::time::Instant::now();
    let mut said = false;
    loop {
        match RunLock::acquire_for(out, Hold::Table) {
            Ok(l) => {
                // The reserve proves a run's directory writable; a table needs the room.
                crate::output::lock::free_reserve(out);
                remove_stale_temporaries(out);
                return Ok(Some(l));
            }
            // Another study, ladder or collect gathering its table: wait for it.
            Err(LockError::Busy {
                ref holder,
                brief: true,
                ..
            }) if start.elapsed() < HOLD_WAIT => {
                if !std::mem::replace(&mut said, true) {
                    crate::err_line!(
                        "waiting for `{}`: {holder} is writing its table",
                        out.display()
                    );
                }
                // A stop (Ctrl-C, SIGTERM) ends the wait: nothing has started yet.
                if crate::runner::STOP.load(std::sync::atomic::Ordering::SeqCst) {
                    return Err(AppError::RunFailed(format!(
                        "stopped while waiting for `{}`; {after}",
                        out.display()
                    )));
                }
                std::thread::sleep(std::time::Duration::from_millis(20));
            }
            // Waited the longest a table takes: say so (the holder may be stuck).
            Err(LockError::Busy {
                holder,
                brief: true,
                ..
            }) => {
                return Err(AppError::Input(format!(
                    "`{}` is still held by {holder} after {} s of waiting, longer than any table takes: wait for it to end (or end it), or choose another directory",
                    out.display(),
                    HOLD_WAIT.as_secs()
                )))
            }
            // A full disk: no reserve fits. The cases then say for themselves why they
            // cannot run, and the table why it cannot be written.
            Err(e @ LockError::Unwritable { .. }) if unwritable_for_room(&e) => {
                crate::err_line!("warning: {e}: the directory is not locked");
                return Ok(None);
            }
            Err(e) => return Err(e.into()),
        }
    }
}

/// Whether a lock that could not be written failed for want of room (not, say, a link
/// planted at the lock's name, which is refused as for any writer).
fn unwritable_for_room(e: &crate::output::lock::LockError) -> bool {
    use crate::output::lock::LockError;
    matches!(e, LockError::Unwritable { source, .. } if crate::app::out_dir::is_full(source))
}

/// How long [`hold_out`] waits for a study's output directory held by another study's,
/// ladder's or collect's table: a gather reads every case's record, seconds for thousands.
const HOLD_WAIT: std::time::Duration = std::time::Duration::from_secs(600);

/// Refuse `out` when a file there carries the name of a table chute writes (`study.csv`,
/// `study.md`; with `reports`, a ladder's `convergence.*` too) but is not one: a user's file,
/// which chute would remove and replace. Chute's own are told by their whole first line (or,
/// for the JSON report, its top-level keys); an empty file (a write cut short) is taken as
/// chute's.
pub(crate) fn refuse_users_tables(out: &Path, reports: bool) -> Result<(), AppError> {
    use crate::converge::report::{MD_MARK, WRITTEN_BY};
    let first_line = |text: &str| text.lines().next().unwrap_or_default().to_string();
    let ours = |name: &str, bytes: &[u8]| {
        let text = String::from_utf8_lossy(bytes);
        let text = text.as_ref();
        match name {
            // chute writes its tables and reports whole (a temporary renamed into place), so
            // an empty one is a user's.
            _ if text.is_empty() => false,
            "study.csv" => {
                let l = first_line(text);
                l.starts_with("case,") && l.ends_with(",status,complete,inputs")
            }
            "study.md" => {
                let l = first_line(text);
                l.starts_with("| case |") && l.ends_with("| status | complete | inputs |")
            }
            // The reports carry chute's mark (`converge::report::WRITTEN_BY`).
            "convergence.json" => serde_json::from_str::<serde_json::Value>(text)
                .is_ok_and(|j| j["written_by"] == WRITTEN_BY),
            "convergence.md" => text.starts_with("# Convergence of `") && text.ends_with(MD_MARK),
            "convergence.png" => crate::output::plots::written_by_chute(bytes, name),
            // A dispersion's files: its per-sample table and its marked footprint.
            "dispersion.csv" => first_line(text).starts_with("sample,"),
            "footprint.png" => crate::output::plots::written_by_chute(bytes, name),
            "footprint.json" => serde_json::from_str::<serde_json::Value>(text)
                .is_ok_and(|j| j["written_by"] == super::dispersion_out::WRITTEN_BY),
            "footprint.html" => text.ends_with(&super::dispersion_out::html_mark()),
            _ => false,
        }
    };
    let mut names = vec!["study.csv", "study.md"];
    names.extend([
        super::dispersion_out::DISPERSION_CSV,
        super::dispersion_out::FOOTPRINT_JSON,
        super::dispersion_out::FOOTPRINT_PNG,
        super::dispersion_out::FOOTPRINT_HTML,
    ]);
    if reports {
        names.extend(crate::converge::REPORT_FILES);
    }
    for name in names {
        let p = out.join(name);
        let Ok(m) = std::fs::symlink_metadata(&p) else {
            continue;
        };
        // A picture that cannot be written is a warning (a directory there, say); only a
        // file of the user's would be replaced.
        if name == "convergence.png" && !m.is_file() {
            continue;
        }
        // Chute's tables are small; a report is read whole (at most a few MB).
        let bytes = match m.is_file() && m.len() < (16 << 20) {
            true => std::fs::read(&p).map_err(|e| AppError::io(&p, e))?,
            false => b"\0".to_vec(),
        };
        if !m.is_file() || !ours(name, &bytes) {
            return Err(AppError::Input(format!(
                "`{}` is not a table or report chute wrote, and chute would replace it: move it, or choose another --out",
                p.display()
            )));
        }
    }
    Ok(())
}

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

/// The study `out` would be claimed for: its name, and the file that identifies it.
fn identity(study: &Study) -> serde_json::Value {
    let text = |p: &Path| p.display().to_string();
    match &study.file {
        Some(f) => serde_json::json!({ "study": study.name, "study_file": text(f) }),
        None => serde_json::json!({ "study": study.name, "base": text(&study.base) }),
    }
}

/// Whether a recorded identity is another study than `study`: another name, or the same name
/// from another file (both files still there and not the same: a link or a moved copy is
/// the same study).
fn another(recorded: &serde_json::Value, study: &Study) -> bool {
    let (mine, key) = match &study.file {
        Some(f) => (f.clone(), "study_file"),
        None => (study.base.clone(), "base"),
    };
    let other_file = |r: &str| {
        let (a, b) = (Path::new(r).canonicalize(), mine.canonicalize());
        matches!((a, b), (Ok(a), Ok(b)) if a != b)
    };
    recorded["study"].as_str() != Some(study.name.as_str())
        || recorded[key].as_str().is_some_and(other_file)
}

fn refused(out: &Path, recorded: &serde_json::Value, by: &Path, study: &Study) -> AppError {
    let other = recorded["study"].as_str().unwrap_or_default();
    let file = recorded["study_file"]
        .as_str()
        .or(recorded["base"].as_str());
    let from = file.map_or(String::new(), |f| format!(" of `{f}`"));
    AppError::Input(format!(
        "`{}` holds the cases of study `{other}`{from} (`{}`), which study `{}` would replace with its table: choose another --out",
        out.display(),
        by.display(),
        study.name
    ))
}

/// Refuse to run `study` into `out` when `out` holds cases another study recorded (their
/// `done.json`): this one would replace those of the same names and the directory's table.
pub(crate) fn refuse_other_studys_out(out: &Path, study: &Study) -> Result<(), AppError> {
    let Ok(entries) = std::fs::read_dir(out) else {
        return Ok(());
    };
    let key = if study.file.is_some() {
        "study_file"
    } else {
        "base"
    };
    for e in entries.filter_map(Result::ok) {
        let done = e.path().join(DONE_FILE);
        let Some(d) = read_json(&done) else { continue };
        let recorded = serde_json::json!({ "study": d["study"], key: d["recipe"][key] });
        if another(&recorded, study) {
            return Err(refused(out, &recorded, &done, study));
        }
    }
    Ok(())
}

/// Take `out` (which exists) for `study`, or refuse it (exit 2) when another study holds it.
pub(crate) fn claim(out: &Path, study: &Study) -> Result<(), AppError> {
    let path = out.join(OWNER_FILE);
    let mine = format!("{:#}\n", identity(study));
    match create_exclusive(out, &path, mine.as_bytes()) {
        Ok(()) => return Ok(()),
        Err(e) if e.kind() != std::io::ErrorKind::AlreadyExists => {
            // A full disk, say: the cases then say for themselves why they cannot run.
            eprintln!(
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
            return match another(&recorded, study) {
                true => Err(refused(out, &recorded, &path, study)),
                false => Ok(()),
            };
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    Err(AppError::Input(format!(
        "`{}` cannot be read as the record of the study that owns `{}`; remove it if no study runs there",
        path.display(),
        out.display()
    )))
}

/// Create `path` with `bytes`, failing with `AlreadyExists` when it exists: written beside
/// it and hard-linked into place (atomic and exclusive), or created exclusively and written
/// where the file system has no hard links.
fn create_exclusive(dir: &Path, path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let tmp = dir.join(format!("{OWNER_FILE}.{}.tmp", std::process::id()));
    let written = crate::output::atomic::signals_held(|| {
        let linked = std::fs::write(&tmp, bytes).and_then(|()| std::fs::hard_link(&tmp, path));
        let _ = std::fs::remove_file(&tmp);
        linked
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

//! `chute collect`: the table of the cases found in some study output directories, written
//! under the lock of the directory it goes to (docs/cli.md §`chute collect`).

use std::path::{Path, PathBuf};

use super::table::{gather, refuse_run_dir, refuse_run_dir_out, write_table, Table};
use super::DONE_FILE;
use crate::app::AppError;

/// Refuse `--out` that holds cases of its own but is not among `dirs`: its table is that
/// study's, which `collect` of other directories would replace.
fn refuse_other_study_out(dirs: &[PathBuf], out: &Path) -> Result<(), AppError> {
    let same = |a: &Path, b: &Path| match (a.canonicalize(), b.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => a == b,
    };
    if dirs.iter().any(|d| same(d, out)) {
        return Ok(());
    }
    let Ok(entries) = std::fs::read_dir(out) else {
        return Ok(());
    };
    // Its cases, or a study's owner record (a study whose first cases are still running).
    let owned = std::fs::symlink_metadata(out.join(super::owner::OWNER_FILE)).is_ok();
    let holds_cases = owned
        || entries
            .filter_map(Result::ok)
            .any(|e| e.path().join(DONE_FILE).is_file());
    match holds_cases {
        true => Err(AppError::Input(format!(
            "`{}` holds the cases of a study of its own, whose table this would replace: give it as a DIR to collect it too, or choose another --out",
            out.display()
        ))),
        false => Ok(()),
    }
}

/// `chute collect`: [`gather`] the cases of `dirs` and [`write_table`] into `out`. Input
/// errors (exit 2), before anything is written: a run directory among `dirs`, or no case.
pub fn collect(dirs: &[PathBuf], out: &Path) -> Result<Table, AppError> {
    for d in dirs {
        refuse_run_dir(d)?;
    }
    refuse_other_study_out(dirs, out)?;
    refuse_run_dir_out(out)?;
    // Gathered and written under the directory's lock, as a study claims its directory and
    // writes its table: a table gathered before a study's last write never replaces it, and
    // a study or run never starts in a directory a table is being written to. A directory
    // made for it and left without a table (no cases, a full disk) is removed again.
    let created = crate::app::out_dir::first_missing(out);
    let result = (|| {
        crate::app::ensure_dir(out)?;
        let held = super::owner::hold_out(out, "no table was written")?;
        super::owner::refuse_users_tables(out, false)?;
        let table = gather(dirs, None)?;
        if table.rows.is_empty() || !dirs.iter().any(|d| holds_a_case(d)) {
            let shown: Vec<String> = dirs.iter().map(|d| format!("`{}`", d.display())).collect();
            return Err(AppError::Input(format!(
                "no cases found in {}: a study's output directory holds one directory per case, each with a {DONE_FILE}",
                shown.join(", ")
            )));
        }
        let mut table = table;
        let study = recorded_dispersion(dirs).transpose().unwrap_or_else(|why| {
            table.notes.push(format!(
                "{} and the footprint not written: {why}",
                super::dispersion_out::DISPERSION_CSV
            ));
            None
        });
        if let Some(study) = study {
            let missing = super::dispersion_out::write_collected(&study, dirs, out)?;
            if !missing.is_empty() {
                table.notes.push(format!(
                    "{} not written: {} of {} samples have not landed",
                    super::dispersion_out::FOOTPRINT_JSON,
                    missing.len(),
                    study.cases.len()
                ));
            }
        }
        write_table(&table, out)?;
        drop(held);
        Ok(table)
    })();
    if result.is_err() && created.is_some() {
        // Half a table (the CSV written, the Markdown not) in a directory made for it.
        for f in super::table::TABLE_FILES {
            let _ = std::fs::remove_file(out.join(f));
        }
        crate::app::out_dir::remove_created(out, created.as_deref());
    }
    result
}

/// The dispersion study that the first case found in `dirs` records, when it is one: `None`
/// for another study, an error saying why when the cases are a dispersion's samples (named
/// `sample-…`) whose study file cannot be read back.
fn recorded_dispersion(dirs: &[PathBuf]) -> Option<Result<super::Study, String>> {
    let done = dirs.iter().find_map(|d| {
        std::fs::read_dir(d)
            .ok()?
            .filter_map(Result::ok)
            .find_map(|e| {
                let text =
                    crate::output::atomic::read_own_string(&e.path().join(DONE_FILE)).ok()?;
                serde_json::from_str::<serde_json::Value>(&text).ok()
            })
    })?;
    let file = done["recipe"]["study_file"].as_str()?;
    match super::Study::load_recorded(Path::new(file)) {
        Ok(st) => st.dispersion.is_some().then_some(Ok(st)),
        Err(e) if done["case"].as_str()?.starts_with("sample-") => Some(Err(format!(
            "the study file `{file}` the samples record cannot be read ({e})"
        ))),
        Err(_) => None,
    }
}

/// Whether `dir` holds a study's case: a directory with a `done.json`, or whose run records
/// the case it was made for (a case killed before its marker). Plain runs are no case.
fn holds_a_case(dir: &Path) -> bool {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return false;
    };
    entries.filter_map(Result::ok).any(|e| {
        let p = e.path();
        p.join(DONE_FILE).exists()
            || crate::output::record::RunRecord::read(&p)
                .is_ok_and(|r| r.is_some_and(|r| r.case_of.is_some()))
    })
}

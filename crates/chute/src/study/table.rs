//! The study table: gathering finished cases from `done.json` and `summary.json`, and
//! writing `study.csv` and `study.md` atomically.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

pub use super::case_state::CaseState;
use super::inputs::{Checker, InputsState};
use super::{Study, DONE_FILE, LANDING_COLUMNS, METRIC_COLUMNS};
use crate::app::AppError;
use crate::output::run_files::SUMMARY;
use crate::scenario::derived::sig4;

pub(crate) fn read_json(path: &Path) -> Option<serde_json::Value> {
    serde_json::from_str(&crate::output::atomic::read_own_string(path).ok()?).ok()
}

/// Write a file atomically ([`crate::output::atomic::write_atomic`]: a temporary file in the
/// same directory, then a rename, so a reader or a concurrent shard never sees half a file;
/// the umask is honoured).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), AppError> {
    crate::output::atomic::write_atomic(path, bytes).map_err(|e| AppError::io(path, e))
}

/// One table row: a finished case.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// Case index in its study (orders the rows).
    pub index: usize,
    /// Case name.
    pub case: String,
    /// The case's overridden values, by key.
    pub overrides: BTreeMap<String, String>,
    /// The metric columns, by name, as text (empty when absent).
    pub metrics: BTreeMap<String, String>,
    /// `done.json` says complete and `summary.json` exists.
    pub complete: bool,
    /// Where the case is: complete, or why not.
    pub state: CaseState,
    /// Whether the recorded inputs are what the case's study would run now.
    pub inputs: InputsState,
}

/// Why the inputs of a case without a run cannot be judged.
const NOT_RUN: &str = "it has not run";

/// The study table: the override columns (in order of first appearance) and the rows.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Table {
    /// Override keys, one column each.
    pub override_keys: Vec<String>,
    /// Rows ordered by case index, then name.
    pub rows: Vec<Row>,
    /// Warnings about the table as a whole (rows run under different study-wide overrides).
    pub notes: Vec<String>,
    /// Why the table may lack cases it cannot name (a study whose case list is unknown).
    pub unknown_cases: Vec<String>,
    /// What the best case minimises (the study file's `minimise`), if anything.
    pub objective: Option<super::objective::Objective>,
}

fn metric_text(v: Option<&serde_json::Value>) -> String {
    match v {
        Some(serde_json::Value::Number(n)) => n.to_string(),
        Some(serde_json::Value::Bool(b)) => b.to_string(),
        Some(serde_json::Value::String(s)) => s.clone(),
        _ => String::new(),
    }
}

/// The JSON of `path`: `Ok(None)` when there is no such file, an error naming it when it
/// cannot be read or parsed.
fn read_json_strict(path: &Path) -> Result<Option<serde_json::Value>, String> {
    match crate::output::atomic::read_own_string(path) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(format!("cannot read `{}`: {e}", path.display())),
        Ok(text) => serde_json::from_str(&text)
            .map(Some)
            .map_err(|e| format!("cannot read `{}`: not valid JSON: {e}", path.display())),
    }
}

/// A row of a case directory whose `done.json` is absent or unreadable, `None` when the
/// directory holds no case at all.
fn unfinished_row(case_dir: &Path, done: Result<Option<serde_json::Value>, String>) -> Option<Row> {
    use crate::output::record::DirState;
    let case = case_dir.file_name()?.to_string_lossy().into_owned();
    // Made for the case of this directory's name (`study/case`): not a backup copy `a.bak`.
    let made_for_a_case = || {
        let of_this = |c: &str| c.split_once('/').is_some_and(|(_, name)| name == case);
        crate::output::record::RunRecord::read(case_dir)
            .is_ok_and(|r| r.is_some_and(|r| r.case_of.as_deref().is_some_and(of_this)))
    };
    if matches!(done, Ok(None)) && !made_for_a_case() {
        // A directory without a case record whose run was not made for its case (a run of its
        // own, one without a readable run.json, a copy of another case's): no case.
        return None;
    }
    let state = match done {
        Err(why) => CaseState::Unreadable(why),
        Ok(_) => match DirState::of(case_dir) {
            Ok(DirState::Running) => CaseState::Running,
            Ok(s @ DirState::Abandoned) => CaseState::Abandoned(format!(
                "`{}` has no {DONE_FILE}: {}",
                case_dir.display(),
                s.unfinished().unwrap_or_default()
            )),
            Ok(DirState::Unrecorded) if !crate::output::run_files::is_run_dir(case_dir) => {
                return None
            }
            Ok(s) => CaseState::Missing(format!(
                "`{}` has no {DONE_FILE}: {}",
                case_dir.display(),
                s.unfinished()
                    .unwrap_or_else(|| "its run ended without its study recording it".into())
            )),
            Err(why) => CaseState::Unreadable(why),
        },
    };
    Some(Row {
        index: usize::MAX,
        case,
        overrides: BTreeMap::new(),
        metrics: BTreeMap::new(),
        complete: false,
        state,
        inputs: InputsState::Unknown("its run was not recorded as finished".into()),
    })
}

/// Why `case_dir`'s `summary.json` is not the one its run wrote, as the digest `done`
/// records shows (`None`: it is, or the record is of an older chute without the digest).
pub(super) fn summary_replaced(case_dir: &Path, done: &serde_json::Value) -> Option<String> {
    let path = case_dir.join(SUMMARY);
    let Some(recorded) = done["summary_digest"].as_str() else {
        // Recorded complete without the digest of its summary (an older chute, or an
        // edited record): the summary cannot be told from another case's.
        return (done["status"] == "complete").then(|| {
            format!(
                "`{}` records no digest of its summary (an older chute wrote it, or it was edited), so `{}` cannot be verified: run the study again",
                case_dir.join(DONE_FILE).display(),
                path.display()
            )
        });
    };
    // One that cannot be read is reported as such elsewhere.
    let now = super::inputs::bytes_digest(&crate::output::atomic::read_own(&path).ok()?);
    (now != recorded).then(|| {
        format!(
            "`{}` is not the summary its run wrote (replaced or edited since): run the study again",
            path.display()
        )
    })
}

/// The state `done` records, checked against the summary it needs.
fn recorded_state(
    done: &serde_json::Value,
    summary: &Result<Option<serde_json::Value>, String>,
) -> CaseState {
    let message = || {
        done["message"]
            .as_str()
            .unwrap_or("no reason recorded")
            .to_string()
    };
    match (done["status"].as_str(), summary) {
        (_, Err(why)) => CaseState::Unreadable(why.clone()),
        (Some("complete"), Ok(Some(_))) => CaseState::Complete,
        (Some("complete"), Ok(None)) => {
            CaseState::Unreadable("its done.json says complete but it has no summary.json".into())
        }
        (Some("incomplete"), _) => CaseState::Incomplete(message()),
        (Some("failed"), _) => CaseState::Failed(message()),
        (other, _) => CaseState::Unreadable(format!(
            "its done.json has no known status ({})",
            other.unwrap_or("none")
        )),
    }
}

/// A row and the `recipe` of its `done.json` (null for a record without one; `None` when no
/// record could be read, which says nothing about the study's case list).
fn read_row(case_dir: &Path, checker: &mut Checker) -> Option<(Row, Option<serde_json::Value>)> {
    let done = match read_json_strict(&case_dir.join(DONE_FILE)) {
        Ok(Some(d)) if d.is_object() => d,
        Ok(Some(_)) => {
            let why = format!(
                "`{}` is not a case record",
                case_dir.join(DONE_FILE).display()
            );
            return unfinished_row(case_dir, Err(why)).map(|r| (r, None));
        }
        other => return unfinished_row(case_dir, other).map(|r| (r, None)),
    };
    let summary = read_json_strict(&case_dir.join(SUMMARY));
    let case = done["case"].as_str().map(str::to_string).or_else(|| {
        case_dir
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
    })?;
    let overrides = done["overrides"]
        .as_array()
        .map(|a| {
            a.iter()
                .filter_map(|kv| Some((kv[0].as_str()?.to_string(), kv[1].as_str()?.to_string())))
                .collect()
        })
        .unwrap_or_default();
    // A run that did not finish shows what its own summary measured, and nothing when the
    // summary there is not its own (it failed before replacing an earlier run's).
    let own = done["status"] == "complete" || !done["summary_digest"].is_null();
    let values = summary
        .as_ref()
        .ok()
        .and_then(Option::as_ref)
        .filter(|_| own);
    let metrics = METRIC_COLUMNS
        .iter()
        .chain(LANDING_COLUMNS)
        .map(|k| (k.to_string(), metric_text(values.and_then(|s| s.get(*k)))))
        .collect();
    let state = match crate::output::record::DirState::of(case_dir) {
        // A run of the case (a `chute resume`) was killed after its record: whatever
        // `done.json` says, the directory now mixes that run's files with the record's.
        Ok(crate::output::record::DirState::Abandoned) => CaseState::Abandoned(
            "a run of it was killed (run.json says running; no process holds it): run the study again".into(),
        ),
        _ => match summary_replaced(case_dir, &done) {
            Some(why) => CaseState::Unreadable(why),
            None => match recorded_state(&done, &summary) {
                // Complete only with all of its run's own files (a failed run may lack some).
                CaseState::Complete => super::skip::case_not_whole(case_dir, &done)
                    .map_or(CaseState::Complete, CaseState::Unreadable),
                other => other,
            },
        },
    };
    let row = Row {
        index: done["index"].as_u64().map_or(usize::MAX, |i| i as usize),
        case,
        overrides,
        metrics,
        complete: state == CaseState::Complete,
        state,
        inputs: checker.state(&done, case_dir),
    };
    Some((row, Some(done["recipe"].clone())))
}

/// Gather every case of the given study output directories (e.g. one per shard): a row per
/// case directory, then a `missing` row for every case of the study that none of them holds
/// (the study's full list: `invocation`'s for `chute study`, else the one recorded in the
/// cases' `done.json`, `study::expected`). Each finished case's recorded inputs are
/// compared with what its study would run now: under the study and study-wide overrides of
/// `invocation` when given, else those recorded with the case (and the table then notes
/// cases recorded under different study-wide overrides). A case found twice keeps its last
/// complete occurrence, or its last one.
pub fn gather(
    dirs: &[PathBuf],
    invocation: Option<(&Study, &[String])>,
) -> Result<Table, AppError> {
    let mut checker = match invocation {
        Some((st, set)) => Checker::for_invocation(st, set),
        None => Checker::default(),
    };
    let mut g = super::gathered::Gathered {
        first: invocation.is_none().then_some(None),
        ..Default::default()
    };
    for dir in dirs {
        let entries = std::fs::read_dir(dir).map_err(|e| AppError::io(dir, e))?;
        let mut paths: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
        paths.sort();
        for p in paths.into_iter().filter(|p| p.is_dir()) {
            // A case directory is a directory: a link there (to another study's case, say)
            // is not this directory's case, as a study never writes through one.
            if std::fs::symlink_metadata(&p).is_ok_and(|m| m.file_type().is_symlink()) {
                g.left_out.push(format!(
                    "`{}` is a link, not a case directory: left out of the table",
                    p.display()
                ));
                continue;
            }
            if let Some((row, recipe)) = read_row(&p, &mut checker) {
                g.add(p, row, recipe)?;
            }
        }
    }
    let super::gathered::Gathered {
        mut by_name,
        recipes,
        found,
        left_out,
        ..
    } = g;
    let list = super::expected::cases(invocation.map(|(st, _)| st), recipes.values());
    let listed = |name: &String| list.cases.iter().any(|(_, c, _)| c == name);
    if invocation.is_some() {
        // The study's own table: its cases only, not other directories beside them (a study
        // written into a directory that holds other runs).
        by_name.retain(|name, _| listed(name));
    } else if list.unknown.is_empty() {
        // The full list is known: a directory without a record of its own that the list does
        // not name (a run made for a case of another study) is no case of this one.
        by_name.retain(|name, _| listed(name) || recipes.contains_key(name));
    }
    for (index, case, set) in list.cases {
        let overrides: BTreeMap<String, String> = set
            .iter()
            .filter_map(|s| super::split_override(s).map(|[k, v]| (k, v)))
            .collect();
        if let Some(row) = by_name.get_mut(&case) {
            row.index = row.index.min(index);
            // A row without a record (running, abandoned) shows the case's overrides too.
            if row.overrides.is_empty() {
                row.overrides = overrides;
            }
            continue;
        }
        let why = match dirs {
            [one] if one.join(&case).is_dir() => format!(
                "`{}` exists but holds no record of it (no `done.json` of this case)",
                one.join(&case).display()
            ),
            [one] => format!("`{}` has no directory for it", one.join(&case).display()),
            _ => "none of the directories given has it".into(),
        };
        by_name.insert(
            case.clone(),
            Row {
                index,
                case,
                overrides,
                metrics: BTreeMap::new(),
                complete: false,
                state: CaseState::Missing(format!("not run: {why}")),
                inputs: InputsState::Unknown(NOT_RUN.into()),
            },
        );
    }
    let mut rows: Vec<Row> = by_name.into_values().collect();
    rows.sort_by(|a, b| (a.index, &a.case).cmp(&(b.index, &b.case)));
    if invocation.is_none() {
        super::owner::mark_earlier_ladders(dirs, &mut rows, &recipes);
    }
    let mut override_keys: Vec<String> = Vec::new();
    for r in &rows {
        for k in r.overrides.keys() {
            if !override_keys.contains(k) {
                override_keys.push(k.clone());
            }
        }
    }
    let notes = super::gathered::mixed_recipes(&rows, &recipes)
        .into_iter()
        .chain(found.values().filter_map(|f| f.note()))
        .chain(left_out)
        .collect();
    // `collect` has no study at hand: the objective of the study file its cases recorded.
    let objective = match invocation {
        Some((st, _)) => st.objective.clone(),
        None => recipes
            .values()
            .find_map(|r| r["study_file"].as_str().map(PathBuf::from))
            .and_then(|f| Study::load_recorded(&f).ok())
            .and_then(|st| st.objective),
    };
    Ok(Table {
        override_keys,
        rows,
        notes,
        unknown_cases: list.unknown,
        objective,
    })
}

/// Refuse a directory that holds a single run at its top level: study files written there
/// would mix a study into a run (or a case) directory.
pub(crate) fn refuse_run_dir(dir: &Path) -> Result<(), AppError> {
    let run_file = crate::output::run_files::run_evidence(dir);
    match run_file {
        Some(f) => Err(AppError::Input(format!(
            "`{}` is a run directory (it holds the {f} of a single run), not the output directory of a study: give the directory the study wrote its cases into (`chute study --out DIR`)",
            dir.display()
        ))),
        None => Ok(()),
    }
}

/// [`refuse_run_dir`] for a directory a command writes a study into: also refused when it
/// lies inside a run directory (`collect --out RUN/frames` would put a table among a run's
/// files, which `--force` and `resume` treat as the run's).
pub(crate) fn refuse_run_dir_out(out: &Path) -> Result<(), AppError> {
    refuse_run_dir(out)?;
    crate::app::out_dir::refuse_inside_run(out)
}

/// A study's table files in its output directory: CSV and Markdown.
pub(crate) const TABLE_FILES: [&str; 2] = ["study.csv", "study.md"];

/// Write `study.csv` and `study.md` into `out` (refused when `out` is, or lies inside, a run
/// directory).
pub fn write_table(table: &Table, out: &Path) -> Result<(), AppError> {
    refuse_run_dir_out(out)?;
    crate::app::ensure_dir(out)?;
    // Again at the end: a file the user put there while the cases ran.
    super::owner::refuse_users_tables(out, false)?;
    let [csv, md] = TABLE_FILES.map(|f| out.join(f));
    write_atomic(&csv, table.to_csv()?.as_bytes())?;
    // Both or neither: a CSV beside no Markdown (a full disk) is half a table.
    write_atomic(&md, table.to_markdown().as_bytes()).inspect_err(|_| {
        let _ = std::fs::remove_file(&csv);
    })
}

impl Table {
    /// Column headers: case, override keys, metrics, status, complete, inputs.
    pub fn headers(&self) -> Vec<String> {
        let mut h = vec!["case".to_string()];
        h.extend(self.override_keys.iter().cloned());
        h.extend(self.metric_columns().iter().map(|s| s.to_string()));
        h.push("status".into());
        h.push("complete".into());
        h.push("inputs".into());
        h
    }

    /// The metric columns: [`METRIC_COLUMNS`], then the [`LANDING_COLUMNS`] that some row has.
    fn metric_columns(&self) -> Vec<&'static str> {
        let some = |k: &&str| {
            self.rows
                .iter()
                .any(|r| r.metrics.get(*k).is_some_and(|v| !v.is_empty()))
        };
        METRIC_COLUMNS
            .iter()
            .copied()
            .chain(LANDING_COLUMNS.iter().copied().filter(some))
            .collect()
    }

    /// One line per row whose recorded inputs are not what its study would run now, then
    /// the table's [`Table::notes`].
    pub fn input_warnings(&self) -> Vec<String> {
        let line = |r: &Row, what: &str, why: &str| format!("case `{}`: {what}: {why}", r.case);
        // Cases not run yet (other shards') in one line: a sharded study of 10⁵ samples
        // would otherwise print a line for each.
        let not_run = |r: &&Row| matches!(&r.inputs, InputsState::Unknown(w) if w == NOT_RUN);
        let waiting: Vec<&str> = (self.rows.iter().filter(not_run))
            .map(|r| r.case.as_str())
            .collect();
        let rows = self.rows.iter().filter_map(|r| match &r.inputs {
            InputsState::Current => None,
            InputsState::Changed(why) => Some(line(
                r,
                "stale (its row is from other inputs; running the study again re-runs it)",
                why,
            )),
            InputsState::Unknown(why) if waiting.len() > 1 && why == NOT_RUN => None,
            InputsState::Unknown(why) => {
                Some(line(r, "cannot tell whether its inputs are current", why))
            }
        });
        let shown = waiting.iter().take(10).map(|c| format!("`{c}`"));
        let more = waiting.len().saturating_sub(10);
        let grouped = (waiting.len() > 1).then(|| {
            let tail = if more > 0 {
                format!(" and {more} more")
            } else {
                String::new()
            };
            let names: Vec<String> = shown.collect();
            format!(
                "{} cases have not run yet: {}{tail}",
                waiting.len(),
                names.join(", ")
            )
        });
        rows.chain(grouped)
            .chain(self.notes.iter().cloned())
            .collect()
    }

    /// One line per case that is not complete (missing, running, failed, incomplete, or
    /// with a file that cannot be read), naming it and saying why.
    pub fn unfinished(&self) -> Vec<String> {
        self.rows
            .iter()
            .filter_map(|r| {
                let why = r.state.why()?;
                Some(format!("case `{}` {}: {why}", r.case, r.state.phrase()))
            })
            .chain(self.unknown_cases.iter().cloned())
            .collect()
    }

    fn cells(&self, r: &Row, fmt: impl Fn(&str) -> String) -> Vec<String> {
        let mut c = vec![r.case.clone()];
        c.extend(
            self.override_keys
                .iter()
                .map(|k| r.overrides.get(k).cloned().unwrap_or_default()),
        );
        c.extend(
            self.metric_columns()
                .iter()
                .map(|k| fmt(r.metrics.get(*k).map_or("", |s| s.as_str()))),
        );
        c.push(r.state.word().to_string());
        c.push(r.complete.to_string());
        c.push(r.inputs.word().to_string());
        c
    }

    /// The table as CSV, numbers at full precision.
    pub fn to_csv(&self) -> Result<String, AppError> {
        let mut w = csv::Writer::from_writer(Vec::new());
        let err = |e: csv::Error| AppError::RunFailed(format!("cannot format study.csv: {e}"));
        w.write_record(self.headers()).map_err(err)?;
        for r in &self.rows {
            w.write_record(self.cells(r, str::to_string)).map_err(err)?;
        }
        let bytes = w
            .into_inner()
            .map_err(|e| AppError::RunFailed(format!("cannot format study.csv: {e}")))?;
        Ok(String::from_utf8_lossy(&bytes).into_owned())
    }

    /// The table as Markdown, numbers to 4 significant digits, missing values as "—".
    pub fn to_markdown(&self) -> String {
        let short = |s: &str| match s.parse::<f64>() {
            _ if s.is_empty() => "—".to_string(),
            Ok(x) if s != "true" && s != "false" => sig4(x),
            _ => s.to_string(),
        };
        let h = self.headers();
        let mut md = format!("| {} |\n|{}\n", h.join(" | "), "---|".repeat(h.len()));
        for r in &self.rows {
            md.push_str(&format!("| {} |\n", self.cells(r, short).join(" | ")));
        }
        if let Some(line) = self.best_line() {
            md.push_str(&format!("\n{line}\n"));
        }
        md
    }
}

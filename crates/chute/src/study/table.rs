//! The study table: gathering finished cases from `done.json` and `summary.json`, and
//! writing `study.csv` and `study.md` atomically.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use super::inputs::{Checker, InputsState};
use super::{Study, DONE_FILE, METRIC_COLUMNS};
use crate::app::AppError;
use crate::output::run_files::RESOLVED_SCENARIO;
use crate::scenario::derived::sig4;

pub(crate) fn read_json(path: &Path) -> Option<serde_json::Value> {
    serde_json::from_str(&std::fs::read_to_string(path).ok()?).ok()
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
    /// Whether the recorded inputs are what the case's study would run now.
    pub inputs: InputsState,
}

/// The study table: the override columns (in order of first appearance) and the rows.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Table {
    /// Override keys, one column each.
    pub override_keys: Vec<String>,
    /// Rows ordered by case index, then name.
    pub rows: Vec<Row>,
    /// Warnings about the table as a whole (rows run under different study-wide overrides).
    pub notes: Vec<String>,
}

fn metric_text(v: Option<&serde_json::Value>) -> String {
    match v {
        Some(serde_json::Value::Number(n)) => n.to_string(),
        Some(serde_json::Value::Bool(b)) => b.to_string(),
        Some(serde_json::Value::String(s)) => s.clone(),
        _ => String::new(),
    }
}

/// A row and the study file and study-wide overrides it was run under (as text).
fn read_row(case_dir: &Path, checker: &mut Checker) -> Option<(Row, String)> {
    let done = read_json(&case_dir.join(DONE_FILE))?;
    let summary = read_json(&case_dir.join("summary.json"));
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
    let metrics = METRIC_COLUMNS
        .iter()
        .map(|k| {
            (
                k.to_string(),
                metric_text(summary.as_ref().and_then(|s| s.get(*k))),
            )
        })
        .collect();
    let recipe = &done["recipe"];
    let recipe = format!(
        "study file {}, --set {}",
        recipe["study_file"].as_str().unwrap_or("(none)"),
        recipe["set"]
    );
    let row = Row {
        index: done["index"].as_u64().map_or(usize::MAX, |i| i as usize),
        case,
        overrides,
        metrics,
        complete: done["status"] == "complete" && summary.is_some(),
        inputs: checker.state(&done),
    };
    Some((row, recipe))
}

/// Gather every finished case (`<dir>/<case>/done.json`) of the given study output
/// directories (e.g. one per shard) and compare each case's recorded inputs with what its
/// study would run now: the study and study-wide overrides of `invocation` when given
/// (`chute study`), else those recorded with the case (`chute collect`, which then also
/// notes cases recorded under different study-wide overrides). A case found twice keeps its
/// last occurrence.
pub fn gather(
    dirs: &[PathBuf],
    invocation: Option<(&Study, &[String])>,
) -> Result<Table, AppError> {
    let mut by_name: BTreeMap<String, Row> = BTreeMap::new();
    let mut checker = match invocation {
        Some((st, set)) => Checker::for_invocation(st, set),
        None => Checker::default(),
    };
    let mut recipes: BTreeMap<String, String> = BTreeMap::new();
    for dir in dirs {
        let entries = std::fs::read_dir(dir).map_err(|e| AppError::io(dir, e))?;
        let mut paths: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
        paths.sort();
        for p in paths.into_iter().filter(|p| p.is_dir()) {
            if let Some((row, recipe)) = read_row(&p, &mut checker) {
                recipes.insert(row.case.clone(), recipe);
                by_name.insert(row.case.clone(), row);
            }
        }
    }
    let mut rows: Vec<Row> = by_name.into_values().collect();
    rows.sort_by(|a, b| (a.index, &a.case).cmp(&(b.index, &b.case)));
    let mut override_keys: Vec<String> = Vec::new();
    for r in &rows {
        for k in r.overrides.keys() {
            if !override_keys.contains(k) {
                override_keys.push(k.clone());
            }
        }
    }
    let mut notes = Vec::new();
    let mut groups: BTreeMap<&str, Vec<&str>> = BTreeMap::new();
    for r in &rows {
        groups
            .entry(recipes[&r.case].as_str())
            .or_default()
            .push(&r.case);
    }
    if groups.len() > 1 {
        let parts: Vec<String> = groups
            .iter()
            .map(|(recipe, cases)| format!("{} with {recipe}", cases.join(", ")))
            .collect();
        notes.push(format!(
            "the table mixes cases run under different studies or study-wide --set overrides: {}",
            parts.join("; ")
        ));
    }
    Ok(Table {
        override_keys,
        rows,
        notes,
    })
}

/// Refuse a directory that holds a single run at its top level: study files written there
/// would mix a study into a run (or a case) directory.
pub(crate) fn refuse_run_dir(dir: &Path) -> Result<(), AppError> {
    let run_file = [RESOLVED_SCENARIO, "summary.json"]
        .into_iter()
        .find(|f| dir.join(f).is_file());
    match run_file {
        Some(f) => Err(AppError::Input(format!(
            "`{}` is a run directory (it holds the {f} of a single run), not the output directory of a study: give the directory the study wrote its cases into (`chute study --out DIR`)",
            dir.display()
        ))),
        None => Ok(()),
    }
}

/// Write `study.csv` and `study.md` into `out` (refused when `out` is a run directory).
pub fn write_table(table: &Table, out: &Path) -> Result<(), AppError> {
    refuse_run_dir(out)?;
    std::fs::create_dir_all(out).map_err(|e| AppError::io(out, e))?;
    write_atomic(&out.join("study.csv"), table.to_csv()?.as_bytes())?;
    write_atomic(&out.join("study.md"), table.to_markdown().as_bytes())
}

/// `chute collect`: [`gather`] the cases of `dirs` and [`write_table`] into `out`. Input
/// errors (exit 2), before anything is written: a run directory among `dirs`, or no case.
pub fn collect(dirs: &[PathBuf], out: &Path) -> Result<Table, AppError> {
    for d in dirs {
        refuse_run_dir(d)?;
    }
    let table = gather(dirs, None)?;
    if table.rows.is_empty() {
        let shown: Vec<String> = dirs.iter().map(|d| format!("`{}`", d.display())).collect();
        return Err(AppError::Input(format!(
            "no cases found in {}: a study's output directory holds one directory per case, each with a {DONE_FILE}",
            shown.join(", ")
        )));
    }
    write_table(&table, out)?;
    Ok(table)
}

impl Table {
    /// Column headers: case, override keys, metrics, complete, inputs.
    pub fn headers(&self) -> Vec<String> {
        let mut h = vec!["case".to_string()];
        h.extend(self.override_keys.iter().cloned());
        h.extend(METRIC_COLUMNS.iter().map(|s| s.to_string()));
        h.push("complete".into());
        h.push("inputs".into());
        h
    }

    /// One line per row whose recorded inputs are not what its study would run now, then
    /// the table's [`Table::notes`].
    pub fn input_warnings(&self) -> Vec<String> {
        let line = |r: &Row, what: &str, why: &str| format!("case `{}`: {what}: {why}", r.case);
        let rows = self.rows.iter().filter_map(|r| match &r.inputs {
            InputsState::Current => None,
            InputsState::Changed(why) => Some(line(
                r,
                "stale (its row is from other inputs; running the study again re-runs it)",
                why,
            )),
            InputsState::Unknown(why) => {
                Some(line(r, "cannot tell whether its inputs are current", why))
            }
        });
        rows.chain(self.notes.iter().cloned()).collect()
    }

    fn cells(&self, r: &Row, fmt: impl Fn(&str) -> String) -> Vec<String> {
        let mut c = vec![r.case.clone()];
        c.extend(
            self.override_keys
                .iter()
                .map(|k| r.overrides.get(k).cloned().unwrap_or_default()),
        );
        c.extend(
            METRIC_COLUMNS
                .iter()
                .map(|k| fmt(r.metrics.get(*k).map_or("", |s| s.as_str()))),
        );
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
        md
    }
}

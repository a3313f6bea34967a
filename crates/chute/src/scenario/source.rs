//! The scenario text as parsed TOML, plus where each key was written, so that later checks
//! (which work on plain values) can still point the user at a file line.

use std::collections::BTreeMap;

use super::error::{Origin, ScenarioError};

/// Where each value came from, by dotted key path (`"canopy.span_m"`).
#[derive(Debug, Clone, Default)]
pub struct Provenance {
    /// The file name used in messages.
    pub file: String,
    /// 1-based (line, column) of each key written in the file.
    pub positions: BTreeMap<String, (usize, usize)>,
    /// The `--set` argument that last wrote each key.
    pub overrides: BTreeMap<String, String>,
}

impl Provenance {
    /// The origin of a dotted key: the last `--set`, else the file, else a default. A key
    /// of an array-of-tables entry (`control[1].lines`) not written itself takes the origin
    /// of its entry, or of the whole array.
    pub fn origin(&self, key: &str) -> Origin {
        let mut paths = vec![key];
        if let Some((entry, _)) = key.split_once("].") {
            let entry = &key[..entry.len() + 1];
            paths.push(entry);
            paths.extend(entry.split_once('[').map(|(array, _)| array));
        }
        if let Some(arg) = paths.iter().find_map(|p| self.overrides.get(*p)) {
            return Origin::Set(arg.clone());
        }
        match paths.iter().find_map(|p| self.positions.get(*p)) {
            Some(&(line, col)) => Origin::File {
                file: self.file.clone(),
                line,
                col,
            },
            None => Origin::Default,
        }
    }

    /// Sort key putting file errors in reading order, overrides after them, defaults last.
    pub fn rank(&self, key: &str) -> (u8, usize, usize) {
        match self.origin(key) {
            Origin::File { line, col, .. } => (0, line, col),
            Origin::Set(_) => (1, 0, 0),
            Origin::Default => (2, 0, 0),
        }
    }
}

/// 1-based (line, column) of a byte offset in `text`; columns count characters.
pub fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let mut offset = offset.min(text.len());
    while !text.is_char_boundary(offset) {
        offset -= 1;
    }
    let before = &text[..offset];
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let col = before[line_start..].chars().count() + 1;
    (line, col)
}

/// Parse the scenario text: the value tree and the position of every key in it.
pub fn parse(text: &str, file: &str) -> Result<(toml::Table, Provenance), ScenarioError> {
    let doc = toml_edit::ImDocument::parse(text)
        .map_err(|e| syntax(text, file, e.span(), e.message()))?;
    let mut prov = Provenance {
        file: file.to_string(),
        ..Default::default()
    };
    collect_table(text, doc.as_table(), "", &mut prov.positions);
    // Same grammar as above, so this only fails if the two parsers disagree; still no panic.
    let table: toml::Table =
        toml::from_str(text).map_err(|e| syntax(text, file, e.span(), e.message()))?;
    Ok((table, prov))
}

fn syntax(
    text: &str,
    file: &str,
    span: Option<std::ops::Range<usize>>,
    msg: &str,
) -> ScenarioError {
    let (line, col) = span.map_or((1, 1), |s| line_col(text, s.start));
    ScenarioError::Syntax {
        file: file.to_string(),
        line,
        col,
        message: msg.trim().replace('\n', " "),
    }
}

fn join(prefix: &str, key: &str) -> String {
    if prefix.is_empty() {
        key.to_string()
    } else {
        format!("{prefix}.{key}")
    }
}

fn record(
    text: &str,
    path: &str,
    span: Option<std::ops::Range<usize>>,
    out: &mut BTreeMap<String, (usize, usize)>,
) {
    if let Some(s) = span {
        out.entry(path.to_string())
            .or_insert_with(|| line_col(text, s.start));
    }
}

fn collect_table(
    text: &str,
    table: &toml_edit::Table,
    prefix: &str,
    out: &mut BTreeMap<String, (usize, usize)>,
) {
    for (k, item) in table.iter() {
        let path = join(prefix, k);
        let key_span = table.key(k).and_then(|key| key.span());
        record(text, &path, key_span.or_else(|| item.span()), out);
        collect_item(text, item, &path, out);
    }
}

fn collect_item(
    text: &str,
    item: &toml_edit::Item,
    path: &str,
    out: &mut BTreeMap<String, (usize, usize)>,
) {
    match item {
        toml_edit::Item::Table(t) => collect_table(text, t, path, out),
        toml_edit::Item::ArrayOfTables(a) => {
            for (i, t) in a.iter().enumerate() {
                let p = format!("{path}[{i}]");
                record(text, &p, t.span(), out);
                collect_table(text, t, &p, out);
            }
        }
        toml_edit::Item::Value(toml_edit::Value::Array(a)) => {
            for (i, v) in a.iter().enumerate() {
                if let toml_edit::Value::InlineTable(_) = v {
                    let p = format!("{path}[{i}]");
                    record(text, &p, v.span(), out);
                    collect_item(text, &toml_edit::Item::Value(v.clone()), &p, out);
                }
            }
        }
        toml_edit::Item::Value(toml_edit::Value::InlineTable(t)) => {
            for (k, v) in t.iter() {
                let p = join(path, k);
                let key_span = t.key(k).and_then(|key| key.span());
                record(text, &p, key_span.or_else(|| v.span()), out);
                if let toml_edit::Value::InlineTable(_) = v {
                    collect_item(text, &toml_edit::Item::Value(v.clone()), &p, out);
                }
            }
        }
        _ => {}
    }
}

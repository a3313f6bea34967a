//! `--set section.key=value` overrides, applied to the raw TOML tree before any check, so
//! that an overridden value goes through exactly the same validation as one from the file.

use super::error::ScenarioError;
use super::keys::Section;
use super::schema::{self, KeyPath, Kind};
use super::sections::SECTIONS;
use super::source::Provenance;

/// Split and interpret one `--set` argument: the dotted key and its value.
///
/// The value is read as a TOML value (`4`, `1e-3`, `[4, 0, 0]`, `"corners"`); when it is not
/// one, or when the key takes a string, the raw text is taken as a plain string, so that
/// `--set load.mode=force` works without shell-escaped quotes.
pub fn parse(arg: &str) -> Result<(String, toml::Value), ScenarioError> {
    parse_in(SECTIONS, arg)
}

/// [`parse`] against `sections`.
pub fn parse_in(sections: &[Section], arg: &str) -> Result<(String, toml::Value), ScenarioError> {
    let Some((key, raw)) = arg.split_once('=') else {
        return Err(ScenarioError::BadOverride {
            arg: arg.to_string(),
            reason: "expected KEY=VALUE, e.g. `--set load.weight_n=200`".into(),
        });
    };
    let key = key.trim();
    let raw = raw.trim();
    if key.is_empty() {
        return Err(ScenarioError::BadOverride {
            arg: arg.to_string(),
            reason: "the key before `=` is empty".into(),
        });
    }
    // A whole array of tables: `--set 'control=[{lines = [0], start_s = 1}]'`.
    if schema::section_in(sections, key).is_some_and(|s| s.array && !s.name.is_empty()) {
        let value = toml_value(raw).unwrap_or_else(|| toml::Value::String(raw.to_string()));
        return Ok((key.to_string(), value));
    }
    let Some(kind) = schema::kind_in(sections, key) else {
        return Err(ScenarioError::UnknownKey {
            key: key.to_string(),
            origin: super::error::Origin::Set(arg.to_string()),
            suggestion: schema::suggest_in(sections, key),
        });
    };
    let parsed = toml_value(raw);
    if parsed.is_none() && !matches!(kind, Kind::Str | Kind::Choice(_)) {
        overflow(key, raw, arg)?;
    }
    let value = match (kind, parsed) {
        (Kind::Str | Kind::Choice(_), Some(v @ toml::Value::String(_))) => v,
        (Kind::Str | Kind::Choice(_), _) => toml::Value::String(raw.to_string()),
        (_, Some(v)) => v,
        (_, None) => toml::Value::String(raw.to_string()),
    };
    Ok((key.to_string(), value))
}

/// A number too large for a double (`1e400`) is refused as such; TOML rejects it, so it
/// would otherwise be taken for a string.
fn overflow(key: &str, raw: &str, arg: &str) -> Result<(), ScenarioError> {
    let numeral =
        raw.bytes().any(|b| b.is_ascii_digit()) && !raw.to_ascii_lowercase().contains("inf");
    match raw.replace('_', "").parse::<f64>() {
        Ok(x) if x.is_infinite() && numeral => Err(ScenarioError::Invalid {
            key: key.to_string(),
            value: raw.to_string(),
            reason: "overflows: the largest number is about 1.8e308".into(),
            origin: super::error::Origin::Set(arg.to_string()),
        }),
        _ => Ok(()),
    }
}

/// `raw` as a single TOML value, or `None` when it is not exactly one.
fn toml_value(raw: &str) -> Option<toml::Value> {
    let mut t: toml::Table = toml::from_str(&format!("v = {raw}")).ok()?;
    if t.len() != 1 {
        return None;
    }
    t.remove("v")
}

/// Apply the overrides in order (a later one wins), recording each as the key's origin.
/// `section[i].key` sets a field of entry `i` of an array of tables (`i` = its length adds
/// an entry).
pub fn apply(
    table: &mut toml::Table,
    prov: &mut Provenance,
    overrides: &[String],
) -> Result<(), ScenarioError> {
    apply_in(SECTIONS, table, prov, overrides)
}

/// [`apply`] against `sections`.
pub fn apply_in(
    sections: &[Section],
    table: &mut toml::Table,
    prov: &mut Provenance,
    overrides: &[String],
) -> Result<(), ScenarioError> {
    for arg in overrides {
        let (path, value) = parse_in(sections, arg)?;
        prov.overrides.insert(path.clone(), arg.clone());
        let p = KeyPath::parse(&path);
        if p.section.is_empty() {
            table.insert(path, value);
            continue;
        }
        let entry = table
            .entry(p.section.to_string())
            .or_insert_with(|| match p.index {
                Some(_) => toml::Value::Array(Vec::new()),
                None => toml::Value::Table(toml::Table::new()),
            });
        let target = match (p.index, entry) {
            (None, toml::Value::Table(t)) => t,
            (Some(i), toml::Value::Array(a)) => entry_mut(a, i, p.section, arg)?,
            (index, entry) => {
                let expected = match index {
                    Some(_) => "an array of tables (`[[section]]` entries)",
                    None => "a table (a `[section]`)",
                };
                return Err(ScenarioError::WrongType {
                    key: p.section.to_string(),
                    expected,
                    found: schema::describe(entry),
                    origin: prov.origin(p.section),
                });
            }
        };
        target.insert(p.key.to_string(), value);
    }
    Ok(())
}

/// Entry `i` of an array of tables; `i` = its length appends an empty one.
fn entry_mut<'a>(
    a: &'a mut Vec<toml::Value>,
    i: usize,
    section: &str,
    arg: &str,
) -> Result<&'a mut toml::Table, ScenarioError> {
    if i == a.len() {
        a.push(toml::Value::Table(toml::Table::new()));
    }
    let n = a.len();
    match a.get_mut(i) {
        Some(toml::Value::Table(t)) => Ok(t),
        Some(_) => Err(ScenarioError::BadOverride {
            arg: arg.to_string(),
            reason: format!("`{section}[{i}]` is not a table"),
        }),
        None => Err(ScenarioError::BadOverride {
            arg: arg.to_string(),
            reason: format!(
                "`{section}` has {n} entries (0-based), so `{section}[{i}]` is neither one of them nor the next"
            ),
        }),
    }
}

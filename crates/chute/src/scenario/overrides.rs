//! `--set section.key=value` overrides, applied to the raw TOML tree before any check, so
//! that an overridden value goes through exactly the same validation as one from the file.

use super::error::ScenarioError;
use super::schema::{self, Kind};
use super::source::Provenance;

/// Split and interpret one `--set` argument: the dotted key and its value.
///
/// The value is read as a TOML value (`4`, `1e-3`, `[4, 0, 0]`, `"corners"`); when it is not
/// one, or when the key takes a string, the raw text is taken as a plain string, so that
/// `--set load.mode=force` works without shell-escaped quotes.
pub fn parse(arg: &str) -> Result<(String, toml::Value), ScenarioError> {
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
    let Some(kind) = schema::kind_of(key) else {
        return Err(ScenarioError::UnknownKey {
            key: key.to_string(),
            origin: super::error::Origin::Set(arg.to_string()),
            suggestion: schema::suggest(key),
        });
    };
    let parsed = toml_value(raw);
    let value = match (kind, parsed) {
        (Kind::Str | Kind::Choice(_), Some(v @ toml::Value::String(_))) => v,
        (Kind::Str | Kind::Choice(_), _) => toml::Value::String(raw.to_string()),
        (_, Some(v)) => v,
        (_, None) => toml::Value::String(raw.to_string()),
    };
    Ok((key.to_string(), value))
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
pub fn apply(
    table: &mut toml::Table,
    prov: &mut Provenance,
    overrides: &[String],
) -> Result<(), ScenarioError> {
    for arg in overrides {
        let (path, value) = parse(arg)?;
        prov.overrides.insert(path.clone(), arg.clone());
        let Some((sec, key)) = path.split_once('.') else {
            table.insert(path, value);
            continue;
        };
        let entry = table
            .entry(sec.to_string())
            .or_insert_with(|| toml::Value::Table(toml::Table::new()));
        let Some(section) = entry.as_table_mut() else {
            return Err(ScenarioError::WrongType {
                key: sec.to_string(),
                expected: "a table (a `[section]`)",
                found: schema::describe(entry),
                origin: prov.origin(sec),
            });
        };
        section.insert(key.to_string(), value);
    }
    Ok(())
}

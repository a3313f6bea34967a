//! A study's `[grid]`: the cartesian product of its value lists, each case named from its
//! values.
use std::collections::BTreeMap;

use super::{input, safe_name, Case};
use crate::app::AppError;

/// A short label for a grid value in a case name: strings unquoted, arrays joined by `_`.
fn label(v: &toml::Value) -> String {
    match v {
        toml::Value::String(s) => s.clone(),
        toml::Value::Array(a) => a.iter().map(label).collect::<Vec<_>>().join("_"),
        other => other.to_string(),
    }
}

/// Whether two grid keys name one scenario key (parts compared without surrounding spaces,
/// as the overrides read them).
fn same_key(a: &str, b: &str) -> bool {
    a.split('.').map(str::trim).eq(b.split('.').map(str::trim))
}

/// Flatten a `[grid]` table (quoted dotted keys or nested tables) into (key, values).
fn flatten_grid(
    prefix: &str,
    t: &toml::Table,
    out: &mut Vec<(String, Vec<toml::Value>)>,
) -> Result<(), AppError> {
    for (k, v) in t {
        let key = if prefix.is_empty() {
            k.clone()
        } else {
            format!("{prefix}.{k}")
        };
        match v {
            toml::Value::Table(sub) => flatten_grid(&key, sub, out)?,
            // `"load.weight_n"` and `load = { weight_n = … }` are one key: two value lists
            // for it would be a grid over a key with two values at once.
            toml::Value::Array(_) if out.iter().any(|(k, _)| same_key(k, &key)) => {
                return Err(input(format!(
                    "grid key `{key}` is given twice (as a dotted key and in a table)"
                )))
            }
            toml::Value::Array(a) if !a.is_empty() => out.push((key, a.clone())),
            _ => {
                return Err(input(format!(
                    "grid key `{key}` must be a non-empty array of values"
                )))
            }
        }
    }
    Ok(())
}

/// The cartesian product of a grid, in key order with the last key varying fastest.
pub(super) fn cases(grid: &toml::Table) -> Result<Vec<Case>, AppError> {
    let mut axes = Vec::new();
    flatten_grid("", grid, &mut axes)?;
    if axes.is_empty() {
        return Err(input("`[grid]` is empty"));
    }
    let total: usize = axes.iter().map(|(_, v)| v.len()).product();
    if total > 100_000 {
        return Err(input(format!(
            "the grid has {total} cases; at most 100000 are allowed"
        )));
    }
    let mut last_seen: BTreeMap<&str, usize> = BTreeMap::new();
    for (k, _) in &axes {
        *last_seen
            .entry(k.rsplit('.').next().unwrap_or(k))
            .or_default() += 1;
    }
    let mut cases = Vec::with_capacity(total);
    for index in 0..total {
        let (mut rest, mut parts, mut set) = (index, Vec::new(), Vec::new());
        let mut picks = vec![0; axes.len()];
        for (a, (_, vals)) in axes.iter().enumerate().rev() {
            picks[a] = rest % vals.len();
            rest /= vals.len();
        }
        for ((key, vals), &p) in axes.iter().zip(&picks) {
            let short = key.rsplit('.').next().unwrap_or(key);
            // The last key segment names the case unless two axes share it.
            let shown = if last_seen.get(short) == Some(&1) {
                short
            } else {
                key.as_str()
            };
            parts.push(format!("{shown}-{}", label(&vals[p])));
            set.push(format!("{key}={}", vals[p]));
        }
        cases.push(Case {
            index,
            name: safe_name(&parts.join("_")),
            set,
        });
    }
    Ok(cases)
}

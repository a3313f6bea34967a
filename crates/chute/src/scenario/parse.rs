//! The loading pipeline: text → raw tree (+ positions) → overrides → schema check →
//! context-dependent defaults → typed structs → validation.

use std::path::{Path, PathBuf};

use super::error::ScenarioError;
use super::sections::SECTIONS;
use super::source::Provenance;
use super::{overrides, schema, source, validate, Scenario};

/// The absolute directory against which a scenario's relative paths resolve (a bare file
/// name is in the current directory: its empty parent cannot be made absolute, and a
/// relative path recorded for a mesh would then resolve against the run directory on
/// resume).
pub fn base_dir(file: &Path) -> PathBuf {
    let dir = match file.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    normalize(&std::path::absolute(dir).unwrap_or_else(|_| dir.to_path_buf()))
}

/// `a/b/../c` → `a/c` without touching the file system (the file may not exist yet, and
/// its absence is reported with a readable path).
fn normalize(p: &Path) -> PathBuf {
    use std::path::Component;
    let mut out = PathBuf::new();
    for c in p.components() {
        match c {
            Component::ParentDir
                if matches!(out.components().next_back(), Some(Component::Normal(_))) =>
            {
                out.pop();
            }
            Component::CurDir => {}
            other => out.push(other),
        }
    }
    out
}

/// A directory-safe default name from a file name: its stem, other characters as `_`.
fn default_name(file: &str) -> String {
    let stem = Path::new(file)
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let clean: String = stem
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || "-_.".contains(c) {
                c
            } else {
                '_'
            }
        })
        .collect();
    let clean = clean.trim_matches(|c| c == '.' || c == '_').to_string();
    if clean.is_empty() {
        "scenario".to_string()
    } else {
        clean
    }
}

/// Run every stage on one scenario text.
pub fn parse_scenario(
    text: &str,
    file: &str,
    base: &Path,
    overrides_: &[String],
) -> Result<Scenario, ScenarioError> {
    let (mut table, mut prov) = source::parse(text, file)?;
    overrides::apply(&mut table, &mut prov, overrides_)?;
    schema::check(&table, &prov)?;
    schema::required(&table)?;
    let kind = get(&table, "model", "kind")
        .and_then(|v| v.as_str())
        .unwrap_or_default()
        .to_string();
    fill_context_defaults(&mut table, &kind, &default_name(file));
    fill_declared_defaults(&mut table);
    let mut s: Scenario = toml::Value::Table(table)
        .try_into()
        .map_err(|e: toml::de::Error| conversion(e, &prov))?;
    let wind_file = s.wind.as_mut().and_then(|w| w.file.as_mut());
    let start_file = s.opening.as_mut().and_then(|o| o.mesh_file.as_mut());
    for p in [s.canopy.mesh_file.as_mut(), wind_file, start_file]
        .into_iter()
        .flatten()
    {
        if p.is_relative() {
            *p = normalize(&base.join(&*p));
        }
    }
    validate::validate(&s, &prov)?;
    s.loaded = load_inputs(&s, &prov)?;
    s.notes = super::LoadNotes(validate::notes(&s, &prov));
    Ok(s)
}

/// Read the input files the model is made from (checked readable by the validation just
/// before; one that changed since is refused the same way).
fn load_inputs(s: &Scenario, prov: &Provenance) -> Result<super::Loaded, ScenarioError> {
    let table = s
        .wind
        .as_ref()
        .filter(|w| w.profile == super::WindLaw::Table);
    let Some(path) = table.and_then(|w| w.file.as_ref()) else {
        return Ok(super::Loaded::default());
    };
    let key = super::wind::WIND_FILE_KEY;
    let file = super::wind::read(path).map_err(|reason| ScenarioError::Invalid {
        key: key.to_string(),
        value: format!("\"{}\"", path.display()),
        reason,
        origin: prov.origin(key),
    })?;
    Ok(super::Loaded {
        wind: Some(std::sync::Arc::new(file)),
    })
}

/// The schema check admits only convertible trees, so this is a safety net, not a path
/// users should see; it still names the file.
fn conversion(e: toml::de::Error, prov: &Provenance) -> ScenarioError {
    ScenarioError::Syntax {
        file: prov.file.clone(),
        line: 1,
        col: 1,
        message: format!("cannot convert the scenario: {}", e.message()),
    }
}

fn get<'a>(t: &'a toml::Table, sec: &str, key: &str) -> Option<&'a toml::Value> {
    t.get(sec)?.as_table()?.get(key)
}

fn section_mut<'a>(t: &'a mut toml::Table, sec: &str) -> &'a mut toml::Table {
    let v = t
        .entry(sec.to_string())
        .or_insert_with(|| toml::Value::Table(toml::Table::new()));
    if !v.is_table() {
        *v = toml::Value::Table(toml::Table::new());
    }
    match v {
        toml::Value::Table(t) => t,
        _ => unreachable!("replaced by a table above"),
    }
}

/// Defaults that depend on other keys, inserted into the raw tree so that the typed structs
/// hold plain values: the name, the load sites (by model and shape) and the snapshot times.
fn fill_context_defaults(t: &mut toml::Table, kind: &str, name: &str) {
    if !t.contains_key("name") {
        t.insert("name".into(), toml::Value::String(name.into()));
    }
    if get(t, "load", "sites").is_none() {
        let shape = get(t, "canopy", "shape")
            .and_then(|v| v.as_str())
            .unwrap_or("rectangle");
        let sites = match (kind, shape) {
            ("rod", _) => "ends",
            (_, "circle") => "rim",
            (_, "mesh") => "center",
            _ => "corners",
        };
        section_mut(t, "load").insert("sites".into(), toml::Value::String(sites.into()));
    }
    fill_adaptive_defaults(t);
    if get(t, "output", "snapshots_s").is_none() {
        let duration = number(t, "time", "duration_s").unwrap_or(super::Time::default().duration_s);
        // k·d/10 rather than 0.k·d keeps round numbers exact (3·10/10 = 3, not 3.0000000000000004).
        let snaps = [3.0, 6.0, 9.0].map(|k| toml::Value::Float(k * duration / 10.0));
        section_mut(t, "output").insert("snapshots_s".into(), toml::Value::Array(snaps.to_vec()));
    }
}

/// A number key of the raw tree (integers widened), when present.
fn number(t: &toml::Table, sec: &str, key: &str) -> Option<f64> {
    match get(t, sec, key) {
        Some(toml::Value::Float(x)) => Some(*x),
        Some(toml::Value::Integer(i)) => Some(*i as f64),
        _ => None,
    }
}

/// With `time.adaptive = true`, the step bounds that are absent get their defaults (so the
/// resolved scenario shows them): `dt_min_s = dt_s/1024`, `dt_max_s = min(100 dt_s,
/// output.frame_interval_s)` (steps end on frame times, so a longer one would never be
/// taken); `error_tolerance_m` is a declared conditional default ([`fill_declared_defaults`]).
/// Without it nothing is added: those keys are then refused by validation.
fn fill_adaptive_defaults(t: &mut toml::Table) {
    if get(t, "time", "adaptive").and_then(|v| v.as_bool()) != Some(true) {
        return;
    }
    let dt = number(t, "time", "dt_s").unwrap_or(super::Time::default().dt_s);
    let frame = number(t, "output", "frame_interval_s")
        .unwrap_or(super::Output::default().frame_interval_s);
    let defaults = [
        ("dt_min_s", super::min_step(dt)),
        ("dt_max_s", (100.0 * dt).min(frame)),
    ];
    let time = section_mut(t, "time");
    for (key, value) in defaults {
        if !time.contains_key(key) {
            time.insert(key.into(), toml::Value::Float(value));
        }
    }
}

/// The declared conditional defaults ([`super::keys::Key::default_with`]): an absent key of a
/// table section gets its value when the condition holds on the tree (or its defaults).
fn fill_declared_defaults(t: &mut toml::Table) {
    for sec in SECTIONS.iter().filter(|s| !s.array && !s.name.is_empty()) {
        for k in sec.keys {
            let Some((cond, value)) = k.meta.default_with else {
                continue;
            };
            if get(t, sec.name, k.name).is_some() || !cond.holds(lookup(t, cond.key).as_ref()) {
                continue;
            }
            section_mut(t, sec.name).insert(k.name.into(), toml::Value::Float(value));
        }
    }
}

/// The value of a table key in the raw tree, else its declared default.
fn lookup(t: &toml::Table, path: &str) -> Option<toml::Value> {
    let p = schema::KeyPath::parse(path);
    let sec = schema::section(p.section)?;
    let written = match p.section {
        "" => t.get(p.key),
        s => get(t, s, p.key),
    };
    written
        .cloned()
        .or_else(|| (sec.defaults)().get(p.key).cloned())
}

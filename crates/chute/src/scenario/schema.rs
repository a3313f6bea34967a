//! The scenario's key table: every section, key and value type, checked on the raw TOML tree
//! before it is converted to typed structs, so that each mistake is reported with its key,
//! its line and (for a misspelt key) the closest known key.
//!
//! A unit test checks that this table and the serde structs name exactly the same keys.

use super::error::ScenarioError;
use super::source::Provenance;

/// The TOML type (and finer constraint) a key accepts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Kind {
    /// Any string.
    Str,
    /// A finite number (integers are accepted and widened).
    Float,
    /// A non-negative integer.
    Count,
    /// `true` or `false`.
    Bool,
    /// One string of a fixed set.
    Choice(&'static [&'static str]),
    /// An array of exactly three finite numbers.
    Vec3,
    /// An array of finite numbers.
    FloatList,
    /// A named site set, or a non-empty array of `[x, y]` pairs.
    Sites,
}

/// Model kinds.
pub const MODEL_KINDS: &[&str] = &["rod", "shell"];
/// Canopy shapes.
pub const SHAPES: &[&str] = &["rectangle", "hexagon", "circle", "mesh"];
/// Load modes.
pub const LOAD_MODES: &[&str] = &["force", "payload", "mass", "node_mass_scale"];
/// Named load-site sets.
pub const SITE_NAMES: &[&str] = &["ends", "corners", "corners_and_midspan", "center", "rim"];
/// Drag laws.
pub const DRAG_LAWS: &[&str] = &["quadratic", "linear"];
/// Shell drag models.
pub const SHELL_DRAG: &[&str] = &["report", "pressure"];

/// Section name, then (key, kind) pairs. The top-level `name` key is listed under "".
pub const SCHEMA: &[(&str, &[(&str, Kind)])] = &[
    ("", &[("name", Kind::Str)]),
    ("model", &[("kind", Kind::Choice(MODEL_KINDS))]),
    (
        "canopy",
        &[
            ("shape", Kind::Choice(SHAPES)),
            ("span_m", Kind::Float),
            ("width_m", Kind::Float),
            ("thickness_m", Kind::Float),
            ("nodes", Kind::Count),
            ("edge_length_m", Kind::Float),
            ("mesh_file", Kind::Str),
            ("radius_m", Kind::Float),
            ("imperfection_m", Kind::Float),
        ],
    ),
    (
        "material",
        &[
            ("youngs_modulus_pa", Kind::Float),
            ("poisson_ratio", Kind::Float),
            ("density_kg_m3", Kind::Float),
        ],
    ),
    (
        "load",
        &[
            ("weight_n", Kind::Float),
            ("mode", Kind::Choice(LOAD_MODES)),
            ("sites", Kind::Sites),
            ("rim_site_count", Kind::Count),
            ("node", Kind::Count),
            ("mass_scale", Kind::Float),
        ],
    ),
    (
        "lines",
        &[
            ("length_m", Kind::Float),
            ("segments", Kind::Count),
            ("radius_m", Kind::Float),
            ("youngs_modulus_pa", Kind::Float),
            ("poisson_ratio", Kind::Float),
            ("density_kg_m3", Kind::Float),
            ("drag_coefficient", Kind::Float),
        ],
    ),
    (
        "fluid",
        &[
            ("density_kg_m3", Kind::Float),
            ("viscosity_pa_s", Kind::Float),
            ("wind_mps", Kind::Vec3),
            ("drag", Kind::Choice(DRAG_LAWS)),
            ("drag_coefficient", Kind::Float),
            ("tangential_drag_coefficient", Kind::Float),
            ("shell_drag", Kind::Choice(SHELL_DRAG)),
            ("linear_drag_coefficient_n_s_m", Kind::Float),
            ("gravity_mps2", Kind::Float),
        ],
    ),
    (
        "time",
        &[
            ("dt_s", Kind::Float),
            ("duration_s", Kind::Float),
            ("newton_max_iterations", Kind::Count),
            ("newton_tolerance_n", Kind::Float),
            ("newton_relative_tolerance", Kind::Float),
            ("newton_step_tolerance_m", Kind::Float),
            ("adaptive", Kind::Bool),
            ("error_tolerance_m", Kind::Float),
            ("dt_min_s", Kind::Float),
            ("dt_max_s", Kind::Float),
        ],
    ),
    (
        "output",
        &[
            ("frame_interval_s", Kind::Float),
            ("snapshots_s", Kind::FloatList),
        ],
    ),
];

/// The keys of a section, or `None` when the section does not exist.
pub fn section(name: &str) -> Option<&'static [(&'static str, Kind)]> {
    SCHEMA
        .iter()
        .find(|(s, _)| *s == name)
        .map(|(_, keys)| *keys)
}

/// The kind of a dotted key (`"canopy.span_m"` or `"name"`), or `None` when unknown.
pub fn kind_of(path: &str) -> Option<Kind> {
    let (sec, key) = split(path);
    section(sec)?
        .iter()
        .find(|(k, _)| *k == key)
        .map(|(_, kind)| *kind)
}

/// Every dotted key the format knows.
pub fn all_keys() -> Vec<String> {
    SCHEMA
        .iter()
        .flat_map(|(s, keys)| keys.iter().map(move |(k, _)| join(s, k)))
        .collect()
}

fn split(path: &str) -> (&str, &str) {
    path.split_once('.').unwrap_or(("", path))
}

fn join(sec: &str, key: &str) -> String {
    if sec.is_empty() {
        key.to_string()
    } else {
        format!("{sec}.{key}")
    }
}

/// The closest known dotted key to an unknown one, when it is close enough to be a typo
/// (or the same key name in another section).
pub fn suggest(path: &str) -> Option<String> {
    let (sec, key) = split(path);
    let close = |a: &str, b: &str| {
        let d = strsim::levenshtein(a, b);
        (d <= (a.len().max(b.len()) / 3).max(2)).then_some(d)
    };
    let mut cands: Vec<(usize, String)> = Vec::new();
    match section(sec) {
        // Known section: a typo of one of its keys, else the same key in another section.
        Some(keys) if path.contains('.') => {
            for (k, _) in keys {
                if let Some(d) = close(key, k) {
                    cands.push((d, join(sec, k)));
                }
            }
            if cands.is_empty() {
                for (s, keys) in SCHEMA {
                    if keys.iter().any(|(k, _)| *k == key) {
                        cands.push((0, join(s, key)));
                    }
                }
            }
        }
        // Unknown section, or a misplaced top-level key: compare with sections and keys.
        _ => {
            for (s, keys) in SCHEMA {
                if !s.is_empty() && path.contains('.') {
                    if let Some(d) = close(sec, s) {
                        if keys.iter().any(|(k, _)| *k == key) {
                            cands.push((d, join(s, key)));
                        }
                    }
                }
                if !s.is_empty() && !path.contains('.') {
                    if let Some(d) = close(key, s) {
                        cands.push((d, format!("[{s}]")));
                    }
                }
                for (k, _) in keys.iter() {
                    if let Some(d) = close(key, k) {
                        cands.push((d, join(s, k)));
                    }
                }
            }
        }
    }
    cands.into_iter().min_by_key(|(d, _)| *d).map(|(_, k)| k)
}

/// Describe a TOML value for a type-mismatch message.
pub fn describe(v: &toml::Value) -> String {
    match v {
        toml::Value::String(s) => format!("the string \"{s}\""),
        toml::Value::Integer(i) => format!("the integer {i}"),
        toml::Value::Float(x) => format!("the number {x}"),
        toml::Value::Boolean(b) => format!("the boolean {b}"),
        toml::Value::Datetime(d) => format!("the date-time {d}"),
        toml::Value::Array(_) => "an array".to_string(),
        toml::Value::Table(_) => "a table".to_string(),
    }
}

/// Check every key and value type of a raw scenario tree; returns the first problem in
/// reading order.
pub fn check(table: &toml::Table, prov: &Provenance) -> Result<(), ScenarioError> {
    let mut errors: Vec<((u8, usize, usize), ScenarioError)> = Vec::new();
    let mut push = |path: &str, e: ScenarioError| errors.push((prov.rank(path), e));
    for (k, v) in table {
        let is_section = !k.is_empty() && section(k).is_some();
        if !is_section {
            match kind_of(k) {
                Some(kind) => check_value(k, kind, v, prov).unwrap_or_else(|e| push(k, e)),
                None => push(k, unknown(k, prov)),
            }
            continue;
        }
        let Some(t) = v.as_table() else {
            push(
                k,
                ScenarioError::WrongType {
                    key: k.clone(),
                    expected: "a table (a `[section]`)",
                    found: describe(v),
                    origin: prov.origin(k),
                },
            );
            continue;
        };
        for (kk, vv) in t {
            let path = join(k, kk);
            match kind_of(&path) {
                Some(kind) => check_value(&path, kind, vv, prov).unwrap_or_else(|e| push(&path, e)),
                None => push(&path, unknown(&path, prov)),
            }
        }
    }
    errors.sort_by_key(|(rank, _)| *rank);
    match errors.into_iter().next() {
        Some((_, e)) => Err(e),
        None => Ok(()),
    }
}

/// The error for an unknown dotted key, with a suggestion when one is close.
pub fn unknown(path: &str, prov: &Provenance) -> ScenarioError {
    ScenarioError::UnknownKey {
        key: path.to_string(),
        origin: prov.origin(path),
        suggestion: suggest(path),
    }
}

fn wrong(path: &str, expected: &'static str, v: &toml::Value, prov: &Provenance) -> ScenarioError {
    ScenarioError::WrongType {
        key: path.to_string(),
        expected,
        found: describe(v),
        origin: prov.origin(path),
    }
}

fn finite(path: &str, v: &toml::Value, prov: &Provenance) -> Result<f64, ScenarioError> {
    let x = match v {
        toml::Value::Integer(i) => *i as f64,
        toml::Value::Float(x) => *x,
        _ => return Err(wrong(path, "a number", v, prov)),
    };
    if x.is_finite() {
        Ok(x)
    } else {
        Err(ScenarioError::Invalid {
            key: path.to_string(),
            value: x.to_string(),
            reason: "must be a finite number (NaN and infinity are not allowed)".into(),
            origin: prov.origin(path),
        })
    }
}

fn number_array(
    path: &str,
    v: &toml::Value,
    expected: &'static str,
    prov: &Provenance,
) -> Result<usize, ScenarioError> {
    let a = v.as_array().ok_or_else(|| wrong(path, expected, v, prov))?;
    for x in a {
        if !matches!(x, toml::Value::Integer(_) | toml::Value::Float(_)) {
            return Err(wrong(path, expected, v, prov));
        }
        finite(path, x, prov)?;
    }
    Ok(a.len())
}

fn check_value(
    path: &str,
    kind: Kind,
    v: &toml::Value,
    prov: &Provenance,
) -> Result<(), ScenarioError> {
    match kind {
        Kind::Str => v
            .as_str()
            .map(|_| ())
            .ok_or_else(|| wrong(path, "a string", v, prov)),
        Kind::Float => finite(path, v, prov).map(|_| ()),
        Kind::Count => match v {
            toml::Value::Integer(i) if *i >= 0 => Ok(()),
            toml::Value::Integer(i) => Err(ScenarioError::Invalid {
                key: path.to_string(),
                value: i.to_string(),
                reason: "must be a non-negative integer".into(),
                origin: prov.origin(path),
            }),
            _ => Err(wrong(path, "an integer", v, prov)),
        },
        Kind::Bool => v
            .as_bool()
            .map(|_| ())
            .ok_or_else(|| wrong(path, "a boolean (true or false)", v, prov)),
        Kind::Choice(allowed) => choice(path, v, allowed, prov),
        Kind::Vec3 => {
            match number_array(path, v, "an array of three numbers, e.g. [0, 0, 0]", prov)? {
                3 => Ok(()),
                _ => Err(wrong(
                    path,
                    "an array of three numbers, e.g. [0, 0, 0]",
                    v,
                    prov,
                )),
            }
        }
        Kind::FloatList => number_array(path, v, "an array of numbers", prov).map(|_| ()),
        Kind::Sites => sites(path, v, prov),
    }
}

fn choice(
    path: &str,
    v: &toml::Value,
    allowed: &'static [&'static str],
    prov: &Provenance,
) -> Result<(), ScenarioError> {
    let s = v.as_str().ok_or_else(|| wrong(path, "a string", v, prov))?;
    if allowed.contains(&s) {
        Ok(())
    } else {
        Err(ScenarioError::BadChoice {
            key: path.to_string(),
            value: s.to_string(),
            allowed,
            context: "",
            origin: prov.origin(path),
        })
    }
}

const SITES_EXPECTED: &str = "a site name or a non-empty array of [x, y] pairs";

fn sites(path: &str, v: &toml::Value, prov: &Provenance) -> Result<(), ScenarioError> {
    match v {
        toml::Value::String(_) => choice(path, v, SITE_NAMES, prov),
        toml::Value::Array(a) if !a.is_empty() => {
            for p in a {
                if number_array(path, p, SITES_EXPECTED, prov)? != 2 {
                    return Err(wrong(path, SITES_EXPECTED, v, prov));
                }
            }
            Ok(())
        }
        _ => Err(wrong(path, SITES_EXPECTED, v, prov)),
    }
}

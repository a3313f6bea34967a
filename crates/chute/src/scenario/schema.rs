//! The raw-tree check: every section, key and value type of a scenario, before the tree is
//! converted to typed structs, so that each mistake is reported with its key, its line and
//! (for a misspelt key) the closest known key. The keys and their kinds come from the
//! declarations in [`super::sections`]; every function here also takes an explicit section
//! list (`*_in`), which the unit tests use for sections the format does not have yet.

use super::error::short;
use super::error::ScenarioError;
pub use super::keys::Kind;
use super::keys::{KeyDecl, Section};
use super::sections::{SiteSet, SECTIONS};
use super::source::Provenance;

/// A key path split into its parts: `name`, `canopy.span_m`, `control[1].lines`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct KeyPath<'a> {
    /// Section name (`""` for a top-level key).
    pub section: &'a str,
    /// Entry of an array of tables.
    pub index: Option<usize>,
    /// Key name.
    pub key: &'a str,
}

impl<'a> KeyPath<'a> {
    /// Split a dotted path (a path without a dot is a top-level key).
    pub fn parse(path: &'a str) -> Self {
        let Some((head, key)) = path.split_once('.') else {
            return KeyPath {
                section: "",
                index: None,
                key: path,
            };
        };
        let (section, index) = match head.strip_suffix(']').and_then(|h| h.split_once('[')) {
            Some((s, i)) => (s, i.parse().ok()),
            None => (head, None),
        };
        KeyPath {
            section,
            index,
            key,
        }
    }
}

/// `section.key`, `section[i].key` or `key`.
pub fn join(section: &str, index: Option<usize>, key: &str) -> String {
    match (section.is_empty(), index) {
        (true, _) => key.to_string(),
        (false, None) => format!("{section}.{key}"),
        (false, Some(i)) => format!("{section}[{i}].{key}"),
    }
}

/// The section named `name` (`""`: the top-level keys).
pub fn section_in<'s>(sections: &'s [Section], name: &str) -> Option<&'s Section> {
    sections.iter().find(|s| s.name == name)
}

/// The section named `name` of the scenario format.
pub fn section(name: &str) -> Option<&'static Section> {
    section_in(SECTIONS, name)
}

/// The kind of a key path in `sections`, or `None` when unknown (an array entry's key needs
/// its index, a table's key must not have one).
pub fn kind_in(sections: &[Section], path: &str) -> Option<Kind> {
    let p = KeyPath::parse(path);
    let sec = section_in(sections, p.section)?;
    if sec.array != p.index.is_some() {
        return None;
    }
    sec.key(p.key).map(|k| k.kind)
}

/// The kind of a dotted key (`"canopy.span_m"` or `"name"`), or `None` when unknown.
pub fn kind_of(path: &str) -> Option<Kind> {
    kind_in(SECTIONS, path)
}

/// Every key path the format knows (array entries as entry 0).
pub fn all_keys() -> Vec<String> {
    SECTIONS
        .iter()
        .flat_map(|s| {
            let index = s.array.then_some(0);
            s.keys.iter().map(move |k| join(s.name, index, k.name))
        })
        .collect()
}

/// The closest known key to an unknown one, when it is close enough to be a typo (or the
/// same key name in another section).
pub fn suggest(path: &str) -> Option<String> {
    suggest_in(SECTIONS, path)
}

/// [`suggest`] over `sections`; an array entry's index is kept.
pub fn suggest_in(sections: &[Section], path: &str) -> Option<String> {
    let p = KeyPath::parse(path);
    let dotted = path.contains('.');
    let close = |a: &str, b: &str| {
        let d = strsim::levenshtein(a, b);
        (d <= (a.len().max(b.len()) / 3).max(2)).then_some(d)
    };
    let at = |s: &Section, key: &str| join(s.name, s.array.then_some(p.index.unwrap_or(0)), key);
    let mut cands: Vec<(usize, String)> = Vec::new();
    match section_in(sections, p.section) {
        // Known section: a typo of one of its keys, else the same key in another section.
        Some(sec) if dotted => {
            for k in sec.keys {
                if let Some(d) = close(p.key, k.name) {
                    cands.push((d, at(sec, k.name)));
                }
            }
            if cands.is_empty() {
                for s in sections {
                    if s.key(p.key).is_some() {
                        cands.push((0, at(s, p.key)));
                    }
                }
            }
        }
        // Unknown section, or a misplaced top-level key: compare with sections and keys.
        _ => {
            for s in sections {
                if !s.name.is_empty() && dotted {
                    if let Some(d) = close(p.section, s.name) {
                        if s.key(p.key).is_some() {
                            cands.push((d, at(s, p.key)));
                        }
                    }
                }
                if !s.name.is_empty() && !dotted {
                    if let Some(d) = close(p.key, s.name) {
                        let header = if s.array { "[[{}]]" } else { "[{}]" };
                        cands.push((d, header.replace("{}", s.name)));
                    }
                }
                for k in s.keys {
                    if let Some(d) = close(p.key, k.name) {
                        cands.push((d, at(s, k.name)));
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
        toml::Value::Float(x) => {
            // As written: a float keeps its point (`61.0`), so it is not mistaken for 61.
            let s = short(*x);
            let point = if s.contains(['.', 'e', 'N', 'i']) {
                ""
            } else {
                ".0"
            };
            format!("the number {s}{point}")
        }
        toml::Value::Boolean(b) => format!("the boolean {b}"),
        toml::Value::Datetime(d) => format!("the date-time {d}"),
        toml::Value::Array(a) => {
            let numbers = a
                .iter()
                .all(|x| matches!(x, toml::Value::Integer(_) | toml::Value::Float(_)));
            let what = match (numbers, a.len()) {
                (true, 1) => "number",
                (true, _) => "numbers",
                (false, 1) => "value",
                (false, _) => "values",
            };
            format!("an array of {} {what}", a.len())
        }
        toml::Value::Table(_) => "a table".to_string(),
    }
}

/// Check every key and value type of a raw scenario tree; returns the first problem in
/// reading order.
pub fn check(table: &toml::Table, prov: &Provenance) -> Result<(), ScenarioError> {
    check_in(SECTIONS, table, prov)
}

/// [`check`] against `sections`.
pub fn check_in(
    sections: &[Section],
    table: &toml::Table,
    prov: &Provenance,
) -> Result<(), ScenarioError> {
    let mut errors = Errors::default();
    let top = section_in(sections, "");
    for (k, v) in table {
        let sec = section_in(sections, k).filter(|s| !s.name.is_empty());
        let Some(sec) = sec else {
            // A top-level key (or an unknown section or key).
            match top.and_then(|t| t.key(k)) {
                Some(d) => errors.value(k, d, v, prov),
                None => errors.push(k, unknown_in(sections, k, prov), prov),
            }
            continue;
        };
        match (sec.array, v) {
            (false, toml::Value::Table(t)) => errors.keys(sections, sec, None, t, prov),
            (true, toml::Value::Array(entries)) => {
                for (i, e) in entries.iter().enumerate() {
                    match e.as_table() {
                        Some(t) => errors.keys(sections, sec, Some(i), t, prov),
                        None => {
                            let path = format!("{k}[{i}]");
                            errors.push(&path, wrong(&path, "a table", e, prov), prov);
                        }
                    }
                }
            }
            (array, _) => {
                let expected = if array {
                    "an array of tables (`[[section]]` entries)"
                } else {
                    "a table (a `[section]`)"
                };
                errors.push(k, wrong(k, expected, v, prov), prov);
            }
        }
    }
    errors.first()
}

/// Problems found so far, each with its place in reading order.
#[derive(Default)]
struct Errors(Vec<((u8, usize, usize), ScenarioError)>);

impl Errors {
    fn push(&mut self, path: &str, e: ScenarioError, prov: &Provenance) {
        self.0.push((prov.rank(path), e));
    }

    fn value(&mut self, path: &str, decl: &KeyDecl, v: &toml::Value, prov: &Provenance) {
        if let Err(e) = check_value(path, decl, v, prov) {
            self.push(path, e, prov);
        }
    }

    /// The keys of one table of section `sec` (entry `index` of an array of tables).
    fn keys(
        &mut self,
        sections: &[Section],
        sec: &Section,
        index: Option<usize>,
        t: &toml::Table,
        prov: &Provenance,
    ) {
        for (k, v) in t {
            let path = join(sec.name, index, k);
            match sec.key(k) {
                Some(d) => self.value(&path, d, v, prov),
                None => self.push(&path, unknown_in(sections, &path, prov), prov),
            }
        }
    }

    fn first(mut self) -> Result<(), ScenarioError> {
        self.0.sort_by_key(|(rank, _)| *rank);
        match self.0.into_iter().next() {
            Some((_, e)) => Err(e),
            None => Ok(()),
        }
    }
}

/// The first required key that is absent: keys of every section that is not optional, of
/// an optional section that is written, and of every entry of an array of tables.
pub fn required(table: &toml::Table) -> Result<(), ScenarioError> {
    required_in(SECTIONS, table)
}

/// [`required`] against `sections`.
pub fn required_in(sections: &[Section], table: &toml::Table) -> Result<(), ScenarioError> {
    for sec in sections {
        let written = if sec.name.is_empty() {
            Some(toml::Value::Table(table.clone()))
        } else {
            table.get(sec.name).cloned()
        };
        let entries: Vec<(Option<usize>, Option<toml::Table>)> = match written {
            Some(toml::Value::Array(a)) => a
                .into_iter()
                .enumerate()
                .map(|(i, e)| (Some(i), e.as_table().cloned()))
                .collect(),
            Some(toml::Value::Table(t)) => vec![(None, Some(t))],
            _ if sec.optional || sec.array => Vec::new(),
            _ => vec![(None, None)],
        };
        for (index, t) in entries {
            for k in sec.keys {
                let (Some(reason), false) = (
                    k.meta.required,
                    t.as_ref().is_some_and(|t| t.contains_key(k.name)),
                ) else {
                    continue;
                };
                return Err(ScenarioError::Missing {
                    key: join(sec.name, index, k.name),
                    reason: reason.into(),
                });
            }
        }
    }
    Ok(())
}

/// The error for an unknown dotted key, with a suggestion when one is close.
pub fn unknown(path: &str, prov: &Provenance) -> ScenarioError {
    unknown_in(SECTIONS, path, prov)
}

/// Keys of earlier versions that are no longer read, and why (a scenario that still sets one
/// is refused with this reason rather than a "did you mean").
const RETIRED: [(&str, &str); 3] = [
    (
        "time.newton_exact_retry",
        "every step goes through the step solver's ladder of stages (docs/engine.md §The step \
         solver); `time.newton_rescue_stages = false` halves a failed step at once",
    ),
    (
        "time.newton_continuation",
        "it is one of the rescue stages, switched together by `time.newton_rescue_stages`",
    ),
    (
        "time.newton_step_homotopy",
        "it is one of the rescue stages, switched together by `time.newton_rescue_stages`",
    ),
];

fn unknown_in(sections: &[Section], path: &str, prov: &Provenance) -> ScenarioError {
    if let Some((_, why)) = RETIRED.iter().find(|(k, _)| *k == path) {
        return ScenarioError::RetiredKey {
            key: path.to_string(),
            origin: prov.origin(path),
            why,
        };
    }
    ScenarioError::UnknownKey {
        key: path.to_string(),
        origin: prov.origin(path),
        suggestion: suggest_in(sections, path),
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
            value: short(x),
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

fn count_array(path: &str, v: &toml::Value, prov: &Provenance) -> Result<(), ScenarioError> {
    let expected = "an array of non-negative integers";
    let a = v.as_array().ok_or_else(|| wrong(path, expected, v, prov))?;
    for x in a {
        match x {
            toml::Value::Integer(i) if *i >= 0 => {}
            _ => return Err(wrong(path, expected, v, prov)),
        }
    }
    Ok(())
}

fn check_value(
    path: &str,
    decl: &KeyDecl,
    v: &toml::Value,
    prov: &Provenance,
) -> Result<(), ScenarioError> {
    match decl.kind {
        Kind::Str => v
            .as_str()
            .map(|_| ())
            .ok_or_else(|| wrong(path, "a string", v, prov)),
        Kind::Float => finite(path, v, prov).map(|_| ()),
        Kind::Count => count(path, decl, v, prov),
        Kind::Bool => v
            .as_bool()
            .map(|_| ())
            .ok_or_else(|| wrong(path, "a boolean (true or false)", v, prov)),
        Kind::Choice(allowed) => choice(path, v, allowed, prov),
        Kind::Vector(n) => {
            let want = match n {
                2 => "an array of two numbers, e.g. [0, 0]",
                3 => "an array of three numbers, e.g. [0, 0, 0]",
                _ => "an array of numbers of the key's length",
            };
            match number_array(path, v, want, prov)? {
                len if len == n => Ok(()),
                _ => Err(wrong(path, want, v, prov)),
            }
        }
        Kind::FloatList => number_array(path, v, "an array of numbers", prov).map(|_| ()),
        Kind::CountList => count_array(path, v, prov),
        Kind::Sites => sites(path, v, prov),
    }
}

/// A count: a non-negative integer. A whole number out of the key's range (`1e9`, `-3`) is
/// reported with the range, the real reason, rather than with its type.
fn count(
    path: &str,
    decl: &KeyDecl,
    v: &toml::Value,
    prov: &Provenance,
) -> Result<(), ScenarioError> {
    let x = match v {
        toml::Value::Integer(i) if *i >= 0 => return Ok(()),
        toml::Value::Integer(i) => *i as f64,
        toml::Value::Float(x) if x.is_finite() && x.fract() == 0.0 => *x,
        _ => return Err(wrong(path, "an integer", v, prov)),
    };
    let invalid = |reason: String| ScenarioError::Invalid {
        key: path.to_string(),
        value: short(x),
        reason,
        origin: prov.origin(path),
    };
    match decl.meta.range {
        Some(r) if !r.contains(x) => Err(invalid(format!("must {} ({})", r.requirement(), r.why))),
        _ if x < 0.0 => Err(invalid("must be a non-negative integer".into())),
        // A whole number in range written as a float (`61.0`, `1e3`).
        _ => Err(wrong(
            path,
            "an integer (written without a decimal point or exponent)",
            v,
            prov,
        )),
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
        toml::Value::String(_) => choice(path, v, SiteSet::NAMES, prov),
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

//! The rules declared with each key ([`super::keys::Key`]), checked generically on the
//! resolved tree (every default filled in, optional keys absent when unset): "required
//! with", "only with" and the range, in that order, so each key gets the most telling error.

use super::error::ScenarioError;
use super::keys::{Cond, KeyDecl, Section};
use super::schema::{self, join, KeyPath};
use super::validate::Checker;

/// Check every declared rule of `sections` on the resolved tree `tree`.
pub(super) fn declared(c: &mut Checker, sections: &[Section], tree: &toml::Table) {
    for sec in sections {
        let entries: Vec<(Option<usize>, &toml::Table)> = match (sec.name, tree.get(sec.name)) {
            ("", _) => vec![(None, tree)],
            (_, Some(toml::Value::Table(t))) => vec![(None, t)],
            (_, Some(toml::Value::Array(a))) => a
                .iter()
                .enumerate()
                .filter_map(|(i, e)| Some((Some(i), e.as_table()?)))
                .collect(),
            _ => Vec::new(),
        };
        if let (Some((cond, why)), false) = (sec.only_with, entries.is_empty()) {
            if (sec.optional || sec.array) && !cond.holds(lookup(tree, cond.key)) {
                let header = if sec.array { "[[{}]]" } else { "[{}]" };
                c.fail(
                    sec.name,
                    header.replace("{}", sec.name),
                    format!("only used with `{}`{why}", show(sections, &cond)),
                );
                continue;
            }
        }
        for (index, t) in entries {
            for k in sec.keys {
                let path = join(sec.name, index, k.name);
                key(c, sections, tree, &path, k, t.get(k.name));
            }
        }
    }
}

/// The declared rules of one key at `path`, whose resolved value is `v`.
fn key(
    c: &mut Checker,
    sections: &[Section],
    tree: &toml::Table,
    path: &str,
    k: &KeyDecl,
    v: Option<&toml::Value>,
) {
    let m = &k.meta;
    let Some(v) = v else {
        if let Some((cond, why)) = m.required_with {
            if cond.holds(lookup(tree, cond.key)) {
                let e = ScenarioError::Missing {
                    key: path.to_string(),
                    reason: format!("`{}` {why}", show(sections, &cond)),
                };
                c.push(cond.key, e);
            }
        }
        return;
    };
    if let Some((cond, why)) = m.only_with {
        if !cond.holds(lookup(tree, cond.key)) {
            let reason = format!("only used with `{}`{why}", show(sections, &cond));
            c.fail(path, value(v), reason);
            return;
        }
    }
    let Some(range) = m.range else {
        return;
    };
    if m.range_when.is_some_and(|w| !w.holds(lookup(tree, w.key))) {
        return;
    }
    let numbers: Vec<&toml::Value> = match v {
        toml::Value::Array(a) => a.iter().collect(),
        v => vec![v],
    };
    for x in numbers {
        let f = match x {
            toml::Value::Float(f) => *f,
            toml::Value::Integer(i) => *i as f64,
            _ => continue,
        };
        if !range.contains(f) {
            let reason = format!("must {} ({})", range.requirement(), range.why);
            c.fail(path, value(x), reason);
            return;
        }
    }
}

/// The value of a key path in the resolved tree.
fn lookup<'t>(tree: &'t toml::Table, path: &str) -> Option<&'t toml::Value> {
    let p = KeyPath::parse(path);
    let table = match (p.section, p.index) {
        ("", _) => tree,
        (s, None) => tree.get(s)?.as_table()?,
        (s, Some(i)) => tree.get(s)?.as_array()?.get(i)?.as_table()?,
    };
    table.get(p.key)
}

/// A condition as written in a file.
fn show(sections: &[Section], cond: &Cond) -> String {
    cond.display(schema::kind_in(sections, cond.key))
}

/// A value as the messages show it: numbers plain, strings quoted.
fn value(v: &toml::Value) -> String {
    match v {
        toml::Value::Float(x) => super::error::short(*x),
        toml::Value::String(s) => format!("\"{s}\""),
        v => v.to_string(),
    }
}

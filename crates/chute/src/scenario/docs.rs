//! The key tables of `docs/scenarios.md`, generated from the declarations in
//! [`super::sections`]. Each table stands between the markers `<!-- keys: SECTION -->` and
//! `<!-- /keys -->` (`top-level` for the keys outside any section); the text around them is
//! written by hand. A test checks that the page holds exactly what [`update`] generates, and
//! rewrites it when run with `CHUTE_BLESS=1` (docs/architecture.md §How a scenario key flows).

use super::keys::{Kind, Section};
use super::schema;
use super::sections::SECTIONS;

const OPEN: &str = "<!-- keys: ";
const CLOSE: &str = "<!-- /keys -->";

/// The marker name of a section.
pub fn marker(sec: &Section) -> &'static str {
    if sec.name.is_empty() {
        "top-level"
    } else {
        sec.name
    }
}

/// `text` with every key table replaced by the generated one; an error names a marker
/// without its section (or unclosed), or a section without its marker.
pub fn update(text: &str) -> Result<String, String> {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    let mut seen = Vec::new();
    while let Some(start) = rest.find(OPEN) {
        let after = &rest[start + OPEN.len()..];
        let name_end = after
            .find(" -->")
            .ok_or("a `<!-- keys: ` marker is not closed with ` -->`")?;
        let name = after[..name_end].trim();
        let sec = SECTIONS
            .iter()
            .find(|s| marker(s) == name)
            .ok_or_else(|| format!("marker `<!-- keys: {name} -->` names no section"))?;
        let body = &after[name_end + 4..];
        let end = body
            .find(CLOSE)
            .ok_or_else(|| format!("`<!-- keys: {name} -->` has no `{CLOSE}`"))?;
        out.push_str(&rest[..start]);
        out.push_str(&format!(
            "{OPEN}{name} -->\n{}{CLOSE}",
            table(SECTIONS, sec)
        ));
        seen.push(name.to_string());
        rest = &body[end + CLOSE.len()..];
    }
    out.push_str(rest);
    if let Some(missing) = SECTIONS
        .iter()
        .find(|s| !seen.iter().any(|n| n == marker(s)))
    {
        return Err(format!(
            "no table for section `{}`: add `<!-- keys: {} -->` and `{CLOSE}` where it belongs",
            marker(missing),
            marker(missing)
        ));
    }
    Ok(out)
}

/// The Markdown table of the keys of `sec`, one of `sections`.
pub fn table(sections: &[Section], sec: &Section) -> String {
    let defaults = (sec.defaults)();
    let mut s =
        String::from("| key | meaning | unit | default | allowed |\n|---|---|---|---|---|\n");
    for k in sec.keys {
        let m = &k.meta;
        let mut default = match (m.required, m.default_doc, m.default_with) {
            (Some(_), ..) => "**required**".to_string(),
            (_, Some(text), _) => text.to_string(),
            (_, _, Some((_, x))) => number(x),
            // A boolean is written back only when true (so old scenarios resolve as before).
            _ if k.kind == Kind::Bool && !defaults.contains_key(k.name) => "`false`".into(),
            _ => defaults.get(k.name).map_or("none".into(), value),
        };
        if !m.default_note.is_empty() {
            default = format!("{default} ({})", m.default_note);
        }
        let cells = [
            format!("`{}`", k.name),
            words(k.doc),
            m.unit.to_string(),
            default,
            allowed(sections, k),
        ];
        let cells: Vec<String> = cells.iter().map(|c| c.replace('|', "\\|")).collect();
        s += &format!("| {} |\n", cells.join(" | "));
    }
    s
}

/// The "allowed" column: the type's values, the range, the notes, the conditions.
fn allowed(sections: &[Section], k: &super::keys::KeyDecl) -> String {
    let m = &k.meta;
    let list = matches!(k.kind, Kind::FloatList | Kind::CountList);
    let mut parts: Vec<String> = Vec::new();
    let of_kind = match k.kind {
        Kind::Choice(names) => names
            .iter()
            .map(|n| format!("`{n}`"))
            .collect::<Vec<_>>()
            .join(", "),
        Kind::Bool => "`true`, `false`".into(),
        Kind::Vector(3) => "three finite numbers".into(),
        Kind::Vector(n) => format!("{n} finite numbers"),
        Kind::CountList if m.range.is_none() => "non-negative integers".into(),
        Kind::Float if m.range.is_none() => "any finite number".into(),
        _ => String::new(),
    };
    parts.push(of_kind);
    if let Some(r) = m.range {
        let each = if list { "each " } else { "" };
        let when = m
            .range_when
            .map(|c| format!(" when `{}`", c.display(schema::kind_in(sections, c.key))))
            .unwrap_or_default();
        parts.push(format!("{each}{}{when}", r.doc()));
    }
    parts.push(m.note.to_string());
    let show = |c: &super::keys::Cond| c.display(schema::kind_in(sections, c.key));
    match (m.only_with, m.required_with) {
        (Some((a, _)), Some((b, _))) if a == b => {
            parts.push(format!(
                "required with, and only allowed with, `{}`",
                show(&a)
            ));
        }
        (only, req) => {
            if let Some((c, _)) = only {
                parts.push(format!("only with `{}`", show(&c)));
            }
            if let Some((c, _)) = req {
                parts.push(format!("required with `{}`", show(&c)));
            }
        }
    }
    parts.retain(|p| !p.is_empty());
    parts.join("; ")
}

/// Doc lines joined into one line.
fn words(doc: &str) -> String {
    doc.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// A default value as the docs show it.
fn value(v: &toml::Value) -> String {
    match v {
        toml::Value::Float(x) => number(*x),
        toml::Value::Integer(i) => i.to_string(),
        toml::Value::String(s) => format!("`{s}`"),
        toml::Value::Boolean(b) => format!("`{b}`"),
        toml::Value::Array(a) => {
            let items: Vec<String> = a.iter().map(value).collect();
            format!("[{}]", items.join(", "))
        }
        v => v.to_string(),
    }
}

/// Plain notation between 1e-3 and 1e5, else scientific (`5.5e10`, `1.81e-5`).
fn number(x: f64) -> String {
    if x == 0.0 || (1e-3..1e5).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

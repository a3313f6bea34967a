//! Scenario errors: one variant per class of mistake, each naming the key and where its value
//! came from (file and line, a `--set` override, or a built-in default).

use std::fmt;
use std::path::PathBuf;

/// Where a scenario value came from; printed after the message so the user can find it.
#[derive(Debug, Clone, PartialEq)]
pub enum Origin {
    /// Written in the scenario file, at a 1-based line and column.
    File {
        /// The file as the user named it.
        file: String,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        col: usize,
    },
    /// Given on the command line as `--set <arg>`.
    Set(String),
    /// Not written anywhere: a built-in default.
    Default,
}

impl fmt::Display for Origin {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Origin::File { file, line, .. } => write!(f, "{file}:{line}"),
            Origin::Set(arg) => write!(f, "from `--set {arg}`"),
            Origin::Default => write!(f, "default value"),
        }
    }
}

/// Everything that can be wrong with a scenario. `Display` is one self-contained message.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ScenarioError {
    /// The scenario file cannot be read.
    #[error("cannot read scenario file `{}`: {reason}", path.display())]
    Read {
        /// The path as given.
        path: PathBuf,
        /// The operating system's reason.
        reason: String,
    },
    /// The text is not valid TOML.
    #[error("{file}:{line}:{col}: TOML syntax error: {message}")]
    Syntax {
        /// The file as the user named it.
        file: String,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        col: usize,
        /// The parser's description.
        message: String,
    },
    /// A `--set` argument that is not of the form `section.key=value`.
    #[error("invalid override `--set {arg}`: {reason}")]
    BadOverride {
        /// The argument as given.
        arg: String,
        /// What is wrong with it.
        reason: String,
    },
    /// A key the scenario format does not know.
    #[error("unknown key `{key}` ({origin}){}", suggestion_text(suggestion))]
    UnknownKey {
        /// Dotted key path.
        key: String,
        /// Where it was written.
        origin: Origin,
        /// The closest known key, when one is close.
        suggestion: Option<String>,
    },
    /// A key that earlier versions of chute read and this one no longer does.
    #[error("`{key}` ({origin}) is no longer a scenario key: {why}; remove it")]
    RetiredKey {
        /// Dotted key path.
        key: String,
        /// Where it was written.
        origin: Origin,
        /// What replaced it.
        why: &'static str,
    },
    /// A required key is absent.
    #[error("missing required key `{key}`: {reason}")]
    Missing {
        /// Dotted key path.
        key: String,
        /// Why it is needed and what it may be.
        reason: String,
    },
    /// A value of the wrong TOML type.
    #[error("`{key}` ({origin}) must be {expected}, found {found}")]
    WrongType {
        /// Dotted key path.
        key: String,
        /// The expected type, in words.
        expected: &'static str,
        /// The value found, in words.
        found: String,
        /// Where it was written.
        origin: Origin,
    },
    /// A string outside its set of allowed values.
    #[error(
        "`{key}` ({origin}) = \"{value}\" is not allowed{}; allowed values: {}",
        context_text(context),
        quote_list(allowed)
    )]
    BadChoice {
        /// Dotted key path.
        key: String,
        /// The value given.
        value: String,
        /// The values allowed here.
        allowed: &'static [&'static str],
        /// Why the set is restricted here (e.g. "for a rod model"), or empty.
        context: &'static str,
        /// Where it was written.
        origin: Origin,
    },
    /// A value of the right type but physically or numerically impossible.
    #[error("`{key}` ({origin}) = {value} is invalid: {reason}")]
    Invalid {
        /// Dotted key path.
        key: String,
        /// The value as written.
        value: String,
        /// Why it cannot be used.
        reason: String,
        /// Where it was written.
        origin: Origin,
    },
    /// A load site outside the canopy's shape.
    #[error(
        "`{key}` ({origin}): load site {index} at ({x}, {y}) m lies outside the canopy ({shape})"
    )]
    SiteOutside {
        /// Dotted key path (`load.sites`).
        key: String,
        /// 0-based index of the site in the list.
        index: usize,
        /// Site x coordinate (m).
        x: f64,
        /// Site y coordinate (m).
        y: f64,
        /// The canopy outline, in words.
        shape: String,
        /// Where it was written.
        origin: Origin,
    },
    /// The mesh file named by `canopy.mesh_file` does not exist.
    #[error("`{key}` ({origin}): mesh file `{}` does not exist", path.display())]
    MeshMissing {
        /// Dotted key path (`canopy.mesh_file`).
        key: String,
        /// The resolved path.
        path: PathBuf,
        /// Where it was written.
        origin: Origin,
    },
}

fn suggestion_text(s: &Option<String>) -> String {
    match s {
        Some(k) => format!("; did you mean `{k}`?"),
        None => String::new(),
    }
}

fn context_text(c: &str) -> String {
    if c.is_empty() {
        String::new()
    } else {
        format!(" {c}")
    }
}

fn quote_list(items: &[&str]) -> String {
    items
        .iter()
        .map(|s| format!("\"{s}\""))
        .collect::<Vec<_>>()
        .join(", ")
}

impl ScenarioError {
    /// The dotted key the error is about, when there is one.
    pub fn key(&self) -> Option<&str> {
        match self {
            ScenarioError::UnknownKey { key, .. }
            | ScenarioError::RetiredKey { key, .. }
            | ScenarioError::Missing { key, .. }
            | ScenarioError::WrongType { key, .. }
            | ScenarioError::BadChoice { key, .. }
            | ScenarioError::Invalid { key, .. }
            | ScenarioError::SiteOutside { key, .. }
            | ScenarioError::MeshMissing { key, .. } => Some(key),
            _ => None,
        }
    }
}

/// A number as messages show it: plain when that is short (`0.05`, `200`, `-3`), else in
/// exponent form (`1e308`, `5.5e10`, `1e-7`), never hundreds of digits; it reads back exactly.
pub fn short(x: f64) -> String {
    let plain = x.to_string();
    let exp = format!("{x:e}");
    if plain.len() > 6 && exp.len() < plain.len() {
        exp
    } else {
        plain
    }
}

#[cfg(test)]
mod tests {
    use super::short;

    #[test]
    fn numbers_in_short_form() {
        for (x, s) in [
            (1e308, "1e308"),
            (55e9, "5.5e10"),
            (0.05, "0.05"),
            (200.0, "200"),
            (-3.0, "-3"),
            (1e-7, "1e-7"),
            (1e12, "1e12"),
            (123_456.0, "123456"),
            (12_345_678.0, "12345678"),
            (1e9, "1e9"),
        ] {
            assert_eq!(short(x), s);
            assert_eq!(short(x).parse::<f64>().unwrap(), x);
        }
    }
}

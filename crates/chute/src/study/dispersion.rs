//! A study's `[dispersion]`: `samples` cases whose scenario keys are drawn from named
//! distributions ([`super::draw`]); sample `i` is case `sample-NNNNN` with its values as
//! `--set` overrides, computed from (seed, `i`) alone.
//!
//! ```toml
//! [dispersion]
//! samples = 100
//! seed = 7
//! latin_hypercube = true
//! [[dispersion.vary]]
//! key = "load.weight_n"
//! normal = { mean = 250.0, std_dev = 10.0, lo = 200.0, hi = 300.0 }
//! [[dispersion.vary]]
//! key = "fluid.wind_mps[0]"        # one component of a vector key
//! uniform = { lo = 2.0, hi = 6.0 }
//! ```
//!
//! The other components of a vector key keep the base scenario's values (zeros for a vector
//! key it leaves unset, such as `canopy.release_point_m`). `set = ["KEY=VALUE", …]` applies to
//! every sample before its draws.

use std::path::Path;

use serde::Deserialize;

use super::draw::{Distribution, Sampler};
use super::{input, Case};
use crate::app::AppError;
use crate::scenario::Scenario;

/// Most samples of one study (the grid's limit on cases).
pub const MAX_SAMPLES: usize = 100_000;

/// `[dispersion]` as written.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct DispersionSpec {
    samples: usize,
    seed: u64,
    #[serde(default)]
    latin_hypercube: bool,
    /// Overrides every sample shares, before its drawn values (a coarser mesh, say).
    #[serde(default)]
    set: Vec<String>,
    vary: Vec<VarySpec>,
}

/// One `[[dispersion.vary]]`: a key and exactly one distribution.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct VarySpec {
    key: String,
    normal: Option<NormalSpec>,
    uniform: Option<Interval>,
    triangular: Option<TriangleSpec>,
}

#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
struct NormalSpec {
    mean: f64,
    std_dev: f64,
    lo: Option<f64>,
    hi: Option<f64>,
}

#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
struct Interval {
    lo: f64,
    hi: f64,
}

#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
struct TriangleSpec {
    lo: f64,
    mode: f64,
    hi: f64,
}

/// A varied key: a scalar key, or component `index` of a vector key.
#[derive(Debug, Clone, PartialEq)]
struct Target {
    key: String,
    index: Option<usize>,
}

impl Target {
    /// `fluid.wind_mps[0]` → (`fluid.wind_mps`, 0); a key without `[k]` is a scalar.
    fn parse(key: &str) -> Result<Self, String> {
        let key = key.trim();
        let Some(open) = key
            .strip_suffix(']')
            .and_then(|k| k.rfind('[').map(|i| (k, i)))
        else {
            return Ok(Self {
                key: key.to_string(),
                index: None,
            });
        };
        let (k, i) = open;
        let digits = &k[i + 1..];
        let index = (digits.bytes().all(|b| b.is_ascii_digit()))
            .then(|| digits.parse().ok())
            .flatten()
            .ok_or_else(|| {
                format!("`{key}`: the component must be a number, as in `fluid.wind_mps[0]`")
            })?;
        Ok(Self {
            key: k[..i].trim().to_string(),
            index: Some(index),
        })
    }
}

impl DispersionSpec {
    /// The cases of the dispersion over `base` (which gives the other components of a vector
    /// key and checks every key).
    pub(super) fn cases(&self, base: &Path) -> Result<Vec<Case>, AppError> {
        if self.samples < 2 || self.samples > MAX_SAMPLES {
            return Err(input(format!(
                "`dispersion.samples` = {}: give 2 to {MAX_SAMPLES} (a footprint needs two landings)",
                self.samples
            )));
        }
        if self.vary.is_empty() {
            return Err(input(
                "`[dispersion]` varies nothing: add `[[dispersion.vary]]` tables",
            ));
        }
        let (targets, dists) = self.inputs()?;
        refuse_drawn_overrides(&self.varied_keys(), &self.set, "`dispersion.set`", false)?;
        let vectors = base_vectors(base, &self.set, &targets, &dists)?;
        let sampler = Sampler {
            seed: self.seed,
            samples: self.samples,
            latin_hypercube: self.latin_hypercube,
        };
        Ok(sampler
            .draw_all(&dists)
            .into_iter()
            .enumerate()
            .map(|(index, values)| Case {
                index,
                name: format!("sample-{index:05}"),
                set: [self.set.clone(), overrides(&targets, &values, &vectors)].concat(),
            })
            .collect())
    }

    /// The drawn keys as `dispersion.csv` names them (`key`, or `key[i]` for a component),
    /// written one way whatever the file's spelling (`fluid.wind_mps [00]` is
    /// `fluid.wind_mps[0]`); a key that does not parse is refused by [`Self::cases`] first.
    pub(super) fn varied_keys(&self) -> Vec<String> {
        let name = |v: &VarySpec| match Target::parse(&v.key) {
            Ok(Target {
                key,
                index: Some(i),
            }) => format!("{key}[{i}]"),
            Ok(Target { key, index: None }) => key,
            Err(_) => v.key.trim().to_string(),
        };
        self.vary.iter().map(name).collect()
    }

    /// The varied keys and their distributions, checked.
    fn inputs(&self) -> Result<(Vec<Target>, Vec<Distribution>), AppError> {
        let mut targets: Vec<Target> = Vec::new();
        let mut dists = Vec::new();
        for (i, v) in self.vary.iter().enumerate() {
            let at = format!("dispersion.vary[{i}] (`{}`)", v.key);
            let target = Target::parse(&v.key).map_err(|e| input(format!("{at}: {e}")))?;
            if targets.contains(&target) {
                return Err(input(format!("{at}: the key is varied twice")));
            }
            let dist = match (v.normal, v.uniform, v.triangular) {
                (Some(n), None, None) => Distribution::try_normal(
                    n.mean,
                    n.std_dev,
                    n.lo.unwrap_or(f64::NEG_INFINITY),
                    n.hi.unwrap_or(f64::INFINITY),
                ),
                (None, Some(u), None) => Distribution::try_uniform(u.lo, u.hi),
                (None, None, Some(t)) => Distribution::try_triangular(t.lo, t.mode, t.hi),
                _ => {
                    return Err(input(format!(
                        "{at}: give exactly one of `normal`, `uniform` or `triangular`"
                    )))
                }
            };
            dists.push(dist.map_err(|e| input(format!("{at}: {e}")))?);
            targets.push(target);
        }
        Ok((targets, dists))
    }
}

/// The base scenario's value of every vector key a component of which is varied; the base
/// must then accept every varied key at the middle of its distribution.
fn base_vectors(
    base: &Path,
    fixed: &[String],
    targets: &[Target],
    dists: &[Distribution],
) -> Result<Vec<(String, Vec<toml::Value>)>, AppError> {
    let load = |set: &[String]| {
        Scenario::load(base, &[fixed, set].concat())
            .map_err(|e| {
                input(format!(
                    "[dispersion] (the base scenario with `dispersion.set`, then each drawn key at the middle of its distribution, as overrides): {e}"
                ))
            })
    };
    let resolved: toml::Table =
        toml::from_str(&load(&[])?.to_toml()).map_err(|e| input(e.to_string()))?;
    let mut vectors: Vec<(String, Vec<toml::Value>)> = Vec::new();
    for t in targets {
        let Some(index) = t.index else {
            continue;
        };
        if vectors.iter().any(|(k, _)| *k == t.key) {
            continue;
        }
        let value = t
            .key
            .split('.')
            .try_fold(&toml::Value::Table(resolved.clone()), |v, part| {
                v.get(part.trim())
            })
            .cloned()
            .or_else(|| unset_vector(&t.key));
        let Some(toml::Value::Array(a)) = value else {
            return Err(input(format!(
                "[dispersion]: `{}` is not a list of numbers in the base scenario, so it has no components",
                t.key
            )));
        };
        if index >= a.len() {
            return Err(input(format!(
                "[dispersion]: `{}[{index}]`: the key has {} components",
                t.key,
                a.len()
            )));
        }
        vectors.push((t.key.clone(), a));
    }
    let middle: Vec<f64> = dists.iter().map(|d| d.quantile(0.5)).collect();
    load(&overrides(targets, &middle, &vectors))?;
    Ok(vectors)
}

/// Refuse an override in `set` (named `what` in the message) of a key the dispersion draws:
/// the draw would replace it silently. With `whole_vectors`, also an override of a vector a
/// component of which is drawn: a study-wide `--set` comes before the sample's whole vector
/// (made from the base and `dispersion.set`, which may give the other components).
pub(crate) fn refuse_drawn_overrides(
    drawn: &[String],
    set: &[String],
    what: &str,
    whole_vectors: bool,
) -> Result<(), AppError> {
    for s in set {
        let Some([key, _]) = super::split_override(s) else {
            continue;
        };
        let hit = drawn.iter().find(|d| {
            let component = (d.strip_prefix(key.as_str())).is_some_and(|r| r.starts_with('['));
            **d == key || (whole_vectors && component)
        });
        if let Some(d) = hit {
            let fix = match d == &key {
                true => "drop one of the two".to_string(),
                false => format!(
                    "give `{key}`'s other components in `dispersion.set` or the base scenario"
                ),
            };
            return Err(input(format!(
                "{what} `{s}`: [dispersion] draws `{d}`, which would replace it: {fix}"
            )));
        }
    }
    Ok(())
}

/// Zeros for a vector key the scenario leaves unset (its declared length).
fn unset_vector(key: &str) -> Option<toml::Value> {
    use crate::scenario::sections::SECTIONS;
    let (section, name) = key.rsplit_once('.')?;
    let decl = SECTIONS.iter().find(|s| s.name == section)?.key(name)?;
    match decl.kind {
        crate::scenario::keys::Kind::Vector(n) => {
            Some(toml::Value::Array(vec![toml::Value::Float(0.0); n]))
        }
        _ => None,
    }
}

/// The `--set` overrides of one sample: `key=value` for a scalar, the whole vector (the base's
/// components with the drawn ones) for a vector key. Values are written in Rust's shortest
/// round-trip form, so a case reads back exactly the drawn number.
fn overrides(
    targets: &[Target],
    values: &[f64],
    vectors: &[(String, Vec<toml::Value>)],
) -> Vec<String> {
    let mut set: Vec<String> = Vec::new();
    for (t, x) in targets.iter().zip(values) {
        if t.index.is_none() {
            set.push(format!("{}={x:?}", t.key));
        }
    }
    for (key, base) in vectors {
        let mut v = base.clone();
        for (t, x) in targets.iter().zip(values).filter(|(t, _)| &t.key == key) {
            if let Some(i) = t.index {
                v[i] = toml::Value::Float(*x);
            }
        }
        let parts: Vec<String> = v
            .iter()
            .map(|e| match e {
                toml::Value::Float(f) => format!("{f:?}"),
                other => other.to_string(),
            })
            .collect();
        set.push(format!("{key}=[{}]", parts.join(", ")));
    }
    set
}

#[cfg(test)]
mod tests;

//! The files of a dispersion study, beside its table: `dispersion.csv` (each sample's inputs
//! and landing) and, once every sample has landed, `footprint.json` (the footprint and the
//! inputs ranked by their share in its spread).

use std::path::{Path, PathBuf};

use super::footprint::{footprint, sensitivity, settling, Footprint, Sensitivity, Settling};
use super::{split_override, Study};
use crate::app::AppError;
use crate::output::atomic::write_atomic;
use crate::output::footprint_plot::Marks;

/// The last line of chute's `footprint.html` (a page without it is the user's).
pub fn html_mark() -> String {
    format!("<!-- written by {WRITTEN_BY} -->\n")
}

/// The per-sample table.
pub const DISPERSION_CSV: &str = "dispersion.csv";
/// The footprint's statistics.
pub const FOOTPRINT_JSON: &str = "footprint.json";
/// The footprint's picture.
pub const FOOTPRINT_PNG: &str = "footprint.png";
/// The footprint as a page for a browser.
pub const FOOTPRINT_HTML: &str = "footprint.html";
/// The mark of chute's `footprint.json` (a file without it is the user's).
pub const WRITTEN_BY: &str = "chute study (dispersion)";
/// The summary fields of a landing, as `dispersion.csv` columns.
const LANDING: [&str; 3] = [
    "flight_time_s",
    "landing_velocity_mps",
    "peak_line_tension_n",
];

/// `footprint.json`.
#[derive(Debug, serde::Serialize)]
struct FootprintFile<'a> {
    written_by: &'static str,
    study: &'a str,
    footprint: Footprint,
    /// The footprint of the first N/4, N/2 and N samples.
    settling: Vec<Settling>,
    /// How `sensitivity` ranks the inputs.
    sensitivity_method: &'static str,
    sensitivity: Vec<Sensitivity>,
}

/// One sample as its case directory shows it.
struct Sample {
    name: String,
    inputs: Vec<(String, f64)>,
    landing: Option<[f64; 2]>,
    fields: Vec<String>,
}

/// The drawn `keys` of a case's `set` (the last value given for each; NaN when absent).
fn inputs(set: &[String], keys: &[String]) -> Vec<(String, f64)> {
    let all = numbers(set);
    keys.iter()
        .map(|k| {
            let x = all
                .iter()
                .rev()
                .find(|(n, _)| n == k)
                .map_or(f64::NAN, |v| v.1);
            (k.clone(), x)
        })
        .collect()
}

/// The numeric values of a case's `set`: scalars by key, list components as `key[i]`.
fn numbers(set: &[String]) -> Vec<(String, f64)> {
    let mut out = Vec::new();
    for s in set {
        let Some([key, value]) = split_override(s) else {
            continue;
        };
        if let Ok(x) = value.trim().parse::<f64>() {
            out.push((key, x));
        } else if let Some(list) = value
            .trim()
            .strip_prefix('[')
            .and_then(|v| v.strip_suffix(']'))
        {
            for (i, part) in list.split(',').enumerate() {
                if let Ok(x) = part.trim().parse::<f64>() {
                    out.push((format!("{key}[{i}]"), x));
                }
            }
        }
    }
    out
}

/// The overrides a case's `done.json` records it ran with (`None` without a record): the inputs
/// that go with its landing, even when the study file has changed since.
fn recorded_set(case_dir: &Path) -> Option<Vec<String>> {
    let text = crate::output::atomic::read_own_string(&case_dir.join(super::DONE_FILE)).ok()?;
    let done: serde_json::Value = serde_json::from_str(&text).ok()?;
    let pairs = done["overrides"].as_array()?;
    pairs
        .iter()
        .map(|p| Some(format!("{}={}", p.get(0)?.as_str()?, p.get(1)?.as_str()?)))
        .collect()
}

fn read_sample(case_dir: Option<PathBuf>, name: &str, set: &[String], keys: &[String]) -> Sample {
    let recorded = case_dir.as_deref().and_then(recorded_set);
    let summary = case_dir
        .and_then(|d| {
            crate::output::atomic::read_own_string(&d.join(crate::output::run_files::SUMMARY)).ok()
        })
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
        .filter(|s| s["complete"] == true);
    let number = |s: &serde_json::Value, k: &str| s.get(k).and_then(|v| v.as_f64());
    let landing = summary.as_ref().and_then(|s| {
        let p = s.get("landing_point_m")?;
        Some([p.get(0)?.as_f64()?, p.get(1)?.as_f64()?])
    });
    let fields = LANDING
        .iter()
        .map(|k| {
            let v = summary.as_ref().and_then(|s| number(s, k));
            v.map_or(String::new(), |x| x.to_string())
        })
        .collect();
    Sample {
        name: name.to_string(),
        inputs: inputs(recorded.as_deref().unwrap_or(set), keys),
        landing,
        fields,
    }
}

/// Write the dispersion files of `study`, whose cases are in `out`, into `out`; the names of
/// the samples that have not landed (no footprint is written until none is missing).
pub fn write(study: &Study, out: &Path) -> Result<Vec<String>, AppError> {
    write_from(study, |name| Some(out.join(name)), out)
}

/// [`write()`] of the cases found in `dirs` (shards collected from several directories).
pub fn write_collected(
    study: &Study,
    dirs: &[PathBuf],
    out: &Path,
) -> Result<Vec<String>, AppError> {
    let find = |name: &str| {
        dirs.iter()
            .map(|d| d.join(name))
            .find(|c| c.join(super::DONE_FILE).is_file())
    };
    write_from(study, find, out)
}

/// The pictures' release point and wind: those of the scenario the first sample ran (its
/// run's resolved scenario in `first_dir`, with every study-wide override), each drawn
/// component replaced by its mean over the samples.
fn marks(first_dir: Option<PathBuf>, keys: &[String], samples: &[Sample]) -> Marks {
    let resolved = first_dir.map(|d| d.join(crate::output::run_files::RESOLVED_SCENARIO));
    let first = resolved.and_then(|f| crate::scenario::Scenario::load(&f, &[]).ok());
    let n = samples.len().max(1) as f64;
    let mean_or = |key: &str, fixed: f64| match keys.iter().position(|k| k == key) {
        Some(i) => samples.iter().map(|s| s.inputs[i].1).sum::<f64>() / n,
        None => fixed,
    };
    let release = first
        .as_ref()
        .and_then(|s| s.canopy.release_point_m)
        .unwrap_or([0.0; 2]);
    let wind = first.as_ref().map_or([0.0; 3], |s| s.fluid.wind_mps);
    Marks {
        release: [0, 1].map(|k| mean_or(&format!("canopy.release_point_m[{k}]"), release[k])),
        wind: Some([0, 1].map(|k| mean_or(&format!("fluid.wind_mps[{k}]"), wind[k]))),
    }
}

fn write_from(
    study: &Study,
    case_dir: impl Fn(&str) -> Option<PathBuf>,
    out: &Path,
) -> Result<Vec<String>, AppError> {
    let keys = study.dispersion.clone().unwrap_or_default();
    let samples: Vec<Sample> = study
        .cases
        .iter()
        .map(|c| read_sample(case_dir(&c.name), &c.name, &c.set, &keys))
        .collect();
    let csv = out.join(DISPERSION_CSV);
    write_atomic(&csv, table(&keys, &samples).as_bytes()).map_err(|e| AppError::io(&csv, e))?;
    let missing: Vec<String> = samples
        .iter()
        .filter(|s| s.landing.is_none())
        .map(|s| s.name.clone())
        .collect();
    let points: Vec<[f64; 2]> = samples.iter().filter_map(|s| s.landing).collect();
    let fp = footprint(&points).filter(|_| missing.is_empty());
    let Some(fp) = fp else {
        // A footprint of some samples would not be the study's: none, rather than a stale one.
        for f in [FOOTPRINT_JSON, FOOTPRINT_PNG, FOOTPRINT_HTML] {
            let _ = std::fs::remove_file(out.join(f));
        }
        return Ok(missing);
    };
    let first_dir = study.cases.first().and_then(|c| case_dir(&c.name));
    let marks = marks(first_dir, &keys, &samples);
    let png = out.join(FOOTPRINT_PNG);
    crate::output::footprint_plot::footprint_plot(&png, &points, &fp, &marks)
        .map_err(|e| AppError::RunFailed(format!("cannot draw {}: {e}", png.display())))?;
    let file = FootprintFile {
        written_by: WRITTEN_BY,
        study: &study.name,
        settling: settling(&points),
        footprint: fp,
        sensitivity_method: "Pearson correlation with the landing's x and y, ranked by r_x² + r_y²",
        sensitivity: sensitivity(&columns(&keys, &samples), &points),
    };
    write_page(out, &file, &samples, marks)?;
    let json = out.join(FOOTPRINT_JSON);
    let body =
        serde_json::to_string_pretty(&file).map_err(|e| AppError::RunFailed(e.to_string()))?;
    write_atomic(&json, body.as_bytes()).map_err(|e| AppError::io(&json, e))?;
    Ok(missing)
}

/// `dispersion.csv`: a row per sample, its drawn `keys`, landing point and landing fields.
fn table(keys: &[String], samples: &[Sample]) -> String {
    let mut text = format!(
        "sample,{},landing_x_m,landing_y_m,{}\n",
        keys.join(","),
        LANDING.join(",")
    );
    for s in samples {
        let values: Vec<String> = s.inputs.iter().map(|(_, x)| x.to_string()).collect();
        let point = s
            .landing
            .map_or([String::new(), String::new()], |p| p.map(|x| x.to_string()));
        text += &format!(
            "{},{},{},{}\n",
            s.name,
            values.join(","),
            point.join(","),
            s.fields.join(",")
        );
    }
    text
}

/// Each drawn key's values over the samples, for the sensitivity ranking.
fn columns(keys: &[String], samples: &[Sample]) -> Vec<(String, Vec<f64>)> {
    let column = |i: usize| -> Vec<f64> {
        let value = |s: &Sample| s.inputs.get(i).map_or(f64::NAN, |v| v.1);
        samples.iter().map(value).collect()
    };
    (keys.iter().enumerate())
        .map(|(i, k)| (k.clone(), column(i)))
        .collect()
}

/// `footprint.html` of `file`, the `samples`' landings and the pictures' `marks`.
fn write_page(
    out: &Path,
    file: &FootprintFile,
    samples: &[Sample],
    marks: Marks,
) -> Result<(), AppError> {
    let landings: Vec<(String, [f64; 2])> = samples
        .iter()
        .filter_map(|s| Some((s.name.clone(), s.landing?)))
        .collect();
    let html = crate::output::footprint_html::page(&crate::output::footprint_html::Page {
        study: file.study,
        landings: &landings,
        footprint: &file.footprint,
        settling: &file.settling,
        sensitivity: &file.sensitivity,
        marks,
    });
    let html = html + &html_mark();
    let path = out.join(FOOTPRINT_HTML);
    write_atomic(&path, html.as_bytes()).map_err(|e| AppError::io(&path, e))
}

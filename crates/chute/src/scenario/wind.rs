//! The wind profile of `[wind]`: the table file read once at load (recorded by digest, like
//! a mesh), the cross-key rules, and the engine's [`WindProfile`] in the model frame.

use std::path::Path;
use std::sync::Arc;

use engine::aero::{WindProfile, WindTable};

use super::validate::Checker;
use super::{Scenario, WindLaw};

/// The key of the wind table file, an input file a run records by digest.
pub const WIND_FILE_KEY: &str = "wind.file";
/// The columns a wind table file has, in order.
pub const WIND_COLUMNS: [&str; 3] = ["altitude_m", "vx_mps", "vy_mps"];
/// Most rows of a wind table (a sounding every few metres through the lower atmosphere).
pub const MAX_WIND_ROWS: usize = 10_000;
/// Largest wind table file read (bytes).
const MAX_WIND_BYTES: u64 = 1 << 20;

/// A wind table as it was read: its rows `(altitude, vx, vy)` and the digest of the bytes.
#[derive(Debug, Clone, PartialEq)]
pub struct WindFile {
    /// Rows (m, m/s, m/s), altitudes increasing.
    pub rows: Vec<[f64; 3]>,
    /// Digest of the bytes parsed ([`crate::study::inputs::bytes_digest`]).
    pub digest: String,
}

/// Read the wind table at `path`: the header [`WIND_COLUMNS`], then 2 to [`MAX_WIND_ROWS`]
/// rows of finite numbers with increasing altitudes. The error names the file and line.
pub fn read(path: &Path) -> Result<WindFile, String> {
    let at = |line: u64, why: String| format!("{}:{line}: {why}", path.display());
    let bytes = crate::mesh::read_capped(path, MAX_WIND_BYTES).map_err(|e| match e {
        crate::mesh::ReadCapped::TooLong(n) => {
            format!(
                "{}: {n} bytes; a wind table holds at most {MAX_WIND_BYTES}",
                path.display()
            )
        }
        crate::mesh::ReadCapped::Io(e) => format!("cannot read {}: {e}", path.display()),
    })?;
    let mut reader = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_reader(&bytes[..]);
    let header = reader.headers().map_err(|e| at(1, e.to_string()))?;
    if header.iter().collect::<Vec<_>>() != WIND_COLUMNS {
        return Err(at(
            1,
            format!("the header must be `{}`", WIND_COLUMNS.join(",")),
        ));
    }
    let mut rows: Vec<[f64; 3]> = Vec::new();
    for record in reader.records() {
        let record = record.map_err(|e| at(e.position().map_or(0, |p| p.line()), e.to_string()))?;
        let line = record.position().map_or(0, |p| p.line());
        if rows.len() == MAX_WIND_ROWS {
            return Err(at(line, format!("more than {MAX_WIND_ROWS} rows")));
        }
        let mut row = [0.0; 3];
        for (k, (cell, name)) in record.iter().zip(WIND_COLUMNS).enumerate() {
            row[k] = cell
                .parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| at(line, format!("{name} = `{cell}` is not a finite number")))?;
        }
        if let Some(prev) = rows.last().filter(|p| row[0] <= p[0]) {
            return Err(at(
                line,
                format!(
                    "altitude {} m is not above the row before ({} m)",
                    row[0], prev[0]
                ),
            ));
        }
        rows.push(row);
    }
    if rows.len() < 2 {
        return Err(at(
            1,
            format!(
                "{} rows: a wind table needs at least two altitudes",
                rows.len()
            ),
        ));
    }
    let digest = crate::study::inputs::bytes_digest(&bytes);
    Ok(WindFile { rows, digest })
}

/// The cross-key rules of `[wind]`.
pub(super) fn check(c: &mut Checker, s: &Scenario) {
    let Some(w) = &s.wind else {
        return;
    };
    if s.fluid.added_mass == Some(true) {
        c.fail(
            "fluid.added_mass",
            true,
            "not with `[wind]`: the carried air's velocity would follow the canopy's height, which the added-mass law does not hold",
        );
    }
    match (w.profile, w.roughness_m, &w.file) {
        (WindLaw::Log, Some(z0), _) if z0 >= w.reference_height_m => c.fail(
            "wind.roughness_m",
            z0,
            format!(
                "the wind is zero below z₀: it must lie below `reference_height_m` ({} m)",
                w.reference_height_m
            ),
        ),
        (WindLaw::Table, _, Some(p)) => {
            if s.fluid.wind_mps != [0.0; 3] {
                c.fail(
                    "fluid.wind_mps",
                    format!("{:?}", s.fluid.wind_mps),
                    "not used with `wind.profile = \"table\"` (the table gives the wind): remove it",
                );
            }
            if let Err(why) = read(p) {
                c.fail(WIND_FILE_KEY, format!("\"{}\"", p.display()), why);
            }
        }
        _ => {}
    }
}

/// The engine's wind profile of `s` in the model frame (z = 0 at `atmosphere.altitude_m`),
/// with `table` the file as the loader read it.
pub fn profile(s: &Scenario, table: Option<&WindFile>) -> WindProfile {
    let Some(w) = &s.wind else {
        return WindProfile::Uniform;
    };
    let origin = s.atmosphere.altitude_m;
    // Heights above the ground: the ground's altitude, sea level without one.
    let ground = s.atmosphere.ground_altitude_m.unwrap_or(0.0) - origin;
    match w.profile {
        WindLaw::Power => WindProfile::Power {
            reference_height: w.reference_height_m,
            exponent: w.exponent.unwrap_or_default(),
            ground,
        },
        WindLaw::Log => WindProfile::Log {
            reference_height: w.reference_height_m,
            roughness: w.roughness_m.unwrap_or_default(),
            ground,
        },
        WindLaw::Table => {
            let rows: Vec<[f64; 3]> = table
                .map(|t| t.rows.iter().map(|r| [r[0] - origin, r[1], r[2]]).collect())
                .unwrap_or_default();
            // The loader refuses a table the engine would: reaching here without one is a bug.
            let t = WindTable::try_new(&rows).expect("the loader read a valid wind table");
            WindProfile::Table(Arc::new(t))
        }
    }
}

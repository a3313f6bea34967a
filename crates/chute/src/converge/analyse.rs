//! From finished levels to convergence estimates: read each level's `done.json` and
//! `summary.json`, flag branch changes, and estimate every headline quantity with
//! [`super::gci`] at a round-off resolution derived from the Newton tolerance.

use std::collections::BTreeMap;
use std::path::Path;

use serde::Serialize;

use super::gci::{self, Verdict};
use super::plan::{Axis, Ladder};
use crate::study::DONE_FILE;

/// A headline quantity and how a residual force maps to an error in it.
#[derive(Debug, Clone, Copy)]
pub struct Quantity {
    /// Its `summary.json` field.
    pub name: &'static str,
    /// Short label for tables and plots.
    pub label: &'static str,
    /// Relative error per unit of relative unbalanced force ε_F (docs/convergence.md):
    /// v_t ∝ W^½ gives ½, C_D·A ∝ W/v² gives 1, a linear response of the shape to its
    /// loads gives 1, and the ±2 % band crossing moves by T δv/(0.02 |v_t|) ≤ 25 ε_F t;
    /// a landing at terminal speed gives ½ for its speed and ½ for the flight time H/|v| and the drift ∫U dt;
    /// the opening's peak force and load factor 1, its fill time and distance
    /// `1/(1 − 0.95)` (a crossing of 95 % of the steady diameter).
    pub sensitivity: f64,
    /// Only reported when some level has it: the drop quantities of a run with a ground.
    pub optional: bool,
}

/// The quantities estimated, in table order.
pub const QUANTITIES: &[Quantity] = &[
    Quantity {
        name: "terminal_velocity_mps",
        label: "v_t (m/s)",
        sensitivity: 0.5,
        optional: false,
    },
    Quantity {
        name: "time_to_terminal_s",
        label: "time to terminal (s)",
        sensitivity: 25.0,
        optional: false,
    },
    Quantity {
        name: "final_extended_height_m",
        label: "final extended height (m)",
        sensitivity: 1.0,
        optional: false,
    },
    Quantity {
        name: "drag_area_m2",
        label: "C_D·A (m²)",
        sensitivity: 1.0,
        optional: false,
    },
    Quantity {
        name: "landing_velocity_mps",
        label: "landing velocity (m/s)",
        sensitivity: 0.5,
        optional: true,
    },
    Quantity {
        name: "flight_time_s",
        label: "flight time (s)",
        sensitivity: 0.5,
        optional: true,
    },
    Quantity {
        name: "drift_m",
        label: "drift (m)",
        sensitivity: 0.5,
        optional: true,
    },
    Quantity {
        name: "opening_peak_force_n",
        label: "opening peak force (N)",
        sensitivity: 1.0,
        optional: true,
    },
    Quantity {
        name: "opening_load_factor",
        label: "opening-load factor",
        sensitivity: 1.0,
        optional: true,
    },
    Quantity {
        name: "opening_fill_time_s",
        label: "fill time (s)",
        sensitivity: FILL_SENSITIVITY,
        optional: true,
    },
    Quantity {
        name: "opening_fill_distance_diameters",
        label: "fill distance (D₀)",
        sensitivity: FILL_SENSITIVITY,
        optional: true,
    },
];

/// The fill time is a crossing of 95 % of the steady diameter: a relative error ε in the
/// diameter moves it by at most ε/(1 − 0.95) of itself.
const FILL_SENSITIVITY: f64 = 1.0 / (1.0 - crate::metrics::opening::FILLED);

/// A level whose final extended height is off the finest level's by more than this fraction
/// is in a qualitatively different state (another branch) and is left out of the fit.
pub const BRANCH_CHANGE: f64 = 0.25;

/// Below any tolerance, the metrics themselves are only good to about this (relative).
const FLOAT_FLOOR: f64 = 1e3 * f64::EPSILON;

/// What a level's case directory holds.
#[derive(Debug, Clone, PartialEq)]
pub struct LevelResult {
    /// `complete`, `incomplete`, `failed`, or `not run` (no `done.json`).
    pub status: String,
    /// Why it failed or stopped.
    pub message: Option<String>,
    /// The quantities of [`QUANTITIES`], in order (`None`: absent or null).
    pub values: Vec<Option<f64>>,
    /// Wall time of the run (s).
    pub wall_time_s: Option<f64>,
}

impl LevelResult {
    /// The value of quantity `qi` of [`QUANTITIES`] (`None`: absent, null, or not listed).
    pub fn value(&self, qi: usize) -> Option<f64> {
        self.values.get(qi).copied().flatten()
    }
}

fn read_json(path: &Path) -> Option<serde_json::Value> {
    serde_json::from_str(&crate::output::atomic::read_own_string(path).ok()?).ok()
}

/// Read `dir/done.json` and `dir/summary.json`.
/// `expected`: the inputs digest the level has in this ladder and the files it reads now.
pub fn read_level(
    dir: &Path,
    expected: Option<&(String, Vec<(&'static str, std::path::PathBuf)>)>,
) -> LevelResult {
    let inputs = expected.map(|(d, _)| d.as_str());
    let files = expected.map_or(&[][..], |(_, f)| f.as_slice());
    let done = read_json(&dir.join(DONE_FILE));
    // A level recorded for other inputs (an earlier ladder's, under other `--set`) is not a
    // level of this ladder: it is not run yet, whatever it holds.
    let recorded = done.as_ref().and_then(|d| d["inputs"].as_str());
    if let (Some(want), Some(_)) = (inputs, &done) {
        if recorded != Some(want) {
            return LevelResult {
                status: "not run".into(),
                message: Some(
                    "its directory holds a run of other inputs (an earlier ladder's): run this ladder without --shard, or the missing shard".into(),
                ),
                values: vec![None; QUANTITIES.len()],
                wall_time_s: None,
            };
        }
    }
    // A level whose run read other bytes of an input file than the file has now (a mesh
    // edited while the ladder ran, then put back) is not a level of these inputs.
    if let (Some(why), Some(_)) = (crate::study::read_other_inputs(dir, files), &done) {
        return LevelResult {
            status: "failed".into(),
            message: Some(format!("{why}: run the ladder again")),
            values: vec![None; QUANTITIES.len()],
            wall_time_s: None,
        };
    }
    let summary = read_json(&dir.join("summary.json"));
    let status = done
        .as_ref()
        .and_then(|d| d["status"].as_str().map(str::to_string))
        .unwrap_or_else(|| "not run".into());
    // A level its ladder did not record (no `done.json`) has no numbers of this ladder.
    let summary = summary.filter(|_| done.is_some());
    let values = QUANTITIES
        .iter()
        .map(|q| {
            summary
                .as_ref()
                .and_then(|s| s[q.name].as_f64())
                .filter(|v| v.is_finite())
        })
        .collect();
    LevelResult {
        status: if status == "complete" && summary.is_none() {
            "failed".into()
        } else {
            status
        },
        message: done
            .as_ref()
            .and_then(|d| d["message"].as_str().map(str::to_string)),
        values,
        wall_time_s: done.as_ref().and_then(|d| d["wall_time_s"].as_f64()),
    }
}

/// One level in the report.
#[derive(Debug, Clone, Serialize)]
pub struct LevelReport {
    /// The varied value.
    pub value: f64,
    /// The value as given.
    pub text: String,
    /// Its case directory under the output directory.
    pub case: String,
    /// Representative size h.
    pub h: f64,
    /// Nodes of the model.
    pub nodes: usize,
    /// `complete`, `incomplete`, `failed` or `not run`.
    pub status: String,
    /// Why it failed, stopped, or was left out.
    pub message: Option<String>,
    /// Whether the fit may use it (complete and on the finest level's branch).
    pub used: bool,
    /// Wall time (s).
    pub wall_time_s: Option<f64>,
}

/// One quantity of one ladder (the `convergence.json` layout of docs/convergence.md).
#[derive(Debug, Clone, Serialize)]
pub struct QuantityReport {
    /// Value per level, in the ladder's order (null: failed, left out or absent).
    pub results: Vec<Option<f64>>,
    /// h per level.
    pub h: Vec<f64>,
    /// Apparent order p (three levels).
    pub observed_order: Option<f64>,
    /// The order used for extrapolation (observed, or formal with two levels).
    pub order_used: Option<f64>,
    /// Safety factor of the GCI.
    pub safety_factor: Option<f64>,
    /// Richardson extrapolation.
    pub extrapolated: Option<f64>,
    /// e_a of the finest pair (fraction).
    pub approximate_error: Option<f64>,
    /// e_ext (fraction).
    pub extrapolated_error: Option<f64>,
    /// GCI of the finest level used (fraction).
    pub gci: Option<f64>,
    /// GCI of each level of the estimate from its next coarser one, at the same order and
    /// safety factor (null for the coarsest and for levels not used): the medium level's
    /// uncertainty when the scenario's default is not the finest level.
    pub gci_by_level: Vec<Option<f64>>,
    /// `monotone`, `oscillatory`, `divergent`, `round-off`; null with fewer than 2 levels.
    pub verdict: Option<&'static str>,
    /// Indices (into `results`) of the levels the estimate used, finest first.
    pub levels_used: Vec<usize>,
    /// Relative difference below which the levels are round-off (from the Newton tolerance).
    pub resolution: f64,
    /// What limited the estimate, if anything.
    pub message: Option<String>,
}

/// One ladder in the report.
#[derive(Debug, Clone, Serialize)]
pub struct StudyReport {
    /// The varied key.
    pub key: String,
    /// `space`, `time` or `tolerance`.
    pub axis: Axis,
    /// The values, in the order given.
    pub values: Vec<f64>,
    /// The levels.
    pub levels: Vec<LevelReport>,
    /// Per quantity.
    pub quantities: BTreeMap<String, QuantityReport>,
    /// ε_F, the relative force the Newton tolerance leaves unresolved (largest over levels).
    pub relative_force_resolution: f64,
    /// Messages for the reader (branch changes, failures, the dt-ladder note).
    pub notes: Vec<String>,
}

impl StudyReport {
    /// The quantities this study reports, in table order (the optional ones only when some
    /// level has them).
    pub fn reported(&self) -> impl Iterator<Item = &'static Quantity> + '_ {
        QUANTITIES
            .iter()
            .filter(|q| self.quantities.contains_key(q.name))
    }
}

/// The note every dt ladder carries.
pub const DT_NOTE: &str = "A steady descent of implicit Euler satisfies the same static balance at any dt: the terminal velocity, the final shape and C_D·A depend on dt only through the transient and the branch it selects. The time to terminal is the dt-sensitive quantity (first order).";

/// The note every error-tolerance ladder carries.
pub const TOLERANCE_NOTE: &str = "Levels differ in the adaptive steps' local error tolerance; h = √tol, since an error-controlled implicit Euler step scales as √tol and its global error is first order in the step. As for a dt ladder, a steady descent is the same static balance at any step: the transient (time to terminal) is the tolerance-sensitive quantity.";

/// Estimate one ladder from its levels' results (same order as `ladder.levels`).
pub fn analyse(ladder: &Ladder, results: &[LevelResult]) -> StudyReport {
    let mut notes = Vec::new();
    match ladder.axis {
        Axis::Time => notes.push(DT_NOTE.to_string()),
        Axis::Tolerance => notes.push(TOLERANCE_NOTE.to_string()),
        Axis::Space => {}
    }
    let mut levels: Vec<LevelReport> = ladder
        .levels
        .iter()
        .zip(results)
        .map(|(l, r)| LevelReport {
            value: l.value,
            text: l.text.clone(),
            case: l.case.clone(),
            h: l.h,
            nodes: l.nodes,
            status: r.status.clone(),
            message: r.message.clone(),
            used: r.status == "complete",
            wall_time_s: r.wall_time_s,
        })
        .collect();
    for (l, lv) in levels.iter().zip(&ladder.levels) {
        if l.status != "complete" {
            let why = l.message.as_deref().unwrap_or("no result");
            notes.push(format!("{}={}: {} ({why})", ladder.key, lv.text, l.status));
        }
    }
    flag_branches(ladder, results, &mut levels, &mut notes);
    let eps_f = ladder
        .levels
        .iter()
        .zip(results)
        .zip(&levels)
        .filter(|(_, l)| l.used)
        .map(|((lv, r), _)| lv.resolution.relative_force(r.values[0].unwrap_or(0.0)))
        .fold(0.0, f64::max);
    let mut quantities = BTreeMap::new();
    for (qi, q) in QUANTITIES.iter().enumerate() {
        if q.optional && results.iter().all(|r| r.value(qi).is_none()) {
            continue;
        }
        let rep = quantity(
            ladder,
            results,
            &levels,
            qi,
            (q.sensitivity * eps_f).max(FLOAT_FLOOR),
        );
        quantities.insert(q.name.to_string(), rep);
    }
    StudyReport {
        key: ladder.key.clone(),
        axis: ladder.axis,
        values: ladder.levels.iter().map(|l| l.value).collect(),
        levels,
        quantities,
        relative_force_resolution: eps_f,
        notes,
    }
}

/// Leave out complete levels whose final extended height is off the finest complete level's
/// by more than [`BRANCH_CHANGE`].
fn flag_branches(
    ladder: &Ladder,
    results: &[LevelResult],
    levels: &mut [LevelReport],
    notes: &mut Vec<String>,
) {
    let hq = QUANTITIES
        .iter()
        .position(|q| q.name == "final_extended_height_m")
        .unwrap_or(2);
    let finest = (0..levels.len())
        .filter(|&i| levels[i].used && results[i].values[hq].is_some())
        .min_by(|&a, &b| levels[a].h.total_cmp(&levels[b].h));
    let Some(f) = finest else { return };
    let Some(h_ref) = results[f].values[hq] else {
        return;
    };
    for i in 0..levels.len() {
        let Some(h) = results[i].values[hq].filter(|_| levels[i].used && i != f) else {
            continue;
        };
        let off = (h - h_ref).abs() / h_ref.abs().max(f64::MIN_POSITIVE);
        if off > BRANCH_CHANGE {
            let msg = format!(
                "{}={}: branch change: final extended height {h:.3} m is {:.0} % off the finest level's {h_ref:.3} m (> {:.0} %), a qualitatively different state; left out of the fit",
                ladder.key,
                ladder.levels[i].text,
                100.0 * off,
                100.0 * BRANCH_CHANGE
            );
            levels[i].used = false;
            levels[i].message = Some(msg.clone());
            notes.push(msg);
        }
    }
}

fn quantity(
    ladder: &Ladder,
    results: &[LevelResult],
    levels: &[LevelReport],
    qi: usize,
    resolution: f64,
) -> QuantityReport {
    let values: Vec<Option<f64>> = results.iter().map(|r| r.value(qi)).collect();
    let mut used: Vec<usize> = (0..levels.len())
        .filter(|&i| levels[i].used && values[i].is_some())
        .collect();
    used.sort_by(|&a, &b| levels[a].h.total_cmp(&levels[b].h));
    let mut message = None;
    let missing = levels
        .iter()
        .zip(&values)
        .filter(|(l, v)| l.used && v.is_none())
        .count();
    if missing > 0 {
        message = Some(format!(
            "{missing} complete level(s) have no value (e.g. terminal velocity not reached)"
        ));
    }
    let h: Vec<f64> = used.iter().take(3).map(|&i| levels[i].h).collect();
    let phi: Vec<f64> = used.iter().take(3).filter_map(|&i| values[i]).collect();
    let est = gci::estimate(&h, &phi, resolution, ladder.axis.formal_order());
    if est.is_none() {
        message = Some(format!(
            "{} usable level(s): at least two are needed",
            used.len()
        ));
    } else if used.len() == 2 && est.is_some_and(|e| e.verdict != Verdict::RoundOff) {
        message = Some(format!(
            "two levels: formal order {} assumed, safety factor {}",
            ladder.axis.formal_order(),
            gci::FS_ASSUMED
        ));
    }
    let mut gci_by_level = vec![None; levels.len()];
    if let Some(e) = est {
        let fine = used.iter().take(3).copied().collect::<Vec<_>>();
        for w in fine.windows(2) {
            let (f, c) = (w[0], w[1]);
            gci_by_level[f] = match (e.verdict, e.order_used, values[f], values[c]) {
                (Verdict::RoundOff, ..) => e.gci,
                (_, Some(p), Some(a), Some(b)) => Some(gci::pair_gci(
                    [levels[f].h, levels[c].h],
                    [a, b],
                    p,
                    e.safety_factor,
                )),
                _ => None,
            };
        }
    }
    QuantityReport {
        gci_by_level,
        results: values,
        h: levels.iter().map(|l| l.h).collect(),
        observed_order: est.and_then(|e| e.observed_order),
        order_used: est.and_then(|e| e.order_used),
        safety_factor: est.map(|e| e.safety_factor),
        extrapolated: est.and_then(|e| e.extrapolated),
        approximate_error: est.map(|e| e.approximate_error),
        extrapolated_error: est.and_then(|e| e.extrapolated_error),
        gci: est.and_then(|e| e.gci),
        verdict: est.map(|e| e.verdict.as_str()),
        levels_used: used.into_iter().take(3).collect(),
        resolution,
        message,
    }
}

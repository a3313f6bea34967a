//! `modes.html`: the run viewer's page (`viewer.html`'s template and script) playing the modes
//! of a `chute steady` report instead of a run's frames.
//!
//! Each mode is drawn over one cycle, `q + a Re(φ e^{iθ})` at [`PHASES`] phases θ in
//! [0, 2π), with `a` a tenth of the body's size (a mode's amplitude is arbitrary); the
//! page's `speed` colour shows the displacement. The page's time runs through the modes in turn: mode `k` plays
//! over `t ∈ [k − 1, k)`; the page's notes say which mode is which.

use serde_json::{json, Value};

use super::viewer::{centre, f32_base64, page, u32_base64};
use crate::steady::SteadyReport;

/// File name beside `stability.json`.
pub const MODES_HTML: &str = "modes.html";

/// Frames per mode cycle.
pub const PHASES: usize = 24;

/// Modes drawn at most (the report's first ones: the growing, then the nearest the shift).
pub const MODES_SHOWN: usize = 8;

/// The drawn displacement, as a fraction of the body's largest extent.
const AMPLITUDE: f64 = 0.1;

/// The page for `r`.
pub fn modes_html(r: &SteadyReport) -> String {
    let q = &r.positions_m;
    let lo = q
        .iter()
        .fold([f64::MAX; 3], |m, p| [0, 1, 2].map(|c| m[c].min(p[c])));
    let hi = q
        .iter()
        .fold([f64::MIN; 3], |m, p| [0, 1, 2].map(|c| m[c].max(p[c])));
    let a = AMPLITUDE * (0..3).map(|c| hi[c] - lo[c]).fold(0.0, f64::max);
    let modes = &r.modes[..r.modes.len().min(MODES_SHOWN)];
    let mut notes: Vec<String> = modes
        .iter()
        .enumerate()
        .map(|(k, m)| {
            format!(
                "t in [{k}, {}): mode {} — {} (growth {:.4} /s, {:.4} Hz)",
                k + 1,
                k + 1,
                m.description,
                m.growth_rate_per_s,
                m.frequency_hz
            )
        })
        .collect();
    notes.push(format!(
        "displacements drawn at {a:.3} m (a tenth of the body's size); the colour `speed` shows the displacement (m)"
    ));
    let results: Vec<Value> = [
        ("steady v_t", format!("{:.4} m/s", r.terminal_velocity_mps)),
        (
            "modes drawn",
            format!("{} of {}", modes.len(), r.modes.len()),
        ),
    ]
    .into_iter()
    .map(|(k, v)| json!([k, v]))
    .collect();
    let name = format!("{}: modes", r.scenario_name);
    let data = json!({
        "format": 1,
        "name": name,
        "results": results,
        "terminal_velocity_mps": Value::Null,
        "scenario_toml": Value::Null,
        "frames": frames(r, modes, a),
        "series": Value::Null,
        "notes": notes,
    });
    page(&name, &data)
}

/// The viewer's frames of `modes` at amplitude `a` (m): one cycle each, in turn.
fn frames(r: &SteadyReport, modes: &[crate::steady::ModeRecord], a: f64) -> Value {
    if modes.is_empty() {
        return Value::Null;
    }
    let q = &r.positions_m;
    let (mut offsets, mut origins, mut shown, mut times) = (vec![], vec![], vec![], vec![]);
    for (k, m) in modes.iter().enumerate() {
        for p in 0..PHASES {
            let theta = std::f64::consts::TAU * p as f64 / PHASES as f64;
            let turn = faer::c64::new(theta.cos(), theta.sin());
            let disp: Vec<[f64; 3]> = m
                .shape
                .iter()
                .map(|z| z.map(|c| a * (c * turn).re))
                .collect();
            let pos: Vec<[f64; 3]> = q
                .iter()
                .zip(&disp)
                .map(|(x, d)| [0, 1, 2].map(|c| x[c] + d[c]))
                .collect();
            let origin = centre(&pos);
            origins.push(origin);
            offsets.extend(pos.iter().flat_map(|x| [0, 1, 2].map(|c| x[c] - origin[c])));
            shown.extend(
                disp.iter()
                    .map(|d| (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()),
            );
            times.push(k as f64 + p as f64 / PHASES as f64);
        }
    }
    json!({
        "nodes": q.len(),
        "triangles": u32_base64(r.triangles.iter().flatten().map(|&i| i as u32)),
        "triangle_count": r.triangles.len(),
        "segments": u32_base64(r.segments.iter().flatten().map(|&i| i as u32)),
        "segment_count": r.segments.len(),
        "roles": Value::Null,
        "times": times,
        "total": times.len(),
        "origins": origins,
        "positions": f32_base64(offsets.into_iter()),
        "speeds": f32_base64(shown.into_iter()),
    })
}

//! `chute validate --case stability`: the steady descent's modes against closed forms and
//! against the flights of the same models (docs/stability.md §Cross-checks).

use super::Check;
use crate::scenario::Scenario;
use engine::aero::Fluid;
use engine::reference::pendulum::Pendulum;
use engine::stability::{modes, steady_descent, Linearized, ModeOptions, SteadyOptions};

/// Every check of the case: the pendulum, the report's canopies, then `round-solid`'s tilt
/// and swing.
pub fn stability(quick: bool) -> Result<Vec<Check>, String> {
    let mut out = pendulum()?;
    out.extend(super::stability_report::checks(quick)?);
    out.extend(round_solid()?);
    Ok(out)
}

/// The lateral modes of a payload pendulum under a drag node against the roots of its
/// characteristic cubic: round-off of a 12-unknown dense solve, 1e-8.
fn pendulum() -> Result<Vec<Check>, String> {
    let p = Pendulum::example();
    let fluid = Fluid::air();
    let (model, q) = p.model(&fluid);
    let opts = SteadyOptions::recommended(&model, p.g, 1);
    let mut start = q.clone();
    start[5] -= 0.01; // a taut line, as after a flight
    let s =
        steady_descent(&model, &start, [0.0, 0.0, -4.0], 0.0, &opts).map_err(|e| e.to_string())?;
    let lin = Linearized::at(&model, &s.q, &s.v, 0.0);
    let found = modes(&lin, &ModeOptions::default()).map_err(|e| e.to_string())?;
    let mut out = Vec::new();
    for root in p.lateral(fluid.density) {
        let nearest = found
            .iter()
            .map(|m| (m.eigenvalue - root).norm() / root.norm())
            .fold(f64::INFINITY, f64::min);
        out.push(Check::near_zero(
            "stability-pendulum",
            &format!(
                "lateral mode λ = {:.5} {:+.5}i /s: |λ_found − λ|/|λ| of the nearest mode",
                root.re, root.im
            ),
            "small-oscillation theory of a two-mass pendulum with drag damping (the cubic's roots)",
            nearest,
            1e-8,
        ));
    }
    Ok(out)
}

/// The flight of `s`: rows `(t, v_x, v_y)` of its time series.
pub(super) fn flight(s: &Scenario) -> Result<Vec<[f64; 3]>, String> {
    Ok(fly(s)?.1)
}

/// The flight of `s`: its summary and the rows `(t, v_x, v_y)` of its time series.
pub(super) fn fly(
    s: &Scenario,
) -> Result<(crate::output::summary::Summary, Vec<[f64; 3]>), String> {
    let dir = tempfile::tempdir().map_err(|e| e.to_string())?;
    let (summary, _) = super::system::simulate_in(s, dir.path())?;
    let mut rdr =
        csv::Reader::from_path(dir.path().join("timeseries.csv")).map_err(|e| e.to_string())?;
    let rows = rdr
        .records()
        .map(|r| {
            let r = r.map_err(|e| e.to_string())?;
            let x = |i: usize| r[i].parse::<f64>().map_err(|e| e.to_string());
            Ok([x(0)?, x(3)?, x(4)?])
        })
        .collect::<Result<Vec<_>, String>>()?;
    Ok((summary, rows))
}

/// The least-squares slope of `ln |v_h|` over `a ≤ t ≤ b` (1/s).
pub fn log_rate(rows: &[[f64; 3]], a: f64, b: f64) -> f64 {
    let pts: Vec<(f64, f64)> = rows
        .iter()
        .filter(|r| (a..=b).contains(&r[0]))
        .map(|r| (r[0], r[1].hypot(r[2]).ln()))
        .collect();
    let n = pts.len() as f64;
    let (mx, my) = pts
        .iter()
        .fold((0.0, 0.0), |s, p| (s.0 + p.0 / n, s.1 + p.1 / n));
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    sxy / pts.iter().map(|p| (p.0 - mx).powi(2)).sum::<f64>()
}

/// `round-solid`'s tilt divergence (its illustrative, unstable C_N(α)) and, with a restoring
/// C_N(α), its swing: each mode against the flight of the same model at
/// 0.25 m (at 0.35 m the cloth's flapping drowns the swing's signal). Tolerances: the tilt
/// 1 % of the mean of its two modes (x and y, 0.4 % apart; the flight mixes them and still
/// nears terminal speed), the swing's frequency 1 % and rate 2 % (peaks sampled at 1 ms over
/// three half periods).
fn round_solid() -> Result<Vec<Check>, String> {
    let edge = "canopy.edge_length_m=0.25";
    let sym = "canopy.imperfection_m=0";
    let r = crate::steady::steady(&super::system::round_solid(&[
        sym,
        edge,
        "time.duration_s=1.2",
    ])?)
    .map_err(|e| e.to_string())?;
    let h = 1e-3;
    let tilts: Vec<f64> = r
        .modes
        .iter()
        .filter(|m| m.description.starts_with("grows: tilt"))
        .map(|m| -(1.0 - h * m.growth_rate_per_s).ln() / h)
        .collect();
    if tilts.is_empty() {
        return Err("no growing tilt mode".into());
    }
    let mapped = tilts.iter().sum::<f64>() / tilts.len() as f64;
    let rows = flight(&super::system::round_solid(&[
        sym,
        edge,
        "time.duration_s=1.6",
    ])?)?;
    let mut out = vec![Check::new(
        "stability-round-solid-tilt",
        &format!("tilt growth (1/s), symmetric flight 1.2–1.6 s, {edge}"),
        mapped,
        "its growing tilt modes (mean), mapped through implicit Euler at 1 ms",
        log_rate(&rows, 1.2, 1.6),
        0.01,
    )];
    let mut sets = vec![
        super::real::RESTORING[0],
        super::real::RESTORING[1],
        edge,
        "time.duration_s=1.2",
    ];
    let r =
        crate::steady::steady(&super::system::round_solid(&sets)?).map_err(|e| e.to_string())?;
    let swing = r
        .modes
        .iter()
        .find(|m| m.description.starts_with("decays: sideways oscillation"))
        .ok_or("no sideways oscillation among the modes")?;
    sets.pop();
    sets.push("time.duration_s=7");
    let (f, rate) = swing_of(&flight(&super::system::round_solid(&sets)?)?)?;
    out.push(Check::new(
        "stability-round-solid-swing",
        &format!("swing frequency (Hz), restoring C_N(α), flight after 2 s, {edge}"),
        swing.frequency_hz,
        "its sideways-oscillation mode",
        f,
        0.01,
    ));
    out.push(Check::new(
        "stability-round-solid-swing",
        &format!("swing decay rate (1/s), restoring C_N(α), flight after 2 s, {edge}"),
        swing.growth_rate_per_s,
        "its sideways-oscillation mode",
        rate,
        0.02,
    ));
    Ok(out)
}

/// The frequency (Hz) and growth rate (1/s) of the lateral speed's oscillation after 2 s:
/// from its zero crossings and the largest |v_x| between them.
fn swing_of(rows: &[[f64; 3]]) -> Result<(f64, f64), String> {
    let late: Vec<&[f64; 3]> = rows.iter().filter(|r| r[0] >= 2.0).collect();
    let crossings: Vec<f64> = late
        .windows(2)
        .filter(|w| w[0][1] * w[1][1] < 0.0)
        .map(|w| w[1][0])
        .collect();
    if crossings.len() < 3 {
        return Err(format!("the swing crossed zero {} times", crossings.len()));
    }
    let half = (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64;
    let peaks: Vec<f64> = crossings
        .windows(2)
        .map(|w| {
            late.iter()
                .filter(|r| r[0] > w[0] && r[0] < w[1])
                .map(|r| r[1].abs())
                .fold(0.0, f64::max)
        })
        .collect();
    let rate = (peaks[peaks.len() - 1] / peaks[0]).ln() / (half * (peaks.len() - 1) as f64);
    Ok((0.5 / half, rate))
}

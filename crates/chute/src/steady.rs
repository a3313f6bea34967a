//! `chute steady`: a scenario's steady descent as an equilibrium and the modes of the motion
//! about it (docs/cli.md §`chute steady`; the method is `engine::stability`).
//!
//! The scenario is flown for `time.duration_s` (no outputs) to come near the equilibrium;
//! Newton then solves `F(q, V) = 0` in the falling frame, holding the payload (or the first
//! canopy node) in place. The modes are those of the exact linearisation there.

pub mod classify;

use std::path::Path;

use engine::stability::{self, Linearized, ModeOptions, SteadyOptions};
use faer::c64;

use crate::app::AppError;
use crate::scenario::Scenario;

/// Files a `chute steady --out DIR` writes.
pub const STABILITY_JSON: &str = "stability.json";
pub use crate::output::mode_viewer::MODES_HTML;

/// One mode of [`SteadyReport::modes`] (a complex pair appears once, with its frequency).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ModeRecord {
    /// `Re λ` (1/s): positive grows, negative decays.
    pub growth_rate_per_s: f64,
    /// `|Im λ| / 2π` (Hz); 0 for a mode that does not oscillate.
    pub frequency_hz: f64,
    /// `−Re λ / |λ|`; null for a neutral mode (λ = 0).
    pub damping_ratio: Option<f64>,
    /// λ as `[Re, Im]` (1/s).
    pub eigenvalue: [f64; 2],
    /// How exactly the mode solves the linearised equations (engine::stability::Mode).
    pub backward_error: f64,
    /// Shares of its kinetic energy by kind of motion.
    pub shares: classify::Shares,
    /// In words.
    pub description: String,
    /// The shape on every node (x, y, z; complex), largest component 1 (not in the JSON).
    #[serde(skip)]
    pub shape: Vec<[c64; 3]>,
}

/// What `chute steady` finds (the contents of `stability.json`).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct SteadyReport {
    /// Scenario name.
    pub scenario_name: String,
    /// The equilibrium's vertical velocity (m/s, signed like `summary.json`'s).
    pub terminal_velocity_mps: f64,
    /// The equilibrium's velocity (m/s; the held node's when it turns).
    pub velocity_mps: [f64; 3],
    /// Its turn rate about the vertical (rad/s, anticlockwise seen from above).
    pub spin_rad_s: f64,
    /// The transient's mean vertical velocity over its final 20 % (m/s), for comparison.
    pub transient_terminal_velocity_mps: f64,
    /// Simulated time of the transient (s).
    pub transient_s: f64,
    /// `‖F‖∞` at the equilibrium (N).
    pub residual_n: f64,
    /// Newton iterations from the transient's end.
    pub newton_iterations: usize,
    /// The Cayley shift σ of the mode search (1/s).
    pub shift_per_s: f64,
    /// The modes found, largest growth rate first.
    pub modes: Vec<ModeRecord>,
    /// The equilibrium's node positions (m; not in the JSON).
    #[serde(skip)]
    pub positions_m: Vec<[f64; 3]>,
    /// The canopy's triangles (node indices; not in the JSON).
    #[serde(skip)]
    pub triangles: Vec<[usize; 3]>,
    /// Rod edges: canopy strip and lines (node indices; not in the JSON).
    #[serde(skip)]
    pub segments: Vec<[usize; 2]>,
}

/// Fly `s` for `time.duration_s` (longer when no equilibrium is near its end:
/// [`LONGER_FLIGHTS`]), solve its steady descent and its modes.
pub fn steady(s: &Scenario) -> Result<SteadyReport, AppError> {
    uninterrupted(s)?;
    let built = crate::build::build(s)?;
    let mut cfg = crate::app::run_config(s, false);
    let leg = s.time.duration_s;
    cfg.stepping.duration_s = leg * (1 + LONGER_FLIGHTS) as f64;
    let mut session =
        crate::runner::Session::new(built, cfg).map_err(|e| AppError::RunFailed(e.to_string()))?;
    let mut tries = 0;
    let eq = loop {
        session
            .advance_to(leg * (1 + tries) as f64)
            .map_err(|e| AppError::RunFailed(format!("the transient stopped: {e}")))?;
        match equilibrium(&session, s.fluid.gravity_mps2) {
            Ok(eq) => break eq,
            Err(_) if tries < LONGER_FLIGHTS && !session.finished() => tries += 1,
            Err(e) => return Err(AppError::RunFailed(e.to_string())),
        }
    };
    let transient = session.summary();
    let b = session.built();
    let (model, state) = (&b.model, &b.state);
    let lin = Linearized::at(model, &eq.q, &eq.v, state.t);
    let mode_opts = ModeOptions::default();
    let found =
        stability::modes(&lin, &mode_opts).map_err(|e| AppError::RunFailed(e.to_string()))?;
    let n_nodes = model.layout.n_nodes;
    let modes = found
        .iter()
        .filter(|m| m.eigenvalue.im >= 0.0)
        .map(|m| record(m, &eq.q, &model.mass, n_nodes))
        .collect();
    Ok(SteadyReport {
        scenario_name: s.name.clone(),
        terminal_velocity_mps: eq.velocity[2],
        velocity_mps: eq.velocity,
        spin_rad_s: eq.spin,
        transient_terminal_velocity_mps: transient.terminal_velocity_mps,
        transient_s: state.t,
        residual_n: eq.residual_n,
        newton_iterations: eq.iterations,
        shift_per_s: mode_opts.shift,
        modes,
        positions_m: (0..n_nodes)
            .map(|i| [eq.q[3 * i], eq.q[3 * i + 1], eq.q[3 * i + 2]])
            .collect(),
        triangles: b.triangles.clone(),
        segments: b.segments.clone(),
    })
}

/// When Newton finds no equilibrium near the transient's end, the flight goes on for another
/// `time.duration_s`, at most this many times.
pub const LONGER_FLIGHTS: usize = 2;

/// The steady descent nearest the session's state (the payload held, or a canopy node).
fn equilibrium(
    session: &crate::runner::Session,
    gravity: f64,
) -> Result<stability::Steady, stability::StabilityError> {
    let b = session.built();
    let (model, state) = (&b.model, &b.state);
    let hold = b
        .payload_node
        .or(b.canopy_nodes.first().copied())
        .unwrap_or(0);
    let opts = SteadyOptions::recommended(model, gravity, hold);
    let v = mean_velocity(model, &state.v);
    stability::steady_descent(model, &state.q, v, state.t, &opts)
}

/// Mass-weighted mean velocity of the nodes (m/s).
fn mean_velocity(model: &engine::Model, v: &[f64]) -> [f64; 3] {
    let n = model.layout.n_nodes;
    let mut p = [0.0; 3];
    let mut m = 0.0;
    for i in 0..n {
        m += model.mass[3 * i];
        for k in 0..3 {
            p[k] += model.mass[3 * i + k] * v[3 * i + k];
        }
    }
    p.map(|x| x / m)
}

fn record(m: &engine::stability::Mode, q: &[f64], mass: &[f64], n_nodes: usize) -> ModeRecord {
    let l: c64 = m.eigenvalue;
    let shares = classify::shares(m, q, mass, n_nodes);
    ModeRecord {
        growth_rate_per_s: l.re,
        frequency_hz: l.im.abs() / std::f64::consts::TAU,
        damping_ratio: (l.norm() >= classify::NEUTRAL).then(|| -l.re / l.norm()),
        eigenvalue: [l.re, l.im],
        backward_error: m.backward_error,
        description: classify::describe(l, &shares),
        shares,
        shape: (0..n_nodes)
            .map(|i| [0, 1, 2].map(|k| m.shape[3 * i + k]))
            .collect(),
    }
}

/// The console table of `r`.
pub fn table(r: &SteadyReport) -> String {
    let mut out = format!(
        "steady descent of `{}`: v_t = {:.4} m/s (the {:.3} s transient's: {:.4} m/s), ‖F‖∞ = {:.2e} N after {} Newton iterations\n",
        r.scenario_name,
        r.terminal_velocity_mps,
        r.transient_s,
        r.transient_terminal_velocity_mps,
        r.residual_n,
        r.newton_iterations
    );
    out += &format!(
        "{:>4}  {:>12}  {:>10}  {:>8}  description\n",
        "mode", "growth (1/s)", "freq (Hz)", "damping"
    );
    for (i, m) in r.modes.iter().enumerate() {
        let zeta = m.damping_ratio.map_or("-".into(), |z| format!("{z:.3}"));
        out += &format!(
            "{:>4}  {:>12.4e}  {:>10.4}  {:>8}  {}\n",
            i + 1,
            m.growth_rate_per_s,
            m.frequency_hz,
            zeta,
            m.description
        );
    }
    out
}

/// Write `r` as `dir/stability.json` and the page animating its modes, `dir/modes.html`
/// ([`check_out`] first; the directory is created when missing).
pub fn write(r: &SteadyReport, dir: &Path) -> Result<(), AppError> {
    check_out(dir)?;
    std::fs::create_dir_all(dir).map_err(|e| AppError::io(dir, e))?;
    let text = serde_json::to_string_pretty(r).map_err(|e| AppError::Input(e.to_string()))?;
    let html = crate::output::mode_viewer::modes_html(r);
    for (name, bytes) in [
        (STABILITY_JSON, text.as_bytes()),
        (MODES_HTML, html.as_bytes()),
    ] {
        let path = dir.join(name);
        crate::output::atomic::write_atomic(&path, bytes).map_err(|e| AppError::io(&path, e))?;
    }
    Ok(())
}

/// A steady descent is one that nothing interrupts: no ground, no line pulls, no wind that
/// changes with height.
fn uninterrupted(s: &Scenario) -> Result<(), AppError> {
    let why = if s.guidance.is_some() {
        Some(("[guidance]", "it pulls the lines as the canopy falls"))
    } else if !s.control.is_empty() {
        Some((
            "[[control]]",
            "its line pulls change the canopy as it falls",
        ))
    } else if s.wind.is_some() {
        Some(("[wind]", "the wind it meets changes with its height"))
    } else if s.atmosphere.ground_altitude_m.is_some() {
        Some((
            "atmosphere.ground_altitude_m",
            "the ground ends the descent",
        ))
    } else {
        None
    };
    match why {
        Some((key, reason)) => Err(AppError::Input(format!(
            "`chute steady` needs a descent that nothing interrupts: `{key}` is set, and {reason}"
        ))),
        None => Ok(()),
    }
}

/// Refuse `dir` as `chute steady`'s output when it holds anything but `stability.json` and `modes.html`
/// (a run, a study), so that results never mix.
pub fn check_out(dir: &Path) -> Result<(), AppError> {
    if let Ok(entries) = std::fs::read_dir(dir) {
        let other = entries
            .flatten()
            .map(|e| e.file_name())
            .find(|n| n != STABILITY_JSON && n != MODES_HTML);
        if let Some(n) = other {
            return Err(AppError::Input(format!(
                "--out `{}` holds `{}`: it is not a `chute steady` directory; choose another --out",
                dir.display(),
                n.to_string_lossy()
            )));
        }
    } else if dir.exists() {
        return Err(AppError::Input(format!(
            "--out `{}` is not a directory; choose another --out",
            dir.display()
        )));
    }
    Ok(())
}

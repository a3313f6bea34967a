//! Whole-parachute cases through the application: scenario text → [`crate::build::build`]
//! → [`crate::runner::simulate`] (outputs written to a temporary directory). `--quick`
//! shortens the runs or coarsens the meshes; each check's quantity text says which.
use super::Check;
use crate::build::{build, Built};
use crate::output::summary::Summary;
use crate::scenario::Scenario;
use engine::ImplicitEuler;
use std::sync::atomic::AtomicBool;

const ROD_200N: &str = include_str!("../../../../scenarios/report-rod-200n.toml");
const SHELL_4: &str = include_str!("../../../../scenarios/report-shell-4-sites.toml");
const HEX_N6: &str = include_str!("../../../../scenarios/dismech-hex-n6.toml");
const ROUND_SOLID: &str = include_str!("../../../../scenarios/round-solid.toml");
const DROP_1000: &str = include_str!("../../../../scenarios/drop-1000m.toml");
/// Where the bundled scenarios live, so that their relative `mesh_file` paths resolve.
const SCENARIO_DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenarios");

type CaseResult = Result<Vec<Check>, String>;

/// Parse a bundled scenario with overrides (no snapshots: shortened runs would put the
/// bundled snapshot times past their end).
pub(super) fn scenario(text: &str, file: &str, overrides: &[&str]) -> Result<Scenario, String> {
    let mut all = vec!["output.snapshots_s=[]".to_string()];
    all.extend(overrides.iter().map(|s| s.to_string()));
    Scenario::from_str_with_name(text, &format!("{SCENARIO_DIR}/{file}"), &all)
        .map_err(|e| e.to_string())
}

/// `round-solid.toml` (the incidence law's round canopy) with `overrides`.
pub(super) fn round_solid(overrides: &[&str]) -> Result<Scenario, String> {
    scenario(ROUND_SOLID, "round-solid.toml", overrides)
}

/// The bundled 4-site shell as the report's model (springs + hinges, dt = 1 ms: the model
/// these checks' references were set on) with `overrides` on top.
fn report_shell_4(overrides: &[&str]) -> Result<Scenario, String> {
    let mut all: Vec<&str> = crate::scenario::REPORT_SHELL_MODEL.to_vec();
    all.extend_from_slice(overrides);
    scenario(SHELL_4, "report-shell-4-sites.toml", &all)
}

/// Build and simulate `s`, writing its outputs to a temporary directory (VTK frames and
/// snapshots off: only the summary is needed).
fn simulate(s: &Scenario) -> Result<(Summary, Built), String> {
    let dir = tempfile::tempdir().map_err(|e| e.to_string())?;
    simulate_in(s, dir.path())
}

/// [`simulate`] writing into `dir` (its time series stays there for the caller).
pub(super) fn simulate_in(s: &Scenario, dir: &std::path::Path) -> Result<(Summary, Built), String> {
    let mut built = build(s).map_err(|e| e.to_string())?;
    let mut cfg = crate::app::run_config(s, false);
    cfg.outputs.frame_interval_s = 0.0;
    cfg.outputs.snapshots_s.clear();
    let stop = AtomicBool::new(false);
    let r = crate::runner::simulate(&mut built, &cfg, dir, &stop).map_err(|e| e.to_string())?;
    if !r.complete {
        return Err(format!(
            "run stopped early: {}",
            r.stop_reason.unwrap_or_default()
        ));
    }
    Ok((r.summary, built))
}

/// The report's rod canopy (6 m × 3 m Kevlar strip, 200 N at the ends). Rod drag is
/// isotropic per node, `A_k = 2 r_d l̄_k`, so whatever the bent shape the steady descent
/// balances the total weight with `½ ρ C_D A v²`, `A = Σ A_k` = 18 m² (span × width): the
/// reference is exact for the steady state, and backward Euler's fixed point is that state.
/// What remains is the transient in the final 20 % window (from 4 s in the quick run): the
/// descent-speed deficit decays like e^(−2 g t/v_t) ≈ e^(−13) and the strip's bending
/// oscillation is damped by drag and backward Euler; 1e-3 bounds both with a wide margin
/// (measured ~5e-7) yet fails for any drag-area or weight error.
pub fn rod_canopy(quick: bool) -> CaseResult {
    let (over, what): (&[&str], &str) = if quick {
        (&["time.duration_s=5"], "5 s run (quick)")
    } else {
        (&[], "10 s run")
    };
    let s = scenario(ROD_200N, "report-rod-200n.toml", over)?;
    let (sum, built) = simulate(&s)?;
    let area = s.canopy.span_m * s.canopy.width_m;
    let vt = (2.0 * built.total_weight_n
        / (s.fluid.density_kg_m3 * s.fluid.drag_coefficient * area))
        .sqrt();
    let name = "rod-canopy-terminal";
    Ok(vec![
        Check::new(
            name,
            &format!("terminal descent speed (m/s), {what}"),
            vt,
            "√(2W/(ρ C_D A)), A = span × width",
            -sum.terminal_velocity_mps,
            1e-3,
        ),
        Check::new(
            name,
            &format!("mean drag_z / total weight, {what}"),
            1.0,
            "steady descent: drag = weight",
            sum.mean_drag_z_n / sum.total_weight_n,
            1e-3,
        ),
    ])
}

/// The round canopy with its payload, released moving with a uniform wind: no air moves
/// sideways past it, so drag never acts sideways and it lands the wind times its time aloft
/// from its still-air landing point, the release point by symmetry. Exact to the solver's
/// tolerance (measured 4e-9 and 9e-9 from 300 m): 1e-6 fails for any wind the laws
/// mishandle or any sideways force.
pub fn wind_landing(quick: bool) -> CaseResult {
    let (alt, what) = match quick {
        true => ("atmosphere.altitude_m=40", "from 40 m (quick)"),
        false => ("atmosphere.altitude_m=300", "from 300 m"),
    };
    let over = [
        "canopy.edge_length_m=0.35",
        alt,
        "fluid.wind_mps=[4.0, -3.0, 0.0]",
        "canopy.released_with_wind=true",
    ];
    let s = scenario(DROP_1000, "drop-1000m.toml", &over)?;
    let (sum, _) = simulate(&s)?;
    let r = &sum.recovery;
    let (t, p) = (r.flight_time_s.zip(r.landing_point_m)).ok_or("the canopy did not land")?;
    let check = |k: usize, u: f64, axis: &str| {
        Check::new(
            "wind-drift-landing",
            &format!("landing {axis} (m), round canopy in a uniform (4, −3) m/s wind, {what}"),
            u * t,
            "U·T: the wind times the time aloft",
            p[k],
            1e-6,
        )
    };
    Ok(vec![check(0, 4.0, "x"), check(1, -3.0, "y")])
}

/// The report's shell canopy (200 N on the 4 corners). Whatever the shape, a steady
/// descent has drag = weight; the check bounds what is left of the transient (the canopy
/// folds and breathes) in the mean over the final 20 % window: 2 %.
pub fn shell_force_balance(quick: bool) -> CaseResult {
    let (over, what): (&[&str], &str) = if quick {
        (
            &["canopy.edge_length_m=0.5", "time.duration_s=5"],
            "ℓ = 0.5 m, 5 s (quick)",
        )
    } else {
        (&["canopy.edge_length_m=0.25"], "ℓ = 0.25 m, 10 s")
    };
    let s = report_shell_4(over)?;
    let (sum, _) = simulate(&s)?;
    Ok(vec![Check::new(
        "shell-canopy-force-balance",
        &format!("mean drag_z / total weight, {what}"),
        1.0,
        "steady descent: drag = weight",
        sum.mean_drag_z_n / sum.total_weight_n,
        0.02,
    )])
}

/// A canopy symmetric under reflections in x and y, loaded symmetrically, in still air: it
/// must neither drift nor spin. The union-jack rectangle is symmetric under both mirror
/// planes, so the horizontal momentum and the angular momentum about the vertical axis
/// stay zero up to round-off, unless an element breaks the symmetry (an ordering bias in
/// the assembly, a one-sided drag term). Checked as dimensionless ratios to the descent
/// speed `|v_z|`: the horizontal drift speed and the rim speed of the spin, `|ω_z| R` (R
/// the largest node distance from the axis); round-off after a few thousand steps is
/// ≲ 1e-10, so 1e-6 leaves room only for round-off growth.
pub fn no_spin(quick: bool) -> CaseResult {
    let duration = if quick { 2.0 } else { 5.0 };
    let d = format!("time.duration_s={duration}");
    let s = report_shell_4(&["canopy.edge_length_m=0.5", &d])?;
    let mut built = build(&s).map_err(|e| e.to_string())?;
    let cfg = crate::app::run_config(&s, false);
    let mut stepper = ImplicitEuler::new(&built.model, cfg.newton).map_err(|e| e.to_string())?;
    let mut state = built.state.clone();
    let steps = (duration / cfg.stepping.dt_s).round() as usize;
    for _ in 0..steps {
        stepper
            .step(&mut built.model, &mut state, cfg.stepping.dt_s)
            .map_err(|e| e.to_string())?;
    }
    let m = &built.model;
    let n = m.layout.n_nodes;
    let mass: f64 = (0..n).map(|i| m.node_mass(i)).sum();
    let mean =
        |k: usize, v: &[f64]| (0..n).map(|i| m.node_mass(i) * v[3 * i + k]).sum::<f64>() / mass;
    let (cx, cy) = (mean(0, &state.q), mean(1, &state.q));
    let (vx, vy, vz) = (mean(0, &state.v), mean(1, &state.v), mean(2, &state.v));
    let (mut lz, mut iz, mut rmax) = (0.0, 0.0, 0.0f64);
    for i in 0..n {
        let (x, y) = (state.q[3 * i] - cx, state.q[3 * i + 1] - cy);
        let (u, w) = (state.v[3 * i] - vx, state.v[3 * i + 1] - vy);
        lz += m.node_mass(i) * (x * w - y * u);
        iz += m.node_mass(i) * (x * x + y * y);
        rmax = rmax.max(x.hypot(y));
    }
    let what = format!("ℓ = 0.5 m, {duration} s");
    let name = "symmetric-canopy-no-spin";
    let src = "mirror symmetry: zero by construction";
    Ok(vec![
        Check::near_zero(
            name,
            &format!("horizontal speed / |v_z|, {what}"),
            src,
            vx.hypot(vy) / vz.abs(),
            1e-6,
        ),
        Check::near_zero(
            name,
            &format!("spin |ω_z| R / |v_z|, {what}"),
            src,
            (lz / iz).abs() * rmax / vz.abs(),
            1e-6,
        ),
    ])
}

/// Newton tolerances for results that must not depend on the iteration path.
const TIGHT: [&str; 3] = [
    "time.newton_tolerance_n=1e-8",
    "time.newton_relative_tolerance=1e-10",
    "time.newton_step_tolerance_m=1e-12",
];

/// The DisMech peer's hexagonal parachute (n = 6 mesh, its parameters, its cos² pressure
/// drag `shell_drag = "pressure"`), against its reported ≈ 2.08 m/s descent. The peer's
/// run is itself 3 s at dt = 10 ms, and the models may differ in details (joints, lumped
/// masses), and the peer reports neither its averaging window nor its Newton tolerance;
/// the tolerance 10 % is for that, not for our discretisation (measured −1.3 %).
/// A second check runs the report's law (cos³ normal drag, `shell_drag = "report"`): a
/// canopy whose facets tilt by θ then loses drag by cos θ more, so it falls faster, and the
/// check against the peer number is looser (25 %, order of magnitude; see docs/validation.md).
/// Both run at tight Newton tolerances instead of the scenario's (the peer's, for the
/// side-by-side timing): at the peer's `1e-4` relative and `1e-4 m` step tests the report-law
/// speed at 3 s depends on the Newton path by 1.6 % (a change of predictor moved it), at
/// these it does not (two predictors agree to 3e-8).
pub fn dismech_hex(_quick: bool) -> CaseResult {
    let mut out = Vec::new();
    for (law, tol) in [("pressure", 0.10), ("report", 0.25)] {
        let o = format!("fluid.shell_drag=\"{law}\"");
        let set: Vec<&str> = std::iter::once(o.as_str()).chain(TIGHT).collect();
        let s = scenario(HEX_N6, "dismech-hex-n6.toml", &set)?;
        let (sum, _) = simulate(&s)?;
        out.push(Check::new(
            &format!("dismech-hex-n6-{law}"),
            &format!("terminal descent speed (m/s), shell_drag = {law}, 3 s"),
            2.08,
            "DisMech hexparachute (peer code), reported",
            -sum.terminal_velocity_mps,
            tol,
        ));
    }
    Ok(out)
}

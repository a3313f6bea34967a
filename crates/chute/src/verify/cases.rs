//! The registry of verification cases, and the engine-level ones (rods, drag, integrator):
//! every set-up comes from [`engine::reference`], the same code the engine's tests run.
//! Shell cases are in [`super::shell_cases`], whole-parachute cases in [`super::system`].
use super::{
    membrane_cases, midedge_cases, real, scordelis_lo, shell_cases, stability, system, Case, Check,
};
use engine::aero::Fluid;
use engine::reference::cantilever::{
    elastica, end_moment, self_weight, tip_load, BISSHOPP_DRUCKER,
};
use engine::reference::falling::{self, fall, tanh_law, Body, G, VT};
use engine::reference::spring::{backward_euler_decay, spring_model};
use engine::reference::vibration::first_period;
use engine::{ImplicitEuler, NewtonOptions, State};

/// Reference rod of the cantilever cases: L = 1 m, 51 nodes, steel, r = 5 mm.
const L: f64 = 1.0;
const N: usize = 51;
const R: f64 = 0.005;

type CaseResult = Result<Vec<Check>, String>;

fn err(e: impl std::fmt::Display) -> String {
    e.to_string()
}

/// Every case, in report order.
pub fn all() -> Vec<Case> {
    let c = |name, quick, run| Case { name, quick, run };
    vec![
        c("be-spring-damping", true, spring_damping),
        c("cantilever-tip-load", true, cantilever_tip_load),
        c("cantilever-self-weight", true, cantilever_self_weight),
        c("elastica", true, elastica_cases),
        c("end-moment-arc", true, end_moment_arc),
        c("cantilever-first-period", true, cantilever_period),
        c("cylinder-bending-energy", true, shell_cases::cylinder_case),
        c("plate-simply-supported", true, shell_cases::plate_case),
        c("shell-cantilever-strip", true, shell_cases::strip_case),
        c("midedge-cylinder", true, midedge_cases::cylinder_case),
        c("midedge-plate", true, midedge_cases::plate_case),
        c(
            "patch-cst-uniform-stretch",
            true,
            membrane_cases::uniform_stretch_case,
        ),
        c(
            "patch-cst-uniaxial-nu",
            true,
            membrane_cases::cst_uniaxial_case,
        ),
        c(
            "patch-fabric-uniaxial-nu12",
            true,
            membrane_cases::fabric_nu12_case,
        ),
        c(
            "patch-fabric-uniaxial-nu21",
            true,
            membrane_cases::fabric_nu21_case,
        ),
        c(
            "patch-no-compression",
            true,
            membrane_cases::no_compression_case,
        ),
        c("patch-springs-uniaxial", true, membrane_cases::springs_case),
        c("scordelis-lo-springs", false, scordelis_lo::roof_case),
        c("scordelis-lo-cst", false, scordelis_lo::roof_cst_case),
        c("falling", true, falling_cases),
        c("wind-drift", true, wind_drift),
        c("rod-canopy-terminal", true, system::rod_canopy),
        c(
            "shell-canopy-force-balance",
            true,
            system::shell_force_balance,
        ),
        c("symmetric-canopy-no-spin", true, system::no_spin),
        c("dismech-hex-n6", true, system::dismech_hex),
        c("real-cd0", true, real::cd0),
        c("real-t10-descent", true, real::t10),
        c("stability", true, stability::stability),
    ]
}

/// An undamped spring (ω = 20 rad/s) from a 1 cm stretch, 50 steps of dt = 0.01 s: the
/// amplitude ratio must be `(1 + (ω dt)²)^(−25)` exactly. The problem is linear, Newton
/// converges to 1e-13 N (forces ~4 N), so round-off (~1e-12 relative over 50 steps) is the
/// only error: 1e-8 still fails for any change of the integrator.
fn spring_damping(_quick: bool) -> CaseResult {
    let (k_axial, rest, mass): (f64, f64, f64) = (200.0, 0.5, 0.1);
    let omega = (k_axial / rest / mass).sqrt();
    let (dt, steps) = (1e-2, 50);
    let (mut model, mut state) = spring_model(k_axial, rest, mass);
    state.q[3] = rest + 0.01;
    let opts = NewtonOptions {
        force_tol_abs: Some(1e-13),
        ..Default::default()
    };
    let mut stepper = ImplicitEuler::new(&model, opts).map_err(err)?;
    let amp = |s: &State| ((s.q[3] - rest).powi(2) + (s.v[3] / omega).powi(2)).sqrt();
    let a0 = amp(&state);
    for _ in 0..steps {
        stepper.step(&mut model, &mut state, dt).map_err(err)?;
    }
    Ok(vec![Check::new(
        "be-spring-damping",
        "amplitude ratio after 50 steps, ω dt = 0.2",
        backward_euler_decay(omega, dt).powi(steps),
        "backward Euler on x'' = −ω²x: |1/(1 + iω dt)|ⁿ",
        amp(&state) / a0,
        1e-8,
    )])
}

// Cantilever tolerances (docs/rods.md): discretisation error of the tip deflection is
// O(1/n²) ≈ 1e-4 for 50 edges and the geometric nonlinearity O((δ/L)²) ≤ 1e-7, so 1 % is a
// wide margin that still catches a wrong stiffness factor or a misplaced clamp (3 % for l/2).
fn cantilever_tip_load(_quick: bool) -> CaseResult {
    let r = tip_load(N, L, R, 1e-4).map_err(err)?;
    Ok(vec![Check::new(
        "cantilever-tip-load",
        "tip deflection δ (m), δ/L = 1e-4",
        r.reference,
        "Euler–Bernoulli: P L³/(3 EI)",
        r.simulated,
        0.01,
    )])
}

fn cantilever_self_weight(_quick: bool) -> CaseResult {
    let r = self_weight(N, L, R).map_err(err)?;
    Ok(vec![Check::new(
        "cantilever-self-weight",
        "tip deflection δ (m) under self-weight",
        r.reference,
        "Euler–Bernoulli: q L⁴/(8 EI)",
        r.simulated,
        0.01,
    )])
}

/// Elastica: P/EA < 1e-4 (nearly inextensible), O(1/n²) ≈ 1e-4 discretisation, and the
/// table's 5 digits: 1 % is a wide margin.
fn elastica_cases(_quick: bool) -> CaseResult {
    let mut out = Vec::new();
    for (alpha, w_ref, u_ref) in BISSHOPP_DRUCKER {
        let (w, u) = elastica(N, L, R, alpha).map_err(err)?;
        let name = format!("elastica-alpha-{alpha}");
        let src = "Bisshopp & Drucker (1945), Table 1";
        out.push(Check::new(&name, "tip deflection w/L", w_ref, src, w, 0.01));
        out.push(Check::new(
            &name,
            "tip shortening (L − x)/L",
            u_ref,
            src,
            u,
            0.01,
        ));
    }
    Ok(out)
}

/// The nodes lie on a circle of radius `R/cos³(ψ/2)` (ψ the turning per node, 0.064 rad):
/// 3ψ²/8 ≈ 1.5e-3 from `EI/M`, inside 0.5 %.
fn end_moment_arc(_quick: bool) -> CaseResult {
    let r = end_moment(N, L, R).map_err(err)?;
    let name = "end-moment-arc";
    Ok(vec![
        Check::new(
            name,
            "arc radius (m), last edge turned by π",
            r.exact,
            "pure bending: R = EI/M",
            r.radius,
            0.005,
        ),
        Check::new(
            name,
            "last edge's turning angle / π",
            1.0,
            "pure bending: θ = M s/EI = π",
            1.0 + r.tip_angle_err,
            0.005,
        ),
    ])
}

/// Spatial O(1/n²) ≈ 1e-4, backward Euler's period lengthening (ω dt)²/3 ≈ 8e-5 at
/// dt = T₁/400, mode-2 content of the start shifting the crossings ≤ 0.4 %: 2 %.
fn cantilever_period(quick: bool) -> CaseResult {
    let periods = if quick { 4.3 } else { 8.3 };
    let r = first_period(N, L, R, 400, periods).map_err(err)?;
    Ok(vec![Check::new(
        "cantilever-first-period",
        &format!("first period T₁ (s), dt = T₁/400, {periods} periods"),
        r.exact,
        "Euler–Bernoulli: 2π/(1.8751² √(EI/ρAL⁴))",
        r.measured,
        0.02,
    )])
}

/// Rigid bodies falling from rest (v_t = 3 m/s, dt = 1 ms). Backward Euler's global error
/// is O(g dt / v_t) ≈ 0.3 % of v_t: 1 % at t = v_t/g. At t = 2 s the transient deficit is
/// 1 − tanh(6.5) ≈ 4e-6 plus the integrator lag, far below 0.1 %.
fn falling_cases(_quick: bool) -> CaseResult {
    let mut out = Vec::new();
    for (body, tag) in [
        (Body::SheetTriangle, "sheet-triangle-drag"),
        (Body::SheetPressure, "sheet-pressure-drag"),
        (Body::StripNodes, "strip-node-drag"),
    ] {
        let r = fall(body, 1e-3, 2.0).map_err(err)?;
        let t1 = VT / G;
        let &(t, v) = r
            .series
            .iter()
            .min_by(|a, b| (a.0 - t1).abs().total_cmp(&(b.0 - t1).abs()))
            .ok_or("empty series")?;
        let name = format!("falling-{tag}");
        let src = "v_t tanh(g t/v_t), v_t = √(2mg/(ρ C_D A))";
        out.push(Check::new(
            &name,
            &format!("descent speed (m/s) at t = {t:.3} s ≈ v_t/g"),
            tanh_law(VT, G, t),
            src,
            v,
            0.01,
        ));
        out.push(Check::new(
            &name,
            "descent speed (m/s) at t = 2 s",
            tanh_law(VT, G, 2.0),
            src,
            r.final_speed,
            1e-3,
        ));
    }
    Ok(out)
}

/// A strip (isotropic node drag) dropped in a 5 m/s wind: the horizontal relative speed
/// decays at a rate ≥ g/v_t ≈ 3.3 /s, so after 4 s it is e^-13 of the start; backward
/// Euler's fixed point is exactly U∞. 0.5 % can only fail if the wind is mishandled.
fn wind_drift(quick: bool) -> CaseResult {
    let fluid = Fluid {
        wind: [5.0, 0.0, 0.0],
        ..Fluid::air()
    };
    let (mut model, mut state) = falling::strip(6, 1.0, 1.0, 0.98, 0.0, &fluid);
    let series = falling::run(&mut model, &mut state, 1e-3, 4000).map_err(err)?;
    let v = series.last().ok_or("no steps")?.1;
    let mut checks = vec![Check::new(
        "wind-drift-strip",
        "horizontal velocity (m/s) after 4 s in U∞ = 5 m/s",
        5.0,
        "steady state: zero relative horizontal velocity",
        v[0],
        5e-3,
    )];
    checks.extend(system::wind_landing(quick)?);
    Ok(checks)
}

//! Recovery-system metrics on whole runs: the suspension lines carry the payload in steady
//! descent, the payload-mode summary fields follow their definitions, and a drop through the
//! 1976 standard atmosphere ends on the ground with the landing interpolated and the
//! equivalent sea-level rate scaled by √(ρ/ρ_SL).
use chute::scenario::Scenario;

use crate::common::{repo, run_complete};

fn rod_scenario(set: &[&str]) -> Scenario {
    let mut all = vec![
        "time.dt_s=2e-3".to_string(),
        "output.snapshots_s=[]".to_string(),
        "output.frame_interval_s=1".to_string(),
    ];
    all.extend(set.iter().map(|s| s.to_string()));
    Scenario::load(&repo().join("scenarios/report-rod-200n.toml"), &all).unwrap()
}

/// [`rod_scenario`] with `set`, run to its end in a scratch directory: the planform area and
/// summary.json.
fn run(set: &[&str]) -> (f64, serde_json::Value) {
    let dir = tempfile::tempdir().unwrap();
    let (b, j) = run_complete(&rod_scenario(set), dir.path());
    (b.planform_area_m2, j)
}

fn f(j: &serde_json::Value, k: &str) -> f64 {
    j[k].as_f64().unwrap_or_else(|| panic!("{k} in {j}"))
}

/// The rod strip on 4 m lines to a 200 N payload: in steady descent the force of the lines on
/// the payload balances its weight less the drag of the line ends on the payload node (about
/// 0.2 %): within 1 %. The steady tension is peak / load factor (their definitions).
/// A symmetric fall has no swing, and the nominal coefficient is drag area / S₀.
#[test]
fn payload_lines_carry_the_payload_in_steady_descent() {
    let (s0, j) = run(&[
        "load.mode=\"payload\"",
        "lines.length_m=4.0",
        "time.duration_s=6",
    ]);
    assert_eq!(j["reached_terminal"], true, "{j}");
    let steady = f(&j, "peak_line_tension_n") / f(&j, "load_factor");
    assert!(
        (steady / 200.0 - 1.0).abs() < 0.01,
        "steady tension {steady} N"
    );
    // The fall from rest overshoots the steady state: the lines see more than the weight.
    assert!(f(&j, "load_factor") > 1.1, "{j}");
    let t_peak = f(&j, "time_of_peak_line_tension_s");
    assert!(t_peak > 0.0 && t_peak < f(&j, "settling_time_s"), "{j}");
    assert!(f(&j, "oscillation_angle_deg") < 1e-6, "{j}");
    assert!((s0 - 18.0).abs() < 1e-12);
    let w = f(&j, "total_weight_n");
    assert!((f(&j, "canopy_loading_pa") - w / s0).abs() < 1e-12 * w);
    let cd0 = f(&j, "drag_area_m2") / s0;
    assert!((f(&j, "drag_coefficient_nominal") - cd0).abs() < 1e-12);
    let v = f(&j, "terminal_velocity_mps");
    let q = 0.5 * 1.225 * v * v;
    assert!((f(&j, "terminal_dynamic_pressure_pa") / q - 1.0).abs() < 1e-12);
    // Constant air: the equivalent sea-level rate is v √(1.225/1.225) = v_t.
    assert!((f(&j, "equivalent_sea_level_descent_mps") / v - 1.0).abs() < 1e-12);
    assert!(j["landing_velocity_mps"].is_null() && j["flight_time_s"].is_null());
}

/// The strip without a payload (force-mode loads) from 1000 m onto ground at 970 m in the
/// 1976 atmosphere: the run stops at the first step on or below the ground (the lowest node),
/// complete; the landing is interpolated inside the last step; the drag area measured with
/// the air of the final window is the isotropic law's C_D·span·width (the density varies by
/// 0.07 % across the window); the equivalent sea-level rate is v_t √(ρ(z̄)/1.225) to the same
/// order.
#[test]
fn a_drop_through_the_standard_atmosphere_lands_on_the_ground() {
    let (s0, j) = run(&[
        "canopy.nodes=21",
        "time.duration_s=20",
        "atmosphere.model=\"isa1976\"",
        "atmosphere.altitude_m=1000",
        "atmosphere.ground_altitude_m=970",
    ]);
    assert_eq!(j["stop_reason"], "ground", "{j}");
    let t = f(&j, "flight_time_s");
    let sim = f(&j, "simulated_time_s");
    assert!(
        t <= sim && t > sim - 2e-3 - 1e-12 && sim < 20.0,
        "{t} {sim}"
    );
    let v_t = f(&j, "terminal_velocity_mps");
    let v_land = f(&j, "landing_velocity_mps");
    assert!((v_land / v_t - 1.0).abs() < 0.02, "{v_land} vs {v_t}");
    // The summary's altitude is the canopy's mean height (no payload), above its lowest node
    // by at most the extended height; that node (an end of the bent strip, x ≠ 0) lands in
    // the symmetry plane y = 0.
    let h = f(&j, "final_extended_height_m");
    let alt = f(&j, "altitude_m");
    assert!(alt > 970.0 && alt < 970.0 + h, "{alt} vs 970 + {h}");
    let p = j["landing_point_m"].as_array().unwrap();
    let (x, y) = (p[0].as_f64().unwrap(), p[1].as_f64().unwrap());
    assert!(x.abs() < 3.0 && x.abs() > 1.0 && y.abs() < 1e-12, "{j}");
    assert_eq!(f(&j, "drift_m"), x.hypot(y), "released at the origin");
    assert_eq!(j["reached_terminal"], true, "{j}");
    let cda = f(&j, "drag_area_m2");
    assert!((cda / (1.75 * s0) - 1.0).abs() < 2e-3, "C_D·A {cda}");
    // ρ at the window's mean height, from the terminal dynamic pressure's definition.
    let rho = 2.0 * f(&j, "terminal_dynamic_pressure_pa") / (v_t * v_t);
    assert!(rho > 1.1117 && rho < 1.1117 * 1.003, "ρ {rho}");
    let eq = f(&j, "equivalent_sea_level_descent_mps");
    assert!(
        (eq / (v_t * (rho / 1.225).sqrt()) - 1.0).abs() < 1e-3,
        "{eq} {v_t}"
    );
}

//! Whole runs through the library (builder + run loop) checked against physics:
//! the rod canopy's terminal speed, the shell canopy's force balance, symmetry (no spin, no
//! drift), and the bundled scenarios' outputs.
use std::path::Path;
use std::sync::atomic::AtomicBool;

use chute::app::run_config;
use chute::build::{build, Built};
use chute::runner::{simulate, RunResult};
use chute::scenario::Scenario;

use crate::common::{read_json, repo};

fn scenario(file: &str, set: &[&str]) -> Scenario {
    let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
    Scenario::load(&repo().join("scenarios").join(file), &set).unwrap()
}

fn run(s: &Scenario, dir: &Path) -> (Built, RunResult) {
    let mut b = build(s).unwrap();
    let r = simulate(&mut b, &run_config(s, false), dir, &AtomicBool::new(false)).unwrap();
    (b, r)
}

fn json(dir: &Path) -> serde_json::Value {
    read_json(dir.join("summary.json"))
}

/// `file` with the overrides `set`, run to its end in a scratch directory: the scenario, the
/// built model at the end and summary.json.
fn complete_run(file: &str, set: &[&str]) -> (Scenario, Built, serde_json::Value) {
    let dir = tempfile::tempdir().unwrap();
    let s = scenario(file, set);
    let (b, r) = run(&s, dir.path());
    assert!(r.complete, "{:?}", r.stop_reason);
    let j = json(dir.path());
    (s, b, j)
}

/// Rod canopy with isotropic node drag: drag does not depend on the shape, so at steady
/// descent Σ ½ ρ C_D A_k v² = W_total exactly and v_t = √(2 W_total / (ρ C_D Σ A_k)), with
/// Σ A_k = span × width. Tolerance 0.5 %: the residual transient e^{−2 g t/v_t} after 4 s is
/// below 1e-5 and Newton's tolerance is ~1e-9 of the weight.
#[test]
fn rod_canopy_falls_at_the_isotropic_drag_terminal_speed() {
    let (s, b, j) = complete_run(
        "report-rod-200n.toml",
        &[
            "canopy.nodes=21",
            "time.dt_s=2e-3",
            "time.duration_s=4",
            "output.frame_interval_s=1",
        ],
    );
    let w = b.total_weight_n;
    let area = s.canopy.span_m * s.canopy.width_m;
    let v_ref = (2.0 * w / (s.fluid.density_kg_m3 * s.fluid.drag_coefficient * area)).sqrt();
    let v = j["terminal_velocity_mps"].as_f64().unwrap();
    assert!(((-v - v_ref) / v_ref).abs() < 5e-3, "v_t {v} vs {v_ref}");
    assert!(j["force_balance_error"].as_f64().unwrap() < 5e-3, "{j}");
    assert_eq!(j["reached_terminal"], true);
}

/// Shell canopy (the report's springs + hinges and drag law, 4 corner loads): at steady
/// descent the total vertical drag carries the total weight. 1 % covers the final window's
/// residual oscillation.
#[test]
fn shell_canopy_drag_balances_weight_without_spin_or_drift() {
    let (_, b, j) = complete_run(
        "report-shell-4-sites.toml",
        &[
            "shell.membrane=springs",
            "shell.bending=hinge",
            "canopy.edge_length_m=0.5",
            "time.dt_s=2e-3",
            "time.duration_s=5",
            "output.frame_interval_s=1",
        ],
    );
    assert!(j["force_balance_error"].as_f64().unwrap() < 1e-2, "{j}");
    let v = j["terminal_velocity_mps"].as_f64().unwrap();
    assert!(v < -1.0, "{j}");
    // The mesh and the load are mirror-symmetric about x = 0 and y = 0: no horizontal
    // drift and no spin about z beyond round-off (1e-6 of the descent speed).
    for vh in j["horizontal_velocity_mps"].as_array().unwrap() {
        assert!(vh.as_f64().unwrap().abs() < 1e-6 * v.abs(), "{j}");
    }
    let (q, vel) = (&b.state.q, &b.state.v);
    let (mut lz, mut inertia) = (0.0, 0.0);
    for &i in &b.canopy_nodes {
        let m = b.model.node_mass(i);
        let (x, y) = (q[3 * i], q[3 * i + 1]);
        lz += m * (x * vel[3 * i + 1] - y * vel[3 * i]);
        inertia += m * (x * x + y * y);
    }
    let omega_z = lz / inertia;
    let radius = (inertia
        / b.canopy_nodes
            .iter()
            .map(|&i| b.model.node_mass(i))
            .sum::<f64>())
    .sqrt();
    assert!(
        (omega_z * radius).abs() < 1e-6 * v.abs(),
        "spin ω_z = {omega_z} rad/s"
    );
}

/// Every bundled scenario passes the builder, and a short run writes every output file with
/// the documented fields.
#[test]
fn bundled_scenarios_run_briefly_and_write_every_output() {
    let files = [
        "report-rod-20n.toml",
        "report-rod-200n.toml",
        "report-rod-2000n.toml",
        "report-shell-4-sites.toml",
        "report-shell-6-sites.toml",
        "round-parachute.toml",
        "dismech-hex-n6.toml",
    ];
    for f in files {
        let probe = scenario(f, &[]);
        let dt = probe.time.dt_s;
        let duration = (20.0 * dt).min(0.5);
        let d = format!("time.duration_s={duration}");
        let fi = format!("output.frame_interval_s={}", 5.0 * dt);
        let sn = format!("output.snapshots_s=[{}]", 10.0 * dt);
        let s = scenario(f, &[&d, &fi, &sn]);
        let dir = tempfile::tempdir().unwrap();
        let (_, r) = run(&s, dir.path());
        assert!(r.complete, "{f}: {:?}", r.stop_reason);
        for out in [
            "summary.json",
            "timeseries.csv",
            "canopy.pvd",
            "velocity.png",
            "height.png",
            "shape.png",
        ] {
            assert!(dir.path().join(out).is_file(), "{f}: no {out}");
        }
        let snap = chute::output::plots::snapshot_file_name(10.0 * dt);
        assert!(dir.path().join(&snap).is_file(), "{f}: no {snap}");
        let frames = std::fs::read_dir(dir.path().join("frames"))
            .unwrap()
            .count();
        assert!(frames >= 4, "{f}: {frames} frames");
        let j = json(dir.path());
        for key in crate::common::SUMMARY_FIELDS {
            assert!(j.get(key).is_some(), "{f}: summary lacks {key}");
        }
        let mut rd = csv::Reader::from_path(dir.path().join("timeseries.csv")).unwrap();
        let h = rd.headers().unwrap().clone();
        for col in [
            "t_s",
            "z_m",
            "vz_mps",
            "vx_mps",
            "vy_mps",
            "z_payload_m",
            "vz_payload_mps",
            "extended_height_m",
            "drag_z_n",
            "newton_iterations",
        ] {
            assert!(h.iter().any(|c| c == col), "{f}: csv lacks {col}");
        }
        let rows = rd.records().count();
        assert!(rows >= 21, "{f}: {rows} rows");
    }
}

//! `chute steady`: the steady descent agrees with the long flight in a fraction of its
//! time, its modes are written and tabled, and the report's lateral instability shows as a
//! growing mode.

use crate::common::*;

/// The report's rod canopy: the equilibrium after a 2 s transient has the 10 s flight's
/// terminal velocity to 0.1 % (the acceptance check of `chute steady`).
#[test]
fn the_rod_canopy_steady_descent_is_the_long_flights() {
    let tmp = tempfile::tempdir().unwrap();
    let rod = rod_file();
    chute_ok(tmp.path(), &["run", &rod, "--out", "flight", "-q"]);
    let flight = read_json(tmp.path().join("flight/summary.json"));
    let vt = flight["terminal_velocity_mps"].as_f64().unwrap();
    let o = chute_ok(
        tmp.path(),
        &["steady", &rod, "--set", "time.duration_s=2", "--out", "st"],
    );
    let s = read_json(tmp.path().join("st/stability.json"));
    let v = s["terminal_velocity_mps"].as_f64().unwrap();
    assert!(
        (v - vt).abs() < 1e-3 * vt.abs(),
        "steady {v} against the flight's {vt}"
    );
    assert!(s["residual_n"].as_f64().unwrap() < 1e-3);
    let modes = s["modes"].as_array().unwrap();
    assert!(!modes.is_empty());
    for m in modes {
        assert!(m["backward_error"].as_f64().unwrap() <= 1e-8, "{m}");
        let sum: f64 = ["lateral", "vertical", "tilt", "spin", "deformation"]
            .iter()
            .map(|k| m["shares"][k].as_f64().unwrap())
            .sum();
        assert!((sum - 1.0).abs() < 1e-9, "shares {sum}");
    }
    // No mode of the rod canopy grows faster than round-off.
    assert!(
        modes[0]["growth_rate_per_s"].as_f64().unwrap() < 1e-6,
        "{}",
        modes[0]
    );
    let table = stdout(&o);
    assert_contains(
        &table,
        &[
            "steady descent of `report-rod-200n`",
            "growth (1/s)",
            "neutral",
        ],
    );
}

/// The 4-site canopy under the pressure drag (the lateral-instability flight of
/// tests/physics/lateral.rs) has a growing sideways mode, at the rate the flights measure
/// (1.2–2.2 /s on its meshes).
#[test]
fn the_lateral_instability_is_a_growing_mode() {
    let tmp = tempfile::tempdir().unwrap();
    let sets = [
        "fluid.shell_drag=pressure",
        "time.dt_s=1e-2",
        "shell.membrane=springs",
        "shell.bending=hinge",
        "canopy.edge_length_m=0.5",
        "time.duration_s=4",
        "canopy.imperfection_m=2e-4",
    ];
    let mut args = vec!["steady", "--json"];
    let file = bundled("report-shell-4-sites.toml");
    args.insert(1, &file);
    for s in &sets {
        args.extend(["--set", s]);
    }
    let o = chute_ok(tmp.path(), &args);
    let s: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    let top = &s["modes"][0];
    let rate = top["growth_rate_per_s"].as_f64().unwrap();
    assert!((1.2..2.2).contains(&rate), "{top}");
    assert_eq!(top["frequency_hz"].as_f64().unwrap(), 0.0);
    let d = top["description"].as_str().unwrap();
    assert!(d.starts_with("grows: sideways drift"), "{d}");
}

/// `--out` never mixes results: a run directory is refused before anything is computed.
#[test]
fn a_run_directory_is_not_a_steady_output() {
    let tmp = tempfile::tempdir().unwrap();
    let rod = rod_file();
    chute_ok(
        tmp.path(),
        &[
            "run",
            &rod,
            "--out",
            "r",
            "-q",
            "--set",
            "time.duration_s=0.05",
        ],
    );
    let o = chute(tmp.path(), &["steady", &rod, "--out", "r"]);
    assert_refused(&o, &["not a `chute steady` directory"]);
    assert!(!tmp.path().join("r/stability.json").exists());
}

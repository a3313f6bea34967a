//! Recovery-system inputs through the binary: `[atmosphere]` and the permeability keys of
//! `[material]` (bad input exits 2 naming the key), `chute check`'s lines on the air and the
//! fall to the ground, the ignored-key warning with `isa1976`, and a run that lands (exit 0).

use crate::common::*;

fn round() -> String {
    repo()
        .join("scenarios/round-parachute.toml")
        .display()
        .to_string()
}

/// `chute check FILE --set …` in `dir`.
fn check(dir: &std::path::Path, file: &str, set: &[&str]) -> std::process::Output {
    let mut args = vec!["check", file];
    for s in set {
        args.extend(["--set", s]);
    }
    chute(dir, &args)
}

#[test]
fn bad_atmosphere_and_fabric_inputs_exit_2_naming_the_key() {
    let dir = tempfile::tempdir().unwrap();
    let isa = "atmosphere.model=\"isa1976\"";
    let cases: &[(&str, &[&str], &[&str])] = &[
        (
            &round(),
            &[isa, "atmosphere.altitude_m=90000"],
            &["atmosphere.altitude_m", "86 km"],
        ),
        (
            &round(),
            &[isa, "atmosphere.altitude_m=-5"],
            &["atmosphere.altitude_m"],
        ),
        (
            &round(),
            &[
                "atmosphere.altitude_m=100",
                "atmosphere.ground_altitude_m=200",
            ],
            &["atmosphere.ground_altitude_m", "below the start"],
        ),
        // Between the canopy (at 100 m) and the payload hanging ~3 m below it.
        (
            &round(),
            &[
                "atmosphere.altitude_m=100",
                "atmosphere.ground_altitude_m=98",
            ],
            &["atmosphere.ground_altitude_m", "the payload"],
        ),
        (
            &round(),
            &["material.permeability_m2=0"],
            &["material.permeability_m2", "positive"],
        ),
        (
            &round(),
            &["material.permeability_m2=-1e-10"],
            &["material.permeability_m2"],
        ),
        (
            &round(),
            &["material.air_permeability_cfm=0"],
            &["material.air_permeability_cfm"],
        ),
        (
            &round(),
            &[
                "material.permeability_m2=1e-10",
                "material.air_permeability_cfm=5",
            ],
            &["material.air_permeability_cfm", "once"],
        ),
        (
            &round(),
            &[
                "material.permeability_m2=1e-10",
                "material.forchheimer_coefficient=-0.1",
            ],
            &["material.forchheimer_coefficient"],
        ),
        (
            &round(),
            &["material.forchheimer_coefficient=0.5"],
            &["material.forchheimer_coefficient", "permeable"],
        ),
        (
            &rod_file(),
            &["material.permeability_m2=1e-10"],
            &["material.permeability_m2", "shell"],
        ),
    ];
    for (file, set, want) in cases {
        let o = check(dir.path(), file, set);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{set:?}: {err}");
        assert!(!err.contains("panicked"), "{err}");
        for w in *want {
            assert!(err.contains(w), "{set:?}: want `{w}` in {err}");
        }
    }
}

/// The air at the start and at the ground (the ISA 1976 table's values, 4 figures) and
/// the fall time at the flat-canopy speed; one warning for both ignored `[fluid]` keys.
#[test]
fn check_prints_the_air_and_the_fall_to_the_ground() {
    let dir = tempfile::tempdir().unwrap();
    let o = check(
        dir.path(),
        &round(),
        &[
            "atmosphere.model=\"isa1976\"",
            "atmosphere.altitude_m=11000",
            "atmosphere.ground_altitude_m=5000",
        ],
    );
    assert_exit(&o, 0);
    let out = stdout(&o);
    for want in [
        "air at the start (11000 m)",
        "T = 216.8 K",
        "ρ = 0.3648 kg/m³",
        "air at the ground (5000 m)",
        "T = 255.7 K",
        "ρ = 0.7364 kg/m³",
        "time to fall to the ground at the flat-canopy speed",
    ] {
        assert!(out.contains(want), "want `{want}` in {out}");
    }
    let warnings: Vec<&str> = out.lines().filter(|l| l.contains("warning")).collect();
    assert_eq!(warnings.len(), 1, "{out}");
    assert!(
        warnings[0].contains("fluid.density_kg_m3") && warnings[0].contains("fluid.viscosity_pa_s"),
        "{out}"
    );
    // The constant model sets nothing aside: no warning.
    let o = check(dir.path(), &round(), &["atmosphere.altitude_m=100"]);
    assert!(!stdout(&o).contains("warning"), "{}", stdout(&o));
}

/// A rod canopy without a payload lands on its lowest node: complete, exit 0, the summary
/// says where and when.
#[test]
fn a_run_that_reaches_the_ground_is_complete() {
    let dir = tempfile::tempdir().unwrap();
    let f = rod_file();
    let o = chute(
        dir.path(),
        &[
            "run",
            &f,
            "--out",
            "out",
            "-q",
            "--no-viewer",
            "--json",
            "--set",
            "canopy.nodes=21",
            "--set",
            "time.dt_s=2e-3",
            "--set",
            "output.snapshots_s=[]",
            "--set",
            "atmosphere.altitude_m=10",
            "--set",
            "atmosphere.ground_altitude_m=5",
        ],
    );
    assert_exit(&o, 0);
    let j: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(j["complete"], true, "{j}");
    assert_eq!(j["stop_reason"], "ground", "{j}");
    let t = j["flight_time_s"].as_f64().unwrap();
    let sim = j["simulated_time_s"].as_f64().unwrap();
    assert!(t <= sim && t > sim - 2e-3 - 1e-12, "{t} vs {sim}");
    assert!(!j["warnings"].to_string().contains("incomplete"), "{j}");
}

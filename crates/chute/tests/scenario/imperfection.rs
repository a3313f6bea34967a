//! `canopy.imperfection_m`: the initial out-of-plane perturbation of a shell canopy.

use chute::build::{build, imperfection::mode};
use chute::scenario::Scenario;

const SHELL: &str = "[model]\nkind = \"shell\"\n[canopy]\nspan_m = 6.0\nwidth_m = 3.0\n\
                     edge_length_m = 0.5\n[load]\nsites = \"corners\"\n";

fn scenario(text: &str, set: &[&str]) -> Result<Scenario, String> {
    let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
    Scenario::from_str_with_name(text, "s.toml", &set).map_err(|e| e.to_string())
}

/// Each canopy node starts at z = a φ(ξ, η) with ξ, η its bounding-box coordinates; x, y,
/// the rest shape and the masses are those of the flat canopy.
#[test]
fn nodes_start_displaced_by_the_documented_mode() {
    let a = 0.05;
    let flat = build(&scenario(SHELL, &[]).unwrap()).unwrap();
    let bent = build(&scenario(SHELL, &["canopy.imperfection_m=0.05"]).unwrap()).unwrap();
    let (q0, q1) = (&flat.state.q, &bent.state.q);
    let mut worst: f64 = 0.0;
    for &i in &flat.canopy_nodes {
        assert_eq!(q0[3 * i + 2], 0.0);
        assert_eq!((q0[3 * i], q0[3 * i + 1]), (q1[3 * i], q1[3 * i + 1]));
        let (xi, eta) = (q0[3 * i] / 3.0, q0[3 * i + 1] / 1.5);
        assert!((q1[3 * i + 2] - a * mode(xi, eta)).abs() < 1e-15);
        worst = worst.max(q1[3 * i + 2].abs());
    }
    // The corners (−x, +y) and (+x, −y) are nodes and carry the largest displacement, −a.
    assert!((worst - a).abs() < 1e-15, "largest |z| = {worst}");
    for i in 0..flat.model.layout.n_nodes {
        assert_eq!(flat.model.node_mass(i), bent.model.node_mass(i));
    }
    assert_eq!(flat.state.v, bent.state.v);
}

/// The default adds nothing: same state, and no key in the resolved scenario.
#[test]
fn zero_amplitude_is_the_flat_start() {
    let s = scenario(SHELL, &[]).unwrap();
    assert_eq!(s.canopy.imperfection_m, 0.0);
    assert!(!s.to_toml().contains("imperfection"));
    let z = scenario(SHELL, &["canopy.imperfection_m=0"]).unwrap();
    assert_eq!(s, z);
    let s = scenario(SHELL, &["canopy.imperfection_m=-0.01"]).unwrap();
    assert!(s.to_toml().contains("imperfection_m = -0.01"));
}

#[test]
fn bad_amplitudes_name_the_key() {
    let rod = "[model]\nkind = \"rod\"\n";
    for (text, set, why) in [
        (rod, "canopy.imperfection_m=0.01", "rod starts straight"),
        (SHELL, "canopy.imperfection_m=0.2", "at most 5 %"),
        (SHELL, "canopy.imperfection_m=nan", "finite"),
    ] {
        let e = scenario(text, &[set]).unwrap_err();
        assert!(
            e.contains("canopy.imperfection_m") && e.contains(why),
            "{set}: {e}"
        );
    }
}

//! The limits on what the keys imply together (docs/scenarios.md §Derived limits): a value
//! each key accepts on its own but that makes a mass, the weight, a stiffness, the drag, the
//! terminal speed, its Mach number or the model's size absurd is refused when the scenario is
//! loaded (so by `chute check`, before any model is built), naming the key that made it so.

use chute::scenario::{Scenario, ScenarioError};

use crate::common::{assert_contains, repo};

fn load(file: &str, set: &[&str]) -> Result<Scenario, ScenarioError> {
    let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
    Scenario::load(&repo().join("scenarios").join(file), &set)
}

/// `--set` of `file` is refused naming `key` and saying `why`.
fn refused(file: &str, set: &str, key: &str, why: &str) {
    let e = load(file, &[set]).expect_err(set);
    assert_eq!(e.key(), Some(key), "{set}: {e}");
    let msg = e.to_string();
    assert!(msg.contains(why), "{set}: {msg}");
}

#[test]
fn absurd_magnitudes_are_refused_naming_the_key() {
    let rod = "report-rod-200n.toml";
    refused(
        rod,
        "load.weight_n=1e308",
        "load.weight_n",
        "makes the total weight 1.000e308 N",
    );
    refused(
        rod,
        "fluid.gravity_mps2=1e300",
        "fluid.gravity_mps2",
        "makes the total weight",
    );
    // The canopy's own mass, not a mesh node's, and blamed on the key, not on the mesh.
    refused(
        rod,
        "canopy.span_m=1e308",
        "canopy.span_m",
        "makes the canopy mass inf kg",
    );
    refused(
        rod,
        "material.density_kg_m3=1e308",
        "material.density_kg_m3",
        "canopy mass",
    );
    refused(
        rod,
        "material.youngs_modulus_pa=1e308",
        "material.youngs_modulus_pa",
        "axial stiffness",
    );
    refused(
        rod,
        "fluid.density_kg_m3=1e300",
        "fluid.density_kg_m3",
        "drag at 1 m/s",
    );
    refused(
        rod,
        "fluid.wind_mps=[1e308,0,0]",
        "fluid.wind_mps",
        "not a finite number",
    );
    let round = "round-parachute.toml";
    refused(
        round,
        "lines.density_kg_m3=1e308",
        "lines.density_kg_m3",
        "suspension lines' mass",
    );
}

#[test]
fn supersonic_air_speeds_are_refused_and_fast_ones_warned() {
    let rod = "report-rod-200n.toml";
    // About 720 m/s through the air at the end, 400 m/s at the start.
    refused(rod, "load.weight_n=1e7", "load.weight_n", "Mach 2.1");
    refused(
        rod,
        "fluid.wind_mps=[400,0,0]",
        "fluid.wind_mps",
        "Mach 1.175",
    );
    // Through the air, not over the ground: at rest in a 200 m/s wind it is Mach 0.59.
    let s = load(rod, &["fluid.wind_mps=[200,0,0]"]).unwrap();
    let w = chute::scenario::plausibility::warnings(&s);
    assert!(
        w.iter()
            .any(|w| w.contains("200.0 m/s wind") && w.contains("Mach 0.5877")),
        "{w:?}"
    );
    // A slow canopy in still air: no warning.
    let s = load(rod, &[]).unwrap();
    assert!(!chute::scenario::plausibility::warnings(&s)
        .iter()
        .any(|w| w.contains("Mach")));
}

/// A canopy large enough to take long, but within the limit, is warned of naming what makes
/// it so; no bundled scenario is.
#[test]
fn a_large_circle_canopy_is_warned_of_naming_its_cause() {
    let warned = |set: &str| {
        let s = load("round-parachute.toml", &[set]).unwrap();
        chute::scenario::plausibility::warnings(&s)
            .into_iter()
            .find(|w| w.contains("triangles"))
    };
    let w = warned("load.rim_site_count=600").expect("warned");
    assert_contains(&w, &["100 rings", "load.rim_site_count = 600"]);
    let w = warned("canopy.edge_length_m=0.01").expect("warned");
    assert!(w.contains("canopy.edge_length_m = 0.01 m makes it"), "{w}");
    assert_eq!(warned("load.rim_site_count=12"), None);
}

#[test]
fn rim_sites_that_refine_the_circle_past_the_limit_are_refused_before_building() {
    // 10 000 sites need 5000 rings (1.5e8 triangles); refused by the loader itself, so no
    // mesh is generated.
    refused(
        "round-parachute.toml",
        "load.rim_site_count=10000",
        "load.rim_site_count",
        "refines the circle to 5000 rings, 1.500e8 triangles",
    );
    // A count the rim already holds is fine.
    load("round-parachute.toml", &["load.rim_site_count=24"]).unwrap();
    // Past the key's own range, the key is named for that, not a quantity it derives (the
    // line nodes, the terminal speed of the thin canopy).
    for n in ["1000000", "100000000", "4000000000"] {
        let set = format!("load.rim_site_count={n}");
        refused(
            "round-parachute.toml",
            &set,
            "load.rim_site_count",
            "between 3 and 10000",
        );
    }
}

#[test]
fn every_bundled_scenario_is_within_the_limits() {
    for e in std::fs::read_dir(repo().join("scenarios")).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_some_and(|x| x == "toml") {
            Scenario::load(&p, &[]).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
        }
    }
}

#[test]
fn a_site_off_an_imported_mesh_is_refused_naming_it() {
    let sets = ["load.mode=force", "load.sites=[[0, 0], [5, 5]]"];
    let s = load("dismech-hex-n6.toml", &sets).unwrap();
    let e = chute::build::build(&s).err().expect("refused");
    let msg = e.to_string();
    assert!(
        msg.starts_with("load.sites: site 2 [5, 5] m is not on the imported canopy"),
        "{msg}"
    );
    // On the canopy (inside a triangle's top view), as before.
    let s = load(
        "dismech-hex-n6.toml",
        &["load.mode=force", "load.sites=[[0, 0], [0.5, 0.2]]"],
    )
    .unwrap();
    chute::build::build(&s).unwrap();
}

/// A mass far too small for the stiffness over one step (a density of 1e-10 kg/m³: E dt²/(ρ l²)
/// ≈ 5e16) makes the Newton matrix singular in f64: refused when loaded, naming the density,
/// instead of a non-finite update at t = 0. The lines are judged the same way.
#[test]
fn a_step_too_stiff_for_its_inertia_is_refused() {
    let rod = "report-rod-200n.toml";
    for d in ["1e-10", "1e-20", "1e-300"] {
        refused(
            rod,
            &format!("material.density_kg_m3={d}"),
            "material.density_kg_m3",
            "too ill-conditioned",
        );
    }
    refused(
        "round-parachute.toml",
        "lines.density_kg_m3=1e-12",
        "lines.density_kg_m3",
        "line segment's stiffness-to-inertia ratio",
    );
    // A length the user shortened is blamed, not the modulus written in the file.
    refused(
        "round-fabric.toml",
        "lines.length_m=1e-6",
        "lines.length_m",
        "line segment's stiffness-to-inertia ratio",
    );
}

/// A load that would more than double the length of the element carrying it (a fabric of
/// 1e-12 m, a line of 1e-15 m radius, a rod strip of no thickness) is refused naming the key,
/// where the first step would fail; the bundled scenarios stay below 1 % of that.
#[test]
fn a_load_no_fabric_could_carry_is_refused() {
    for (file, set, key, element) in [
        (
            "report-shell-4-sites.toml",
            "canopy.thickness_m=1e-12",
            "canopy.thickness_m",
            "F/(E h l) of the canopy element",
        ),
        (
            "drop-1000m.toml",
            "lines.radius_m=1e-15",
            "lines.radius_m",
            "F/(E π r²) of a suspension line",
        ),
        (
            "report-rod-2000n.toml",
            "canopy.thickness_m=1e-9",
            "canopy.thickness_m",
            "F/(E w h) of the strip",
        ),
        (
            "round-parachute.toml",
            "material.youngs_modulus_pa=1e3",
            "material.youngs_modulus_pa",
            "would more than double the element's length",
        ),
    ] {
        refused(file, set, key, element);
    }
    // Just inside: a hundredth of the strain that is refused still loads.
    load("report-shell-4-sites.toml", &["canopy.thickness_m=1e-7"]).unwrap();
}

/// A rule relating two keys blames the one the user changed with `--set`, not the one the
/// file wrote: a canopy shrunk below ten thicknesses is refused naming its size.
#[test]
fn a_rule_between_two_keys_blames_the_one_changed() {
    let rod = "report-rod-200n.toml";
    refused(rod, "canopy.span_m=1e-6", "canopy.span_m", "thickness");
    refused(rod, "canopy.width_m=1e-9", "canopy.width_m", "thickness");
    refused(
        rod,
        "canopy.thickness_m=1",
        "canopy.thickness_m",
        "thickness",
    );
    let round = "round-fabric.toml";
    refused(
        round,
        "canopy.radius_m=1e-6",
        "canopy.radius_m",
        "thickness",
    );
    refused(round, "canopy.radius_m=0.1", "canopy.radius_m", "two edges");
    refused(
        round,
        "canopy.edge_length_m=2.9",
        "canopy.edge_length_m",
        "two edges",
    );
}

/// An imported mesh's area is not known when the scenario is loaded, so its masses and weight
/// are not; the factors that would make them absurd still are: the gravity, the mass factor
/// of the payload node, the canopy's mass per area.
#[test]
fn an_imported_mesh_scenario_is_held_to_the_factors_it_knows() {
    let hex = "dismech-hex-n6.toml";
    refused(
        hex,
        "fluid.gravity_mps2=1e300",
        "fluid.gravity_mps2",
        "gravitational acceleration",
    );
    refused(
        hex,
        "load.mass_scale=1e200",
        "load.mass_scale",
        "mass factor",
    );
    // A factor so small that the node's mass cancels to zero (1 + (s − 1) in f64) is the
    // key's fault, not the mesh file's.
    for tiny in ["1e-30", "1e-6"] {
        refused(
            hex,
            &format!("load.mass_scale={tiny}"),
            "load.mass_scale",
            "too ill-conditioned",
        );
    }
    assert!(load(hex, &["load.mass_scale=1e-4"]).is_ok());
    // The mesh file is read for its lumped masses: a payload node so heavy that the flat
    // canopy would fall faster than sound is refused, one near it warned about (the same
    // terminal speed the builder prints: 1.750 m/s × √(s/100) here).
    refused(hex, "load.mass_scale=1e10", "load.mass_scale", "Mach 9.245");
    let s = load(hex, &["load.mass_scale=1e8"]).unwrap();
    let w = chute::scenario::plausibility::warnings(&s);
    assert!(w.iter().any(|w| w.contains("Mach 0.9")), "{w:?}");
    refused(
        hex,
        "material.density_kg_m3=1e300",
        "material.density_kg_m3",
        "mass per area",
    );
}

//! Every bundled scenario parses and validates, and the resolved TOML round-trips.

use std::path::{Path, PathBuf};

use chute::scenario::{CanopyShape, LoadMode, ModelKind, Scenario, ScenarioError, SiteSet, Sites};

use crate::common::repo;

fn bundled() -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(repo().join("scenarios"))
        .expect("scenarios/ exists")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    v.sort();
    v
}

/// The DisMech mesh is added by another branch; until it is merged, the one acceptable
/// failure of that scenario is the missing-mesh error naming the expected path.
fn load_allowing_pending_mesh(p: &Path) -> Option<Scenario> {
    match Scenario::load(p, &[]) {
        Ok(s) => Some(s),
        Err(ScenarioError::MeshMissing { path, .. }) if p.ends_with("dismech-hex-n6.toml") => {
            assert!(
                path.ends_with("crates/chute/data/meshes/hexparachute_n6_python.txt"),
                "{path:?}"
            );
            eprintln!(
                "note: {} pending its mesh file {}",
                p.display(),
                path.display()
            );
            None
        }
        Err(e) => panic!("{}: {e}", p.display()),
    }
}

#[test]
fn all_bundled_scenarios_validate() {
    let files = bundled();
    assert!(files.len() >= 7, "{files:?}");
    for f in &files {
        if let Some(s) = load_allowing_pending_mesh(f) {
            assert_eq!(
                s.name,
                f.file_stem().unwrap().to_string_lossy(),
                "name matches file"
            );
        }
    }
}

#[test]
fn report_scenarios_have_report_values() {
    for (file, w) in [
        ("report-rod-20n", 20.0),
        ("report-rod-200n", 200.0),
        ("report-rod-2000n", 2000.0),
    ] {
        let s = Scenario::load(&repo().join(format!("scenarios/{file}.toml")), &[]).unwrap();
        assert_eq!(s.model.kind, ModelKind::Rod);
        assert_eq!(
            (s.canopy.span_m, s.canopy.width_m, s.canopy.thickness_m),
            (6.0, 3.0, 0.002)
        );
        assert_eq!(s.canopy.nodes, 61);
        assert_eq!(s.material.youngs_modulus_pa, 55e9);
        assert_eq!(s.load.weight_n, w);
        assert_eq!(s.load.sites, Sites::Named(SiteSet::Ends));
        assert_eq!(s.fluid.drag_coefficient, 1.75);
        assert_eq!((s.time.dt_s, s.time.duration_s), (1e-3, 10.0));
    }
    for (file, set) in [
        ("report-shell-4-sites", SiteSet::Corners),
        ("report-shell-6-sites", SiteSet::CornersAndMidspan),
    ] {
        let s = Scenario::load(&repo().join(format!("scenarios/{file}.toml")), &[]).unwrap();
        assert_eq!(s.model.kind, ModelKind::Shell);
        assert_eq!(s.load.weight_n, 200.0);
        assert_eq!(s.load.sites, Sites::Named(set));
        assert_eq!(s.canopy.edge_length_m, 0.125);
        assert_eq!(s.fluid.tangential_drag_coefficient, 0.5);
        assert_eq!(
            s.site_count(),
            Some(if set == SiteSet::Corners { 4 } else { 6 })
        );
    }
    let s = Scenario::load(&repo().join("scenarios/round-parachute.toml"), &[]).unwrap();
    assert_eq!(
        (s.canopy.shape, s.load.mode),
        (CanopyShape::Circle, LoadMode::Payload)
    );
    assert!((8..=12).contains(&s.site_count().unwrap()));
}

#[test]
fn resolved_toml_round_trips_for_every_bundled_scenario() {
    let dir = tempfile::tempdir().unwrap();
    for f in bundled() {
        // Copy next to a stand-in mesh so that the DisMech case validates here too, and so that
        // the relative mesh path is resolved against the copy's directory.
        let sub = dir.path().join("scenarios");
        std::fs::create_dir_all(&sub).unwrap();
        let copy = sub.join(f.file_name().unwrap());
        std::fs::copy(&f, &copy).unwrap();
        let mesh = dir
            .path()
            .join("crates/chute/data/meshes/hexparachute_n6_python.txt");
        std::fs::create_dir_all(mesh.parent().unwrap()).unwrap();
        std::fs::write(&mesh, "*Nodes\n").unwrap();
        let s = Scenario::load(&copy, &[]).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
        if s.canopy.shape == CanopyShape::Mesh {
            assert_eq!(
                s.canopy.mesh_file.as_deref(),
                Some(mesh.as_path()),
                "resolved against the file"
            );
        }
        let text = s.to_toml();
        let back = Scenario::from_str_with_name(&text, "elsewhere/resolved.toml", &[])
            .unwrap_or_else(|e| panic!("{}: {e}\n{text}", f.display()));
        assert_eq!(back, s, "{}", f.display());
    }
}

#[test]
fn round_trip_with_every_optional_key_set() {
    let text = r#"
name = "all-keys"
[model]
kind = "shell"
[load]
sites = [[0.5, 0.25], [-1.0, 1.0]]
[fluid]
drag = "linear"
linear_drag_coefficient_n_s_m = 12.5
wind_mps = [1.5, -0.5, 0.1]
[time]
newton_tolerance_n = 1e-7
[output]
snapshots_s = []
"#;
    let s = Scenario::from_str_with_name(text, "all.toml", &[]).unwrap();
    assert_eq!(s.fluid.linear_drag_coefficient_n_s_m, Some(12.5));
    assert_eq!(s.load.sites, Sites::Points(vec![[0.5, 0.25], [-1.0, 1.0]]));
    let back = Scenario::from_str_with_name(&s.to_toml(), "all.toml", &[]).unwrap();
    assert_eq!(back, s);
}

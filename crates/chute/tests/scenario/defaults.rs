//! Defaults: the report's values, and the context-dependent ones (name, sites, snapshots).

use crate::common::assert_contains;
use chute::scenario::schema;
use chute::scenario::{CanopyShape, DragLaw, LoadMode, Scenario, ShellDrag, SiteSet, Sites};

fn parse(text: &str) -> Scenario {
    Scenario::from_str_with_name(text, "dir/my-case.toml", &[]).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn minimal_rod_scenario_gets_the_report_defaults() {
    let s = parse("[model]\nkind = \"rod\"\n");
    assert_eq!(s.name, "my-case", "name defaults to the file stem");
    assert_eq!(s.canopy.shape, CanopyShape::Rectangle);
    assert_eq!(
        (s.canopy.span_m, s.canopy.width_m, s.canopy.thickness_m),
        (6.0, 3.0, 0.002)
    );
    assert_eq!(s.canopy.nodes, 61);
    assert_eq!(
        (s.material.youngs_modulus_pa, s.material.density_kg_m3),
        (55e9, 1440.0)
    );
    assert_eq!(s.load.mode, LoadMode::Force);
    assert_eq!(s.load.sites, Sites::Named(SiteSet::Ends));
    assert_eq!(
        (
            s.fluid.drag_coefficient,
            s.fluid.tangential_drag_coefficient
        ),
        (1.75, 0.5)
    );
    assert_eq!(
        (s.fluid.drag, s.fluid.shell_drag),
        (DragLaw::Quadratic, ShellDrag::Report)
    );
    assert_eq!((s.fluid.density_kg_m3, s.fluid.gravity_mps2), (1.225, 9.81));
    assert_eq!((s.time.dt_s, s.time.duration_s), (1e-3, 10.0));
    assert_eq!(s.output.snapshots_s, vec![3.0, 6.0, 9.0]);
}

#[test]
fn sites_default_by_model_and_shape() {
    let cases = [
        ("shell", "rectangle", SiteSet::Corners),
        ("shell", "hexagon", SiteSet::Corners),
        ("shell", "circle", SiteSet::Rim),
    ];
    for (kind, shape, want) in cases {
        let s = parse(&format!(
            "[model]\nkind = \"{kind}\"\n[canopy]\nshape = \"{shape}\"\n"
        ));
        assert_eq!(s.load.sites, Sites::Named(want), "{kind} {shape}");
    }
}

#[test]
fn snapshots_follow_the_duration_and_explicit_ones_are_kept() {
    let s = parse("[model]\nkind = \"rod\"\n[time]\nduration_s = 2\n");
    assert_eq!(s.output.snapshots_s, vec![0.6, 1.2, 1.8]);
    let s = parse("[model]\nkind = \"rod\"\n[output]\nsnapshots_s = [1, 2.5]\n");
    assert_eq!(s.output.snapshots_s, vec![1.0, 2.5]);
}

/// Absent: the default times (filled once, by the loader); `[]`: none, also in the run
/// loop's configuration and after the resolved scenario is read back.
#[test]
fn empty_snapshot_list_means_no_snapshots() {
    let s = parse("[model]\nkind = \"rod\"\n");
    assert_eq!(
        chute::app::run_config(&s, false).outputs.snapshots_s,
        vec![3.0, 6.0, 9.0]
    );
    let s = parse("[model]\nkind = \"rod\"\n[output]\nsnapshots_s = []\n");
    assert!(s.output.snapshots_s.is_empty());
    assert!(chute::app::run_config(&s, false)
        .outputs
        .snapshots_s
        .is_empty());
    let again = parse(&s.to_toml());
    assert!(again.output.snapshots_s.is_empty(), "{}", s.to_toml());
    let s = Scenario::from_str_with_name(
        "[model]\nkind = \"rod\"\n",
        "t.toml",
        &["output.snapshots_s=[]".to_string()],
    )
    .unwrap();
    assert!(chute::app::run_config(&s, false)
        .outputs
        .snapshots_s
        .is_empty());
}

#[test]
fn awkward_file_names_give_safe_default_names() {
    let s = Scenario::from_str_with_name("[model]\nkind = \"rod\"\n", "<string>", &[]).unwrap();
    assert_eq!(s.name, "string");
    let s = Scenario::from_str_with_name("[model]\nkind = \"rod\"\n", "a b/c d.toml", &[]).unwrap();
    assert_eq!(s.name, "c_d");
}

/// The key table used for "unknown key" and type checks names exactly the serde fields:
/// a scenario with every optional key set serialises to exactly the schema's keys.
#[test]
fn schema_matches_the_serde_structs() {
    let text = "[model]\nkind = \"shell\"\n[canopy]\nshape = \"mesh\"\nmesh_file = \"m.obj\"\nimperfection_m = 0.01\n\
                [fluid]\nlinear_drag_coefficient_n_s_m = 1.0\nadded_mass = true\n[time]\nnewton_tolerance_n = 1.0\nadaptive = true\n\
                newton_relative_tolerance = 0.1\nnewton_step_tolerance_m = 1e-9\nnewton_strict = true\n\
                newton_rescue_stages = false\nerror_norm = \"max\"\nerror_filter = false\n\
                [lines]\ndrag_coefficient = 1.0\n[shell]\nmembrane = \"fabric\"\nbending = \"midedge\"\n\
                [material]\nwarp_modulus_pa = 1e9\nweft_modulus_pa = 5e8\nshear_modulus_pa = 1e7\n\
                fabric_poisson_ratio = 0.3\nwarp_direction_deg = 10.0\nno_compression = true\n\
                wrinkle_strain = 1e-4\npermeability_m2 = 1e-10\nforchheimer_coefficient = 0.5\n\
                [atmosphere]\naltitude_m = 100.0\nground_altitude_m = 0.0\n";
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("m.obj"), "").unwrap();
    let s =
        Scenario::from_str_with_name(text, &dir.path().join("s.toml").display().to_string(), &[])
            .unwrap();
    // The two permeability forms exclude each other: set the second one directly.
    let mut s = s;
    s.material.air_permeability_cfm = Some(1.0);
    s.canopy.initial_velocity_mps = Some([1.0, 0.0, 0.0]);
    s.canopy.release_point_m = Some([1.0, 2.0]);
    s.canopy.released_with_wind = true;
    // A round canopy's vent and cone (with a circle only).
    s.canopy.vent_radius_m = 0.1;
    s.canopy.profile = Some(chute::scenario::CanopyProfile::Conical);
    s.canopy.cone_angle_deg = Some(20.0);
    // The incidence table (with its law only).
    s.fluid.incidence_alpha_deg = Some(vec![-90.0, 90.0]);
    s.fluid.incidence_cn = Some(vec![0.0, 0.0]);
    s.fluid.inflation_speed = Some(chute::scenario::InflationSpeed::Canopy);
    // The pull and guidance sections (payload mode only): set them directly too.
    s.control.push(chute::scenario::Control {
        hold_s: Some(1.0),
        sensor: Some("alt".into()),
        below_m: Some(1.0),
        ..Default::default()
    });
    s.sensor.push(Default::default());
    s.guidance = Some(Default::default());
    // The wind's keys (each with its own law).
    s.wind = Some(chute::scenario::Wind {
        exponent: Some(0.1),
        roughness_m: Some(0.1),
        file: Some("w.csv".into()),
        ..Default::default()
    });
    // Contact and a packed start (their sections absent by default).
    s.contact = Some(chute::scenario::Contact {
        distance_m: Some(0.01),
        ..Default::default()
    });
    s.opening = Some(chute::scenario::Opening {
        packed_radius_m: Some(0.1),
        mesh_file: Some("folded.obj".into()),
        ..Default::default()
    });
    let table: toml::Table = toml::from_str(&s.to_toml()).unwrap();
    let mut keys = Vec::new();
    for (k, v) in &table {
        match (v.as_table(), v.as_array()) {
            (Some(t), _) => keys.extend(t.keys().map(|kk| format!("{k}.{kk}"))),
            (_, Some(a)) => {
                for (i, e) in a.iter().enumerate() {
                    let t = e.as_table().unwrap();
                    keys.extend(t.keys().map(|kk| format!("{k}[{i}].{kk}")));
                }
            }
            _ => keys.push(k.clone()),
        }
    }
    keys.sort();
    let mut want = schema::all_keys();
    // A generated rectangle's pattern excludes a mesh file (its round trip: shell_laws.rs).
    want.retain(|k| k != "canopy.mesh_pattern");
    want.sort();
    assert_eq!(keys, want);
}

/// `time.adaptive = true` fills the error-control keys (tolerance 1e-5 m, dt_min = dt/1024,
/// dt_max = min(100 dt, frame interval)), the resolved scenario shows them and reads back
/// equal; without it none of them is written, so fixed-step scenarios resolve as before.
#[test]
fn adaptive_defaults_are_filled_and_resolved() {
    let s = parse("[model]\nkind = \"rod\"\n[time]\nadaptive = true\ndt_s = 2e-4\n");
    assert!(s.time.adaptive);
    assert_eq!(s.time.error_tolerance_m, Some(1e-5));
    assert_eq!(s.time.dt_min_s, Some(2e-4 / 1024.0));
    assert_eq!(s.time.dt_max_s, Some(100.0 * 2e-4));
    let a = s.adaptive_settings().unwrap();
    assert_eq!((a.error_tolerance_m, a.dt_max_s), (1e-5, 0.02));
    // Bounded by the frame interval (0.05 s by default).
    let s = parse("[model]\nkind = \"rod\"\n[time]\nadaptive = true\n");
    assert_eq!(s.time.dt_max_s, Some(0.05));
    let s = parse(
        "[model]\nkind = \"rod\"\n[time]\nadaptive = true\nerror_tolerance_m = 1e-4\n\
         dt_min_s = 1e-6\ndt_max_s = 0.01\n",
    );
    assert_eq!(
        (s.time.error_tolerance_m, s.time.dt_min_s, s.time.dt_max_s),
        (Some(1e-4), Some(1e-6), Some(0.01))
    );
    let text = s.to_toml();
    assert_contains(&text, &["adaptive = true", "dt_max_s = 0.01"]);
    assert_eq!(parse(&text), s);
    // Fixed step: no adaptive key in the resolved scenario, and no settings.
    let s = parse("[model]\nkind = \"rod\"\n");
    assert!(s.adaptive_settings().is_none());
    let text = s.to_toml();
    assert!(
        !text.contains("adaptive") && !text.contains("dt_min_s"),
        "{text}"
    );
    let s = parse("[model]\nkind = \"rod\"\n[time]\nadaptive = false\n");
    assert!(!s.time.adaptive && s.time.dt_max_s.is_none());
}

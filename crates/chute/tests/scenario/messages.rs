//! Messages that name the key the user changed and the real reason, with numbers in short
//! form, and the plausibility warnings for values no fabric has.

use chute::scenario::{plausibility, Scenario};

use crate::common::{assert_contains, repo};

/// The error of the report's rod scenario under `set`.
fn rod_error(set: &[&str]) -> String {
    let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
    let f = repo().join("scenarios/report-rod-200n.toml");
    match Scenario::load(&f, &set) {
        Ok(_) => panic!("accepted: {set:?}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn each_corrected_message_names_the_changed_key_and_the_real_reason() {
    let cases: &[(&[&str], &str)] = &[
        (
            &["time.dt_s=1e308"],
            "`time.dt_s` (from `--set time.dt_s=1e308`) = 1e308 is invalid: longer than time.duration_s = 10 s",
        ),
        (
            &["time.dt_s=2", "time.duration_s=1"],
            "`time.dt_s` (from `--set time.dt_s=2`) = 2 is invalid: longer than time.duration_s = 1 s",
        ),
        (
            &["time.duration_s=1e9"],
            "`time.duration_s` (from `--set time.duration_s=1e9`) = 1e9 is invalid: 1e12 steps with time.dt_s = 0.001 s; at most 1e8",
        ),
        (
            &["time.duration_s=0.0001"],
            "`time.duration_s` (from `--set time.duration_s=0.0001`) = 0.0001 is invalid: shorter than one step",
        ),
        (
            &["time.dt_s=0.1"],
            "`time.dt_s` (from `--set time.dt_s=0.1`) = 0.1 is invalid: frames are written at steps, so a step must not be longer than output.frame_interval_s = 0.05 s",
        ),
        (
            &["output.frame_interval_s=0.0001"],
            "`output.frame_interval_s` (from `--set output.frame_interval_s=0.0001`) = 0.0001 is invalid: frames are written at steps, so it must be at least time.dt_s = 0.001 s",
        ),
        (
            &["canopy.nodes=1e9"],
            "`canopy.nodes` (from `--set canopy.nodes=1e9`) = 1e9 is invalid: must be between 3 and 100000",
        ),
        (
            &["canopy.nodes=-3"],
            "`canopy.nodes` (from `--set canopy.nodes=-3`) = -3 is invalid: must be between 3 and 100000",
        ),
        (
            &["canopy.nodes=61.0"],
            "must be an integer (written without a decimal point or exponent), found the number 61.0",
        ),
        (
            &["load.weight_n=1e400"],
            "`load.weight_n` (from `--set load.weight_n=1e400`) = 1e400 is invalid: overflows",
        ),
        (
            &["fluid.wind_mps=[1,2]"],
            "must be an array of three numbers, e.g. [0, 0, 0], found an array of 2 numbers",
        ),
    ];
    for (set, want) in cases {
        let got = rod_error(set);
        assert!(got.contains(want), "{set:?}:\n got  {got}\n want {want}");
        assert!(got.len() < 300, "{set:?}: long message {got}");
    }
}

#[test]
fn a_mesh_file_that_is_a_directory_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let text = format!(
        "name = \"t\"\n[model]\nkind = \"shell\"\n[canopy]\nshape = \"mesh\"\nmesh_file = \"{}\"\n",
        dir.path().display()
    );
    let e = Scenario::from_str_with_name(&text, "t.toml", &[]).unwrap_err();
    let msg = e.to_string();
    assert_contains(
        &msg,
        &["`canopy.mesh_file` (t.toml:6)", "it is a directory"],
    );
    assert!(!msg.contains("does not exist"), "{msg}");
}

#[test]
fn material_values_no_fabric_has_are_warned_about() {
    let f = repo().join("scenarios/report-rod-200n.toml");
    let load = |set: &[&str]| {
        let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
        plausibility::warnings(&Scenario::load(&f, &set).unwrap())
    };
    assert!(load(&[]).is_empty(), "{:?}", load(&[]));
    // 55e9 Pa written in MPa by mistake, and g/cm³ for kg/m³.
    let w = load(&[
        "material.youngs_modulus_pa=55e15",
        "material.density_kg_m3=1.44",
    ]);
    assert_eq!(w.len(), 2, "{w:?}");
    assert!(
        w[0].starts_with("material.youngs_modulus_pa = 5.5e16 Pa is far above"),
        "{w:?}"
    );
    assert!(
        w[1].starts_with("material.density_kg_m3 = 1.44 kg/m³ is far below"),
        "{w:?}"
    );
    // Every bundled scenario is a real fabric.
    for e in std::fs::read_dir(repo().join("scenarios")).unwrap() {
        let p = e.unwrap().path();
        let s = Scenario::load(&p, &[]).unwrap();
        assert!(plausibility::warnings(&s).is_empty(), "{p:?}");
    }
}

/// Two snapshot times that round to the same millisecond would write one file: warned about,
/// naming both times and the file; distinct names are not.
#[test]
fn snapshot_times_sharing_a_file_name_are_warned_about() {
    let f = repo().join("scenarios/report-rod-200n.toml");
    let load = |set: &str| plausibility::warnings(&Scenario::load(&f, &[set.to_string()]).unwrap());
    let w = load("output.snapshots_s=[0.0121, 0.0124, 0.5]");
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].contains("0.0121 s and 0.0124 s") && w[0].contains("snapshot_0.012s.png"),
        "{w:?}"
    );
    assert!(load("output.snapshots_s=[0.012, 0.013]").is_empty());
}

//! Each class of scenario error, through the library: the variant, the key, the origin (file
//! line or `--set`) and a message a user can act on.

use crate::common::assert_contains;
use std::path::Path;

use chute::scenario::{Origin, Scenario, ScenarioError};

const HEAD: &str = "name = \"t\"\n[model]\nkind = \"shell\"\n"; // lines 1–3

fn err_with(text: &str, set: &[&str]) -> ScenarioError {
    let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
    match Scenario::from_str_with_name(text, "t.toml", &set) {
        Ok(_) => panic!("accepted:\n{text}\n{set:?}"),
        Err(e) => e,
    }
}

fn err(body: &str) -> ScenarioError {
    err_with(&format!("{HEAD}{body}"), &[])
}

/// Assert that the error `e` matches a pattern (a variant, its fields, a guard); else show it.
macro_rules! assert_is {
    ($e:expr, $p:pat $(if $g:expr)?) => {
        assert!(matches!($e, $p $(if $g)?), "{:?}", $e)
    };
}

/// The error of `body` (after [`HEAD`]), which must name line `line` of the file.
fn err_at(body: &str, line: usize) -> ScenarioError {
    let e = err(body);
    at_line(&e, line);
    e
}

fn at_line(e: &ScenarioError, line: usize) {
    let msg = e.to_string();
    assert!(
        msg.contains(&format!("t.toml:{line}")),
        "expected t.toml:{line} in: {msg}"
    );
}

/// `e`'s message contains every one of `parts`.
fn says(e: &ScenarioError, parts: &[&str]) {
    let msg = e.to_string();
    for part in parts {
        assert!(msg.contains(part), "no {part:?} in: {msg}");
    }
}

#[test]
fn missing_file_names_the_path() {
    let e = Scenario::load(Path::new("/no/such/dir/scen.toml"), &[]).unwrap_err();
    assert!(matches!(e, ScenarioError::Read { .. }));
    let msg = e.to_string();
    assert_contains(&msg, &["/no/such/dir/scen.toml", "cannot read"]);
}

#[test]
fn syntax_error_has_file_line_and_column() {
    let e = err("[canopy]\nspan_m = = 3\n");
    match &e {
        ScenarioError::Syntax { line, col, .. } => assert_eq!((*line, *col), (5, 10), "{e}"),
        other => panic!("{other:?}"),
    }
    assert!(
        e.to_string().starts_with("t.toml:5:10: TOML syntax error"),
        "{e}"
    );
    let e = err("[canopy\n");
    assert!(matches!(e, ScenarioError::Syntax { line: 4, .. }), "{e}");
}

#[test]
fn unknown_key_suggests_the_closest() {
    let e = err_at("[canopy]\nspan_m = 6\nwidht_m = 3\n", 6);
    assert_is!(&e, ScenarioError::UnknownKey { key, .. } if key == "canopy.widht_m");
    assert!(
        e.to_string().ends_with("did you mean `canopy.width_m`?"),
        "{e}"
    );
    // The right key in the wrong section.
    says(
        &err("[canopy]\ndensity_kg_m3 = 1000\n"),
        &["did you mean `material.density_kg_m3`?"],
    );
    // A misspelt section.
    says(
        &err("[canopee]\nspan_m = 6\n"),
        &["unknown key `canopee`", "[canopy]"],
    );
    // Nothing close: no suggestion.
    let e = err("[canopy]\nzzzzzzzzzzzz = 1\n");
    assert!(
        matches!(
            &e,
            ScenarioError::UnknownKey {
                suggestion: None,
                ..
            }
        ),
        "{e:?}"
    );
    // Reported in reading order: the first of two unknown keys.
    let e = err("[time]\nxx_dt = 1\n[canopy]\naaa = 1\n");
    assert_is!(&e, ScenarioError::UnknownKey { key, .. } if key == "time.xx_dt");
}

#[test]
fn wrong_type_names_key_expected_type_and_line() {
    let e = err_at("[canopy]\nspan_m = \"six\"\n", 5);
    assert_is!(&e, ScenarioError::WrongType { key, expected: "a number", .. } if key == "canopy.span_m");
    says(&e, &["found the string \"six\""]);
    says(
        &err("[canopy]\nnodes = 6.5\n"),
        &["`canopy.nodes`", "an integer"],
    );
    says(&err("[fluid]\nwind_mps = [1, 2]\n"), &["three numbers"]);
    says(
        &err_with("canopy = 3\n[model]\nkind = \"rod\"\n", &[]),
        &["`canopy`", "a table"],
    );
    says(&err("[load]\nsites = [[1, \"a\"]]\n"), &["`load.sites`"]);
}

#[test]
fn non_positive_physical_quantities_say_why() {
    for (body, key, line) in [
        ("[canopy]\nspan_m = -6\n", "canopy.span_m", 5),
        ("[canopy]\nthickness_m = 0\n", "canopy.thickness_m", 5),
        (
            "[material]\nyoungs_modulus_pa = -1e9\n",
            "material.youngs_modulus_pa",
            5,
        ),
        ("[load]\nweight_n = 0\n", "load.weight_n", 5),
        ("[fluid]\ndensity_kg_m3 = -1.2\n", "fluid.density_kg_m3", 5),
        ("[time]\ndt_s = 0.0\n", "time.dt_s", 5),
        ("[lines]\nradius_m = -0.001\n", "lines.radius_m", 5),
    ] {
        let e = err_at(body, line);
        assert!(
            matches!(&e, ScenarioError::Invalid { key: k, .. } if k == key),
            "{body}: {e:?}"
        );
        says(&e, &["must be positive"]);
    }
    says(
        &err("[canopy]\nnodes = -3\n"),
        &["must be between 3 and 100000"],
    );
    says(&err("[material]\npoisson_ratio = 0.7\n"), &["(−1, 0.5]"]);
    says(&err("[canopy]\nthickness_m = 2\n"), &["is it in metres"]);
    says(
        &err("[time]\ndt_s = 20\n"),
        &["longer than time.duration_s"],
    );
    // Snapshots after the end are skipped with a warning (so short test runs of a bundled
    // scenario need no override); negative ones are errors.
    says(
        &err("[output]\nsnapshots_s = [1, -1]\n"),
        &["`output.snapshots_s`", "must not be negative"],
    );
}

#[test]
fn rod_needs_enough_nodes() {
    says(
        &err_with("[model]\nkind = \"rod\"\n[canopy]\nnodes = 2\n", &[]),
        &["`canopy.nodes` (t.toml:4) = 2 is invalid"],
    );
}

#[test]
fn nan_and_infinity_are_refused() {
    for v in ["nan", "inf", "-inf", "+nan"] {
        let e = err_at(&format!("[canopy]\nspan_m = {v}\n"), 5);
        assert!(
            e.to_string().contains("must be a finite number"),
            "{v}: {e}"
        );
    }
    says(
        &err("[fluid]\nwind_mps = [0, nan, 0]\n"),
        &["`fluid.wind_mps`", "finite"],
    );
}

#[test]
fn out_of_set_values_list_the_allowed_ones() {
    let e = err_with("[model]\nkind = \"membrane\"\n", &[]);
    assert_eq!(
        e.to_string(),
        "`model.kind` (t.toml:2) = \"membrane\" is not allowed; allowed values: \"rod\", \"shell\""
    );
    says(
        &err("[fluid]\ndrag = \"cubic\"\n"),
        &["\"quadratic\", \"linear\""],
    );
    // Allowed in general, but not for this model.
    let e = err_with(
        "[model]\nkind = \"rod\"\n[load]\nsites = \"corners\"\n",
        &[],
    );
    says(
        &e,
        &["not allowed for a rod canopy; allowed values: \"ends\", \"center\""],
    );
    says(
        &err_with(
            "[model]\nkind = \"rod\"\n[canopy]\nshape = \"circle\"\n",
            &[],
        ),
        &["for a rod model"],
    );
    says(
        &err("[canopy]\nshape = \"circle\"\n[load]\nsites = \"corners\"\n"),
        &["\"rim\", \"center\""],
    );
    says(
        &err("[load]\nmode = \"node_mass_scale\"\n"),
        &["`load.mode`", "mesh"],
    );
}

#[test]
fn load_sites_outside_the_canopy() {
    // Rectangle 6 × 3 centred on the origin: x ∈ [−3, 3], y ∈ [−1.5, 1.5].
    let ok = format!("{HEAD}[load]\nsites = [[3, 1.5], [-3, -1.5], [0, 0]]\n");
    Scenario::from_str_with_name(&ok, "t.toml", &[]).unwrap();
    let e = err_at("[load]\nsites = [[0, 0], [3.01, 0]]\n", 5);
    assert_is!(&e, ScenarioError::SiteOutside { index: 1, .. });
    says(&e, &["(3.01, 0)", "rectangle"]);
    // Hexagon of circumradius 1 with a corner on +x: the corner is inside, (0, 0.9) is beyond
    // the apothem √3/2 ≈ 0.866.
    let hex = "[canopy]\nshape = \"hexagon\"\nradius_m = 1\n";
    let ok = format!("{HEAD}{hex}[load]\nsites = [[1, 0], [0, 0.866]]\n");
    Scenario::from_str_with_name(&ok, "t.toml", &[]).unwrap();
    says(
        &err(&format!("{hex}[load]\nsites = [[0, 0.9]]\n")),
        &["hexagon"],
    );
    let circle = "[canopy]\nshape = \"circle\"\nradius_m = 1\n";
    says(
        &err(&format!("{circle}[load]\nsites = [[0.8, 0.8]]\n")),
        &["circle of radius 1 m"],
    );
}

#[test]
fn mesh_file_must_exist_and_be_given() {
    let e = err("[canopy]\nshape = \"mesh\"\nmesh_file = \"nope/mesh.txt\"\n");
    assert_is!(&e, ScenarioError::MeshMissing { .. });
    let msg = e.to_string();
    assert_contains(&msg, &["`canopy.mesh_file` (t.toml:6)", "nope/mesh.txt"]);
    let e = err("[canopy]\nshape = \"mesh\"\n");
    assert_is!(&e, ScenarioError::Missing { key, .. } if key == "canopy.mesh_file");
    says(
        &err("[canopy]\nmesh_file = \"m.txt\"\n"),
        &["is invalid: only used with `canopy.shape = \"mesh\"`"],
    );
}

#[test]
fn relative_mesh_paths_resolve_against_the_scenario_file() {
    let dir = tempfile::tempdir().unwrap();
    for folder in ["meshes", "scen"] {
        std::fs::create_dir_all(dir.path().join(folder)).unwrap();
    }
    std::fs::write(dir.path().join("meshes/m.txt"), "").unwrap();
    let file = dir.path().join("scen/s.toml");
    std::fs::write(
        &file,
        format!("{HEAD}[canopy]\nshape = \"mesh\"\nmesh_file = \"../meshes/m.txt\"\n"),
    )
    .unwrap();
    let s = Scenario::load(&file, &[]).unwrap();
    assert_eq!(s.canopy.mesh_file.unwrap(), dir.path().join("meshes/m.txt"));
    std::fs::write(dir.path().join("meshes/m.stl"), "").unwrap();
    let e = Scenario::load(&file, &["canopy.mesh_file=../meshes/m.stl".into()]).unwrap_err();
    says(&e, &["`.obj`"]);
}

#[test]
fn missing_required_keys() {
    let e = err_with("name = \"x\"\n", &[]);
    assert_is!(&e, ScenarioError::Missing { key, .. } if key == "model.kind");
    says(&e, &["missing required key `model.kind`"]);
    says(
        &err("[fluid]\ndrag = \"linear\"\n"),
        &["fluid.linear_drag_coefficient_n_s_m"],
    );
}

#[test]
fn bad_names_are_refused() {
    for n in ["", "../evil", "a/b", ".hidden", "sp ace"] {
        let e = err_with(&format!("name = \"{n}\"\n[model]\nkind = \"rod\"\n"), &[]);
        assert!(e.to_string().starts_with("`name` (t.toml:1)"), "{n}: {e}");
    }
}

#[test]
fn override_errors_say_they_came_from_set() {
    let e = err_with(HEAD, &["canopy.span_m=-1"]);
    assert!(
        matches!(
            &e,
            ScenarioError::Invalid {
                origin: Origin::Set(_),
                ..
            }
        ),
        "{e:?}"
    );
    assert_eq!(
        e.to_string(),
        "`canopy.span_m` (from `--set canopy.span_m=-1`) = -1 is invalid: must be positive (a length)"
    );
    let e = err_with(HEAD, &["canopy.spam_m=1"]);
    assert_eq!(
        e.to_string(),
        "unknown key `canopy.spam_m` (from `--set canopy.spam_m=1`); did you mean `canopy.span_m`?"
    );
    says(
        &err_with(HEAD, &["fluid.drag=cubic"]),
        &["from `--set fluid.drag=cubic`", "\"linear\""],
    );
    says(
        &err_with(HEAD, &["canopy.nodes=many"]),
        &["`canopy.nodes` (from `--set canopy.nodes=many`) must be an integer"],
    );
    let e = err_with(HEAD, &["canopy.span_m"]);
    assert_is!(&e, ScenarioError::BadOverride { .. });
    says(&e, &["expected KEY=VALUE"]);
    says(&err_with(HEAD, &["=3"]), &["key before `=` is empty"]);
    says(
        &err_with(HEAD, &["load.sites=[[9, 0]]"]),
        &["from `--set load.sites=[[9, 0]]`", "outside"],
    );
}

/// Every error about a key names it in its message.
#[test]
fn every_keyed_error_names_its_key() {
    let bodies = [
        "[canopy]\nspan_m = \"x\"\n",
        "[canopy]\nspan_m = -1\n",
        "[canopy]\nspn_m = 1\n",
        "[fluid]\ndrag = \"x\"\n",
        "[load]\nsites = [[99, 0]]\n",
        "[canopy]\nshape = \"mesh\"\nmesh_file = \"x.txt\"\n",
        "[time]\nnewton_max_iterations = 0\n",
        "[output]\nframe_interval_s = 1e-5\n",
    ];
    for b in bodies {
        let e = err(b);
        let key = e
            .key()
            .unwrap_or_else(|| panic!("no key: {e:?}"))
            .to_string();
        assert!(e.to_string().contains(&format!("`{key}`")), "{e}");
    }
}

/// The adaptive time-step keys: type, sign, order `dt_min_s ≤ dt_s ≤ dt_max_s ≤ frame
/// interval`, and refused without `time.adaptive = true`; each error names its key and line.
#[test]
fn adaptive_keys_are_checked() {
    let e = err_at("[time]\nadaptive = \"yes\"\n", 5);
    assert_is!(&e, ScenarioError::WrongType { key, .. } if key == "time.adaptive");
    says(&e, &["a boolean (true or false)"]);
    let cases: &[(&str, &str, usize, &str)] = &[
        (
            "[time]\nerror_tolerance_m = 1e-5\n",
            "time.error_tolerance_m",
            5,
            "only used with `time.adaptive = true`",
        ),
        (
            "[time]\ndt_max_s = 0.01\n",
            "time.dt_max_s",
            5,
            "only used with `time.adaptive = true`",
        ),
        (
            "[time]\nadaptive = true\nerror_tolerance_m = 0\n",
            "time.error_tolerance_m",
            6,
            "must be positive (a position error per step)",
        ),
        (
            "[time]\nadaptive = true\ndt_min_s = -1e-6\n",
            "time.dt_min_s",
            6,
            "must be positive",
        ),
        (
            "[time]\nadaptive = true\ndt_min_s = 0.01\n",
            "time.dt_min_s",
            6,
            "must not exceed the first step time.dt_s = 0.001 s",
        ),
        (
            "[time]\nadaptive = true\ndt_max_s = 1e-4\n",
            "time.dt_max_s",
            6,
            "must not be below the first step time.dt_s = 0.001 s",
        ),
        (
            "[time]\nadaptive = true\ndt_max_s = 0.1\n",
            "time.dt_max_s",
            6,
            "output.frame_interval_s = 0.05 s",
        ),
    ];
    for (body, key, line, why) in cases {
        let e = err_at(body, *line);
        assert!(
            matches!(&e, ScenarioError::Invalid { key: k, .. } if k == key),
            "{body}: {e:?}"
        );
        assert!(e.to_string().contains(why), "{body}: {e}");
    }
    says(
        &err("[time]\nadaptive = true\ndt_max_s = nan\n"),
        &["`time.dt_max_s` (t.toml:6)", "finite"],
    );
    // A bad default follows from a bad first step: the first step is reported.
    let e = err("[time]\nadaptive = true\ndt_s = -1\n");
    assert_is!(&e, ScenarioError::Invalid { key, .. } if key == "time.dt_s");
    // Overrides name their origin.
    says(
        &err_with(HEAD, &["time.adaptive=true", "time.error_tolerance_m=-1"]),
        &["`time.error_tolerance_m` (from `--set time.error_tolerance_m=-1`)"],
    );
    says(
        &err_with(HEAD, &["time.adaptive=maybe"]),
        &["`time.adaptive` (from `--set time.adaptive=maybe`) must be a boolean"],
    );
}

/// The incidence law's table: required with it, used only with it, and one the engine can
/// read (covering ±90°, increasing, odd, one coefficient per angle), each error at the line of
/// the key at fault.
#[test]
fn the_incidence_table_is_checked_naming_its_key() {
    let law = "[fluid]\nshell_drag = \"incidence\"\n"; // lines 4–5
    let e = err(law);
    assert_is!(&e, ScenarioError::Missing { key, .. } if key == "fluid.incidence_alpha_deg" || key == "fluid.incidence_cn");
    let table = |a: &str, c: &str| format!("{law}incidence_alpha_deg = {a}\nincidence_cn = {c}\n");
    let cases = [
        (
            "[-45, 0, 90]",
            "[0.1, 0.0, -0.1]",
            6,
            "fluid.incidence_alpha_deg",
            "cover −90° to 90°",
        ),
        (
            "[-90, 0, 0, 90]",
            "[0.1, 0.0, 0.0, -0.1]",
            6,
            "fluid.incidence_alpha_deg",
            "increase strictly",
        ),
        (
            "[-90, 0, 90]",
            "[0.3, 0.0, -0.1]",
            7,
            "fluid.incidence_cn",
            "must be odd",
        ),
        (
            "[-90, 0, 90]",
            "[0.3, 0.0]",
            7,
            "fluid.incidence_cn",
            "as many angles as coefficients",
        ),
    ];
    for (a, c, line, key, why) in cases {
        let e = err_at(&table(a, c), line);
        assert_is!(&e, ScenarioError::Invalid { key: k, .. } if k == key);
        says(&e, &[why]);
    }
    let e = err_at("[fluid]\nincidence_cn = [0.0, 0.0]\n", 5);
    assert_is!(&e, ScenarioError::Invalid { key, .. } if key == "fluid.incidence_cn");
}

/// A round canopy's vent leaves cloth, a cone has an angle, and neither is for other outlines.
#[test]
fn vents_and_profiles_are_checked_naming_their_key() {
    let round = "[canopy]\nshape = \"circle\"\nradius_m = 1.5\nedge_length_m = 0.25\n"; // lines 4–7
    let e = err_at(&format!("{round}vent_radius_m = 1.4\n"), 8);
    assert_is!(&e, ScenarioError::Invalid { key, .. } if key == "canopy.vent_radius_m");
    says(&e, &["a vent as large as the canopy", "1.25 m"]);
    let e = err(&format!("{round}profile = \"conical\"\n"));
    assert_is!(&e, ScenarioError::Missing { key, .. } if key == "canopy.cone_angle_deg");
    let e = err_at(
        &format!("{round}profile = \"conical\"\ncone_angle_deg = 90\n"),
        9,
    );
    assert_is!(&e, ScenarioError::Invalid { key, .. } if key == "canopy.cone_angle_deg");
    let e = err_at("[canopy]\nvent_radius_m = 0.2\n", 5);
    assert_is!(&e, ScenarioError::Invalid { key, .. } if key == "canopy.vent_radius_m");
}

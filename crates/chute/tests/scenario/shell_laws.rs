//! The shell-law keys of the bending laws (docs/shells.md): `shell.bending` and
//! `canopy.mesh_pattern` (values, where they are allowed, line numbers, round trip).

use chute::scenario::{Bending, MeshPattern, Scenario, ScenarioError};

const HEAD: &str = "name = \"t\"\n[model]\nkind = \"shell\"\n"; // lines 1–3

fn load(text: &str) -> Result<Scenario, ScenarioError> {
    Scenario::from_str_with_name(text, "t.toml", &[])
}

/// The error of `text` names `key` and `t.toml:line` and says `why`.
fn refused(text: &str, key: &str, line: usize, why: &str) {
    let e = load(text)
        .err()
        .unwrap_or_else(|| panic!("accepted:\n{text}"));
    let msg = e.to_string();
    assert_eq!(e.key(), Some(key), "{msg}");
    assert!(msg.contains(&format!("t.toml:{line}")), "{msg}");
    assert!(msg.contains(why), "want `{why}` in: {msg}");
}

#[test]
fn bending_and_pattern_are_read_and_round_trip() {
    let text = format!(
        "{HEAD}[canopy]\nshape = \"rectangle\"\nmesh_pattern = \"unstructured\"\n[shell]\nbending = \"midedge\"\n"
    );
    let s = load(&text).unwrap();
    assert_eq!(s.shell.bending, Some(Bending::Midedge));
    assert_eq!(s.canopy.mesh_pattern, Some(MeshPattern::Unstructured));
    let again = load(&toml::to_string(&s).unwrap()).unwrap();
    assert_eq!(again.shell.bending, Some(Bending::Midedge));
    assert_eq!(again.canopy.mesh_pattern, Some(MeshPattern::Unstructured));
    // Absent: the report's laws, and nothing is written back.
    let s = load(HEAD).unwrap();
    assert_eq!((s.shell.bending, s.canopy.mesh_pattern), (None, None));
    let text = toml::to_string(&s).unwrap();
    assert!(
        !text.contains("bending") && !text.contains("mesh_pattern"),
        "{text}"
    );
}

#[test]
fn bad_values_and_misplaced_keys_are_refused() {
    refused(
        &format!("{HEAD}[shell]\nbending = \"plates\"\n"),
        "shell.bending",
        5,
        "\"hinge\", \"midedge\"",
    );
    refused(
        "name = \"t\"\n[model]\nkind = \"rod\"\n[shell]\nbending = \"midedge\"\n",
        "shell.bending",
        5,
        "model.kind = \"shell\"",
    );
    refused(
        &format!("{HEAD}[canopy]\nmesh_pattern = \"spiral\"\n"),
        "canopy.mesh_pattern",
        5,
        "\"union_jack\", \"cross\", \"unstructured\"",
    );
    refused(
        &format!("{HEAD}[canopy]\nshape = \"circle\"\nmesh_pattern = \"cross\"\n"),
        "canopy.mesh_pattern",
        6,
        "canopy.shape = \"rectangle\"",
    );
    refused(
        "name = \"t\"\n[model]\nkind = \"rod\"\n[canopy]\nmesh_pattern = \"cross\"\n",
        "canopy.mesh_pattern",
        5,
        "model.kind = \"shell\"",
    );
}

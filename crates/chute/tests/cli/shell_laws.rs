//! The mid-edge bending and mesh-pattern keys through the binary: a non-manifold mesh is
//! refused naming its file line, and the keys' bad values exit 2 naming the key.

use crate::common::*;

/// Exit 2 and every `want` in the last (`error: `) line of stderr, no panic.
fn refused(dir: &std::path::Path, args: &[&str], want: &[&str]) {
    let o = chute(dir, args);
    let err = stderr(&o);
    assert_exit(&o, 2);
    assert!(!err.contains("panicked"), "{err}");
    let last = err.trim_end().lines().last().unwrap_or("");
    assert!(last.starts_with("error: "), "{err}");
    for w in want {
        assert!(last.contains(w), "want `{w}` in: {err}");
    }
}

#[test]
fn midedge_on_a_non_manifold_mesh_names_the_line() {
    // Edge 1–2 is shared by the triangles of lines 8, 9 and 10.
    let mesh = "*Nodes\n0 0 0\n1 0 0\n0 1 0\n0 -1 0\n0 0 1\n*Triangles\n1 2 3\n2 1 4\n1 2 5\n";
    let scenario = "name = \"t\"\n[model]\nkind = \"shell\"\n[canopy]\nshape = \"mesh\"\n\
         mesh_file = \"m.txt\"\n[shell]\nbending = \"midedge\"\n[load]\nmode = \"force\"\n\
         sites = [[0.2, 0.2]]\n";
    let dir = tmp_with_files(&[("m.txt", mesh), ("s.toml", scenario)]);
    for cmd in ["check", "run"] {
        refused(
            dir.path(),
            &[cmd, "s.toml"],
            &[
                "m.txt:10",
                "non-manifold triangle",
                "edge 1–2 is shared by 3 triangles",
            ],
        );
    }
}

#[test]
fn bad_bending_and_pattern_values_name_the_key() {
    let dir = tmp_with_files(&[("s.toml", "name = \"t\"\n[model]\nkind = \"shell\"\n")]);
    refused(
        dir.path(),
        &["check", "s.toml", "--set", "shell.bending=plate"],
        &["`shell.bending`", "\"hinge\", \"midedge\""],
    );
    refused(
        dir.path(),
        &["check", "s.toml", "--set", "canopy.mesh_pattern=spiral"],
        &["`canopy.mesh_pattern`", "\"union_jack\""],
    );
    refused(
        dir.path(),
        &[
            "check",
            "s.toml",
            "--set",
            "model.kind=rod",
            "--set",
            "shell.bending=midedge",
        ],
        &["`shell.bending`", "model.kind = \"shell\""],
    );
}

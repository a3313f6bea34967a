//! Bad meshes and implausible values through the binary: a mesh with an unused node is an
//! input error of `check` and `run` (exit 2, file, line and node named) before any output is
//! written; values no fabric has are warned about.
use crate::common::*;

#[test]
fn unused_vertex_is_an_input_error_before_any_output() {
    let tmp = tempfile::tempdir().unwrap();
    // The bundled DisMech parachute cut before its `*Edges`.
    let full =
        std::fs::read_to_string(repo().join("crates/chute/data/meshes/hexparachute_n6_python.txt"))
            .unwrap();
    let cut = &full[..full.find("*Edges").unwrap()];
    std::fs::write(tmp.path().join("cut.txt"), cut).unwrap();
    let scenario = std::fs::read_to_string(repo().join("scenarios/dismech-hex-n6.toml"))
        .unwrap()
        .replace(
            "../crates/chute/data/meshes/hexparachute_n6_python.txt",
            "cut.txt",
        );
    std::fs::write(tmp.path().join("s.toml"), scenario).unwrap();
    for args in [
        &["check", "s.toml"][..],
        &["run", "s.toml", "--out", "o", "-q"][..],
    ] {
        let o = chute(tmp.path(), args);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(
            err.contains("canopy.mesh_file: ")
                && err.contains("cut.txt:2: node 1 is on no triangle and no rod edge"),
            "{args:?}: {err}"
        );
        assert!(!err.contains("non-positive mass"), "{err}");
    }
    assert!(!tmp.path().join("o").exists(), "a run directory was left");
}

#[test]
fn implausible_material_is_warned_about_by_check() {
    let o = check_bundled("report-rod-200n.toml", &["material.youngs_modulus_pa=55e3"]);
    assert_exit_says(
        &o,
        0,
        &["warning: material.youngs_modulus_pa = 55000 Pa is far below any real fabric"],
    );
}

/// A study file whose size reads 0 but that never ends (a link to `/proc/self/pagemap`) is
/// read at most up to the limit of a study file and refused (exit 2; the kernel may refuse
/// the bounded read itself), not read until memory runs out.
#[test]
fn an_endless_study_file_is_refused_at_its_limit() {
    let pagemap = std::path::Path::new("/proc/self/pagemap");
    if !pagemap.exists() {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    std::os::unix::fs::symlink(pagemap, tmp.path().join("pm.toml")).unwrap();
    let o = chute(tmp.path(), &["study", "pm.toml"]);
    assert_exit_says(&o, 2, &["cannot read study file"]);
}

/// `chute check scenarios/<file> --set <set>` exits 2 with every one of `want` in its message.
fn check_refuses(file: &str, set: &str, want: &[&str]) {
    assert_refused(&check_bundled(file, &[set]), want);
}

/// An imported mesh's lines (its rod edges, of the lines' material) are held to the same
/// stiffness-to-inertia limit as generated lines: refused by `check` naming the key, not a
/// failure at t = 0.
#[test]
fn an_imported_meshs_lines_are_held_to_the_step_stiffness_limit() {
    let set = "lines.youngs_modulus_pa=1e22";
    let want = ["lines.youngs_modulus_pa", "shortest mesh line edge"];
    check_refuses("dismech-hex-n6.toml", set, &want);
}

/// A model larger than any parachute (a 1e40 m rod passed every other limit and failed at
/// t = 0) is refused by `check`, blaming the key.
#[test]
fn a_model_larger_than_any_parachute_is_refused() {
    let want = ["canopy.span_m", "largest dimension"];
    check_refuses("report-rod-20n.toml", "canopy.span_m=1e40", &want);
}

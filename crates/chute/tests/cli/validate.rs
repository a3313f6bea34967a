//! `chute validate` through the binary: the quick suite passes, its JSON has the documented
//! fields, and a deliberately broken reference (the hidden test option `--break-reference`)
//! makes the command exit non-zero, for a cantilever case and for the membrane patch tests.
use crate::common::chute_command as chute;

#[test]
fn quick_suite_passes_and_json_has_the_documented_fields() {
    let out = chute()
        .args(["validate", "--quick", "--json"])
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "status {:?}\n{stdout}\n{}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    let checks: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    let checks = checks.as_array().unwrap();
    assert!(checks.len() >= 30, "{} checks", checks.len());
    for c in checks {
        assert!(c["name"].is_string(), "{c}");
        for k in ["reference", "simulated", "rel_error", "tolerance"] {
            assert!(c[k].is_f64(), "{k} in {c}");
        }
        assert_eq!(c["pass"], serde_json::Value::Bool(true), "{c}");
        assert!(c["rel_error"].as_f64() <= c["tolerance"].as_f64(), "{c}");
    }
    // Every case of the brief is present.
    for prefix in [
        "be-spring-damping",
        "cantilever-tip-load",
        "cantilever-self-weight",
        "elastica-alpha-1",
        "elastica-alpha-2",
        "elastica-alpha-5",
        "elastica-alpha-10",
        "end-moment-arc",
        "cantilever-first-period",
        "cylinder-bending-energy",
        "plate-simply-supported",
        "shell-cantilever-strip",
        "midedge-cylinder",
        "midedge-plate",
        "patch-cst-uniform-stretch",
        "patch-cst-uniaxial-nu",
        "patch-fabric-uniaxial-nu12",
        "patch-fabric-uniaxial-nu21",
        "patch-no-compression",
        "patch-springs-uniaxial",
        "falling-sheet",
        "falling-strip",
        "wind-drift",
        "rod-canopy-terminal",
        "shell-canopy-force-balance",
        "symmetric-canopy-no-spin",
        "dismech-hex-n6",
        "real-t10-descent",
    ] {
        assert!(
            checks
                .iter()
                .any(|c| c["name"].as_str().unwrap().starts_with(prefix)),
            "missing {prefix}"
        );
    }
}

#[test]
fn a_broken_reference_makes_the_command_fail() {
    // The option scales the references of the named case by 1.5; the table must show FAIL
    // and the exit status must be non-zero. `--case` keeps this second run short.
    let out = chute()
        .args(["validate", "--quick", "--case", "cantilever"])
        .args(["--break-reference", "cantilever-tip-load"])
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{stdout}");
    let line = stdout
        .lines()
        .find(|l| l.starts_with("cantilever-tip-load"))
        .unwrap();
    assert!(line.contains("FAIL"), "{line}");
    // The other cantilever cases still pass: only the broken reference fails.
    assert!(stdout.contains(" 1 failed"), "{stdout}");
    assert!(stdout
        .lines()
        .any(|l| l.starts_with("cantilever-self-weight")
            && l.split_whitespace().last() == Some("ok")));
}

#[test]
fn a_broken_membrane_patch_reference_fails_only_its_rows() {
    // The patch tests are exact to ~1e-12, so a reference off by 1.5 (and 1 instead of 0 for
    // the near-zero rows) must fail every row of the broken case and none of the others.
    let out = chute()
        .args(["validate", "--quick", "--json", "--case", "patch-"])
        .args(["--break-reference", "patch-fabric-uniaxial-nu21"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let checks: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let checks = checks.as_array().unwrap();
    let (mut broken, mut others) = (0, 0);
    for c in checks {
        let name = c["name"].as_str().unwrap();
        assert!(name.starts_with("patch-"), "{c}");
        if name.starts_with("patch-fabric-uniaxial-nu21") {
            broken += 1;
            assert_eq!(c["pass"], serde_json::Value::Bool(false), "{c}");
        } else {
            others += 1;
            assert_eq!(c["pass"], serde_json::Value::Bool(true), "{c}");
        }
    }
    assert_eq!(broken, 4, "{checks:?}");
    assert!(others >= 20, "{others} other patch rows");
}

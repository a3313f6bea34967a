//! `chute validate` through the binary: the quick suite passes, its JSON has the documented
//! fields, and a deliberately broken reference (the hidden test option `--break-reference`)
//! makes the command exit non-zero.
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
        "falling-sheet",
        "falling-strip",
        "wind-drift",
        "rod-canopy-terminal",
        "shell-canopy-force-balance",
        "symmetric-canopy-no-spin",
        "dismech-hex-n6",
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
        .any(|l| l.starts_with("cantilever-self-weight") && l.contains(" ok ")));
}

//! `chute bench --quick --json` prints a JSON list with the documented fields.
//!
//! The hidden `--tiny` swaps the ladder for three small cases of a few steps (rod, shell and
//! the peer's hexagonal n6), so these tests take well under a second; the real ladder is
//! exercised by running `chute bench` (docs/performance.md).

use std::process::Command;

use chute::bench::CaseResult;

#[test]
fn bench_quick_json_has_documented_fields() {
    let out = Command::new(env!("CARGO_BIN_EXE_chute"))
        .args(["bench", "--quick", "--json", "--tiny"])
        .output()
        .expect("run chute");
    assert!(
        out.status.success(),
        "chute bench failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).expect("utf-8");
    // The documented contract, checked on the raw JSON (not only through our own type).
    let raw: serde_json::Value = serde_json::from_str(&text).expect("JSON on stdout");
    let list = raw.as_array().expect("a list");
    assert_eq!(list.len(), 3);
    for obj in list {
        for key in ["name", "dofs", "nnz", "ms_per_step", "newton_per_step"] {
            assert!(obj.get(key).is_some(), "missing `{key}` in {obj}");
        }
    }
    let cases: Vec<CaseResult> = serde_json::from_str(&text).expect("CaseResult list");
    assert!(cases.iter().any(|c| c.name.contains("n6")));
    for c in &cases {
        assert!(c.dofs >= c.free_dofs && c.free_dofs > 0, "{c:?}");
        assert!(c.nnz >= c.free_dofs, "{c:?}");
        assert!(c.ms_per_step > 0.0 && c.ms_per_step.is_finite(), "{c:?}");
        // Each step needs at least one Newton iteration (the predictor never solves a
        // loaded, accelerating canopy to 1e-9 relative precision).
        assert!(c.newton_per_step >= 1.0, "{c:?}");
        let shares = c.share_assembly + c.share_merit + c.share_factor + c.share_solve;
        assert!(shares > 0.0 && shares <= 1.0 + 1e-9, "{c:?}");
        assert!(c.peak_rss_mib > 0.0, "{c:?}");
    }
    let n6 = cases.iter().find(|c| c.name.contains("n6")).unwrap();
    // The peer's mesh: 188 nodes, 3 DOFs each plus one twist per rod edge (66 edges).
    assert_eq!((n6.nodes, n6.dofs), (188, 188 * 3 + 66));
}

fn tiny_bench(extra: &[&str]) -> Vec<CaseResult> {
    let out = Command::new(env!("CARGO_BIN_EXE_chute"))
        .args(["bench", "--json", "--tiny"])
        .args(extra)
        .output()
        .expect("run chute");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("CaseResult list")
}

/// The experiment options reach every case's child process: without modified Newton every
/// iteration factorises, with it (the default) the shell case reuses factorisations.
#[test]
fn bench_options_reach_the_cases() {
    let shell = |r: &[CaseResult]| r.iter().find(|c| c.name == "shell-250").cloned().unwrap();
    let fresh = shell(&tiny_bench(&["--no-reuse"]));
    assert!(
        (fresh.factorizations_per_step - fresh.newton_per_step).abs() < 1e-12,
        "{fresh:?}"
    );
    let default = tiny_bench(&[]);
    let reused = shell(&default);
    assert!(
        reused.factorizations_per_step < reused.newton_per_step,
        "{reused:?}"
    );
    // `--set` reaches them too: three Newton iterations are too few for the rod's first
    // steps, which fail and are retried with half the step, as a run would.
    let rod = |r: &[CaseResult]| r.iter().find(|c| c.name == "rod-100").cloned().unwrap();
    assert_eq!(rod(&default).halvings, 0, "{default:?}");
    let capped = rod(&tiny_bench(&["--set", "time.newton_max_iterations=3"]));
    assert!(capped.halvings > 0, "{capped:?}");
    assert!(
        (capped.t_end_s - rod(&default).t_end_s).abs() < 1e-12,
        "{capped:?}"
    );
}

/// A bad `--set` is a scenario error (exit 2) naming the key, before any case runs.
#[test]
fn bench_rejects_a_bad_override() {
    let out = Command::new(env!("CARGO_BIN_EXE_chute"))
        .args(["bench", "--tiny", "--set", "canopy.spam_m=1"])
        .output()
        .expect("run chute");
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("unknown key `canopy.spam_m`") && err.contains("did you mean `canopy.span_m`"),
        "{err}"
    );
}

//! `chute bench --quick --json` prints a JSON list with the documented fields.
//!
//! `CHUTE_BENCH_TINY=1` swaps the ladder for three small cases of a few steps (rod, shell and
//! the peer's hexagonal n6), so this test takes well under a second; the real ladder is
//! exercised by running `chute bench` (docs/performance.md).

use std::process::Command;

use chute::bench::CaseResult;

#[test]
fn bench_quick_json_has_documented_fields() {
    let out = Command::new(env!("CARGO_BIN_EXE_chute"))
        .args(["bench", "--quick", "--json"])
        .env("CHUTE_BENCH_TINY", "1")
        .env_remove("CHUTE_BENCH_CASE")
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

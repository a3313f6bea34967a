//! `chute bench --quick --json` prints a JSON list with the documented fields.
//!
//! The hidden `--tiny` swaps the ladder for three small cases of a few steps (rod, shell and
//! the peer's hexagonal n6), so these tests take well under a second; the real ladder is
//! exercised by running `chute bench` (docs/performance.md).

use chute::bench::CaseResult;

use crate::common::{assert_contains, chute, repo, stderr, stdout};

/// `chute bench --json --tiny EXTRA…`: its stdout, after checking it succeeded.
fn tiny_bench_json(extra: &[&str]) -> String {
    let args: Vec<&str> = ["bench", "--json", "--tiny"]
        .iter()
        .chain(extra)
        .copied()
        .collect();
    let out = chute(&repo(), &args);
    assert!(out.status.success(), "chute bench failed: {}", stderr(&out));
    stdout(&out)
}

fn tiny_bench(extra: &[&str]) -> Vec<CaseResult> {
    serde_json::from_str(&tiny_bench_json(extra)).expect("CaseResult list")
}

#[test]
fn bench_quick_json_has_documented_fields() {
    let text = tiny_bench_json(&["--quick"]);
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
        let shares = c.share_assembly + c.share_factor + c.share_solve;
        assert!(shares > 0.0 && shares <= 1.0 + 1e-9, "{c:?}");
        assert!(c.peak_rss_mib > 0.0, "{c:?}");
        // Each stage of the ladder is reached only by solves the stage before did not
        // converge, and every solve ends in exactly one converged stage or a failure.
        let k = &c.counters;
        for st in [k.held, k.newton, k.continuation, k.homotopy] {
            assert!(st.converged <= st.runs, "{c:?}");
        }
        assert!(
            k.continuation.runs <= k.newton.runs - k.newton.converged,
            "{c:?}"
        );
        assert!(
            k.homotopy.runs <= k.continuation.runs - k.continuation.converged,
            "{c:?}"
        );
        let converged =
            k.held.converged + k.newton.converged + k.continuation.converged + k.homotopy.converged;
        assert_eq!(converged + c.halvings as u64, k.solves, "{c:?}");
    }
    for key in ["held", "newton", "continuation", "homotopy"] {
        assert!(
            list[0]["counters"].get(key).is_some(),
            "missing `counters.{key}` in {}",
            list[0]
        );
    }
    let n6 = cases.iter().find(|c| c.name.contains("n6")).unwrap();
    // The peer's mesh: 188 nodes, 3 DOFs each plus one twist per rod edge (66 edges).
    assert_eq!((n6.nodes, n6.dofs), (188, 188 * 3 + 66));
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
    // `--set` reaches them too: two iterations per stage are too few for one of the shell's
    // first steps, which fails and is retried with half the step, as a run would. (Strict
    // tolerance and no rescue stages: their budgets or the accuracy test could take it. Not
    // one iteration: the first Newton update is solved only to its forcing term, 1e-3 of
    // the residual, which no step size brings under the strict tolerance.)
    assert_eq!(shell(&default).halvings, 0, "{default:?}");
    let capped = shell(&tiny_bench(&[
        "--set",
        "time.newton_rescue_stages=false",
        "--set",
        "time.newton_strict=true",
        "--set",
        "time.newton_max_iterations=2",
    ]));
    assert!(capped.halvings > 0, "{capped:?}");
    assert!(
        (capped.t_end_s - shell(&default).t_end_s).abs() < 1e-12,
        "{capped:?}"
    );
}

/// A bad `--set` is a scenario error (exit 2) naming the key, before any case runs.
#[test]
fn bench_rejects_a_bad_override() {
    let out = chute(&repo(), &["bench", "--tiny", "--set", "canopy.spam_m=1"]);
    assert_eq!(out.status.code(), Some(2));
    let err = stderr(&out);
    assert_contains(
        &err,
        &[
            "unknown key `canopy.spam_m`",
            "did you mean `canopy.span_m`",
        ],
    );
}

/// `chute bench --elements --json`: one entry per shell law, measured (positive times) and
/// relative to the report's law of its kind (springs, hinges: ratio 1).
#[test]
fn bench_elements_times_every_shell_law() {
    let out = chute(&repo(), &["bench", "--elements", "--json"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let costs: Vec<chute::bench::elements::ElementCost> =
        serde_json::from_str(&stdout(&out)).expect("ElementCost list");
    let laws: Vec<&str> = costs.iter().map(|c| c.law.as_str()).collect();
    assert_eq!(
        laws,
        ["springs", "cst", "fabric", "fabric-nc", "hinge", "midedge"]
    );
    for c in &costs {
        // Only what is deterministic: counts and times that were measured (finite and
        // positive). How the two paths compare in speed depends on the machine's load; it
        // is measured by `chute bench --elements` (docs/performance.md).
        assert!(c.elements > 0, "{c:?}");
        for ns in [c.ns_per_element, c.force_ns_per_element] {
            assert!(ns.is_finite() && ns > 0.0, "{c:?}");
        }
        let base = if c.kind == "membrane" {
            "springs"
        } else {
            "hinge"
        };
        if c.law == base {
            assert_eq!(c.ratio_per_element, 1.0, "{c:?}");
            assert_eq!(c.ratio_force_per_element, 1.0, "{c:?}");
        }
    }
}

/// A `--plot` path that cannot take the picture (no such directory, or inside a run
/// directory, whose file it would replace without holding it) is refused before the
/// benchmark runs (status 2), not after it (status 3).
#[test]
fn an_unwritable_plot_path_is_refused_before_the_benchmark() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::create_dir(tmp.path().join("r")).unwrap();
    let record = r#"{"status": "complete", "reason": null, "inputs": [], "viewer": true}"#;
    std::fs::write(tmp.path().join("r/run.json"), record).unwrap();
    for plot in ["nosuch/scaling.png", "r/velocity.png"] {
        let o = chute(tmp.path(), &["bench", "--tiny", "--plot", plot]);
        assert_eq!(o.status.code(), Some(2), "{plot}: {}", stderr(&o));
        assert!(!stdout(&o).contains("rod"), "{plot}: the benchmark ran");
    }
    assert!(!tmp.path().join("r/velocity.png").exists());
}

//! Adaptive time steps through the application: a short error-controlled run of the report's
//! rod (coarse) ends exactly on its duration, on every frame, snapshot and sync time, and
//! reports its steps; Newton failures keep their halving policy; bad keys exit with status 2.
//! (Resume equality of adaptive runs: `reliability_resume.rs`.)
use crate::common::*;

use std::path::Path;
use std::sync::atomic::AtomicBool;

use chute::app::{run as app_run, RunOptions};

fn opts(dir: &Path) -> RunOptions {
    std::fs::create_dir_all(dir).unwrap();
    RunOptions {
        out_dir: dir.to_path_buf(),
        force: true,
        progress: false,
        checkpoint_every_s: None,
        resume: None,
        viewer: false,
        case_of: None,
    }
}

/// Frame times listed in `canopy.pvd`.
fn pvd_times(dir: &Path) -> Vec<f64> {
    let text = std::fs::read_to_string(dir.join("canopy.pvd")).unwrap();
    text.split("timestep=\"")
        .skip(1)
        .map(|s| s[..s.find('"').unwrap()].parse().unwrap())
        .collect()
}

#[test]
fn adaptive_run_lands_on_the_end_and_every_output_time() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("a");
    let s = rod(0.3, &["time.adaptive=true"]);
    let o = app_run(&s, &opts(&dir)).unwrap();
    assert!(o.complete, "{:?}", o.message);
    let rows = csv_rows(&dir.join("timeseries.csv"));
    let t: Vec<f64> = rows.iter().map(|r| r[0]).collect();
    let dt: Vec<f64> = rows[1..].iter().map(|r| r[12]).collect();
    // Exactly on the duration (bits), and every step's dt is its time increment.
    assert_eq!(t.last().unwrap().to_bits(), 0.3f64.to_bits());
    for (w, h) in t.windows(2).zip(&dt) {
        assert!((w[1] - w[0] - h).abs() <= 1e-15, "t {w:?}, dt {h}");
    }
    // Frames at k · 0.05 s exactly, each at the end of a step; the snapshot at 0.05 s drawn;
    // sync points (every 0.1 s for these settings) are steps too.
    // (k · 0.05 up to round-off: 6 · 0.05 = 0.30000000000000004 is written at the end, 0.3.)
    let frames = pvd_times(&dir);
    assert_eq!(frames.len(), 7, "{frames:?}");
    for (k, f) in frames.iter().enumerate() {
        assert!((f - k as f64 * 0.05).abs() <= 1e-15, "frame {k} at {f}");
    }
    for f in &frames {
        assert!(t.contains(f), "no step ends at frame time {f}");
    }
    assert!(dir.join("snapshot_0.05s.png").is_file());
    // Error control is on. From rest every node falls at g and the 100 N end loads add to
    // the end nodes (1.296 kg): a_end = 100/1.296 + 9.81 ≈ 87 m/s². The mass-RMS estimate
    // (h²/2) a_rms has g ≤ a_rms ≤ a_end, so the first 1 ms step (err ≥ g dt²/(2 tol) ≈ 0.49,
    // and here > 1) is rejected and the accepted retry 0.9 √(2 tol/a_rms) lies between
    // 0.9 √(2 tol/a_end) ≈ 0.43 ms and 1 ms. As the strip bends the ends' acceleration
    // decays and the step grows; none exceeds dt_max.
    let (lo, hi) = dt
        .iter()
        .fold((f64::MAX, 0.0f64), |(a, b), &h| (a.min(h), b.max(h)));
    assert!((0.43e-3..1e-3).contains(&dt[0]), "first step {}", dt[0]);
    assert!(o.summary["rejected_steps_error"].as_u64().unwrap() >= 1);
    assert!(hi > dt[0] && hi <= 0.05, "dt in [{lo}, {hi}]");
    let v = &o.summary;
    assert_eq!(v["adaptive"], true);
    assert_eq!(v["error_tolerance_m"], 1e-5);
    assert_eq!(v["dt_max_s"], 0.05);
    assert_eq!(v["steps"].as_u64().unwrap() as usize, dt.len());
    // (serde_json reads floats to within an ulp.)
    let close = |x: &serde_json::Value, y: f64| (x.as_f64().unwrap() - y).abs() <= 1e-15 * y;
    assert!(close(&v["dt_used_min_s"], lo) && close(&v["dt_used_max_s"], hi));
    let mean = v["dt_used_mean_s"].as_f64().unwrap();
    assert!((mean - 0.3 / dt.len() as f64).abs() < 1e-12, "{mean}");
    assert!(v["rejected_steps_error"].as_u64().unwrap() >= 1);
    assert_eq!(v["rejected_steps_newton"], 0);
    // The resolved scenario records the filled-in settings.
    let resolved = std::fs::read_to_string(dir.join("scenario.resolved.toml")).unwrap();
    assert_contains(
        &resolved,
        &["adaptive = true", "error_tolerance_m = 0.00001"],
    );

    // A 10× looser tolerance takes fewer steps (h ∝ √tol: ~3× fewer where controlled).
    let loose = tmp.path().join("b");
    let s = rod(0.3, &["time.adaptive=true", "time.error_tolerance_m=1e-4"]);
    let o2 = app_run(&s, &opts(&loose)).unwrap();
    let n2 = o2.summary["steps"].as_u64().unwrap() as f64;
    assert!(
        n2 < 0.6 * dt.len() as f64,
        "{n2} steps vs {} at 10 × the tolerance",
        dt.len()
    );
}

/// A NaN blow-up for 3 evaluations in an adaptive run: 3 Newton rejections, each halving the
/// step and capping the controller there, then the run completes on its duration.
#[test]
fn adaptive_newton_failures_halve_the_step_and_are_counted() {
    let s = rod(0.2, &["time.adaptive=true"]);
    let mut built = chute::build::build(&s).unwrap();
    let mut trig = Trigger::new(2, 0.1);
    trig.nan_evals = 3;
    built.model.add_force(trig);
    let tmp = tempfile::tempdir().unwrap();
    let mut cfg = chute::app::run_config(&s, false);
    // Each failure must reach the run loop: one stage, which meets the NaN at its first
    // evaluation (later stages would evaluate again and use up the trigger's NaNs).
    cfg.newton.hold_factors = false;
    cfg.newton.continuation = false;
    cfg.newton.step_homotopy = false;
    let r = chute::runner::simulate(&mut built, &cfg, tmp.path(), &AtomicBool::new(false)).unwrap();
    assert!(r.complete, "{:?}", r.stop_reason);
    assert_eq!(r.summary.stepping.rejected_steps_newton, 3);
    let rows = csv_rows(&tmp.path().join("timeseries.csv"));
    assert_eq!(rows.last().unwrap()[0], 0.2);
    // The first step accepted after the failures is 1/8 of the one that failed (the step
    // ending on the frame at 0.1 s, where the trigger fires), and the next GROW_AFTER steps
    // (this one included) are no longer (the cap).
    let t: Vec<f64> = rows.iter().map(|r| r[0]).collect();
    let k = (1..rows.len())
        .find(|&k| {
            let failed = 0.1 - t[k - 1];
            failed > 0.0 && (8.0 * rows[k][12] - failed).abs() <= 1e-9 * failed
        })
        .expect("a step of 1/8 of the failed one");
    let cap = rows[k][12];
    let after: Vec<f64> = rows[k..k + chute::runner::GROW_AFTER as usize]
        .iter()
        .map(|r| r[12])
        .collect();
    assert!(
        after.iter().all(|&h| h <= cap * (1.0 + 1e-12)),
        "{cap}: {after:?}"
    );
    assert_eq!(count_containing(&r.summary.warnings, "step rejected"), 3);
}

/// Each new key with a bad value: exit status 2, a message naming the key (and where it came
/// from), for `check` and `run`, and no output directory.
#[test]
fn bad_adaptive_keys_exit_2_naming_the_key() {
    let dir = tempfile::tempdir().unwrap();
    let f = repo().join("scenarios/report-rod-200n.toml");
    let f = f.to_str().unwrap();
    let cases: &[(&[&str], &str)] = &[
        (&["time.adaptive=maybe"], "`time.adaptive` (from `--set time.adaptive=maybe`) must be a boolean"),
        (&["time.error_tolerance_m=1e-5"], "`time.error_tolerance_m` (from `--set time.error_tolerance_m=1e-5`) = 1e-5 is invalid: only used with `time.adaptive = true`"),
        (&["time.adaptive=true", "time.error_tolerance_m=0"], "`time.error_tolerance_m` (from `--set time.error_tolerance_m=0`) = 0 is invalid: must be positive"),
        (&["time.adaptive=true", "time.dt_min_s=0.002"], "`time.dt_min_s` (from `--set time.dt_min_s=0.002`) = 0.002 is invalid: the smallest step must not exceed the first step time.dt_s"),
        (&["time.adaptive=true", "time.dt_max_s=5e-4"], "`time.dt_max_s` (from `--set time.dt_max_s=5e-4`) = 0.0005 is invalid: the largest step must not be below"),
        (&["time.adaptive=true", "time.dt_max_s=1"], "`time.dt_max_s` (from `--set time.dt_max_s=1`) = 1 is invalid: steps end on every frame time"),
        (&["time.adaptive=true", "time.dt_min_s=-1"], "`time.dt_min_s` (from `--set time.dt_min_s=-1`) = -1 is invalid: must be positive"),
    ];
    for (sets, want) in cases {
        for cmd in ["check", "run"] {
            let mut args = vec![cmd, f];
            for s in *sets {
                args.extend(["--set", s]);
            }
            let o = chute(dir.path(), &args);
            let err = String::from_utf8_lossy(&o.stderr);
            assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
            assert!(err.contains(want), "{args:?}: want `{want}` in {err}");
            assert!(!err.contains("panicked"), "{err}");
        }
    }
    assert!(!dir.path().join("runs").exists());
}

#[test]
fn check_shows_the_adaptive_settings() {
    let o = check_bundled("report-rod-200n.toml", &["time.adaptive=true"]);
    assert_exit(&o, 0);
    let out = String::from_utf8_lossy(&o.stdout);
    assert_contains(
        &out,
        &[
            "adaptive, local error ≤ 1e-5 m per step",
            "first dt = 0.001 s",
            "9.7656e-7, 0.05] s",
        ],
    );
    let out = stdout(&check_bundled("report-rod-200n.toml", &[]));
    assert!(out.contains("10000 (dt = 0.001 s, 10 s)"), "{out}");
    assert!(!out.contains("adaptive,"), "{out}");
}

/// An adaptive run extended by `resume` from its end is the longer run bit for bit, also
/// when that end (0.3 s) is not a binary multiple of the sync interval (3 × 0.1 is
/// 0.30000000000000004): sync and frame times are taken as the decimals they name.
#[test]
fn an_adaptive_run_extended_from_an_end_off_the_binary_grid_is_the_longer_run() {
    let tmp = tempfile::tempdir().unwrap();
    let rod = bundled("report-rod-20n.toml");
    let rod = rod.as_str();
    let a = [
        "--set",
        "time.adaptive=true",
        "--set",
        "time.error_tolerance_m=1e-6",
        "-q",
    ];
    let run = |out: &str, d: &str, extra: &[&str]| {
        let dur = format!("time.duration_s={d}");
        let args = [
            &["run", rod, "--out", out, "--set", dur.as_str()][..],
            &a,
            extra,
        ]
        .concat();
        chute_ok(tmp.path(), &args);
    };
    run("long", "0.6", &[]);
    run("ext", "0.3", &["--checkpoint-every", "0.05"]);
    chute_ok(
        tmp.path(),
        &["resume", "ext", "--set", "time.duration_s=0.6", "-q"],
    );
    let ts = |d: &str| std::fs::read(tmp.path().join(d).join("timeseries.csv")).unwrap();
    assert!(
        ts("long") == ts("ext"),
        "the extended run's time series differs"
    );
}

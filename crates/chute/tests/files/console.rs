//! The console summary after `chute run`: key results first in four significant figures with
//! units, warnings as plain lines, the files; `--json` prints summary.json alone on stdout;
//! `-q` prints nothing; snapshot times beyond the duration give one warning.

use std::path::{Path, PathBuf};
use std::process::Output;

use crate::common::{assert_contains, assert_exit};

use chute::output::console::{format_run_summary, human_duration, key_results, not_reached_reason};
use chute::output::{Stepping, Summary};

fn summary() -> Summary {
    Summary {
        summary_version: chute::output::summary::SUMMARY_VERSION,
        scenario_name: "round".into(),
        complete: true,
        stop_reason: None,
        simulated_time_s: 10.0,
        terminal_velocity_mps: -6.123456,
        terminal_velocity_std_mps: 0.00123456,
        terminal_velocity_trend_mps: 0.0004,
        reached_terminal: true,
        time_to_terminal_s: Some(3.21987),
        final_window_start_s: 8.0,
        max_extended_height_m: 1.987654,
        final_extended_height_m: 1.5,
        total_weight_n: 109.2,
        canopy_weight_n: Some(9.2),
        mean_drag_z_n: 108.91234,
        drag_area_m2: Some(4.7654321),
        force_balance_error: 0.0026527,
        horizontal_velocity_mps: [0.0, 0.0],
        glide_angle_deg: 0.0,
        reynolds_number: 1.2e6,
        recovery: Default::default(),
        steps: 10_000,
        newton_iterations: 31_234,
        wall_time_s: 187.4,
        dofs: 2946,
        stepping: Stepping::default(),
        solver: None,
        triggers: Vec::new(),
        warnings: vec!["something to know".into()],
    }
}

#[test]
fn key_results_come_first_in_four_significant_figures() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("summary.json"), "{}").unwrap();
    std::fs::write(dir.path().join("viewer.html"), "").unwrap();
    std::fs::create_dir(dir.path().join("frames")).unwrap();
    std::fs::write(dir.path().join("frames/frame_000000.vtu"), "").unwrap();
    std::fs::write(dir.path().join(".hidden.tmp"), "").unwrap();
    let text = format_run_summary(&summary(), dir.path());
    let lines: Vec<&str> = text.lines().collect();
    assert!(
        lines[0].starts_with("run `round` complete: 10.00 s simulated in 3 min 7 s (10000 steps, 3.123 Newton iterations per step, 2946 DOFs)"),
        "{}",
        lines[0]
    );
    let expect = [
        "  terminal velocity  -6.123 m/s ± 0.001235 m/s (mean and std of vz over the final 2.000 s)",
        "  reached            yes",
        "  time to terminal   3.220 s",
        "  drag area C_D·A    4.765 m²",
        "  extended height    1.500 m at the end, 1.988 m at most",
        "  force balance      |drag_z − W|/W = 0.2653 % (drag_z 108.9 N, W 109.2 N: the load and lines 100.0 N and the canopy 9.200 N)",
    ];
    assert_eq!(&lines[2..8], &expect, "{text}");
    let rest = lines[8..].join("\n");
    assert!(
        rest.contains("warnings:\n  something to know\n"),
        "warnings as plain lines: {rest}"
    );
    assert!(
        rest.contains("  frames/ (1 files)\n  summary.json\n  viewer.html"),
        "{rest}"
    );
    assert!(!rest.contains(".hidden"), "{rest}");
    assert!(rest.contains("viewer.html in a browser"), "{rest}");
}

#[test]
fn not_reached_says_why() {
    let mut s = summary();
    s.reached_terminal = false;
    s.time_to_terminal_s = None;
    s.terminal_velocity_std_mps = 0.3;
    s.terminal_velocity_trend_mps = -0.02;
    let why = not_reached_reason(&s).unwrap();
    assert_eq!(
        why,
        "vz still changing: std 4.899 %, trend 0.3266 % of |v_t| (limit 1 %)"
    );
    let rows = key_results(&s);
    assert_eq!(rows[1].1, format!("no: {why}"));
    assert_eq!(rows[2].1, "–");
    s.terminal_velocity_std_mps = 0.001;
    assert!(not_reached_reason(&s)
        .unwrap()
        .contains("leaves the ±2 % band"));
    s.warnings = vec!["run too short to judge terminal velocity: 3 samples".into()];
    assert!(not_reached_reason(&s).unwrap().starts_with("run too short"));
    s.complete = false;
    assert!(not_reached_reason(&s)
        .unwrap()
        .starts_with("the run stopped early; run too short"));
    s.warnings.clear();
    s.terminal_velocity_mps = 0.5;
    assert!(not_reached_reason(&s).unwrap().contains("not descending"));
    assert_eq!(not_reached_reason(&summary()), None);
}

#[test]
fn durations_read_like_a_clock() {
    assert_eq!(human_duration(0.012345), "0.01235 s");
    assert_eq!(human_duration(12.345), "12.35 s");
    assert_eq!(human_duration(187.4), "3 min 7 s");
    assert_eq!(human_duration(7505.0), "2 h 5 min");
}

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// A short coarse rod run (~0.1 s of wall time) into `dir/out` with extra arguments, which
/// must succeed (exit 0).
fn rod_run(dir: &Path, extra: &[&str]) -> Output {
    let o = crate::common::chute_command()
        .arg("run")
        .arg(repo().join("scenarios/report-rod-200n.toml"))
        .arg("--out")
        .arg(dir.join("out"))
        .args(["--set", "canopy.nodes=21", "--set", "time.duration_s=0.1"])
        .args(["--set", "output.snapshots_s=[0.05, 5.0, 6.0, 7.0]"])
        .args(extra)
        .output()
        .unwrap();
    assert_exit(&o, 0);
    o
}

#[test]
fn json_prints_summary_json_and_nothing_else_on_stdout() {
    let dir = tempfile::tempdir().unwrap();
    let o = rod_run(dir.path(), &["--json"]);
    let file = std::fs::read(dir.path().join("out/summary.json")).unwrap();
    assert_eq!(o.stdout, file, "stdout is summary.json byte for byte");
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["scenario_name"], "report-rod-200n");
    // One warning for the three snapshots the 0.1 s run never reached.
    let warnings: Vec<String> = serde_json::from_value(v["warnings"].clone()).unwrap();
    let snaps: Vec<&String> = warnings.iter().filter(|w| w.contains("snapshot")).collect();
    assert_eq!(snaps.len(), 1, "{warnings:?}");
    assert!(
        snaps[0].starts_with("snapshots at 5 s, 6 s, 7 s not drawn: the run ended at 0.1"),
        "{}",
        snaps[0]
    );
    assert!(dir.path().join("out/snapshot_0.05s.png").is_file());
    assert!(dir.path().join("out/viewer.html").is_file());
}

#[test]
fn default_output_is_for_people_and_quiet_is_quiet() {
    let dir = tempfile::tempdir().unwrap();
    let o = rod_run(dir.path(), &["--no-viewer"]);
    let text = String::from_utf8(o.stdout).unwrap();
    assert!(
        text.starts_with("run `report-rod-200n` complete: 0.1000 s simulated"),
        "{text}"
    );
    assert_contains(&text, &["\n  terminal velocity  ", " m/s ± "]);
    assert!(
        text.contains("\nwarnings:\n  snapshots at 5 s, 6 s, 7 s not drawn"),
        "{text}"
    );
    assert!(!text.contains("viewer.html"), "--no-viewer: {text}");
    assert!(!dir.path().join("out/viewer.html").exists());
    let o = rod_run(dir.path(), &["--force", "-q"]);
    assert!(
        o.stdout.is_empty(),
        "{}",
        String::from_utf8_lossy(&o.stdout)
    );
    assert!(dir.path().join("out/viewer.html").is_file());
}

#[test]
fn a_summary_without_metrics_reads_back_and_prints_dashes() {
    let mut s = summary();
    s.terminal_velocity_mps = f64::NAN;
    s.terminal_velocity_std_mps = f64::NAN;
    s.max_extended_height_m = f64::NAN;
    s.force_balance_error = f64::NAN;
    s.horizontal_velocity_mps = [f64::NAN; 2];
    s.reached_terminal = false;
    s.time_to_terminal_s = None;
    s.drag_area_m2 = None;
    s.warnings = vec!["metrics unavailable: the time series is empty".into()];
    let json = s.to_json();
    assert!(json.contains("\"terminal_velocity_mps\": null"), "{json}");
    let back: Summary = serde_json::from_str(&json).expect("nulls read back as NaN");
    assert!(back.terminal_velocity_mps.is_nan() && back.horizontal_velocity_mps[1].is_nan());
    assert_eq!(back.total_weight_n, 109.2);
    let rows = key_results(&back);
    assert_eq!(rows[0].1, "– (not computed: see the warnings)");
    assert_eq!(
        rows[1].1,
        "no: the metrics could not be computed (see the warnings)"
    );
    assert_eq!(rows[4].1, "1.500 m at the end, – at most");
    assert!(
        rows[5].1.starts_with("|drag_z − W|/W = – (drag_z 108.9 N"),
        "{}",
        rows[5].1
    );
}

/// A sensor pull is a key result: its firing, or that it did not fire.
#[test]
fn sensor_pulls_are_key_results() {
    let mut s = summary();
    let fired = chute::control::TriggerRecord {
        control: 0,
        sensor: "altimeter".into(),
        below_m: 0.8,
        reading_time_s: Some(6.62),
        reading_m: Some(0.7912),
        pull_start_s: Some(6.64),
    };
    let idle = chute::control::TriggerRecord {
        control: 1,
        reading_time_s: None,
        reading_m: None,
        pull_start_s: None,
        ..fired.clone()
    };
    s.triggers = vec![fired, idle];
    let rows = key_results(&s);
    let pulls: Vec<&String> = rows
        .iter()
        .filter(|(k, _)| *k == "sensor pull")
        .map(|(_, v)| v)
        .collect();
    assert_eq!(
        pulls,
        [
            "control[0] (sensor `altimeter`, ≤ 0.8000 m): fired by the reading 0.7912 m at 6.620 s; ramp from 6.640 s",
            "control[1] (sensor `altimeter`, ≤ 0.8000 m): did not fire",
        ]
    );
}

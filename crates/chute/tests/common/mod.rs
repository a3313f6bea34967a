//! Helpers shared by the test crates: the `chute` binary, the repository, small scenarios,
//! test-only forces, directory diffs. Each test crate uses a part of them.
#![allow(dead_code)]
pub mod image;
pub mod mutate;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;

use chute::scenario::Scenario;
use engine::{EvalInput, Force, JacobianKind, LocalBlocks};

/// The repository root (absolute).
pub fn repo() -> PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    root.canonicalize().unwrap_or(root)
}

/// The `chute` binary as a command, without the SLURM array variables of the environment
/// (they would select a study shard).
pub fn chute_command() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_chute"));
    c.env_remove("SLURM_ARRAY_TASK_ID")
        .env_remove("SLURM_ARRAY_TASK_COUNT");
    c
}

/// Run `chute ARGS` in `cwd` and wait for it.
pub fn chute(cwd: &Path, args: &[&str]) -> Output {
    chute_command()
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("binary runs")
}

/// [`chute`], which must succeed (exit status 0).
pub fn chute_ok(cwd: &Path, args: &[&str]) -> Output {
    let o = chute(cwd, args);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    o
}

/// [`chute`], failing the test instead of hanging when it has not ended within `secs` (a
/// command that would wait forever, on a FIFO say, must not stall the suite).
pub fn chute_within(cwd: &Path, args: &[&str], secs: u64) -> Output {
    let mut c = chute_command();
    c.args(args).current_dir(cwd);
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(c.output().expect("binary runs"));
    });
    rx.recv_timeout(std::time::Duration::from_secs(secs))
        .unwrap_or_else(|_| panic!("`chute {}` still runs after {secs} s", args.join(" ")))
}

/// Run the system tool `program ARGS` in `cwd` (`cp -al`, `mkfifo`) and check it succeeded.
pub fn tool(cwd: &Path, program: &str, args: &[&std::ffi::OsStr]) {
    let s = Command::new(program)
        .args(args)
        .current_dir(cwd)
        .status()
        .unwrap_or_else(|e| panic!("{program}: {e}"));
    assert!(s.success(), "{program} {args:?}: {s}");
}

/// The process's stderr as text.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The process's stdout as text.
pub fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// Assert that `o` exited with `code`, showing its stderr otherwise.
pub fn assert_exit(o: &Output, code: i32) {
    assert_eq!(o.status.code(), Some(code), "{}", stderr(o));
}

/// Assert that `o` exited with `code` and that its stderr contains every one of `want`.
pub fn assert_exit_says(o: &Output, code: i32, want: &[&str]) {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(code), "{err}");
    for w in want {
        assert!(err.contains(w), "want `{w}` in: {err}");
    }
}

/// Assert that `o` was refused (exit status 2) with every one of `want` in its stderr.
pub fn assert_refused(o: &Output, want: &[&str]) {
    assert_exit_says(o, 2, want);
}

/// The path of the bundled scenario `scenarios/NAME`, as text.
pub fn bundled(name: &str) -> String {
    repo().join("scenarios").join(name).display().to_string()
}

/// The path of the report's rod (`scenarios/report-rod-200n.toml`), as text.
pub fn rod_file() -> String {
    bundled("report-rod-200n.toml")
}

/// `chute SUB scenarios/NAME ARGS…` in `cwd`: a subcommand of a bundled scenario.
pub fn chute_bundled(cwd: &Path, sub: &str, name: &str, args: &[&str]) -> Output {
    let path = bundled(name);
    chute(cwd, &[&[sub, path.as_str()][..], args].concat())
}

/// `chute check scenarios/NAME --set S…` (one `--set` for each of `sets`) in a fresh
/// directory.
pub fn check_bundled(name: &str, sets: &[&str]) -> Output {
    let tmp = tempfile::tempdir().unwrap();
    let args: Vec<&str> = sets.iter().flat_map(|s| ["--set", s]).collect();
    chute_bundled(tmp.path(), "check", name, &args)
}

/// The JSON file at `path` (a run's `summary.json` or record, say), which must be there.
pub fn read_json(path: impl AsRef<Path>) -> serde_json::Value {
    let path = path.as_ref();
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{path:?}: {e}"))
}

/// Assert that `text` contains every one of `want`.
pub fn assert_contains(text: &str, want: &[&str]) {
    for w in want {
        assert!(text.contains(w), "want `{w}` in: {text}");
    }
}

/// How many of `lines` (the warnings of a summary, say) contain `needle`.
pub fn count_containing(lines: &[String], needle: &str) -> usize {
    lines.iter().filter(|l| l.contains(needle)).count()
}

/// The first of `lines` (the warnings of a summary, say) that contains `needle`; there must be one.
pub fn find_containing<'a>(lines: &'a [String], needle: &str) -> &'a str {
    let found = lines.iter().find(|l| l.contains(needle));
    found.unwrap_or_else(|| panic!("no `{needle}` in {lines:?}"))
}

/// Assert that the stderr of `o` contains none of `unwanted`.
pub fn assert_stderr_lacks(o: &Output, unwanted: &[&str]) {
    let err = stderr(o);
    for u in unwanted {
        assert!(!err.contains(u), "`{u}` in: {err}");
    }
}

/// The rod strip of the report, coarse (21 nodes) and short: ~0.3 s of wall time per 0.1 s.
pub fn rod(duration: f64, extra: &[&str]) -> Scenario {
    let mut sets = vec![
        "canopy.nodes=21".to_string(),
        format!("time.duration_s={duration}"),
        "output.snapshots_s=[0.05, 0.3]".to_string(),
    ];
    sets.extend(extra.iter().map(|s| s.to_string()));
    Scenario::load(&repo().join("scenarios/report-rod-200n.toml"), &sets).unwrap()
}

/// A 3 m square canopy on four corner lines, coarse (0.5 m edges): the symmetric payload
/// case of the line-pull tests (lines 0 (−x, −y), 1 (+x, −y), 2 (+x, +y), 3 (−x, +y)).
pub const SQUARE_ON_CORNERS: [&str; 5] = [
    "canopy.shape=rectangle",
    "canopy.span_m=3",
    "canopy.width_m=3",
    "canopy.edge_length_m=0.5",
    "load.sites=corners",
];

/// `round-parachute.toml` made to fail part-way (exit 3): 0.5 m edges, six of its lines
/// shortened by 2 m in one step at t = 0.2 s, one iteration per stage, no rescue stages and
/// the strict force tolerance (so neither the accuracy test nor a Krylov-corrected first
/// update can accept the step). The step change of the lines' rest length is a jump the step
/// size cannot shrink, so the step at the pull is solved at no size (measured: stops at
/// t = 0.2 s, with frames, a snapshot and a checkpoint before it).
pub const FAILING_PULL_SETS: [&str; 12] = [
    "--set",
    "canopy.edge_length_m=0.5",
    "--set",
    "control=[{lines = [0, 1, 2, 3, 4, 5], start_s = 0.2, shorten_m = 2.0}]",
    "--set",
    "time.newton_max_iterations=1",
    "--set",
    "time.newton_rescue_stages=false",
    "--set",
    "time.newton_strict=true",
    "--set",
    "output.snapshots_s=[0.1]",
];

/// The bundled round parachute (`scenarios/round-parachute.toml`).
pub fn round_file() -> String {
    repo()
        .join("scenarios/round-parachute.toml")
        .display()
        .to_string()
}

/// Run `s` into `dir` and require it complete: the model at the end and `summary.json`.
pub fn run_complete(s: &Scenario, dir: &Path) -> (chute::build::Built, serde_json::Value) {
    let mut b = chute::build::build(s).unwrap();
    let cfg = chute::app::run_config(s, false);
    let r = chute::runner::simulate(&mut b, &cfg, dir, &AtomicBool::new(false)).unwrap();
    assert!(r.complete, "{:?}", r.stop_reason);
    let text = std::fs::read_to_string(dir.join("summary.json")).unwrap();
    (b, serde_json::from_str(&text).unwrap())
}

/// A coarse shell canopy (the report's springs + hinges, triangle drag) for the same checks
/// on the other model.
pub fn shell(duration: f64) -> Scenario {
    let mut sets: Vec<String> = chute::scenario::REPORT_SHELL_MODEL
        .iter()
        .map(|s| s.to_string())
        .collect();
    sets.extend([
        "canopy.edge_length_m=1".to_string(),
        format!("time.duration_s={duration}"),
        "output.snapshots_s=[0.05]".to_string(),
    ]);
    Scenario::load(&repo().join("scenarios/report-shell-4-sites.toml"), &sets).unwrap()
}

/// A test-only force acting on one DOF. It is zero (so it leaves every result unchanged)
/// except that, once the trial time reaches `at_s`:
/// - it sets `stop` (a deterministic stand-in for Ctrl-C), and
/// - its first `nan_evals` evaluations from then on return NaN, whatever the time of later
///   trials (a blow-up that persists while the run loop retries with smaller steps).
pub struct Trigger {
    dof: [usize; 1],
    pub at_s: f64,
    pub stop: Arc<AtomicBool>,
    pub set_stop: bool,
    pub nan_evals: usize,
    pub evals_after: Arc<AtomicUsize>,
    triggered: AtomicBool,
}

impl Trigger {
    pub fn new(dof: usize, at_s: f64) -> Self {
        Self {
            dof: [dof],
            at_s,
            stop: Arc::new(AtomicBool::new(false)),
            set_stop: false,
            nan_evals: 0,
            evals_after: Arc::new(AtomicUsize::new(0)),
            triggered: AtomicBool::new(false),
        }
    }
}

impl Force for Trigger {
    fn name(&self) -> &str {
        "test-trigger"
    }
    fn stencil_size(&self) -> usize {
        1
    }
    fn stencils(&self) -> &[usize] {
        &self.dof
    }
    fn jacobian_kind(&self) -> JacobianKind {
        JacobianKind::CONSTANT
    }
    fn evaluate(&self, input: &EvalInput<'_>, out: &mut LocalBlocks) {
        out.f[0] = 0.0;
        if input.t >= self.at_s {
            self.triggered.store(true, Ordering::SeqCst);
            if self.set_stop {
                self.stop.store(true, Ordering::SeqCst);
            }
        }
        if self.triggered.load(Ordering::SeqCst)
            && self.evals_after.fetch_add(1, Ordering::SeqCst) < self.nan_evals
        {
            out.f[0] = f64::NAN;
        }
    }
}

/// Run `act` and assert that it left every file under `dir` as it was (names and bytes).
pub fn assert_untouched(dir: &Path, act: impl FnOnce()) {
    let before = files(dir);
    act();
    assert!(before == files(dir), "{dir:?} was changed");
}

/// A new temporary directory holding each `(name, text)` of `files`.
pub fn tmp_with_files(files: &[(&str, &str)]) -> tempfile::TempDir {
    let tmp = tempfile::tempdir().unwrap();
    for (name, text) in files {
        std::fs::write(tmp.path().join(name), text).unwrap();
    }
    tmp
}

/// Every file under `dir`, by relative path.
pub fn files(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    fn walk(root: &Path, d: &Path, out: &mut BTreeMap<String, Vec<u8>>) {
        for e in std::fs::read_dir(d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                walk(root, &p, out);
            } else {
                let rel = p.strip_prefix(root).unwrap().to_string_lossy().into_owned();
                out.insert(rel, std::fs::read(&p).unwrap());
            }
        }
    }
    let mut out = BTreeMap::new();
    walk(dir, dir, &mut out);
    out
}

/// Assert that two run directories hold the same files with the same bytes, except the wall
/// time in `summary.json` (it measures the machine, not the run), the study case in
/// `run.json` and `checkpoint.bin`.
pub fn assert_same_outputs(a: &Path, b: &Path) {
    let strip = |name: &str, bytes: &[u8]| -> Vec<u8> {
        if name == "run.json" {
            // The study case a run was made for (a run of its own has none).
            let mut j: serde_json::Value = serde_json::from_slice(bytes).unwrap();
            j.as_object_mut().unwrap().remove("case_of");
            return j.to_string().into_bytes();
        }
        if name != "summary.json" {
            return bytes.to_vec();
        }
        String::from_utf8_lossy(bytes)
            .lines()
            .filter(|l| !WALL_TIMES.iter().any(|w| l.contains(&format!("\"{w}\""))))
            .collect::<Vec<_>>()
            .join("\n")
            .into_bytes()
    };
    let skip = |k: &String| k != "checkpoint.bin" && k != "done.json";
    let fa = files(a);
    let fb = files(b);
    let ka: Vec<&String> = fa.keys().filter(|k| skip(k)).collect();
    let kb: Vec<&String> = fb.keys().filter(|k| skip(k)).collect();
    assert_eq!(ka, kb, "different file sets in {a:?} and {b:?}");
    assert!(ka.iter().any(|k| k.ends_with(".vtu")), "no frames written");
    for k in ka {
        assert!(
            strip(k, &fa[k]) == strip(k, &fb[k]),
            "{k} differs between {a:?} and {b:?}"
        );
    }
}

/// Data rows of a `timeseries.csv` (header checked).
pub fn csv_rows(path: &Path) -> Vec<Vec<f64>> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    assert!(lines.next().unwrap().starts_with("t_s,"));
    assert!(text.ends_with('\n'), "a partial row at the end of {path:?}");
    lines
        .map(|l| l.split(',').map(|x| x.parse::<f64>().unwrap()).collect())
        .collect()
}

/// The wall times of `summary.json` (at the top level and in `solver`): the only values
/// that differ between runs of the same scenario.
pub const WALL_TIMES: [&str; 4] = ["wall_time_s", "assembly_s", "factor_s", "solve_s"];

/// `summary.json` as JSON without its wall times ([`WALL_TIMES`]).
pub fn without_wall_times(mut j: serde_json::Value) -> serde_json::Value {
    j.as_object_mut().unwrap().remove("wall_time_s");
    if let Some(solver) = j["solver"].as_object_mut() {
        WALL_TIMES[1..].iter().for_each(|w| {
            solver.remove(*w).expect("a solver time");
        });
    }
    j
}

/// Every field of the `solver` object of `summary.json` (docs/outputs.md §solver).
pub const SOLVER_FIELDS: [&str; 26] = [
    "assembly_s",
    "factor_s",
    "solve_s",
    "evaluations",
    "jacobian_evaluations",
    "factorizations",
    "indefinite_factorizations",
    "iterations",
    "solves",
    "krylov_iterations",
    "krylov_failures",
    "line_search_points",
    "held",
    "newton",
    "continuation",
    "homotopy",
    "stages_skipped",
    "accuracy_accepts",
    "roundoff_accepts",
    "noise_probes",
    "error_filters",
    "error_filter_fallbacks",
    "bounded_moves",
    "path_rejects",
    "pattern_rebuilds",
    "pattern_s",
];

/// Every field documented in docs/outputs.md §summary.json.
pub const SUMMARY_FIELDS: [&str; 57] = [
    "summary_version",
    "scenario_name",
    "complete",
    "stop_reason",
    "simulated_time_s",
    "terminal_velocity_mps",
    "terminal_velocity_std_mps",
    "terminal_velocity_trend_mps",
    "reached_terminal",
    "time_to_terminal_s",
    "final_window_start_s",
    "max_extended_height_m",
    "final_extended_height_m",
    "total_weight_n",
    "canopy_weight_n",
    "mean_drag_z_n",
    "drag_area_m2",
    "force_balance_error",
    "horizontal_velocity_mps",
    "glide_angle_deg",
    "reynolds_number",
    "canopy_loading_pa",
    "terminal_dynamic_pressure_pa",
    "drag_coefficient_nominal",
    "settling_time_s",
    "equivalent_sea_level_descent_mps",
    "altitude_m",
    "peak_line_tension_n",
    "time_of_peak_line_tension_s",
    "load_factor",
    "peak_payload_acceleration_g",
    "oscillation_angle_deg",
    "landing_velocity_mps",
    "flight_time_s",
    "landing_point_m",
    "drift_m",
    "landing_miss_m",
    "opening_peak_force_n",
    "opening_load_factor",
    "opening_fill_time_s",
    "opening_fill_distance_diameters",
    "steps",
    "newton_iterations",
    "wall_time_s",
    "dofs",
    "dt_s",
    "adaptive",
    "error_tolerance_m",
    "dt_min_s",
    "dt_max_s",
    "rejected_steps_error",
    "rejected_steps_newton",
    "dt_used_min_s",
    "dt_used_mean_s",
    "dt_used_max_s",
    "solver",
    "warnings",
];

/// The DisMech hexagonal parachute as a project of its own in `dir`: `hex.toml` reading
/// `mesh.txt` beside it (a copy of the bundled mesh), so that tests can move or edit both.
pub fn hex_project(dir: &Path) {
    let mesh = repo().join("crates/chute/data/meshes/hexparachute_n6_python.txt");
    std::fs::copy(&mesh, dir.join("mesh.txt")).unwrap();
    let scenario = std::fs::read_to_string(repo().join("scenarios/dismech-hex-n6.toml"))
        .unwrap()
        .replace(
            "../crates/chute/data/meshes/hexparachute_n6_python.txt",
            "mesh.txt",
        );
    std::fs::write(dir.join("hex.toml"), scenario).unwrap();
}

/// Make the run record in `dir` say its run read other bytes of its first input file (as a
/// run started after the file was edited would).
pub fn forge_input_digest(dir: &Path) {
    let record = dir.join("run.json");
    let mut r = read_json(&record);
    r["inputs"][0]["digest"] = "fnv1a64:0123456789abcdef".into();
    std::fs::write(&record, r.to_string()).unwrap();
}

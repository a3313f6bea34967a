//! `chute bench`: timings of implicit-Euler steps on a ladder of model sizes.
//!
//! Cases (see [`ladder`]): DER rods of 100, 1k, 10k nodes (the report's Kevlar strip), the
//! report's rectangular shell canopy at ≈ 250, 1k, 4k, 16k and 33k nodes (≈ 100k DOFs), and
//! the DisMech peer's hexagonal parachutes `dismech-hex-n6` / `dismech-hex-n12`.
//!
//! Every case runs in its own child process (this executable re-run as `chute bench --case
//! <name>` with the same experiment options), so its peak resident memory (`VmHWM` of
//! `/proc/self/status`) is its own and not the high-water mark of a larger case run earlier.
//! The child builds the model, takes `warmup` untimed steps, zeroes the stepper's
//! [`engine::Counters`], then times `steps` steps and prints one JSON object. Steps are taken
//! as a run takes them ([`crate::runner::Driver`]): a failed Newton solve halves the step.
//!
//! Why a warm-up: a canopy released flat and at rest first falls almost rigidly, so the
//! constant-velocity predictor nearly solves the first steps and they cost one cheap Newton
//! iteration each; timing them would flatter the solver. After the warm-up the loads have
//! bent the canopy and drag has built up, which is the regime of most of a flight. The
//! peer-comparison cases instead time the peer's whole run (300 steps of 1e-2 s from rest,
//! no warm-up), which is exactly what the peer's per-step figure averages over.
//!
//! The options besides `--quick`, `--json`, `--plot`, `--set` and `--case` are hidden: the
//! test ladder (`--tiny`), diagnostics (`--mem`, `--trace`) and the Newton experiment knobs
//! for A/B comparisons ([`NewtonExperiment`]); docs/performance.md lists them.

pub mod contact;
pub mod elements;
pub mod fabric;
pub mod flight;
pub mod plot;
mod table;

pub use table::peak_rss_mib;
use table::{header, row, rss_mib};

use std::path::PathBuf;
use std::time::Instant;

use serde::{Deserialize, Serialize};

use crate::app::AppError;
use crate::scenario::{Scenario, REPORT_SHELL_MODEL};

/// `chute bench`.
#[derive(Debug, Clone, Default, PartialEq, clap::Args)]
pub struct BenchArgs {
    /// Fewer and smaller sizes.
    #[arg(long)]
    pub quick: bool,
    /// Print the timings as JSON.
    #[arg(long)]
    pub json: bool,
    /// Also draw the scaling plot (ms per Newton iteration against DOFs) to this PNG.
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
    /// Override a scenario key in every case (repeatable), e.g. a Newton tolerance.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Run only this case, in this process, and print its JSON object (what the child
    /// process of each case does; e.g. to profile one case).
    #[arg(long, value_name = "NAME")]
    pub case: Option<String>,
    /// Three small cases of a few steps (the CLI test's ladder).
    #[arg(long, hide = true)]
    pub tiny: bool,
    /// Instead of the ladder: the cost of one element of each shell membrane and bending
    /// law, per element and relative to springs / hinges (docs/performance.md).
    #[arg(long)]
    pub elements: bool,
    /// Instead of the ladder: what self-contact costs on the `opening` scenario at three
    /// meshes, at its peak force (docs/opening.md §Cost).
    #[arg(long, conflicts_with = "elements")]
    pub contact: bool,
    /// Resident memory after each stage, and the stepper's counters, on stderr.
    #[arg(long, hide = true)]
    pub mem: bool,
    /// Every step attempt and its Newton residual history on stderr.
    #[arg(long, hide = true)]
    pub trace: bool,
    /// Time this many steps instead of the case's own count (a shorter `flight-1k` for
    /// quick A/B iterations).
    #[arg(long, hide = true, value_name = "N")]
    pub steps: Option<usize>,
    /// Advance to this time (s), then print the solver's unit costs there and stop.
    #[arg(long, hide = true, value_name = "T")]
    pub units: Option<f64>,
    /// Newton experiment knobs.
    #[command(flatten)]
    pub newton: NewtonExperiment,
}

/// Changes to the run's solver settings, for A/B experiments (hidden flags of `chute bench`).
#[derive(Debug, Clone, Default, PartialEq, clap::Args)]
pub struct NewtonExperiment {
    /// Plain Newton: no held stage, a fresh Jacobian at every iteration.
    #[arg(long, hide = true)]
    pub no_reuse: bool,
    /// No held stage (factors are still kept within a step by modified Newton).
    #[arg(long, hide = true)]
    pub no_held: bool,
    /// No line search in the Newton stage.
    #[arg(long, hide = true)]
    pub no_line_search: bool,
    /// Contraction factor up to which the Newton stage keeps its factors.
    #[arg(long, hide = true, value_name = "C")]
    pub contraction: Option<f64>,
    /// Anderson depth of the held stage (0: the chord iteration).
    #[arg(long, hide = true, value_name = "M")]
    pub anderson: Option<usize>,
    /// Iterations of the held stage.
    #[arg(long, hide = true, value_name = "N")]
    pub held_iterations: Option<usize>,
    /// The predictor of the first Newton iterate.
    #[arg(long, hide = true, value_enum)]
    pub predictor: Option<PredictorChoice>,
    /// Factors in single (`single`) or double (`double`) precision.
    #[arg(long, hide = true, value_name = "P")]
    pub factors: Option<String>,
}

/// `--predictor`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum PredictorChoice {
    /// [`engine::Predictor::ConstantVelocity`].
    Velocity,
    /// [`engine::Predictor::ConstantAcceleration`].
    Acceleration,
    /// [`engine::Predictor::ConstantJerk`].
    Jerk,
    /// [`engine::Predictor::Adaptive`].
    Adaptive,
}

impl NewtonExperiment {
    /// Apply the knobs to the run's settings.
    pub fn apply(&self, n: &mut engine::NewtonOptions) {
        if self.no_reuse {
            n.hold_factors = false;
            n.reuse_contraction = 0.0;
        }
        if self.no_held {
            n.hold_factors = false;
        }
        if self.no_line_search {
            n.line_search = false;
        }
        if let Some(c) = self.contraction {
            n.reuse_contraction = c;
        }
        if let Some(m) = self.anderson {
            n.anderson_depth = m;
        }
        if let Some(k) = self.held_iterations {
            n.held_iterations = k;
        }
        if let Some(p) = &self.factors {
            n.single_precision_factors = p == "single";
        }
        if let Some(p) = self.predictor {
            n.predictor = match p {
                PredictorChoice::Velocity => engine::Predictor::ConstantVelocity,
                PredictorChoice::Acceleration => engine::Predictor::ConstantAcceleration,
                PredictorChoice::Jerk => engine::Predictor::ConstantJerk,
                PredictorChoice::Adaptive => engine::Predictor::Adaptive,
            };
        }
    }

    /// The same knobs as command-line arguments (for a case's child process).
    fn args(&self) -> Vec<String> {
        let mut a: Vec<String> = [
            (self.no_reuse, "--no-reuse"),
            (self.no_held, "--no-held"),
            (self.no_line_search, "--no-line-search"),
        ]
        .iter()
        .filter(|(on, _)| *on)
        .map(|(_, flag)| flag.to_string())
        .collect();
        let mut opt = |flag: &str, v: Option<String>| {
            if let Some(v) = v {
                a.extend([flag.to_string(), v]);
            }
        };
        opt("--contraction", self.contraction.map(|c| c.to_string()));
        opt("--anderson", self.anderson.map(|c| c.to_string()));
        opt(
            "--held-iterations",
            self.held_iterations.map(|c| c.to_string()),
        );
        opt(
            "--predictor",
            self.predictor.map(|p| {
                match p {
                    PredictorChoice::Velocity => "velocity",
                    PredictorChoice::Acceleration => "acceleration",
                    PredictorChoice::Jerk => "jerk",
                    PredictorChoice::Adaptive => "adaptive",
                }
                .to_string()
            }),
        );
        a
    }
}

impl BenchArgs {
    /// The arguments of the child process that runs case `name` with these options.
    fn child_args(&self, name: &str) -> Vec<String> {
        let mut a = vec!["bench".to_string(), "--case".into(), name.into()];
        let flags = [
            (self.quick, "--quick"),
            (self.tiny, "--tiny"),
            (self.mem, "--mem"),
            (self.trace, "--trace"),
        ];
        a.extend(flags.iter().filter(|f| f.0).map(|f| f.1.to_string()));
        if let Some(n) = self.steps {
            a.extend(["--steps".into(), n.to_string()]);
        }
        for kv in &self.set {
            a.extend(["--set".into(), kv.clone()]);
        }
        a.extend(self.newton.args());
        a
    }
}

const SHELL: &str = include_str!("../../../scenarios/report-shell-4-sites.toml");
const SHELL_PATH: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../scenarios/report-shell-4-sites.toml"
);
const ROD: &str = include_str!("../../../scenarios/report-rod-200n.toml");
const ROD_PATH: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../scenarios/report-rod-200n.toml"
);
const ROUND: &str = include_str!("../../../scenarios/round-fabric.toml");
const ROUND_PATH: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../scenarios/round-fabric.toml"
);
const HEX: &str = include_str!("../../../scenarios/dismech-hex-n6.toml");
/// The hexagonal scenario's `mesh_file` is relative to its own directory, so it is parsed
/// under its real path (this binary's source tree).
const HEX_PATH: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../scenarios/dismech-hex-n6.toml"
);

/// One rung of the ladder.
#[derive(Debug, Clone)]
pub struct Case {
    /// Name (the hexagonal cases contain `n6` / `n12`).
    pub name: String,
    /// Which bundled scenario: `"rod"`, `"shell"`, `"main"`, `"round"` or `"hex"`.
    pub base: &'static str,
    /// `--set` overrides applied to it.
    pub overrides: Vec<String>,
    /// Untimed steps first.
    pub warmup: usize,
    /// Timed steps.
    pub steps: usize,
}

fn case(name: &str, base: &'static str, ov: &[&str], warmup: usize, steps: usize) -> Case {
    Case {
        name: name.into(),
        base,
        overrides: ov.iter().map(|s| s.to_string()).collect(),
        warmup,
        steps,
    }
}

/// The cases of a run, small to large. `tiny` is the CLI test's ladder.
pub fn ladder(quick: bool, tiny: bool) -> Vec<Case> {
    let n12 = "canopy.mesh_file=../crates/chute/data/meshes/hexparachute_n12.txt";
    if tiny {
        return vec![
            case("rod-100", "rod", &["canopy.nodes=100"], 2, 3),
            case("shell-250", "shell", &["canopy.edge_length_m=0.28"], 2, 3),
            case("dismech-hex-n6", "hex", &[], 0, 3),
        ];
    }
    let mut v = vec![
        case("rod-100", "rod", &["canopy.nodes=100"], 50, 500),
        case("rod-1k", "rod", &["canopy.nodes=1000"], 50, 200),
        case(
            "shell-250",
            "shell",
            &["canopy.edge_length_m=0.28"],
            50,
            500,
        ),
        case(
            "shell-1k",
            "shell",
            &["canopy.edge_length_m=0.138"],
            50,
            200,
        ),
        case("dismech-hex-n6", "hex", &[], 0, 300),
        case("dismech-hex-n12", "hex", &[n12], 0, 300),
        // shell-1k with mid-edge bending (the cost of the converged shell's bending law).
        case(
            "shell-1k-midedge",
            "shell",
            &["canopy.edge_length_m=0.138", "shell.bending=midedge"],
            50,
            200,
        ),
    ];
    v.extend(fabric::cases());
    v.push(flight::cross());
    if !quick {
        v.extend([
            case("main-job", "main", &[], 0, 2500),
            flight::flight(),
            case("rod-10k", "rod", &["canopy.nodes=10000"], 20, 50),
            case(
                "shell-4k",
                "shell",
                &["canopy.edge_length_m=0.068"],
                50,
                100,
            ),
            case(
                "shell-16k",
                "shell",
                &["canopy.edge_length_m=0.034"],
                20,
                30,
            ),
            case(
                "shell-33k",
                "shell",
                &["canopy.edge_length_m=0.0235"],
                10,
                10,
            ),
        ]);
    }
    v
}

/// What one case measured. Shares are fractions of the timed wall time.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct CaseResult {
    /// Case name.
    pub name: String,
    /// Nodes of the model.
    pub nodes: usize,
    /// Degrees of freedom (3 per node + 1 per rod edge).
    pub dofs: usize,
    /// Free DOFs (the Newton system's size).
    pub free_dofs: usize,
    /// Stored nonzeros of the Jacobian (both triangles).
    pub nnz: usize,
    /// Time step (s).
    pub dt_s: f64,
    /// Timed steps.
    pub steps: usize,
    /// Wall time per step (ms).
    pub ms_per_step: f64,
    /// Newton iterations (linear solves) per step.
    pub newton_per_step: f64,
    /// Wall time per Newton iteration (ms).
    pub ms_per_newton: f64,
    /// Numeric factorisations per step (modified Newton reuses them).
    pub factorizations_per_step: f64,
    /// Residual evaluations (element passes) per step.
    pub evaluations_per_step: f64,
    /// Share in element evaluation + scatter.
    pub share_assembly: f64,
    /// Share in numeric factorisation.
    pub share_factor: f64,
    /// Share in triangular solves.
    pub share_solve: f64,
    /// Steps of the timed run whose Newton solve failed and that were retried with half the
    /// step, as in a run (their cost is included in `ms_per_step`, which stays per step of
    /// the nominal `dt`).
    pub halvings: usize,
    /// Peak resident memory of the case's process (MiB), model build included.
    pub peak_rss_mib: f64,
    /// Simulated time at the end of the timed run (s).
    pub t_end_s: f64,
    /// Mass-weighted mean vertical velocity of the model at the end of the timed run (m/s):
    /// the terminal velocity once the flight is long enough (`flight-1k`).
    #[serde(default)]
    pub vz_end_mps: f64,
    /// What the step solver did over the timed steps (stage runs, factorisations,
    /// evaluations, Krylov iterations …; docs/outputs.md §solver).
    pub counters: engine::Counters,
}

/// Mass-weighted mean vertical velocity of the nodes (m/s).
fn mean_vz(model: &engine::Model, v: &[f64]) -> f64 {
    let (mut p, mut m) = (0.0, 0.0);
    for i in 0..model.layout.n_nodes {
        let d = 3 * i + 2;
        p += model.mass[d] * v[d];
        m += model.mass[d];
    }
    p / m
}

/// Run the benchmark ladder, or with `--case` one case in this process.
pub fn main(args: &BenchArgs) -> Result<(), AppError> {
    if let Some(p) = &args.plot {
        plot::refuse_path(p)?;
    }
    if args.contact {
        let costs = contact::measure()?;
        if args.json {
            let text = serde_json::to_string_pretty(&costs).expect("serialisable");
            crate::out_line!("{text}");
        } else {
            crate::out_text!("{}", contact::table(&costs));
        }
        return Ok(());
    }
    if args.elements {
        let costs = elements::measure()?;
        if args.json {
            crate::out_line!(
                "{}",
                serde_json::to_string_pretty(&costs).expect("serialisable")
            );
        } else {
            crate::out_text!("{}", elements::table(&costs));
        }
        return Ok(());
    }
    let cases = ladder(args.quick, args.tiny);
    if let Some(name) = &args.case {
        let mut c = cases
            .iter()
            .chain(ladder(false, false).iter())
            .chain(std::iter::once(&flight::large_canopy()))
            .find(|c| &c.name == name)
            .cloned()
            .ok_or_else(|| AppError::Input(format!("no bench case `{name}`")))?;
        if let Some(n) = args.steps {
            c.steps = n;
        }
        let r = run_case(&c, args)?;
        crate::out_line!("{}", serde_json::to_string(&r).expect("serialisable"));
        return Ok(());
    }
    // Bad `--set` values are reported here, once, rather than by every child.
    for c in &cases {
        scenario_of(c, &args.set)?;
    }
    let exe = std::env::current_exe().map_err(|e| AppError::io("current_exe", e))?;
    let mut results = Vec::new();
    if !args.json {
        crate::out_line!("{}", header());
    }
    for (i, c) in cases.iter().enumerate() {
        // Progress on stderr: a --json run prints nothing else until the end.
        crate::err_line!("bench: case {} ({} of {}) …", c.name, i + 1, cases.len());
        let r = run_child(&exe, c, args)?;
        if !args.json {
            crate::out_line!("{}", row(&r));
        }
        results.push(r);
    }
    if !args.json {
        crate::out_line!("\n{}", table::LEGEND);
    }
    if args.json {
        crate::out_line!(
            "{}",
            serde_json::to_string_pretty(&results).expect("serialisable")
        );
    }
    if let Some(path) = &args.plot {
        plot::scaling_plot(path, &results)
            .map_err(|e| AppError::RunFailed(format!("plot: {e}")))?;
    }
    Ok(())
}

fn run_child(exe: &std::path::Path, c: &Case, args: &BenchArgs) -> Result<CaseResult, AppError> {
    let out = std::process::Command::new(exe)
        .args(args.child_args(&c.name))
        .stderr(std::process::Stdio::inherit())
        .output()
        .map_err(|e| AppError::io(exe, e))?;
    if !out.status.success() {
        return Err(AppError::RunFailed(format!(
            "bench case `{}` exited with {}",
            c.name, out.status
        )));
    }
    let text = String::from_utf8_lossy(&out.stdout);
    serde_json::from_str(text.trim())
        .map_err(|e| AppError::RunFailed(format!("bench case `{}`: bad output: {e}", c.name)))
}

/// The case's scenario with its own overrides, then `set` (the `--set` options). The shell
/// cases fly the report's model (springs + hinges, dt = 1 ms: [`REPORT_SHELL_MODEL`]), the
/// ladder's reference (docs/performance.md), whatever the bundled scenario ships.
fn scenario_of(c: &Case, set: &[String]) -> Result<Scenario, AppError> {
    let (text, path, model): (_, _, &[&str]) = match c.base {
        "rod" => (ROD, ROD_PATH, &[]),
        "shell" => (SHELL, SHELL_PATH, &REPORT_SHELL_MODEL),
        "main" => (SHELL, SHELL_PATH, &[]),
        "round" => (ROUND, ROUND_PATH, &[]),
        _ => (HEX, HEX_PATH, &[]),
    };
    let mut overrides: Vec<String> = model.iter().map(|s| s.to_string()).collect();
    overrides.extend(c.overrides.iter().cloned());
    overrides.extend(set.iter().cloned());
    Ok(Scenario::from_str_with_name(text, path, &overrides)?)
}

/// Build and time one case in this process.
pub fn run_case(c: &Case, args: &BenchArgs) -> Result<CaseResult, AppError> {
    let s = scenario_of(c, &args.set)?;
    let mut built = crate::build::build(&s)?;
    let mut cfg = crate::app::run_config(&s, false);
    args.newton.apply(&mut cfg.newton);
    let mem = |stage: &str| {
        if args.mem {
            crate::err_line!("{stage}: {}", rss_mib());
        }
    };
    mem("after build");
    let mut stepper = crate::runner::new_stepper(&built.model, &cfg)
        .map_err(|e| AppError::RunFailed(e.to_string()))?;
    if args.mem {
        let (l, s) = stepper.solver_memory_bytes();
        crate::err_line!(
            "after stepper: {} (L {} MiB, scratch {} MiB)",
            rss_mib(),
            l >> 20,
            s >> 20
        );
    }
    let dt = cfg.stepping.dt_s;
    let mut driver = crate::runner::Driver::new(&cfg)
        .map_err(|e| AppError::RunFailed(e.to_string()))?
        .with_trace(args.trace);
    let mut run = |b: &mut crate::build::Built, st: &mut engine::ImplicitEuler, n: usize| {
        let t_end = b.state.t + n as f64 * dt;
        driver
            .advance_to(st, b, t_end)
            .map_err(|e| AppError::RunFailed(format!("{}: t = {}: {e}", c.name, b.state.t)))
    };
    if c.warmup > 0 {
        run(&mut built, &mut stepper, 1)?;
        mem("after 1 step");
        run(&mut built, &mut stepper, c.warmup - 1)?;
    }
    if args.mem {
        crate::err_line!("after warm-up: {}\n{:?}", rss_mib(), stepper.counters());
    }
    if let Some(t) = args.units {
        driver
            .advance_to(&mut stepper, &mut built, t)
            .map_err(|e| AppError::RunFailed(format!("{e}")))?;
        let u = stepper.unit_costs(&built.model, &built.state, dt, 10);
        crate::err_line!("{u:#?}");
    }
    let failures_before = driver.newton_failures();
    stepper.reset_counters();
    let t0 = Instant::now();
    let t_end = built.state.t + c.steps as f64 * dt;
    driver
        .advance_to(&mut stepper, &mut built, t_end)
        .map_err(|e| AppError::RunFailed(format!("{}: t = {}: {e}", c.name, built.state.t)))?;
    let wall = t0.elapsed().as_secs_f64();
    let tm = *stepper.counters();
    if args.mem {
        crate::err_line!("timed: {tm:?}");
    }
    let n = c.steps.max(1) as f64;
    let share = |x: f64| if wall > 0.0 { x / wall } else { 0.0 };
    Ok(CaseResult {
        name: c.name.clone(),
        nodes: built.model.layout.n_nodes,
        dofs: built.model.n_dofs(),
        free_dofs: stepper.n_free(),
        nnz: stepper.nnz(),
        dt_s: dt,
        steps: c.steps,
        ms_per_step: 1e3 * wall / n,
        newton_per_step: tm.iterations as f64 / n,
        ms_per_newton: 1e3 * wall / (tm.iterations.max(1) as f64),
        factorizations_per_step: tm.factorizations as f64 / n,
        evaluations_per_step: tm.evaluations as f64 / n,
        share_assembly: share(tm.assembly_s),
        share_factor: share(tm.factor_s),
        share_solve: share(tm.solve_s),
        halvings: (driver.newton_failures() - failures_before) as usize,
        peak_rss_mib: peak_rss_mib(),
        t_end_s: built.state.t,
        vz_end_mps: mean_vz(&built.model, &built.state.v),
        counters: tm,
    })
}

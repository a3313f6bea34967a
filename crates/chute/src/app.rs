//! The interface between the command line and the simulation: `check` and `run` a scenario.
//! The other commands live in their own modules: [`crate::verify`] (`chute validate`), [`crate::bench`],
//! [`crate::study`].

use std::path::PathBuf;

use crate::scenario::{Scenario, ScenarioError};

/// How to run one scenario.
#[derive(Debug, Clone, PartialEq)]
pub struct RunOptions {
    /// Output directory (created; must be writable).
    pub out_dir: PathBuf,
    /// Overwrite an existing, non-empty output directory.
    pub force: bool,
    /// Show a progress bar on stderr.
    pub progress: bool,
    /// Write a checkpoint every this many simulated seconds.
    pub checkpoint_every_s: Option<f64>,
    /// Resume from the checkpoint in this run directory.
    pub resume: Option<PathBuf>,
}

/// What a run produced.
#[derive(Debug, Clone, PartialEq)]
pub struct RunOutcome {
    /// The contents of `summary.json` (docs/outputs.md).
    pub summary: serde_json::Value,
    /// Whether the run reached `time.duration_s`.
    pub complete: bool,
    /// Why the run stopped early, or a warning worth showing.
    pub message: Option<String>,
}

/// Everything that can stop a command; [`AppError::exit_code`] maps it to the process status.
#[derive(Debug, thiserror::Error)]
pub enum AppError {
    /// A bad scenario (exit 2). Boxed: it is the largest variant.
    #[error(transparent)]
    Scenario(Box<ScenarioError>),
    /// A scenario the builders cannot turn into a model, e.g. a bad mesh file (exit 2).
    #[error(transparent)]
    Build(#[from] crate::build::BuildError),
    /// Any other bad input: output directory, study file, shard spec (exit 2).
    #[error("{0}")]
    Input(String),
    /// The simulation failed (exit 3).
    #[error("run failed: {0}")]
    RunFailed(String),
    /// Reading or writing a file failed (exit 1).
    #[error("{}: {source}", path.display())]
    Io {
        /// The file or directory.
        path: PathBuf,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// Some verification cases failed (exit 1).
    #[error("{failed} verification case(s) failed")]
    ValidationFailed {
        /// Number of failed cases.
        failed: usize,
    },
}

impl From<ScenarioError> for AppError {
    fn from(e: ScenarioError) -> Self {
        AppError::Scenario(Box::new(e))
    }
}

impl AppError {
    /// Process exit status: 2 for input errors, 3 for a failed run, 1 for anything else.
    pub fn exit_code(&self) -> i32 {
        match self {
            AppError::Scenario(_) | AppError::Build(_) | AppError::Input(_) => 2,
            AppError::RunFailed(_) => 3,
            AppError::Io { .. } | AppError::ValidationFailed { .. } => 1,
        }
    }

    /// Wrap an I/O error with the path it concerns.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        AppError::Io {
            path: path.into(),
            source,
        }
    }
}

/// Derived quantities of a scenario (name, value with units), for `chute check`: the
/// model is built (meshes generated or read, masses lumped) so every number is the one a run
/// would use.
pub fn check(s: &Scenario) -> Result<Vec<(String, String)>, AppError> {
    let built = crate::build::build(s)?;
    check_ground(s, &built)?;
    let mut out = built.derived.clone();
    out.extend(atmosphere_lines(s, &built));
    out.extend(fabric_lines(s, &built));
    out.extend(s.notes.0.iter().map(|w| ("warning".to_string(), w.clone())));
    let t = &s.time;
    match s.adaptive_settings() {
        None => out.push((
            "time steps".into(),
            format!(
                "{:.0} (dt = {} s, {} s)",
                (t.duration_s / t.dt_s).ceil(),
                t.dt_s,
                t.duration_s
            ),
        )),
        Some(a) => {
            out.push((
                "time steps".into(),
                format!(
                    "adaptive, local error ≤ {:e} m per step; first dt = {} s, dt in [{:.4e}, {}] s, {} s",
                    a.error_tolerance_m, t.dt_s, a.dt_min_s, a.dt_max_s, t.duration_s
                ),
            ));
            // The step the tolerance allows at the start of a fall (a = g): h = √(2 tol/g).
            let h = (2.0 * a.error_tolerance_m / s.fluid.gravity_mps2).sqrt();
            out.push((
                "adaptive dt at a = g".into(),
                format!(
                    "{h:.3e} s (√(2 tol/g)); at least {:.0} steps",
                    (t.duration_s / a.dt_max_s).ceil()
                ),
            ));
        }
    }
    Ok(out)
}

/// The run loop's settings for scenario `s`.
pub fn run_config(s: &Scenario, progress: bool) -> crate::runner::RunConfig {
    use crate::scenario::DragLaw;
    crate::runner::RunConfig {
        name: s.name.clone(),
        dt_s: s.time.dt_s,
        // Fixed step: ten halvings after failed Newton solves; adaptive: time.dt_min_s.
        min_dt_s: s
            .adaptive_settings()
            .map_or(s.time.dt_s / 1024.0, |a| a.dt_min_s),
        adaptive: s.adaptive_settings(),
        duration_s: s.time.duration_s,
        frame_interval_s: s.output.frame_interval_s,
        // The loader fills the default times; an empty list means none.
        snapshots_s: s.output.snapshots_s.clone(),
        newton: engine::NewtonOptions {
            max_iterations: s.time.newton_max_iterations,
            force_tol_abs: s.time.newton_tolerance_n,
            // The default absolute tolerance is 1e-9 of the total weight (+ 1 N).
            reference_acceleration: s.fluid.gravity_mps2,
            force_tol_rel: s
                .time
                .newton_relative_tolerance
                .unwrap_or(engine::NewtonOptions::default().force_tol_rel),
            step_tol: s
                .time
                .newton_step_tolerance_m
                .unwrap_or(engine::NewtonOptions::default().step_tol),
            continuation: s.time.newton_rescue_stages,
            step_homotopy: s.time.newton_rescue_stages,
            // The held stage, chord iterations, the divergence limit, the adaptive predictor
            // and the accuracy-based tolerance (docs/engine.md §The step solver).
            ..engine::NewtonOptions::recommended()
        }
        // The accuracy-based test replaces the default tolerance only: a scenario that sets
        // `time.newton_tolerance_n` (e.g. a peer's tolerances) gets exactly that one.
        .strict_if(s.time.newton_strict || s.time.newton_tolerance_n.is_some()),
        air_density: s.fluid.density_kg_m3,
        air_viscosity: s.fluid.viscosity_pa_s,
        quadratic_drag: s.fluid.drag == DragLaw::Quadratic,
        air: crate::build::drag::fluid(s),
        altitude_m: s.atmosphere.altitude_m,
        ground_z_m: s
            .atmosphere
            .ground_altitude_m
            .map(|g| g - s.atmosphere.altitude_m),
        gravity_mps2: s.fluid.gravity_mps2,
        guidance: s
            .atmosphere
            .ground_altitude_m
            .and_then(|g| crate::control::Controller::new(s, g - s.atmosphere.altitude_m)),
        scenario_warnings: s.notes.0.clone(),
        progress,
    }
}

/// Build the model, simulate, and write the output directory (which must exist).
///
/// With `opts.resume` the run continues from `checkpoint.bin` in that directory (which must
/// be `opts.out_dir`); the scenario must resolve to the one the checkpoint was written with,
/// except for `time.duration_s`, which may only grow (a run may be extended). With
/// `opts.force` an earlier run in the directory is cleared first
/// ([`crate::output::run_files::clear`]), once the model is known to be valid, so a run that
/// cannot start leaves the earlier one intact and one that starts never mixes with it. With
/// `opts.checkpoint_every_s` a checkpoint is written periodically. The process-wide
/// [`crate::runner::STOP`] flag (set by the Ctrl-C / SIGTERM handler of the binary) stops the
/// run gracefully.
pub fn run(s: &Scenario, opts: &RunOptions) -> Result<RunOutcome, AppError> {
    let watch = Watch {
        stop: &crate::runner::STOP,
        sim_time: None,
    };
    run_watched(s, opts, watch)
}

/// How a run is watched from another thread (the Python bindings): the flag that stops it
/// gracefully, and where it publishes its simulated time ([`crate::runner::RunControl`]).
#[derive(Debug, Clone, Copy)]
pub struct Watch<'a> {
    /// Graceful stop request, checked before every step.
    pub stop: &'a std::sync::atomic::AtomicBool,
    /// Receives the simulated time after every accepted step (`f64::to_bits`).
    pub sim_time: Option<&'a std::sync::atomic::AtomicU64>,
}

/// [`run`] with its own stop flag and progress instead of the process-wide
/// [`crate::runner::STOP`].
pub fn run_watched(
    s: &Scenario,
    opts: &RunOptions,
    watch: Watch<'_>,
) -> Result<RunOutcome, AppError> {
    use crate::output::run_files;
    let mut built = crate::build::build(s)?;
    check_ground(s, &built)?;
    let scenario_toml = s.to_toml();
    let resume = match &opts.resume {
        Some(dir) => Some(load_checkpoint(dir, &opts.out_dir, &scenario_toml)?),
        None => None,
    };
    if opts.force && resume.is_none() {
        if !dir_is_empty(&opts.out_dir) && !run_files::is_run_dir(&opts.out_dir) {
            return Err(not_a_run_dir(&opts.out_dir));
        }
        run_files::clear(&opts.out_dir).map_err(|e| AppError::io(&opts.out_dir, e))?;
    }
    let resolved = opts.out_dir.join(run_files::RESOLVED_SCENARIO);
    crate::output::atomic::write_atomic(&resolved, scenario_toml.as_bytes())
        .map_err(|e| AppError::io(&resolved, e))?;
    let cfg = run_config(s, opts.progress);
    let ctl = crate::runner::RunControl {
        stop: watch.stop,
        checkpoint_every_s: opts.checkpoint_every_s,
        resume,
        scenario_toml,
        sim_time: watch.sim_time,
    };
    let r = crate::runner::simulate_with(&mut built, &cfg, &opts.out_dir, &ctl).map_err(
        |e| match e {
            crate::runner::RunError::Io { path, source } => AppError::Io { path, source },
            crate::runner::RunError::Checkpoint(m) => AppError::Input(format!("checkpoint: {m}")),
            e => AppError::RunFailed(e.to_string()),
        },
    )?;
    let summary = serde_json::from_str(&r.summary.to_json())
        .map_err(|e| AppError::RunFailed(format!("summary: {e}")))?;
    // Landing is how a run with a ground ends: complete, nothing to warn about.
    let message = r.stop_reason.filter(|m| m != crate::runner::GROUND);
    Ok(RunOutcome {
        summary,
        complete: r.complete,
        message,
    })
}

/// `chute check`'s lines on the air: the model, the air at the start and at the ground, and
/// the time to fall from one to the other at the flat-canopy speed √(2W/(ρ(h) C_D A)).
fn atmosphere_lines(s: &Scenario, b: &crate::build::Built) -> Vec<(String, String)> {
    use crate::scenario::derived::sig4;
    use crate::scenario::AtmosphereModel;
    let a = &s.atmosphere;
    let fluid = crate::build::drag::fluid(s);
    let describe = |h: f64| -> String {
        let air = fluid.at(h - a.altitude_m);
        match a.model {
            AtmosphereModel::Constant => format!(
                "ρ = {} kg/m³, μ = {} Pa·s (constant)",
                sig4(air.density),
                sig4(air.viscosity)
            ),
            AtmosphereModel::Isa1976 => {
                let st = engine::aero::atmosphere::isa1976(h);
                format!(
                    "T = {} K, p = {} Pa, ρ = {} kg/m³, μ = {} Pa·s",
                    sig4(st.temperature_k),
                    sig4(st.pressure_pa),
                    sig4(st.density_kg_m3),
                    sig4(st.viscosity_pa_s)
                )
            }
        }
    };
    let model = match a.model {
        AtmosphereModel::Constant => "constant (fluid.density_kg_m3, fluid.viscosity_pa_s)",
        AtmosphereModel::Isa1976 => "isa1976 (U.S. Standard Atmosphere 1976)",
    };
    let mut out = vec![
        ("atmosphere".to_string(), model.to_string()),
        (
            format!("air at the start ({} m)", sig4(a.altitude_m)),
            describe(a.altitude_m),
        ),
    ];
    let Some(g) = a.ground_altitude_m else {
        return out;
    };
    out.push((format!("air at the ground ({} m)", sig4(g)), describe(g)));
    // ∫ dh / v_flat(h) by the composite midpoint rule on 2000 intervals (ρ is smooth inside
    // each layer; the error is far below the flat-canopy estimate's own).
    let n = 2000;
    let dh = (a.altitude_m - g) / n as f64;
    let w = b.total_weight_n;
    let time: f64 = (0..n)
        .map(|i| {
            let h = g + (i as f64 + 0.5) * dh;
            let rho = fluid.at(h - a.altitude_m).density;
            dh / (2.0 * w / (rho * b.flat_drag_area_m2)).sqrt()
        })
        .sum();
    out.push((
        "time to fall to the ground at the flat-canopy speed".into(),
        format!("{} s ({} m)", sig4(time), sig4(a.altitude_m - g)),
    ));
    out
}

/// `chute check`'s lines on a permeable fabric: k (and where it came from) and the leakage
/// speed at the canopy loading W/S₀ in the air at the start.
fn fabric_lines(s: &Scenario, b: &crate::build::Built) -> Vec<(String, String)> {
    use crate::scenario::derived::sig4;
    let Some(f) = crate::build::drag::fabric(s) else {
        return Vec::new();
    };
    let air = crate::build::drag::fluid(s).at(0.0);
    let loading = b.total_weight_n / b.planform_area_m2;
    let source = match s.material.air_permeability_cfm {
        Some(q) => format!(" (from {} ft³/(ft²·min), ASTM D737, Darcy term)", sig4(q)),
        None => String::new(),
    };
    vec![
        (
            "fabric permeability k".into(),
            format!(
                "{} m²{source}, C_F = {}, h = {} m",
                sig4(f.permeability),
                sig4(f.forchheimer),
                sig4(f.thickness)
            ),
        ),
        (
            "leakage through the fabric at W/S₀".into(),
            format!(
                "{} m/s at {} Pa",
                sig4(f.leakage_at(loading, air.density, air.viscosity)),
                sig4(loading)
            ),
        ),
    ]
}

/// The ground must lie below where the landing body (the payload, or the lowest canopy node)
/// starts; only the builder knows that height.
fn check_ground(s: &Scenario, b: &crate::build::Built) -> Result<(), AppError> {
    let Some(g) = s.atmosphere.ground_altitude_m else {
        return Ok(());
    };
    let n = b.model.layout.n_nodes;
    let z = |i: usize| b.state.q[3 * i + 2];
    let (what, z0) = match b.payload_node {
        Some(p) => ("the payload", z(p)),
        None => (
            "the lowest canopy node",
            b.canopy_nodes
                .iter()
                .map(|&i| z(i))
                .fold(f64::INFINITY, f64::min),
        ),
    };
    debug_assert!(b.canopy_nodes.iter().all(|&i| i < n));
    let start = s.atmosphere.altitude_m + z0;
    if g >= start {
        return Err(crate::build::BuildError::key(
            "atmosphere.ground_altitude_m",
            format!(
                "{g} m is not below {what}, which starts at {start} m (atmosphere.altitude_m {} m {:+} m)",
                s.atmosphere.altitude_m, z0
            ),
        )
        .into());
    }
    Ok(())
}

/// Whether `dir` has no entries (or does not exist).
fn dir_is_empty(dir: &std::path::Path) -> bool {
    std::fs::read_dir(dir).map_or(true, |mut it| it.next().is_none())
}

/// `--force` is refused on a non-empty directory chute did not write: it would delete or
/// mix with someone else's files.
pub fn not_a_run_dir(dir: &std::path::Path) -> AppError {
    AppError::Input(format!(
        "output directory `{}` is not empty and is not a chute run directory (it has no {}); --force only replaces an earlier chute run: choose another --out DIR",
        dir.display(),
        crate::output::run_files::RESOLVED_SCENARIO
    ))
}

/// Read the checkpoint of run directory `dir` and check it belongs to this scenario.
fn load_checkpoint(
    dir: &std::path::Path,
    out_dir: &std::path::Path,
    scenario_toml: &str,
) -> Result<crate::checkpoint::Checkpoint, AppError> {
    let same_dir = match (dir.canonicalize(), out_dir.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    };
    if !same_dir {
        return Err(AppError::Input(format!(
            "resuming `{}` continues that run in place; the output directory `{}` must be the same directory",
            dir.display(),
            out_dir.display()
        )));
    }
    let c = crate::checkpoint::Checkpoint::read(dir)
        .map_err(|e| AppError::Input(format!("cannot resume from `{}`: {e}", dir.display())))?;
    let cannot = |why: String| AppError::Input(format!("cannot resume `{}`: {why}", dir.display()));
    if let Some(d) = scenario_difference(&c.scenario_toml, scenario_toml) {
        return Err(cannot(format!(
            "`{}` = {} (checkpoint) vs {} (now); only time.duration_s may change",
            d.key, d.was, d.now
        )));
    }
    let (was, now) = (
        resolved_value(&c.scenario_toml, DURATION_KEY).and_then(|v| v.parse::<f64>().ok()),
        resolved_value(scenario_toml, DURATION_KEY).and_then(|v| v.parse::<f64>().ok()),
    );
    if let (Some(was), Some(now)) = (was, now) {
        if now < was {
            return Err(cannot(format!(
                "time.duration_s = {now} s is shorter than the recorded run's {was} s (checkpoint at t = {} s); a resumed run can only be extended",
                crate::scenario::derived::sig4(c.t)
            )));
        }
    }
    Ok(c)
}

/// The one key a resumed run may change.
pub const DURATION_KEY: &str = "time.duration_s";

/// A key whose value differs between two resolved scenarios.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Difference {
    /// The dotted key (`load.weight_n`).
    pub key: String,
    /// Its value in the first text (`<absent>` when it has none).
    pub was: String,
    /// Its value in the second.
    pub now: String,
}

/// The `key = value` lines of a resolved scenario as (dotted key, value text), tracking the
/// `[section]` and `[[section]]` headers (entries of arrays of tables numbered from 0).
fn resolved_entries(text: &str) -> Vec<(String, String)> {
    let mut section = String::new();
    let mut counts: std::collections::BTreeMap<String, usize> = Default::default();
    let mut out = Vec::new();
    for line in text.lines().map(str::trim) {
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        if let Some(name) = line.strip_prefix("[[").and_then(|l| l.strip_suffix("]]")) {
            let n = counts.entry(name.to_string()).or_default();
            section = format!("{name}[{n}]");
            *n += 1;
        } else if let Some(name) = line.strip_prefix('[').and_then(|l| l.strip_suffix(']')) {
            section = name.to_string();
        } else if let Some((k, v)) = line.split_once('=') {
            let k = k.trim();
            let key = if section.is_empty() {
                k.to_string()
            } else {
                format!("{section}.{k}")
            };
            out.push((key, v.trim().to_string()));
        }
    }
    out
}

/// The value text of `key` in a resolved scenario.
pub fn resolved_value(text: &str, key: &str) -> Option<String> {
    resolved_entries(text)
        .into_iter()
        .find_map(|(k, v)| (k == key).then_some(v))
}

/// The first key (in the checkpoint's order, then keys only `now` has) whose value differs
/// between two resolved scenarios, ignoring `time.duration_s` (a resumed run may be
/// extended).
pub fn scenario_difference(was: &str, now: &str) -> Option<Difference> {
    let keep = |(k, _): &(String, String)| k != DURATION_KEY;
    let a: Vec<_> = resolved_entries(was).into_iter().filter(keep).collect();
    let b: Vec<_> = resolved_entries(now).into_iter().filter(keep).collect();
    let find = |list: &[(String, String)], key: &str| {
        list.iter()
            .find(|(k, _)| k == key)
            .map_or_else(|| "<absent>".to_string(), |(_, v)| v.clone())
    };
    a.iter()
        .chain(&b)
        .map(|(k, _)| Difference {
            key: k.clone(),
            was: find(&a, k),
            now: find(&b, k),
        })
        .find(|d| d.was != d.now)
}

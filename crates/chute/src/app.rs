//! The interface between the command line and the simulation: `check` and `run` a scenario,
//! and the `validate` / `bench` entry points.
//!
//! `validate::main` returns [`AppError::NotImplemented`] until the verification suite is
//! written, rather than fake results; `bench` lives in [`crate::bench`].

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
    /// The contents of `summary.json` (DESIGN.md §Output directory).
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
    /// A part of the application that is not built yet (exit 1).
    #[error("not implemented yet: {0}")]
    NotImplemented(&'static str),
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
            AppError::Scenario(_) | AppError::Input(_) => 2,
            AppError::RunFailed(_) => 3,
            AppError::Io { .. }
            | AppError::ValidationFailed { .. }
            | AppError::NotImplemented(_) => 1,
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
    let built = crate::build::build(s).map_err(|e| AppError::Input(e.to_string()))?;
    let mut out = built.derived;
    out.push((
        "time steps".into(),
        format!(
            "{:.0} (dt = {} s, {} s)",
            (s.time.duration_s / s.time.dt_s).ceil(),
            s.time.dt_s,
            s.time.duration_s
        ),
    ));
    Ok(out)
}

/// The run loop's settings for scenario `s`.
pub fn run_config(s: &Scenario, progress: bool) -> crate::runner::RunConfig {
    use crate::scenario::DragLaw;
    let snapshots_s = if s.output.snapshots_s.is_empty() {
        [0.3, 0.6, 0.9]
            .iter()
            .map(|f| f * s.time.duration_s)
            .collect()
    } else {
        s.output.snapshots_s.clone()
    };
    crate::runner::RunConfig {
        name: s.name.clone(),
        dt_s: s.time.dt_s,
        min_dt_s: s.time.dt_s / 1024.0,
        duration_s: s.time.duration_s,
        frame_interval_s: s.output.frame_interval_s,
        snapshots_s,
        newton: engine::NewtonOptions {
            max_iterations: s.time.newton_max_iterations,
            force_tol_abs: s.time.newton_tolerance_n,
            reuse_jacobian: true,
            // Cholesky of ½(J + Jᵀ) instead of LU of J (drag is the only skew part); exact LU
            // when it does not contract. docs/performance.md has the measurements.
            symmetric_approx: true,
            ..Default::default()
        },
        air_density: s.fluid.density_kg_m3,
        air_viscosity: s.fluid.viscosity_pa_s,
        quadratic_drag: s.fluid.drag == DragLaw::Quadratic,
        progress,
    }
}

/// Build the model, simulate, and write the output directory (which must exist).
pub fn run(s: &Scenario, opts: &RunOptions) -> Result<RunOutcome, AppError> {
    if opts.resume.is_some() || opts.checkpoint_every_s.is_some() {
        return Err(AppError::NotImplemented("checkpoint and resume"));
    }
    let mut built = crate::build::build(s).map_err(|e| AppError::Input(e.to_string()))?;
    let resolved = opts.out_dir.join("scenario.resolved.toml");
    crate::output::atomic::write_atomic(&resolved, s.to_toml().as_bytes())
        .map_err(|e| AppError::io(&resolved, e))?;
    let cfg = run_config(s, opts.progress);
    let stop = std::sync::atomic::AtomicBool::new(false);
    let r =
        crate::runner::simulate(&mut built, &cfg, &opts.out_dir, &stop).map_err(|e| match e {
            crate::runner::RunError::Io { path, source } => AppError::Io { path, source },
            e => AppError::RunFailed(e.to_string()),
        })?;
    let summary = serde_json::from_str(&r.summary.to_json())
        .map_err(|e| AppError::RunFailed(format!("summary: {e}")))?;
    Ok(RunOutcome {
        summary,
        complete: r.complete,
        message: r.stop_reason,
    })
}

/// `chute validate`: the verification cases against analytic references.
pub mod validate {
    use super::AppError;
    use std::path::PathBuf;

    /// Arguments of `chute validate`.
    #[derive(Debug, Clone, PartialEq, Default)]
    pub struct ValidateArgs {
        /// Run the short versions of the cases.
        pub quick: bool,
        /// Where to write the report and plots.
        pub out: Option<PathBuf>,
        /// Print the table as JSON on stdout.
        pub json: bool,
    }

    /// Run the verification suite; `Err(ValidationFailed)` when any case fails.
    pub fn main(args: &ValidateArgs) -> Result<(), AppError> {
        let _ = args;
        Err(AppError::NotImplemented(
            "the verification suite (`chute::validate::main`)",
        ))
    }
}

/// `chute bench`: timings on a ladder of mesh sizes (implemented in [`crate::bench`]).
pub use crate::bench;

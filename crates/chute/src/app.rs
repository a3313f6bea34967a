//! The interface between the command line and the simulation: `check` and `run` a scenario,
//! and the `validate` / `bench` entry points.
//!
//! The builders and the run loop are written by the integrator; until then `run`,
//! `validate::main` and `bench::main` return [`AppError::NotImplemented`] rather than fake
//! results. `check` already reports the quantities that follow from the scenario alone.

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

/// Derived quantities of a scenario (name, value with units), for `chute check`.
///
/// For now these are the ones that follow from the scenario alone
/// ([`Scenario::derived_quantities`]); the integrator adds those of the built model (DOFs,
/// lumped masses).
pub fn check(s: &Scenario) -> Result<Vec<(String, String)>, AppError> {
    Ok(s.derived_quantities())
}

/// Build the model, simulate, and write the output directory.
pub fn run(s: &Scenario, opts: &RunOptions) -> Result<RunOutcome, AppError> {
    let _ = (s, opts);
    Err(AppError::NotImplemented(
        "the scenario builders and the run loop (`chute::app::run`)",
    ))
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

/// `chute bench`: timings on a ladder of mesh sizes.
pub mod bench {
    use super::AppError;

    /// Arguments of `chute bench`.
    #[derive(Debug, Clone, PartialEq, Default)]
    pub struct BenchArgs {
        /// Fewer and smaller sizes.
        pub quick: bool,
        /// Print the timings as JSON on stdout.
        pub json: bool,
    }

    /// Run the benchmark ladder.
    pub fn main(args: &BenchArgs) -> Result<(), AppError> {
        let _ = args;
        Err(AppError::NotImplemented(
            "the benchmark ladder (`chute::bench::main`)",
        ))
    }
}

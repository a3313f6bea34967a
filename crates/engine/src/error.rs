//! Error types of the engine.
use thiserror::Error;

/// Errors raised while building a model or its solver.
#[derive(Debug, Error)]
pub enum EngineError {
    /// A force referenced a DOF outside the model.
    #[error("force `{force}` references DOF {dof}, but the model has only {n} DOFs")]
    DofOutOfRange { force: String, dof: usize, n: usize },
    /// A free DOF has zero mass, so the dynamic Jacobian could be singular.
    #[error("free DOF {dof} has non-positive mass {mass}")]
    NonPositiveMass { dof: usize, mass: f64 },
    /// The sparse symbolic analysis failed.
    #[error("sparse symbolic factorisation failed: {0}")]
    Symbolic(String),
    /// Invalid input to a model builder.
    #[error("invalid model: {0}")]
    Invalid(String),
}

/// Why a time step (or a static solve) failed. The state is left unchanged.
#[derive(Debug, Clone, Error)]
pub enum StepError {
    /// Newton did not converge within the iteration limit.
    #[error("Newton did not converge in {iterations} iterations: residual {residual:.3e} N (tolerance {tolerance:.3e} N), worst DOF {worst_dof}")]
    NotConverged {
        iterations: usize,
        residual: f64,
        tolerance: f64,
        worst_dof: usize,
    },
    /// The residual grew beyond `NewtonOptions::divergence_limit` × its initial value.
    #[error("Newton diverged after {iterations} iterations: residual {residual:.3e} N grew beyond {limit:.0e} × the initial {initial:.3e} N, worst DOF {worst_dof}")]
    Diverged {
        iterations: usize,
        residual: f64,
        initial: f64,
        limit: f64,
        worst_dof: usize,
    },
    /// A force, residual or solution became NaN or infinite.
    #[error("non-finite value in {what} (DOF {dof})")]
    NonFinite { what: &'static str, dof: usize },
    /// The sparse factorisation failed (singular Jacobian).
    #[error("linear solve failed: {0}")]
    Linear(String),
}

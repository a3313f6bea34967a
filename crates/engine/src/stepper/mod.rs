//! Time stepping and static equilibrium, both built on one Newton–Raphson core, and the
//! local-error control of adaptive time steps.
pub mod error_control;
mod implicit_euler;
mod newton;
mod options;
mod predictor;
mod retry_ledger;
mod start_policy;
mod statics;

pub use error_control::{
    advance, error_norm, local_error_norm, Advance, Decision, ErrorController, ErrorNorm,
};
pub use implicit_euler::{ImplicitEuler, Trial};
pub use options::{NewtonOptions, Predictor, StepReport, Timings};
pub use statics::StaticSolver;

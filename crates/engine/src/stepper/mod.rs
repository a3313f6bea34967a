//! Time stepping and static equilibrium, both built on one Newton–Raphson core.
mod implicit_euler;
mod newton;
pub mod start_policy;
mod statics;

pub use implicit_euler::ImplicitEuler;
pub use newton::{NewtonOptions, Predictor, StepReport, Timings};
pub use statics::StaticSolver;

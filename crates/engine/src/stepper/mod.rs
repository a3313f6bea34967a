//! Time stepping and static equilibrium.
//!
//! A step is solved by a ladder of stages (`controller.rs`, `stage/`) sharing one workspace
//! (`workspace.rs`), one held factorisation (`linearization.rs`) and one convergence test
//! (`convergence.rs`); its size comes from `step_size.rs`, with the local-error control of
//! `error_control.rs` for adaptive steps.
mod anderson;
mod controller;
pub(crate) mod convergence;
pub mod error_control;
mod implicit_euler;
mod linearization;
mod options;
mod predictor;
mod retry_ledger;
mod stage;
mod statics;
pub mod step_size;
mod unit_costs;
mod workspace;

pub use controller::{Attempt, ImplicitEuler};
pub use error_control::{error_norm, local_error_norm, Decision, ErrorController, ErrorNorm};
pub use implicit_euler::Trial;
pub use options::{Counters, NewtonOptions, Predictor, Stage, StageCounts, StepReport};
pub use statics::StaticSolver;
pub use step_size::{Plan, SizeState, StepSizes, StepSizing};
pub use unit_costs::UnitCosts;
pub use workspace::{ITERATE_GAP, PATH_GAP};

//! Physics through the library: whole runs against analytic results, failed-step recovery,
//! checkpoint and resume, metrics (with the lateral-instability warning), shell bending against
//! plate theory, the GCI arithmetic of `chute converge`, and the solver counters of a run.

mod adaptive;
#[path = "../common/mod.rs"]
mod common;

mod control;
mod failure;
mod gci;
mod lateral;
mod metrics;
mod opening;
mod recovery;
mod resume;
mod round_symmetry;
mod runs;
mod sensor;
mod session;
mod shell_bending;
mod shell_midedge;
mod solver;

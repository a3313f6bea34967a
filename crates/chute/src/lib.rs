//! chute: parachute scenarios, builders, metrics, outputs and the command line.
pub mod app;
pub mod cli;
pub mod scenario;
pub mod study;

pub use app::{bench, validate};

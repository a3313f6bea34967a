//! chute: parachute scenarios, builders, metrics, outputs and the command line.

pub mod build;
pub mod mesh;
pub mod metrics;
pub mod output;
pub mod runner;

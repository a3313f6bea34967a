//! chute: parachute scenarios, builders, metrics, outputs and the command line.

pub mod app;
pub mod bench;
pub mod bench_plot;
pub mod build;
pub mod checkpoint;
pub mod cli;
pub mod converge;
pub mod mesh;
pub mod metrics;
pub mod output;
pub mod runner;
pub mod scenario;
pub mod study;
pub mod validate;

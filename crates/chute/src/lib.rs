#![warn(missing_docs)]
//! chute: parachute scenarios, builders, metrics, outputs and the command line. How the
//! layers fit together (scenario → builders → engine → observers → outputs, and how a
//! scenario key flows) is described in docs/architecture.md §Application.

pub mod api;
pub mod app;
pub mod bench;
pub mod build;
pub mod checkpoint;
pub mod cli;
pub mod control;
pub mod converge;
pub mod mesh;
pub mod metrics;
pub mod output;
pub mod runner;
pub mod scenario;
pub mod study;
pub mod verify;

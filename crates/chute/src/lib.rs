//! chute: parachute scenarios, builders, metrics, outputs and the command line.
pub mod mesh;

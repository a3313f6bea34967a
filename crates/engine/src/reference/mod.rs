//! Reference problems with analytic solutions, shared by the engine's tests and by
//! `chute validate`, so that the test suite and the validation report always exercise the
//! same set-ups.
//!
//! - [`cantilever`]: clamped DER cantilevers (tip load, self-weight, Bisshopp–Drucker
//!   elastica, end-moment arc) and the first natural period ([`vibration`]);
//! - [`sheet`]: flat triangulated sheets with stiff edge springs;
//! - [`falling`]: rigid bodies falling under quadratic drag (the tanh law) and drifting in
//!   wind;
//! - [`spring`]: the one-spring oscillator of backward-Euler's numerical damping.
//!
//! Functions return the simulated quantity next to its analytic value; the callers decide
//! the tolerance (and justify it).

pub mod cantilever;
pub mod falling;
pub mod pendulum;
pub mod sheet;
pub mod spring;
pub mod vibration;

use crate::error::{EngineError, StepError};

/// Why a reference problem could not be run.
#[derive(Debug, thiserror::Error)]
pub enum RefError {
    /// Building the model or its solver failed.
    #[error(transparent)]
    Build(#[from] EngineError),
    /// A static solve or a time step failed.
    #[error(transparent)]
    Solve(#[from] StepError),
    /// The run finished but the quantity could not be measured.
    #[error("measurement failed: {0}")]
    Measure(String),
}

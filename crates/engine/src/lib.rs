//! # chute-engine
//!
//! A small implicit-Euler engine for discrete elastic rods (DER), discrete shells and drag.
//! It knows nothing about parachutes: it steps a [`Model`] (lumped masses, fixed DOFs and a
//! list of [`Force`] elements) forward in time, or solves for static equilibrium.
//!
//! Generalised coordinates `q` are laid out as `[x0 y0 z0 x1 y1 z1 … θ0 θ1 …]`: three
//! Cartesian positions per node (m) followed by one twist angle per rod edge (rad). See
//! [`dof::DofLayout`].
//!
//! Layers (nothing points upward):
//! - [`force`]: the one trait every force implements, and the local blocks it writes;
//! - [`assembly`]: the global sparse pattern built once, and scatter maps into it;
//! - [`linsolve`]: sparse LLᵀ / LU with the symbolic factorisation reused;
//! - [`stepper`]: implicit Euler with Newton–Raphson and a line search, a static solver, and
//!   local-error control for adaptive steps ([`stepper::error_control`]).
//! - elements: [`rod`] (DER), [`shell`] (hinge shells), [`aero`] (drag), [`loads`].

pub mod aero;
pub mod assembly;
pub mod conformance;
pub mod dof;
pub mod element;
pub mod error;
pub mod fdcheck;
pub mod force;
pub mod linsolve;
pub mod loads;
pub mod model;
pub mod reference;
pub mod rod;
pub mod shell;
pub mod stepper;
pub mod vec3;

pub use dof::DofLayout;
pub use error::{EngineError, StepError};
pub use force::{EvalInput, Force, JacobianKind, LocalBlocks};
pub use model::{Model, State};
pub use stepper::{
    ErrorController, ImplicitEuler, NewtonOptions, Predictor, StaticSolver, StepReport, Timings,
    Trial,
};

//! # chute-engine
//!
//! A small implicit-Euler engine for discrete elastic rods (DER), discrete shells and drag.
//! It knows nothing about parachutes: it steps a [`Model`] (lumped masses, fixed DOFs and a
//! list of [`Force`] elements) forward in time, or solves for static equilibrium.
//!
//! Generalised coordinates `q` are laid out as `[x0 y0 z0 x1 y1 z1 … θ0 θ1 …]`: three
//! Cartesian positions per node (m) followed by one twist angle per rod edge (rad). See
//! [`DofLayout`].
//!
//! Layers (nothing points upward; docs/architecture.md has the picture):
//! - [`force`]: the one trait the stepper sees, and the local blocks a force writes;
//! - [`element`]: fixed-size elements and the [`element::Family`] that implements [`Force`]
//!   for them, so that a force law is one `impl Element`;
//! - elements: [`rod`] (DER), [`shell`] (hinge shells), [`aero`] (drag), [`loads`];
//! - [`stepper`]: implicit Euler with Newton–Raphson and a line search, a static solver, and
//!   local-error control for adaptive steps ([`stepper::error_control`]); internally a
//!   sparse assembler (pattern built once) and sparse LLᵀ / LU with the symbolic
//!   factorisation reused;
//! - verification: [`fdcheck`] and [`conformance`] (the checks [`force_conformance!`] stamps
//!   on every force).
//!
//! ## Example: a mass on a spring, released from a stretch
//!
//! ```
//! use engine::prelude::*;
//!
//! // Two nodes 1 m apart along x; node 0 is clamped, node 1 (1 kg) hangs on a spring.
//! let q0 = vec![0.0, 0.0, 0.0, 1.0, 0.0, 0.0];
//! let mut model = Model::new(DofLayout::new(2, 0));
//! model.add_node_mass(0, 1.0);
//! model.add_node_mass(1, 1.0);
//! model.fix_node(0);
//! // Axial stiffness 100 N over a rest length of 1 m: spring constant 100 N/m.
//! model.add_force(Stretch::new("spring", &[[0, 1]], &q0, vec![100.0]));
//!
//! let mut state = State::at_rest(q0);
//! state.q[3] = 1.1; // 10 cm stretch
//! let mut stepper = ImplicitEuler::new(&model, NewtonOptions::recommended())?;
//! for _ in 0..100 {
//!     stepper.step(&mut model, &mut state, 1e-3)?;
//! }
//! // ω = 10 rad/s: after 0.1 s the stretch is ≈ 0.1 cos(1) m (backward Euler damps a little).
//! let stretch = state.q[3] - 1.0;
//! assert!((stretch - 0.1 * 1f64.cos()).abs() < 2e-3, "{stretch}");
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![warn(missing_docs)]

pub mod aero;
pub(crate) mod assembly;
pub mod conformance;
pub mod contact;
pub mod dof;
pub mod element;
pub mod error;
pub mod fdcheck;
pub mod force;
pub(crate) mod linsolve;
pub mod loads;
pub mod model;
pub(crate) mod real;
#[cfg(feature = "reference")]
pub mod reference;
pub mod rod;
pub mod shell;
pub mod stability;
pub mod stepper;
pub(crate) mod vec3;

pub use dof::DofLayout;
pub use error::{EngineError, HistoryError, InvalidModel, SparseError, StepError};
pub use force::{EvalInput, Force, JacobianKind, LocalBlocks};
/// Most terms the forces' low-rank Jacobian parts may have in all ([`Force::low_rank_rank`]).
pub use linsolve::MAX_RANK as MAX_LOW_RANK;
pub use model::{ForceId, Model, State};
pub use stepper::{
    Attempt, Counters, ErrorController, ErrorNorm, ImplicitEuler, NewtonOptions, Predictor, Stage,
    StageCounts, StaticSolver, StepReport, StepSizes, StepSizing, Trial,
};

/// The types most programs need: `use engine::prelude::*;`.
pub mod prelude {
    pub use crate::aero::{
        AddedMass, Fabric, Fluid, InflationPressure, LinearDrag, NodeDrag, PressureDrag,
        TriangleDrag,
    };
    pub use crate::element::{Element, Family};
    pub use crate::loads::{DofForces, Gravity, PlanarEdgeMoment, PointForces};
    pub use crate::rod::{RodNetwork, RodSpec, Section, Stretch};
    pub use crate::shell::{
        CstMembrane, FabricMembrane, HingeBending, MidedgeBending, Orthotropic, ShellMaterial,
        TensionField, TriMesh,
    };
    pub use crate::{
        DofLayout, EngineError, EvalInput, Force, ForceId, ImplicitEuler, JacobianKind, Model,
        NewtonOptions, Predictor, State, StaticSolver, StepError,
    };
}

//! External loads: gravity and constant point forces (both a [`ConstantForces`] family),
//! constant generalised forces on single DOFs and a planar end moment. All honour the load
//! scale used by the static solver's load stepping.

mod constant;
mod dof_forces;
mod edge_moment;

pub use constant::{ConstantForces, ConstantLoad, Gravity, PointForces};
pub use dof_forces::{DofForces, DofLoad};
pub use edge_moment::{EdgeMomentLaw, PlanarEdgeMoment};

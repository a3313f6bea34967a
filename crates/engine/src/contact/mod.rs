//! Contact between the parts of a model that must not pass through each other (canopy
//! cloth, lines): Incremental Potential Contact (Li et al., SIGGRAPH 2020; its codimensional
//! form for cloth and rods, Li, Kaufman & Jiang, 2021).
//!
//! Built so far: the pieces every contact pair needs, each checked against finite
//! differences on random configurations:
//! - [`ad`]: exact gradients and Hessians of short formulas (second-order forward AD);
//! - [`distance`]: point–triangle and edge–edge squared distances, the feature pair that
//!   realises each;
//! - [`barrier`]: the log barrier on a squared distance and one pair's energy, gradient and
//!   (projected positive semi-definite) Hessian;
//! - [`broad`]: the candidate pairs within a reach (an R*-tree of grown bounding boxes);
//! - [`ccd`]: how far a pair may move along an update before it closes (additive CCD);
//! - [`intersect`]: whether the mesh passes through itself (exact predicates), the invariant.
//!
//! Not yet built (docs/notes/contact-design-2026-12-07.md): the pair set's
//! sparsity in the step solver, the line search's use of the CCD bound, and the force family
//! that puts them into a model.

pub mod ad;
pub mod barrier;
pub mod broad;
pub mod ccd;
pub mod distance;
pub mod force;
pub mod intersect;

pub use force::SelfContact;

#[cfg(test)]
mod tests;

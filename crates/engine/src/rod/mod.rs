//! Discrete Elastic Rods (Bergou et al. 2008): stretching, bending and twisting.
//!
//! - [`section`]: cross-sections and stiffnesses;
//! - [`frames`]: parallel transport, reference/material frames, curvature binormal,
//!   reference twist, and the frame history [`RodFrames`];
//! - `bend`, `twist`: material curvatures, reference twist and their exact gradients;
//! - [`bend_twist`]: the bend–twist force family [`BendTwist`];
//! - [`stretch`]: axial springs [`Stretch`] (shared with shells);
//! - [`network`]: the builder [`RodNetwork`] (rods, joints, pins, masses, clamps).
mod bend;
pub mod bend_twist;
pub mod frames;
pub mod network;
mod scalar;
pub mod section;
pub mod stretch;
mod twist;

pub use bend_twist::{BendTwist, BendTwistData, BendTwistElement, BendTwistLaw};
pub use frames::RodFrames;
pub use network::{RodHandles, RodNetwork, RodSpec};
pub use section::{Section, SectionError};
pub use stretch::{
    Command, EdgeSpring, Firing, Pull, RestSchedule, Scheduled, Stretch, StretchHistory,
    StretchLaw, TriggeredPull,
};

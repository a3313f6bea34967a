//! Aerodynamic drag elements (all implement [`Force`]).
//!
//! - [`NodeDrag`]: quadratic drag on rod nodes with rest projected areas (report §II.A);
//! - [`TriangleDrag`]: quadratic normal + tangential drag on shell triangles (report §II.D),
//!   exact Jacobians in positions and velocities;
//! - [`PressureDrag`]: the DisMech peer's per-node normal pressure law on triangles;
//! - [`InflationPressure`]: a canopy's trapped-air pressure, uniform coefficient, on every
//!   triangle's inside normal whatever its angle to the flow;
//! - [`IncidencePressure`]: the inflation pressure plus a windward excess that gives the
//!   canopy a tabulated normal-force curve `C_N(α)` ([`IncidenceCurve`]): swing and glide;
//! - [`LinearDrag`]: linear (Stokes-like) drag for low Reynolds numbers;
//! - [`AddedMass`]: the air a canopy carries along, accelerated with it (potential flow);
//! - [`Fluid`], [`reynolds`] and [`DragRegime`]: which law applies; [`Profile`]: density and
//!   viscosity varying with height (uniform, exponential, the 1976 standard atmosphere of
//!   [`atmosphere`]), taken at each element's own height; [`WindProfile`]: wind varying with
//!   height ([`wind`]), likewise;
//! - [`Fabric`] and [`permeability`]: air leaking through a permeable canopy
//!   (Darcy–Forchheimer), for the triangle laws;
//! - [`resultant`]: the total force of any element family (for observers).
//!
//! Drag acts on the velocity relative to the wind, `v − U∞`. Speeds in the quadratic laws are
//! regularised, `|u|_ε = √(|u|² + ε²)` ([`DEFAULT_EPSILON`]), so Jacobians exist at rest.
//! See `docs/aero.md`.

mod added_mass;
pub mod atmosphere;
mod fluid;
mod geometry;
pub mod incidence;
mod inflation;
mod linear;
mod node_drag;
pub mod permeability;
mod pressure;
mod regularize;
mod triangle;
pub mod wind;

pub use added_mass::AddedMass;
pub use fluid::{reynolds, DragRegime, Fluid, LocalFluid, Profile};
pub use incidence::{IncidenceCurve, IncidencePressure, IncidencePressureLaw};
pub use inflation::{InflationPressure, InflationPressureLaw};
pub use linear::{stokes_sphere, LinearDrag, LinearDragLaw};
pub use node_drag::{NodeDrag, NodeDragLaw};
pub use permeability::Fabric;
pub use pressure::{PressureDrag, PressureDragLaw};
pub use regularize::{reg_norm, DEFAULT_EPSILON};
pub use triangle::{TriangleDrag, TriangleDragLaw};
pub use wind::{LocalWind, WindProfile, WindTable, WindTableError};

use crate::dof::DofLayout;
use crate::force::{EvalInput, Force};

/// Resultant (vector sum over nodes) of the translational forces of `force` at `(q, v)`
/// (N): every stencil entry on a node coordinate `3i + k` (`i < layout.n_nodes`) adds to
/// component `k`; twist DOFs (generalised moments, N·m) are skipped, which is why the layout
/// is needed. Evaluated at t = 0 (drag does not depend on time). Allocates its own buffers:
/// meant for observers, not the Newton loop.
pub fn resultant(force: &dyn Force, layout: &DofLayout, q: &[f64], v: &[f64]) -> [f64; 3] {
    let mut blocks = force.new_blocks();
    force.evaluate(&EvalInput::outside_step(q, v, 0.0, false), &mut blocks);
    let n_pos = 3 * layout.n_nodes;
    let mut total = [0.0; 3];
    for (&d, &f) in force.stencils().iter().zip(&blocks.f) {
        if d < n_pos {
            total[d % 3] += f;
        }
    }
    total
}

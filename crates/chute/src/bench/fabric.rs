//! The fabric-membrane rung of `chute bench`: the report's 1k-node shell canopy with the
//! orthotropic, no-compression membrane in place of the edge springs, so its cost per step
//! and per Newton iteration can be read beside `shell-1k` (docs/performance.md).

use super::{case, Case};

/// Fabric constants of the case: the report's Kevlar modulus along the warp, half of it
/// along the weft, a weak shear modulus (E/20) and ν₁₂ = 0.3, warp at 30° to the span, no
/// compression with the default regularisation strain.
const FABRIC: &[&str] = &[
    "canopy.edge_length_m=0.138",
    "shell.membrane=fabric",
    "material.warp_modulus_pa=55e9",
    "material.weft_modulus_pa=27.5e9",
    "material.shear_modulus_pa=2.75e9",
    "material.fabric_poisson_ratio=0.3",
    "material.warp_direction_deg=30",
    "material.no_compression=true",
];

/// The fabric law of [`FABRIC`] without its mesh and without no-compression.
pub(super) fn fabric_law() -> Vec<&'static str> {
    FABRIC[1..FABRIC.len() - 1].to_vec()
}

/// `shell-1k-fabric` (same mesh, warm-up and timed steps as `shell-1k`).
pub fn cases() -> Vec<Case> {
    vec![case("shell-1k-fabric", "shell", FABRIC, 50, 200)]
}

//! How far the no-compression regularisation moves the canopy (`material.wrinkle_strain`).
//!
//! The regularised tension field (engine `shell/tension_field.rs`) carries a principal stress
//! `σᵢ` at a strain short of the elastic one, `Q⁻¹σ`, by exactly `ε_r² k_ref / σᵢ` along it
//! (stationarity `σ = μ P⁻¹` with `μ = ε_r² k_ref`; unit test
//! `strain_at_a_given_stress_is_short_of_the_elastic_one_by_mu_over_the_stress`). Under the
//! canopy's load tension that is the regularisation's strain error. With the typical tension
//! `σ_L = W / perimeter` (the weight carried across the canopy's edge; an order-of-magnitude
//! scale: it is higher near the load sites and lower in the crown) the error is
//! `δε ≈ ε_r² k_ref / σ_L`. Measured on the bench's Kevlar weave (`shell-1k-fabric`, 6 m × 3 m,
//! 200 N, k_ref ≈ 8.6e7 N/m, σ_L ≈ 11 N/m; docs/shells.md §No compression): ε_r = 1e-5
//! (δε ≈ 8e-4) flies, 3e-5 (7e-3), 1e-4 (0.08) and 1e-3 (7.8) fail within 0.25 s — the fabric
//! let go of the pre-tension `ε_r k_ref` contracts freely (no compression resists it): with
//! 1e-3 its nodes move inward at a median 17 m/s after 16 ms, until folds pass through each
//! other and Newton fails at every step size.

use super::derived::sig4 as short;
use super::Scenario;
use super::{Membrane, ModelKind};

/// Default `material.wrinkle_strain`: the regularised no-compression law carries a tension
/// of about `ε_r E h` at zero strain (docs/shells.md §No compression).
pub const DEFAULT_WRINKLE_STRAIN: f64 = 1e-5;

/// Above this strain error a run gets a warning (`chute check`, `run`, `resume`).
pub const WARN: f64 = 1e-3;
/// Above this strain error the scenario is refused: the regularisation, not the fabric,
/// would shape the canopy.
pub const REFUSE: f64 = 0.1;

/// The regularisation's strain error estimate for a scenario.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Regularisation {
    /// `ε_r` (the key, or its default).
    pub strain: f64,
    /// `k_ref = (Q₁₁ + Q₂₂)/2` of the fabric law (N/m).
    pub k_ref: f64,
    /// `σ_L = W / perimeter` (N/m).
    pub load_tension: f64,
    /// `δε = ε_r² k_ref / σ_L`.
    pub strain_error: f64,
}

impl Regularisation {
    /// The largest `ε_r` whose strain error stays within `limit`: `√(limit σ_L / k_ref)`.
    pub fn strain_for(&self, limit: f64) -> f64 {
        (limit * self.load_tension / self.k_ref).sqrt()
    }

    /// What the estimate says, for an error or a warning.
    pub fn explain(&self, limit: f64) -> String {
        format!(
            "the no-compression regularisation leaves the fabric short of its elastic strain by \
             ε_r²·k/σ ≈ {} under this canopy's load tension σ ≈ weight/perimeter = {} N/m \
             (k = (Q₁₁ + Q₂₂)/2 = {} N/m); above {} its pre-tension ε_r·k = {} N/m rather than \
             the fabric shapes the canopy, which contracts unresisted when released; use \
             wrinkle_strain ≤ {} (docs/shells.md §No compression)",
            short(self.strain_error),
            short(self.load_tension),
            short(self.k_ref),
            super::error::short(limit),
            short(self.strain * self.k_ref),
            short(self.strain_for(limit)),
        )
    }
}

/// The estimate for a shell canopy with a no-compression fabric and a known outline (`None`
/// otherwise: other membranes have no regularisation; a mesh file's perimeter is not known
/// before it is read, and such canopies are not checked).
pub fn estimate(s: &Scenario) -> Option<Regularisation> {
    if s.model.kind != ModelKind::Shell
        || s.shell.membrane != Some(Membrane::Fabric)
        || s.material.no_compression != Some(true)
    {
        return None;
    }
    let perimeter = s.canopy_perimeter()?;
    let law = s.fabric_law()?;
    let q = law.stiffness();
    let k_ref = 0.5 * (q[0][0] + q[1][1]);
    let strain = s.material.wrinkle_strain.unwrap_or(DEFAULT_WRINKLE_STRAIN);
    let load_tension = s.load.weight_n / perimeter;
    let strain_error = strain * strain * k_ref / load_tension;
    (strain_error.is_finite() && k_ref > 0.0).then_some(Regularisation {
        strain,
        k_ref,
        load_tension,
        strain_error,
    })
}

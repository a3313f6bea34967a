//! Quantities that follow from the scenario alone (before any model is built). `chute check`
//! prints the built model's quantities (`chute::build`), so masses and areas are the lumped
//! ones a run uses; this module only holds what validation needs before building.

use super::{CanopyShape, Scenario, SiteSet, Sites};

/// `x` with 4 significant digits, in plain notation for moderate magnitudes.
pub fn sig4(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let mag = x.abs().log10().floor() as i32;
    if (-3..5).contains(&mag) {
        let decimals = (3 - mag).max(0) as usize;
        format!("{x:.decimals$}")
    } else {
        format!("{x:.3e}")
    }
}

impl Scenario {
    /// Number of load sites (lines in payload mode), when it is known without the mesh.
    pub fn site_count(&self) -> Option<usize> {
        match (&self.load.sites, self.canopy.shape) {
            (Sites::Points(p), _) => Some(p.len()),
            (Sites::Named(SiteSet::Ends), _) => Some(2),
            (Sites::Named(SiteSet::Center), _) => Some(1),
            (Sites::Named(SiteSet::Rim), _) => Some(self.load.rim_site_count),
            (Sites::Named(SiteSet::CornersAndMidspan), _) => Some(6),
            (Sites::Named(SiteSet::Corners), CanopyShape::Hexagon) => Some(6),
            (Sites::Named(SiteSet::Corners), _) => Some(4),
        }
    }

    /// The rest outline's perimeter (m), when it is known without the mesh (not for
    /// `canopy.shape = "mesh"`).
    pub fn canopy_perimeter(&self) -> Option<f64> {
        let c = &self.canopy;
        match c.shape {
            CanopyShape::Rectangle => Some(2.0 * (c.span_m + c.width_m)),
            CanopyShape::Hexagon => Some(6.0 * c.radius_m),
            CanopyShape::Circle => Some(2.0 * std::f64::consts::PI * c.radius_m),
            CanopyShape::Mesh => None,
        }
    }

    /// The orthotropic fabric law of the `material.warp_…`, `weft_…`, `shear_…` and
    /// `fabric_poisson_ratio` keys on `canopy.thickness_m`, when all four are set.
    pub fn fabric_law(&self) -> Option<engine::shell::Orthotropic> {
        let m = &self.material;
        Some(engine::shell::Orthotropic {
            warp_modulus: m.warp_modulus_pa?,
            weft_modulus: m.weft_modulus_pa?,
            shear_modulus: m.shear_modulus_pa?,
            poisson_ratio: m.fabric_poisson_ratio?,
            thickness: self.canopy.thickness_m,
        })
    }
}

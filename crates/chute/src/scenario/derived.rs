//! Quantities that follow from the scenario alone (before any model is built), for
//! `chute check`: areas, masses, weights, stiffnesses and the flat-canopy terminal velocity.
//! Quantities that need the built model (DOFs, lumped masses of an imported mesh) are added
//! by the builder layer.

use super::{CanopyShape, DragLaw, LoadMode, ModelKind, Scenario, SiteSet, Sites};

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

    /// Canopy mass ρ·A·h (kg), when the area is known.
    pub fn canopy_mass_kg(&self) -> Option<f64> {
        Some(self.planform_area_m2()? * self.canopy.thickness_m * self.material.density_kg_m3)
    }

    /// Suspension-line mass n·ρ·π r²·L (kg); zero unless the load hangs on lines.
    pub fn lines_mass_kg(&self) -> Option<f64> {
        if self.load.mode != LoadMode::Payload {
            return Some(0.0);
        }
        let l = &self.lines;
        let one = l.density_kg_m3 * std::f64::consts::PI * l.radius_m.powi(2) * l.length_m;
        Some(self.site_count()? as f64 * one)
    }

    /// Total weight W + (m_canopy + m_lines)·g (N), when known before building.
    pub fn total_weight_n(&self) -> Option<f64> {
        if self.load.mode == LoadMode::NodeMassScale {
            return None;
        }
        let m = self.canopy_mass_kg()? + self.lines_mass_kg()?;
        Some(self.load.weight_n + m * self.fluid.gravity_mps2)
    }

    /// Descent speed of the flat, rigid canopy where drag balances the total weight (m/s):
    /// quadratic v = √(2 W / (ρ C_D A)); linear v = W / c.
    pub fn flat_terminal_speed_mps(&self) -> Option<f64> {
        let w = self.total_weight_n()?;
        let f = &self.fluid;
        match (f.drag, f.linear_drag_coefficient_n_s_m) {
            (DragLaw::Linear, Some(c)) => Some(w / c),
            (DragLaw::Linear, None) => None,
            (DragLaw::Quadratic, _) => Some(
                (2.0 * w / (f.density_kg_m3 * f.drag_coefficient * self.planform_area_m2()?))
                    .sqrt(),
            ),
        }
    }

    /// Characteristic canopy length for the Reynolds number (m): span, or diameter.
    pub fn reference_length_m(&self) -> Option<f64> {
        match (self.model.kind, self.canopy.shape) {
            (ModelKind::Rod, _) | (_, CanopyShape::Rectangle) => Some(self.canopy.span_m),
            (_, CanopyShape::Hexagon | CanopyShape::Circle) => Some(2.0 * self.canopy.radius_m),
            (_, CanopyShape::Mesh) => None,
        }
    }

    /// Named derived quantities with units, for `chute check`.
    pub fn derived_quantities(&self) -> Vec<(String, String)> {
        let na = || "n/a (needs the built mesh)".to_string();
        let opt = |x: Option<f64>, unit: &str| x.map_or_else(na, |v| format!("{} {unit}", sig4(v)));
        let mut out: Vec<(String, String)> = Vec::new();
        let mut add = |k: &str, v: String| out.push((k.to_string(), v));
        add("planform area", opt(self.planform_area_m2(), "m²"));
        add("canopy mass", opt(self.canopy_mass_kg(), "kg"));
        add(
            "load sites",
            self.site_count().map_or_else(na, |n| n.to_string()),
        );
        if self.load.mode == LoadMode::Payload {
            add("suspension lines mass", opt(self.lines_mass_kg(), "kg"));
        }
        add("total weight", opt(self.total_weight_n(), "N"));
        let (e, h, nu) = (
            self.material.youngs_modulus_pa,
            self.canopy.thickness_m,
            self.material.poisson_ratio,
        );
        match self.model.kind {
            ModelKind::Rod => {
                let w = self.canopy.width_m;
                add(
                    "rod nodes / edges",
                    format!(
                        "{} / {}",
                        self.canopy.nodes,
                        self.canopy.nodes.saturating_sub(1)
                    ),
                );
                add("stretching stiffness EA", format!("{} N", sig4(e * w * h)));
                add(
                    "bending stiffness EI1 (out of plane)",
                    format!("{} N·m²", sig4(e * w * h.powi(3) / 12.0)),
                );
                add(
                    "bending stiffness EI2 (in plane)",
                    format!("{} N·m²", sig4(e * h * w.powi(3) / 12.0)),
                );
                let g = e / (2.0 * (1.0 + nu));
                add(
                    "torsional stiffness GJ",
                    format!("{} N·m²", sig4(g * w * h.powi(3) / 3.0)),
                );
            }
            ModelKind::Shell => {
                add("membrane stiffness E·h", format!("{} N/m", sig4(e * h)));
                add(
                    "plate bending stiffness D = E h³/12",
                    format!("{} N·m", sig4(e * h.powi(3) / 12.0)),
                );
            }
        }
        let v = self.flat_terminal_speed_mps();
        add("flat-canopy terminal speed", opt(v, "m/s"));
        let re = v
            .zip(self.reference_length_m())
            .map(|(v, l)| self.fluid.density_kg_m3 * v * l / self.fluid.viscosity_pa_s);
        add("Reynolds number at that speed", re.map_or_else(na, sig4));
        let t = &self.time;
        add(
            "time steps",
            format!("{:.0}", (t.duration_s / t.dt_s).ceil()),
        );
        out
    }
}

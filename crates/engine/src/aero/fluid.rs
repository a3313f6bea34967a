//! The surrounding fluid: density, viscosity and a uniform wind, and the Reynolds number
//! that says which drag law applies.

/// A uniform, steady fluid.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fluid {
    /// Density ρ (kg/m³).
    pub density: f64,
    /// Dynamic viscosity μ (Pa·s).
    pub viscosity: f64,
    /// Free-stream (wind) velocity U∞ (m/s); drag acts on `v − U∞`.
    pub wind: [f64; 3],
}

impl Fluid {
    /// Dry air at sea level, 15 °C (ISA): ρ = 1.225 kg/m³, μ = 1.81·10⁻⁵ Pa·s, no wind.
    pub fn air() -> Self {
        Self {
            density: 1.225,
            viscosity: 1.81e-5,
            wind: [0.0; 3],
        }
    }

    /// Reynolds number `Re = ρ v L / μ` of a body of size `length` (m) moving at `speed`
    /// (m/s) relative to this fluid (dimensionless).
    pub fn reynolds(&self, speed: f64, length: f64) -> f64 {
        reynolds(self.density, speed, length, self.viscosity)
    }

    /// Drag regime at `speed` (m/s) for a body of size `length` (m).
    pub fn regime(&self, speed: f64, length: f64) -> DragRegime {
        DragRegime::of(self.reynolds(speed, length))
    }
}

impl Default for Fluid {
    fn default() -> Self {
        Self::air()
    }
}

/// Reynolds number `Re = ρ v L / μ` (dimensionless) from density ρ (kg/m³), speed v (m/s),
/// length L (m) and dynamic viscosity μ (Pa·s). `speed` is taken in absolute value.
pub fn reynolds(density: f64, speed: f64, length: f64, viscosity: f64) -> f64 {
    density * speed.abs() * length / viscosity
}

/// Which drag law the Reynolds number supports.
///
/// The bounds are the usual textbook ones for bluff bodies (plates, discs, spheres): creeping
/// (Stokes) flow below Re ≈ 1, where drag is linear in speed, and a drag coefficient that is
/// roughly constant above Re ≈ 10³, where the quadratic law holds. In between neither law is
/// accurate.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DragRegime {
    /// `Re < 1`: use linear (Stokes-like) drag.
    Stokes,
    /// `1 ≤ Re < 10³`: transitional; both laws are approximations.
    Transitional,
    /// `Re ≥ 10³`: quadratic drag with a constant C_D.
    Quadratic,
}

impl DragRegime {
    /// Lower Reynolds number of the quadratic (constant-C_D) regime.
    pub const QUADRATIC_MIN_RE: f64 = 1e3;
    /// Upper Reynolds number of the Stokes regime.
    pub const STOKES_MAX_RE: f64 = 1.0;

    /// Classify a Reynolds number.
    pub fn of(re: f64) -> Self {
        if re < Self::STOKES_MAX_RE {
            Self::Stokes
        } else if re < Self::QUADRATIC_MIN_RE {
            Self::Transitional
        } else {
            Self::Quadratic
        }
    }
}

//! The surrounding fluid: density and viscosity (uniform or varying with height), the wind
//! (uniform or varying with height, [`super::wind`]), and the Reynolds number that says which
//! drag law applies.

use super::atmosphere::isa1976;
use super::wind::{LocalWind, WindProfile};

/// A steady fluid whose density, viscosity and wind may vary with height.
#[derive(Debug, Clone, PartialEq)]
pub struct Fluid {
    /// Density ρ (kg/m³): everywhere for [`Profile::Uniform`], at z = 0 otherwise.
    pub density: f64,
    /// Dynamic viscosity μ (Pa·s): everywhere for [`Profile::Uniform`] and
    /// [`Profile::Exponential`], at z = 0 for [`Profile::Isa1976`].
    pub viscosity: f64,
    /// Free-stream (wind) velocity U∞ (m/s); drag acts on `v − U∞`. With a
    /// [`Fluid::wind_profile`] law, the wind at its reference height.
    pub wind: [f64; 3],
    /// How density and viscosity vary with the height z of the model (m).
    pub profile: Profile,
    /// How the wind varies with height (uniform: [`Fluid::wind`] everywhere).
    pub wind_profile: WindProfile,
}

/// How a fluid's density and viscosity vary with the model's height z (m, up).
///
/// Drag elements evaluate the fluid at their own height (a node's z, a triangle's centroid)
/// and carry the exact `∂ρ/∂z` (and `∂μ/∂z`) terms in their position Jacobians.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Profile {
    /// ρ = [`Fluid::density`] and μ = [`Fluid::viscosity`] everywhere.
    Uniform,
    /// Isothermal atmosphere: `ρ(z) = ρ₀ exp(−z/H)` with ρ₀ = [`Fluid::density`] and the scale
    /// height `H` (m, > 0); μ = [`Fluid::viscosity`] everywhere.
    Exponential {
        /// Scale height H (m).
        scale_height: f64,
    },
    /// The U.S. Standard Atmosphere 1976 ([`isa1976`]) at the geometric altitude
    /// `altitude + z`; [`Fluid::density`] and [`Fluid::viscosity`] are not used by it
    /// ([`Fluid::isa1976`] sets them to the values at z = 0, for information).
    Isa1976 {
        /// Geometric altitude of the model's z = 0 (m).
        altitude: f64,
    },
}

/// The fluid at one height: density, viscosity and their rates of change with height.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LocalFluid {
    /// Density ρ (kg/m³).
    pub density: f64,
    /// dρ/dz (kg/m⁴).
    pub density_gradient: f64,
    /// Dynamic viscosity μ (Pa·s).
    pub viscosity: f64,
    /// dμ/dz (Pa·s/m).
    pub viscosity_gradient: f64,
}

impl Fluid {
    /// Dry air at sea level, 15 °C (ISA): ρ = 1.225 kg/m³, μ = 1.81·10⁻⁵ Pa·s, no wind,
    /// uniform.
    pub fn air() -> Self {
        Self {
            density: 1.225,
            viscosity: 1.81e-5,
            wind: [0.0; 3],
            profile: Profile::Uniform,
            wind_profile: WindProfile::Uniform,
        }
    }

    /// Still air of the U.S. Standard Atmosphere 1976 with the model's z = 0 at the geometric
    /// altitude `altitude` (m); `density` and `viscosity` hold the values there.
    pub fn isa1976(altitude: f64) -> Self {
        let a = isa1976(altitude);
        Self {
            density: a.density_kg_m3,
            viscosity: a.viscosity_pa_s,
            wind: [0.0; 3],
            profile: Profile::Isa1976 { altitude },
            wind_profile: WindProfile::Uniform,
        }
    }

    /// Whether density, viscosity and wind are the same at every height (no `∂/∂z` terms).
    pub fn is_uniform(&self) -> bool {
        self.profile == Profile::Uniform && self.wind_profile.is_uniform()
    }

    /// The wind at height `z` (m) and its shear `dU/dz`.
    #[inline]
    pub fn wind_at(&self, z: f64) -> LocalWind {
        self.wind_profile.at(self.wind, z)
    }

    /// The fluid at height `z` (m). For [`Profile::Uniform`] the values are the fields
    /// themselves, bit for bit, with zero gradients.
    #[inline]
    pub fn at(&self, z: f64) -> LocalFluid {
        match self.profile {
            Profile::Uniform => LocalFluid {
                density: self.density,
                density_gradient: 0.0,
                viscosity: self.viscosity,
                viscosity_gradient: 0.0,
            },
            Profile::Exponential { scale_height } => {
                let rho = self.density * (-z / scale_height).exp();
                LocalFluid {
                    density: rho,
                    density_gradient: -rho / scale_height,
                    viscosity: self.viscosity,
                    viscosity_gradient: 0.0,
                }
            }
            Profile::Isa1976 { altitude } => {
                let a = isa1976(altitude + z);
                LocalFluid {
                    density: a.density_kg_m3,
                    density_gradient: a.density_gradient,
                    viscosity: a.viscosity_pa_s,
                    viscosity_gradient: a.viscosity_gradient,
                }
            }
        }
    }

    /// Reynolds number `Re = ρ v L / μ` of a body of size `length` (m) moving at `speed`
    /// (m/s) relative to this fluid at z = 0 (dimensionless).
    pub fn reynolds(&self, speed: f64, length: f64) -> f64 {
        let f = self.at(0.0);
        reynolds(f.density, speed, length, f.viscosity)
    }

    /// Drag regime at `speed` (m/s) for a body of size `length` (m), at z = 0.
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

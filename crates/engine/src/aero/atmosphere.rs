//! The U.S. Standard Atmosphere 1976 (NOAA/NASA/USAF, NOAA-S/T 76-1562) below 86 km:
//! temperature, pressure and density from the geometric altitude, the viscosity by
//! Sutherland's law, and the exact derivatives of density and viscosity with altitude.
//!
//! The standard defines its seven lower layers in **geopotential** altitude
//! `H = r₀ Z / (r₀ + Z)` (m′, with `r₀` = 6 356 766 m and `Z` the geometric altitude): the
//! molecular-scale temperature is linear in `H` in each layer, `T = T_b + L_b (H − H_b)`, and
//! the pressure follows from hydrostatic equilibrium with the constant `g₀` = 9.806 65 m/s²:
//! `P = P_b (T_b/T)^{g₀M₀/(R* L_b)}` (or `P_b exp(−g₀M₀ (H − H_b)/(R* T_b))` where
//! `L_b = 0`). Then `ρ = P M₀ / (R* T)`. Below 80 km the molecular-scale temperature is the
//! kinetic temperature; from 80 to 86 km they differ by at most 0.04 % (the mean molecular
//! weight falls slightly), which this module does not model: density and pressure are exact
//! there, the temperature is the molecular-scale one.
//!
//! Outside 0–86 km the end layers are continued (the standard itself tabulates the first
//! layer down to −5 km); callers that need the standard's range check it themselves
//! ([`ISA_MAX_ALTITUDE_M`]).

/// Effective Earth radius for geopotential altitude, r₀ (m).
pub const EARTH_RADIUS_M: f64 = 6_356_766.0;
/// Standard gravity g₀ (m/s²).
pub const G0: f64 = 9.80665;
/// Universal gas constant R* as the 1976 standard gives it (J/(kmol·K)).
pub const GAS_CONSTANT: f64 = 8_314.32;
/// Mean molecular weight of sea-level air M₀ (kg/kmol).
pub const MOLAR_MASS: f64 = 28.9644;
/// Sutherland's constant β (kg/(m·s·K^½)).
pub const SUTHERLAND_BETA: f64 = 1.458e-6;
/// Sutherland's temperature S (K).
pub const SUTHERLAND_S: f64 = 110.4;
/// Highest geometric altitude of the standard's lower atmosphere (m).
pub const ISA_MAX_ALTITUDE_M: f64 = 86_000.0;

/// Base geopotential altitude (m′) and temperature gradient (K/m′) of the seven layers.
const LAYERS: [(f64, f64); 7] = [
    (0.0, -6.5e-3),
    (11_000.0, 0.0),
    (20_000.0, 1.0e-3),
    (32_000.0, 2.8e-3),
    (47_000.0, 0.0),
    (51_000.0, -2.8e-3),
    (71_000.0, -2.0e-3),
];
/// Sea-level temperature (K) and pressure (Pa).
const T0: f64 = 288.15;
const P0: f64 = 101_325.0;

/// The state of the standard atmosphere at one altitude.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AtmosphereState {
    /// Geometric altitude Z (m).
    pub altitude_m: f64,
    /// Geopotential altitude H (m′).
    pub geopotential_altitude_m: f64,
    /// Temperature T (K; molecular-scale, see the module docs).
    pub temperature_k: f64,
    /// Pressure P (Pa).
    pub pressure_pa: f64,
    /// Density ρ (kg/m³).
    pub density_kg_m3: f64,
    /// Dynamic viscosity μ by Sutherland's law (Pa·s).
    pub viscosity_pa_s: f64,
    /// dρ/dZ (kg/m⁴).
    pub density_gradient: f64,
    /// dμ/dZ (Pa·s/m).
    pub viscosity_gradient: f64,
}

/// Sutherland's law `μ = β T^{3/2} / (T + S)` (Pa·s) and `dμ/dT` (Pa·s/K).
pub fn sutherland(t: f64) -> (f64, f64) {
    let (b, s) = (SUTHERLAND_BETA, SUTHERLAND_S);
    let mu = b * t * t.sqrt() / (t + s);
    let dmu = b * t.sqrt() * (0.5 * t + 1.5 * s) / ((t + s) * (t + s));
    (mu, dmu)
}

/// Geopotential altitude `H = r₀ Z/(r₀ + Z)` (m′) of the geometric altitude `Z` (m).
pub fn geopotential(z: f64) -> f64 {
    EARTH_RADIUS_M * z / (EARTH_RADIUS_M + z)
}

/// `g₀ M₀ / R*` (K/m′): the hydrostatic exponent.
const HYDROSTATIC: f64 = G0 * MOLAR_MASS / GAS_CONSTANT;

/// Temperature and pressure at the base of each layer, chained from sea level once.
static BASES: std::sync::LazyLock<[(f64, f64); 7]> = std::sync::LazyLock::new(layer_bases);

fn layer_bases() -> [(f64, f64); 7] {
    let mut out = [(T0, P0); 7];
    for i in 1..LAYERS.len() {
        let (h0, l) = LAYERS[i - 1];
        let (t, p) = out[i - 1];
        out[i] = temperature_pressure(LAYERS[i].0 - h0, l, t, p);
    }
    out
}

/// Temperature and pressure `dh` (m′) above a layer base of temperature `tb`, pressure `pb`
/// and gradient `l`.
fn temperature_pressure(dh: f64, l: f64, tb: f64, pb: f64) -> (f64, f64) {
    if l == 0.0 {
        (tb, pb * (-HYDROSTATIC * dh / tb).exp())
    } else {
        let t = tb + l * dh;
        (t, pb * (tb / t).powf(HYDROSTATIC / l))
    }
}

/// The U.S. Standard Atmosphere 1976 at geometric altitude `z` (m).
pub fn isa1976(z: f64) -> AtmosphereState {
    let h = geopotential(z);
    let i = LAYERS.iter().rposition(|&(hb, _)| h >= hb).unwrap_or(0);
    let (hb, l) = LAYERS[i];
    let (tb, pb) = BASES[i];
    let (t, p) = temperature_pressure(h - hb, l, tb, pb);
    let rho = p * MOLAR_MASS / (GAS_CONSTANT * t);
    let (mu, dmu_dt) = sutherland(t);
    // dH/dZ = (r₀/(r₀ + Z))²; dρ/dH = ρ (−g₀M₀/(R* T) − L/T) (hydrostatic, ideal gas).
    let dh_dz = (EARTH_RADIUS_M / (EARTH_RADIUS_M + z)).powi(2);
    AtmosphereState {
        altitude_m: z,
        geopotential_altitude_m: h,
        temperature_k: t,
        pressure_pa: p,
        density_kg_m3: rho,
        viscosity_pa_s: mu,
        density_gradient: -rho * (HYDROSTATIC + l) / t * dh_dz,
        viscosity_gradient: dmu_dt * l * dh_dz,
    }
}

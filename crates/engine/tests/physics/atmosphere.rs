//! The 1976 U.S. Standard Atmosphere against its published values, and the density
//! gradient the drag Jacobians use against differences of ρ(z).
//!
//! References: the standard's own tables (geometric altitude:
//! ρ = 1.2250, 1.1117, 0.73643, 0.36480 kg/m³ and T = 288.15, 281.65, 255.68, 216.77 K at
//! 0, 1, 5 and 11 km), the layer-base pressures of the standard's defining table (at the
//! geopotential altitudes 11, 20, 32, 47, 51, 71 km′: 22 632.1, 5 474.89, 868.019, 110.906,
//! 66.9389, 3.956 42 Pa), its value at 86 km (P = 0.373 38 Pa, ρ = 6.958·10⁻⁶ kg/m³) and
//! the sea-level viscosity μ₀ = 1.7894·10⁻⁵ Pa·s. Each tolerance is half a unit of the last
//! digit quoted.
use engine::aero::atmosphere::{geopotential, isa1976, EARTH_RADIUS_M};
use engine::aero::{Fluid, Profile};

/// `|x − reference| ≤ half a unit in the last of `digits` significant digits`.
fn agrees(x: f64, reference: f64, digits: i32) -> bool {
    let unit = 10f64.powi(reference.abs().log10().floor() as i32 - (digits - 1));
    (x - reference).abs() <= 0.5 * unit
}

#[test]
fn density_and_temperature_match_the_standard_tables() {
    for (z, rho, t) in [
        (0.0, 1.2250, 288.15),
        (1_000.0, 1.1117, 281.65),
        (5_000.0, 0.73643, 255.68),
        (11_000.0, 0.36480, 216.77),
    ] {
        let a = isa1976(z);
        eprintln!(
            "z = {z} m: ρ = {:.6} kg/m³, T = {:.4} K",
            a.density_kg_m3, a.temperature_k
        );
        assert!(
            agrees(a.density_kg_m3, rho, 5),
            "ρ({z}) = {}",
            a.density_kg_m3
        );
        assert!(
            agrees(a.temperature_k, t, 5),
            "T({z}) = {}",
            a.temperature_k
        );
    }
    assert!(agrees(isa1976(0.0).pressure_pa, 101_325.0, 6));
    assert!(agrees(isa1976(0.0).viscosity_pa_s, 1.7894e-5, 5));
}

#[test]
fn layer_bases_and_the_top_match_the_standard() {
    for (h, p) in [
        (11_000.0, 22_632.1),
        (20_000.0, 5_474.89),
        (32_000.0, 868.019),
        (47_000.0, 110.906),
        (51_000.0, 66.9389),
        (71_000.0, 3.95642),
    ] {
        // The geometric altitude of the geopotential altitude h.
        let z = EARTH_RADIUS_M * h / (EARTH_RADIUS_M - h);
        assert!((geopotential(z) - h).abs() < 1e-8 * h);
        let a = isa1976(z);
        assert!(
            agrees(a.pressure_pa, p, 6),
            "P at H = {h}: {}",
            a.pressure_pa
        );
    }
    let top = isa1976(86_000.0);
    assert!(
        agrees(top.pressure_pa, 0.37338, 5),
        "P(86 km) = {}",
        top.pressure_pa
    );
    assert!(
        agrees(top.density_kg_m3, 6.958e-6, 4),
        "ρ(86 km) = {}",
        top.density_kg_m3
    );
}

/// dρ/dz and dμ/dz are the derivatives of ρ(z) and μ(z) (central differences, h = 0.1 m:
/// truncation ~ h² ρ‴/6 relative 1e-11, round-off 1e-16/(h·1e-4) ≈ 1e-11), inside every
/// layer; and `Fluid` hands them on at `altitude + z`.
#[test]
fn gradients_are_the_derivatives() {
    let h = 0.1;
    for z in [
        -500.0, 300.0, 5_000.0, 15_000.0, 25_000.0, 40_000.0, 49_000.0, 60_000.0, 80_000.0,
    ] {
        let a = isa1976(z);
        let fd_rho = (isa1976(z + h).density_kg_m3 - isa1976(z - h).density_kg_m3) / (2.0 * h);
        let fd_mu = (isa1976(z + h).viscosity_pa_s - isa1976(z - h).viscosity_pa_s) / (2.0 * h);
        let e_rho = (a.density_gradient - fd_rho).abs() / a.density_gradient.abs();
        assert!(
            e_rho < 1e-7,
            "dρ/dz at {z}: {} vs {fd_rho}",
            a.density_gradient
        );
        let scale = a.viscosity_pa_s * 1e-5;
        assert!(
            (a.viscosity_gradient - fd_mu).abs() < 1e-7 * scale.max(a.viscosity_gradient.abs())
        );
        let f = Fluid::isa1976(z - 200.0).at(200.0);
        assert_eq!(f.density, a.density_kg_m3);
        assert_eq!(f.density_gradient, a.density_gradient);
    }
    // The isothermal profile: ρ₀ e^{−z/H}.
    let f = Fluid {
        profile: Profile::Exponential { scale_height: 8.0 },
        ..Fluid::air()
    };
    let at = f.at(-4.0);
    assert!((at.density - 1.225 * 0.5f64.exp()).abs() < 1e-15);
    assert!((at.density_gradient + at.density / 8.0).abs() < 1e-15);
}

/// A uniform fluid is its fields, bit for bit.
#[test]
fn uniform_fluid_is_unchanged() {
    let f = Fluid::air();
    let at = f.at(1234.5);
    assert_eq!(at.density.to_bits(), f.density.to_bits());
    assert_eq!(at.viscosity.to_bits(), f.viscosity.to_bits());
    assert_eq!((at.density_gradient, at.viscosity_gradient), (0.0, 0.0));
}

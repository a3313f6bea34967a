//! Air leaking through a permeable fabric (Darcy–Forchheimer) and the split of the normal flow
//! into the part that passes through the fabric and the part that goes around it.
//!
//! Across a fabric of thickness `h`, Darcy permeability `k` (m²) and Forchheimer coefficient
//! `C_F` (–), air passing at the superficial (leakage) speed `u_p` needs the pressure drop
//!
//! `Δp_f(u_p) = h (μ u_p / k + ρ C_F u_p² / √k) = a u_p + b u_p²`, `a = μ h/k`, `b = ρ C_F h/√k`.
//!
//! A drag law whose normal pressure is `Δp = c w²` for the normal speed `w = |u_n|` (m/s)
//! then sees only the flow that goes around the fabric, `Δp = c (w − u_p)²`, and the two
//! pressures are equal: `u_p` is the root of
//!
//! `G(u_p) = a u_p + b u_p² − c (w − u_p)² = 0` on `[0, w]`.
//!
//! **The root exists and is unique** for `a > 0`, `b ≥ 0`, `c ≥ 0`, `w ≥ 0`: `G(0) = −c w² ≤ 0`,
//! `G(w) = a w + b w² ≥ 0`, and `G′(u) = a + 2b u + 2c (w − u) ≥ a > 0` on `[0, w]`, so `G` is
//! strictly increasing there and changes sign once. It is the root
//! `u_p = 2 c w² / (B + √D)`, `B = a + 2cw`, `D = a² + 4acw + 4bcw²` (the larger root of the
//! quadratic, written without cancellation; `D ≥ a² > 0`). The pressure is evaluated as
//! `Δp = a u_p + b u_p²`, accurate also when `u_p → w` (very open fabric), where
//! `c (w − u_p)²` would cancel.
//!
//! **Derivatives** by the implicit function theorem, `∂u_p/∂θ = −G_θ/G_u` with
//! `G_u = a + 2b u_p + 2c (w − u_p) > 0`, and `m = a + 2b u_p`:
//! `∂Δp/∂w = 2c m (w − u_p)/G_u`, `∂Δp/∂c = m (w − u_p)²/G_u`,
//! `∂Δp/∂a = 2c u_p (w − u_p)/G_u`, `∂Δp/∂b = 2c u_p² (w − u_p)/G_u`.
//! See docs/aero.md §Permeability.

use super::fluid::LocalFluid;

/// A permeable fabric: thickness, Darcy permeability and Forchheimer coefficient.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fabric {
    /// Thickness h (m).
    pub thickness: f64,
    /// Darcy permeability k (m²), > 0.
    pub permeability: f64,
    /// Forchheimer coefficient C_F (–), ≥ 0.
    pub forchheimer: f64,
}

impl Fabric {
    /// A fabric of thickness `thickness` (m), permeability `permeability` (m²) and
    /// Forchheimer coefficient `forchheimer` (–).
    pub fn new(thickness: f64, permeability: f64, forchheimer: f64) -> Self {
        Self {
            thickness,
            permeability,
            forchheimer,
        }
    }

    /// `h/k` (1/m): the Darcy coefficient per unit viscosity, `a = μ h/k`.
    pub fn darcy(&self) -> f64 {
        self.thickness / self.permeability
    }

    /// `h C_F/√k` (–): the inertial coefficient per unit density, `b = ρ h C_F/√k`.
    pub fn inertial(&self) -> f64 {
        self.thickness * self.forchheimer / self.permeability.sqrt()
    }

    /// Pressure drop `h (μ u/k + ρ C_F u²/√k)` (Pa) at the leakage speed `u` (m/s, ≥ 0).
    pub fn pressure_drop(&self, u: f64, density: f64, viscosity: f64) -> f64 {
        let (a, b) = (viscosity * self.darcy(), density * self.inertial());
        a * u + b * u * u
    }

    /// Leakage speed (m/s) that the pressure drop `dp` (Pa, ≥ 0) drives through the fabric:
    /// the root of `a u + b u² = Δp`.
    pub fn leakage_at(&self, dp: f64, density: f64, viscosity: f64) -> f64 {
        let (a, b) = (viscosity * self.darcy(), density * self.inertial());
        2.0 * dp / (a + (a * a + 4.0 * b * dp).sqrt())
    }

    /// Darcy permeability (m²) of a fabric of thickness `thickness` (m) that passes air of
    /// viscosity `viscosity` (Pa·s) at the speed `speed` (m/s) under the pressure drop
    /// `pressure_drop` (Pa), from the Darcy term alone: `k = h μ u / Δp`.
    pub fn darcy_permeability(
        thickness: f64,
        viscosity: f64,
        speed: f64,
        pressure_drop: f64,
    ) -> f64 {
        thickness * viscosity * speed / pressure_drop
    }
}

/// The normal pressure with leakage, `Δp` (Pa), and its partial derivatives.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Leakage {
    /// Leakage speed u_p ∈ [0, w] (m/s).
    pub speed: f64,
    /// `Δp = a u_p + b u_p² = c (w − u_p)²` (Pa).
    pub pressure: f64,
    /// `∂Δp/∂w` (Pa·s/m).
    pub d_w: f64,
    /// `∂Δp/∂c` (m²/s²).
    pub d_c: f64,
    /// `∂Δp/∂a` (m/s).
    pub d_a: f64,
    /// `∂Δp/∂b` (m²/s²).
    pub d_b: f64,
}

/// Split the normal speed `w` (m/s, ≥ 0) between leakage and flow around for the drag
/// coefficient `c` (kg/m³, `Δp = c (w − u_p)²`) and the fabric coefficients `a = μ h/k`
/// (Pa·s/m, > 0) and `b = ρ C_F h/√k` (kg/m³, ≥ 0); see the module docs.
#[inline]
pub fn leakage(w: f64, c: f64, a: f64, b: f64) -> Leakage {
    let bb = a + 2.0 * c * w;
    let d = a * a + 4.0 * a * c * w + 4.0 * b * c * w * w;
    let u = 2.0 * c * w * w / (bb + d.sqrt());
    let around = w - u;
    let gu = a + 2.0 * b * u + 2.0 * c * around;
    let m = a + 2.0 * b * u;
    let k = 2.0 * c * around / gu;
    Leakage {
        speed: u,
        pressure: u * (a + b * u),
        d_w: m * k,
        d_c: m * around * around / gu,
        d_a: u * k,
        d_b: u * u * k,
    }
}

/// The split of [`leakage`] for a pressure `c w²` whose coefficient `c` (kg/m³) changes with
/// height at `dc` (kg/m⁴), behind `fabric` in the air `air` (whose ρ and μ set the fabric's
/// coefficients): `Δp` (Pa), `∂Δp/∂w` (Pa·s/m) and `∂Δp/∂z` (Pa/m), the last through `c`,
/// `a = μ h/k` and `b = ρ C_F h/√k` all at once. For laws whose `c` depends on height only
/// through ρ (the per-node pressure and the inflation pressure).
#[inline]
pub(crate) fn leakage_in(
    w: f64,
    c: f64,
    dc: f64,
    air: &LocalFluid,
    fabric: &Fabric,
) -> (f64, f64, f64) {
    let (darcy, inertial) = (fabric.darcy(), fabric.inertial());
    let l = leakage(w, c, air.viscosity * darcy, air.density * inertial);
    let dz = l.d_c * dc
        + l.d_b * inertial * air.density_gradient
        + l.d_a * darcy * air.viscosity_gradient;
    (l.pressure, l.d_w, dz)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The root satisfies both forms of the pressure, lies in [0, w], and the derivatives
    /// match central differences (relative 1e-7) over several decades of openness.
    #[test]
    fn root_and_derivatives() {
        for &(w, c, a, b) in &[
            (3.0, 0.9, 20.0, 0.0),
            (3.0, 0.9, 20.0, 12.0),
            (0.4, 1.1, 0.05, 3.0),
            (7.0, 0.6, 500.0, 40.0),
            (1e-4, 0.7, 2.0, 1.0),
        ] {
            let l = leakage(w, c, a, b);
            assert!((0.0..=w).contains(&l.speed));
            let around = c * (w - l.speed).powi(2);
            assert!((l.pressure - around).abs() <= 1e-12 * l.pressure.max(1e-300) + 1e-15);
            // Steps relative to each parameter's size (b may be 0: step 1e-6 on its O(1)
            // scale keeps the round-off of Δp/h below 1e-9).
            let fd = |f: &dyn Fn(f64) -> f64, x: f64, floor: f64| {
                let h = 1e-6 * x.abs().max(floor);
                (f(x + h) - f(x - h)) / (2.0 * h)
            };
            let checks = [
                (l.d_w, fd(&|x| leakage(x, c, a, b).pressure, w, 1e-3)),
                (l.d_c, fd(&|x| leakage(w, x, a, b).pressure, c, 1e-3)),
                (l.d_a, fd(&|x| leakage(w, c, x, b).pressure, a, 1e-3)),
                (l.d_b, fd(&|x| leakage(w, c, a, x).pressure, b, 1.0)),
            ];
            for (exact, approx) in checks {
                let scale = exact.abs().max(approx.abs()).max(1e-12);
                assert!(
                    (exact - approx).abs() < 1e-6 * scale,
                    "w {w} c {c} a {a} b {b}: {exact} vs {approx}"
                );
            }
        }
    }

    #[test]
    fn inverse_of_the_fabric_law() {
        let f = Fabric::new(1e-4, 5e-11, 0.8);
        for dp in [0.0, 1.0, 14.1, 124.5, 2e3] {
            let u = f.leakage_at(dp, 1.2, 1.8e-5);
            assert!((f.pressure_drop(u, 1.2, 1.8e-5) - dp).abs() <= 1e-12 * dp.max(1.0));
        }
    }
}

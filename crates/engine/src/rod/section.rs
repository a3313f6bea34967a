//! Rod cross-sections and their stiffnesses.
//!
//! The material directors of an edge are `d1 = m1` and `d2 = m2` (see `frames`). For a
//! rectangle, `d1` lies along the width `w` and `d2` along the height (thickness) `h`.
//! "Bending about `d1`" turns the tangent towards `d2`: for a thin strip that is the easy,
//! out-of-plane direction, resisted by `EI1 = E w h³/12`.

use std::f64::consts::PI;

/// A uniform cross-section (lengths in m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Section {
    /// Solid circle of radius `radius` (m).
    Circle {
        /// Radius (m).
        radius: f64,
    },
    /// Solid rectangle: `width` along the first material director `d1`, `height` along `d2`.
    Rectangle {
        /// Extent along `d1` (m).
        width: f64,
        /// Extent along `d2` (m).
        height: f64,
    },
}

impl Section {
    /// Cross-section area `A` (m²): `π r²` or `w h`.
    pub fn area(&self) -> f64 {
        match *self {
            Section::Circle { radius } => PI * radius * radius,
            Section::Rectangle { width, height } => width * height,
        }
    }

    /// Second moment of area about `d1`, `I1 = ∫ y2² dA` (m⁴): `π r⁴/4` or `w h³/12`.
    pub fn i1(&self) -> f64 {
        match *self {
            Section::Circle { radius } => PI * radius.powi(4) / 4.0,
            Section::Rectangle { width, height } => width * height.powi(3) / 12.0,
        }
    }

    /// Second moment of area about `d2`, `I2 = ∫ y1² dA` (m⁴): `π r⁴/4` or `h w³/12`.
    pub fn i2(&self) -> f64 {
        match *self {
            Section::Circle { radius } => PI * radius.powi(4) / 4.0,
            Section::Rectangle { width, height } => height * width.powi(3) / 12.0,
        }
    }

    /// Bending stiffness about `d1`, `EI1 = E I1` (N·m²), for Young's modulus `e` (Pa).
    pub fn ei1(&self, e: f64) -> f64 {
        e * self.i1()
    }

    /// Bending stiffness about `d2`, `EI2 = E I2` (N·m²).
    pub fn ei2(&self, e: f64) -> f64 {
        e * self.i2()
    }

    /// Saint-Venant torsion constant `J` (m⁴).
    ///
    /// Circle: `π r⁴/2` (exact). Rectangle with long side `a` and short side `b`: the exact
    /// series `J = (a b³/3) [1 − (192/π⁵)(b/a) Σ_{n odd} tanh(nπa/2b)/n⁵]`, summed until the
    /// terms are below 1e-16. For a thin strip (`a ≫ b`) it tends to `a b³/3`, the
    /// thin-strip approximation, which overestimates `J` by about `63 % · b/a`.
    pub fn torsion_constant(&self) -> f64 {
        match *self {
            Section::Circle { radius } => PI * radius.powi(4) / 2.0,
            Section::Rectangle { width, height } => {
                let (a, b) = if width >= height {
                    (width, height)
                } else {
                    (height, width)
                };
                let mut sum = 0.0;
                let mut n = 1.0f64;
                loop {
                    let term = (n * PI * a / (2.0 * b)).tanh() / n.powi(5);
                    sum += term;
                    if term < 1e-16 {
                        break;
                    }
                    n += 2.0;
                }
                a * b.powi(3) / 3.0 * (1.0 - 192.0 / PI.powi(5) * (b / a) * sum)
            }
        }
    }

    /// Torsional stiffness `GJ` (N·m²) for shear modulus `g` (Pa).
    pub fn gj(&self, g: f64) -> f64 {
        g * self.torsion_constant()
    }

    /// Polar second moment of area `I1 + I2` (m⁴), which sets the rotary inertia of the
    /// cross-section about the rod axis.
    pub fn polar_moment(&self) -> f64 {
        self.i1() + self.i2()
    }

    /// Rotational inertia per unit length about the axis, `ρ (I1 + I2)` (kg·m²/m), for
    /// density `rho` (kg/m³). An edge of rest length `l̄` gives its twist DOF `ρ (I1+I2) l̄`.
    pub fn polar_inertia_density(&self, rho: f64) -> f64 {
        rho * self.polar_moment()
    }

    /// Check that the dimensions are positive and finite.
    pub fn validate(&self) -> Result<(), SectionError> {
        let ok = |x: f64| x.is_finite() && x > 0.0;
        match *self {
            Section::Circle { radius } if !ok(radius) => Err(SectionError::Radius(radius)),
            Section::Rectangle { width, height } if !(ok(width) && ok(height)) => {
                Err(SectionError::Rectangle { width, height })
            }
            _ => Ok(()),
        }
    }
}

/// A cross-section dimension that is not positive and finite.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum SectionError {
    /// The circle's radius (m).
    #[error("circle radius must be positive, got {0}")]
    Radius(f64),
    /// The rectangle's width and height (m).
    #[error("rectangle width and height must be positive, got {width} × {height}")]
    Rectangle {
        /// Width (m).
        width: f64,
        /// Height (m).
        height: f64,
    },
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn torsion_constant_matches_tables() {
        // Square: J = 0.140577 a⁴ (Timoshenko & Goodier, β = 0.1406 for a/b = 1).
        let sq = Section::Rectangle {
            width: 1.0,
            height: 1.0,
        };
        assert!((sq.torsion_constant() - 0.140577).abs() < 2e-6);
        // a/b = 10: β = 0.312 (tables), J = β a b³.
        let r = Section::Rectangle {
            width: 0.1,
            height: 1.0,
        };
        assert!((r.torsion_constant() / (1.0 * 0.1f64.powi(3)) - 0.3123).abs() < 5e-4);
        let c = Section::Circle { radius: 0.5 };
        assert!((c.gj(2.0) - 2.0 * PI * 0.0625 / 2.0).abs() < 1e-15);
    }

    #[test]
    fn strip_is_soft_about_its_width() {
        let s = Section::Rectangle {
            width: 0.1,
            height: 0.01,
        };
        assert!((s.ei2(1.0) / s.ei1(1.0) - 100.0).abs() < 1e-9);
    }
}

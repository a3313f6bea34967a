//! The whole canopy's normal-force coefficient against incidence, `C_N(α)`, as a table.

use std::f64::consts::FRAC_PI_2;

/// `C_N(α)` of a whole canopy: the force normal to its axis over `q S₀`, positive when it
/// opposes the canopy's sideways motion through the air (restoring, as pure drag would be),
/// against the total angle of attack `α` between the axis and the relative wind (rad).
/// Linear between the tabulated points.
#[derive(Debug, Clone, PartialEq)]
pub struct IncidenceCurve {
    /// Angles of attack (rad), ascending, from 0 to π/2.
    alpha: Vec<f64>,
    /// `C_N` at each angle (–), 0 at α = 0.
    cn: Vec<f64>,
}

/// Why a table is not a usable `C_N(α)`.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CurveError {
    /// Angles and coefficients differ in number, or fewer than two points.
    #[error("needs at least two (α, C_N) points, as many angles as coefficients")]
    Shape,
    /// A value is NaN or infinite.
    #[error("point {0} is not a finite number")]
    NotFinite(usize),
    /// Angles do not increase strictly.
    #[error("the angles must increase strictly (point {0})")]
    NotAscending(usize),
    /// The table leaves part of [−90°, 90°] uncovered.
    #[error("the angles must cover −90° to 90° (they span {lo:.1}° to {hi:.1}°)")]
    Coverage {
        /// First angle (deg).
        lo: f64,
        /// Last angle (deg).
        hi: f64,
    },
    /// `C_N(−α) ≠ −C_N(α)`: an axisymmetric canopy has no preferred side.
    #[error("C_N must be odd, C_N(−α) = −C_N(α) (an axisymmetric canopy has no preferred side): at {alpha_deg}° it is {at} against {mirror}")]
    NotOdd {
        /// The angle checked (deg).
        alpha_deg: f64,
        /// `C_N(α)`.
        at: f64,
        /// `C_N(−α)`.
        mirror: f64,
    },
}

impl IncidenceCurve {
    /// The curve through `(alpha_deg[i], cn[i])`, which must cover −90° to 90° with strictly
    /// increasing angles and be odd (to 1e-9 of its largest value); the law reads its
    /// positive half.
    pub fn try_from_degrees(alpha_deg: &[f64], cn: &[f64]) -> Result<Self, CurveError> {
        if alpha_deg.len() != cn.len() || cn.len() < 2 {
            return Err(CurveError::Shape);
        }
        let bad = |x: &f64| !x.is_finite();
        if let Some(i) = (0..cn.len()).find(|&i| bad(&alpha_deg[i]) || bad(&cn[i])) {
            return Err(CurveError::NotFinite(i));
        }
        if let Some(i) = (1..cn.len()).find(|&i| alpha_deg[i] <= alpha_deg[i - 1]) {
            return Err(CurveError::NotAscending(i));
        }
        let (lo, hi) = (alpha_deg[0], alpha_deg[cn.len() - 1]);
        if lo > -90.0 || hi < 90.0 {
            return Err(CurveError::Coverage { lo, hi });
        }
        let whole = Self {
            alpha: alpha_deg.iter().map(|a| a.to_radians()).collect(),
            cn: cn.to_vec(),
        };
        let scale = cn.iter().fold(0.0_f64, |m, c| m.max(c.abs()));
        for &a in alpha_deg {
            let (at, mirror) = (whole.lookup(a.to_radians()), whole.lookup(-a.to_radians()));
            if (at + mirror).abs() > 1e-9 * scale.max(1e-300) {
                return Err(CurveError::NotOdd {
                    alpha_deg: a,
                    at,
                    mirror,
                });
            }
        }
        let keep: Vec<usize> = (0..cn.len()).filter(|&i| alpha_deg[i] >= 0.0).collect();
        let mut alpha: Vec<f64> = keep.iter().map(|&i| whole.alpha[i]).collect();
        let mut values: Vec<f64> = keep.iter().map(|&i| cn[i]).collect();
        if alpha[0] > 0.0 {
            alpha.insert(0, 0.0);
            values.insert(0, 0.0);
        }
        Ok(Self { alpha, cn: values })
    }

    /// `C_N` at the total angle of attack `alpha` (rad, ≥ 0); beyond π/2 (the wind from
    /// behind the canopy) the value at π/2.
    pub fn at(&self, alpha: f64) -> f64 {
        self.lookup(alpha.clamp(0.0, FRAC_PI_2))
    }

    /// Linear interpolation in the table (clamped at its ends).
    fn lookup(&self, a: f64) -> f64 {
        let n = self.alpha.len();
        let j = self.alpha.partition_point(|&x| x <= a).clamp(1, n - 1);
        let (a0, a1) = (self.alpha[j - 1], self.alpha[j]);
        let t = ((a - a0) / (a1 - a0)).clamp(0.0, 1.0);
        self.cn[j - 1] + t * (self.cn[j] - self.cn[j - 1])
    }

    /// The tabulated angles (rad) and coefficients of the positive half.
    pub fn points(&self) -> (&[f64], &[f64]) {
        (&self.alpha, &self.cn)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn odd(a: &[f64], c: &[f64]) -> Result<IncidenceCurve, CurveError> {
        IncidenceCurve::try_from_degrees(a, c)
    }

    #[test]
    fn interpolates_the_positive_half_and_clamps_past_ninety() {
        let c = odd(
            &[-90.0, -30.0, 0.0, 30.0, 90.0],
            &[0.4, 0.1, 0.0, -0.1, -0.4],
        )
        .unwrap();
        assert_eq!(c.at(0.0), 0.0);
        assert!((c.at(15f64.to_radians()) + 0.05).abs() < 1e-12);
        assert!((c.at(60f64.to_radians()) + 0.25).abs() < 1e-12);
        assert_eq!(c.at(2.0), c.at(FRAC_PI_2));
    }

    #[test]
    fn refuses_tables_that_do_not_describe_an_axisymmetric_canopy() {
        assert_eq!(
            odd(&[-45.0, 0.0, 90.0], &[0.1, 0.0, -0.2]),
            Err(CurveError::Coverage {
                lo: -45.0,
                hi: 90.0
            })
        );
        assert_eq!(
            odd(&[-90.0, 0.0, 0.0, 90.0], &[0.0; 4]),
            Err(CurveError::NotAscending(2))
        );
        assert!(matches!(
            odd(&[-90.0, 0.0, 90.0], &[0.3, 0.0, -0.2]),
            Err(CurveError::NotOdd { .. })
        ));
        assert_eq!(odd(&[-90.0, 90.0], &[0.0]), Err(CurveError::Shape));
        assert_eq!(
            odd(&[-90.0, f64::NAN], &[0.0, 0.0]),
            Err(CurveError::NotFinite(1))
        );
    }
}

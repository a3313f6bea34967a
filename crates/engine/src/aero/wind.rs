//! Wind that varies with height: `U(z)` and its rate `dU/dz`.
//!
//! Drag acts on `v − U(z_e)` at each element's own height `z_e` (a node's z, a triangle's
//! centroid), so a sheared wind adds `−(∂F/∂u)(dU/dz)(∂z_e/∂q)` to the position Jacobian
//! (`add_shear`), as the density's `∂ρ/∂z` does. The profiles (docs/aero.md §Wind that varies with height):
//! - uniform: [`super::Fluid::wind`] everywhere;
//! - power law `U = U_ref (h/h_ref)^α` and logarithmic law `U = U_ref ln(h/z₀)/ln(h_ref/z₀)`
//!   of the height `h` above the ground, with `U_ref` = [`super::Fluid::wind`] (the
//!   atmospheric boundary layer's standard forms: e.g. Stull, *An Introduction to Boundary
//!   Layer Meteorology*, 1988, §9.7);
//! - a table of horizontal winds against height, interpolated by monotone cubic Hermite
//!   splines (Fritsch & Carlson, SIAM J. Numer. Anal. 17(2), 1980): continuous `dU/dz`, as
//!   Newton's quadratic convergence wants, and no overshoot between the measured values.

use std::sync::Arc;

use crate::force::BlockMut;

/// The wind at one height: velocity `U` (m/s) and its rate of change with height `dU/dz`
/// (1/s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LocalWind {
    /// `U` (m/s).
    pub velocity: [f64; 3],
    /// `dU/dz` (1/s).
    pub shear: [f64; 3],
}

/// How the wind varies with the model's height z (m).
#[derive(Debug, Clone, PartialEq, Default)]
pub enum WindProfile {
    /// [`super::Fluid::wind`] at every height.
    #[default]
    Uniform,
    /// `U = U_ref (h/h_ref)^α` with `h = z − ground` (0 at and below the ground).
    Power {
        /// Height `h_ref` above the ground at which the wind is `U_ref` (m, > 0).
        reference_height: f64,
        /// Exponent `α` (> 0; about 1/7 over open country).
        exponent: f64,
        /// Model height of the ground (m).
        ground: f64,
    },
    /// `U = U_ref ln(h/z₀)/ln(h_ref/z₀)` with `h = z − ground` (0 at and below `h = z₀`).
    Log {
        /// Height `h_ref` above the ground at which the wind is `U_ref` (m, > `roughness`).
        reference_height: f64,
        /// Roughness length `z₀` (m, > 0; about 0.03 m over open grass).
        roughness: f64,
        /// Model height of the ground (m).
        ground: f64,
    },
    /// Horizontal winds at tabulated heights ([`WindTable`]); [`super::Fluid::wind`] is not
    /// used.
    Table(Arc<WindTable>),
}

/// Why a wind table was refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum WindTableError {
    /// Fewer than two heights.
    #[error("a wind table needs at least two heights, got {0}")]
    TooShort(usize),
    /// Heights not strictly increasing, or not finite.
    #[error("heights must be finite and strictly increasing: row {row} ({z} m) is not above the one before")]
    NotIncreasing {
        /// 0-based row.
        row: usize,
        /// Its height (m).
        z: f64,
    },
    /// A wind component that is not finite.
    #[error("row {row}: the wind is not finite")]
    NotFinite {
        /// 0-based row.
        row: usize,
    },
}

/// Horizontal winds `(u_x, u_y)` at heights `z` (model frame), with the Fritsch–Carlson
/// slopes of each component; below the first and above the last height the wind is that
/// of the end row, and the end slopes are 0 so that `dU/dz` stays continuous there.
#[derive(Debug, Clone, PartialEq)]
pub struct WindTable {
    z: Vec<f64>,
    u: Vec<[f64; 2]>,
    slope: Vec<[f64; 2]>,
}

impl WindTable {
    /// The table of `rows` `(z, u_x, u_y)` (m, m/s, m/s), heights strictly increasing.
    pub fn try_new(rows: &[[f64; 3]]) -> Result<Self, WindTableError> {
        if rows.len() < 2 {
            return Err(WindTableError::TooShort(rows.len()));
        }
        for (row, r) in rows.iter().enumerate() {
            if !r[1].is_finite() || !r[2].is_finite() {
                return Err(WindTableError::NotFinite { row });
            }
            let above = row == 0 || r[0] > rows[row - 1][0];
            if !r[0].is_finite() || !above {
                return Err(WindTableError::NotIncreasing { row, z: r[0] });
            }
        }
        let z: Vec<f64> = rows.iter().map(|r| r[0]).collect();
        let u: Vec<[f64; 2]> = rows.iter().map(|r| [r[1], r[2]]).collect();
        let mut slope = vec![[0.0; 2]; z.len()];
        for k in 0..2 {
            let d: Vec<f64> = (0..z.len() - 1)
                .map(|i| (u[i + 1][k] - u[i][k]) / (z[i + 1] - z[i]))
                .collect();
            for i in 1..z.len() - 1 {
                slope[i][k] = monotone_slope(d[i - 1], d[i]);
            }
        }
        Ok(Self { z, u, slope })
    }

    /// The wind and its rate at height `z`.
    fn at(&self, z: f64) -> LocalWind {
        let last = self.z.len() - 1;
        let held = |i: usize| LocalWind {
            velocity: [self.u[i][0], self.u[i][1], 0.0],
            shear: [0.0; 3],
        };
        if z <= self.z[0] {
            return held(0);
        }
        if z >= self.z[last] {
            return held(last);
        }
        let i = self.z.partition_point(|&zi| zi <= z) - 1;
        let h = self.z[i + 1] - self.z[i];
        let t = (z - self.z[i]) / h;
        // Cubic Hermite basis and its derivative in t.
        let (t2, t3) = (t * t, t * t * t);
        let b = [
            2.0 * t3 - 3.0 * t2 + 1.0,
            t3 - 2.0 * t2 + t,
            -2.0 * t3 + 3.0 * t2,
            t3 - t2,
        ];
        let db = [
            6.0 * t2 - 6.0 * t,
            3.0 * t2 - 4.0 * t + 1.0,
            -6.0 * t2 + 6.0 * t,
            3.0 * t2 - 2.0 * t,
        ];
        let mut out = LocalWind {
            velocity: [0.0; 3],
            shear: [0.0; 3],
        };
        for k in 0..2 {
            let p = [
                self.u[i][k],
                h * self.slope[i][k],
                self.u[i + 1][k],
                h * self.slope[i + 1][k],
            ];
            out.velocity[k] = (0..4).map(|j| b[j] * p[j]).sum();
            out.shear[k] = (0..4).map(|j| db[j] * p[j]).sum::<f64>() / h;
        }
        out
    }
}

/// Fritsch–Carlson slope at an interior knot from the secants on either side: the harmonic
/// mean when they have one sign, 0 at an extremum (no overshoot).
fn monotone_slope(left: f64, right: f64) -> f64 {
    if left * right <= 0.0 {
        0.0
    } else {
        2.0 * left * right / (left + right)
    }
}

impl WindProfile {
    /// Whether the wind is the same at every height (no shear terms).
    pub fn is_uniform(&self) -> bool {
        *self == WindProfile::Uniform
    }

    /// The wind at model height `z` (m), with `reference` the wind `U_ref` of the profile
    /// laws (for [`WindProfile::Uniform`], the wind itself, bit for bit, with zero shear).
    pub fn at(&self, reference: [f64; 3], z: f64) -> LocalWind {
        let scaled = |(f, df): (f64, f64)| LocalWind {
            velocity: reference.map(|u| u * f),
            shear: reference.map(|u| u * df),
        };
        match self {
            WindProfile::Uniform => LocalWind {
                velocity: reference,
                shear: [0.0; 3],
            },
            &WindProfile::Power {
                reference_height,
                exponent,
                ground,
            } => {
                let h = z - ground;
                scaled(if h > 0.0 {
                    let f = (h / reference_height).powf(exponent);
                    (f, exponent * f / h)
                } else {
                    (0.0, 0.0)
                })
            }
            &WindProfile::Log {
                reference_height,
                roughness,
                ground,
            } => {
                let h = z - ground;
                let scale = (reference_height / roughness).ln();
                scaled(if h > roughness {
                    ((h / roughness).ln() / scale, 1.0 / (h * scale))
                } else {
                    (0.0, 0.0)
                })
            }
            WindProfile::Table(t) => t.at(z),
        }
    }
}

/// Add the shear terms of a wind taken at the mean height of a stencil's `nodes` nodes to
/// the position Jacobian: a law whose velocities enter only as `v_i − U(z̄)`, with
/// `z̄ = Σ z_k / nodes`, has `∂F/∂z_k ∋ −(1/nodes) Σ_i (∂F/∂v_i) dU/dz`. `b.dfdv` must hold
/// the law's complete velocity Jacobian and `b.dfdq` its position Jacobian without them.
pub(crate) fn add_shear(b: &mut BlockMut<'_>, nodes: usize, shear: [f64; 3]) {
    if shear == [0.0; 3] {
        return;
    }
    let k = 3 * nodes;
    for r in 0..k {
        let row = &b.dfdv[r * k..(r + 1) * k];
        let t: f64 = row
            .chunks_exact(3)
            .map(|c| c[0] * shear[0] + c[1] * shear[1] + c[2] * shear[2])
            .sum();
        for node in 0..nodes {
            b.dfdq[r * k + 3 * node + 2] -= t / nodes as f64;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Central differences of `U(z)` against `dU/dz` at `z`.
    fn check_rate(p: &WindProfile, reference: [f64; 3], z: f64) {
        let h = 1e-6 * (1.0 + z.abs());
        let (up, um) = (p.at(reference, z + h), p.at(reference, z - h));
        let w = p.at(reference, z);
        for k in 0..3 {
            let fd = (up.velocity[k] - um.velocity[k]) / (2.0 * h);
            assert!(
                (fd - w.shear[k]).abs() <= 1e-7 * (1.0 + fd.abs()),
                "{p:?} z {z}: {fd} vs {}",
                w.shear[k]
            );
        }
    }

    #[test]
    fn laws_pass_their_reference_wind_and_have_exact_rates() {
        let u = [4.0, -2.0, 0.0];
        let power = WindProfile::Power {
            reference_height: 10.0,
            exponent: 1.0 / 7.0,
            ground: -30.0,
        };
        let log = WindProfile::Log {
            reference_height: 10.0,
            roughness: 0.03,
            ground: -30.0,
        };
        for p in [&power, &log] {
            let at_ref = p.at(u, -20.0).velocity;
            for k in 0..3 {
                assert!((at_ref[k] - u[k]).abs() < 1e-12, "{p:?}: {at_ref:?}");
            }
            assert_eq!(p.at(u, -31.0).velocity, [0.0; 3]);
            for z in [-29.5, -20.0, -5.0, 40.0] {
                check_rate(p, u, z);
            }
        }
        // The 1/7 law doubles the wind 128 times higher.
        let w = power.at(u, -30.0 + 1280.0).velocity[0];
        assert!((w - 8.0).abs() < 1e-12, "{w}");
        assert_eq!(
            WindProfile::Uniform.at(u, 7.0),
            LocalWind {
                velocity: u,
                shear: [0.0; 3]
            }
        );
    }

    #[test]
    fn a_table_passes_its_rows_without_overshoot_with_a_continuous_rate() {
        let rows = [
            [0.0, 2.0, 0.0],
            [10.0, 5.0, 1.0],
            [20.0, 5.5, 3.0],
            [40.0, 3.0, 3.0],
        ];
        let p = WindProfile::Table(Arc::new(WindTable::try_new(&rows).unwrap()));
        for r in &rows {
            let w = p.at([9.0; 3], r[0]).velocity;
            assert!(
                (w[0] - r[1]).abs() < 1e-12 && (w[1] - r[2]).abs() < 1e-12,
                "{w:?}"
            );
        }
        // Between rows 2 and 3 the x-wind falls from 5.5 to 3: no value outside [3, 5.5].
        for i in 0..=100 {
            let z = 20.0 + 0.2 * i as f64;
            let x = p.at([0.0; 3], z).velocity[0];
            assert!((3.0 - 1e-12..=5.5 + 1e-12).contains(&x), "{z}: {x}");
        }
        for z in [-1.0, 3.0, 15.0, 33.0, 50.0] {
            check_rate(&p, [0.0; 3], z);
        }
        // dU/dz is continuous at every row, the ends included (held wind beyond them).
        for r in &rows {
            let (below, above) = (p.at([0.0; 3], r[0] - 1e-9), p.at([0.0; 3], r[0] + 1e-9));
            for k in 0..2 {
                assert!(
                    (below.shear[k] - above.shear[k]).abs() < 1e-6,
                    "{r:?}: {below:?} {above:?}"
                );
            }
        }
    }

    #[test]
    fn bad_tables_are_refused() {
        use WindTableError::*;
        assert_eq!(WindTable::try_new(&[[0.0, 1.0, 1.0]]), Err(TooShort(1)));
        let e = WindTable::try_new(&[[0.0, 1.0, 1.0], [0.0, 2.0, 1.0]]);
        assert_eq!(e, Err(NotIncreasing { row: 1, z: 0.0 }));
        let e = WindTable::try_new(&[[0.0, 1.0, 1.0], [1.0, f64::NAN, 1.0]]);
        assert_eq!(e, Err(NotFinite { row: 1 }));
    }
}

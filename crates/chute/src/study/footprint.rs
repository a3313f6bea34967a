//! The landing footprint of a dispersion study: the mean landing point, the sample covariance
//! and its 1σ/2σ/3σ ellipses, the circular error probable, and which inputs drive the spread.
//!
//! - Covariance: the unbiased sample covariance `S = Σ (p − p̄)(p − p̄)ᵀ/(n − 1)`.
//! - Ellipse kσ: semi-axes `k√λ₁`, `k√λ₂` of the eigenvalues of `S`, the major axis at
//!   `θ = ½ atan2(2 s_xy, s_xx − s_yy)` from +x (for a normal footprint the kσ ellipse holds
//!   `1 − e^{−k²/2}` of the landings: 39 %, 86 %, 99 %).
//! - CEP50, CEP90: the radii about the mean point within which 50 % and 90 % of the landings
//!   lie (empirical quantiles, linear between order statistics).
//! - Sensitivity: Pearson's correlation of each input with the landing's x and y; inputs are
//!   ranked by `r_x² + r_y²`, the share of the landing's variance a linear fit in that input
//!   alone explains when x and y are uncorrelated.

/// The footprint of a set of landing points.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Footprint {
    /// Number of landings.
    pub samples: usize,
    /// The mean landing point `[x, y]` (m).
    pub mean_m: [f64; 2],
    /// The sample covariance `[s_xx, s_xy, s_yy]` (m²).
    pub covariance_m2: [f64; 3],
    /// The 1σ, 2σ and 3σ ellipses.
    pub ellipses: [Ellipse; 3],
    /// Radius about the mean holding half of the landings (m).
    pub cep50_m: f64,
    /// Radius about the mean holding 90 % of the landings (m).
    pub cep90_m: f64,
}

/// One covariance ellipse.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Ellipse {
    /// `k` of the kσ ellipse.
    pub sigma: f64,
    /// Semi-major axis (m).
    pub semi_major_m: f64,
    /// Semi-minor axis (m).
    pub semi_minor_m: f64,
    /// Direction of the major axis from +x towards +y (degrees, in (−90, 90]).
    pub angle_deg: f64,
}

/// One input's share in the spread.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Sensitivity {
    /// The varied key.
    pub key: String,
    /// Correlation with the landing's x.
    pub r_x: f64,
    /// Correlation with the landing's y.
    pub r_y: f64,
}

/// The footprint of the first `samples` landings: how its statistics settle as N grows.
/// Standard errors are the normal-theory ones: the mean's `√(s_xx/n)`, `√(s_yy/n)`; a 1σ
/// semi-axis `a`'s `a/√(2(n − 1))`.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Settling {
    /// Number of landings (the first ones, in sample order).
    pub samples: usize,
    /// Their mean point (m).
    pub mean_m: [f64; 2],
    /// Standard error of the mean's x and y (m).
    pub mean_standard_error_m: [f64; 2],
    /// The 1σ ellipse's semi-axes, major then minor (m).
    pub semi_axes_m: [f64; 2],
    /// Standard error of each semi-axis (m).
    pub semi_axes_standard_error_m: [f64; 2],
    /// Radius about the mean holding half of these landings (m).
    pub cep50_m: f64,
}

/// The footprints of the first N/4, N/2 and all N of `points` (those with two or more).
pub fn settling(points: &[[f64; 2]]) -> Vec<Settling> {
    let n = points.len();
    let mut sizes = vec![n / 4, n / 2, n];
    sizes.dedup();
    sizes
        .into_iter()
        .filter_map(|k| {
            let f = footprint(&points[..k])?;
            let kf = k as f64;
            let axes = [f.ellipses[0].semi_major_m, f.ellipses[0].semi_minor_m];
            Some(Settling {
                samples: k,
                mean_m: f.mean_m,
                mean_standard_error_m: [0, 2].map(|i| (f.covariance_m2[i] / kf).sqrt()),
                semi_axes_m: axes,
                semi_axes_standard_error_m: axes.map(|a| a / (2.0 * (kf - 1.0)).sqrt()),
                cep50_m: f.cep50_m,
            })
        })
        .collect()
}

/// The footprint of `points`, or `None` for fewer than two.
pub fn footprint(points: &[[f64; 2]]) -> Option<Footprint> {
    let n = points.len();
    if n < 2 {
        return None;
    }
    let nf = n as f64;
    let mean = [0, 1].map(|k| points.iter().map(|p| p[k]).sum::<f64>() / nf);
    let moment = |a: usize, b: usize| {
        points
            .iter()
            .map(|p| (p[a] - mean[a]) * (p[b] - mean[b]))
            .sum::<f64>()
            / (nf - 1.0)
    };
    let (sxx, sxy, syy) = (moment(0, 0), moment(0, 1), moment(1, 1));
    let half = 0.5 * (sxx + syy);
    let root = (0.25 * (sxx - syy).powi(2) + sxy * sxy).sqrt();
    let (l1, l2) = (half + root, (half - root).max(0.0));
    let angle = 0.5 * (2.0 * sxy).atan2(sxx - syy);
    let ellipses = [1.0, 2.0, 3.0].map(|k| Ellipse {
        sigma: k,
        semi_major_m: k * l1.sqrt(),
        semi_minor_m: k * l2.sqrt(),
        angle_deg: angle.to_degrees(),
    });
    let mut radii: Vec<f64> = points
        .iter()
        .map(|p| (p[0] - mean[0]).hypot(p[1] - mean[1]))
        .collect();
    radii.sort_by(f64::total_cmp);
    Some(Footprint {
        samples: n,
        mean_m: mean,
        covariance_m2: [sxx, sxy, syy],
        ellipses,
        cep50_m: quantile(&radii, 0.5),
        cep90_m: quantile(&radii, 0.9),
    })
}

/// The `q` quantile of sorted `v`, linear between order statistics (Hyndman & Fan type 7).
fn quantile(v: &[f64], q: f64) -> f64 {
    let h = q * (v.len() - 1) as f64;
    let (i, f) = (h.floor() as usize, h.fract());
    match v.get(i + 1) {
        Some(next) => v[i] + f * (next - v[i]),
        None => v[i],
    }
}

/// Pearson's correlation of `a` and `b` (0 when either is constant).
fn correlation(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len() as f64;
    let (ma, mb) = (a.iter().sum::<f64>() / n, b.iter().sum::<f64>() / n);
    let cov: f64 = a.iter().zip(b).map(|(x, y)| (x - ma) * (y - mb)).sum();
    let va: f64 = a.iter().map(|x| (x - ma).powi(2)).sum();
    let vb: f64 = b.iter().map(|y| (y - mb).powi(2)).sum();
    match va > 0.0 && vb > 0.0 {
        true => cov / (va * vb).sqrt(),
        false => 0.0,
    }
}

/// The inputs `(key, values)` ranked by how much of the landing points' spread each explains
/// alone (`r_x² + r_y²`, largest first).
pub fn sensitivity(inputs: &[(String, Vec<f64>)], points: &[[f64; 2]]) -> Vec<Sensitivity> {
    let (x, y): (Vec<f64>, Vec<f64>) = points.iter().map(|p| (p[0], p[1])).unzip();
    let mut out: Vec<Sensitivity> = inputs
        .iter()
        .map(|(key, v)| Sensitivity {
            key: key.clone(),
            r_x: correlation(v, &x),
            r_y: correlation(v, &y),
        })
        .collect();
    let share = |s: &Sensitivity| s.r_x * s.r_x + s.r_y * s.r_y;
    out.sort_by(|a, b| share(b).total_cmp(&share(a)));
    out
}

#[cfg(test)]
mod tests {
    use super::super::draw::{Distribution, Sampler};
    use super::*;

    #[test]
    fn a_square_and_a_circle_have_their_exact_footprints() {
        let square = [[1.0, 1.0], [-1.0, 1.0], [-1.0, -1.0], [1.0, -1.0]];
        let f = footprint(&square).unwrap();
        assert_eq!(f.mean_m, [0.0, 0.0]);
        // s_xx = s_yy = 4/3, s_xy = 0: a circle of radius 2/√3 at 1σ.
        assert_eq!(f.covariance_m2, [4.0 / 3.0, 0.0, 4.0 / 3.0]);
        let r = (4.0f64 / 3.0).sqrt();
        assert!((f.ellipses[1].semi_major_m - 2.0 * r).abs() < 1e-15);
        assert!((f.ellipses[1].semi_minor_m - 2.0 * r).abs() < 1e-15);
        assert!((f.cep50_m - 2f64.sqrt()).abs() < 1e-15);
        let ring: Vec<[f64; 2]> = (0..36)
            .map(|k| {
                let a = k as f64 * 10f64.to_radians();
                [5.0 + 3.0 * a.cos(), -2.0 + 3.0 * a.sin()]
            })
            .collect();
        let f = footprint(&ring).unwrap();
        assert!(
            (f.cep50_m - 3.0).abs() < 1e-12 && (f.cep90_m - 3.0).abs() < 1e-12,
            "{f:?}"
        );
        assert!(footprint(&ring[..1]).is_none());
    }

    #[test]
    fn a_tilted_normal_cloud_gives_its_ellipse_and_cep() {
        // x' ~ N(0, 4²) along 30°, y' ~ N(0, 1) across it: 1σ ellipse 4 × 1 m at 30°; for a
        // circular normal the CEP50 is 1.1774 σ, here checked for the circular case below.
        let n = 20_000;
        let normal = Distribution::try_normal(0.0, 1.0, f64::NEG_INFINITY, f64::INFINITY).unwrap();
        let draws = Sampler {
            seed: 11,
            samples: n,
            latin_hypercube: false,
        }
        .draw_all(&[normal, normal]);
        let th = 30f64.to_radians();
        let tilted: Vec<[f64; 2]> = draws
            .iter()
            .map(|d| {
                let (a, b) = (4.0 * d[0], d[1]);
                [a * th.cos() - b * th.sin(), a * th.sin() + b * th.cos()]
            })
            .collect();
        let f = footprint(&tilted).unwrap();
        // Standard errors: an axis σ̂ has relative error ≈ 1/√(2n) = 0.5 %; 5 of them.
        let e = &f.ellipses[0];
        assert!((e.semi_major_m / 4.0 - 1.0).abs() < 0.025, "{e:?}");
        assert!((e.semi_minor_m - 1.0).abs() < 0.025, "{e:?}");
        assert!((e.angle_deg - 30.0).abs() < 1.0, "{e:?}");
        let round: Vec<[f64; 2]> = draws.iter().map(|d| [d[0], d[1]]).collect();
        let f = footprint(&round).unwrap();
        // Rayleigh radius: CEP50 = σ√(2 ln 2), CEP90 = σ√(2 ln 10); the sample quantile's
        // relative standard error is below 1 % at n = 20 000.
        let (c50, c90) = ((2.0 * 2f64.ln()).sqrt(), (2.0 * 10f64.ln()).sqrt());
        assert!((f.cep50_m / c50 - 1.0).abs() < 0.03, "{}", f.cep50_m);
        assert!((f.cep90_m / c90 - 1.0).abs() < 0.03, "{}", f.cep90_m);
    }

    /// The settling table is the footprint of each prefix, and its standard errors shrink
    /// as 1/√n; on normal draws each prefix's axes lie within 5 standard errors of the truth.
    #[test]
    fn settling_is_the_footprint_of_each_prefix() {
        let normal = Distribution::try_normal(0.0, 1.0, f64::NEG_INFINITY, f64::INFINITY).unwrap();
        let d = Sampler {
            seed: 4,
            samples: 400,
            latin_hypercube: false,
        }
        .draw_all(&[normal, normal]);
        let points: Vec<[f64; 2]> = d.iter().map(|v| [30.0 * v[0], 10.0 * v[1]]).collect();
        let table = settling(&points);
        assert_eq!(
            table.iter().map(|s| s.samples).collect::<Vec<_>>(),
            [100, 200, 400]
        );
        for s in &table {
            let f = footprint(&points[..s.samples]).unwrap();
            assert_eq!(s.mean_m, f.mean_m);
            assert_eq!(s.cep50_m, f.cep50_m);
            for (k, truth) in [30.0, 10.0].into_iter().enumerate() {
                let err = (s.semi_axes_m[k] - truth).abs();
                assert!(err < 5.0 * s.semi_axes_standard_error_m[k], "{s:?}");
            }
        }
        let ratio = table[0].mean_standard_error_m[0] / table[2].mean_standard_error_m[0];
        assert!((ratio - 2.0).abs() < 0.3, "1/√n: {ratio}");
        assert!(settling(&points[..1]).is_empty());
    }

    #[test]
    fn the_input_that_moves_the_landing_ranks_first() {
        let n = 2000;
        let u = Distribution::try_uniform(0.0, 1.0).unwrap();
        let d = Sampler {
            seed: 2,
            samples: n,
            latin_hypercube: true,
        }
        .draw_all(&[u, u, u]);
        // x driven by input 1, y weakly by input 2, input 0 irrelevant.
        let points: Vec<[f64; 2]> = d
            .iter()
            .map(|v| [10.0 * v[1], 0.5 * v[2] + 0.1 * v[1]])
            .collect();
        let inputs: Vec<(String, Vec<f64>)> = (0..3)
            .map(|k| (format!("in{k}"), d.iter().map(|v| v[k]).collect()))
            .collect();
        let ranked = sensitivity(&inputs, &points);
        let order: Vec<&str> = ranked.iter().map(|s| s.key.as_str()).collect();
        assert_eq!(order, ["in1", "in2", "in0"]);
        assert!(
            ranked[0].r_x > 0.99 && ranked[2].r_x.abs() < 0.1,
            "{ranked:?}"
        );
    }
}

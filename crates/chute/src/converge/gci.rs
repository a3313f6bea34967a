//! The arithmetic of solution verification (Celik et al., "Procedure for estimation and
//! reporting of uncertainty due to discretization in CFD applications", J. Fluids Eng. 130,
//! 078001, 2008): apparent order, Richardson extrapolation, relative errors, the fine-level
//! grid convergence index (GCI) and a verdict. Pure functions; see docs/convergence.md.
//!
//! Notation (finest level first): φ₁, φ₂, φ₃ the values on representative sizes
//! h₁ < h₂ < h₃, r₂₁ = h₂/h₁, r₃₂ = h₃/h₂, ε₂₁ = φ₂ − φ₁, ε₃₂ = φ₃ − φ₂.

use serde::Serialize;

/// Safety factor of the GCI with an observed order (three or more levels).
pub const FS_OBSERVED: f64 = 1.25;
/// Safety factor of the GCI with an assumed (formal) order (two levels).
pub const FS_ASSUMED: f64 = 3.0;

/// How a quantity behaves under refinement.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Verdict {
    /// Differences shrink without changing sign: 0 ≤ R < R_max (see [`three_levels`]).
    Monotone,
    /// Differences shrink and alternate in sign: −R_max < R < 0.
    Oscillatory,
    /// The finer difference does not shrink with h at any positive order: |R| ≥ R_max.
    Divergent,
    /// The finest difference is below what the Newton tolerance can resolve.
    RoundOff,
}

impl Verdict {
    /// The word used in convergence.json and convergence.md.
    pub fn as_str(self) -> &'static str {
        match self {
            Verdict::Monotone => "monotone",
            Verdict::Oscillatory => "oscillatory",
            Verdict::Divergent => "divergent",
            Verdict::RoundOff => "round-off",
        }
    }
}

/// The estimate for one quantity from its finest two or three levels.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Estimate {
    /// The behaviour under refinement.
    pub verdict: Verdict,
    /// Apparent order p from three levels; `None` with two levels, round-off or divergence.
    pub observed_order: Option<f64>,
    /// The order the extrapolation and GCI used: observed, or the formal one with two levels.
    pub order_used: Option<f64>,
    /// Safety factor of the GCI (1.25 observed, 3 assumed).
    pub safety_factor: f64,
    /// Richardson extrapolation φ_ext (round-off: φ₁).
    pub extrapolated: Option<f64>,
    /// e_a = |(φ₁ − φ₂)/φ₁|.
    pub approximate_error: f64,
    /// e_ext = |(φ_ext − φ₁)/φ_ext|.
    pub extrapolated_error: Option<f64>,
    /// GCI_fine = Fs e_a / (r₂₁^p − 1); round-off: the resolution itself; divergent: the
    /// range band 3 max(|φ₁ − φ₂|, |φ₁ − φ₃|)/|φ₁|.
    pub gci: Option<f64>,
}

/// Apparent order by Celik's fixed-point iteration
/// p = |ln|ε₃₂/ε₂₁| + q(p)| / ln r₂₁, q(p) = ln((r₂₁^p − s)/(r₃₂^p − s)), s = sign(ε₃₂/ε₂₁);
/// `None` when it does not converge (or an argument of a logarithm is not positive). The
/// start is Celik's q = 0 value, or p = 1 when that is below 0.1.
pub fn apparent_order(r21: f64, r32: f64, e21: f64, e32: f64) -> Option<f64> {
    if !(r21 > 1.0 && r32 > 1.0 && e21 != 0.0 && e32 != 0.0) {
        return None;
    }
    let s = (e32 / e21).signum();
    let ln_ratio = (e32 / e21).abs().ln();
    // Celik starts from q = 0; on non-uniform levels that start can be p ≈ 0, where q(p) is
    // undefined (r^p − 1 → 0), so start from first order there.
    let mut p = (ln_ratio / r21.ln()).abs();
    if p < 0.1 {
        p = 1.0;
    }
    for _ in 0..1000 {
        let (a, b) = (r21.powf(p) - s, r32.powf(p) - s);
        if !(a > 0.0 && b > 0.0) {
            return None;
        }
        let next = ((ln_ratio + (a / b).ln()) / r21.ln()).abs();
        if !next.is_finite() {
            return None;
        }
        if (next - p).abs() <= 1e-12 * next.max(1.0) {
            return Some(next);
        }
        p = next;
    }
    None
}

/// Richardson extrapolation from the finest pair: (r^p φ₁ − φ₂)/(r^p − 1).
pub fn richardson(r21: f64, p: f64, phi1: f64, phi2: f64) -> f64 {
    let rp = r21.powf(p);
    (rp * phi1 - phi2) / (rp - 1.0)
}

/// The GCI of a level from the next coarser one, at order `p` and safety factor `fs`:
/// Fs |(φ_f − φ_c)/φ_f| / ((h_c/h_f)^p − 1). With the pair (1, 2) it is [`Estimate::gci`];
/// with (2, 3) it is the uncertainty of the medium level.
pub fn pair_gci(h: [f64; 2], phi: [f64; 2], p: f64, fs: f64) -> f64 {
    fs * rel(phi[0], phi[1]) / ((h[1] / h[0]).powf(p) - 1.0)
}

fn rel(a: f64, b: f64) -> f64 {
    ((a - b) / a).abs()
}

/// Estimate from levels sorted finest first with `h` strictly increasing. `resolution` is the
/// relative difference the solver tolerance cannot resolve (> 0); `formal_order` is used with
/// two levels. Fewer than two levels: `None`.
pub fn estimate(h: &[f64], phi: &[f64], resolution: f64, formal_order: f64) -> Option<Estimate> {
    match (h, phi) {
        ([h1, h2, h3, ..], [p1, p2, p3, ..]) => {
            Some(three_levels([*h1, *h2, *h3], [*p1, *p2, *p3], resolution))
        }
        ([h1, h2], [p1, p2]) => Some(two_levels([*h1, *h2], [*p1, *p2], resolution, formal_order)),
        _ => None,
    }
}

fn round_off(phi1: f64, e_a: f64, resolution: f64, fs: f64) -> Estimate {
    Estimate {
        verdict: Verdict::RoundOff,
        observed_order: None,
        order_used: None,
        safety_factor: fs,
        extrapolated: Some(phi1),
        approximate_error: e_a,
        extrapolated_error: None,
        gci: Some(resolution),
    }
}

/// The largest |ε₂₁/ε₃₂| of a sequence φ = φ₀ + c h^p with p > 0: R(p) =
/// (r₂₁^p − 1)/(r₂₁^p (r₃₂^p − 1)) falls from ln r₂₁/ln r₃₂ at p → 0 to 0 at p → ∞; 1 for
/// uniform refinement. (A finer difference larger than the coarser one is still convergence
/// when the finer step refines more: r₂₁ = 1.5 after r₃₂ = 1.333 gives R = 1 at p = 1.)
pub fn r_max(r21: f64, r32: f64) -> f64 {
    r21.ln() / r32.ln()
}

/// Celik's procedure on three levels, with the verdict from R = ε₂₁/ε₃₂ against
/// [`r_max`].
pub fn three_levels(h: [f64; 3], phi: [f64; 3], resolution: f64) -> Estimate {
    let [p1, p2, p3] = phi;
    let (r21, r32) = (h[1] / h[0], h[2] / h[1]);
    let (e21, e32) = (p2 - p1, p3 - p2);
    let e_a = rel(p1, p2);
    if e21.abs() <= resolution * p1.abs() {
        return round_off(p1, e_a, resolution, FS_OBSERVED);
    }
    let ratio = if e32 == 0.0 { f64::INFINITY } else { e21 / e32 };
    let verdict = if ratio.abs() >= r_max(r21, r32) {
        Verdict::Divergent
    } else if ratio < 0.0 {
        Verdict::Oscillatory
    } else {
        Verdict::Monotone
    };
    let p = match verdict {
        Verdict::Divergent => None,
        _ => apparent_order(r21, r32, e21, e32),
    };
    let mut est = Estimate {
        verdict,
        observed_order: p,
        order_used: p,
        safety_factor: FS_OBSERVED,
        extrapolated: None,
        approximate_error: e_a,
        extrapolated_error: None,
        gci: None,
    };
    if verdict == Verdict::Divergent {
        // No order and no extrapolation; a range band (Fs = 3 on the largest spread) so a
        // sequence whose differences are tiny but erratic still gets a bound.
        let spread = rel(p1, p2).max(rel(p1, p3));
        est.safety_factor = FS_ASSUMED;
        est.gci = Some(FS_ASSUMED * spread);
    }
    if let Some(p) = p {
        let ext = richardson(r21, p, p1, p2);
        est.extrapolated = Some(ext);
        est.extrapolated_error = Some(rel(ext, p1));
        est.gci = Some(FS_OBSERVED * e_a / (r21.powf(p) - 1.0));
    }
    est
}

/// Two levels: the formal order is assumed and the safety factor is 3; the behaviour cannot be
/// observed, so the verdict is `monotone` unless the difference is round-off.
pub fn two_levels(h: [f64; 2], phi: [f64; 2], resolution: f64, formal_order: f64) -> Estimate {
    let [p1, p2] = phi;
    let r21 = h[1] / h[0];
    let e_a = rel(p1, p2);
    if (p2 - p1).abs() <= resolution * p1.abs() {
        return round_off(p1, e_a, resolution, FS_ASSUMED);
    }
    let ext = richardson(r21, formal_order, p1, p2);
    Estimate {
        verdict: Verdict::Monotone,
        observed_order: None,
        order_used: Some(formal_order),
        safety_factor: FS_ASSUMED,
        extrapolated: Some(ext),
        approximate_error: e_a,
        extrapolated_error: Some(rel(ext, p1)),
        gci: Some(FS_ASSUMED * e_a / (r21.powf(formal_order) - 1.0)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fixed_point_solves_its_own_equation() {
        // Uniform refinement: q = 0 and p = ln(ε₃₂/ε₂₁)/ln r exactly.
        let p = apparent_order(2.0, 2.0, 0.25, 1.0).unwrap();
        assert!((p - 2.0).abs() < 1e-12, "{p}");
        // Non-uniform: the returned p satisfies p ln r₂₁ = ln|ε₃₂/ε₂₁| + q(p).
        let (r21, r32, e21, e32) = (1.5, 1.3, 0.1, 0.2);
        let p = apparent_order(r21, r32, e21, e32).unwrap();
        let q = ((r21.powf(p) - 1.0) / (r32.powf(p) - 1.0)).ln();
        assert!((p * r21.ln() - ((e32 / e21).ln() + q)).abs() < 1e-10);
    }
}

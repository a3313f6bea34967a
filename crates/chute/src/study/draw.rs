//! The random inputs of a dispersion study: the distributions a scenario key may be drawn
//! from, and the draw of sample `i` from (study seed, `i`) alone, so that a sample is the same
//! however a study is split, sharded or resumed (docs/notes/dispersion-design-2026-12-07.md).
//!
//! Every draw is the quantile of a uniform number, `x = F⁻¹(u)`: one path serves simple random
//! sampling and the Latin hypercube, whose `u` of input `d` for sample `i` lies in stratum
//! `π_d(i)` of `n` (McKay, Beckman & Conover, Technometrics 21(2), 1979), with the
//! permutation `π_d` drawn from the seed and `d` alone.

use rand::seq::SliceRandom;
use rand::{RngCore, SeedableRng};
use rand_chacha::ChaCha12Rng;

/// A distribution of one input.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Distribution {
    /// Normal of mean μ and standard deviation σ, truncated to `[lo, hi]` (±∞ for none);
    /// σ = 0 is the constant μ.
    Normal {
        /// μ.
        mean: f64,
        /// σ (≥ 0).
        std_dev: f64,
        /// Lower bound (< μ), or −∞.
        lo: f64,
        /// Upper bound (> μ), or +∞.
        hi: f64,
    },
    /// Uniform on `[lo, hi]` (`lo = hi`: a constant).
    Uniform {
        /// Lower end.
        lo: f64,
        /// Upper end.
        hi: f64,
    },
    /// Triangular on `[lo, hi]` with its peak at `mode`.
    Triangular {
        /// Lower end.
        lo: f64,
        /// The peak, in `[lo, hi]`.
        mode: f64,
        /// Upper end.
        hi: f64,
    },
}

/// Why a distribution's parameters were refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DistributionError {
    /// A parameter that is not a finite number (bounds may be infinite).
    #[error("{0} must be a finite number")]
    NotFinite(&'static str),
    /// A negative standard deviation.
    #[error("the standard deviation {0} is negative")]
    NegativeStdDev(f64),
    /// Truncation bounds that leave the mean outside.
    #[error("the bounds [{lo}, {hi}] must hold the mean {mean} strictly inside")]
    MeanOutside {
        /// μ.
        mean: f64,
        /// Lower bound.
        lo: f64,
        /// Upper bound.
        hi: f64,
    },
    /// An interval whose ends are out of order.
    #[error("need lo ≤ hi, got lo = {lo}, hi = {hi}")]
    Reversed {
        /// Lower end.
        lo: f64,
        /// Upper end.
        hi: f64,
    },
    /// A mode outside its interval.
    #[error("need lo ≤ mode ≤ hi, got {lo} ≤ {mode} ≤ {hi}")]
    OutOfOrder {
        /// Lower end.
        lo: f64,
        /// The mode (the midpoint for a uniform).
        mode: f64,
        /// Upper end.
        hi: f64,
    },
}

impl Distribution {
    /// A normal of mean `mean` and standard deviation `std_dev` truncated to `[lo, hi]`.
    pub fn try_normal(
        mean: f64,
        std_dev: f64,
        lo: f64,
        hi: f64,
    ) -> Result<Self, DistributionError> {
        finite(&[(mean, "the mean"), (std_dev, "the standard deviation")])?;
        if std_dev < 0.0 {
            return Err(DistributionError::NegativeStdDev(std_dev));
        }
        if lo.is_nan() || hi.is_nan() || !(lo < mean && mean < hi) {
            return Err(DistributionError::MeanOutside { mean, lo, hi });
        }
        Ok(Self::Normal {
            mean,
            std_dev,
            lo,
            hi,
        })
    }

    /// A uniform on `[lo, hi]`.
    pub fn try_uniform(lo: f64, hi: f64) -> Result<Self, DistributionError> {
        finite(&[(lo, "lo"), (hi, "hi")])?;
        if lo > hi {
            return Err(DistributionError::Reversed { lo, hi });
        }
        Ok(Self::Uniform { lo, hi })
    }

    /// A triangular on `[lo, hi]` peaking at `mode`.
    pub fn try_triangular(lo: f64, mode: f64, hi: f64) -> Result<Self, DistributionError> {
        finite(&[(lo, "lo"), (mode, "the mode"), (hi, "hi")])?;
        if lo > hi {
            return Err(DistributionError::Reversed { lo, hi });
        }
        if !(lo <= mode && mode <= hi) {
            return Err(DistributionError::OutOfOrder { lo, mode, hi });
        }
        Ok(Self::Triangular { lo, mode, hi })
    }

    /// The quantile `F⁻¹(p)` for `p ∈ (0, 1)`.
    pub fn quantile(&self, p: f64) -> f64 {
        match *self {
            Self::Normal {
                mean, std_dev: 0.0, ..
            } => mean,
            Self::Normal {
                mean,
                std_dev,
                lo,
                hi,
            } => {
                let (a, b) = (phi((lo - mean) / std_dev), phi((hi - mean) / std_dev));
                let x = mean + std_dev * phi_inv(a + p * (b - a));
                x.clamp(lo, hi)
            }
            Self::Uniform { lo, hi } => lo + p * (hi - lo),
            Self::Triangular { lo, mode, hi } => {
                let (w, left) = (hi - lo, mode - lo);
                if w == 0.0 {
                    lo
                } else if p * w < left {
                    lo + (p * w * left).sqrt()
                } else {
                    hi - ((1.0 - p) * w * (hi - mode)).sqrt()
                }
            }
        }
    }
}

fn finite(values: &[(f64, &'static str)]) -> Result<(), DistributionError> {
    match values.iter().find(|(x, _)| !x.is_finite()) {
        Some((_, name)) => Err(DistributionError::NotFinite(name)),
        None => Ok(()),
    }
}

/// The standard normal distribution function Φ(x) = ½ erfc(−x/√2).
pub fn phi(x: f64) -> f64 {
    0.5 * libm::erfc(-x / std::f64::consts::SQRT_2)
}

/// Φ⁻¹(p): Acklam's rational approximation (relative error 1.15e-9), then one Halley step on
/// `Φ(x) − p` with the exact Φ, which takes it to double precision.
pub fn phi_inv(p: f64) -> f64 {
    if p <= 0.0 {
        return f64::NEG_INFINITY;
    }
    if p >= 1.0 {
        return f64::INFINITY;
    }
    const A: [f64; 6] = [
        -3.969683028665376e1,
        2.209460984245205e2,
        -2.759285104469687e2,
        1.38357751867269e2,
        -3.066479806614716e1,
        2.506628277459239,
    ];
    const B: [f64; 5] = [
        -5.447609879822406e1,
        1.615858368580409e2,
        -1.556989798598866e2,
        6.680131188771972e1,
        -1.328068155288572e1,
    ];
    const C: [f64; 6] = [
        -7.784894002430293e-3,
        -3.223964580411365e-1,
        -2.400758277161838,
        -2.549732539343734,
        4.374664141464968,
        2.938163982698783,
    ];
    const D: [f64; 4] = [
        7.784695709041462e-3,
        3.224671290700398e-1,
        2.445134137142996,
        3.754408661907416,
    ];
    let tail = |q: f64| {
        (((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5])
            / ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1.0)
    };
    let x = if p < 0.02425 {
        tail((-2.0 * p.ln()).sqrt())
    } else if p > 1.0 - 0.02425 {
        -tail((-2.0 * (1.0 - p).ln()).sqrt())
    } else {
        let q = p - 0.5;
        let r = q * q;
        (((((A[0] * r + A[1]) * r + A[2]) * r + A[3]) * r + A[4]) * r + A[5]) * q
            / (((((B[0] * r + B[1]) * r + B[2]) * r + B[3]) * r + B[4]) * r + 1.0)
    };
    // Halley: e = Φ(x) − p, u = e √(2π) e^{x²/2}, x ← x − u/(1 + x u/2).
    let e = phi(x) - p;
    let u = e * (2.0 * std::f64::consts::PI).sqrt() * (0.5 * x * x).exp();
    x - u / (1.0 + 0.5 * x * u)
}

/// How the samples of a study are drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sampler {
    /// The study's seed.
    pub seed: u64,
    /// Number of samples `n`.
    pub samples: usize,
    /// Latin hypercube (one sample in each of the `n` strata of every input) instead of
    /// independent draws.
    pub latin_hypercube: bool,
}

/// The stream tags, so that the samples' numbers and the permutations never share a stream.
const SAMPLE_STREAM: u64 = 0x5341_4d50_4c45_5321; // "SAMPLES!"
const STRATA_STREAM: u64 = 0x5354_5241_5441_2121; // "STRATA!!"

impl Sampler {
    /// The values of sample `i` (0-based, `< samples`) for the inputs `inputs`, computed
    /// from (seed, `i`) alone (and, with the Latin hypercube, from (seed, input) for the
    /// strata).
    pub fn draw(&self, i: usize, inputs: &[Distribution]) -> Vec<f64> {
        assert!(i < self.samples, "sample {i} of {}", self.samples);
        self.draw_in(i, inputs, |d| self.strata(d)[i])
    }

    /// Every sample's values ([`Sampler::draw`] for each `i`, each permutation drawn once).
    pub fn draw_all(&self, inputs: &[Distribution]) -> Vec<Vec<f64>> {
        let strata: Vec<Vec<usize>> = match self.latin_hypercube {
            true => (0..inputs.len()).map(|d| self.strata(d)).collect(),
            false => Vec::new(),
        };
        (0..self.samples)
            .map(|i| self.draw_in(i, inputs, |d| strata[d][i]))
            .collect()
    }

    /// Sample `i`, with `stratum(d)` its stratum of input `d` (Latin hypercube only).
    fn draw_in(
        &self,
        i: usize,
        inputs: &[Distribution],
        stratum: impl Fn(usize) -> usize,
    ) -> Vec<f64> {
        let mut rng = stream(self.seed, SAMPLE_STREAM, i as u64);
        inputs
            .iter()
            .enumerate()
            .map(|(d, dist)| {
                let u = open_unit(&mut rng);
                let p = match self.latin_hypercube {
                    false => u,
                    true => (stratum(d) as f64 + u) / self.samples as f64,
                };
                dist.quantile(p)
            })
            .collect()
    }

    /// The strata of input `d`: `π_d`, a permutation of `0..n` drawn from (seed, `d`).
    fn strata(&self, d: usize) -> Vec<usize> {
        let mut perm: Vec<usize> = (0..self.samples).collect();
        perm.shuffle(&mut stream(self.seed, STRATA_STREAM, d as u64));
        perm
    }
}

/// The ChaCha12 generator keyed by (seed, tag, index): independent streams for every sample.
fn stream(seed: u64, tag: u64, index: u64) -> ChaCha12Rng {
    let mut key = [0u8; 32];
    for (chunk, word) in key.chunks_exact_mut(8).zip([seed, tag, index, 0]) {
        chunk.copy_from_slice(&word.to_le_bytes());
    }
    ChaCha12Rng::from_seed(key)
}

/// A uniform number in the open interval (0, 1): `(k + ½)/2⁵³` for 53 random bits `k`.
fn open_unit(rng: &mut ChaCha12Rng) -> f64 {
    ((rng.next_u64() >> 11) as f64 + 0.5) / (1u64 << 53) as f64
}

#[cfg(test)]
mod tests;

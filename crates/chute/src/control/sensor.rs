//! A height sensor on the payload (`[[sensor]]`): when it samples and what it reads.
//!
//! Sample `k` (k = 0, 1, …) is taken at `t_k = k / rate_hz`. Its reading is the landing
//! body's height above the ground at `t_k`, interpolated linearly between the two accepted
//! states around `t_k` (implicit Euler's states are first-order in time; so is this), plus
//! Gaussian noise of standard deviation `noise_m`. The noise of sample `k` is drawn from a
//! ChaCha12 generator seeded by `(seed, k)` alone, so a reading does not depend on how the
//! run was stepped, split, checkpointed or resumed.
use rand::SeedableRng;
use rand_chacha::ChaCha12Rng;
use rand_distr::{Distribution, StandardNormal};

use crate::scenario::Sensor;

/// Relative slack (in samples) with which a sample at the very end of a step belongs to that
/// step: `t_k = k / rate` and a step's end computed as a sum of steps agree only to round-off.
const SAMPLE_SLACK: f64 = 1e-9;

/// One height sensor.
#[derive(Debug, Clone, PartialEq)]
pub struct HeightSensor {
    /// Its name (`sensor[j].name`).
    pub name: String,
    /// Samples per second (Hz).
    pub rate_hz: f64,
    /// Delay from a sample to the pull it fires (s).
    pub latency_s: f64,
    /// Standard deviation of the reading's noise (m).
    pub noise_m: f64,
    /// Seed of the noise.
    pub seed: u64,
}

impl HeightSensor {
    /// The sensor declared by `s`.
    pub fn new(s: &Sensor) -> Self {
        Self {
            name: s.name.clone(),
            rate_hz: s.rate_hz,
            latency_s: s.latency_s,
            noise_m: s.noise_m,
            seed: s.seed as u64,
        }
    }

    /// Time of sample `k` (s).
    pub fn sample_time(&self, k: u64) -> f64 {
        k as f64 / self.rate_hz
    }

    /// The samples taken in the step `(t_a, t_b]`; the step that ends at `t_b` owns a sample
    /// at `t_b`. Consecutive steps own disjoint samples and miss none.
    pub fn samples_in(&self, t_a: f64, t_b: f64) -> std::ops::Range<u64> {
        let last = |t: f64| (t * self.rate_hz + SAMPLE_SLACK).floor();
        let first = (last(t_a) + 1.0).max(0.0) as u64;
        first..(last(t_b) + 1.0).max(0.0) as u64
    }

    /// Noise of sample `k` (m): `noise_m` times a standard normal draw from the generator of
    /// `(seed, k)`.
    pub fn noise(&self, k: u64) -> f64 {
        if self.noise_m == 0.0 {
            return 0.0;
        }
        let mut key = [0u8; 32];
        key[..8].copy_from_slice(&self.seed.to_le_bytes());
        key[8..16].copy_from_slice(&k.to_le_bytes());
        let z: f64 = StandardNormal.sample(&mut ChaCha12Rng::from_seed(key));
        self.noise_m * z
    }

    /// The reading of sample `k` between the accepted states `(t_a, h_a)` and `(t_b, h_b)`
    /// (time, true height) that enclose its time.
    pub fn reading(&self, k: u64, (t_a, h_a): (f64, f64), (t_b, h_b): (f64, f64)) -> f64 {
        let t = self.sample_time(k);
        let w = if t_b > t_a {
            ((t - t_a) / (t_b - t_a)).clamp(0.0, 1.0)
        } else {
            1.0
        };
        h_a + w * (h_b - h_a) + self.noise(k)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sensor(rate_hz: f64, noise_m: f64, seed: u64) -> HeightSensor {
        HeightSensor {
            name: "alt".into(),
            rate_hz,
            latency_s: 0.0,
            noise_m,
            seed,
        }
    }

    #[test]
    fn steps_own_disjoint_samples_and_miss_none() {
        // 20 Hz sampled by 3 ms steps accumulated as a run does (sums, not products).
        let s = sensor(20.0, 0.0, 0);
        let mut t = 0.0;
        let mut owned = vec![0u64]; // sample 0 belongs to the start
        for _ in 0..1000 {
            let t_b = t + 0.003;
            owned.extend(s.samples_in(t, t_b));
            t = t_b;
        }
        let want: Vec<u64> = (0..=60).collect(); // 3 s: samples 0 … 60
        assert_eq!(owned, want);
        // A sample at a step's end up to round-off belongs to that step.
        assert_eq!(s.samples_in(0.04, 0.1 - 1e-15), 1..3);
        assert_eq!(s.samples_in(0.1 - 1e-15, 0.13), 3..3);
    }

    #[test]
    fn a_reading_interpolates_between_the_states_around_it() {
        let s = sensor(10.0, 0.0, 0);
        // Sample 3 at 0.3 s, a quarter into the step 0.25 → 0.45 s from 10 m to 2 m.
        let r = s.reading(3, (0.25, 10.0), (0.45, 2.0));
        assert!((r - 8.0).abs() < 1e-12, "{r}");
    }

    #[test]
    fn noise_depends_on_seed_and_sample_only_and_has_the_declared_spread() {
        let s = sensor(10.0, 0.5, 7);
        assert_eq!(s.noise(12), s.noise(12));
        assert_eq!(s.noise(12), sensor(99.0, 0.5, 7).noise(12));
        assert_ne!(s.noise(12), sensor(10.0, 0.5, 8).noise(12));
        assert_ne!(s.noise(12), s.noise(13));
        // Mean 0 and standard deviation 0.5 to sampling error: over n draws the mean's
        // standard error is σ/√n, the variance's σ²√(2/n); 5 standard errors.
        let n = 20_000;
        let x: Vec<f64> = (0..n).map(|k| s.noise(k)).collect();
        let mean = x.iter().sum::<f64>() / n as f64;
        let var = x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1) as f64;
        let nf = n as f64;
        assert!(mean.abs() < 5.0 * 0.5 / nf.sqrt(), "mean {mean}");
        assert!(
            (var - 0.25).abs() < 5.0 * 0.25 * (2.0 / nf).sqrt(),
            "variance {var}"
        );
        assert_eq!(sensor(10.0, 0.0, 7).noise(12), 0.0);
    }
}

use super::*;

/// Two-sided false-alarm rate of each statistical assertion: 1.2e-7 at z = 5.3 (about 1e-6
/// over the assertions of one test).
const Z: f64 = 5.3;

#[test]
fn the_normal_quantile_inverts_phi_to_its_conditioning() {
    assert_eq!(phi_inv(0.5), 0.0);
    assert!((phi_inv(0.975) - 1.959963984540054).abs() < 1e-15);
    for k in 1..2000 {
        let p = k as f64 / 2000.0;
        for p in [p, p * 1e-9, 1.0 - p * 1e-9] {
            // Φ near x carries a relative rounding of x ε into p as x² ε (φ/Φ ≈ |x| in the
            // tail): the round trip is exact to that conditioning.
            let x = phi_inv(p);
            let back = phi(x);
            let tol = 4.0 * (1.0 + x * x) * f64::EPSILON * p;
            assert!((back - p).abs() <= tol, "{p}: {back}");
        }
    }
    assert_eq!(phi_inv(0.0), f64::NEG_INFINITY);
    assert_eq!(phi_inv(1.0), f64::INFINITY);
}

#[test]
fn bad_parameters_are_refused() {
    use DistributionError::*;
    assert_eq!(
        Distribution::try_normal(1.0, -0.1, 0.0, 2.0),
        Err(NegativeStdDev(-0.1))
    );
    let outside = Distribution::try_normal(5.0, 1.0, 6.0, 9.0);
    assert_eq!(
        outside,
        Err(MeanOutside {
            mean: 5.0,
            lo: 6.0,
            hi: 9.0
        })
    );
    assert_eq!(
        Distribution::try_normal(f64::NAN, 1.0, 0.0, 1.0),
        Err(NotFinite("the mean"))
    );
    assert_eq!(
        Distribution::try_uniform(2.0, 1.0),
        Err(Reversed { lo: 2.0, hi: 1.0 })
    );
    assert!(matches!(
        Distribution::try_triangular(0.0, 3.0, 2.0),
        Err(OutOfOrder { .. })
    ));
    assert!(Distribution::try_normal(0.0, 1.0, f64::NEG_INFINITY, f64::INFINITY).is_ok());
}

/// Mean, variance and fourth central moment of `d` by the midpoint rule on its quantile
/// function (2·10⁵ points: far below the sampling error tested against).
fn moments(d: &Distribution) -> (f64, f64, f64) {
    let n = 200_000;
    let x: Vec<f64> = (0..n)
        .map(|k| d.quantile((k as f64 + 0.5) / n as f64))
        .collect();
    let mean = x.iter().sum::<f64>() / n as f64;
    let central = |p: i32| x.iter().map(|v| (v - mean).powi(p)).sum::<f64>() / n as f64;
    (mean, central(2), central(4))
}

fn inputs() -> [Distribution; 3] {
    [
        Distribution::try_normal(10.0, 2.0, 5.0, 13.0).unwrap(),
        Distribution::try_uniform(-1.0, 3.0).unwrap(),
        Distribution::try_triangular(0.0, 0.2, 1.0).unwrap(),
    ]
}

/// The sample mean and variance of each input, and the correlation of each pair, lie within
/// Z standard errors of the declared distribution's (independent inputs: correlation 0).
fn check_sample_statistics(latin_hypercube: bool) {
    let n = 20_000;
    let sampler = Sampler {
        seed: 42,
        samples: n,
        latin_hypercube,
    };
    let inputs = inputs();
    let draws = sampler.draw_all(&inputs);
    let column = |d: usize| draws.iter().map(|r| r[d]).collect::<Vec<f64>>();
    let nf = n as f64;
    for (d, dist) in inputs.iter().enumerate() {
        let (mu, var, m4) = moments(dist);
        let x = column(d);
        let mean = x.iter().sum::<f64>() / nf;
        let s2 = x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (nf - 1.0);
        assert!(
            (mean - mu).abs() <= Z * (var / nf).sqrt(),
            "{dist:?}: mean {mean} vs {mu}"
        );
        let se_var = ((m4 - var * var) / nf).sqrt();
        assert!(
            (s2 - var).abs() <= Z * se_var,
            "{dist:?}: variance {s2} vs {var}"
        );
        assert!(x
            .iter()
            .all(|v| (mu - 10.0 * var.sqrt()..=mu + 10.0 * var.sqrt()).contains(v)));
    }
    for (a, b) in [(0, 1), (0, 2), (1, 2)] {
        let (x, y) = (column(a), column(b));
        let (mx, my) = (x.iter().sum::<f64>() / nf, y.iter().sum::<f64>() / nf);
        let cov: f64 = x.iter().zip(&y).map(|(p, q)| (p - mx) * (q - my)).sum();
        let sx = x.iter().map(|p| (p - mx).powi(2)).sum::<f64>().sqrt();
        let sy = y.iter().map(|q| (q - my).powi(2)).sum::<f64>().sqrt();
        let r = cov / (sx * sy);
        assert!(r.abs() <= Z / nf.sqrt(), "inputs {a}, {b}: correlation {r}");
    }
}

#[test]
fn random_samples_have_the_declared_moments() {
    check_sample_statistics(false);
}

#[test]
fn latin_hypercube_samples_have_the_declared_moments() {
    check_sample_statistics(true);
}

#[test]
fn a_latin_hypercube_puts_one_sample_in_every_stratum() {
    let n = 257;
    let sampler = Sampler {
        seed: 7,
        samples: n,
        latin_hypercube: true,
    };
    let unit = [Distribution::try_uniform(0.0, 1.0).unwrap(); 3];
    for d in 0..3 {
        let mut strata: Vec<usize> = (0..n)
            .map(|i| (sampler.draw(i, &unit)[d] * n as f64) as usize)
            .collect();
        strata.sort_unstable();
        assert_eq!(strata, (0..n).collect::<Vec<_>>(), "input {d}");
    }
}

#[test]
fn a_sample_depends_on_the_seed_and_its_index_alone() {
    let inputs = inputs();
    let small = Sampler {
        seed: 3,
        samples: 10,
        latin_hypercube: false,
    };
    let large = Sampler {
        samples: 100_000,
        ..small
    };
    // One sample alone is the same as in the whole set, with or without strata.
    for lhs in [false, true] {
        let s = Sampler {
            seed: 3,
            samples: 40,
            latin_hypercube: lhs,
        };
        let all = s.draw_all(&inputs);
        assert!((0..40).all(|i| s.draw(i, &inputs) == all[i]));
    }
    // The same sample of a 10-sample and a 100 000-sample study, in any order.
    assert_eq!(small.draw(7, &inputs), large.draw(7, &inputs));
    let later: Vec<Vec<f64>> = (0..10).rev().map(|i| small.draw(i, &inputs)).collect();
    assert_eq!(later[2], small.draw(7, &inputs));
    assert_ne!(small.draw(7, &inputs), small.draw(6, &inputs));
    assert_ne!(
        small.draw(7, &inputs),
        Sampler { seed: 4, ..small }.draw(7, &inputs)
    );
}

#[test]
fn zero_spread_draws_the_same_value_every_time() {
    let fixed = [
        Distribution::try_normal(2.5, 0.0, 0.0, 5.0).unwrap(),
        Distribution::try_uniform(1.0, 1.0).unwrap(),
        Distribution::try_triangular(4.0, 4.0, 4.0).unwrap(),
    ];
    for lhs in [false, true] {
        let sampler = Sampler {
            seed: 1,
            samples: 50,
            latin_hypercube: lhs,
        };
        for i in 0..50 {
            assert_eq!(sampler.draw(i, &fixed), vec![2.5, 1.0, 4.0]);
        }
    }
}

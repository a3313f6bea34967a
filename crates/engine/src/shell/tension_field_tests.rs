//! Unit tests of [`super`]: the wrinkling angle by Newton and the inner solve.
use super::*;
use crate::conformance::Rng;

/// The weak-shear fabric of the conformance tests (N/m) and the bench's Kevlar weave.
const LAWS: [Voigt3; 2] = [
    [
        [1.2363e5, 1.8547e4, 0.0],
        [1.8547e4, 6.1817e4, 0.0],
        [0.0, 0.0, 5e3],
    ],
    [[5.6e6, 8.4e5, 0.0], [8.4e5, 2.8e6, 0.0], [0.0, 0.0, 2.8e5]],
];

/// A random strain of magnitude `10^[lo, hi]` in a random direction.
fn strain(rng: &mut Rng, lo: f64, hi: f64) -> Voigt {
    let size = 10f64.powf(rng.uniform(lo, hi));
    let e = [0, 1, 2].map(|_| rng.symmetric(1.0));
    e.map(|x| size * x / dot(&e, &e).sqrt())
}

#[test]
fn wrinkling_angle_by_newton_matches_the_sampled_roots() {
    let mut rng = Rng::new(3);
    for q in LAWS {
        let tf = TensionField::new(q, 1e-5);
        let (mut wrinkled, mut found) = (0, 0);
        for _ in 0..2000 {
            let eps = strain(&mut rng, -6.0, -1.0);
            let Some((c, s, t, g)) = tf.wrinkle(&eps) else {
                continue;
            };
            wrinkled += 1;
            let Some((c1, s1, t1, g1)) = tf.wrinkle_newton(&eps) else {
                continue;
            };
            found += 1;
            // The same wrinkle normal (up to sign), tension and wrinkle strain.
            assert!((c * s1 - s * c1).abs() < 1e-9, "{eps:?}");
            assert!(
                (t1 - t).abs() <= 1e-8 * t && (g1 - g).abs() <= 1e-8 * g,
                "{eps:?}"
            );
        }
        assert!(wrinkled > 500, "{wrinkled} wrinkled draws");
        assert!(
            found as f64 > 0.99 * wrinkled as f64,
            "{found} of {wrinkled}"
        );
    }
}

#[test]
fn inner_solve_converges_in_few_steps_to_the_same_state_from_either_start() {
    let mut rng = Rng::new(5);
    for (q, eps_r) in [(LAWS[0], 1e-2), (LAWS[0], 1e-5), (LAWS[1], 1e-5)] {
        let tf = TensionField::new(q, eps_r);
        let (mut total, n) = (0, 4000);
        for _ in 0..n {
            let eps = strain(&mut rng, -6.0, -1.5);
            let r = tf.relax(&eps);
            total += r.iterations;
            // The previous start: the better of both, with the wrinkling angle sampled.
            let mut p = tf.start(&eps);
            let near = tf.unregularised_start_sampled(&eps);
            if near.is_some_and(|n| tf.objective(&eps, &n) < tf.objective(&eps, &p)) {
                p = near.unwrap();
            }
            let reference = tf.relax_from(&eps, p, tf.newton_step(&eps, &p));
            let scale = dot(&r.stress, &r.stress).sqrt();
            for k in 0..3 {
                let diff = (r.stress[k] - reference.stress[k]).abs();
                assert!(diff <= 1e-10 * scale, "{eps:?}: {r:?} vs {reference:?}");
            }
        }
        let mean = total as f64 / n as f64;
        // (3.4 for ε_r = 1e-5 and 4.3 for 1e-2 over these strains, 1e-6–0.03.)
        assert!(
            mean < if eps_r > 1e-3 { 5.0 } else { 4.0 },
            "ε_r = {eps_r}: {mean} iterations on average"
        );
    }
}

/// Tension-field theory on the material axes (no shear strain, so the principal axes of `P*`
/// are the axes): taut under biaxial tension (`P* = 0`); wrinkled along 1 when
/// `−ε₁ > Q₁₂ε₂/Q₁₁` (then `σ₁₁ = 0`, so `P₁₁ = −ε₁ − Q₁₂ε₂/Q₁₁`); slack under biaxial
/// compression (`σ = 0`, `P* = −ε`). The barrier moves each wrinkled value by the stress it
/// leaves, `σᵢ = μ/λᵢ`, i.e. by `ε_r² k_ref/(Q λ)` in strain: the tolerance.
#[test]
fn wrinkling_state_and_strains_are_those_of_tension_field_theory() {
    let eps_r = 1e-5;
    for q in LAWS {
        let tf = TensionField::new(q, eps_r);
        let k_ref = 0.5 * (q[0][0] + q[1][1]);
        let qmin = q[0][0].min(q[1][1]) - q[0][1].abs();
        let tol = |l: f64| 10.0 * eps_r * eps_r * k_ref / (qmin * l);
        for (a, b) in [(1e-2, 2e-2), (3e-3, 1e-3), (5e-2, 1e-2)] {
            let taut = tf.wrinkling(&[a, b, 0.0]);
            assert_eq!(taut.slack_directions, 0, "{a} {b}");
            assert!(taut.principal[0] < eps_r * eps_r / a.min(b), "{taut:?}");

            let w = tf.wrinkling(&[-a, b, 0.0]);
            let exact = a - q[0][1] * b / q[0][0];
            assert!(exact > 0.0);
            assert_eq!(w.slack_directions, 1, "{a} {b}: {w:?}");
            assert!(
                (w.principal[0] - exact).abs() < tol(exact),
                "{w:?} vs {exact}"
            );
            assert!(w.principal[1] < eps_r, "{w:?}");

            let s = tf.wrinkling(&[-a, -b, 0.0]);
            assert_eq!(s.slack_directions, 2, "{a} {b}: {s:?}");
            let (hi, lo) = (a.max(b), a.min(b));
            assert!((s.principal[0] - hi).abs() < tol(lo), "{s:?}");
            assert!((s.principal[1] - lo).abs() < tol(lo), "{s:?}");
        }
    }
}

/// The tangent `D = ∂σ/∂ε` against central differences of the stress at the default ε_r
/// (1e-5) and 1e-4, on strains of 1e-6–1e-2: the scale of the regularisation itself,
/// where the stiffness turns over within ~ε_r (the conformance tests check the element at
/// ε_r = 1e-2, which finite differences on positions resolve). The difference step
/// `1e-4 ε_r` leaves a truncation error ~(1e-4)² of `D` and a round-off error
/// ~1e-16 σ/(1e-4 ε_r) ≤ 1e-7 k here: the bound is 1e-6 k (measured: ≤ 1.6e-9 k).
#[test]
fn tangent_matches_differences_of_the_stress_at_the_regularisation_scale() {
    let mut rng = Rng::new(12);
    for q in LAWS {
        for eps_r in [1e-5, 1e-4] {
            let tf = TensionField::new(q, eps_r);
            let h = 1e-4 * eps_r;
            for _ in 0..3000 {
                let eps = strain(&mut rng, -6.0, -2.0);
                let d = tf.relax_with_tangent(&eps).1;
                for j in 0..3 {
                    let (mut ep, mut em) = (eps, eps);
                    ep[j] += h;
                    em[j] -= h;
                    let (sp, sm) = (tf.stress(&ep), tf.stress(&em));
                    for i in 0..3 {
                        let fd = (sp[i] - sm[i]) / (2.0 * h);
                        assert!(
                            (fd - d[i][j]).abs() <= 1e-6 * q[0][0],
                            "ε_r {eps_r}, ε {eps:?}: D[{i}][{j}] {} vs {fd}",
                            d[i][j]
                        );
                    }
                }
            }
        }
    }
}

/// The regularised law inverted in closed form: stationarity `σ = μ P⁻¹` makes the strain at a
/// stress `σ ≻ 0` exactly `ε = Q⁻¹σ − μ σ⁻¹` (Voigt). So a relaxation of that strain must give
/// back `σ`, and the regularisation leaves the strain short of the elastic `Q⁻¹σ` by
/// `ε_r² k_ref / σᵢ` along each principal stress `σᵢ`: the strain error the scenario's check
/// of `material.wrinkle_strain` estimates (docs/shells.md §No compression).
#[test]
fn strain_at_a_given_stress_is_short_of_the_elastic_one_by_mu_over_the_stress() {
    let mut rng = Rng::new(17);
    for q in LAWS {
        for eps_r in [1e-5, 1e-4, 1e-3] {
            let tf = TensionField::new(q, eps_r);
            let k_ref = 0.5 * (q[0][0] + q[1][1]);
            for _ in 0..500 {
                // Principal stresses from 1e-4 to 1e2 times the pre-tension ε_r k_ref.
                let s = [0, 1].map(|_| eps_r * k_ref * 10f64.powf(rng.uniform(-4.0, 2.0)));
                let (sn, c) = rng.uniform(0.0, std::f64::consts::PI).sin_cos();
                let sigma = [
                    s[0] * c * c + s[1] * sn * sn,
                    s[0] * sn * sn + s[1] * c * c,
                    (s[0] - s[1]) * c * sn,
                ];
                // μ σ⁻¹ as a Voigt strain (P₁₁, P₂₂, 2P₁₂).
                let det = sigma[0] * sigma[1] - sigma[2] * sigma[2];
                let p = [
                    tf.mu * sigma[1] / det,
                    tf.mu * sigma[0] / det,
                    -2.0 * tf.mu * sigma[2] / det,
                ];
                let elastic = mul(&tf.compliance, &sigma);
                let eps = [0, 1, 2].map(|k| elastic[k] - p[k]);
                let r = tf.relax(&eps);
                for k in 0..3 {
                    let scale = s[0].max(s[1]);
                    assert!(
                        (r.stress[k] - sigma[k]).abs() <= 1e-8 * scale,
                        "ε_r {eps_r}, σ {sigma:?}: relaxed {:?}",
                        r.stress
                    );
                }
                // Along each principal stress the strain is short by ε_r² k_ref / σᵢ.
                for (i, (a, b)) in [(c, sn), (-sn, c)].into_iter().enumerate() {
                    // n·E n of a Voigt strain (E₁₁, E₂₂, 2E₁₂).
                    let m = [a * a, b * b, a * b];
                    let short = dot(&m, &elastic) - dot(&m, &eps);
                    let want = eps_r * eps_r * k_ref / s[i];
                    assert!((short - want).abs() <= 1e-9 * want, "{short} vs {want}");
                }
            }
        }
    }
}

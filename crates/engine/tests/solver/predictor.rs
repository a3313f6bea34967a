//! The implicit-Euler predictor (`NewtonOptions::predictor`) only changes Newton's starting
//! point: every predictor reaches the same states (to the Newton tolerance), and for a smooth
//! motion the extrapolating guesses need fewer iterations than constant velocity.

use engine::aero::{Fluid, TriangleDrag};
use engine::{ImplicitEuler, NewtonOptions, Predictor};
use rand::{rngs::StdRng, Rng, SeedableRng};

const TOL: f64 = 1e-8; // N (forces ~100 N)
const DT: f64 = 2e-3;
const STEPS: usize = 100;

/// The thrown crumpled sheet with triangle drag: it decelerates smoothly from ~10 m/s towards
/// its terminal speed (accelerations of ~100 m/s² that change over ~0.1 s ≫ dt).
fn run(predictor: Predictor) -> (Vec<f64>, u64) {
    let mut rng = StdRng::seed_from_u64(3);
    let (mut model, mut state, s) =
        engine::reference::sheet::thrown_crumpled_sheet(&mut || rng.random_range(-1.0..1.0));
    model.add_force(TriangleDrag::new(&s.tris, 1.75, 0.5, &Fluid::air()));
    let opts = NewtonOptions {
        force_tol_abs: Some(TOL),
        force_tol_rel: 0.0,
        hold_factors: true,
        reuse_contraction: 0.3,
        predictor,
        ..Default::default()
    };
    let mut st = ImplicitEuler::new(&model, opts).unwrap();
    for _ in 0..STEPS {
        st.step(&mut model, &mut state, DT).unwrap();
    }
    (state.q, st.counters().iterations)
}

#[test]
fn predictors_reach_the_same_states_and_extrapolation_saves_iterations() {
    let (q_cv, it_cv) = run(Predictor::ConstantVelocity);
    let (q_ca, it_ca) = run(Predictor::ConstantAcceleration);
    let (q_cj, it_cj) = run(Predictor::ConstantJerk);
    let (q_ad, it_ad) = run(Predictor::Adaptive);
    eprintln!("iterations: velocity {it_cv}, acceleration {it_ca}, jerk {it_cj}, adaptive {it_ad}");
    // Each step's root is unique near the previous state (M/dt² ≥ 1e4 N/m for the lightest
    // node, 0.042 kg, against stress-free springs); two solutions within the tolerance differ
    // by ≤ 2 · 1e3 TOL / (m/dt²) ≈ 2e-9 m per step (1e3 TOL: the step-size criterion), and
    // implicit Euler does not amplify such differences: ≤ 100 × 2e-9 m = 2e-7 m.
    for (name, q) in [
        ("acceleration", &q_ca),
        ("jerk", &q_cj),
        ("adaptive", &q_ad),
    ] {
        let d = q
            .iter()
            .zip(&q_cv)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        eprintln!("{name}: max |Δq| = {d:.2e} m");
        assert!(d <= 2e-7, "{name}: states differ by {d} m");
    }
    assert!(it_ca < it_cv, "extrapolation saved no iterations");
    assert!(
        it_cj < it_ca,
        "constant jerk saved no iterations over constant acceleration"
    );
    assert!(it_ad < it_cv, "adaptive saved no iterations");
}

//! `NewtonOptions::accuracy_fraction`: a step accepted on the accuracy-based test is within
//! `η` of backward Euler's local error (plus the floor's displacement `h² ε a_ref`) of the
//! strictly converged step from the same state (docs/engine.md §Newton tolerance).

use engine::{ImplicitEuler, Model, NewtonOptions, State};

use crate::common::thrown_sheet_with_drag;

const G: f64 = 9.81;

/// The thrown crumpled sheet under triangle drag: drag ≈ 100 N against ≈ 10 N of weight, so
/// the accelerations (and the local error) are large and the test has room to act.
fn model() -> (Model, State) {
    thrown_sheet_with_drag(11)
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// Step a strict trajectory; from each of its states also solve the step with the accuracy
/// test (plain exact Newton and the tuned `recommended()` path) and compare.
fn check(loose: NewtonOptions, dt: f64, steps: usize) -> u64 {
    let strict = NewtonOptions {
        force_tol_abs: Some(1e-11),
        force_tol_rel: 0.0,
        max_iterations: 60,
        ..Default::default()
    };
    let (mut m, mut s) = model();
    let mut exact = ImplicitEuler::new(&m, strict).unwrap();
    let mut fast = ImplicitEuler::new(&m, loose).unwrap();
    for step in 0..steps {
        let q_fast = fast.try_step(&m, &s, dt).unwrap().q().to_vec();
        let prev = s.clone();
        exact.step(&mut m, &mut s, dt).unwrap();
        // Backward Euler's local error estimate of the step: ½ ‖q_{n+1} − q_n − h v_n‖∞.
        let e = 0.5
            * s.q
                .iter()
                .zip(&prev.q)
                .zip(&prev.v)
                .map(|((q, q0), v0)| (q - q0 - dt * v0).abs())
                .fold(0.0, f64::max);
        let floor = dt * dt * loose.accuracy_floor * G;
        let bound = loose.accuracy_fraction * e + floor;
        let d = max_diff(&q_fast, &s.q);
        assert!(
            d <= bound,
            "step {step}: accepted state {d:.3e} m from the strict one > {bound:.3e} m \
             (η e = {:.3e}, floor {floor:.3e})",
            loose.accuracy_fraction * e
        );
        // The comparison has teeth: the local error is far above round-off.
        assert!(e > 1e-6, "step {step}: e = {e}");
    }
    fast.counters().accuracy_accepts
}

#[test]
fn the_residual_left_moves_the_state_by_at_most_one_percent_of_the_local_error() {
    let plain = NewtonOptions {
        accuracy_fraction: 0.01,
        accuracy_floor: 1e-4,
        reference_acceleration: G,
        ..Default::default()
    };
    let tuned = NewtonOptions {
        reference_acceleration: G,
        ..NewtonOptions::recommended()
    };
    for (name, o) in [("plain", plain), ("recommended", tuned)] {
        for dt in [1e-3, 5e-3] {
            let accepted = check(o, dt, 20);
            // The test did loosen the solve (else the comparison would be vacuous).
            assert!(accepted > 0, "{name} dt {dt}: never accepted on accuracy");
        }
    }
}

#[test]
fn strict_options_never_use_the_accuracy_test() {
    let (mut m, mut s) = model();
    let o = NewtonOptions {
        reference_acceleration: G,
        ..NewtonOptions::recommended()
    }
    .strict();
    let mut st = ImplicitEuler::new(&m, o).unwrap();
    for _ in 0..10 {
        st.step(&mut m, &mut s, 1e-3).unwrap();
    }
    assert_eq!(st.counters().accuracy_accepts, 0);
    assert!(st.counters().iterations > 0);
}

//! Backward-Euler numerical damping: an undamped spring of angular frequency ω stepped with
//! `dt` loses amplitude by exactly `1/√(1 + (ω dt)²)` per step.
use engine::reference::spring::{backward_euler_decay, spring_model};
use engine::rod::Stretch;
use engine::{DofLayout, ImplicitEuler, Model, NewtonOptions, State};

#[test]
fn amplitude_decays_by_exact_backward_euler_factor() {
    let (k_axial, rest, mass): (f64, f64, f64) = (200.0, 0.5, 0.1);
    let omega = (k_axial / rest / mass).sqrt(); // axial stiffness k/l̄
    for &dt in &[1e-3f64, 1e-2, 5e-2] {
        let (mut model, mut state) = spring_model(k_axial, rest, mass);
        state.q[3] = rest + 0.01; // 1 cm initial stretch
        let opts = NewtonOptions {
            force_tol_abs: Some(1e-13),
            ..Default::default()
        };
        let mut stepper = ImplicitEuler::new(&model, opts).unwrap();
        let amp = |s: &State| ((s.q[3] - rest).powi(2) + (s.v[3] / omega).powi(2)).sqrt();
        let expected = backward_euler_decay(omega, dt);
        // Stop while the amplitude is ≥ 10 µm: below that, round-off in x − l̄ (x ≈ 0.5 m)
        // rather than the integrator limits the measured ratio.
        while amp(&state) > 1e-5 {
            let a0 = amp(&state);
            let rep = stepper.step(&mut model, &mut state, dt).unwrap();
            assert!(rep.iterations <= 2, "linear problem: {rep:?}");
            let ratio = amp(&state) / a0;
            assert!(
                (ratio - expected).abs() < 1e-9,
                "dt={dt}: ratio {ratio} vs {expected}"
            );
            // Motion stays on the axis.
            assert_eq!(state.q[4], 0.0);
        }
    }
}

#[test]
fn fixed_dofs_do_not_move_and_state_is_unchanged_on_failure() {
    let (mut model, mut state) = spring_model(1e3, 1.0, 1.0);
    state.q[3] = 1.5;
    let opts = NewtonOptions {
        max_iterations: 0,
        ..Default::default()
    };
    let mut stepper = ImplicitEuler::new(&model, opts).unwrap();
    let before = state.clone();
    let err = stepper.step(&mut model, &mut state, 1e-2).unwrap_err();
    assert!(err.to_string().contains("did not converge"), "{err}");
    assert_eq!(state, before);
    let mut stepper = ImplicitEuler::new(&model, NewtonOptions::default()).unwrap();
    stepper.step(&mut model, &mut state, 1e-2).unwrap();
    assert_eq!(&state.q[0..3], &[0.0, 0.0, 0.0]);
    assert_eq!(&state.v[0..3], &[0.0, 0.0, 0.0]);
}

#[test]
fn missing_mass_is_a_clear_error() {
    let mut model = Model::new(DofLayout::new(2, 0));
    let q = vec![0.0, 0.0, 0.0, 1.0, 0.0, 0.0];
    model.add_force(Stretch::new("spring", &[[0, 1]], &q, vec![1.0]));
    model.add_node_mass(0, 1.0);
    let err = ImplicitEuler::new(&model, NewtonOptions::default())
        .err()
        .unwrap();
    assert!(err.to_string().contains("non-positive mass"), "{err}");
}

#[test]
fn jacobian_reuse_reaches_the_same_tolerance() {
    // A stiff nonlinear (transverse) spring motion stepped with full and modified Newton:
    // both converge to the same residual tolerance, so the trajectories agree to within
    // the Newton tolerance propagated over the steps (far below 1e-9 m here).
    let run = |reuse: bool| {
        let (mut model, mut state) = spring_model(1e4, 1.0, 0.5);
        state.v[4] = 3.0; // transverse kick: geometric nonlinearity
        state.q[3] = 1.1;
        let opts = NewtonOptions {
            hold_factors: reuse,
            reuse_contraction: if reuse { 0.3 } else { 0.0 },
            // Spring forces are ~1e3 N, so 1e-8 N is ~1e-11 relative: near round-off.
            force_tol_abs: Some(1e-8),
            ..Default::default()
        };
        let mut stepper = ImplicitEuler::new(&model, opts).unwrap();
        let mut factorizations = 0;
        for _ in 0..200 {
            let rep = stepper.step(&mut model, &mut state, 1e-3).unwrap();
            factorizations += rep.factorizations;
            // Converged by the residual test, or by the step test (|Δq| ≤ 1e-12 m) with the
            // residual within 1e3 × tolerance, as documented in `stepper/convergence.rs`.
            assert!(rep.residual <= 1e3 * 1e-8, "{rep:?} reuse={reuse}");
        }
        (state, factorizations)
    };
    let (full, f_full) = run(false);
    let (reused, f_reused) = run(true);
    for (a, b) in full.q.iter().zip(&reused.q) {
        assert!((a - b).abs() < 1e-9, "{a} vs {b}");
    }
    assert!(
        f_reused < f_full,
        "reuse saved no factorisations: {f_reused} vs {f_full}"
    );
}

#[test]
fn tiny_steps_far_from_the_origin_converge_to_the_roundoff_floor() {
    // At dt = 1e-6 s and 10 km from the origin the inertia term's round-off (ε m |q|/dt² ≈
    // 1 N) is far above the default tolerance (~1e-8 N): Newton must stop at the floor
    // instead of failing on round-off.
    let (mut model, mut state) = spring_model(1e3, 1.0, 0.5);
    // Offset along the spring's axis, so the moving coordinate itself is large.
    state.q[0] = 1e4;
    state.q[3] = 1e4 + 1.2;
    state.v[3] = 1.0;
    let mut stepper = ImplicitEuler::new(&model, NewtonOptions::default()).unwrap();
    for _ in 0..10 {
        stepper.step(&mut model, &mut state, 1e-6).unwrap();
    }
    // The motion is still the spring's: x moved by ≈ v t = 1e-5 m.
    assert!(
        (state.q[3] - 1e4 - 1.2 - 1e-5).abs() < 1e-7,
        "{}",
        state.q[3]
    );
}

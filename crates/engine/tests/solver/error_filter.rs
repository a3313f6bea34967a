//! The local error estimate filtered through the step's Newton matrix (RADAU5-style,
//! `engine::stepper::error_control` module docs): `ê = (M + h² K)⁻¹ M e` scales a mode of
//! angular frequency ω by `1/(1 + ω²h²)`, so a smooth mode passes and a stiff one is damped;
//! without factors for the step's own `h` the raw estimate is used.
use engine::loads::{ConstantForces, Gravity};
use engine::reference::spring::spring_model;
use engine::stepper::error_control::raw_estimate;
use engine::{DofLayout, ImplicitEuler, Model, NewtonOptions, Predictor, State};

/// One step of a spring (axial ω, transverse 0 at its rest length) pushed from rest by a
/// small constant force along x (`axis = 0`, the axial mode) or z (`axis = 2`, a transverse
/// one): the filtered estimate over the raw one along the push, and ω h. (One push at a
/// time: with both, the tilt of the spring couples the larger transverse estimate into the
/// axial one by ~0.5 %.)
fn filtered_over_raw(h: f64, axis: usize) -> (f64, f64) {
    let (k_axial, rest, mass): (f64, f64, f64) = (200.0, 0.5, 0.1);
    let omega = (k_axial / (rest * mass)).sqrt();
    let (mut model, state) = spring_model(k_axial, rest, mass);
    // 1 mN: the step moves the node by ≤ h² F/m ≤ 25 µm, so the spring stays linear and its
    // transverse (geometric) stiffness stays ~0.
    let mut push = [0.0; 3];
    push[axis] = 1e-3;
    model.add_force(ConstantForces::new("push", &[1], &[push]));
    let opts = NewtonOptions {
        force_tol_abs: Some(1e-15),
        ..Default::default()
    };
    let mut stepper = ImplicitEuler::new(&model, opts).unwrap();
    stepper.set_error_filter(true);
    let trial = stepper.try_step(&model, &state, h).unwrap();
    assert!(trial.error_filtered());
    let mut raw = vec![0.0; 6];
    raw_estimate(&model, &state.v, trial.v(), h, &mut raw);
    let d = 3 + axis;
    assert!(raw[d] != 0.0, "{raw:?}");
    (trial.local_error()[d] / raw[d], omega * h)
}

#[test]
fn filter_damps_a_stiff_mode_by_1_over_1_plus_omega2_h2_and_keeps_a_smooth_one() {
    // ω = 63 rad/s: ω h = 0.063 (resolved) and 3.2 (stiff).
    for h in [1e-3, 5e-2] {
        let (axial, wh) = filtered_over_raw(h, 0);
        let (transverse, _) = filtered_over_raw(h, 2);
        let expected = 1.0 / (1.0 + wh * wh);
        assert!(
            (axial - expected).abs() < 1e-6 * expected,
            "h={h}: axial ratio {axial} vs {expected}"
        );
        assert!((transverse - 1.0).abs() < 1e-6, "h={h}: {transverse}");
    }
    // The stiff case is really damped (≈ 1/11), the resolved one barely (≈ 0.996).
    assert!(filtered_over_raw(5e-2, 0).0 < 0.1);
    assert!(filtered_over_raw(1e-3, 0).0 > 0.99);
}

#[test]
fn a_step_without_factors_for_its_own_dt_uses_the_raw_estimate() {
    // A free fall: after one step the constant-acceleration predictor is the exact
    // backward-Euler solution of the next step, which then converges at the predictor
    // without factorising; the factors held are those of the first step's dt.
    let mut model = Model::new(DofLayout::new(1, 0));
    model.add_node_mass(0, 2.0);
    model.add_force(Gravity::new(&[0], &[2.0], [0.0, 0.0, -9.81]));
    let mut state = State::at_rest(vec![0.0; 3]);
    let opts = NewtonOptions {
        predictor: Predictor::ConstantAcceleration,
        ..Default::default()
    };
    let mut stepper = ImplicitEuler::new(&model, opts).unwrap();
    stepper.set_error_filter(true);
    let trial = stepper.try_step(&model, &state, 1e-2).unwrap();
    // No stiffness: the filter leaves a rigid fall's estimate as it is.
    assert!(trial.error_filtered());
    let e1 = trial.local_error()[2];
    assert!((e1 - 0.5 * 1e-2 * (-9.81 * 1e-2)).abs() < 1e-15, "{e1}");
    trial.commit(&mut model, &mut state);
    let trial = stepper.try_step(&model, &state, 2e-2).unwrap();
    assert_eq!(
        trial.report().factorizations,
        0,
        "converged at the predictor"
    );
    assert!(!trial.error_filtered());
    let mut raw = vec![0.0; 3];
    raw_estimate(&model, &state.v, trial.v(), 2e-2, &mut raw);
    assert_eq!(trial.local_error(), &raw[..]);
    assert!(raw[2] < 0.0);
    let t = stepper.counters();
    assert_eq!((t.error_filters, t.error_filter_fallbacks), (1, 1));
}

#[test]
fn the_filter_is_off_unless_asked_for() {
    let (model, state) = spring_model(200.0, 0.5, 0.1);
    let mut stepper = ImplicitEuler::new(&model, NewtonOptions::default()).unwrap();
    let trial = stepper.try_step(&model, &state, 1e-2).unwrap();
    assert!(!trial.error_filtered());
    assert_eq!(stepper.counters().error_filter_fallbacks, 0);
}

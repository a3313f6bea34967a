//! `NewtonOptions::single_precision`: Newton matrices factorised in single precision give
//! the same steps to within the solve's tolerance, and an ill-conditioned matrix switches
//! the run back to double.

use engine::prelude::*;

/// `steps` steps of `dt` of the 9 × 5-node Kevlar sheet (6 m × 3 m, 50 N per corner) from
/// rest with `opts`; the final state and whether single precision was still on.
fn fly(opts: NewtonOptions, dt: f64, steps: usize) -> (State, bool) {
    let (mut model, mut state) = engine::reference::sheet::kevlar_sheet(9, 5, 6.0, 3.0, 50.0);
    let mut st = ImplicitEuler::new(&model, opts).unwrap();
    for _ in 0..steps {
        st.step(&mut model, &mut state, dt).unwrap();
    }
    (state, st.single_precision())
}

#[test]
fn single_precision_steps_agree_with_double_to_the_tolerance() {
    let dt = 1e-3;
    let strict = NewtonOptions::recommended().strict();
    let (s64, _) = fly(strict, dt, 40);
    let (s32, on) = fly(
        NewtonOptions {
            single_precision: true,
            ..strict
        },
        dt,
        40,
    );
    assert!(on, "the check switched a well-conditioned sheet to double");
    // Both meet ‖R‖∞ ≤ ~1e-9 (1 N + Σm g) per step on a Newton matrix ≥ M/dt² (≥ 1e5 N/m
    // per DOF here): each step's states agree to ~1e-14 m, 40 steps to far below 1e-10 m.
    let dq = s64
        .q
        .iter()
        .zip(&s32.q)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    assert!(dq < 1e-10, "{dq} m");
}

#[test]
fn an_ill_conditioned_newton_matrix_switches_to_double() {
    let opts = NewtonOptions {
        single_precision: true,
        ..NewtonOptions::recommended()
    };
    let (model, mut state) = engine::reference::sheet::kevlar_sheet(9, 5, 6.0, 3.0, 50.0);
    // Crumpled (by up to 5 mm), so that the stiff in-plane and the soft
    // out-of-plane directions couple in the Newton matrix.
    for (i, q) in state.q.iter_mut().enumerate() {
        *q += 0.005 * (1.7 * i as f64).sin();
    }
    // Well conditioned at 1 ms; at dt = 0.5 s, M/dt² is ~1e-7 of the Kevlar membrane's
    // stiffness: single precision cannot factorise or solve the Newton matrix accurately
    // (cond × 6e-8 ≫ 1e-3), and the first factorisation (its breakdown) or the first solve
    // (its accuracy check) switches the stepper to double, whether or not the step then
    // converges.
    for (dt, stays) in [(1e-3, true), (0.5, false)] {
        let mut st = ImplicitEuler::new(&model, opts).unwrap();
        let _ = st.try_step(&model, &state, dt);
        assert_eq!(st.single_precision(), stays, "dt = {dt}");
    }
}

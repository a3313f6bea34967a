//! The step solver's ladder of stages (`stepper/controller.rs`): every stage converges to the
//! same implicit-Euler equations, the later stages take steps the Newton stage gives up on,
//! the held stage takes smooth steps without a factorisation, and the retry ledger stops the
//! expensive stages once their failures outweigh the solves that succeeded.

use engine::prelude::*;

use crate::common::exact_residuals;

const G: f64 = 9.81;

/// The report's Kevlar sheet (6 m × 3 m, 7 × 4 nodes) under 50 N per corner, flat at rest.
fn kevlar() -> (Model, State) {
    engine::reference::sheet::kevlar_sheet(7, 4, 6.0, 3.0, 50.0)
}

/// `‖M (q − q_n − dt v_n)/dt² − F(q, (q − q_n)/dt)‖∞` (N) over the free DOFs.
fn exact_residual(model: &Model, prev: &State, q: &[f64], dt: f64) -> f64 {
    exact_residuals(model, prev, q, dt)
        .into_iter()
        .zip(&model.fixed)
        .filter(|(_, &fixed)| !fixed)
        .fold(0.0, |worst, (r, _)| worst.max(r))
}

/// `steps` steps of `dt` from rest with `opts`, each failure retried as two half steps (as
/// the run loop would): the failures, the counters, and the largest exact residual of an
/// accepted full step.
fn run(opts: NewtonOptions, dt: f64, steps: usize) -> (usize, engine::Counters, f64) {
    let (mut model, mut state) = kevlar();
    let mut st = ImplicitEuler::new(&model, opts).unwrap();
    let (mut failed, mut worst) = (0, 0.0f64);
    for _ in 0..steps {
        let prev = state.clone();
        match st.step(&mut model, &mut state, dt) {
            Ok(_) => worst = worst.max(exact_residual(&model, &prev, &state.q, dt)),
            Err(_) => {
                failed += 1;
                for _ in 0..2 {
                    st.step(&mut model, &mut state, dt / 2.0)
                        .expect("half step");
                }
            }
        }
    }
    (failed, *st.counters(), worst)
}

/// Strict tolerances: 1e-6 N on forces of ~50 N.
fn strict(o: NewtonOptions) -> NewtonOptions {
    NewtonOptions {
        reference_acceleration: G,
        force_tol_abs: Some(1e-6),
        force_tol_rel: 0.0,
        ..o
    }
    .strict()
}

/// Whichever stage converged, an accepted step meets the exact equations to the tolerance
/// (1e3 × it where the step-size test ended the solve); at dt = 1e-2 s from rest the Kevlar
/// sheet rotates its stiff membrane too fast for factors held from the step before (the
/// held stage gives up), and the Newton stage's chord iterations reuse its factorisations.
#[test]
fn every_stage_converges_to_the_same_equations() {
    let (failed, c, worst) = run(strict(NewtonOptions::recommended()), 1e-2, 40);
    eprintln!("{c:?}\nworst exact residual {worst:.3e} N");
    assert_eq!(failed, 0, "{c:?}");
    assert!(worst <= 1e3 * 1e-6, "{worst}");
    assert!(c.held.runs > 0, "{c:?}");
    assert!(
        c.iterations > c.factorizations,
        "no chord iterations: {c:?}"
    );
}

/// With three Newton iterations per solve the Newton stage gives up on every step of the
/// sheet's first 0.4 s from rest; the continuation and homotopy stages (four times that
/// budget, and sub-steps) take most of them whole, on the same equations. Each step is tried
/// from the same state by fresh steppers (`try_step`, nothing committed; no ledger history),
/// the run itself advanced by the recommended settings.
#[test]
fn later_stages_take_steps_the_newton_stage_gives_up_on() {
    let tight = |later| NewtonOptions {
        max_iterations: 3,
        continuation: later,
        step_homotopy: later,
        ..strict(NewtonOptions::recommended())
    };
    let dt = 1e-2;
    let (mut model, mut state) = kevlar();
    let mut main = ImplicitEuler::new(&model, strict(NewtonOptions::recommended())).unwrap();
    let (mut failed_without, mut failed_with, mut rescued, mut worst) = (0, 0, 0, 0.0f64);
    for _ in 0..40 {
        let mut without = ImplicitEuler::new(&model, tight(false)).unwrap();
        failed_without += usize::from(without.try_step(&model, &state, dt).is_err());
        let mut with = ImplicitEuler::new(&model, tight(true)).unwrap();
        match with.try_step(&model, &state, dt) {
            Ok(t) => worst = worst.max(exact_residual(&model, &state, t.q(), dt)),
            Err(_) => failed_with += 1,
        }
        let c = with.counters();
        rescued += c.continuation.converged + c.homotopy.converged;
        main.step(&mut model, &mut state, dt).unwrap();
    }
    eprintln!("{failed_without} failures without, {failed_with} with, {rescued} rescued");
    assert!(failed_without > 0, "the Newton stage alone took every step");
    assert!(
        2 * failed_with < failed_without,
        "{failed_with} of {failed_without}"
    );
    assert_eq!(rescued as usize, failed_without - failed_with);
    assert!(worst <= 1e3 * 1e-6, "{worst}");
}

/// The retry ledger (`stepper/retry_ledger.rs`): the later stages run only while the
/// factorisations of failed solves do not exceed those of successful ones. With one
/// iteration per stage and a round-off tolerance no solve can converge, so every later stage
/// fails: the first failing solve runs them (nothing has been wasted yet), the next does not,
/// and dropping the held factors at a sync point clears the ledger, so the one after runs
/// them again.
#[test]
fn later_stages_stop_once_failures_outweigh_the_solves_that_succeeded() {
    let o = NewtonOptions {
        max_iterations: 1,
        force_tol_abs: Some(1e-12),
        step_homotopy: false,
        ..strict(NewtonOptions::recommended())
    };
    let (mut model, mut state) = kevlar();
    let mut st = ImplicitEuler::new(&model, o).unwrap();
    let mut counts = Vec::new();
    for sync in [false, false, true] {
        if sync {
            st.invalidate_factorization();
        }
        assert!(st.step(&mut model, &mut state, 1e-2).is_err());
        let c = st.counters();
        counts.push((c.continuation.runs, c.stages_skipped));
    }
    assert_eq!(counts, [(1, 0), (1, 1), (2, 1)], "{:?}", st.counters());
}

/// The sheet in free fall without drag or load moves rigidly, so its Newton matrix (`M/h²`
/// plus the stress-free membrane's stiffness) does not change: after the first step, which
/// factorises it, the held stage solves every step without a factorisation.
#[test]
fn the_held_stage_takes_smooth_steps_without_factorising() {
    let no_drag =
        |_: &_| -> Box<dyn Force> { Box::new(engine::loads::DofForces::new(vec![], vec![])) };
    let (mut model, mut state) =
        engine::reference::sheet::kevlar_sheet_with(7, 4, 6.0, 3.0, 0.0, no_drag);
    let opts = strict(NewtonOptions::recommended());
    let mut st = ImplicitEuler::new(&model, opts).unwrap();
    for _ in 0..20 {
        st.step(&mut model, &mut state, 1e-2).unwrap();
    }
    let c = st.counters();
    assert_eq!(c.held.runs, 19, "{c:?}");
    assert_eq!(c.held.converged, 19, "{c:?}");
    assert_eq!(c.factorizations, 1, "{c:?}");
}

//! `NewtonOptions::exact_retry`: a step that modified Newton (stale factors, the symmetric
//! approximation of the drag Jacobian, the extrapolating predictor) gives up on, but that
//! exact Newton with a line search converges, is taken instead of being rejected.

use engine::prelude::*;

const G: f64 = 9.81;

/// The report's Kevlar sheet under corner forces (`engine::reference::sheet::kevlar_sheet`).
fn kevlar(nx: usize, ny: usize, lx: f64, ly: f64, corner_n: f64) -> (Model, State) {
    engine::reference::sheet::kevlar_sheet(nx, ny, lx, ly, corner_n)
}

/// `steps` steps of `dt` with `opts`: the number of failed solves (each would halve `dt` in
/// a run; the step is then taken as two half steps) and the stepper's timings.
fn failures(
    opts: NewtonOptions,
    dt: f64,
    steps: usize,
    m: (Model, State),
) -> (usize, engine::Timings) {
    let (mut model, mut state) = m;
    let mut st = ImplicitEuler::new(&model, opts).unwrap();
    let mut failed = 0;
    for _ in 0..steps {
        // A failure is retried at dt/2 twice, as the run loop would.
        if st.step(&mut model, &mut state, dt).is_err() {
            failed += 1;
            for _ in 0..2 {
                st.step(&mut model, &mut state, dt / 2.0)
                    .expect("half step");
            }
        }
    }
    (failed, *st.timings())
}

/// The 7 × 4-node Kevlar sheet (6 m × 3 m, 50 N per corner) at dt = 1e-2 s from rest:
/// modified Newton without the retry fails 5 of the first 40 steps (measured; each would
/// halve dt in a run); with the retry every step is taken at the full dt.
#[test]
fn a_step_modified_newton_abandons_is_taken_by_the_exact_retry() {
    let o = NewtonOptions {
        reference_acceleration: G,
        ..NewtonOptions::recommended()
    };
    let without = NewtonOptions {
        exact_retry: false,
        ..o
    };
    let (failed_before, _) = failures(without, 1e-2, 40, kevlar(7, 4, 6.0, 3.0, 50.0));
    // The control: this case does defeat the fast path.
    assert!(failed_before > 0, "modified Newton took every step");
    let (failed, t) = failures(o, 1e-2, 40, kevlar(7, 4, 6.0, 3.0, 50.0));
    assert_eq!(failed, 0, "{t:?}");
    assert!(
        t.exact_retries > 0 && t.exact_retries == t.exact_retries_converged,
        "{t:?}"
    );
}

/// The retry's first stage keeps the symmetric approximation's Cholesky/LDLᵀ factors and
/// corrects every update by BiCGStab; LU (several times the storage and the time of those
/// factors) is only its fallback. On the Kevlar sheet with the report's (non-symmetric)
/// triangle drag every retry converges in that first stage: no LU at all, and still no step
/// rejected.
#[test]
fn the_exact_retry_converges_without_lu_where_the_correction_converges() {
    let o = NewtonOptions {
        reference_acceleration: G,
        ..NewtonOptions::recommended()
    };
    let sheet = || engine::reference::sheet::kevlar_sheet_report_drag(7, 4, 6.0, 3.0, 50.0);
    let (failed, t) = failures(o, 1e-2, 40, sheet());
    assert_eq!(failed, 0, "{t:?}");
    assert!(t.exact_retries > 0, "{t:?}");
    assert_eq!(t.lu_factorizations, 0, "{t:?}");
    // The control: J is not symmetric, so without the approximation every factorisation is LU.
    let exact = NewtonOptions {
        symmetric_approx: false,
        ..o
    };
    let (_, t) = failures(exact, 1e-2, 5, sheet());
    assert_eq!(t.lu_factorizations, t.factorizations, "{t:?}");
}

/// The retry ledger (`stepper/retry_ledger.rs`): a failed solve is retried only while the
/// factorisations of failed solves do not exceed those of successful ones. With one Newton
/// iteration allowed and a round-off tolerance, no solve of the Kevlar sheet can converge,
/// so every retry fails: the first failure is retried (nothing has been wasted yet), the
/// next is not (failures now outweigh the zero successes), and dropping the held factors at
/// a sync point clears the ledger, so the one after is retried again.
#[test]
fn failed_retries_stop_once_they_outweigh_the_solves_that_succeeded() {
    let o = NewtonOptions {
        reference_acceleration: G,
        max_iterations: 1,
        force_tol_abs: Some(1e-12),
        accuracy_fraction: 0.0,
        continuation: false,
        step_homotopy: false,
        ..NewtonOptions::recommended()
    };
    let (mut model, mut state) = kevlar(7, 4, 6.0, 3.0, 50.0);
    let mut st = ImplicitEuler::new(&model, o).unwrap();
    let mut counts = Vec::new();
    for sync in [false, false, true] {
        if sync {
            st.invalidate_factorization();
        }
        assert!(st.step(&mut model, &mut state, 1e-2).is_err());
        let t = st.timings();
        counts.push((t.exact_retries, t.exact_retries_skipped));
    }
    assert_eq!(counts, [(1, 0), (1, 1), (2, 1)], "{:?}", st.timings());
}

//! The Newton update of a non-symmetric Jacobian (triangle drag): the symmetric part is
//! factorised (never LU), and the update is corrected by BiCGStab where the skew part matters
//! (`stepper/linearization.rs`). The residual is exact, so every accepted step must satisfy
//! the *exact* implicit-Euler equations to the tolerance; we recompute that residual
//! independently here.

use engine::{ImplicitEuler, Model, NewtonOptions, State};

use crate::common::{exact_residuals, thrown_sheet_with_drag};

/// The thrown sheet (seed 7): drag (≈ 100 N) dominates the weight, so the skew part of J is
/// as large as it gets here.
fn model() -> (Model, State) {
    thrown_sheet_with_drag(7)
}

/// `‖M (q − q_n − dt v_n)/dt² − F(q, (q − q_n)/dt)‖∞` (N) over every DOF.
fn exact_residual(model: &Model, prev: &State, q: &[f64], dt: f64) -> f64 {
    exact_residuals(model, prev, q, dt)
        .into_iter()
        .fold(0.0, f64::max)
}

const TOL: f64 = 1e-9; // N; forces are ~100 N, round-off ~1e-13 N.

fn strict(o: NewtonOptions) -> NewtonOptions {
    NewtonOptions {
        force_tol_abs: Some(TOL),
        force_tol_rel: 0.0,
        max_iterations: 50,
        ..o
    }
    .strict()
}

/// Plain Newton and the recommended ladder (held factors, chord iterations) reach the exact
/// equations and the same states.
#[test]
fn held_and_chord_updates_converge_to_the_exact_equations() {
    const DT: f64 = 0.005;
    let (mut m_plain, mut s_plain) = model();
    let (mut m_fast, mut s_fast) = model();
    let mut plain = ImplicitEuler::new(&m_plain, strict(NewtonOptions::default())).unwrap();
    let mut fast = ImplicitEuler::new(&m_fast, strict(NewtonOptions::recommended())).unwrap();
    for step in 0..10 {
        let prev = s_fast.clone();
        let r0 = exact_residual(&m_fast, &prev, &prev.q, DT);
        plain.step(&mut m_plain, &mut s_plain, DT).unwrap();
        fast.step(&mut m_fast, &mut s_fast, DT).unwrap();
        let r = exact_residual(&m_fast, &prev, &s_fast.q, DT);
        // The control: the start of the step is far from the solution.
        assert!(r0 > 1e3 * TOL);
        // The documented criterion: ‖R‖∞ ≤ TOL, or an update below `step_tol` (1e-12 m) with
        // ‖R‖∞ ≤ 1e3 TOL (the springs' 1e4 N/m turn 1e-12 m into 1e-8 N).
        assert!(
            r <= 1e3 * TOL,
            "step {step}: exact residual {r} > 1e3 × {TOL}"
        );
        // Near the previous state the root is unique (M/dt² ≥ 1.7e3 N/m for the lightest
        // node, 0.042 kg, dominates the stress-free springs' geometric terms), so
        // |Δq| ≤ 2 · 1e3 TOL / (m/dt²) ≈ 1.2e-9 m per step; 1e-8 m allows that for each of the
        // 10 steps.
        let dq = s_plain
            .q
            .iter()
            .zip(&s_fast.q)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(dq <= 1e-8, "step {step}: paths differ by {dq} m");
    }
    let (cp, cf) = (plain.counters(), fast.counters());
    eprintln!("plain {cp:?}\nrecommended {cf:?}");
    // Plain Newton factorises at every iteration; the ladder reuses factors.
    assert_eq!(cp.factorizations, cp.iterations, "{cp:?}");
    assert!(cf.factorizations < cf.iterations, "{cf:?}");
}

/// At dt = 0.05 s the drag Jacobian over dt (∝ ρ C_D A |v| / dt) is no longer small against
/// M/dt² (∝ 1/dt²): the symmetric part's update leaves a linearised residual
/// `‖(J − J_s) Δ‖` above 0.1 ‖R‖, and the Newton update is corrected by BiCGStab (no LU);
/// every step still reaches the exact equations.
#[test]
fn strong_drag_corrects_the_update_by_krylov() {
    const DT: f64 = 0.05;
    let (mut m, mut s) = model();
    let mut st = ImplicitEuler::new(&m, strict(NewtonOptions::default())).unwrap();
    for step in 0..5 {
        let prev = s.clone();
        st.step(&mut m, &mut s, DT).unwrap();
        let r = exact_residual(&m, &prev, &s.q, DT);
        assert!(r <= 1e3 * TOL, "step {step}: exact residual {r}");
    }
    let c = st.counters();
    eprintln!("{c:?}");
    assert!(c.krylov_iterations > 0, "the correction was not exercised");
    assert_eq!(c.krylov_failures, 0, "every correction converged");
}

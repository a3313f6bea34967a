//! `NewtonOptions::symmetric_approx`: with a non-symmetric Jacobian (triangle drag), the
//! Cholesky factorisation of `½ (J + Jᵀ)` replaces LU of `J`. The residual is still exact,
//! so every accepted step must satisfy the *exact* implicit-Euler equations to the same
//! tolerance as the exact path; we recompute that residual independently here.

use engine::aero::{Fluid, TriangleDrag};
use engine::fdcheck::dense_eval;
use engine::{ImplicitEuler, Model, NewtonOptions, State};
use rand::{rngs::StdRng, Rng, SeedableRng};

/// `reference::sheet::thrown_crumpled_sheet` with triangle drag, thrown at ~10 m/s: drag
/// (≈ 100 N) dominates the weight, so the skew part of J is as large as it gets here.
fn model() -> (Model, State) {
    let mut rng = StdRng::seed_from_u64(7);
    let (mut model, state, s) =
        engine::reference::sheet::thrown_crumpled_sheet(&mut || rng.random_range(-1.0..1.0));
    model.add_force(TriangleDrag::new(&s.tris, 1.75, 0.5, &Fluid::air()));
    (model, state)
}

/// `‖M (q − q_n − dt v_n)/dt² − F(q, (q − q_n)/dt)‖∞` (N), assembled independently (dense,
/// force by force; no force depends on time).
fn exact_residual(model: &Model, prev: &State, q: &[f64], dt: f64) -> f64 {
    let v: Vec<f64> = q.iter().zip(&prev.q).map(|(a, b)| (a - b) / dt).collect();
    let mut f = vec![0.0; q.len()];
    for force in &model.forces {
        let (fi, _, _) = dense_eval(force.as_ref(), q, &v);
        f.iter_mut().zip(&fi).for_each(|(a, b)| *a += b);
    }
    (0..q.len())
        .map(|d| (model.mass[d] * (q[d] - prev.q[d] - dt * prev.v[d]) / (dt * dt) - f[d]).abs())
        .fold(0.0, f64::max)
}

#[test]
fn symmetric_approximation_converges_to_the_exact_equations() {
    const TOL: f64 = 1e-9; // N; forces are ~100 N, round-off ~1e-13 N.
    const DT: f64 = 0.005;
    let opts = |approx, reuse| NewtonOptions {
        force_tol_abs: Some(TOL),
        force_tol_rel: 0.0,
        max_iterations: 50,
        symmetric_approx: approx,
        reuse_jacobian: reuse,
        ..Default::default()
    };
    for reuse in [false, true] {
        let (mut m_exact, mut s_exact) = model();
        let (mut m_sym, mut s_sym) = model();
        let mut exact = ImplicitEuler::new(&m_exact, opts(false, reuse)).unwrap();
        let mut sym = ImplicitEuler::new(&m_sym, opts(true, reuse)).unwrap();
        for step in 0..10 {
            let prev = s_sym.clone();
            let r0 = exact_residual(&m_sym, &prev, &prev.q, DT);
            exact.step(&mut m_exact, &mut s_exact, DT).unwrap();
            sym.step(&mut m_sym, &mut s_sym, DT).unwrap();
            let r = exact_residual(&m_sym, &prev, &s_sym.q, DT);
            eprintln!("reuse {reuse} step {step}: ‖R(q_n)‖ = {r0:.2e}, ‖R‖ = {r:.2e} N");
            // The control: the start of the step is far from the solution, so the check below
            // could fail if the approximation leaked into the residual.
            assert!(r0 > 1e3 * TOL);
            // The engine's documented criterion: ‖R‖∞ ≤ TOL, or an update below `step_tol`
            // (1e-12 m) with ‖R‖∞ ≤ 1e3 TOL (the springs' 1e4 N/m turn 1e-12 m into 1e-8 N,
            // so linearly converging modified Newton can stop there).
            assert!(
                r <= 1e3 * TOL,
                "step {step}: exact residual {r} > 1e3 × {TOL}"
            );
            // Both paths solve the same equations; near the previous state the root is unique
            // (M/dt² ≥ 1.7e3 N/m for the lightest node, 0.042 kg, dominates the stress-free
            // springs' geometric terms), so |Δq| ≤ 2 · 1e3 TOL / (m/dt²) ≈ 1.2e-9 m per step;
            // 1e-8 m allows that for each of the 10 steps.
            let dq = s_exact
                .q
                .iter()
                .zip(&s_sym.q)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            eprintln!("   |Δq| = {dq:.2e} m");
            assert!(dq <= 1e-8, "step {step}: paths differ by {dq} m");
        }
        let (te, ts) = (exact.timings(), sym.timings());
        eprintln!("reuse {reuse}: exact {te:?}\nsymmetric {ts:?}");
        assert_eq!(te.lu_factorizations, te.factorizations, "exact path is LU");
        assert_eq!(ts.lu_factorizations, 0, "approximation path is Cholesky");
        assert!(ts.factorizations > 0);
    }
}

/// At dt = 0.05 s the drag Jacobian over dt (∝ ρ C_D A |v| / dt) is no longer small against
/// M/dt² (∝ 1/dt²): the symmetric approximation's linearised residual `‖(J − J_s) Δ‖` exceeds
/// 0.1 ‖R‖ at some iterates. The solve must then correct the approximate updates into exact
/// Newton updates (BiCGStab preconditioned by the held Cholesky factors, no LU) and still
/// converge to the exact equations.
#[test]
fn strong_drag_corrects_the_approximation_by_krylov() {
    const TOL: f64 = 1e-9;
    const DT: f64 = 0.05;
    let (mut m, mut s) = model();
    let opts = NewtonOptions {
        force_tol_abs: Some(TOL),
        force_tol_rel: 0.0,
        max_iterations: 50,
        symmetric_approx: true,
        ..Default::default()
    };
    let mut st = ImplicitEuler::new(&m, opts).unwrap();
    for step in 0..5 {
        let prev = s.clone();
        st.step(&mut m, &mut s, DT).unwrap();
        let r = exact_residual(&m, &prev, &s.q, DT);
        assert!(r <= 1e3 * TOL, "step {step}: exact residual {r}");
    }
    let t = st.timings();
    eprintln!("{t:?}");
    assert!(t.approx_fallbacks > 0, "the correction was not exercised");
    assert!(t.krylov_iterations > 0);
    assert_eq!(t.krylov_failures, 0, "every correction converged");
    assert_eq!(t.lu_factorizations, 0, "no LU storage was needed");
}

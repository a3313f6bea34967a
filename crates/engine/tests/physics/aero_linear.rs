//! Linear (Stokes-like) drag: the exponential transient `v(t) = v_t (1 − e^{−c t/m})` and the
//! terminal velocity `v_t = m g / Σc`.

use engine::aero::{Fluid, LinearDrag};
use engine::loads::Gravity;
use engine::reference::falling::run;
use engine::rod::Stretch;
use engine::{DofLayout, Model, State};

const G: f64 = 9.81;

#[test]
fn single_node_transient_is_backward_euler_of_the_exponential() {
    // m = 0.5 kg, c = 2.5 N·s/m: λ = c/m = 5 /s, v_t = m g / c = 1.962 m/s.
    let (m, c, dt) = (0.5, 2.5, 1e-3);
    let (lam, vt) = (c / m, m * G / c);
    let mut model = Model::new(DofLayout::new(1, 0));
    model.add_node_mass(0, m);
    model.add_force(Gravity::new(&[0], &[m], [0.0, 0.0, -G]));
    model.add_force(LinearDrag::new(&[0], &[c], &Fluid::air()));
    let mut state = State::at_rest(vec![0.0; 3]);
    let steps = 2000; // 10 time constants
    let series = run(&mut model, &mut state, dt, steps).unwrap();
    let (mut v_be, mut max_err) = (0.0f64, 0.0f64);
    for &(t, v) in &series {
        // The problem is linear, so Newton solves it exactly: the discrete recurrence
        // v_{n+1} = (v_n − g dt)/(1 + λ dt) must hold to round-off. The stepper recovers v
        // as Δq/dt, which carries ε_mach |q|/dt ≈ 1e-12 m/s per step at |q| ≈ 2.5 m; the
        // recurrence is contractive, so 1e-10 m/s bounds the accumulated round-off.
        v_be = (v_be - G * dt) / (1.0 + lam * dt);
        assert!((v[2] - v_be).abs() < 1e-10, "t = {t}: {} vs {v_be}", v[2]);
        let exact = -vt * (1.0 - (-lam * t).exp());
        max_err = max_err.max((v[2] - exact).abs());
    }
    // Backward Euler's global error for v' = −λ(v − v_∞): (1 + λdt)^{−n} − e^{−λ t_n}
    // ≈ (λdt/2) λt e^{−λt}, maximal at λt = 1: v_t λ dt / (2e), up to O((λdt)²) ≈ 0.5 %
    // relative corrections; 2 % leaves room only for those.
    let predicted = vt * lam * dt / (2.0 * std::f64::consts::E);
    eprintln!("max error {max_err:.4e}, predicted {predicted:.4e}");
    assert!(
        (max_err / predicted - 1.0).abs() < 0.02,
        "{max_err} vs {predicted}"
    );
    // Terminal velocity after 10 time constants: e^{−10} = 4.5e-5 of v_t remains.
    assert!((-state.v[2] / vt - 1.0).abs() < 1e-4, "v = {}", state.v[2]);
}

#[test]
fn strip_with_uneven_coefficients_reaches_total_mass_over_total_coefficient() {
    // Five nodes joined by stiff springs, with uneven masses and drag coefficients: the
    // springs redistribute the forces and the whole strip settles at v_t = M g / Σc. The
    // slowest decay rate is Σc/M = 5 /s, so 8 s leave e^{−40}; the steady state is a fixed
    // point of backward Euler, so only Newton's tolerance remains (1e-9 relative).
    let masses = [0.1, 0.3, 0.2, 0.25, 0.15];
    let coeffs = [0.5, 0.1, 2.0, 0.9, 1.5];
    let n = masses.len();
    let q: Vec<f64> = (0..n).flat_map(|i| [0.3 * i as f64, 0.0, 0.0]).collect();
    let nodes: Vec<usize> = (0..n).collect();
    let edges: Vec<[usize; 2]> = (0..n - 1).map(|i| [i, i + 1]).collect();
    let mut model = Model::new(DofLayout::new(n, 0));
    for (i, &m) in masses.iter().enumerate() {
        model.add_node_mass(i, m);
    }
    model.add_force(Gravity::new(&nodes, &masses, [0.0, 0.0, -G]));
    model.add_force(Stretch::new("strip", &edges, &q, vec![1e4; n - 1]));
    let drag = LinearDrag::new(&nodes, &coeffs, &Fluid::air());
    let total_c = drag.total_coefficient();
    model.add_force(drag);
    let mut state = State::at_rest(q);
    run(&mut model, &mut state, 1e-2, 800).unwrap();
    let vt = masses.iter().sum::<f64>() * G / total_c;
    for i in 0..n {
        let vz = state.v[3 * i + 2];
        assert!((-vz / vt - 1.0).abs() < 1e-9, "node {i}: {vz} vs {vt}");
    }
}

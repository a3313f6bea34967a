//! Single-precision factors (`NewtonOptions::single_precision_factors`): the same steps as
//! double precision where they suffice, and a switch to double precision where the matrix is
//! too ill-conditioned for them (docs/engine.md §Precision of the factors).

use engine::prelude::*;
use engine::reference::cantilever::{cantilever, round};

const G: f64 = 9.81;

/// A steel cantilever of `n` nodes over 1 m (r = 1 mm) released under its own weight.
fn rod(n: usize) -> (Model, State) {
    let c = cantilever(n, 1.0, round(1e-3)).unwrap();
    let mut model = c.model;
    let nodes: Vec<usize> = (0..n).collect();
    let masses: Vec<f64> = nodes.iter().map(|&i| model.node_mass(i)).collect();
    model.add_force(Gravity::new(&nodes, &masses, [0.0, 0.0, -G]));
    (model, c.state)
}

/// `steps` steps of 1 ms; the states, the counters, and whether the factors were still
/// single precision at the end.
fn fly(n: usize, single: bool, steps: usize) -> (State, engine::Counters, bool) {
    let (mut model, mut state) = rod(n);
    let opts = NewtonOptions {
        single_precision_factors: single,
        reference_acceleration: G,
        ..NewtonOptions::recommended()
    };
    let mut st = ImplicitEuler::new(&model, opts).unwrap();
    for _ in 0..steps {
        st.step(&mut model, &mut state, 1e-3)
            .expect("no failed step");
    }
    (state, *st.counters(), st.single_precision_factors())
}

/// Largest |q_a − q_b| over the node positions (m).
fn gap(a: &State, b: &State) -> f64 {
    a.q.iter()
        .zip(&b.q)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// 2,000 nodes 0.5 mm apart: axial stiffness EA/l ≈ 1.3e9 N/m against an inertia
/// m/h² ≈ 12 N/m, a condition number beyond 1/ε₃₂ ≈ 1.7e7. The single-precision factors
/// cannot precondition it; the stepper switches to double precision and takes the same
/// steps as a double-precision run, to the accuracy test's tolerance (a fraction 1e-3 of the
/// step's local error, ~g h²/2 = 5e-6 m, per step).
#[test]
fn an_ill_conditioned_rod_switches_to_double_precision() {
    let (s32, c32, still_single) = fly(2000, true, 10);
    let (s64, _, _) = fly(2000, false, 10);
    assert!(!still_single, "{c32:?}");
    assert!(gap(&s32, &s64) <= 10.0 * 1e-3 * 5e-6, "{}", gap(&s32, &s64));
}

/// 40 nodes 2.6 cm apart are well conditioned for single precision: the factors stay single,
/// and the states agree with double precision to the same tolerance.
#[test]
fn a_well_conditioned_rod_keeps_single_precision() {
    let (s32, c32, still_single) = fly(40, true, 10);
    let (s64, _, _) = fly(40, false, 10);
    assert!(still_single, "{c32:?}");
    assert!(gap(&s32, &s64) <= 10.0 * 1e-3 * 5e-6, "{}", gap(&s32, &s64));
}

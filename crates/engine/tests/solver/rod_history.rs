//! Checkpointing the DER frame history: a rod restored from `Force::history` on a freshly
//! built model continues bit-for-bit like the original (what `chute resume` relies on).
use engine::loads::DofForces;
use engine::reference::cantilever::{cantilever, round, Cantilever};
use engine::{ImplicitEuler, NewtonOptions};

fn opts() -> NewtonOptions {
    NewtonOptions {
        hold_factors: true,
        reuse_contraction: 0.3,
        ..Default::default()
    }
}

/// A cantilever whipped by a tip load along y and z: its edges bend and twist, so the
/// reference frames move away from their rest values and the history matters.
fn whipped() -> Cantilever {
    let mut c = cantilever(12, 1.0, round(0.01)).unwrap();
    let tip = c.tip();
    c.model.add_force(DofForces::new(
        vec![3 * tip + 1, 3 * tip + 2],
        vec![40.0, -60.0],
    ));
    c
}

#[test]
fn restored_history_continues_bit_identically() {
    let dt = 2e-3;
    let mut a = whipped();
    let mut sa = ImplicitEuler::new(&a.model, opts()).unwrap();
    for _ in 0..30 {
        sa.step(&mut a.model, &mut a.state, dt).unwrap();
    }
    let hist: Vec<Vec<f64>> = a.model.forces.iter().map(|f| f.history()).collect();
    assert!(
        hist.iter().any(|h| !h.is_empty()),
        "the bend-twist family must expose its history"
    );

    let mut b = whipped();
    b.state = a.state.clone();
    for (f, h) in b.model.forces.iter_mut().zip(&hist) {
        f.restore_history(h).unwrap();
    }
    // A fresh stepper holds no factorisation: drop A's too, as the run loop does at its
    // checkpoints, so both take the same Newton path.
    sa.invalidate_factorization();
    let mut sb = ImplicitEuler::new(&b.model, opts()).unwrap();
    for _ in 0..30 {
        sa.step(&mut a.model, &mut a.state, dt).unwrap();
        sb.step(&mut b.model, &mut b.state, dt).unwrap();
    }
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&a.state.q), bits(&b.state.q));
    assert_eq!(bits(&a.state.v), bits(&b.state.v));

    // Without the history the continuation differs (the test can fail).
    let mut c = whipped();
    c.state = b.state.clone();
    let mut sc = ImplicitEuler::new(&c.model, opts()).unwrap();
    sb.invalidate_factorization();
    for _ in 0..5 {
        sb.step(&mut b.model, &mut b.state, dt).unwrap();
        sc.step(&mut c.model, &mut c.state, dt).unwrap();
    }
    assert_ne!(bits(&b.state.q), bits(&c.state.q));
}

#[test]
fn wrong_history_length_is_an_error_not_a_panic() {
    let mut a = whipped();
    for f in a.model.forces.iter_mut() {
        let n = f.history().len();
        let err = f
            .restore_history(&vec![0.0; n + 1])
            .unwrap_err()
            .to_string();
        assert!(err.contains(f.name()), "{err}");
    }
}

//! Models and an independent residual shared by the solver tests.

use engine::aero::{Fluid, TriangleDrag};
use engine::fdcheck::dense_eval;
use engine::{Model, State};
use rand::{rngs::StdRng, Rng, SeedableRng};

/// `reference::sheet::thrown_crumpled_sheet` (crumpled by draws of `seed`) under triangle
/// drag, thrown at ~10 m/s: drag ≈ 100 N against ≈ 10 N of weight.
pub fn thrown_sheet_with_drag(seed: u64) -> (Model, State) {
    let mut rng = StdRng::seed_from_u64(seed);
    let (mut model, state, s) =
        engine::reference::sheet::thrown_crumpled_sheet(&mut || rng.random_range(-1.0..1.0));
    model.add_force(TriangleDrag::new(&s.tris, 1.75, 0.5, &Fluid::air()));
    (model, state)
}

/// `|M (q − q_n − dt v_n)/dt² − F(q, (q − q_n)/dt)|` (N) at every DOF, assembled
/// independently (dense, force by force; no force depends on time).
pub fn exact_residuals(model: &Model, prev: &State, q: &[f64], dt: f64) -> Vec<f64> {
    let v: Vec<f64> = q.iter().zip(&prev.q).map(|(a, b)| (a - b) / dt).collect();
    let mut f = vec![0.0; q.len()];
    for force in &model.forces {
        let (fi, _, _) = dense_eval(force.as_ref(), q, &v);
        f.iter_mut().zip(&fi).for_each(|(a, b)| *a += b);
    }
    (0..q.len())
        .map(|d| (model.mass[d] * (q[d] - prev.q[d] - dt * prev.v[d]) / (dt * dt) - f[d]).abs())
        .collect()
}

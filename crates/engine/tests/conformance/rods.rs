//! The rod network of the conformance cases is stress-free at rest.
use crate::fixtures::rods;
use engine::fdcheck::dense_eval;

#[test]
fn rest_shape_is_stress_free() {
    let (model, q) = rods();
    for f in &model.forces {
        let (force, _, _) = dense_eval(f.as_ref(), &q, &vec![0.0; q.len()]);
        let fmax = force.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        // Round-off of forces ~EA·1e-16 (EA ≈ 300 N) and of curvatures ~1e-16.
        assert!(fmax < 1e-9, "{}: {fmax}", f.name());
        assert!(f.energy(&q).unwrap().abs() < 1e-12);
    }
}

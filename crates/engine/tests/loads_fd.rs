//! Finite-difference checks of the external loads with a Jacobian or an energy: the planar
//! end moment (energy −Mφ, force M∇φ, Jacobian M∇²φ) and the constant DOF forces, on random
//! edges of random orientation and length (all four quadrants of φ).
use engine::fdcheck::check_force;
use engine::loads::{DofForces, PlanarEdgeMoment};
use engine::Force;
use rand::{rngs::StdRng, Rng, SeedableRng};

#[test]
fn planar_edge_moment_matches_finite_differences() {
    let mut rng = StdRng::seed_from_u64(11);
    let mut worst = 0.0f64;
    for _ in 0..50 {
        // Two nodes (6 DOFs), edge length 0.3–3 m at a random angle; M up to ±50 N·m.
        let len = rng.random_range(0.3..3.0);
        let phi = rng.random_range(-3.1..3.1);
        let a: [f64; 3] = std::array::from_fn(|_| rng.random_range(-1.0..1.0));
        let b = [
            a[0] + len * f64::cos(phi),
            a[1] + rng.random_range(-1.0..1.0),
            a[2] + len * f64::sin(phi),
        ];
        let q: Vec<f64> = a.iter().chain(&b).copied().collect();
        let mut m = PlanarEdgeMoment::new(0, 1, rng.random_range(-50.0..50.0));
        // Commit at the configuration so the unwrapping branch is the one around φ.
        m.commit(&q);
        let r = check_force(&m, &q, &[0.0; 6], 1e-6);
        worst = worst.max(r.max());
    }
    println!("planar edge moment: worst FD error {worst:.2e}");
    assert!(worst < 1e-6, "{worst}");
}

#[test]
fn planar_edge_moment_unwraps_across_pi() {
    // An edge turning through φ = π keeps a continuous angle once committed on the way.
    let mut m = PlanarEdgeMoment::new(0, 1, 1.0);
    let mut last = 0.0;
    for k in 0..=40 {
        let phi = 1.2 * std::f64::consts::PI * k as f64 / 40.0;
        let q = [0.0, 0.0, 0.0, phi.cos(), 0.0, phi.sin()];
        let e = -m.energy(&q).unwrap();
        assert!((e - phi).abs() < 1e-12, "φ = {phi}, got {e}");
        m.commit(&q);
        last = e;
    }
    assert!(last > std::f64::consts::PI);
}

#[test]
fn dof_forces_are_minus_energy_gradient() {
    let f = DofForces::new(vec![1, 4], vec![2.5, -7.0]);
    let q = [0.3, -1.2, 0.7, 2.0, 0.1];
    let r = check_force(&f, &q, &[0.0; 5], 1e-6);
    assert!(r.max() < 1e-9, "{r:?}");
}

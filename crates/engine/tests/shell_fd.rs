//! Finite-difference checks of shell stretching and hinge bending: force vs −∇E and ∂F/∂q
//! vs central differences of F, on strongly deformed random meshes and on single hinges
//! near θ = 0 and θ = ±π. Relative errors (to the largest analytic entry) must be < 1e-6.
use engine::fdcheck::check_force;
use engine::shell::dihedral::{angle, angle_grad_hess};
use engine::shell::{install, HingeBending, ShellMaterial, TriMesh};
use engine::vec3::V3;
use engine::{DofLayout, Model};
use nalgebra::{Rotation3, Unit};
use rand::{rngs::StdRng, Rng, SeedableRng};

/// An `n × n`-node grid in the unit square, cells split along alternating diagonals.
fn grid(n: usize) -> (Vec<[usize; 3]>, Vec<f64>) {
    let id = |i: usize, j: usize| j * n + i;
    let mut faces = Vec::new();
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            if (i + j) % 2 == 0 {
                faces.extend([[a, b, c], [a, c, d]]);
            } else {
                faces.extend([[a, b, d], [b, c, d]]);
            }
        }
    }
    let h = 1.0 / (n - 1) as f64;
    let q = (0..n * n)
        .flat_map(|k| [(k % n) as f64 * h, (k / n) as f64 * h, 0.0])
        .collect();
    (faces, q)
}

fn perturb(q: &[f64], amp: f64, rng: &mut StdRng) -> Vec<f64> {
    q.iter()
        .map(|x| x + amp * rng.random_range(-1.0..1.0))
        .collect()
}

const TOL: f64 = 1e-6;

#[test]
fn shell_forces_match_finite_differences_on_random_meshes() {
    let mut rng = StdRng::seed_from_u64(7);
    let mat = ShellMaterial {
        youngs_modulus: 1e9,
        thickness: 1e-3,
        density: 1000.0,
    };
    for trial in 0..4 {
        let (faces, flat) = grid(4);
        // A curved, non-flat rest shape and a strongly deformed current shape (node
        // displacements up to 40 % of the 1/3 m spacing in every direction).
        let q_rest = perturb(&flat, 0.05, &mut rng);
        let q = perturb(&q_rest, 0.13, &mut rng);
        let mesh = TriMesh::from_q(faces, &q_rest, 16).unwrap();
        let mut model = Model::new(DofLayout::new(16, 0));
        install(&mesh, &mat, &mut model, &q_rest);
        let v = vec![0.0; q.len()];
        for f in &model.forces {
            let r = check_force(f.as_ref(), &q, &v, 1e-6);
            println!("trial {trial} {}: {r:?}", f.name());
            assert!(
                r.force_vs_energy < TOL && r.dfdq < TOL,
                "{}: {r:?}",
                f.name()
            );
        }
    }
}

/// A hinge with edge on the x axis, wing A in the z = 0 plane (+y side) and wing B rotated
/// by `alpha` about the edge away from face A's normal (+z), so that θ = alpha.
fn hinge_at(alpha: f64) -> [V3; 4] {
    [
        V3::new(0.0, 0.0, 0.0),
        V3::new(1.0, 0.0, 0.0),
        V3::new(0.3, 0.8, 0.0),
        V3::new(0.6, -1.1 * alpha.cos(), -1.1 * alpha.sin()),
    ]
}

#[test]
fn dihedral_angle_has_the_documented_value_and_sign() {
    use std::f64::consts::PI;
    for &alpha in &[
        0.0,
        1e-4,
        -1e-4,
        0.7,
        -0.7,
        2.5,
        -2.5,
        PI - 1e-3,
        -(PI - 1e-3),
    ] {
        let th = angle(&hinge_at(alpha));
        assert!((th - alpha).abs() < 1e-13, "alpha {alpha}: θ = {th}");
    }
    // Exactly flat: θ = 0 and the gradient is finite.
    let (th, g, h) = angle_grad_hess(&hinge_at(0.0));
    assert_eq!(th, 0.0);
    assert!(g.iter().chain(h.iter()).all(|x| x.is_finite()));
}

#[test]
fn hinge_bending_matches_finite_differences_near_flat_and_folded() {
    use std::f64::consts::PI;
    let mut rng = StdRng::seed_from_u64(11);
    let hinge = engine::shell::Hinge {
        edge: [0, 1],
        opposite: [2, 3],
        faces: [0, 1],
    };
    for &(alpha, rest) in &[
        (0.0, 0.3),
        (1e-5, -0.2),
        (PI - 1e-3, 0.0),
        (-(PI - 1e-3), 0.0),
        (PI - 1e-3, -(PI - 2e-3)), // rest angle across the branch cut: wrapped
        (1.3, 0.4),
    ] {
        for _ in 0..3 {
            // Random rotation, translation and size, so no coordinate is special.
            let axis = Unit::new_normalize(V3::new(
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
            ));
            let rot = Rotation3::from_axis_angle(&axis, rng.random_range(0.0..6.0));
            let shift = V3::new(rng.random(), rng.random(), rng.random());
            let scale = rng.random_range(0.5..2.0);
            let q: Vec<f64> = hinge_at(alpha)
                .iter()
                .flat_map(|x| {
                    let y = rot * (x * scale) + shift;
                    [y.x, y.y, y.z]
                })
                .collect();
            let f = HingeBending::with_rest_angles("bend", &[hinge], vec![rest], vec![2.5]);
            let r = check_force(&f, &q, &[0.0; 12], 1e-6);
            println!("alpha {alpha:.6} rest {rest:.4}: {r:?}");
            assert!(r.force_vs_energy < TOL && r.dfdq < TOL, "{r:?}");
        }
    }
}

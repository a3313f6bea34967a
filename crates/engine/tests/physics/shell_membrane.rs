//! Continuum membranes on homogeneous deformations (the patch test): on an irregular mesh a
//! uniform deformation gradient gives every triangle the analytic Green strain, the energy
//! `A ψ(E)` exactly, and zero net force on every interior node.
use engine::fdcheck::dense_eval;
use engine::shell::CstMembrane;
use engine::Force;
use nalgebra::{Matrix2, Matrix3, Rotation3, Unit, Vector3};
use rand::{rngs::StdRng, Rng, SeedableRng};

use crate::mesh::alternating_faces;

/// An `n × n`-node unit square in z = 0 with interior nodes jittered by up to 30 % of the
/// spacing and cells split along alternating diagonals: `(faces, q, interior nodes)`.
pub fn irregular_square(n: usize, seed: u64) -> (Vec<[usize; 3]>, Vec<f64>, Vec<usize>) {
    let mut rng = StdRng::seed_from_u64(seed);
    let h = 1.0 / (n - 1) as f64;
    let id = |i: usize, j: usize| j * n + i;
    let mut q = Vec::new();
    let mut interior = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let inside = i > 0 && j > 0 && i < n - 1 && j < n - 1;
            let jitter = if inside { 0.3 * h } else { 0.0 };
            q.extend([
                i as f64 * h + rng.random_range(-jitter..=jitter),
                j as f64 * h + rng.random_range(-jitter..=jitter),
                0.0,
            ]);
            if inside {
                interior.push(id(i, j));
            }
        }
    }
    (alternating_faces(n), q, interior)
}

/// `q` mapped by `x ↦ R F x` (F acting in the plane, R a random rotation) and the in-plane
/// Green strain `½(FᵀF − I)` of the map.
pub fn deform(q: &[f64], f: Matrix2<f64>, rng: &mut StdRng) -> (Vec<f64>, Matrix2<f64>) {
    let axis = Vector3::new(rng.random(), rng.random(), rng.random::<f64>() + 0.1);
    let rot = Rotation3::from_axis_angle(&Unit::new_normalize(axis), rng.random_range(0.0..6.0));
    let mut f3 = Matrix3::identity();
    f3.fixed_view_mut::<2, 2>(0, 0).copy_from(&f);
    let map = rot.matrix() * f3;
    let out = q
        .chunks(3)
        .flat_map(|x| {
            let y = map * Vector3::new(x[0], x[1], x[2]);
            [y.x, y.y, y.z]
        })
        .collect();
    (out, 0.5 * (f.transpose() * f - Matrix2::identity()))
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

/// Largest net force on an interior node, relative to the largest nodal force.
pub fn interior_imbalance(force: &dyn Force, q: &[f64], interior: &[usize]) -> f64 {
    let (f, _, _) = dense_eval(force, q, &vec![0.0; q.len()]);
    let worst = interior
        .iter()
        .flat_map(|&i| f[3 * i..3 * i + 3].iter())
        .fold(0.0f64, |m, x| m.max(x.abs()));
    worst / max_abs(&f)
}

#[test]
fn cst_homogeneous_deformation_patch_test() {
    let (faces, q, interior) = irregular_square(6, 5);
    let (e, nu, h) = (1e9, 0.3, 1e-3);
    let m = CstMembrane::new("cst", &faces, &q, e, nu, h).unwrap();
    let mut rng = StdRng::seed_from_u64(9);
    for f in [
        Matrix2::new(1.1, 0.0, 0.0, 0.95),
        Matrix2::new(1.02, 0.3, -0.1, 0.9),
        Matrix2::new(0.8, 0.05, 0.0, 0.85),
    ] {
        let (x, green) = deform(&q, f, &mut rng);
        // Every triangle sees the invariants of the analytic strain (its own frame is
        // rotated in the plane, so compare trace and determinant).
        for i in 0..faces.len() {
            let [e11, e22, g12] = m.strain(&x, i);
            let tr = e11 + e22;
            let det = e11 * e22 - 0.25 * g12 * g12;
            assert!(
                (tr - green.trace()).abs() < 1e-13,
                "trace {tr} vs {}",
                green.trace()
            );
            assert!((det - green.determinant()).abs() < 1e-13, "det {det}");
        }
        // Energy A ψ(E) with ψ = E h/(2(1 − ν²)) [(tr E)² − 2(1 − ν) det E].
        let c = e * h / (1.0 - nu * nu);
        let psi = 0.5 * c * (green.trace().powi(2) - 2.0 * (1.0 - nu) * green.determinant());
        let w = m.energy(&x).unwrap();
        assert!((w - psi).abs() < 1e-12 * psi.abs(), "energy {w} vs {psi}");
        // Round-off of forces ~1e-16 × (Q A/ℓ)·(number of terms): 1e-12 relative.
        let imbalance = interior_imbalance(&m, &x, &interior);
        assert!(imbalance < 1e-12, "interior imbalance {imbalance:e}");
    }
}

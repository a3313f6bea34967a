//! Fixtures of the continuum-membrane cases (constant-strain triangles, fabric) and the
//! checks the conformance macro does not make: a stress-free rest shape, invariance under
//! rigid motions, and the positive semi-definite projection.
use crate::fixtures::{grid, pick};
use engine::conformance::Rng;
use engine::fdcheck::dense_eval;
use engine::shell::membrane::project_psd;
use engine::shell::{CstMembrane, FabricMembrane, Orthotropic};
use engine::Force;
use nalgebra::{Matrix2, Matrix3, Rotation3, Unit, Vector2, Vector3};

/// The faces and curved rest shape of the shell fixture: a 4 × 4-node unit square with
/// every coordinate moved by up to ±0.05 m.
pub fn membrane_mesh() -> (Vec<[usize; 3]>, Vec<f64>) {
    let (faces, flat) = grid(4, 1.0);
    let mut rng = Rng::new(7);
    let q_rest = flat.iter().map(|x| x + rng.symmetric(0.05)).collect();
    (faces, q_rest)
}

/// Constant-strain triangles on [`membrane_mesh`]: E = 2 GPa, ν = 0.3, h = 0.5 mm.
pub fn cst() -> (CstMembrane, Vec<f64>) {
    let (faces, q) = membrane_mesh();
    let m = CstMembrane::new("cst", &faces, &q, 2e9, 0.3, 5e-4).expect("valid mesh");
    (m, q)
}

/// A woven-fabric-like law: warp twice as stiff as weft, weak in shear, ν₁₂ = 0.3.
pub const FABRIC: Orthotropic = Orthotropic {
    warp_modulus: 1.2e9,
    weft_modulus: 0.6e9,
    shear_modulus: 0.05e9,
    poisson_ratio: 0.3,
    thickness: 1e-4,
};

/// The warp direction of the fabric cases: 30° from x in the plane, tilted out of it (each
/// rest triangle takes its projection).
pub const WARP: [f64; 3] = [0.866_025_403_784_438_6, 0.5, 0.1];

/// Fabric triangles on [`membrane_mesh`], with the no-compression regularisation strain
/// `no_compression` if given.
pub fn fabric(no_compression: Option<f64>) -> (FabricMembrane, Vec<f64>) {
    let (faces, q) = membrane_mesh();
    let m = FabricMembrane::new("fabric", &faces, &q, &FABRIC, WARP, no_compression)
        .expect("valid mesh");
    (m, q)
}

/// Regularisation strain of the no-compression cases: the transitions are smooth over
/// strains of ~ε_r, so central differences with h = 1e-6 (strain steps ~1e-6) resolve them
/// with truncation error ~(1e-6/ε_r)² = 1e-8.
pub const EPS_R: f64 = 1e-2;

/// One fabric triangle in the plane z = 0 (warp at 30°) with no compression:
/// `(force, q_rest)`.
pub fn fabric_triangle() -> (FabricMembrane, Vec<f64>) {
    let q = vec![0.0, 0.0, 0.0, 1.0, 0.1, 0.0, 0.3, 0.9, 0.0];
    let warp = [WARP[0], WARP[1], 0.0];
    let m = FabricMembrane::new("fabric-nc", &[[0, 1, 2]], &q, &FABRIC, warp, Some(EPS_R))
        .expect("valid triangle");
    (m, q)
}

/// Deform the rest triangle of [`fabric_triangle`] so that its *elastic* (unrelaxed) stress
/// `Q ε` has principal values `s₁ ≥ s₂`, drawn from the lists (in units of `4 ε_r G₁₂ h`,
/// the smoothing width of a principal stress whose axes are far from the warp and weft,
/// where the weak shear sets the stiffness), with principal axes at a random angle to the
/// warp; then rotate and shift it randomly in space.
pub fn set_elastic_stress(rng: &mut Rng, q: &mut [f64], s1: &[f64], s2: &[f64]) {
    let stiff = FABRIC.stiffness();
    let unit = 4.0 * EPS_R * stiff[2][2];
    let (a, b) = (unit * pick(rng, s1), unit * pick(rng, s2));
    let psi = rng.uniform(0.0, 3.2);
    let (c, s) = (psi.cos(), psi.sin());
    // Stress tensor V diag(a, b) Vᵀ in the (warp, weft) frame, to Voigt and to strain.
    let sig = [
        a * c * c + b * s * s,
        a * s * s + b * c * c,
        (a - b) * c * s,
    ];
    let q3 = Matrix3::from_fn(|r, k| stiff[r][k]);
    let eps = q3.lu().solve(&Vector3::from(sig)).expect("Q is invertible");
    // A deformation gradient with FᵀF = I + 2E (Cholesky), applied in the material frame.
    let cauchy_green = Matrix2::new(1.0 + 2.0 * eps[0], eps[2], eps[2], 1.0 + 2.0 * eps[1]);
    let f = cauchy_green
        .cholesky()
        .expect("strains ≥ −½")
        .l()
        .transpose();
    let (t1, t2) = (
        Vector2::new(WARP[0], WARP[1]),
        Vector2::new(-WARP[1], WARP[0]),
    );
    let rot = rotation(rng);
    let shift = Vector3::new(rng.symmetric(1.0), rng.symmetric(1.0), rng.symmetric(1.0));
    let rest = [[0.0, 0.0], [1.0, 0.1], [0.3, 0.9]];
    for (k, x) in rest.iter().enumerate() {
        let xv = Vector2::new(x[0], x[1]);
        let y = f * Vector2::new(xv.dot(&t1), xv.dot(&t2));
        let z = rot * Vector3::new(y.x, y.y, 0.0) + shift;
        q[3 * k..3 * k + 3].copy_from_slice(z.as_slice());
    }
}

/// A random rotation.
pub fn rotation(rng: &mut Rng) -> Matrix3<f64> {
    let axis = Vector3::new(rng.symmetric(1.0), rng.symmetric(1.0), rng.symmetric(1.0));
    *Rotation3::from_axis_angle(&Unit::new_normalize(axis), rng.uniform(0.0, 6.0)).matrix()
}

/// Apply `x ↦ A x + c` to every node of `q`.
pub fn map_nodes(q: &mut [f64], a: &Matrix3<f64>, c: Vector3<f64>) {
    for x in q.chunks_mut(3) {
        let y = a * Vector3::new(x[0], x[1], x[2]) + c;
        x.copy_from_slice(y.as_slice());
    }
}

/// A large homogeneous deformation on top of the draw: stretches of 0.6–1.6 along the
/// axes of a random frame (so also shear), then a random rotation and shift.
pub fn large_deformation(rng: &mut Rng, q: &mut [f64]) {
    let frame = rotation(rng);
    let stretch = Matrix3::from_diagonal(&Vector3::new(
        rng.uniform(0.6, 1.6),
        rng.uniform(0.6, 1.6),
        pick(rng, &[0.7, 1.0, 1.4]),
    ));
    let a = rotation(rng) * frame * stretch * frame.transpose();
    let c = Vector3::new(rng.symmetric(1.0), rng.symmetric(1.0), rng.symmetric(1.0));
    map_nodes(q, &a, c);
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

/// Largest force and the energy of `f` after a rigid motion of the rest shape `q`, and the
/// same two after a uniform 1 % stretch (the scales of the round-off bounds).
fn rigid_motion_response(f: &dyn Force, q: &[f64], rng: &mut Rng) -> [f64; 4] {
    let mut moved = q.to_vec();
    let c = Vector3::new(rng.symmetric(3.0), rng.symmetric(3.0), rng.symmetric(3.0));
    map_nodes(&mut moved, &rotation(rng), c);
    let (force, _, _) = dense_eval(f, &moved, &vec![0.0; q.len()]);
    let mut strained = q.to_vec();
    map_nodes(
        &mut strained,
        &(Matrix3::identity() * 1.01),
        Vector3::zeros(),
    );
    let (scale, _, _) = dense_eval(f, &strained, &vec![0.0; q.len()]);
    let energy = |x: &[f64]| f.energy(x).unwrap_or(f64::NAN);
    [
        max_abs(&force),
        energy(&moved),
        max_abs(&scale),
        energy(&strained),
    ]
}

#[test]
fn cst_rest_shape_and_rigid_motions_are_stress_free() {
    let (m, q) = cst();
    let mut rng = Rng::new(3);
    for _ in 0..5 {
        let [force, energy, force_1pc, energy_1pc] = rigid_motion_response(&m, &q, &mut rng);
        // Rotated coordinates carry round-off ~1e-16 × |x| into ε, so F ~ 1e-16 Q A/ℓ and
        // W ~ 1e-32 Q A: bounds of 1e-10 (forces) and 1e-20 (energies) of the 1 %-strain
        // values leave orders of magnitude for round-off and none for a real error.
        assert!(
            force < 1e-10 * force_1pc,
            "rigid-motion force {force:e} vs {force_1pc:e}"
        );
        assert!(
            energy.abs() < 1e-20 * energy_1pc,
            "rigid-motion energy {energy:e}"
        );
    }
}

#[test]
fn psd_projection_keeps_psd_blocks_and_removes_negative_modes() {
    let (m, q) = cst();
    let mut rng = Rng::new(11);
    let mut saw_indefinite = false;
    for trial in 0..8 {
        // Uniform compression (trial even) or tension of the rest shape, plus noise.
        let s = if trial % 2 == 0 { 0.8 } else { 1.2 };
        let mut x: Vec<f64> = q.iter().map(|v| s * v + rng.symmetric(0.02)).collect();
        large_deformation(&mut rng, &mut x);
        let mut exact = m.new_blocks();
        let v = vec![0.0; x.len()];
        let input = engine::EvalInput::outside_step(&x, &v, 0.0, true);
        m.evaluate(&input, &mut exact);
        let proj = cst().0.with_psd_projection(true);
        let mut projected = proj.new_blocks();
        proj.evaluate(&input, &mut projected);
        assert_eq!(
            exact.f, projected.f,
            "the projection must not touch the force"
        );
        for (e, p) in exact.dfdq.chunks(81).zip(projected.dfdq.chunks(81)) {
            let ke = nalgebra::SMatrix::<f64, 9, 9>::from_fn(|r, c| -e[r * 9 + c]);
            let kp = nalgebra::SMatrix::<f64, 9, 9>::from_fn(|r, c| -p[r * 9 + c]);
            let scale = ke.abs().max();
            let lmin = ke.symmetric_eigenvalues().min();
            let pmin = kp.symmetric_eigenvalues().min();
            assert!(
                pmin > -1e-12 * scale,
                "projected block has eigenvalue {pmin:e}"
            );
            if lmin >= 0.0 {
                assert!((ke - kp).abs().max() < 1e-12 * scale, "PSD block changed");
            } else {
                saw_indefinite = true;
                // The projection is the nearest PSD matrix: it moves K by exactly the
                // negative part, ‖K − K₊‖_F = ‖λ₋‖.
                let neg: f64 = ke
                    .symmetric_eigenvalues()
                    .iter()
                    .map(|l| l.min(0.0).powi(2))
                    .sum::<f64>()
                    .sqrt();
                let moved = (ke - kp).norm();
                assert!((moved - neg).abs() < 1e-9 * scale, "{moved:e} vs {neg:e}");
            }
        }
    }
    assert!(
        saw_indefinite,
        "compressed triangles must have indefinite Hessians"
    );
    let mut block = vec![0.0; 81];
    project_psd(&mut block);
    assert!(block.iter().all(|&x| x == 0.0));
}

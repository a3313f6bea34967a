//! TriMesh topology and its errors; lumped masses; rigid motions give zero elastic force;
//! the dihedral angle's value and sign.
use engine::fdcheck::dense_eval;
use engine::shell::dihedral::{angle, angle_grad_hess};
use engine::shell::{install, MeshError, ShellMaterial, TriMesh};
type V3 = nalgebra::Vector3<f64>;
use engine::{DofLayout, Model};
use nalgebra::{Rotation3, Unit};
use rand::{rngs::StdRng, Rng, SeedableRng};

/// Two triangles forming the unit square, counter-clockwise about +z.
fn square() -> (Vec<[usize; 3]>, Vec<[f64; 3]>) {
    let p = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ];
    (vec![[0, 1, 2], [0, 2, 3]], p)
}

#[test]
fn square_topology() {
    let (f, p) = square();
    let m = TriMesh::new(f, &p).unwrap();
    assert_eq!(m.edges.len(), 5);
    assert_eq!(m.hinges.len(), 1);
    let h = m.hinges[0];
    // Face 0 traverses 2 → 0, so the hinge edge is [2, 0] with face 0's vertex 1 first.
    assert_eq!(h.edge, [2, 0]);
    assert_eq!(h.opposite, [1, 3]);
    assert_eq!(h.faces, [0, 1]);
    assert_eq!(m.boundary_edges.len(), 4);
    assert_eq!(m.boundary_nodes, vec![0, 1, 2, 3]);
    assert_eq!(m.vertex_faces[0], vec![0, 1]);
    assert_eq!(m.vertex_faces[1], vec![0]);
    assert!((m.area() - 1.0).abs() < 1e-15);
    let va: f64 = m.vertex_areas.iter().sum();
    assert!((va - 1.0).abs() < 1e-15);
    assert!((m.vertex_areas[0] - 1.0 / 3.0).abs() < 1e-15);
    assert!((m.vertex_areas[1] - 1.0 / 6.0).abs() < 1e-15);
}

#[test]
fn mesh_errors_are_specific() {
    let (_, p) = square();
    let err = TriMesh::new(vec![[0, 1, 4]], &p).unwrap_err();
    assert!(
        matches!(err, MeshError::IndexOutOfRange { node: 4, .. }),
        "{err}"
    );
    let err = TriMesh::new(vec![[0, 1, 1]], &p).unwrap_err();
    assert!(err.to_string().contains("repeated vertex"), "{err}");
    let mut line = p.clone();
    line[2] = [2.0, 0.0, 0.0];
    let err = TriMesh::new(vec![[0, 1, 2]], &line).unwrap_err();
    assert!(err.to_string().contains("zero area"), "{err}");
    let err = TriMesh::new(vec![[0, 1, 2], [0, 3, 2]], &p).unwrap_err();
    assert!(
        matches!(
            err,
            MeshError::InconsistentOrientation { faces: [0, 1], .. }
        ),
        "{err}"
    );
    // Three faces on edge 0–1 (a "book" of three pages).
    let mut p3 = p.clone();
    p3.push([0.5, 0.0, 1.0]);
    let err = TriMesh::new(vec![[0, 1, 2], [1, 0, 3], [0, 1, 4]], &p3).unwrap_err();
    assert!(
        matches!(err, MeshError::NonManifoldEdge { count: 3, .. }),
        "{err}"
    );
    let mut bad = p.clone();
    bad[3][1] = f64::NAN;
    assert!(matches!(
        TriMesh::new(vec![[0, 1, 2]], &bad).unwrap_err(),
        MeshError::NonFinite { node: 3 }
    ));
}

#[test]
fn install_adds_named_forces_and_lumped_mass() {
    let (f, p) = square();
    let m = TriMesh::new(f, &p).unwrap();
    let q: Vec<f64> = p.iter().flatten().copied().collect();
    // A fifth node (e.g. a rod node) that the shell does not touch.
    let mut q5 = q.clone();
    q5.extend([5.0, 5.0, 5.0]);
    let mut model = Model::new(DofLayout::new(5, 0));
    let mat = ShellMaterial {
        youngs_modulus: 2e9,
        thickness: 2e-3,
        density: 1500.0,
    };
    install(&m, &mat, &mut model, &q5).unwrap();
    let names: Vec<&str> = model.forces.iter().map(|f| f.name()).collect();
    assert_eq!(names, ["shell-stretch", "shell-bend"]);
    // ρ h A = 1500 · 0.002 · 1 = 3 kg, a third of each face to each vertex.
    assert!((model.total_mass() - 3.0).abs() < 1e-12);
    assert!((model.node_mass(0) - 1.0).abs() < 1e-12);
    assert!((model.node_mass(1) - 0.5).abs() < 1e-12);
    assert_eq!(model.node_mass(4), 0.0);
    // k_b = (2/√3) E h³/12.
    assert!((mat.hinge_stiffness() - 2.0 / 3f64.sqrt() * 2e9 * 8e-9 / 12.0).abs() < 1e-12);
}

/// Random curved mesh (perturbed grid), elastic forces at a rigidly moved rest state.
#[test]
fn rigid_motions_give_zero_elastic_force() {
    let mut rng = StdRng::seed_from_u64(3);
    let n = 5;
    // Cells split along the same diagonal.
    let faces = engine::reference::sheet::sheet(n, n, 1.0, 1.0, 0.0).tris;
    let q_rest: Vec<f64> = (0..n * n)
        .flat_map(|k| {
            let (x, y) = ((k % n) as f64 * 0.25, (k / n) as f64 * 0.25);
            [x, y, 0.3 * (x * 2.0).sin() * y + 0.02 * rng.random::<f64>()]
        })
        .collect();
    let mesh = TriMesh::from_q(faces, &q_rest, n * n).unwrap();
    let mat = ShellMaterial {
        youngs_modulus: 1e9,
        thickness: 1e-3,
        density: 1000.0,
    };
    let mut model = Model::new(DofLayout::new(n * n, 0));
    install(&mesh, &mat, &mut model, &q_rest).unwrap();
    let axis = Unit::new_normalize(V3::new(0.3, -0.5, 0.8));
    let rot = Rotation3::from_axis_angle(&axis, 2.1);
    let shift = V3::new(3.0, -1.0, 7.0);
    let moved: Vec<f64> = q_rest
        .chunks(3)
        .flat_map(|p| {
            let y = rot * V3::new(p[0], p[1], p[2]) + shift;
            [y.x, y.y, y.z]
        })
        .collect();
    let v = vec![0.0; moved.len()];
    for f in &model.forces {
        // Force scale for a unit strain / unit angle: k_s (≈ 2e5 N) or k_b/ℓ (≈ 4e-1 N).
        let scale = match f.name() {
            "shell-stretch" => mat.stretch_stiffness(0.25),
            _ => mat.hinge_stiffness() / 0.25,
        };
        for q in [&q_rest, &moved] {
            let (force, _, _) = dense_eval(f.as_ref(), q, &v);
            let worst = force.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            // Round-off: lengths and angles carry ~1e-15 relative error (×10 for the
            // trigonometry and translation by up to 7 m).
            assert!(worst < 1e-12 * scale, "{}: |F| = {worst:e}", f.name());
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

//! The two-pass evaluation (per-edge dihedral quantities shared by both faces) against the
//! per-face kernel it replaced ([`super::reference`]), on a curved, deformed mesh with a
//! boundary.

use super::{reference, MidedgeBending, PlateBending, NS};
use crate::conformance::Rng;
use crate::force::{BlockMut, EvalInput, Force, JacobianKind, LocalBlocks};
use crate::shell::TriMesh;

/// An `n × n`-node sheet of side 1 m (`reference::sheet`), nodes moved by up to ±0.05 m,
/// and the mid-edge force on it (edge angles after the nodes).
fn mesh(n: usize, rng: &mut Rng) -> (MidedgeBending, Vec<f64>, usize) {
    let sheet = crate::reference::sheet::sheet(n, n, 1.0, 1.0, 0.0);
    let faces = sheet.tris;
    let q: Vec<f64> = sheet.q.iter().map(|x| x + rng.symmetric(0.05)).collect();
    let mesh = TriMesh::from_q(faces, &q, n * n).expect("valid mesh");
    let plate = PlateBending {
        youngs_modulus: 1e9,
        poisson_ratio: 0.3,
        thickness: 1e-3,
    };
    let force = MidedgeBending::new("midedge", &mesh, &q, &plate, 3 * n * n);
    let mut q = q;
    q.resize(3 * n * n + mesh.edges.len(), 0.0);
    (force, q, 3 * n * n)
}

/// Largest `|a − b|` over the largest `|b|`.
fn rel_diff(a: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    let diff = a
        .iter()
        .zip(b)
        .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()));
    diff / scale
}

/// Every face's force and Jacobian agree with the per-face kernel to round-off, with and
/// without the Jacobian, and with buffers that lack the scratch.
#[test]
fn two_passes_equal_the_per_face_kernel() {
    let mut rng = Rng::new(17);
    let (force, q0, nodes) = mesh(6, &mut rng);
    let q: Vec<f64> = q0
        .iter()
        .enumerate()
        .map(|(d, x)| x + rng.symmetric(if d < nodes { 0.04 } else { 0.5 }))
        .collect();
    let v = vec![0.0; q.len()];
    for jacobian in [true, false] {
        let input = EvalInput::outside_step(&q, &v, 0.0, jacobian);
        let mut blocks = force.new_blocks();
        force.evaluate(&input, &mut blocks);
        let mut bare = LocalBlocks::new(NS, force.len(), JacobianKind::ELASTIC);
        force.evaluate(&input, &mut bare);
        assert_eq!(bare.f, blocks.f, "a resized scratch gives the same forces");
        let (mut f, mut dfdq) = (vec![0.0; NS], vec![0.0; NS * NS]);
        for i in 0..force.len() {
            let st = &force.stencils()[NS * i..NS * (i + 1)];
            let b = BlockMut {
                index: i,
                f: &mut f,
                dfdq: if jacobian { &mut dfdq } else { &mut [] },
                dfdv: &mut [],
            };
            reference::evaluate(&force.data()[i], st, &input, b);
            let fi = &blocks.f[NS * i..NS * (i + 1)];
            assert!(rel_diff(fi, &f) < 1e-12, "face {i}: force {fi:?} vs {f:?}");
            if jacobian {
                let ji = &blocks.dfdq[NS * NS * i..NS * NS * (i + 1)];
                let e = rel_diff(ji, &dfdq);
                assert!(e < 1e-12, "face {i}: Jacobian differs by {e:e}");
            }
        }
    }
}

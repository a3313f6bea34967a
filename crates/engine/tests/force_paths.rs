//! Every element's force-only path (`EvalInput::jacobian = false`, used by modified Newton)
//! must give the same force as its full path, bit for bit up to round-off.
use engine::aero::{Fluid, LinearDrag, NodeDrag, PressureDrag, TriangleDrag};
use engine::force::{EvalInput, Force};
use engine::rod::{RodNetwork, RodSpec, Section, Stretch};
use engine::shell::{HingeBending, TriMesh};
use engine::{DofLayout, Model};
use rand::{rngs::StdRng, Rng, SeedableRng};

fn forces(f: &dyn Force, q: &[f64], v: &[f64], jacobian: bool) -> Vec<f64> {
    let mut b = f.new_blocks();
    f.evaluate(
        &EvalInput {
            q,
            v,
            t: 0.0,
            jacobian,
        },
        &mut b,
    );
    b.f
}

fn assert_same(f: &dyn Force, q: &[f64], v: &[f64]) {
    let (a, b) = (forces(f, q, v, true), forces(f, q, v, false));
    let scale = a.iter().fold(1e-300f64, |m, x| m.max(x.abs()));
    for (x, y) in a.iter().zip(&b) {
        assert!((x - y).abs() <= 1e-12 * scale, "{}: {x} vs {y}", f.name());
    }
}

#[test]
fn force_only_paths_match_full_paths() {
    let mut rng = StdRng::seed_from_u64(7);
    // A 3×3-node sheet (8 triangles), randomly deformed, with random velocities.
    let n = 9;
    let mut q: Vec<f64> = (0..n)
        .flat_map(|i| [(i % 3) as f64, (i / 3) as f64, 0.0])
        .collect();
    let faces: Vec<[usize; 3]> = (0..2)
        .flat_map(|r| {
            (0..2).flat_map(move |c| {
                let a = 3 * r + c;
                [[a, a + 1, a + 4], [a, a + 4, a + 3]]
            })
        })
        .collect();
    let mesh = TriMesh::from_q(faces.clone(), &q, n).unwrap();
    let q_rest = q.clone();
    for x in q.iter_mut() {
        *x += rng.random_range(-0.3..0.3);
    }
    let v: Vec<f64> = (0..3 * n).map(|_| rng.random_range(-5.0..5.0)).collect();
    let fluid = Fluid {
        wind: [1.0, -2.0, 0.5],
        ..Fluid::air()
    };
    let nodes: Vec<usize> = (0..n).collect();
    let areas = vec![0.1; n];
    assert_same(&TriangleDrag::new(&faces, 1.75, 0.5, &fluid), &q, &v);
    assert_same(&PressureDrag::new(&faces, &q_rest, 10.0, &fluid), &q, &v);
    assert_same(&NodeDrag::new(&nodes, &areas, 1.75, &fluid), &q, &v);
    assert_same(&LinearDrag::new(&nodes, &areas, &fluid), &q, &v);
    assert_same(
        &Stretch::new("s", &mesh.edges, &q_rest, vec![1e3; mesh.edges.len()]),
        &q,
        &v,
    );
    let k = vec![2.0; mesh.hinges.len()];
    assert_same(&HingeBending::new("h", &mesh.hinges, &q_rest, k), &q, &v);
    // A bent, twisted rod.
    let m = 6;
    let mut model = Model::new(DofLayout::new(m, m - 1));
    let mut qr: Vec<f64> = (0..m).flat_map(|i| [0.2 * i as f64, 0.0, 0.0]).collect();
    qr.resize(model.n_dofs(), 0.0);
    let mut net = RodNetwork::new();
    net.add_rod(RodSpec::new(
        (0..m).collect(),
        Section::Rectangle {
            width: 0.02,
            height: 0.002,
        },
        1e9,
        4e8,
        1000.0,
    ));
    net.install(&mut model, &qr, 0).unwrap();
    let mut qd = qr.clone();
    for x in qd.iter_mut() {
        *x += rng.random_range(-0.05..0.05);
    }
    let vd = vec![0.0; qd.len()];
    for f in &model.forces {
        assert_same(f.as_ref(), &qd, &vd);
    }
}

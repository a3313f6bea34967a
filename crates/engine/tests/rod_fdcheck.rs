//! Finite-difference checks of the rod elements (stretch, bend–twist) on random, strongly
//! deformed configurations with random twists and random time-parallel transported frames,
//! including a joint where edges enter the bend–twist stencil reversed (all four sign
//! combinations occur at node 2).
use engine::fdcheck::check_force;
use engine::rod::{RodNetwork, RodSpec, Section};
use engine::{DofLayout, Model};
use rand::{rngs::StdRng, Rng, SeedableRng};

const TWIST_OFFSET: usize = 2;

/// Rod A along x (rectangular), rod B leaving node 2 along y, rod C arriving at node 2 from
/// below. Nodes 0–8; 8 edges; rest shape gently curved so that κ̄ ≠ 0.
fn network() -> (RodNetwork, Vec<[f64; 3]>) {
    let pts = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.1, 0.0],
        [2.0, 0.0, 0.15],
        [3.0, -0.1, 0.1],
        [4.0, 0.0, 0.0],
        [2.1, 1.0, 0.2],
        [2.0, 2.0, 0.1],
        [1.9, -0.2, -2.0],
        [2.0, 0.1, -1.0],
    ];
    let rect = Section::Rectangle {
        width: 0.08,
        height: 0.02,
    };
    let mut net = RodNetwork::new();
    net.add_rod(
        RodSpec::new(vec![0, 1, 2, 3, 4], rect, 2e5, 8e4, 1.0).with_first_director([0.0, 1.0, 0.0]),
    );
    net.add_rod(RodSpec::new(
        vec![2, 5, 6],
        Section::Circle { radius: 0.03 },
        3e5,
        1e5,
        1.0,
    ));
    net.add_rod(RodSpec::new(vec![7, 8, 2], rect, 1e5, 5e4, 1.0));
    (net, pts)
}

fn build() -> (Model, Vec<f64>) {
    let (net, pts) = network();
    let layout = DofLayout::new(pts.len(), TWIST_OFFSET + net.n_edges() + 1);
    let mut q = vec![0.0; layout.len()];
    for (i, p) in pts.iter().enumerate() {
        q[3 * i..3 * i + 3].copy_from_slice(p);
    }
    let mut model = Model::new(layout);
    let h = net.install(&mut model, &q, TWIST_OFFSET).unwrap();
    // 3 in-rod pairs on A, 1 on B, 1 on C; at node 2 the 4 edge ends give 6 pairs, one
    // of them in-rod (A), so 5 joint pairs.
    assert_eq!(h.n_bend_twist, 3 + 1 + 1 + 5);
    (model, q)
}

fn force_index(model: &Model, name: &str) -> usize {
    model.forces.iter().position(|f| f.name() == name).unwrap()
}

fn perturbed(q: &[f64], n_nodes: usize, amp: f64, rng: &mut StdRng) -> Vec<f64> {
    let mut p = q.to_vec();
    for (d, x) in p.iter_mut().enumerate() {
        if d < 3 * n_nodes {
            *x += amp * rng.random_range(-1.0..1.0);
        } else {
            *x = rng.random_range(-3.0..3.0);
        }
    }
    p
}

#[test]
fn rest_shape_is_stress_free() {
    let (model, q) = build();
    for f in &model.forces {
        let (force, _, _) = engine::fdcheck::dense_eval(f.as_ref(), &q, &vec![0.0; q.len()]);
        let fmax = force.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        assert!(fmax < 1e-9, "{}: {fmax}", f.name());
        assert!(f.energy(&q).unwrap().abs() < 1e-12);
    }
}

#[test]
fn bend_twist_and_stretch_match_finite_differences() {
    let mut rng = StdRng::seed_from_u64(7);
    let mut worst = [0.0f64; 3];
    for trial in 0..6 {
        let (mut model, q) = build();
        let n_nodes = model.layout.n_nodes;
        let bt = force_index(&model, "rod-bend-twist");
        // Random history: commit a random intermediate configuration (frames are
        // time-parallel transported there and reference twists put on their branch).
        let q_mid = perturbed(&q, n_nodes, 0.25, &mut rng);
        model.forces[bt].commit(&q_mid);
        let q_eval = perturbed(&q, n_nodes, 0.3, &mut rng);
        let v = vec![0.0; q.len()];
        for f in &model.forces {
            let r = check_force(f.as_ref(), &q_eval, &v, 1e-6);
            println!("trial {trial} {}: {r:?}", f.name());
            assert!(r.force_vs_energy < 1e-6, "{}: {r:?}", f.name());
            assert!(r.dfdq < 1e-6, "{}: {r:?}", f.name());
            if f.name() == "rod-bend-twist" {
                worst[0] = worst[0].max(r.force_vs_energy);
                worst[1] = worst[1].max(r.dfdq);
            } else {
                worst[2] = worst[2].max(r.max());
            }
        }
    }
    println!(
        "worst: bend-twist force {:.2e}, dF/dq {:.2e}; stretch {:.2e}",
        worst[0], worst[1], worst[2]
    );
}

#[test]
fn jacobian_is_symmetric_and_twist_only_couples_through_gj() {
    let (mut model, q) = build();
    let bt = force_index(&model, "rod-bend-twist");
    let mut rng = StdRng::seed_from_u64(3);
    let q_mid = perturbed(&q, model.layout.n_nodes, 0.2, &mut rng);
    model.forces[bt].commit(&q_mid);
    let qe = perturbed(&q, model.layout.n_nodes, 0.2, &mut rng);
    let n = q.len();
    let (_, k, _) = engine::fdcheck::dense_eval(model.forces[bt].as_ref(), &qe, &vec![0.0; n]);
    let kmax = k.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    for a in 0..n {
        for b in 0..n {
            assert!((k[a * n + b] - k[b * n + a]).abs() < 1e-12 * kmax);
        }
    }
}

//! The rod-network builder: masses, Voronoi lengths, joints, pins, closed rods, directors,
//! clamps and input validation.
use engine::loads::PointForces;
use engine::reference::cantilever::static_opts;
use engine::rod::{BendTwist, RodNetwork, RodSpec, Section};
use engine::{DofLayout, Model, State, StaticSolver};

fn line_q(n: usize, l: f64, n_twists: usize) -> Vec<f64> {
    let mut q = vec![0.0; 3 * n + n_twists];
    for k in 0..n {
        q[3 * k] = (k as f64 - 0.5) * l;
    }
    q
}

fn spec(nodes: Vec<usize>) -> RodSpec {
    RodSpec::new(
        nodes,
        Section::Circle { radius: 0.005 },
        200e9,
        200e9 / 2.6,
        7850.0,
    )
}

#[test]
fn masses_and_voronoi_lengths() {
    let n = 11;
    let q = line_q(n, 0.1, 10);
    let mut net = RodNetwork::new();
    net.add_rod(spec((0..n).collect()));
    let mut model = Model::new(DofLayout::new(n, 10));
    let h = net.install(&mut model, &q, 0).unwrap();
    let sec = Section::Circle { radius: 0.005 };
    let total = 7850.0 * sec.area() * 1.0;
    assert!((model.total_mass() / total - 1.0).abs() < 1e-12);
    assert!((model.node_mass(0) / (total / 20.0) - 1.0).abs() < 1e-12);
    let rot = 7850.0 * sec.polar_moment() * 0.1;
    assert!((model.mass[h.twist_dofs[3]] / rot - 1.0).abs() < 1e-12);
    assert!((h.voronoi_len[0] - 0.05).abs() < 1e-12 && (h.voronoi_len[5] - 0.1).abs() < 1e-12);
    assert_eq!(h.rod_voronoi_len[0], h.voronoi_len);
    assert_eq!(h.n_bend_twist, n - 2);
}

/// A cantilever made of two rods meeting at a rigid joint, the second listed from the tip
/// back to the joint (so its edges enter the joint reversed), deflects exactly like one rod:
/// the joint element has the same stiffness and Voronoi length as an in-rod element.
#[test]
fn rigid_joint_with_reversed_rod_equals_one_rod() {
    let n = 31;
    let l = 1.0 / (n as f64 - 1.5);
    let p = 0.05;
    let run = |split: bool| {
        let q = line_q(n, l, n - 1);
        let mut net = RodNetwork::new();
        if split {
            net.add_rod(spec((0..=15).collect()));
            net.add_rod(spec((15..n).rev().collect()));
        } else {
            net.add_rod(spec((0..n).collect()));
        }
        let mut model = Model::new(DofLayout::new(n, n - 1));
        let h = net.install(&mut model, &q, 0).unwrap();
        assert_eq!(h.n_bend_twist, n - 2);
        net.clamp_end(&mut model, 0, true, 0);
        model.add_force(PointForces::new(&[n - 1], &[[0.0, p, -p]]));
        let mut state = State::at_rest(q);
        let mut s = StaticSolver::new(&model, static_opts()).unwrap();
        s.solve(&mut model, &mut state, 2).unwrap();
        [state.q[3 * n - 2], state.q[3 * n - 1]]
    };
    let (one, two) = (run(false), run(true));
    println!("one rod {one:?}, two rods {two:?}");
    for k in 0..2 {
        assert!((one[k] - two[k]).abs() < 1e-9 * one[k].abs());
    }
}

/// At a pinned node only in-rod pairs are coupled; without the pin every pair is.
#[test]
fn pin_removes_cross_rod_coupling() {
    // A T: rod 0 along x through node 1, rod 1 from node 1 along y.
    let q = vec![0., 0., 0., 1., 0., 0., 2., 0., 0., 1., 1., 0., 0., 0., 0.];
    for (pinned, expected) in [(false, 3), (true, 1)] {
        let mut net = RodNetwork::new();
        net.add_rod(spec(vec![0, 1, 2]));
        net.add_rod(spec(vec![1, 3]));
        if pinned {
            net.pin(1);
        }
        let mut model = Model::new(DofLayout::new(4, 3));
        let h = net.install(&mut model, &q, 0).unwrap();
        assert_eq!(h.n_bend_twist, expected);
        // The lone edge of rod 1 has no bend–twist element when pinned: its twist is fixed.
        assert_eq!(model.fixed[h.twist_dofs[2]], pinned);
    }
}

#[test]
fn closed_rod_couples_last_and_first_edges() {
    let m = 8;
    let mut q = vec![0.0; 3 * m + m];
    for k in 0..m {
        let a = std::f64::consts::TAU * k as f64 / m as f64;
        q[3 * k] = a.cos();
        q[3 * k + 1] = a.sin();
    }
    let mut nodes: Vec<usize> = (0..m).collect();
    nodes.push(0);
    let mut net = RodNetwork::new();
    net.add_rod(spec(nodes));
    let mut model = Model::new(DofLayout::new(m, m));
    let h = net.install(&mut model, &q, 0).unwrap();
    assert_eq!(h.n_bend_twist, m);
    let bt = model
        .forces
        .iter()
        .find(|f| f.name() == "rod-bend-twist")
        .unwrap();
    let (f, _, _) = engine::fdcheck::dense_eval(bt.as_ref(), &q, &vec![0.0; q.len()]);
    assert!(
        f.iter().all(|x| x.abs() < 1e-9),
        "ring rest shape is stress-free"
    );
}

/// The default first director of a rod along x is ŷ; a user director is projected normal to
/// the first edge; the twist DOFs start at `twist_offset`.
#[test]
fn directors_and_twist_offset() {
    use engine::rod::frames::first_director;
    type V3 = nalgebra::Vector3<f64>;
    let q = line_q(6, 1.0, 6);
    let mut net = RodNetwork::new();
    net.add_rod(spec(vec![0, 1, 2]));
    net.add_rod(spec(vec![3, 4, 5]).with_first_director([0.3, 0.0, 2.0]));
    let mut model = Model::new(DofLayout::new(6, 6));
    let h = net.install(&mut model, &q, 2).unwrap();
    assert_eq!(h.twist_dofs, vec![20, 21, 22, 23]);
    let bt = model
        .forces
        .iter()
        .find(|f| f.name() == "rod-bend-twist")
        .unwrap();
    assert_eq!(bt.stencils()[9..11], [20, 21]);
    assert_eq!(bt.stencils()[20..22], [22, 23]);
    let d = first_director(&V3::x(), None).unwrap();
    assert!((d - V3::y()).norm() < 1e-15);
    let d = first_director(&V3::x(), Some([0.3, 0.0, 2.0])).unwrap();
    assert!((d - V3::z()).norm() < 1e-15);
    assert!(first_director(&V3::x(), Some([2.0, 0.0, 0.0])).is_none());
    // An empty family is valid.
    let empty = BendTwist::new(
        "t",
        Vec::new(),
        net.edges(),
        &[0, 1, 2, 3],
        vec![V3::y(); 4],
        &q,
    );
    assert!(empty.is_empty() && empty.elements().len() == 0);
}

#[test]
fn invalid_networks_are_reported() {
    let q = line_q(3, 1.0, 2);
    let cases: Vec<(RodSpec, usize, &str)> = vec![
        (spec(vec![0]), 2, "fewer than 2 nodes"),
        (spec(vec![0, 1, 7]), 2, "uses node 7"),
        (spec(vec![0, 1, 1]), 2, "zero-length edge"),
        (
            spec(vec![0, 1, 2]),
            1,
            "needs per-edge DOFs (rod twists, mid-edge angles) 0..2",
        ),
        (
            spec(vec![0, 1, 2]).with_first_director([1.0, 0.0, 0.0]),
            2,
            "parallel",
        ),
        (
            RodSpec::new(vec![0, 1], Section::Circle { radius: -1.0 }, 1.0, 1.0, 1.0),
            2,
            "radius",
        ),
    ];
    for (s, twists, msg) in cases {
        let mut net = RodNetwork::new();
        net.add_rod(s);
        let mut model = Model::new(DofLayout::new(3, twists));
        let q = if twists == 2 {
            q.clone()
        } else {
            line_q(3, 1.0, twists)
        };
        let err = net.install(&mut model, &q, 0).unwrap_err().to_string();
        assert!(err.contains(msg), "{err} (expected `{msg}`)");
    }
}

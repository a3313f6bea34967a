//! The self-contact case: two 3 × 3-node cloth sheets 1.2 m apart with two parallel lines
//! between them, 0.6 m from each sheet and 0.8 m from each other, under an activation
//! distance of 1 m; every coordinate moved by up to ±0.2 m, so point–triangle, edge–edge and
//! point–edge pairs are active. Lengths are O(1) as the checks' step assumes: the central
//! differences' truncation error grows as (h/d)², d the distance of the closest pair, so
//! the same case at the millimetre scale would need a step 100 times smaller.
use crate::fixtures::grid;
use engine::contact::barrier::Barrier;
use engine::contact::broad::Surface;
use engine::contact::SelfContact;

/// `(force, q0)`; `project` as the step solver uses it (false: the exact Hessian).
pub fn self_contact(project: bool) -> (SelfContact, Vec<f64>) {
    let (faces, flat) = grid(3, 10.0);
    let mut q = Vec::new();
    let mut tris = Vec::new();
    for (sheet, (dx, z)) in [(0.0, 0.0), (1.3, 1.2)].into_iter().enumerate() {
        let first = sheet * 9;
        q.extend(flat.chunks(3).flat_map(|p| [p[0] + dx, p[1] + dx, z]));
        tris.extend(faces.iter().map(|t| t.map(|i| i + first)));
    }
    let mut lines = Vec::new();
    for (line, y) in [4.0, 4.8].into_iter().enumerate() {
        let first = 18 + 3 * line;
        q.extend((0..3).flat_map(|k| [1.0 + 4.0 * k as f64, y, 0.6]));
        lines.extend([[first, first + 1], [first + 1, first + 2]]);
    }
    let surface = Surface::from_mesh(&tris, &lines);
    let barrier = Barrier {
        d_hat: 1.0,
        kappa: 1e3,
    };
    (
        SelfContact::new("contact", surface, barrier, &q, 5.0, project),
        q,
    )
}

/// The case exercises every kind of pair: each has members within the activation distance.
#[test]
fn every_kind_of_pair_is_active() {
    use engine::contact::broad::Candidate;
    let (f, q) = self_contact(false);
    let mut active = [0; 3];
    for c in f.pairs() {
        let kind = match c {
            Candidate::PointTriangle(_) => 0,
            Candidate::EdgeEdge(_) => 1,
            Candidate::PointEdge(_) => 2,
        };
        active[kind] += usize::from(c.squared_distance(&q) < f.barrier().d_hat);
    }
    assert!(
        active.iter().all(|&n| n > 0),
        "active pairs by kind: {active:?}"
    );
}

/// The pairs a step takes are history: restored on a freshly built force, they are the
/// same pairs (and so the same pattern and the same bits after a resume).
#[test]
fn the_pairs_taken_are_restored_with_the_history() {
    use engine::Force;
    let (mut f, q) = self_contact(true);
    // A step whose motion outruns the held reach takes the pairs afresh, here.
    let mut moved = q.clone();
    moved.iter_mut().step_by(3).for_each(|x| *x *= 1.5);
    let v = vec![10.0; q.len()];
    assert!(f.begin_step(&moved, &v, 0.1));
    let (mut g, _) = self_contact(true);
    assert_ne!(g.pairs(), f.pairs());
    g.restore_history(&f.history()).unwrap();
    assert_eq!(g.pairs(), f.pairs());
    assert_eq!(g.stencils(), f.stencils());
    assert!(g.restore_history(&[1.0]).is_err());
}

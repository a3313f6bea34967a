//! Self-contact keeps surfaces apart through whole motions that would otherwise pass them
//! through each other: the invariant (no edge through a triangle, exact predicates, and no
//! line through a line between two states) is checked after every accepted step, and each
//! test fails at the first crossing. Each scene is also run without contact, to show that it
//! does cross there (the check can fail).
use engine::contact::barrier::Barrier;
use engine::contact::broad::Surface;
use engine::contact::intersect::{first_crossing, segments_passing};
use engine::contact::SelfContact;
use engine::loads::{Gravity, PointForces};
use engine::rod::Stretch;
use engine::shell::CstMembrane;
use engine::{DofLayout, ImplicitEuler, Model, NewtonOptions, State};

/// Advance by `dt`, halving (down to 1/64) where a step fails.
fn advance(s: &mut ImplicitEuler, m: &mut Model, st: &mut State, dt: f64, depth: u32) {
    if s.step(m, st, dt).is_ok() {
        return;
    }
    assert!(depth < 6, "step of {dt} s failed at t = {}", st.t);
    advance(s, m, st, 0.5 * dt, depth + 1);
    advance(s, m, st, 0.5 * dt, depth + 1);
}

/// Run `steps` steps of `dt`, calling `check(previous q, new q)` after each.
fn run(
    mut model: Model,
    q: Vec<f64>,
    v0: [f64; 3],
    dt: f64,
    steps: usize,
    mut check: impl FnMut(&[f64], &[f64]),
) -> Vec<f64> {
    let mut state = State::at_rest(q);
    for (d, v) in state.v.iter_mut().enumerate() {
        *v = if model.fixed[d] { 0.0 } else { v0[d % 3] };
    }
    let mut s = ImplicitEuler::new(&model, NewtonOptions::recommended()).expect("model");
    for _ in 0..steps {
        let before = state.q.clone();
        advance(&mut s, &mut model, &mut state, dt, 0);
        check(&before, &state.q);
    }
    state.q
}

/// The barrier of the scenes: activation distance 10 mm; κ such that a node of the sheets
/// (0.5 g) arriving at 2 m/s is stopped about 1 mm short (`b(d̂/100) ≈ ½ m v²`).
const BARRIER: Barrier = Barrier {
    d_hat: 1e-4,
    kappa: 1e5,
};

/// A strip of 13 × 5 nodes (0.1 m apart) folded in two: the first six columns flat at z = 0
/// and held, a fold, and the last six columns back above them at z = 0.1 m; cloth-like
/// membrane (E h = 10 kN/m, 0.05 kg/m²) under gravity, falling at 1 m/s.
fn folded_strip(contact: bool) -> (Model, Vec<f64>, Surface) {
    let (nx, ny) = (13, 5);
    let id = |i: usize, j: usize| i * ny + j;
    let mut q = Vec::new();
    for i in 0..nx {
        let (x, z) = match i {
            0..=5 => (0.1 * i as f64, 0.0),
            6 => (0.55, 0.05),
            _ => (0.5 - 0.1 * (i - 7) as f64, 0.1),
        };
        q.extend((0..ny).flat_map(|j| [x, 0.1 * j as f64, z]));
    }
    let mut faces = Vec::new();
    for i in 0..nx - 1 {
        for j in 0..ny - 1 {
            faces.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            faces.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    let n = nx * ny;
    let mut model = Model::new(DofLayout::new(n, 0));
    let masses = vec![5e-4; n];
    (0..n).for_each(|i| model.add_node_mass(i, masses[i]));
    (0..6 * ny).for_each(|i| model.fix_node(i));
    let nodes: Vec<usize> = (0..n).collect();
    model.add_force(Gravity::new(&nodes, &masses, [0.0, 0.0, -9.81]));
    let surface = cloth(&mut model, &faces, &q, 1e8, contact);
    (model, q, surface)
}

/// A membrane of Young's modulus `e` (ν = 0.3, 0.1 mm) on `faces` at rest shape `q`, and
/// contact of its surface when `contact`: the surface.
fn cloth(model: &mut Model, faces: &[[usize; 3]], q: &[f64], e: f64, contact: bool) -> Surface {
    let membrane = CstMembrane::new("membrane", faces, q, e, 0.3, 1e-4).expect("mesh");
    model.add_force(membrane);
    let surface = Surface::from_mesh(faces, &[]);
    if contact {
        let c = SelfContact::new("contact", surface.clone(), BARRIER, q, 0.0, true);
        model.add_force(c);
    }
    surface
}

/// The upper half of a folded strip falls onto the lower half and comes to rest on it, no
/// edge ever through a triangle; without contact it falls through.
#[test]
fn a_sheet_dropped_onto_itself_never_passes_through() {
    let (model, q, surface) = folded_strip(true);
    let q = run(model, q, [0.0, 0.0, -1.0], 2e-3, 150, |_, q| {
        assert_eq!(first_crossing(&surface, q), None, "crossing");
    });
    // The upper half (columns 8–12, clear of the fold) rests on the lower one, within a few
    // activation distances above it.
    for i in 8 * 5..13 * 5 {
        let z = q[3 * i + 2];
        assert!(z > 0.0 && z < 0.03, "node {i} at z = {z}");
    }
    let (model, q, surface) = folded_strip(false);
    let mut crossed = false;
    run(model, q, [0.0, 0.0, -1.0], 2e-3, 150, |_, q| {
        crossed |= first_crossing(&surface, q).is_some();
    });
    assert!(
        crossed,
        "without contact the strip should fall through itself"
    );
}

/// A taut line A along x (11 nodes, 1 m, ends held) and a free line B along y 50 mm above
/// its middle (11 nodes, 1 m), both EA = 1 kN with 1 g per node; B falls at 1 m/s under
/// gravity while its ends are pulled down and towards each other's side in x (1 N each):
/// it drapes over A and wraps under it.
fn two_lines(contact: bool) -> (Model, Vec<f64>, Vec<[usize; 2]>) {
    let n = 11;
    let mut q: Vec<f64> = (0..n)
        .flat_map(|k| [0.1 * k as f64 - 0.5, 0.0, 0.0])
        .collect();
    q.extend((0..n).flat_map(|k| [0.0, 0.1 * k as f64 - 0.5, 0.05]));
    let mut lines = Vec::new();
    for l in 0..2 {
        lines.extend((0..n - 1).map(|k| [l * n + k, l * n + k + 1]));
    }
    let mut model = Model::new(DofLayout::new(2 * n, 0));
    (0..2 * n).for_each(|i| model.add_node_mass(i, 1e-3));
    model.fix_node(0);
    model.fix_node(n - 1);
    model.add_force(Stretch::new("lines", &lines, &q, vec![1e3; lines.len()]));
    let nodes: Vec<usize> = (n..2 * n).collect();
    model.add_force(Gravity::new(&nodes, &vec![1e-3; n], [0.0, 0.0, -9.81]));
    let pulls = [[0.2, 0.0, -1.0], [-0.2, 0.0, -1.0]];
    model.add_force(PointForces::new(&[n, 2 * n - 1], &pulls));
    if contact {
        let surface = Surface::from_mesh(&[], &lines);
        let c = SelfContact::new("contact", surface, BARRIER, &q, 0.0, true);
        model.add_force(c);
    }
    (model, q, lines)
}

#[test]
fn a_line_wrapped_around_another_never_passes_through() {
    let (model, q, lines) = two_lines(true);
    let q = run(model, q, [0.0, 0.0, -1.0], 1e-3, 300, |a, b| {
        assert_eq!(
            segments_passing(&lines, a, b),
            None,
            "the lines passed through each other"
        );
    });
    // B hangs over A (which sags under it): B's middle node rests above A's, within a few
    // activation distances, and B's ends hang well below.
    let (mid, a_mid, end) = (q[3 * 16 + 2], q[3 * 5 + 2], q[3 * 11 + 2]);
    assert!(
        mid > a_mid && mid < a_mid + 0.03,
        "B's middle at z = {mid}, A's at {a_mid}"
    );
    assert!(end < a_mid - 0.2, "B's end at z = {end}");
    let (model, q, lines) = two_lines(false);
    let mut crossed = false;
    run(model, q, [0.0, 0.0, -1.0], 1e-3, 300, |a, b| {
        crossed |= segments_passing(&lines, a, b).is_some()
    });
    assert!(
        crossed,
        "without contact the lines should pass through each other"
    );
}

/// A tube (radius 0.15 m, 0.5 m long, 16 × 6 nodes moved randomly by up to 5 mm) of a slack
/// membrane (E h = 1 N/m: fabric buckles at once under compression, which constant-strain
/// triangles do not), every node pushed towards the axis by 0.05 N: the tube crumples.
fn tube(contact: bool) -> (Model, Vec<f64>, Surface) {
    let (around, along) = (16, 6);
    let id = |i: usize, j: usize| i * around + j % around;
    let mut rng = engine::conformance::Rng::new(11);
    let mut q = Vec::new();
    let mut push = Vec::new();
    for i in 0..along {
        for j in 0..around {
            let a = std::f64::consts::TAU * j as f64 / around as f64;
            let (c, s) = (a.cos(), a.sin());
            q.extend([0.15 * c, 0.15 * s, 0.1 * i as f64].map(|x| x + rng.symmetric(0.005)));
            push.push([-0.05 * c, -0.05 * s, 0.0]);
        }
    }
    let mut faces = Vec::new();
    for i in 0..along - 1 {
        for j in 0..around {
            faces.push([id(i, j), id(i, j + 1), id(i + 1, j + 1)]);
            faces.push([id(i, j), id(i + 1, j + 1), id(i + 1, j)]);
        }
    }
    let n = around * along;
    let mut model = Model::new(DofLayout::new(n, 0));
    (0..n).for_each(|i| model.add_node_mass(i, 5e-4));
    model.add_force(PointForces::new(&(0..n).collect::<Vec<_>>(), &push));
    let surface = cloth(&mut model, &faces, &q, 1e4, contact);
    (model, q, surface)
}

/// The tube crumples (its nodes' mean radius under three quarters of the tube's: each ring's
/// 16 folded segments of 59 mm take room) without any edge passing through the membrane;
/// without contact its walls pass through each other.
#[test]
fn a_tube_crumpled_by_an_inward_load_never_passes_through() {
    let (model, q, surface) = tube(true);
    let q = run(model, q, [0.0; 3], 1e-3, 150, |_, q| {
        assert_eq!(first_crossing(&surface, q), None, "crossing");
    });
    let r_mean = q.chunks(3).map(|p| p[0].hypot(p[1])).sum::<f64>() / (q.len() / 3) as f64;
    assert!(r_mean < 0.75 * 0.15, "mean radius {r_mean} m");
    let (model, q, surface) = tube(false);
    let mut crossed = false;
    run(model, q, [0.0; 3], 1e-3, 150, |_, q| {
        crossed |= first_crossing(&surface, q).is_some();
    });
    assert!(
        crossed,
        "without contact the walls should pass through each other"
    );
}

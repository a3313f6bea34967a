//! Static rod benchmarks against analytic solutions: small-deflection cantilevers (tip load,
//! self-weight), the large-deflection elastica of Bisshopp & Drucker, the circular arc under
//! an end moment, and the anisotropy / torsion of a rectangular strip.
mod rod_common;
use engine::loads::{Gravity, PointForces};
use engine::rod::{RodSpec, Section};
use engine::StaticSolver;
use rod_common::{cantilever, round, static_opts, Cantilever, DofForces, PlanarEdgeMoment};

const L: f64 = 1.0;
const N: usize = 51;
const R: f64 = 0.005;

fn ei_round() -> f64 {
    Section::Circle { radius: R }.ei1(200e9)
}

fn solve(c: &mut Cantilever, steps: usize) {
    let mut s = StaticSolver::new(&c.model, static_opts()).unwrap();
    s.solve(&mut c.model, &mut c.state, steps).unwrap();
}

/// Discretisation error of the tip deflection is −1/(4 (n−½)²) ≈ −1e-4 for 50 edges
/// (see docs/rods.md), geometric nonlinearity O((δ/L)²) ≈ 1e-8: 1 % is a wide margin that
/// still catches any wrong stiffness factor or a misplaced clamp section (3 % for l/2).
#[test]
fn tip_load_small_deflection() {
    let mut c = cantilever(N, L, round(R));
    let ei = ei_round();
    let p = 3.0 * ei * 1e-4 / (L * L); // δ/L = 1e-4
    c.model
        .add_force(PointForces::new(&[c.tip()], &[[0.0, 0.0, -p]]));
    let q0 = c.state.q.clone();
    solve(&mut c, 1);
    let delta = -c.disp(c.tip(), 2, &q0);
    let exact = p * L.powi(3) / (3.0 * ei);
    let err = delta / exact - 1.0;
    println!("tip load: δ = {delta:.6e}, PL³/3EI = {exact:.6e}, rel err {err:.2e}");
    assert!(err.abs() < 0.01);
}

/// Self-weight q = ρ A g lumped to the nodes; δ = qL⁴/8EI. Discretisation O(1/n²) and
/// nonlinearity O((δ/L)²) ≈ 6e-5 are both far below 1 %.
#[test]
fn self_weight_small_deflection() {
    let mut c = cantilever(N, L, round(R));
    let nodes: Vec<usize> = (0..c.n).collect();
    let masses: Vec<f64> = nodes.iter().map(|&i| c.model.node_mass(i)).collect();
    c.model
        .add_force(Gravity::new(&nodes, &masses, [0.0, 0.0, -9.81]));
    let q0 = c.state.q.clone();
    solve(&mut c, 1);
    let q = 7850.0 * Section::Circle { radius: R }.area() * 9.81;
    let exact = q * L.powi(4) / (8.0 * ei_round());
    let delta = -c.disp(c.tip(), 2, &q0);
    let err = delta / exact - 1.0;
    println!("self weight: δ = {delta:.6e}, qL⁴/8EI = {exact:.6e}, rel err {err:.2e}");
    assert!(err.abs() < 0.01);
}

/// Bisshopp & Drucker (1945), tip load kept vertical, α = PL²/EI. The rod is nearly
/// inextensible (P/EA < 1e-4) and the O(1/n²) discretisation error is ~1e-4, so 1 % is the
/// brief's tolerance with a wide margin.
#[test]
fn elastica_bisshopp_drucker() {
    let table = [
        (1.0, 0.30172, 0.05643),
        (2.0, 0.49346, 0.16064),
        (5.0, 0.71379, 0.38763),
        (10.0, 0.81061, 0.55500),
    ];
    for (alpha, w_ref, u_ref) in table {
        let mut c = cantilever(N, L, round(R));
        let p = alpha * ei_round() / (L * L);
        c.model
            .add_force(PointForces::new(&[c.tip()], &[[0.0, 0.0, -p]]));
        solve(&mut c, (4.0 * alpha) as usize);
        let tip = c.tip();
        let w = -c.state.q[3 * tip + 2] / L;
        let u = (L - c.state.q[3 * tip]) / L;
        let (ew, eu) = (w / w_ref - 1.0, u / u_ref - 1.0);
        println!("α = {alpha}: w/L = {w:.5} ({w_ref}, err {ew:.1e}), (L−x)/L = {u:.5} ({u_ref}, err {eu:.1e})");
        assert!(ew.abs() < 0.01 && eu.abs() < 0.01);
    }
}

/// Circumcentre and radius of three points in the x–z plane.
fn circle(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> ([f64; 2], f64) {
    let d = 2.0 * (a[0] * (b[1] - c[1]) + b[0] * (c[1] - a[1]) + c[0] * (a[1] - b[1]));
    let s = |p: [f64; 2]| p[0] * p[0] + p[1] * p[1];
    let ux = (s(a) * (b[1] - c[1]) + s(b) * (c[1] - a[1]) + s(c) * (a[1] - b[1])) / d;
    let uz = (s(a) * (c[0] - b[0]) + s(b) * (a[0] - c[0]) + s(c) * (b[0] - a[0])) / d;
    ([ux, uz], ((a[0] - ux).powi(2) + (a[1] - uz).powi(2)).sqrt())
}

/// A pure end moment bends the rod into a circle of radius EI/M (exact for the continuum).
/// Discretely every node carries the same moment, so the nodes lie exactly on a circle of
/// radius R_d = R / cos³(ψ/2) with ψ the turning angle per node: for a half circle over 49
/// nodes, ψ ≈ 0.064 and R_d/R − 1 ≈ 3ψ²/8 ≈ 1.5e-3, inside the 0.5 % tolerance.
#[test]
fn end_moment_gives_circular_arc() {
    let mut c = cantilever(N, L, round(R));
    let ei = ei_round();
    // The last edge sits (n−1) l from the clamp section (edge midpoint to edge midpoint).
    let arc = (c.n - 2) as f64 * c.l;
    let m = std::f64::consts::PI * ei / arc; // last edge turns by π
    let tip = c.tip();
    c.model.add_force(PlanarEdgeMoment::new(tip - 1, tip, m));
    solve(&mut c, 20);
    let p = |i: usize| [c.state.q[3 * i], c.state.q[3 * i + 2]];
    let (centre, radius) = circle(p(1), p(N / 2), p(tip));
    let exact = ei / m;
    let mut worst = 0.0f64;
    for i in 0..c.n {
        let d = ((p(i)[0] - centre[0]).powi(2) + (p(i)[1] - centre[1]).powi(2)).sqrt();
        worst = worst.max((d / exact - 1.0).abs());
    }
    let e = [
        c.state.q[3 * tip] - c.state.q[3 * tip - 3],
        c.state.q[3 * tip + 2] - c.state.q[3 * tip - 1],
    ];
    let phi = e[1].atan2(e[0]).rem_euclid(std::f64::consts::TAU);
    let e_phi = phi / std::f64::consts::PI - 1.0;
    println!("end moment: R = {radius:.6} vs EI/M = {exact:.6}, worst node {worst:.2e}, tip angle err {e_phi:.2e}");
    assert!((radius / exact - 1.0).abs() < 0.005);
    assert!(worst < 0.005);
    assert!(e_phi.abs() < 0.005);
}

fn strip(nodes: Vec<usize>) -> RodSpec {
    let sec = Section::Rectangle {
        width: 0.02,
        height: 0.002,
    };
    RodSpec::new(nodes, sec, 1e9, 1e9 / 2.7, 1000.0).with_first_director([0.0, 1.0, 0.0])
}

/// A 20 mm × 2 mm strip lying along x with its width along y: out-of-plane (z) bending is
/// resisted by E w h³/12, in-plane (y) by E h w³/12. The same tip load P deflects it (w/h)² =
/// 100 times more in z than in y; each deflection is checked against PL³/3EI (1 %, as for
/// the round rod: discretisation −1e-4, nonlinearity ≤ 1e-6) and the cross-deflection must
/// vanish.
#[test]
fn strip_bends_anisotropically() {
    let sec = Section::Rectangle {
        width: 0.02,
        height: 0.002,
    };
    let p = 3.0 * sec.ei1(1e9) * 1e-3 / (L * L); // δ_z/L = 1e-3
    let mut delta = [0.0; 3];
    for (k, ei) in [(2usize, sec.ei1(1e9)), (1, sec.ei2(1e9))] {
        let mut c = cantilever(N, L, strip);
        let mut f = [0.0; 3];
        f[k] = -p;
        c.model.add_force(PointForces::new(&[c.tip()], &[f]));
        let q0 = c.state.q.clone();
        solve(&mut c, 1);
        delta[k] = -c.disp(c.tip(), k, &q0);
        let exact = p * L.powi(3) / (3.0 * ei);
        let cross = c.disp(c.tip(), 3 - k, &q0).abs();
        let err = delta[k] / exact - 1.0;
        println!(
            "strip load along {k}: δ = {:.5e} vs {exact:.5e} (err {err:.1e}), cross {cross:.1e}",
            delta[k]
        );
        assert!(err.abs() < 0.01);
        assert!(cross < 1e-9 * exact);
    }
    let ratio = delta[2] / delta[1];
    println!("δ_z/δ_y = {ratio:.4} (expected (w/h)² = 100)");
    assert!((ratio / 100.0 - 1.0).abs() < 0.01);
}

/// A pure end torque T on the last edge's twist: the discrete twist chain is exact, so the
/// last edge turns by T (n−1) l / GJ (its midpoint is (n−1) l from the clamp section) to
/// solver precision, and the strip does not bend at all.
#[test]
fn end_torque_twists_without_bending() {
    let mut c = cantilever(N, L, strip);
    let gj = strip(vec![0, 1]).section.gj(1e9 / 2.7);
    let t = 1e-3;
    let last = c.handles.twist_dofs[c.n - 2];
    c.model.add_force(DofForces::new(vec![last], vec![t]));
    let q0 = c.state.q.clone();
    solve(&mut c, 1);
    let exact = t * (c.n - 2) as f64 * c.l / gj;
    let err = c.state.q[last] / exact - 1.0;
    let moved = (0..3 * c.n).fold(0.0f64, |m, d| m.max((c.state.q[d] - q0[d]).abs()));
    println!(
        "torque: θ = {:.6e} vs TL/GJ = {exact:.6e} (err {err:.1e}), max node motion {moved:.1e}",
        c.state.q[last]
    );
    assert!(err.abs() < 1e-6);
    assert!(moved < 1e-12);
}

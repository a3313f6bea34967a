//! Static rod benchmarks against analytic solutions: small-deflection cantilevers (tip load,
//! self-weight), the large-deflection elastica of Bisshopp & Drucker, the circular arc under
//! an end moment, and the anisotropy / torsion of a rectangular strip.
use engine::loads::{DofForces, PointForces};
use engine::reference::cantilever::{
    cantilever, elastica, end_moment, self_weight, tip_load, Cantilever, BISSHOPP_DRUCKER,
};
use engine::rod::{RodSpec, Section};
use engine::Force;

const L: f64 = 1.0;
const N: usize = 51;
const R: f64 = 0.005;

fn solve(c: &mut Cantilever, steps: usize) {
    c.solve_static(steps).unwrap();
}

/// Discretisation error of the tip deflection is −1/(4 (n−½)²) ≈ −1e-4 for 50 edges
/// (see docs/rods.md), geometric nonlinearity O((δ/L)²) ≈ 1e-8: 1 % is a wide margin that
/// still catches any wrong stiffness factor or a misplaced clamp section (3 % for l/2).
#[test]
fn tip_load_small_deflection() {
    let r = tip_load(N, L, R, 1e-4).unwrap();
    let (delta, exact, err) = (r.simulated, r.reference, r.rel_error());
    println!("tip load: δ = {delta:.6e}, PL³/3EI = {exact:.6e}, rel err {err:.2e}");
    assert!(err.abs() < 0.01);
}

/// Self-weight q = ρ A g lumped to the nodes; δ = qL⁴/8EI. Discretisation O(1/n²) and
/// nonlinearity O((δ/L)²) ≈ 6e-5 are both far below 1 %.
#[test]
fn self_weight_small_deflection() {
    let r = self_weight(N, L, R).unwrap();
    let (delta, exact, err) = (r.simulated, r.reference, r.rel_error());
    println!("self weight: δ = {delta:.6e}, qL⁴/8EI = {exact:.6e}, rel err {err:.2e}");
    assert!(err.abs() < 0.01);
}

/// Bisshopp & Drucker (1945), tip load kept vertical, α = PL²/EI. The rod is nearly
/// inextensible (P/EA < 1e-4) and the O(1/n²) discretisation error is ~1e-4, so 1 % is the
/// brief's tolerance with a wide margin.
#[test]
fn elastica_bisshopp_drucker() {
    for (alpha, w_ref, u_ref) in BISSHOPP_DRUCKER {
        let (w, u) = elastica(N, L, R, alpha).unwrap();
        let (ew, eu) = (w / w_ref - 1.0, u / u_ref - 1.0);
        println!("α = {alpha}: w/L = {w:.5} ({w_ref}, err {ew:.1e}), (L−x)/L = {u:.5} ({u_ref}, err {eu:.1e})");
        assert!(ew.abs() < 0.01 && eu.abs() < 0.01);
    }
}

/// A pure end moment bends the rod into a circle of radius EI/M (exact for the continuum).
/// Discretely every node carries the same moment, so the nodes lie exactly on a circle of
/// radius R_d = R / cos³(ψ/2) with ψ the turning angle per node: for a half circle over 49
/// nodes, ψ ≈ 0.064 and R_d/R − 1 ≈ 3ψ²/8 ≈ 1.5e-3, inside the 0.5 % tolerance.
#[test]
fn end_moment_gives_circular_arc() {
    let r = end_moment(N, L, R).unwrap();
    let (radius, exact, worst, e_phi) = (r.radius, r.exact, r.worst_node, r.tip_angle_err);
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
        let mut c = cantilever(N, L, strip).unwrap();
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
    let mut c = cantilever(N, L, strip).unwrap();
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

/// The shooting solution of the elastica reproduces Bisshopp & Drucker's table to its five
/// digits (half a unit of the last digit, 5e-6, plus the table's own rounding: 1e-5).
#[test]
fn elastica_shooting_matches_the_table() {
    for (alpha, w_ref, u_ref) in BISSHOPP_DRUCKER {
        let (w, u) = engine::reference::cantilever::elastica_exact(alpha);
        println!("α = {alpha}: w/L = {w:.7} ({w_ref}), (L−x)/L = {u:.7} ({u_ref})");
        assert!((w - w_ref).abs() < 1e-5 && (u - u_ref).abs() < 1e-5);
    }
}

#[test]
fn planar_edge_moment_unwraps_across_pi() {
    // An edge turning through φ = π keeps a continuous angle once committed on the way.
    let mut m = engine::loads::PlanarEdgeMoment::new(0, 1, 1.0);
    let mut last = 0.0;
    for k in 0..=40 {
        let phi = 1.2 * std::f64::consts::PI * k as f64 / 40.0;
        let q = [0.0, 0.0, 0.0, phi.cos(), 0.0, phi.sin()];
        let e = -m.energy(&q).unwrap();
        assert!((e - phi).abs() < 1e-12, "φ = {phi}, got {e}");
        m.commit(&q, &[0.0; 6]);
        last = e;
    }
    assert!(last > std::f64::consts::PI);
}

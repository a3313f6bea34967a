//! Finite-difference checks of every drag Jacobian (∂F/∂x and ∂F/∂v) on random, strongly
//! deformed configurations, including triangles seen edge-on and flow crossing a triangle.
//!
//! Tolerance 1e-6 (relative to the largest Jacobian entry): central differences with
//! h = 1e-6 on O(1) coordinates have truncation error O(h²) ≈ 1e-12 and round-off
//! O(1e-16/h) ≈ 1e-10, so a correct Jacobian passes with orders of magnitude to spare, while
//! any missing term (e.g. ∂n̂/∂x, or a factor 2) shows up as an O(1) error.
use engine::reference::sheet;

use engine::aero::{Fluid, LinearDrag, NodeDrag, PressureDrag, TriangleDrag};
use engine::fdcheck::{check_force, dense_eval};
use engine::Force;
use rand::{rngs::StdRng, Rng, SeedableRng};

const TOL: f64 = 1e-6;
const H: f64 = 1e-6;

fn windy(rng: &mut StdRng) -> Fluid {
    Fluid {
        density: 1.225,
        viscosity: 1.81e-5,
        wind: [0, 1, 2].map(|_| rng.random_range(-3.0..3.0)),
    }
}

/// A 3 × 3-node sheet (8 triangles) with every node displaced by up to ±0.4 of the 1 m
/// spacing in each direction: triangles are sheared, tilted and stretched.
fn deformed_sheet(rng: &mut StdRng) -> (Vec<f64>, Vec<[usize; 3]>) {
    let s = sheet::sheet(3, 3, 2.0, 2.0, 0.0);
    let q =
        s.q.iter()
            .map(|&x| x + rng.random_range(-0.4..0.4))
            .collect();
    (q, s.tris)
}

fn random_v(rng: &mut StdRng, n: usize, scale: f64) -> Vec<f64> {
    (0..n).map(|_| rng.random_range(-scale..scale)).collect()
}

fn assert_fd(force: &dyn Force, q: &[f64], v: &[f64], h: f64, what: &str) {
    let r = check_force(force, q, v, h);
    eprintln!("{what}: dF/dq {:.2e}, dF/dv {:.2e}", r.dfdq, r.dfdv);
    assert!(r.dfdq < TOL && r.dfdv < TOL, "{what}: {r:?}");
}

/// Unit normal and mean velocity of triangle `t`.
fn normal_and_mean(q: &[f64], v: &[f64], t: [usize; 3]) -> ([f64; 3], [f64; 3]) {
    let p = |g: &[f64], i: usize| [g[3 * i], g[3 * i + 1], g[3 * i + 2]];
    let (a, b, c) = (p(q, t[0]), p(q, t[1]), p(q, t[2]));
    let e1 = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let e2 = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
    let n = [
        e1[1] * e2[2] - e1[2] * e2[1],
        e1[2] * e2[0] - e1[0] * e2[2],
        e1[0] * e2[1] - e1[1] * e2[0],
    ];
    let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    let u = [0, 1, 2].map(|k| (v[3 * t[0] + k] + v[3 * t[1] + k] + v[3 * t[2] + k]) / 3.0);
    (n.map(|x| x / l), u)
}

/// Shift the velocities of triangle `t`'s nodes so that its relative mean velocity has
/// normal component exactly `s` (m/s).
fn set_normal_speed(q: &[f64], v: &mut [f64], t: [usize; 3], wind: [f64; 3], s: f64) {
    let (n, u) = normal_and_mean(q, v, t);
    let cur: f64 = (0..3).map(|k| (u[k] - wind[k]) * n[k]).sum();
    for &i in &t {
        for k in 0..3 {
            v[3 * i + k] += (s - cur) * n[k];
        }
    }
}

#[test]
fn node_drag_jacobian_matches_fd() {
    let mut rng = StdRng::seed_from_u64(11);
    for _ in 0..20 {
        let fluid = windy(&mut rng);
        let n = 5;
        let nodes: Vec<usize> = (0..n).collect();
        let areas = random_v(&mut rng, n, 1.0)
            .iter()
            .map(|a| a.abs() + 0.1)
            .collect::<Vec<_>>();
        let drag = NodeDrag::new(&nodes, &areas, 1.75, &fluid);
        let q = random_v(&mut rng, 3 * n, 2.0);
        let v = random_v(&mut rng, 3 * n, 10.0);
        assert_fd(&drag, &q, &v, H, "node drag");
    }
}

#[test]
fn linear_drag_jacobian_matches_fd() {
    let mut rng = StdRng::seed_from_u64(12);
    let fluid = windy(&mut rng);
    let nodes = [0, 2, 3];
    let drag = LinearDrag::new(&nodes, &[0.3, 1.0, 2.5], &fluid);
    let q = random_v(&mut rng, 12, 2.0);
    let v = random_v(&mut rng, 12, 10.0);
    assert_fd(&drag, &q, &v, H, "linear drag");
}

#[test]
fn triangle_drag_jacobians_match_fd_on_random_configurations() {
    let mut rng = StdRng::seed_from_u64(13);
    for _ in 0..20 {
        let fluid = windy(&mut rng);
        let (q, tris) = deformed_sheet(&mut rng);
        let drag = TriangleDrag::new(&tris, 1.75, 0.5, &fluid);
        let v = random_v(&mut rng, q.len(), 10.0);
        assert_fd(&drag, &q, &v, H, "triangle drag");
    }
}

#[test]
fn triangle_drag_jacobians_match_fd_edge_on_and_through_reversal() {
    let mut rng = StdRng::seed_from_u64(14);
    for &s in &[0.0, 1e-6, -1e-6, 1e-3, -1e-3, 0.3, -0.3] {
        let fluid = windy(&mut rng);
        let (q, tris) = deformed_sheet(&mut rng);
        let drag = TriangleDrag::new(&tris, 1.75, 0.5, &fluid);
        // One triangle (and only that one) sees the flow at normal speed s; s = 0 is exactly
        // edge-on.
        let tri = [tris[3]];
        let single = TriangleDrag::new(&tri, 1.75, 0.5, &fluid);
        let mut v = random_v(&mut rng, q.len(), 5.0);
        set_normal_speed(&q, &mut v, tri[0], fluid.wind, s);
        assert_fd(&single, &q, &v, H, &format!("single triangle, s = {s}"));
        assert_fd(&drag, &q, &v, H, &format!("sheet, s = {s}"));
    }
}

#[test]
fn triangle_normal_drag_opposes_the_normal_flow_on_both_sides() {
    // Flow reversing through a triangle: the normal force must always oppose the normal
    // relative velocity (the |n̂·û| of the law), and vanish edge-on.
    let mut rng = StdRng::seed_from_u64(15);
    let (q, tris) = deformed_sheet(&mut rng);
    let tri = [tris[0]];
    let fluid = Fluid::air();
    let normal_only = TriangleDrag::new(&tri, 1.75, 0.0, &fluid);
    for &s in &[-2.0, -1e-3, 0.0, 1e-3, 2.0] {
        let mut v = random_v(&mut rng, q.len(), 3.0);
        set_normal_speed(&q, &mut v, tri[0], fluid.wind, s);
        let (n, _) = normal_and_mean(&q, &v, tri[0]);
        let (f, _, _) = dense_eval(&normal_only, &q, &v);
        let fn_total: f64 = tri[0]
            .iter()
            .map(|&i| (0..3).map(|k| f[3 * i + k] * n[k]).sum::<f64>())
            .sum();
        if s == 0.0 {
            assert_eq!(fn_total, 0.0);
        } else {
            assert!(fn_total * s < 0.0, "s = {s}: normal force {fn_total}");
        }
    }
}

#[test]
fn pressure_drag_jacobians_match_fd_including_reversal() {
    let mut rng = StdRng::seed_from_u64(16);
    for _ in 0..20 {
        let fluid = windy(&mut rng);
        let (q, tris) = deformed_sheet(&mut rng);
        let rest = sheet::sheet(3, 3, 2.0, 2.0, 0.0);
        let drag = PressureDrag::new(&tris, &rest.q, 1.75, &fluid);
        let v = random_v(&mut rng, q.len(), 10.0);
        assert_fd(&drag, &q, &v, H, "pressure drag");
    }
    // Reversal: a node's normal speed on either side of zero. |s| s has a kink in its second
    // derivative at 0, so central differences are exact only while h·|∂s/∂dof| < |s|; with
    // |s| ≥ 1e-3 and h = 1e-6 that holds.
    for &s in &[1e-2, -1e-2, 1e-3, -1e-3] {
        let fluid = windy(&mut rng);
        let (q, tris) = deformed_sheet(&mut rng);
        let tri = [tris[5]];
        let drag = PressureDrag::new(&tri, &q, 1.75, &fluid);
        let mut v = random_v(&mut rng, q.len(), 5.0);
        // Make every node of the triangle see normal speed s.
        let (n, _) = normal_and_mean(&q, &v, tri[0]);
        for &i in &tri[0] {
            let cur: f64 = (0..3).map(|k| (v[3 * i + k] - fluid.wind[k]) * n[k]).sum();
            for k in 0..3 {
                v[3 * i + k] += (s - cur) * n[k];
            }
        }
        assert_fd(&drag, &q, &v, H, &format!("pressure drag, s = {s}"));
    }
}

//! The drag laws evaluated directly against their formulas: which coefficient acts in which
//! flow, the cos³ (TriangleDrag) and cos² (PressureDrag) angle laws, the regularisation at
//! rest, the resultant helper and the Reynolds number. These are exact identities, so the
//! tolerance is round-off (1e-12 relative).
use engine::reference::sheet;

use engine::aero::{
    resultant, reynolds, stokes_sphere, DragRegime, Fluid, NodeDrag, PressureDrag, TriangleDrag,
    DEFAULT_EPSILON,
};
use engine::fdcheck::dense_eval;
use engine::force::{EvalInput, Force, JacobianKind, LocalBlocks};
use engine::DofLayout;
use rand::{rngs::StdRng, Rng, SeedableRng};

const RTOL: f64 = 1e-12;

fn close(a: [f64; 3], b: [f64; 3]) -> bool {
    let scale = b.iter().fold(1e-300f64, |m, x| m.max(x.abs()));
    (0..3).all(|k| (a[k] - b[k]).abs() <= RTOL * scale)
}

/// The 2 × 1 m sheet (4 triangles, area 2 m²) in the plane z = 0 moving with uniform
/// velocity `vel` in still air: the resultant of TriangleDrag with coefficients (cn, ct).
fn sheet_drag(cn: f64, ct: f64, vel: [f64; 3]) -> [f64; 3] {
    let s = sheet::sheet(3, 2, 2.0, 1.0, 0.0);
    let drag = TriangleDrag::new(&s.tris, cn, ct, &Fluid::air());
    let v: Vec<f64> = (0..s.n_nodes).flat_map(|_| vel).collect();
    resultant(&drag, &DofLayout::new(s.n_nodes, 0), &s.q, &v)
}

#[test]
fn sheet_sliding_edge_on_sees_only_tangential_coefficient() {
    let rho = Fluid::air().density;
    let vel = [3.0, -1.0, 0.0];
    let speed = (10.0f64).sqrt();
    let expect = vel.map(|x| -0.5 * rho * 0.5 * 2.0 * speed * x);
    for cn in [0.0, 1.75, 100.0] {
        let f = sheet_drag(cn, 0.5, vel);
        assert!(close(f, expect), "C_n = {cn}: {f:?} vs {expect:?}");
    }
}

#[test]
fn sheet_facing_the_flow_sees_only_normal_coefficient() {
    let rho = Fluid::air().density;
    for vz in [-4.0f64, 4.0] {
        let expect = [0.0, 0.0, -0.5 * rho * 1.75 * 2.0 * vz.abs() * vz];
        for ct in [0.0, 0.5, 100.0] {
            let f = sheet_drag(1.75, ct, [0.0, 0.0, vz]);
            assert!(close(f, expect), "C_t = {ct}, v_z = {vz}: {f:?}");
        }
    }
}

#[test]
fn oblique_flow_follows_cos_cubed_normal_and_quadratic_tangential_law() {
    // Flow at angle θ from the normal: normal force ½ρC_n A |u|² cos³θ, tangential
    // ½ρC_t A |u|² sin²θ, both opposing their components.
    let rho = Fluid::air().density;
    let (cn, ct, a, speed) = (1.75, 0.5, 2.0, 5.0);
    for deg in [10.0f64, 45.0, 80.0, 135.0] {
        let th = deg.to_radians();
        let vel = [speed * th.sin(), 0.0, speed * th.cos()];
        let f = sheet_drag(cn, ct, vel);
        let fz = -0.5 * rho * cn * a * speed * speed * th.cos().powi(3);
        let fx = -0.5 * rho * ct * a * speed * speed * th.sin().powi(2);
        assert!(
            close(f, [fx, 0.0, fz]),
            "θ = {deg}°: {f:?} vs {:?}",
            [fx, 0.0, fz]
        );
    }
}

#[test]
fn pressure_drag_follows_cos_squared_law_with_rest_area() {
    // Per-node law with the undeformed area: stretch the sheet by 2 in x (area doubles);
    // the force must still use A₀ and be normal-only: −½ρC_D A₀ |u|² cos²θ sign(cos θ) n̂.
    let rho = Fluid::air().density;
    let rest = sheet::sheet(3, 2, 2.0, 1.0, 0.0);
    let drag = PressureDrag::new(&rest.tris, &rest.q, 1.75, &Fluid::air());
    let q: Vec<f64> = rest
        .q
        .chunks(3)
        .flat_map(|p| [2.0 * p[0], p[1], p[2]])
        .collect();
    for deg in [0.0f64, 30.0, 89.0, 120.0] {
        let th = deg.to_radians();
        let vel = [4.0 * th.sin(), 0.0, 4.0 * th.cos()];
        let v: Vec<f64> = (0..rest.n_nodes).flat_map(|_| vel).collect();
        let f = resultant(&drag, &DofLayout::new(rest.n_nodes, 0), &q, &v);
        let c = th.cos();
        let fz = -0.5 * rho * 1.75 * 2.0 * 16.0 * c * c.abs();
        assert!(close(f, [0.0, 0.0, fz]), "θ = {deg}°: {f:?} vs {fz}");
    }
}

#[test]
fn node_drag_is_defined_at_rest_and_matches_formula() {
    let fluid = Fluid {
        wind: [1.0, 2.0, -2.0],
        ..Fluid::air()
    };
    let drag = NodeDrag::new(&[0, 1], &[0.4, 0.6], 1.2, &fluid);
    let q = vec![0.0; 6];
    // Node 0 moves with the wind (relative rest), node 1 has relative velocity (3, 0, 4).
    let v = vec![1.0, 2.0, -2.0, 4.0, 2.0, 2.0];
    let (f, _, kv) = dense_eval(&drag, &q, &v);
    assert_eq!(&f[0..3], &[0.0, 0.0, 0.0]);
    // At relative rest the Jacobian is −½ρC_D A ε I: finite, negative definite.
    let c0 = 0.5 * fluid.density * 1.2 * 0.4;
    assert!((kv[0] + c0 * DEFAULT_EPSILON).abs() < 1e-20 && kv[1] == 0.0);
    let c1 = 0.5 * fluid.density * 1.2 * 0.6;
    let expect = [-c1 * 5.0 * 3.0, 0.0, -c1 * 5.0 * 4.0];
    assert!(close([f[3], f[4], f[5]], expect), "{:?}", &f[3..6]);
}

/// A force on one node and one twist DOF, to check that `resultant` skips twists.
struct NodeAndTwist;
impl Force for NodeAndTwist {
    fn name(&self) -> &str {
        "node-and-twist"
    }
    fn stencil_size(&self) -> usize {
        4
    }
    fn stencils(&self) -> &[usize] {
        &[3, 4, 5, 6]
    }
    fn jacobian_kind(&self) -> JacobianKind {
        JacobianKind::CONSTANT
    }
    fn evaluate(&self, _: &EvalInput<'_>, out: &mut LocalBlocks) {
        out.f.copy_from_slice(&[1.0, 2.0, 3.0, 100.0]);
    }
}

#[test]
fn resultant_sums_node_forces_and_skips_twists() {
    let layout = DofLayout::new(2, 1);
    let z = vec![0.0; layout.len()];
    assert_eq!(resultant(&NodeAndTwist, &layout, &z, &z), [1.0, 2.0, 3.0]);
}

#[test]
fn reynolds_number_and_regimes() {
    // Re = ρ v L / μ for a 6 m canopy at 5 m/s in sea-level air ≈ 2.0e6: quadratic regime.
    let air = Fluid::air();
    let re = air.reynolds(5.0, 6.0);
    assert!((re - 1.225 * 5.0 * 6.0 / 1.81e-5).abs() < 1e-6 * re);
    assert_eq!(re, reynolds(1.225, -5.0, 6.0, 1.81e-5));
    assert_eq!(air.regime(5.0, 6.0), DragRegime::Quadratic);
    // A 1 mm particle settling at 1 mm/s in air: Re ≈ 0.07, Stokes regime.
    assert_eq!(air.regime(1e-3, 1e-3), DragRegime::Stokes);
    assert_eq!(DragRegime::of(50.0), DragRegime::Transitional);
    assert!((stokes_sphere(1.81e-5, 1e-3) - 6.0 * std::f64::consts::PI * 1.81e-8).abs() < 1e-20);
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

/// Unit normal and mean velocity of triangle `t`.
fn normal_and_mean(q: &[f64], v: &[f64], t: [usize; 3]) -> ([f64; 3], [f64; 3]) {
    let p = |i: usize| nalgebra::Vector3::new(q[3 * i], q[3 * i + 1], q[3 * i + 2]);
    let n = (p(t[1]) - p(t[0])).cross(&(p(t[2]) - p(t[0]))).normalize();
    let u = [0, 1, 2].map(|k| (v[3 * t[0] + k] + v[3 * t[1] + k] + v[3 * t[2] + k]) / 3.0);
    ([n.x, n.y, n.z], u)
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
fn triangle_normal_drag_opposes_the_normal_flow_on_both_sides() {
    // Flow reversing through a triangle: the normal force must always oppose the normal
    // relative velocity (the |n̂·û| of the law), and vanish edge-on.
    let mut rng = StdRng::seed_from_u64(15);
    let (q, tris) = deformed_sheet(&mut rng);
    let tri = [tris[0]];
    let fluid = Fluid::air();
    let normal_only = TriangleDrag::new(&tri, 1.75, 0.0, &fluid);
    for &s in &[-2.0, -1e-3, 0.0, 1e-3, 2.0] {
        let mut v = (0..q.len())
            .map(|_| rng.random_range(-3.0..3.0))
            .collect::<Vec<f64>>();
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

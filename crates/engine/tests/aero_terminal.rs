//! Falling bodies against the analytic quadratic-drag solution: from rest,
//! `v(t) = v_t tanh(g t / v_t)`, `v_t = √(2 m g / (ρ C_D A))`.
//!
//! Bodies: a flat, stiff horizontal sheet with [`TriangleDrag`] or [`PressureDrag`], and a
//! straight horizontal strip (nodes + springs) with [`NodeDrag`]. Masses are lumped in
//! proportion to each node's drag area, so every node has the same drag per unit mass and the
//! body translates rigidly: the springs carry no load and the 1-DOF solution is exact.
//!
//! Parameters: ρ = 1.225 kg/m³, C_D = 1.75, A = 1 m², v_t = 3 m/s ⇒ m = v_t² ρ C_D A / (2g)
//! ≈ 0.98 kg; the transient time scale is v_t/g ≈ 0.31 s, so 2 s reach tanh(6.5) = 1 − 4e-6.
mod aero_support;

use aero_support::{run, sheet, tanh_law};
use engine::aero::{Fluid, NodeDrag, PressureDrag, TriangleDrag};
use engine::loads::Gravity;
use engine::rod::Stretch;
use engine::{DofLayout, Model, State};

const G: f64 = 9.81;
const CD: f64 = 1.75;
const VT: f64 = 3.0;
const AREA: f64 = 1.0;
const T_END: f64 = 2.0;
/// Spring stiffness (N): stiff compared with the weight (≈ 10 N), so the body is rigid.
const K_SPRING: f64 = 1e5;

fn mass_for_vt(fluid: &Fluid) -> f64 {
    VT * VT * fluid.density * CD * AREA / (2.0 * G)
}

#[derive(Clone, Copy, Debug)]
enum Body {
    SheetTriangle,
    SheetPressure,
    StripNodes,
}

fn build(body: Body, fluid: &Fluid) -> (Model, State) {
    let m = mass_for_vt(fluid);
    match body {
        Body::SheetTriangle | Body::SheetPressure => {
            let s = sheet(3, 3, 1.0, 1.0, 10.0);
            let mut model = Model::new(DofLayout::new(s.n_nodes, 0));
            let masses = s.lumped_masses(m);
            for (i, &mi) in masses.iter().enumerate() {
                model.add_node_mass(i, mi);
            }
            let nodes: Vec<usize> = (0..s.n_nodes).collect();
            model.add_force(Gravity::new(&nodes, &masses, [0.0, 0.0, -G]));
            model.add_force(s.springs(K_SPRING));
            match body {
                Body::SheetTriangle => model.add_force(TriangleDrag::new(&s.tris, CD, 0.5, fluid)),
                _ => model.add_force(PressureDrag::new(&s.tris, &s.q, CD, fluid)),
            }
            (model, State::at_rest(s.q))
        }
        Body::StripNodes => {
            // 11 nodes over 2 m, width 0.5 m: drag radius r_d = 0.25 m, A_k = 2 r_d l̄_k with
            // rest Voronoi lengths l̄_k (half at the ends), Σ A_k = 1 m².
            let (n, len, width) = (11, 2.0, 0.5);
            let h = len / (n - 1) as f64;
            let q: Vec<f64> = (0..n).flat_map(|i| [i as f64 * h, 0.0, 10.0]).collect();
            let voronoi: Vec<f64> = (0..n)
                .map(|i| if i == 0 || i == n - 1 { h / 2.0 } else { h })
                .collect();
            let areas: Vec<f64> = voronoi.iter().map(|l| width * l).collect();
            let masses: Vec<f64> = areas.iter().map(|a| m * a / AREA).collect();
            let mut model = Model::new(DofLayout::new(n, 0));
            for (i, &mi) in masses.iter().enumerate() {
                model.add_node_mass(i, mi);
            }
            let nodes: Vec<usize> = (0..n).collect();
            let edges: Vec<[usize; 2]> = (0..n - 1).map(|i| [i, i + 1]).collect();
            model.add_force(Gravity::new(&nodes, &masses, [0.0, 0.0, -G]));
            model.add_force(Stretch::new("strip", &edges, &q, vec![K_SPRING; n - 1]));
            model.add_force(NodeDrag::new(&nodes, &areas, CD, fluid));
            (model, State::at_rest(q))
        }
    }
}

/// Max over the run of |v_z − v_exact| / v_t, and the final descent speed (m/s).
fn fall(body: Body, dt: f64) -> (f64, f64) {
    let fluid = Fluid::air();
    let (mut model, mut state) = build(body, &fluid);
    let steps = (T_END / dt).round() as usize;
    let series = run(&mut model, &mut state, dt, steps);
    let err = series
        .iter()
        .map(|&(t, v)| (-v[2] - tanh_law(VT, G, t)).abs() / VT)
        .fold(0.0, f64::max);
    (err, -series.last().unwrap().1[2])
}

fn check_body(body: Body) {
    let (e1, v_end) = fall(body, 1e-3);
    let (e2, _) = fall(body, 5e-4);
    eprintln!(
        "{body:?}: max err {e1:.3e} (dt=1e-3), {e2:.3e} (dt=5e-4), ratio {:.3}, v_end {v_end}",
        e1 / e2
    );
    // Backward Euler's global error is C·dt with C = O(g/v_t) relative (g dt/v_t ≈ 0.3 % at
    // dt = 1e-3; measured 6.0e-4), inside the 1 % the model must meet.
    assert!(e1 < 0.01, "{body:?}: error {e1}");
    // First order: halving dt halves the error, up to the O(dt²) term, itself O(g dt / v_t)
    // ≈ 0.3 % relative to the leading term, so 2 ± 0.1 leaves room only for that.
    let ratio = e1 / e2;
    assert!((ratio - 2.0).abs() < 0.1, "{body:?}: error ratio {ratio}");
    // Steady speed: backward Euler's fixed point is exactly v_t (up to the regularisation,
    // 1e-13 relative); at t = 2 s the transient deficit is 1 − tanh(6.5) ≈ 4e-6 plus the
    // integrator lag, far below the required 0.1 %.
    assert!((v_end / VT - 1.0).abs() < 1e-3, "{body:?}: v_end {v_end}");
}

#[test]
fn flat_sheet_with_triangle_drag_follows_tanh_law() {
    check_body(Body::SheetTriangle);
}

#[test]
fn flat_sheet_with_pressure_drag_follows_tanh_law() {
    check_body(Body::SheetPressure);
}

#[test]
fn straight_strip_with_node_drag_follows_tanh_law() {
    check_body(Body::StripNodes);
}

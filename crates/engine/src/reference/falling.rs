//! Rigid bodies falling under quadratic drag. From rest the descent speed follows
//! `v(t) = v_t tanh(g t / v_t)` with `v_t = √(2 m g / (ρ C_D A))`; in a horizontal wind
//! U∞ the horizontal velocity relaxes to U∞.
//!
//! Bodies: a flat, stiff horizontal sheet with [`TriangleDrag`] or [`PressureDrag`], and a
//! straight horizontal strip (nodes + springs) with [`NodeDrag`]. Masses are lumped in
//! proportion to each node's drag area, so every node has the same drag per unit mass and the
//! body translates rigidly: the springs carry no load and the 1-DOF solution is exact.
use super::sheet::{sheet, Sheet};
use super::RefError;
use crate::aero::{Fluid, InflationPressure, NodeDrag, PressureDrag, TriangleDrag};
use crate::loads::Gravity;
use crate::rod::Stretch;
use crate::{DofLayout, ImplicitEuler, Model, NewtonOptions, State};

/// Gravity (m/s²).
pub const G: f64 = 9.81;
/// Normal drag coefficient of the falling bodies.
pub const CD: f64 = 1.75;
/// Tangential (skin-friction) drag coefficient of the sheets.
pub const CD_T: f64 = 0.5;
/// Target terminal speed (m/s); the mass is set from it.
pub const VT: f64 = 3.0;
/// Drag area of every falling body (m²).
pub const AREA: f64 = 1.0;
/// Axial stiffness of the edge springs (N): stiff compared with the weight (≈ 10 N), so the
/// body is rigid.
pub const K_SPRING: f64 = 1e5;

/// Exact terminal-velocity transient from rest, `v(t) = v_t tanh(g t / v_t)` (m/s, downwards).
pub fn tanh_law(v_t: f64, g: f64, t: f64) -> f64 {
    v_t * (g * t / v_t).tanh()
}

/// Exact drop from rest under quadratic drag, the integral of [`tanh_law`]:
/// `d(t) = (v_t²/g) ln cosh(g t / v_t)` (m, downwards).
pub fn drop_law(v_t: f64, g: f64, t: f64) -> f64 {
    v_t * v_t / g * (g * t / v_t).cosh().ln()
}

/// A point mass at height `z0` (m) at rest: one node of mass [`mass_for_vt`], gravity and
/// [`NodeDrag`] with area [`AREA`] and [`CD`], so it falls by [`tanh_law`] and
/// [`drop_law`] towards [`VT`] exactly (no other DOF, nothing to deform).
pub fn point_mass(fluid: &Fluid, z0: f64) -> (Model, State) {
    let m = mass_for_vt(fluid);
    let mut model = Model::new(DofLayout::new(1, 0));
    model.add_node_mass(0, m);
    model.add_force(Gravity::new(&[0], &[m], [0.0, 0.0, -G]));
    model.add_force(NodeDrag::new(&[0], &[AREA], CD, fluid));
    (model, State::at_rest(vec![0.0, 0.0, z0]))
}

/// Mass (kg) that gives the terminal speed [`VT`] with [`CD`] and [`AREA`]:
/// `m = v_t² ρ C_D A / (2g)` (≈ 0.98 kg in sea-level air).
pub fn mass_for_vt(fluid: &Fluid) -> f64 {
    VT * VT * fluid.density * CD * AREA / (2.0 * G)
}

/// Mass-weighted mean velocity of all nodes (m/s).
pub fn mean_velocity(model: &Model, state: &State) -> [f64; 3] {
    let mut p = [0.0; 3];
    let n = model.layout.n_nodes;
    for i in 0..n {
        for k in 0..3 {
            p[k] += model.mass[3 * i + k] * state.v[3 * i + k];
        }
    }
    p.map(|x| x / model.total_mass())
}

/// Step `model` from `state` with `dt` for `steps` steps (default Newton options, force
/// scale set by the weight: `reference_acceleration` = [`G`]); return `(t, mean velocity)`
/// after every step.
pub fn run(
    model: &mut Model,
    state: &mut State,
    dt: f64,
    steps: usize,
) -> Result<Vec<(f64, [f64; 3])>, RefError> {
    let opts = NewtonOptions {
        reference_acceleration: G,
        ..Default::default()
    };
    let mut stepper = ImplicitEuler::new(model, opts)?;
    let mut out = Vec::with_capacity(steps);
    for _ in 0..steps {
        stepper.step(model, state, dt)?;
        out.push((state.t, mean_velocity(model, state)));
    }
    Ok(out)
}

/// Which falling body.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Body {
    /// 1 m × 1 m sheet of 8 triangles with [`TriangleDrag`].
    SheetTriangle,
    /// The same sheet with [`PressureDrag`].
    SheetPressure,
    /// The same sheet with [`InflationPressure`] (`C_p = C_D`).
    SheetInflation,
    /// The same sheet with [`InflationPressure::with_canopy_speed`]: the speed held over
    /// each step.
    SheetInflationCanopy,
    /// 2 m × 0.5 m strip of 11 nodes with [`NodeDrag`] (`A_k = 2 r_d l̄_k`, `r_d` = width/2).
    StripNodes,
}

/// Model and rest state of `body` at height 10 m, with mass [`mass_for_vt`].
pub fn build(body: Body, fluid: &Fluid) -> (Model, State) {
    let m = mass_for_vt(fluid);
    match body {
        Body::SheetTriangle
        | Body::SheetPressure
        | Body::SheetInflation
        | Body::SheetInflationCanopy => {
            let s = sheet(3, 3, 1.0, 1.0, 10.0);
            let mut model = rigid_sheet(&s, m);
            match body {
                Body::SheetTriangle => model.add_force(TriangleDrag::new(&s.tris, CD, CD_T, fluid)),
                Body::SheetPressure => model.add_force(PressureDrag::new(&s.tris, &s.q, CD, fluid)),
                Body::SheetInflationCanopy => model.add_force(
                    InflationPressure::new(&s.tris, &s.q, CD, fluid).with_canopy_speed(),
                ),
                _ => model.add_force(InflationPressure::new(&s.tris, &s.q, CD, fluid)),
            };
            (model, State::at_rest(s.q))
        }
        Body::StripNodes => strip(11, 2.0, 0.5, m, 10.0, fluid),
    }
}

/// A model of sheet `s` of mass `m` (kg) lumped in proportion to area, with gravity and
/// stiff edge springs ([`K_SPRING`]): a body that a uniform force per area moves rigidly.
pub fn rigid_sheet(s: &Sheet, m: f64) -> Model {
    let mut model = Model::new(DofLayout::new(s.n_nodes, 0));
    let masses = s.lumped_masses(m);
    for (i, &mi) in masses.iter().enumerate() {
        model.add_node_mass(i, mi);
    }
    let nodes: Vec<usize> = (0..s.n_nodes).collect();
    model.add_force(Gravity::new(&nodes, &masses, [0.0, 0.0, -G]));
    model.add_force(s.springs(K_SPRING));
    model
}

/// A straight horizontal strip along x at height `z0` (m): `n` nodes over `len` (m), width
/// `width` (m), total mass `m` (kg) lumped in proportion to the rest Voronoi lengths (half at
/// the ends), gravity, stiff springs and [`NodeDrag`] with `A_k = width · l̄_k`, so that
/// `Σ A_k = len · width`.
pub fn strip(n: usize, len: f64, width: f64, m: f64, z0: f64, fluid: &Fluid) -> (Model, State) {
    let h = len / (n - 1) as f64;
    let q: Vec<f64> = (0..n).flat_map(|i| [i as f64 * h, 0.0, z0]).collect();
    let areas: Vec<f64> = (0..n)
        .map(|i| width * if i == 0 || i == n - 1 { h / 2.0 } else { h })
        .collect();
    let total: f64 = areas.iter().sum();
    let masses: Vec<f64> = areas.iter().map(|a| m * a / total).collect();
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

/// A single horizontal right triangle (legs 1 m, area 0.5 m²) of mass `m` (kg) split
/// equally, with stiff springs, gravity and [`TriangleDrag`] (`C_D` = [`CD`], tangential
/// [`CD_T`]). One triangle of springs is rigid, and equal nodal shares keep it from rotating.
pub fn triangle(m: f64, fluid: &Fluid) -> (Model, State) {
    let q = vec![0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
    let mut model = Model::new(DofLayout::new(3, 0));
    for i in 0..3 {
        model.add_node_mass(i, m / 3.0);
    }
    let nodes = [0, 1, 2];
    let edges = [[0, 1], [1, 2], [2, 0]];
    model.add_force(Gravity::new(&nodes, &[m / 3.0; 3], [0.0, 0.0, -G]));
    model.add_force(Stretch::new("edges", &edges, &q, vec![K_SPRING; 3]));
    model.add_force(TriangleDrag::new(&[[0, 1, 2]], CD, CD_T, fluid));
    (model, State::at_rest(q))
}

/// Result of a fall from rest.
#[derive(Debug, Clone)]
pub struct FallResult {
    /// Max over the run of `|v_z − v_exact(t)| / v_t`.
    pub max_rel_error: f64,
    /// Final descent speed (m/s, positive down).
    pub final_speed: f64,
    /// `(t, descent speed)` after every step (s, m/s).
    pub series: Vec<(f64, f64)>,
}

/// Drop `body` from rest in still air and step it with `dt` until `t_end` (s).
pub fn fall(body: Body, dt: f64, t_end: f64) -> Result<FallResult, RefError> {
    let fluid = Fluid::air();
    let (mut model, mut state) = build(body, &fluid);
    let steps = (t_end / dt).round() as usize;
    let series = run(&mut model, &mut state, dt, steps)?;
    let max_rel_error = series
        .iter()
        .map(|&(t, v)| (-v[2] - tanh_law(VT, G, t)).abs() / VT)
        .fold(0.0, f64::max);
    let final_speed = series
        .last()
        .map(|s| -s.1[2])
        .ok_or_else(|| RefError::Measure("no steps".into()))?;
    Ok(FallResult {
        max_rel_error,
        final_speed,
        series: series.iter().map(|&(t, v)| (t, -v[2])).collect(),
    })
}

//! The Scordelis–Lo roof (MacNeal & Harder 1985, "A proposed standard set of problems to
//! test finite element accuracy", *Finite Elements in Analysis and Design* 1, 3–20; Belytschko
//! et al. 1985): a cylindrical panel of radius 25, length 50, thickness 0.25, E = 4.32e8,
//! ν = 0, 40° half-angle, under self-weight 90 per unit area, on rigid end diaphragms (the
//! end nodes held in y and z, free in x), longitudinal edges free. Reference: the vertical
//! displacement at the middle of a free edge, 0.3024 (linear theory; MacNeal & Harder's
//! value). Here the bending laws of the rectangle patterns with the edge-spring membrane, as
//! information: the springs cannot represent ν = 0 (their in-plane ν is 1/3 on these
//! meshes, `docs/shells.md`), so only a membrane with the material's ν can meet the
//! reference.
use super::midedge_cases::{Law, PATTERNS};
use super::Check;
use crate::mesh::generate::{rectangle_pattern, Pattern};
use engine::loads::PointForces;
use engine::shell::{self, midedge, PlateBending, ShellMaterial, TriMesh};
use engine::{DofLayout, Model, NewtonOptions, State, StaticSolver};

/// Radius, length, thickness, Young's modulus, load per area, half-angle (rad).
const R: f64 = 25.0;
const L: f64 = 50.0;
const T: f64 = 0.25;
const E: f64 = 4.32e8;
const Q: f64 = 90.0;
const HALF_ANGLE: f64 = 40.0 * std::f64::consts::PI / 180.0;
/// Reference midside vertical displacement (MacNeal & Harder 1985).
pub const REFERENCE: f64 = 0.3024;
/// The load is applied at this fraction and the displacement scaled back, so the solve
/// stays linear (geometric effects ~ (w/R) × fraction ≈ 1e-5).
const LOAD_FRACTION: f64 = 1e-3;

/// Midside vertical displacement of the roof meshed in `pattern` with `n` cells across the
/// arc, bending by `law` (ν = 0) and the edge-spring membrane; linear (scaled) response.
pub fn midside_displacement(pattern: Pattern, n: usize, law: Law) -> Result<f64, String> {
    let width = 2.0 * R * HALF_ANGLE;
    let m = rectangle_pattern(L, width, width / n as f64, pattern);
    // Roll the flat mesh (x along the axis, y the arc length) onto the cylinder, crown on top.
    let mut q: Vec<f64> = m
        .positions
        .iter()
        .flat_map(|p| {
            let phi = p[1] / R;
            [p[0], R * phi.sin(), R * phi.cos()]
        })
        .collect();
    let tri = TriMesh::from_q(m.faces.clone(), &q, m.n_nodes()).map_err(|e| e.to_string())?;
    let twists = if law == Law::Midedge {
        tri.edges.len()
    } else {
        0
    };
    let mut model = Model::new(DofLayout::new(m.n_nodes(), twists));
    q.resize(model.n_dofs(), 0.0);
    let mat = ShellMaterial {
        youngs_modulus: E,
        thickness: T,
        density: 1.0,
    };
    let err = |e: engine::EngineError| e.to_string();
    match law {
        Law::Hinge => shell::install(&tri, &mat, &mut model, &q).map_err(err)?,
        Law::Midedge => {
            let plate = PlateBending {
                youngs_modulus: E,
                poisson_ratio: 0.0,
                thickness: T,
            };
            shell::install_stretch_and_mass(&tri, &mat, &mut model, &q).map_err(err)?;
            midedge::install(&tri, &plate, 1.0, &mut model, &q, 0).map_err(err)?;
        }
    }
    // Diaphragms: the end nodes held in their plane (y, z); the crown centre in x.
    for (i, p) in m.positions.iter().enumerate() {
        if (p[0].abs() - 0.5 * L).abs() < 1e-9 * L {
            model.fixed[3 * i + 1] = true;
            model.fixed[3 * i + 2] = true;
        }
    }
    let c = m.node_set("center").ok_or("no centre node")?[0];
    model.fixed[3 * c] = true;
    let nodes: Vec<usize> = (0..m.n_nodes()).collect();
    let forces: Vec<[f64; 3]> = tri
        .vertex_areas
        .iter()
        .map(|&a| [0.0, 0.0, -LOAD_FRACTION * Q * a])
        .collect();
    model.add_force(PointForces::new(&nodes, &forces));
    let opts = NewtonOptions {
        force_tol_abs: Some(1e-9 * LOAD_FRACTION * Q * L * width),
        ..Default::default()
    };
    let mut solver = StaticSolver::new(&model, opts).map_err(|e| e.to_string())?;
    let mut state = State::at_rest(q.clone());
    solver
        .solve(&mut model, &mut state, 1)
        .map_err(|e| e.to_string())?;
    let mids = m.node_set("long_edge_midpoints").ok_or("no midpoints")?;
    let dz: f64 = mids
        .iter()
        .map(|&i| q[3 * i + 2] - state.q[3 * i + 2])
        .sum::<f64>()
        / mids.len() as f64;
    Ok(dz / LOAD_FRACTION)
}

/// The roof on every pattern with the springs membrane, mid-edge and hinge bending, at `n`
/// = 8, 16 (quick) or 8, 16, 32 cells across the arc: information rows.
pub fn roof_case(quick: bool) -> Result<Vec<Check>, String> {
    let ladder: &[usize] = if quick { &[8, 16] } else { &[8, 16, 32] };
    let src = "MacNeal & Harder (1985): 0.3024";
    let mut out = Vec::new();
    for (pattern, name) in PATTERNS {
        for (law, tag) in [(Law::Midedge, "midedge"), (Law::Hinge, "hinges")] {
            for &n in ladder {
                out.push(Check::info(
                    &format!("scordelis-lo-springs-{tag}"),
                    &format!("midside vertical displacement, {name}, {n} cells across"),
                    REFERENCE,
                    src,
                    midside_displacement(pattern, n, law)?,
                ));
            }
        }
    }
    Ok(out)
}

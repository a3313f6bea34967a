//! Drag elements for the canopy and the lines.
use super::canopy::Geometry;
use super::load::Plan;
use crate::scenario::{DragLaw, ModelKind, Scenario, ShellDrag};
use engine::aero::{Fluid, LinearDrag, NodeDrag, PressureDrag, TriangleDrag};
use engine::rod::RodHandles;
use engine::{ForceId, Model};

/// What was installed.
pub struct DragInstall {
    /// The drag families.
    pub forces: Vec<ForceId>,
    /// The per-triangle family.
    pub triangle: Option<ForceId>,
    /// Σ C_D A of the flat canopy facing the flow (m²).
    pub flat_cd_area: f64,
}

/// Install drag on the canopy (node drag for a rod canopy, triangle drag for a shell) and
/// node drag on suspension lines (A_k = 2 r l̄_k with the line radius r).
pub fn install(
    s: &Scenario,
    geo: &Geometry,
    plan: &Plan,
    handles: &RodHandles,
    model: &mut Model,
) -> DragInstall {
    let f = &s.fluid;
    let fluid = Fluid {
        density: f.density_kg_m3,
        viscosity: f.viscosity_pa_s,
        wind: f.wind_mps,
    };
    let mut out = DragInstall {
        forces: Vec::new(),
        triangle: None,
        flat_cd_area: 0.0,
    };
    let cd = f.drag_coefficient;
    // Canopy: nodes and their projected areas (rod: 2 r_d l̄_k with r_d = width/2).
    let (nodes, areas): (Vec<usize>, Vec<f64>) = if s.model.kind == ModelKind::Rod {
        let r = plan.canopy_rod.expect("rod canopy");
        let chain = &plan.rods.rods()[r].nodes;
        let vl = &handles.rod_voronoi_len[r];
        (
            chain.clone(),
            vl.iter().map(|l| s.canopy.width_m * l).collect(),
        )
    } else {
        let tri = geo.tri_mesh.as_ref().expect("shell canopy");
        let nodes = geo.canopy_nodes.clone();
        let areas = nodes.iter().map(|&i| tri.vertex_areas[i]).collect();
        (nodes, areas)
    };
    let area: f64 = areas.iter().sum();
    out.flat_cd_area = cd * area;
    match (f.drag, s.model.kind) {
        (DragLaw::Linear, _) => {
            let c = f.linear_drag_coefficient_n_s_m.unwrap_or(0.0);
            let coeffs: Vec<f64> = areas.iter().map(|a| c * a / area).collect();
            out.forces
                .push(model.add_force(LinearDrag::new(&nodes, &coeffs, &fluid)));
        }
        (DragLaw::Quadratic, ModelKind::Rod) => {
            out.forces
                .push(model.add_force(NodeDrag::new(&nodes, &areas, cd, &fluid)));
        }
        (DragLaw::Quadratic, ModelKind::Shell) => {
            let faces = geo.triangles();
            let id = match f.shell_drag {
                ShellDrag::Report => model.add_force(TriangleDrag::new(
                    &faces,
                    cd,
                    f.tangential_drag_coefficient,
                    &fluid,
                )),
                ShellDrag::Pressure => {
                    let q: Vec<f64> = geo.mesh.positions.iter().flatten().copied().collect();
                    let mut qfull = q;
                    qfull.resize(model.n_dofs(), 0.0);
                    model.add_force(PressureDrag::new(&faces, &qfull, cd, &fluid))
                }
            };
            out.forces.push(id);
            out.triangle = Some(id);
        }
    }
    // Lines: isotropic node drag with the line diameter as projected width.
    let (mut ln, mut la) = (Vec::new(), Vec::new());
    for &r in &plan.line_rods {
        let rod = &plan.rods.rods()[r];
        for (&node, &l) in rod.nodes.iter().zip(&handles.rod_voronoi_len[r]) {
            ln.push(node);
            la.push(2.0 * s.lines.radius_m * l);
        }
    }
    let cd_lines = s.lines.drag_coefficient.unwrap_or(cd);
    if !ln.is_empty() && f.drag == DragLaw::Quadratic && cd_lines > 0.0 {
        out.forces
            .push(model.add_force(NodeDrag::new(&ln, &la, cd_lines, &fluid)));
    }
    out
}

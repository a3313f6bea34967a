//! Drag elements for the canopy and the lines, in the scenario's air (constant or the 1976
//! standard atmosphere) and, for a shell, with the fabric's permeability.
use super::canopy::Geometry;
use super::load::Plan;
use crate::resolve::ModelSpec;
use crate::scenario::{DragLaw, InflationSpeed, Material, ModelKind, ShellDrag};
use engine::aero::atmosphere::sutherland;
use engine::aero::{
    AddedMass, Fabric, IncidencePressure, InflationPressure, LinearDrag, NodeDrag, PressureDrag,
    TriangleDrag,
};
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

/// Pressure drop of the ASTM D737 air-permeability test, 0.5 in of water (Pa).
pub const ASTM_D737_PRESSURE_PA: f64 = 124.5;
/// Temperature of the standard textile-testing atmosphere (ASTM D1776: 21 °C) in which the
/// D737 flow is measured (K); the air's viscosity there converts the flow to a permeability.
pub const ASTM_D737_TEMPERATURE_K: f64 = 294.15;
/// One ft³/(ft²·min) as a speed (m/s): 0.3048 m / 60 s.
pub const CFM_PER_FT2_MPS: f64 = 0.3048 / 60.0;

/// Darcy permeability (m²) of a fabric of thickness `thickness_m` rated `cfm` ft³/(ft²·min)
/// in the ASTM D737 test: `k = h μ u / Δp` with the Darcy term alone, u = cfm · 0.3048/60
/// m/s, Δp = 124.5 Pa and μ of air at 21 °C (Sutherland).
pub fn permeability_from_cfm(cfm: f64, thickness_m: f64) -> f64 {
    let mu = sutherland(ASTM_D737_TEMPERATURE_K).0;
    Fabric::darcy_permeability(
        thickness_m,
        mu,
        cfm * CFM_PER_FT2_MPS,
        ASTM_D737_PRESSURE_PA,
    )
}

/// The canopy fabric's permeability, when material `m` gives one (thickness `h`, m).
pub fn fabric(m: &Material, h: f64) -> Option<Fabric> {
    let k = m
        .permeability_m2
        .or_else(|| m.air_permeability_cfm.map(|q| permeability_from_cfm(q, h)))?;
    Some(Fabric::new(h, k, m.forchheimer_coefficient.unwrap_or(0.0)))
}

/// Install drag on the canopy (node drag for a rod canopy, triangle drag for a shell) and
/// node drag on suspension lines (A_k = 2 r l̄_k with the line radius r).
pub fn install(
    s: &ModelSpec,
    geo: &Geometry,
    plan: &Plan,
    handles: &RodHandles,
    model: &mut Model,
) -> DragInstall {
    let f = &s.fluid;
    let fluid = &s.air;
    let fabric = s.permeability;
    let mut out = DragInstall {
        forces: Vec::new(),
        triangle: None,
        flat_cd_area: 0.0,
    };
    let cd = f.drag_coefficient;
    // Canopy: nodes and their projected areas (rod: 2 r_d l̄_k with r_d = width/2).
    let (nodes, areas): (Vec<usize>, Vec<f64>) = if s.kind == ModelKind::Rod {
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
    match (f.drag, s.kind) {
        (DragLaw::Linear, _) => {
            let c = f.linear_drag_coefficient_n_s_m.unwrap_or(0.0);
            let coeffs: Vec<f64> = areas.iter().map(|a| c * a / area).collect();
            out.forces
                .push(model.add_force(LinearDrag::new(&nodes, &coeffs, fluid)));
        }
        (DragLaw::Quadratic, ModelKind::Rod) => {
            out.forces
                .push(model.add_force(NodeDrag::new(&nodes, &areas, cd, fluid)));
        }
        (DragLaw::Quadratic, ModelKind::Shell) => {
            let faces = geo.triangles();
            let id = match f.shell_drag {
                ShellDrag::Report => {
                    let d = TriangleDrag::new(&faces, cd, f.tangential_drag_coefficient, fluid);
                    match fabric {
                        Some(fab) => model.add_force(d.with_fabric(fab)),
                        None => model.add_force(d),
                    }
                }
                ShellDrag::Pressure => {
                    let d = PressureDrag::new(&faces, &rest_q(geo, model), cd, fluid);
                    match fabric {
                        Some(fab) => model.add_force(d.with_fabric(fab)),
                        None => model.add_force(d),
                    }
                }
                ShellDrag::Inflation | ShellDrag::Incidence => {
                    // Skin friction: the report law with its normal part off (the pressure
                    // replaces it, and only it sees the fabric's leakage). Under the
                    // incidence law the table is the whole canopy's normal force, friction
                    // included, so none is added.
                    let ct = f.tangential_drag_coefficient;
                    if ct > 0.0 && f.shell_drag == ShellDrag::Inflation {
                        let t = TriangleDrag::new(&faces, 0.0, ct, fluid);
                        out.forces.push(model.add_force(t));
                    }
                    let rest = rest_q(geo, model);
                    match (s.incidence.clone(), fabric) {
                        (None, fab) => {
                            let mut p = InflationPressure::new(&faces, &rest, cd, fluid);
                            if let Some(fab) = fab {
                                p = p.with_fabric(fab);
                            }
                            if f.inflation_speed == Some(InflationSpeed::Canopy) {
                                p = p.with_canopy_speed();
                            }
                            model.add_force(p)
                        }
                        (Some(c), None) => {
                            model.add_force(IncidencePressure::new(&faces, &rest, cd, c, fluid))
                        }
                        (Some(c), Some(fab)) => model.add_force(
                            IncidencePressure::new(&faces, &rest, cd, c, fluid).with_fabric(fab),
                        ),
                    }
                }
            };
            out.forces.push(id);
            out.triangle = Some(id);
        }
    }
    // Not a drag family: it does no work over a steady descent and observers leave it out.
    if f.added_mass == Some(true) && s.kind == ModelKind::Shell {
        // The carried air starts with the canopy (at rest, or at `initial_velocity`).
        let q = rest_q(geo, model);
        let mut v = vec![0.0; q.len()];
        for node in v[..3 * model.layout.n_nodes].chunks_exact_mut(3) {
            node.copy_from_slice(&s.initial_velocity);
        }
        model.add_force(AddedMass::new(&geo.triangles(), &q, &v, fluid));
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
    let cd_lines = s.line_drag_coefficient;
    if !ln.is_empty() && f.drag == DragLaw::Quadratic && cd_lines > 0.0 {
        out.forces
            .push(model.add_force(NodeDrag::new(&ln, &la, cd_lines, fluid)));
    }
    out
}

/// The rest positions of the canopy mesh as a vector over all of the model's DOFs (the
/// triangle laws read their rest areas or orientations from it).
fn rest_q(geo: &Geometry, model: &Model) -> Vec<f64> {
    let mut q: Vec<f64> = geo.mesh.positions.iter().flatten().copied().collect();
    q.resize(model.n_dofs(), 0.0);
    q
}

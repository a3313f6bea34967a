//! The derived quantities of an imported mesh (`canopy.mesh_file`), which only the mesh
//! file knows: its weight and terminal speed, and the stiffness-to-inertia ratios of its
//! shortest elements.

use super::{air_density, input, Derived, TERMINAL_SPEED};
use crate::scenario::{DragLaw, Scenario};

/// An imported mesh's weight (its lumped masses, the payload node's × `load.mass_scale`,
/// under gravity) and flat-canopy terminal speed, from the mesh file (read here; when it
/// cannot be, the builder says why). Empty for anything else.
pub(super) fn descent(s: &Scenario) -> Vec<Derived> {
    let (Some(path), DragLaw::Quadratic) = (&s.canopy.mesh_file, s.fluid.drag) else {
        return Vec::new();
    };
    let Ok(mesh) = crate::mesh::read_file(path) else {
        return Vec::new();
    };
    // The payload node's mass is its lumped mass (a third of its triangles' and half of its
    // line edges' masses) times the factor.
    let node = s.load.node.wrapping_sub(1);
    let (area, share) = mesh.lumped_areas();
    let (length, reach) = mesh.lumped_lengths();
    let (m, ld, ln) = (&s.material, &s.load, &s.lines);
    let rho_h = m.density_kg_m3 * s.canopy.thickness_m;
    let rho_l = ln.density_kg_m3 * std::f64::consts::PI * ln.radius_m * ln.radius_m;
    let lumped = |total: f64, of: &[f64]| {
        total + (ld.mass_scale - 1.0) * of.get(node).copied().unwrap_or(0.0)
    };
    let mass = rho_h * lumped(area, &share) + rho_l * lumped(length, &reach);
    let weight = mass * s.fluid.gravity_mps2;
    let (rho, air) = air_density(s);
    let mut inputs = vec![
        input("load.mass_scale", ld.mass_scale, 100.0),
        input("fluid.gravity_mps2", s.fluid.gravity_mps2, 9.81),
        input("material.density_kg_m3", m.density_kg_m3, 1000.0),
        input("canopy.thickness_m", s.canopy.thickness_m, 1e-3),
    ];
    let total = Derived {
        name: "total weight",
        unit: "N",
        value: weight,
        inputs: inputs.clone(),
    };
    inputs.extend([
        air,
        input("fluid.drag_coefficient", s.fluid.drag_coefficient, 1.0),
    ]);
    let terminal = Derived {
        name: TERMINAL_SPEED,
        unit: "m/s",
        value: (2.0 * weight / (rho * s.fluid.drag_coefficient * area)).sqrt(),
        inputs,
    };
    vec![total, terminal]
}

/// The stiffness-to-inertia ratios `E dt²/(ρ l²)` of an imported mesh's shortest line edge
/// (its rod edges carry the lines' material) and shortest triangle edge; empty for anything
/// else, or a mesh that cannot be read (the builder says why).
pub(super) fn step_stiffness(s: &Scenario) -> Vec<Derived> {
    let Some(path) = &s.canopy.mesh_file else {
        return Vec::new();
    };
    let Ok(mesh) = crate::mesh::read_file(path) else {
        return Vec::new();
    };
    let dist = |a: usize, b: usize| {
        let (p, q) = (mesh.positions[a], mesh.positions[b]);
        ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt()
    };
    let shortest = |edges: &mut dyn Iterator<Item = [usize; 2]>| {
        edges.map(|[a, b]| dist(a, b)).fold(f64::INFINITY, f64::min)
    };
    let line = shortest(&mut mesh.rod_edges.iter().copied());
    let tri = shortest(
        &mut mesh
            .faces
            .iter()
            .flat_map(|f| [[f[0], f[1]], [f[1], f[2]], [f[2], f[0]]]),
    );
    let dt = input("time.dt_s", s.time.dt_s, 1e-3);
    let (m, ln) = (&s.material, &s.lines);
    // The ratio of an edge of length `l` of the material `[E, ρ]` (keys, values).
    let ratio = |name, l: f64, [e, rho]: [(&'static str, f64); 2]| Derived {
        name,
        unit: "",
        value: e.1 * s.time.dt_s.powi(2) / (rho.1 * l * l),
        inputs: vec![input(e.0, e.1, 1e9), input(rho.0, rho.1, 1000.0), dt],
    };
    let canopy = [
        ("material.youngs_modulus_pa", m.youngs_modulus_pa),
        ("material.density_kg_m3", m.density_kg_m3),
    ];
    let lines = [
        ("lines.youngs_modulus_pa", ln.youngs_modulus_pa),
        ("lines.density_kg_m3", ln.density_kg_m3),
    ];
    [
        (
            "shortest mesh edge's stiffness-to-inertia ratio over a step E dt²/(ρ l²)",
            tri,
            canopy,
        ),
        (
            "shortest mesh line edge's stiffness-to-inertia ratio over a step E dt²/(ρ l²)",
            line,
            lines,
        ),
    ]
    .into_iter()
    .filter(|(_, l, _)| l.is_finite())
    .map(|(name, l, keys)| ratio(name, l, keys))
    .collect()
}

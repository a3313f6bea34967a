//! Bending on the three rectangle mesh patterns (union-jack, cross, unstructured), mid-edge
//! against Kirchhoff plate theory and, as information, the report's hinges on the same
//! meshes: the cylinder bending energy and the simply supported square plate with a ladder
//! of meshes (observed orders). Shared by `chute validate` and the physics tests.
use super::shell_cases::{
    navier_ss_square, solve_static, support_simply_under_pressure, wrap_on_cylinder, MAT,
};
use super::Check;
use crate::mesh::generate::{rectangle_pattern, Pattern};
use crate::mesh::CanopyMesh;
use engine::shell::{self, midedge, MidedgeBending, PlateBending, TriMesh};
use engine::{DofLayout, Model};

/// Poisson ratio of the mid-edge cases (the hinges have none of their own).
pub const NU: f64 = 0.3;

/// Plate constants of the mid-edge cases: [`MAT`]'s E and h with ν = [`NU`].
pub const PLATE: PlateBending = PlateBending {
    youngs_modulus: MAT.youngs_modulus,
    poisson_ratio: NU,
    thickness: MAT.thickness,
};

/// The three rectangle patterns with their names.
pub const PATTERNS: [(Pattern, &str); 3] = [
    (Pattern::UnionJack, "union-jack"),
    (Pattern::Cross, "cross"),
    (Pattern::Unstructured, "unstructured"),
];

/// A bending law of the shell.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Law {
    /// The report's dihedral hinges, `k_b = (2/√3) E h³/12`.
    Hinge,
    /// Mid-edge bending with [`PLATE`].
    Midedge,
}

/// Model of the flat mesh `m`: edge springs, lumped masses and the bending `law` (mid-edge:
/// one angle DOF per mesh edge, after the nodes); its rest `q` and the mesh.
pub fn bending_model(m: &CanopyMesh, law: Law) -> Result<(Model, Vec<f64>, TriMesh), String> {
    let tri = m.tri_mesh().map_err(|e| e.to_string())?;
    let twists = if law == Law::Midedge {
        tri.edges.len()
    } else {
        0
    };
    let mut model = Model::new(DofLayout::new(m.n_nodes(), twists));
    let mut q = m.q();
    q.resize(model.n_dofs(), 0.0);
    let err = |e: engine::EngineError| e.to_string();
    match law {
        Law::Hinge => shell::install(&tri, &MAT, &mut model, &q).map_err(err)?,
        Law::Midedge => {
            let parts = shell::ShellParts::try_new(&tri, &MAT, &model, &q).map_err(err)?;
            parts.springs(&mut model);
            parts.masses(&mut model);
            midedge::install(&tri, &PLATE, MAT.density, &mut model, &q, 0).map_err(err)?;
        }
    }
    Ok((model, q, tri))
}

/// Mid-edge bending energy per area (J/m²) of the `1 m × 1 m` `pattern` mesh of edge `ell`
/// (m) wrapped onto a cylinder of radius `r` (m; axis along x when `axis_x`): the nodes are
/// held on the cylinder and the edge angles relax (a static solve in them alone). Faces
/// whose flat centroid lies in the central `0.5 m × 0.5 m` window are summed, so the free
/// boundary (whose angles relax differently) does not enter.
pub fn cylinder_density(pattern: Pattern, ell: f64, r: f64, axis_x: bool) -> Result<f64, String> {
    let m = rectangle_pattern(1.0, 1.0, ell, pattern);
    let tri = m.tri_mesh().map_err(|e| e.to_string())?;
    let flat = m.q();
    let mut model = Model::new(DofLayout::new(m.n_nodes(), tri.edges.len()));
    let mut rest = flat.clone();
    rest.resize(model.n_dofs(), 0.0);
    midedge::install(&tri, &PLATE, MAT.density, &mut model, &rest, 0).map_err(|e| e.to_string())?;
    (0..m.n_nodes()).for_each(|i| model.fix_node(i));
    let (mut q, _) = wrap_on_cylinder(&m, r, axis_x);
    q.resize(model.n_dofs(), 0.0);
    // Residuals are moments ~ D ℓ/R per edge; 1e-10 of that is round-off level.
    let state = solve_static(&mut model, q, 1e-10 * PLATE.stiffness() * ell / r)?;
    let bend = MidedgeBending::new("bend", &tri, &rest, &PLATE, 3 * m.n_nodes());
    let (mut energy, mut area) = (0.0, 0.0);
    for (i, f) in tri.faces.iter().enumerate() {
        let c = |k: usize| f.iter().map(|&n| flat[3 * n + k]).sum::<f64>() / 3.0;
        if c(0).abs() < 0.25 && c(1).abs() < 0.25 {
            energy += bend.face_energy(&state.q, i);
            area += tri.face_areas[i];
        }
    }
    Ok(energy / area)
}

/// Plate-theory cylinder energy per area `½ D/R²` (J/m²) of [`PLATE`].
pub fn cylinder_reference(r: f64) -> f64 {
    0.5 * PLATE.stiffness() / (r * r)
}

/// Pressure (Pa) giving a mid-edge centre deflection of about `1e-3 h` on the unit plate
/// (membrane effects ~ (w/h)² negligible).
pub fn plate_pressure() -> f64 {
    1e-3 * PLATE.thickness * PLATE.stiffness() / navier_ss_square()
}

/// Navier centre deflection (m) of the unit simply supported plate of stiffness `d` (N·m)
/// under pressure `p` (Pa): `β p a⁴/D`.
pub fn plate_reference(p: f64, d: f64) -> f64 {
    navier_ss_square() * p / d
}

/// Centre deflection (m, positive down) of the simply supported unit square plate meshed in
/// `pattern` with edge `1/n` under pressure `p` (Pa), bending by `law`. Boundary nodes are
/// held in z; the edge angles stay free (no moment at the support); the centre node (x, y)
/// and a long-edge midpoint (x) remove the in-plane rigid modes.
pub fn plate_deflection(pattern: Pattern, n: usize, law: Law, p: f64) -> Result<f64, String> {
    let m = rectangle_pattern(1.0, 1.0, 1.0 / n as f64, pattern);
    let (mut model, q, tri) = bending_model(&m, law)?;
    let c = support_simply_under_pressure(&mut model, &m, &tri, p)?;
    let state = solve_static(&mut model, q, 1e-6 * p)?;
    Ok(-state.q[3 * c + 2])
}

/// Observed order of convergence `log₂(e₁/e₂)` of errors on meshes refined by 2.
pub fn observed_order(e_coarse: f64, e_fine: f64) -> f64 {
    (e_coarse.abs() / e_fine.abs()).log2()
}

/// Cylinder energy, every pattern and both axes: nodes on the cylinder are exact; the
/// chord-vs-arc error of the faces is O((ℓ/R)²) (6e-4 at ℓ = 2.5 cm, 2.5e-3 at 5 cm), the
/// tolerance. The hinges on the same meshes, against `½ (E h³/12)/R²`, as information.
pub fn cylinder_case(quick: bool) -> Result<Vec<Check>, String> {
    let (r, ell): (f64, f64) = (1.0, if quick { 0.05 } else { 0.025 });
    let tol = (ell / r).powi(2);
    let mut out = Vec::new();
    for (pattern, name) in PATTERNS {
        for (axis_x, tag) in [(true, "x"), (false, "y")] {
            out.push(Check::new(
                "midedge-cylinder",
                &format!("energy/area (J/m²), R = 1 m, {name} ℓ = {ell} m, axis {tag}"),
                cylinder_reference(r),
                "plate theory: ½ D/R², D = E h³/(12(1 − ν²)), ν = 0.3",
                cylinder_density(pattern, ell, r, axis_x)?,
                tol,
            ));
        }
        let m = rectangle_pattern(1.0, 1.0, ell, pattern);
        let (q, _) = wrap_on_cylinder(&m, r, true);
        let window = |x: f64, y: f64| x.abs() < 0.25 && y.abs() < 0.25;
        out.push(Check::info(
            "midedge-cylinder-hinges",
            &format!("hinge energy/area (J/m²), {name} ℓ = {ell} m, axis x (information)"),
            0.5 * MAT.plate_stiffness() / (r * r),
            "½ (E h³/12)/R² (nominal; the hinges' D depends on the mesh)",
            super::shell_cases::energy_density(&m, &q, &window),
        ));
    }
    Ok(out)
}

/// Simply supported plate on every pattern, meshes `n = 8, 16, 32` (quick: 8, 16): the
/// finest error is within 4 × (1/n)² (the ladder's error constant is ≈ 3.2 on every
/// pattern), the observed order of the last refinement is 2 ± 0.3, and (full) the
/// Richardson extrapolation `(4 w₂ₙ − wₙ)/3` is within 1e-3 of Navier. The hinges on the
/// finest mesh, against Navier with `E h³/12`, as information.
pub fn plate_case(quick: bool) -> Result<Vec<Check>, String> {
    let p = plate_pressure();
    let reference = plate_reference(p, PLATE.stiffness());
    let ladder: &[usize] = if quick { &[8, 16] } else { &[8, 16, 32] };
    let src = "Navier series: 0.0040624 q a⁴/D, D = E h³/(12(1 − ν²))";
    let mut out = Vec::new();
    for (pattern, name) in PATTERNS {
        let w = ladder
            .iter()
            .map(|&n| plate_deflection(pattern, n, Law::Midedge, p))
            .collect::<Result<Vec<f64>, String>>()?;
        let k = w.len() - 1;
        let n = ladder[k];
        out.push(Check::new(
            "midedge-plate",
            &format!("centre deflection (m), {name} {n}×{n}"),
            reference,
            src,
            w[k],
            4.0 / (n * n) as f64,
        ));
        out.push(Check::new(
            "midedge-plate-order",
            &format!("observed order, {name} {}→{n}", ladder[k - 1]),
            2.0,
            "second order in ℓ (plate bending, nonconforming normals)",
            observed_order(w[k - 1] - reference, w[k] - reference),
            0.15,
        ));
        if !quick {
            out.push(Check::new(
                "midedge-plate-richardson",
                &format!("(4 w₃₂ − w₁₆)/3 (m), {name}"),
                reference,
                src,
                (4.0 * w[2] - w[1]) / 3.0,
                1e-3,
            ));
        }
        out.push(Check::info(
            "midedge-plate-hinges",
            &format!("hinge centre deflection (m), {name} {n}×{n} (information)"),
            plate_reference(p, MAT.plate_stiffness()),
            "Navier with E h³/12 (nominal; the hinges' D depends on the mesh)",
            plate_deflection(pattern, n, Law::Hinge, p)?,
        ));
    }
    Ok(out)
}

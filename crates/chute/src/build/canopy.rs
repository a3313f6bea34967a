//! Canopy geometry: a rod strip along x, or a shell mesh (generated or imported).
use super::BuildError;
use crate::mesh::generate::Pattern;
use crate::mesh::{self, constructed, CanopyMesh};
use crate::resolve::ModelSpec;
use crate::scenario::round;
use crate::scenario::{Bending, CanopyShape, Membrane, MeshPattern, ModelKind};
use engine::shell::{
    midedge, CstMembrane, FabricMembrane, MembraneError, Orthotropic, PlateBending, ShellMaterial,
    TriMesh,
};

/// The canopy before loads and lines are added.
pub struct Geometry {
    /// Positions of canopy nodes and of any rod nodes from an imported mesh (m).
    pub mesh: CanopyMesh,
    /// Shell topology (shell model).
    pub tri_mesh: Option<TriMesh>,
    /// Canopy node indices.
    pub canopy_nodes: Vec<usize>,
    /// Rod canopy: its node chain along the span.
    pub rod_chain: Option<Vec<usize>>,
    /// Rod chains from an imported mesh (suspension lines).
    pub mesh_lines: Vec<Vec<usize>>,
    /// Flat planform area of the canopy (m²).
    pub planform_area: f64,
    /// Largest canopy dimension (m), the Reynolds-number length.
    pub reference_length: f64,
    /// The digest of the mesh file's bytes that were parsed (an imported mesh).
    pub mesh_digest: Option<String>,
}

impl Geometry {
    /// Canopy triangles (empty for a rod canopy).
    pub fn triangles(&self) -> Vec<[usize; 3]> {
        self.tri_mesh
            .as_ref()
            .map(|t| t.faces.clone())
            .unwrap_or_default()
    }
}

/// The shell material of the canopy.
pub fn shell_material(s: &ModelSpec) -> ShellMaterial {
    ShellMaterial {
        youngs_modulus: s.material.youngs_modulus_pa,
        thickness: s.canopy.thickness_m,
        density: s.material.density_kg_m3,
    }
}

/// The plate bending constants of the scenario's canopy (mid-edge bending).
pub fn plate_bending(s: &ModelSpec) -> PlateBending {
    PlateBending {
        youngs_modulus: s.material.youngs_modulus_pa,
        poisson_ratio: s.material.poisson_ratio,
        thickness: s.canopy.thickness_m,
    }
}

/// Install the shell on `tri`: the scenario's membrane, its bending law and the lumped masses;
/// mid-edge angles take the per-edge DOFs from `first_twist` on.
pub fn install_shell(
    s: &ModelSpec,
    tri: &TriMesh,
    model: &mut engine::Model,
    q: &[f64],
    first_twist: usize,
) -> Result<Option<FabricMembrane>, BuildError> {
    let mat = shell_material(s);
    let wrinkles = install_membrane(s, tri, model, q)?;
    let parts = engine::shell::ShellParts::try_new(tri, &mat, model, q)?;
    parts.masses(model);
    match s.bending {
        Bending::Hinge => parts.hinges(model),
        Bending::Midedge => {
            midedge::install(tri, &plate_bending(s), mat.density, model, q, first_twist)?;
        }
    }
    Ok(wrinkles)
}

/// The fabric constants of the scenario (`shell.membrane = "fabric"`; validation has
/// checked that they are present and positive definite).
pub fn fabric(s: &ModelSpec) -> Result<Orthotropic, BuildError> {
    let m = &s.material;
    let keys = [
        (m.warp_modulus_pa, "material.warp_modulus_pa"),
        (m.weft_modulus_pa, "material.weft_modulus_pa"),
        (m.shear_modulus_pa, "material.shear_modulus_pa"),
        (m.fabric_poisson_ratio, "material.fabric_poisson_ratio"),
    ];
    s.fabric_law.ok_or_else(|| {
        let key = keys
            .iter()
            .find(|(v, _)| v.is_none())
            .map_or("", |(_, k)| k);
        BuildError::key(key, "required with shell.membrane = \"fabric\"")
    })
}

/// Add the scenario's membrane (`shell.membrane`) on `tri`: the report's edge springs,
/// constant-strain triangles, or the fabric law, under the name
/// [`engine::shell::STRETCH_NAME`]. Returns a copy of a fabric membrane that cannot carry
/// compression, for the frames' wrinkling fields ([`crate::build::Built::wrinkles`]).
pub fn install_membrane(
    s: &ModelSpec,
    tri: &TriMesh,
    model: &mut engine::Model,
    q: &[f64],
) -> Result<Option<FabricMembrane>, BuildError> {
    let name = engine::shell::STRETCH_NAME;
    let m = &s.material;
    match s.membrane {
        Membrane::Springs => {
            engine::shell::ShellParts::try_new(tri, &shell_material(s), model, q)?.springs(model)
        }
        Membrane::Cst => {
            let h = s.canopy.thickness_m;
            let (e, nu) = (m.youngs_modulus_pa, m.poisson_ratio);
            let f = CstMembrane::new(name, &tri.faces, q, e, nu, h)
                .map_err(|e| membrane_error(e, "shell.membrane"))?;
            model.add_force(f);
        }
        Membrane::Fabric => {
            let eps_r = s.wrinkle_strain;
            let f = FabricMembrane::new(name, &tri.faces, q, &fabric(s)?, s.warp, eps_r)
                .map_err(|e| membrane_error(e, "material.fabric_poisson_ratio"))?;
            let probe = eps_r.is_some().then(|| f.clone());
            model.add_force(f);
            return Ok(probe);
        }
    }
    Ok(None)
}

/// A membrane error as a build error naming the key the user changes: the warp direction
/// when it is normal to a triangle, the mesh for a degenerate triangle, else `law_key`.
fn membrane_error(e: MembraneError, law_key: &'static str) -> BuildError {
    match e {
        MembraneError::AxisNormalToFace { .. } => {
            BuildError::key("material.warp_direction_deg", e.to_string())
        }
        MembraneError::DegenerateFace { .. } => BuildError::key("canopy", e.to_string()),
        MembraneError::Material(_) => BuildError::key(law_key, e.to_string()),
    }
}

/// Build the canopy geometry of `s`.
pub fn geometry(s: &ModelSpec) -> Result<Geometry, BuildError> {
    let c = &s.canopy;
    if s.kind == ModelKind::Rod {
        let n = c.nodes;
        let h = c.span_m / (n - 1) as f64;
        let positions = (0..n)
            .map(|i| [-0.5 * c.span_m + i as f64 * h, 0.0, 0.0])
            .collect();
        let mesh = CanopyMesh {
            positions,
            ..Default::default()
        };
        return Ok(Geometry {
            mesh,
            tri_mesh: None,
            canopy_nodes: (0..n).collect(),
            rod_chain: Some((0..n).collect()),
            mesh_lines: Vec::new(),
            planform_area: c.span_m * c.width_m,
            reference_length: c.span_m,
            mesh_digest: None,
        });
    }
    let mut mesh_digest = None;
    let mut nominal = None;
    let mesh = match c.shape {
        CanopyShape::Rectangle => mesh::generate::rectangle_pattern(
            c.span_m,
            c.width_m,
            c.edge_length_m,
            pattern(c.mesh_pattern),
        ),
        CanopyShape::Hexagon => mesh::generate::hexagon(c.radius_m, c.edge_length_m),
        CanopyShape::Circle => {
            let (mesh, area) = round_canopy(s)?;
            nominal = Some(area);
            mesh
        }
        CanopyShape::Mesh => {
            let path = c.mesh_file.as_ref().ok_or_else(|| {
                BuildError::key("canopy.mesh_file", "required when shape = \"mesh\"")
            })?;
            let (mesh, digest) = mesh::read_file_digested(path).map_err(BuildError::from)?;
            mesh_digest = Some(digest);
            mesh
        }
    };
    if mesh.faces.is_empty() {
        return Err(BuildError::key(
            "canopy.mesh_file",
            "the mesh has no triangles",
        ));
    }
    let tri = mesh.tri_mesh()?;
    let canopy_nodes = mesh.shell_nodes();
    let mesh_lines = mesh.rod_chains();
    let (lo, hi) = extent(&mesh, &canopy_nodes);
    let reference_length = (hi[0] - lo[0]).max(hi[1] - lo[1]);
    Ok(Geometry {
        planform_area: nominal.unwrap_or(tri.area()),
        tri_mesh: Some(tri),
        canopy_nodes,
        rod_chain: None,
        mesh_lines,
        reference_length,
        mesh,
        mesh_digest,
    })
}

/// The round canopy of `s` (vent and profile) and its nominal area `S₀` (m²): the
/// constructed surface's, vent included (Knacke's reference area).
fn round_canopy(s: &ModelSpec) -> Result<(CanopyMesh, f64), BuildError> {
    let c = &s.canopy;
    let sites = s.rim_sites;
    let disc = mesh::generate::circle_with_rim_sites(c.radius_m, c.edge_length_m, sites);
    let rings = mesh::generate::circle_rings(c.radius_m, c.edge_length_m, sites);
    let profile = s.profile;
    // The vent is cut in the disc, whose radius is the distance along a gore.
    let area = constructed::shaped(disc.clone(), profile, c.radius_m)
        .tri_mesh()?
        .area();
    let disc = match round::vent_cut(c, rings) {
        Some(cut) => constructed::with_vent(disc, cut),
        None => disc,
    };
    Ok((constructed::shaped(disc, profile, c.radius_m), area))
}

/// The generator's pattern for `canopy.mesh_pattern` (absent: the report's union-jack).
fn pattern(p: Option<MeshPattern>) -> Pattern {
    match p.unwrap_or(MeshPattern::UnionJack) {
        MeshPattern::UnionJack => Pattern::UnionJack,
        MeshPattern::Cross => Pattern::Cross,
        MeshPattern::Unstructured => Pattern::Unstructured,
    }
}

/// Bounding box of `nodes`.
pub fn extent(mesh: &CanopyMesh, nodes: &[usize]) -> ([f64; 3], [f64; 3]) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for &i in nodes {
        for k in 0..3 {
            lo[k] = lo[k].min(mesh.positions[i][k]);
            hi[k] = hi[k].max(mesh.positions[i][k]);
        }
    }
    (lo, hi)
}

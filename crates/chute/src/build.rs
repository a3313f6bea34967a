//! Builders: turn a [`ModelSpec`] (a validated [`Scenario`], resolved) into an engine model
//! plus the bookkeeping the observers need (which nodes are canopy, where the payload is,
//! which forces are drag).

/// An engine model ready to run, with what observers and outputs need to know about it.
pub struct Built {
    /// The engine model (masses, fixed DOFs, forces).
    pub model: engine::Model,
    /// Initial state (at rest, flat canopy).
    pub state: engine::State,
    /// Canopy node indices (metrics are mass-weighted over these).
    pub canopy_nodes: Vec<usize>,
    /// The payload node, when the load hangs on lines.
    pub payload_node: Option<usize>,
    /// Load sites: the canopy nodes that carry the load (forces, masses or line attachments).
    pub load_sites: Vec<usize>,
    /// Canopy triangles (shell models; empty for rods).
    pub triangles: Vec<[usize; 3]>,
    /// Line segments drawn and written to VTK (rod canopy edges, suspension lines).
    pub segments: Vec<[usize; 2]>,
    /// The drag families.
    pub drag_forces: Vec<engine::ForceId>,
    /// The triangle drag family (per-triangle output).
    pub triangle_drag: Option<engine::ForceId>,
    /// A copy of the canopy's membrane when it cannot carry compression (fabric with
    /// `material.no_compression`), evaluated for the frames' wrinkling fields.
    pub wrinkle_probe: Option<engine::shell::FabricMembrane>,
    /// Total weight of everything that falls (N).
    pub total_weight_n: f64,
    /// Weight of the canopy alone (N).
    pub canopy_weight_n: f64,
    /// Σ C_D A of the flat canopy facing the flow (m²): flat terminal velocity reference.
    pub flat_drag_area_m2: f64,
    /// Flat (planform) area of the canopy S₀ (m²).
    pub planform_area_m2: f64,
    /// Horizontal position of the canopy's centre at t = 0 (m; `canopy.release_point_m`).
    pub release_point_m: [f64; 2],
    /// A packed start (`[opening]`): the airspeed at line stretch (m/s); `None` when flat.
    pub opening_speed_mps: Option<f64>,
    /// The surface that self-contact guards (`[contact]`): the canopy's triangles and the
    /// lines; `None` without contact.
    pub contact: Option<engine::contact::broad::Surface>,
    /// Reference length for the Reynolds number (m): the canopy's largest dimension.
    pub reference_length_m: f64,
    /// Derived quantities for `chute check` (name, value with units).
    pub derived: Vec<(String, String)>,
    /// Rod twist DOFs; the edge angles of mid-edge bending follow them.
    pub rod_twists: usize,
    /// The suspension lines of the payload mode (empty otherwise) and their schedules.
    pub lines: Option<control::Lines>,
    /// The digest of each input file as it was parsed, by scenario key (what a run records:
    /// the file may have changed since it was read).
    pub input_digests: Vec<(&'static str, String)>,
}

mod canopy;
pub mod contact;
pub mod control;
pub mod drag;
pub mod imperfection;
mod load;
pub mod packing;
mod sites;

use crate::resolve::ModelSpec;
use crate::scenario::derived::sig4;
use crate::scenario::{Bending, ModelKind, Scenario};
use engine::loads::Gravity;
use engine::{DofLayout, Model, State};

pub use canopy::Geometry;

/// Why a scenario could not be turned into a model. Messages name the scenario key.
#[derive(Debug, thiserror::Error)]
pub enum BuildError {
    /// A scenario value that only the builder can reject (e.g. lines too short).
    #[error("{key}: {message}")]
    Key {
        /// The scenario key, e.g. `lines.length_m` or `control[1].lines`.
        key: std::borrow::Cow<'static, str>,
        /// What is wrong.
        message: String,
    },
    /// A mesh file could not be read.
    #[error("canopy.mesh_file: {0}")]
    MeshFile(#[from] crate::mesh::MeshFileError),
    /// The mesh is not a valid shell.
    #[error("canopy mesh: {0}")]
    Mesh(#[from] engine::shell::MeshError),
    /// The engine rejected the model.
    #[error("model: {0}")]
    Engine(#[from] engine::EngineError),
}

impl BuildError {
    pub(crate) fn key(
        key: impl Into<std::borrow::Cow<'static, str>>,
        message: impl Into<String>,
    ) -> Self {
        Self::Key {
            key: key.into(),
            message: message.into(),
        }
    }
}

/// Build the model of scenario `s` ([`model`] of its [`ModelSpec`]), with the quantities that
/// `chute check` prints.
pub fn build(s: &Scenario) -> Result<Built, BuildError> {
    let spec = ModelSpec::of(s);
    let mut built = model(&spec)?;
    built.derived = derived(s, &spec, &built);
    if let Some(w) = &s.loaded.wind {
        let key = crate::scenario::wind::WIND_FILE_KEY;
        built.input_digests.push((key, w.digest.clone()));
    }
    Ok(built)
}

/// Build the model of `s`: canopy (rod or shell), load (forces, masses or payload on lines),
/// gravity and drag. The canopy starts flat, at rest, in the plane z = 0.
pub fn model(s: &ModelSpec) -> Result<Built, BuildError> {
    let geo = canopy::geometry(s)?;
    let sites = sites::resolve(s, &geo)?;
    let mut plan = load::plan(s, &geo, &sites)?;
    // Per-edge DOFs: the rods' twists, then (mid-edge bending) one normal angle per shell edge.
    let midedge = s.bending == Bending::Midedge;
    let shell_edges = match &geo.tri_mesh {
        Some(tri) if midedge => tri.edges.len(),
        _ => 0,
    };
    let layout = DofLayout::new(plan.positions.len(), plan.rods.n_edges() + shell_edges);
    let mut model = Model::new(layout);
    let mut q: Vec<f64> = plan.positions.iter().flatten().copied().collect();
    q.resize(layout.len(), 0.0);
    // A packed start: the lines (straight, at full length) are built where they start; the
    // cloth's rest shape stays the flat disc.
    let mut start_digest = None;
    let q_start = match &s.pack {
        Some(pack) => {
            let mut p = q.clone();
            let lines: Vec<Vec<usize>> = (plan.payload_lines.iter())
                .map(|&k| plan.rods.rods()[plan.line_rods[k]].nodes.clone())
                .collect();
            let start = start_mesh(s, &geo)?;
            let nodes = (&geo.canopy_nodes[..], &plan.sites[..]);
            packing::apply(
                &mut p,
                pack,
                nodes,
                &lines,
                start.as_ref().map(|m| &m.0[..]),
            );
            if let Some((_, digest)) = start {
                start_digest = Some(digest);
            }
            p
        }
        None => q.clone(),
    };
    let handles = plan.rods.install(&mut model, &q_start, 0)?;
    let wrinkle_probe = match &geo.tri_mesh {
        Some(tri) => canopy::install_shell(s, tri, &mut model, &q, plan.rods.n_edges())?,
        None => None,
    };
    plan.add_masses_and_loads(s, &mut model);
    check_masses(s, &model)?;
    let g = s.gravity_mps2;
    let nodes: Vec<usize> = (0..layout.n_nodes).collect();
    let masses: Vec<f64> = nodes.iter().map(|&i| model.node_mass(i)).collect();
    let gravity = Gravity::new(&nodes, &masses, [0.0, 0.0, -g]);
    let total_weight_n = -gravity.total()[2] + plan.applied_force_n;
    model.add_force(gravity);
    let canopy_weight_n = geo
        .canopy_nodes
        .iter()
        .map(|&i| model.node_mass(i))
        .sum::<f64>()
        * g
        - plan.site_mass_kg * g;
    let drag = drag::install(s, &geo, &plan, &handles, &mut model);
    let lines = plan.lines(s, &handles);
    let mut q = q_start;
    if s.canopy.imperfection_m != 0.0 {
        imperfection::apply(&mut q, &geo.canopy_nodes, s.canopy.imperfection_m)?;
    }
    // Every model term is invariant under a horizontal shift (the air varies with height
    // only), so the release point moves the flight and nothing else.
    for node in q[..3 * layout.n_nodes].chunks_exact_mut(3) {
        node[0] += s.release_point[0];
        node[1] += s.release_point[1];
    }
    let segments = plan.segments(&geo);
    let contact = match &s.contact {
        Some((distance, c)) => Some(contact::install(
            &mut model,
            &q,
            (&geo.triangles(), &segments),
            &geo.canopy_nodes,
            (*distance, c.stop_speed_mps),
        )?),
        None => None,
    };
    Ok(Built {
        state: initial_state(q, layout.n_nodes, s.initial_velocity),
        canopy_nodes: geo.canopy_nodes.clone(),
        payload_node: plan.payload_node,
        load_sites: plan.sites.clone(),
        triangles: geo.triangles(),
        segments,
        rod_twists: plan.rods.n_edges(),
        drag_forces: drag.forces,
        triangle_drag: drag.triangle,
        wrinkle_probe,
        total_weight_n,
        canopy_weight_n,
        flat_drag_area_m2: drag.flat_cd_area,
        planform_area_m2: geo.planform_area,
        release_point_m: s.release_point,
        contact,
        opening_speed_mps: s.pack.as_ref().map(|_| {
            let w = s.air.wind_at(0.0).velocity;
            let v = s.initial_velocity;
            (0..3).map(|k| (v[k] - w[k]).powi(2)).sum::<f64>().sqrt()
        }),
        reference_length_m: geo.reference_length,
        derived: Vec::new(),
        lines,
        model,
        input_digests: (geo.mesh_digest.iter())
            .map(|d| (crate::scenario::MESH_FILE_KEY, d.clone()))
            .chain(start_digest.map(|d| (crate::scenario::START_MESH_FILE_KEY, d)))
            .collect(),
    })
}

/// A folded canopy's node positions (m) and the digest of the bytes read.
type StartMesh = (Vec<[f64; 3]>, String);

/// The folded canopy of `[opening] pack = "mesh"` (its positions and the digest of the bytes
/// read), checked to be the canopy mesh's nodes and triangles; `None` for another packing.
fn start_mesh(s: &ModelSpec, geo: &Geometry) -> Result<Option<StartMesh>, BuildError> {
    let Some(path) = s.pack.as_ref().and_then(|p| p.mesh_file.as_ref()) else {
        return Ok(None);
    };
    let key = crate::scenario::START_MESH_FILE_KEY;
    let (mesh, digest) =
        crate::mesh::read_file_digested(path).map_err(|e| BuildError::key(key, e.to_string()))?;
    let (n, faces) = (geo.canopy_nodes.len(), geo.triangles());
    if mesh.positions.len() != n || mesh.faces != faces {
        return Err(BuildError::key(
            key,
            format!(
                "{}: {} nodes and {} triangles, not the canopy mesh's {n} nodes and {} triangles in its order",
                path.display(),
                mesh.positions.len(),
                mesh.faces.len(),
                faces.len()
            ),
        ));
    }
    Ok(Some((mesh.positions, digest)))
}

/// The state at t = 0: positions `q`, every one of the `n_nodes` nodes at `velocity` (m/s),
/// twists and edge angles at rest.
fn initial_state(q: Vec<f64>, n_nodes: usize, velocity: [f64; 3]) -> State {
    let mut state = State::at_rest(q);
    for v in state.v[..3 * n_nodes].chunks_exact_mut(3) {
        v.copy_from_slice(&velocity);
    }
    state
}

impl Built {
    /// The wrinkling cell data of the canopy's triangles at positions `q`, when its membrane
    /// cannot carry compression ([`Built::wrinkle_probe`]); `None` otherwise.
    pub fn wrinkles(&self, q: &[f64]) -> Option<crate::output::vtk::Wrinkles> {
        let probe = self.wrinkle_probe.as_ref()?;
        let (strain, state) = (0..probe.len())
            .map(|i| {
                let w = probe
                    .wrinkling(q, i)
                    .expect("the probe has a tension field");
                (w.principal[0].max(0.0), w.slack_directions)
            })
            .unzip();
        Some(crate::output::vtk::Wrinkles { strain, state })
    }
}

/// Every free DOF must have mass before anything runs (the stepper would refuse the model
/// only after the output directory is written); a massless node is blamed on the mesh file.
fn check_masses(s: &ModelSpec, model: &Model) -> Result<(), BuildError> {
    let Err(engine::EngineError::NonPositiveMass { dof, mass }) = model.validate(true) else {
        return model.validate(false).map_err(BuildError::from);
    };
    let n = model.layout.n_nodes;
    let what = if dof < 3 * n {
        format!("node {} (1-based)", dof / 3 + 1)
    } else {
        format!("the twist of rod edge {}", dof - 3 * n)
    };
    let message = format!("{what} has mass {mass} kg: it is on no triangle, rod edge or load");
    Err(match &s.canopy.mesh_file {
        Some(p) => BuildError::MeshFile(crate::mesh::MeshFileError::File {
            path: p.display().to_string(),
            message,
        }),
        None => BuildError::key("canopy", message),
    })
}

/// Quantities printed by `chute check`.
fn derived(s: &Scenario, spec: &ModelSpec, b: &Built) -> Vec<(String, String)> {
    // The air where the canopy starts (z = 0).
    let air = spec.air.at(0.0);
    let rho = air.density;
    let v_flat = (2.0 * b.total_weight_n / (rho * b.flat_drag_area_m2)).sqrt();
    let re = rho * v_flat * b.reference_length_m / air.viscosity;
    let fixed = b.model.fixed.iter().filter(|&&f| f).count();
    let mut d = vec![
        ("model".into(), format!("{:?}", s.model.kind).to_lowercase()),
        ("nodes".into(), b.model.layout.n_nodes.to_string()),
        (
            "DOFs".into(),
            format!("{} ({} fixed)", b.model.n_dofs(), fixed),
        ),
        ("canopy nodes".into(), b.canopy_nodes.len().to_string()),
        (
            "planform area".into(),
            format!("{} m²", sig4(b.planform_area_m2)),
        ),
        (
            "canopy weight".into(),
            format!("{} N", sig4(b.canopy_weight_n)),
        ),
        (
            "total weight".into(),
            format!("{} N", sig4(b.total_weight_n)),
        ),
        (
            "flat-canopy C_D·A".into(),
            format!("{} m²", sig4(b.flat_drag_area_m2)),
        ),
        (
            "flat-canopy terminal speed √(2W/(ρ C_D A))".into(),
            format!("{} m/s", sig4(v_flat)),
        ),
        (
            "Reynolds number at that speed".into(),
            format!("{} (L = {} m)", sig4(re), sig4(b.reference_length_m)),
        ),
    ];
    if s.model.kind == ModelKind::Rod {
        let (w, h, e) = (
            s.canopy.width_m,
            s.canopy.thickness_m,
            s.material.youngs_modulus_pa,
        );
        d.push((
            "strip bending stiffness EI = E w h³/12".into(),
            format!("{} N·m²", sig4(e * w * h.powi(3) / 12.0)),
        ));
        d.push((
            "strip axial stiffness EA".into(),
            format!("{} N", sig4(e * w * h)),
        ));
    } else {
        let m = canopy::shell_material(spec);
        if s.shell.bending == Some(Bending::Midedge) {
            d.push((
                "plate stiffness D = E h³/(12(1 − ν²))".into(),
                format!("{} N·m", sig4(canopy::plate_bending(spec).stiffness())),
            ));
        } else {
            d.push((
                "hinge plate stiffness D = E h³/12".into(),
                format!("{} N·m", sig4(m.plate_stiffness())),
            ));
        }
        d.push((
            "membrane stiffness E h".into(),
            format!(
                "{} N/m",
                sig4(s.material.youngs_modulus_pa * s.canopy.thickness_m)
            ),
        ));
    }
    d.extend(control::describe(s));
    d
}

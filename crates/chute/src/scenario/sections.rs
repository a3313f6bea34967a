//! Every scenario key, declared once: name, type, default, unit, range, conditions and doc
//! line. The serde structs, the schema, the per-key checks and the key tables of
//! `docs/scenarios.md` all come from here (see [`super::keys`]; adding a key:
//! docs/architecture.md §How a scenario key flows). Rules between keys that are more than a
//! condition are written by hand in [`super::validate`]; the `note` of a key documents them.

use std::path::PathBuf;

use super::keys::{choice, key, section, when, Bound, Cond, KeyType, Kind, Section};

mod control;
mod drag;
pub use control::{Control, Guidance, PullSide, Sensor, SensorKind};
pub use drag::{InflationSpeed, ShellDrag};
mod opening;
pub use opening::{Contact, Opening, Packing, DISTANCE_PER_EDGE, PACKED_RADIUS_PER_RADIUS};
mod time;
pub use time::{ErrorNorm, Time, DEFAULT_ERROR_TOLERANCE_M};
mod wind;
pub use wind::{Wind, WindLaw};

/// `[model]`, `[canopy]`, …: every section, in file (and resolved-TOML) order.
pub const SECTIONS: &[Section] = &[
    Section::table::<TopLevel>(""),
    Section::table::<ModelSection>("model"),
    Section::table::<Canopy>("canopy"),
    Section::table::<Material>("material"),
    Section::table::<Shell>("shell"),
    Section::table::<Load>("load"),
    Section::table::<Lines>("lines"),
    Section::table::<Fluid>("fluid"),
    Section::table::<Atmosphere>("atmosphere"),
    Section::optional::<Wind>("wind"),
    Section::optional::<Contact>("contact").only_with(SHELL, SHELL_CONTACT),
    Section::optional::<Opening>("opening").only_with(PAYLOAD, OPENING_ONLY),
    Section::table::<Time>("time"),
    Section::table::<Output>("output"),
    Section::array::<Sensor>("sensor").only_with(PAYLOAD, LINES_ONLY),
    Section::array::<Control>("control").only_with(PAYLOAD, LINES_ONLY),
    Section::optional::<Guidance>("guidance").only_with(PAYLOAD, LINES_ONLY),
];

const NODE_MASS_SCALE: Cond = when("load.mode", "node_mass_scale");
const MESH: Cond = when("canopy.shape", "mesh");
const SHELL: Cond = when("model.kind", "shell");
const INCIDENCE: Cond = when("fluid.shell_drag", "incidence");
/// The condition of the fabric keys.
const FABRIC: Cond = when("shell.membrane", "fabric");
/// The rest of their "only used with" message.
const FABRIC_ONLY: &str =
    " (the other membranes are isotropic: `youngs_modulus_pa`, `poisson_ratio`)";
const ISA: Cond = when("atmosphere.model", "isa1976");
/// The condition of line pulls: suspension lines exist only in payload mode.
const PAYLOAD: Cond = when("load.mode", "payload");
/// Why.
const LINES_ONLY: &str = " (a pull shortens suspension lines, which only the payload mode has)";
/// Why contact needs a shell canopy.
const SHELL_CONTACT: &str = " (contact acts between the cloth's triangles and the lines)";
/// Why an opening needs the payload mode.
const OPENING_ONLY: &str = " (a packed canopy opens on its lines, which only the payload mode has)";
/// Why a permeability needs a shell canopy.
const SHELL_ONLY: &str =
    " (leakage acts through the fabric's normal, which a rod strip does not have)";

section! {
    /// The top-level keys (held by [`super::Scenario`] itself).
    pub struct TopLevel {
        /// run name; default output directory `runs/<name>`
        name: String = String::new() => key()
            .default_doc("file stem")
            .note("1–100 of `A–Z a–z 0–9 - _ .`, not starting with `.`"),
    }
}

choice! {
    /// Structural model of the canopy.
    pub enum ModelKind {
        /// Discrete elastic rod along the span (report §II.A–B).
        Rod = "rod",
        /// Discrete shell (report §II.C–D).
        Shell = "shell",
    }
}

section! {
    /// `[model]`.
    pub struct ModelSection {
        /// structural model: a discrete elastic rod along the span, or a discrete shell
        kind: ModelKind = ModelKind::Rod => key().required(
            "say which structural model to use: `[model] kind = \"rod\"` or \"shell\""
        ),
    }
}

choice! {
    /// Canopy outline.
    pub enum CanopyShape {
        /// `span_m × width_m`.
        Rectangle = "rectangle",
        /// Regular hexagon of circumradius `radius_m`.
        Hexagon = "hexagon",
        /// Disc of radius `radius_m`.
        Circle = "circle",
        /// Imported from `mesh_file`.
        Mesh = "mesh",
    }
}

choice! {
    /// How the generated rectangle is triangulated.
    pub enum MeshPattern {
        /// Cells split by one diagonal each, alternating like a union-jack (the report's).
        UnionJack = "union_jack",
        /// Cells split into four triangles through a node at the cell centre.
        Cross = "cross",
        /// Irregular Delaunay mesh refined to angles ≥ 25° (seeded: always the same mesh).
        Unstructured = "unstructured",
    }
}

section! {
    /// `[canopy]`: geometry.
    pub struct Canopy {
        /// outline
        shape: CanopyShape = CanopyShape::Rectangle => key().note("a rod must be `rectangle`"),
        /// length along x; for a rod, the rod length
        span_m: f64 = 6.0 => key().unit("m").positive("a length"),
        /// width along y; for a rod, the strip width (drag radius width/2, cross-section width)
        width_m: f64 = 3.0 => key().unit("m").positive("a length"),
        /// sheet thickness (rod cross-section height)
        thickness_m: f64 = 0.002 => key().unit("m").positive("a length").note(
            "≤ 1/10 of the in-plane size (thin-structure models; catches mm/m mix-ups)"
        ),
        /// rod: nodes along the span
        nodes: usize = 61 => key()
            .between(3.0, 100_000.0, "a rod needs 3 nodes to bend")
            .range_when(when("model.kind", "rod")),
        /// shell: target edge length of the generated mesh
        edge_length_m: f64 = 0.25 => key()
            .unit("m")
            .positive("a length")
            .note("≤ half the in-plane size, ≤ 4·10⁵ triangles"),
        /// `shape = "mesh"`: DisMech `.txt` or Wavefront `.obj`; relative paths resolve
        /// against the scenario file's directory (stored absolute)
        #[serde(skip_serializing_if = "Option::is_none")]
        mesh_file: Option<PathBuf> = None => key()
            .only_with(MESH, "")
            .required_with(MESH, "reads the canopy from a mesh file (.txt DisMech or .obj)")
            .note("must exist"),
        /// hexagon circumradius or circle radius
        radius_m: f64 = 1.0 => key().unit("m").positive("a length"),
        /// `shape = "rectangle"` shell: triangulation of the generated mesh (below)
        #[serde(skip_serializing_if = "Option::is_none")]
        mesh_pattern: Option<MeshPattern> = None => key()
            .only_with(when("canopy.shape", "rectangle"), "")
            .default_doc("`union_jack`"),
        /// circle: radius of the apex vent, its hem the mesh ring nearest it (at least the
        /// first); 0 for none, not written to the resolved scenario
        #[serde(skip_serializing_if = "is_zero")]
        vent_radius_m: f64 = 0.0 => key()
            .unit("m")
            .default_doc("0 (no vent)")
            .non_negative("a radius")
            .only_with(when("canopy.shape", "circle"), "")
            .note("≤ `radius_m` − `edge_length_m` (one ring of cloth)"),
        /// circle: the gores' shape, each gore `radius_m` long from apex to skirt: `flat`,
        /// `conical` (at `cone_angle_deg` to the skirt's plane) or `hemispherical`
        #[serde(skip_serializing_if = "Option::is_none")]
        profile: Option<CanopyProfile> = None => key()
            .only_with(when("canopy.shape", "circle"), "")
            .default_doc("`flat`"),
        /// `profile = "conical"`: the cloth's angle to the skirt's plane
        #[serde(skip_serializing_if = "Option::is_none")]
        cone_angle_deg: Option<f64> = None => key()
            .unit("deg")
            .only_with(when("canopy.profile", "conical"), "")
            .required_with(when("canopy.profile", "conical"), "needs the cloth's angle to the skirt's plane (deg)")
            .range(Bound::Excl(0.0), Bound::Excl(90.0), "a cone between a disc and a cylinder"),
        /// shell: amplitude of the initial out-of-plane perturbation in a fixed asymmetric
        /// mode (below); 0 is the flat start and is not written to the resolved scenario
        #[serde(skip_serializing_if = "is_zero")]
        imperfection_m: f64 = 0.0 => key()
            .unit("m")
            .default_doc("0 (flat)")
            .note("shell only; magnitude ≤ 5 % of the in-plane size"),
        /// velocity of every node (canopy, lines, payload) at t = 0, e.g. the wind at the
        /// release height for a canopy released from a carrier drifting with the air
        #[serde(skip_serializing_if = "Option::is_none")]
        initial_velocity_mps: Option<[f64; 3]> = None => key()
            .unit("m/s")
            .default_doc("at rest"),
        /// every node starts with the wind at the canopy's height (a canopy released from a
        /// carrier drifting with the air), however the wind is drawn or profiled
        #[serde(skip_serializing_if = "is_false")]
        released_with_wind: bool = false => key()
            .note("not with `initial_velocity_mps`"),
        /// horizontal position `[x, y]` of the canopy's centre at t = 0; landing points are
        /// measured from the same origin, so a dispersion can draw the release point
        #[serde(skip_serializing_if = "Option::is_none")]
        release_point_m: Option<[f64; 2]> = None => key()
            .unit("m")
            .default_doc("`[0, 0]`"),
    }
}

choice! {
    /// The shape of a round canopy's gores (`canopy.shape = "circle"`).
    pub enum CanopyProfile {
        /// A flat disc (flat circular).
        Flat = "flat",
        /// A cone, its cloth at `cone_angle_deg` to the skirt's plane.
        Conical = "conical",
        /// A hemisphere.
        Hemispherical = "hemispherical",
    }
}

/// An unset switch is left out of the resolved scenario (it stays as before the key existed).
fn is_false(b: &bool) -> bool {
    !*b
}

/// A zero amplitude is left out of the resolved scenario (it stays as before the key existed).
fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

section! {
    /// `[material]` of the canopy.
    pub struct Material {
        /// Young's modulus E
        youngs_modulus_pa: f64 = 55e9 => key()
            .unit("Pa")
            .positive("a stiffness")
            .default_note("Kevlar"),
        /// Poisson's ratio ν
        poisson_ratio: f64 = 0.36 => key().range(
            Bound::Excl(-1.0),
            Bound::Incl(0.5),
            "a stable isotropic material"
        ),
        /// density ρ (areal density ρ·h)
        density_kg_m3: f64 = 1440.0 => key().unit("kg/m³").positive("the canopy needs mass"),
        /// fabric: Young's modulus E₁ along the warp
        #[serde(skip_serializing_if = "Option::is_none")]
        warp_modulus_pa: Option<f64> = None => key()
            .unit("Pa")
            .positive("a stiffness")
            .only_with(FABRIC, FABRIC_ONLY)
            .required_with(FABRIC, "needs the warp modulus E₁ (Pa)"),
        /// fabric: Young's modulus E₂ along the weft
        #[serde(skip_serializing_if = "Option::is_none")]
        weft_modulus_pa: Option<f64> = None => key()
            .unit("Pa")
            .positive("a stiffness")
            .only_with(FABRIC, FABRIC_ONLY)
            .required_with(FABRIC, "needs the weft modulus E₂ (Pa)"),
        /// fabric: in-plane shear modulus G₁₂
        #[serde(skip_serializing_if = "Option::is_none")]
        shear_modulus_pa: Option<f64> = None => key()
            .unit("Pa")
            .positive("a stiffness")
            .only_with(FABRIC, FABRIC_ONLY)
            .required_with(FABRIC, "needs the in-plane shear modulus G₁₂ (Pa)"),
        /// fabric: Poisson ratio ν₁₂, the weft contraction under warp stress
        #[serde(skip_serializing_if = "Option::is_none")]
        fabric_poisson_ratio: Option<f64> = None => key()
            .only_with(FABRIC, FABRIC_ONLY)
            .required_with(FABRIC, "needs the Poisson ratio ν₁₂ (weft contraction under warp stress)")
            .note("ν₁₂² < `warp_modulus_pa`/`weft_modulus_pa` (a positive-definite law)"),
        /// fabric: warp direction in the canopy's rest plane, from +x towards +y
        #[serde(skip_serializing_if = "Option::is_none")]
        warp_direction_deg: Option<f64> = None => key()
            .unit("°")
            .range(Bound::Incl(-360.0), Bound::Incl(360.0), "an angle in degrees")
            .only_with(FABRIC, FABRIC_ONLY)
            .default_doc("0 (along +x)"),
        /// fabric: carry no compression (a wrinkling, tension-field membrane)
        #[serde(skip_serializing_if = "Option::is_none")]
        no_compression: Option<bool> = None => key()
            .only_with(FABRIC, FABRIC_ONLY)
            .default_doc("false"),
        /// `no_compression`: regularisation strain ε_r; the relaxed law is smooth over strains
        /// ~ε_r and carries a tension ~ε_r·E·h at zero strain
        #[serde(skip_serializing_if = "Option::is_none")]
        wrinkle_strain: Option<f64> = None => key()
            .range(Bound::Excl(0.0), Bound::Incl(0.01), "a small strain")
            .only_with(
                when("material.no_compression", "true"),
                " (it regularises the no-compression law)"
            )
            .default_doc("1e-5")
            .note("refused when its strain error ε_r²·k/(weight/perimeter) exceeds 0.1, warned of above 1e-3 (see below)"),
        /// Darcy permeability k of the fabric: air leaks through it, Δp = h (μ u_p/k + ρ C_F
        /// u_p²/√k) over the thickness h = `canopy.thickness_m` (docs/engineering.md)
        #[serde(skip_serializing_if = "Option::is_none")]
        permeability_m2: Option<f64> = None => key()
            .unit("m²")
            .positive("a permeability; leave the key out for an impermeable fabric")
            .only_with(SHELL, SHELL_ONLY)
            .default_doc("absent: impermeable")
            .note("not with `air_permeability_cfm`, nor with `fluid.drag = \"linear\"`"),
        /// the fabric's air permeability as data sheets give it (ASTM D737: ft³/min through 1
        /// ft² at 124.5 Pa), converted to `permeability_m2` with the Darcy term alone
        #[serde(skip_serializing_if = "Option::is_none")]
        air_permeability_cfm: Option<f64> = None => key()
            .unit("ft³/(ft²·min)")
            .positive("an air flow; leave the key out for an impermeable fabric")
            .only_with(SHELL, SHELL_ONLY)
            .default_doc("absent: impermeable")
            .note("not with `permeability_m2`, nor with `fluid.drag = \"linear\"`"),
        /// Forchheimer (inertial) coefficient C_F of the fabric's pressure drop
        #[serde(skip_serializing_if = "Option::is_none")]
        forchheimer_coefficient: Option<f64> = None => key()
            .non_negative("the inertial pressure drop opposes the leakage")
            .default_doc("0")
            .note("only with `permeability_m2` or `air_permeability_cfm`"),
    }
}

choice! {
    /// In-plane (membrane) law of a shell canopy.
    pub enum Membrane {
        /// Edge springs, k_s = (√3/2) E h |ē| (the report's; ν fixed by the mesh).
        Springs = "springs",
        /// Constant-strain triangles: isotropic St Venant–Kirchhoff with E and ν.
        Cst = "cst",
        /// Constant-strain triangles with an orthotropic (warp/weft) fabric law.
        Fabric = "fabric",
    }
}

section! {
    /// `[shell]`: the discrete shell's laws (shell canopies only).
    pub struct Shell {
        /// membrane law: `springs` (the report's), `cst` (E and ν on any mesh) or `fabric`
        /// (orthotropic, optionally no compression; below)
        #[serde(skip_serializing_if = "Option::is_none")]
        membrane: Option<Membrane> = None => key()
            .only_with(SHELL, " (a rod canopy stretches as a rod)")
            .default_doc("`springs`"),
        /// bending law: `hinge` (the report's) or `midedge` (converges on any mesh; below)
        #[serde(skip_serializing_if = "Option::is_none")]
        bending: Option<Bending> = None => key()
            .only_with(SHELL, " (a rod canopy bends as a rod)")
            .default_doc("`hinge`"),
    }
}

choice! {
    /// Bending law of a shell canopy.
    pub enum Bending {
        /// Dihedral-angle hinges, ½ k_b (θ − θ̄)² (the report's).
        Hinge = "hinge",
        /// Mid-edge normals: a discrete shape operator per triangle with one normal angle per
        /// edge as an extra DOF; Kirchhoff plate bending with the material's ν.
        Midedge = "midedge",
    }
}

choice! {
    /// How the load is applied.
    pub enum LoadMode {
        /// Constant downward forces W/n at the n sites (the report's model).
        Force = "force",
        /// A payload node of mass W/g hanging on suspension lines from the sites.
        Payload = "payload",
        /// Point masses W/(g n) added at the n sites.
        Mass = "mass",
        /// Mesh input: mesh node `node` (1-based) gets its lumped mass and weight ×
        /// `mass_scale` (the DisMech hexagonal-parachute convention); `weight_n` and `sites`
        /// are unused.
        NodeMassScale = "node_mass_scale",
    }
}

choice! {
    /// Named load-site sets.
    pub enum SiteSet {
        /// Rod: its two end nodes.
        Ends = "ends",
        /// Rectangle: the 4 corners; hexagon: the 6 corners.
        Corners = "corners",
        /// Rectangle: the 4 corners and the 2 mid-points of the long (span) edges.
        CornersAndMidspan = "corners_and_midspan",
        /// The node nearest the origin.
        Center = "center",
        /// Circle: `rim_site_count` equally spaced rim points, the first on +x.
        Rim = "rim",
    }
}

/// Load sites: a named set, or explicit `[x, y]` points (m) resolved by the builder to the
/// nearest canopy node.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(untagged)]
pub enum Sites {
    /// A named set.
    Named(SiteSet),
    /// Explicit points in the canopy plane (m).
    Points(Vec<[f64; 2]>),
}

impl KeyType for Sites {
    const KIND: Kind = Kind::Sites;
}

section! {
    /// `[load]`.
    pub struct Load {
        /// total load W
        weight_n: f64 = 200.0 => key()
            .unit("N")
            .positive("the load must pull the canopy down"),
        /// how W is applied (below)
        mode: LoadMode = LoadMode::Force => key()
            .note("`node_mass_scale` only with `canopy.shape = \"mesh\"`"),
        /// where: a named set or `[[x, y], …]` points
        sites: Sites = Sites::Named(SiteSet::Ends) => key()
            .unit("– / m")
            .default_doc("rod `ends`; rectangle, hexagon `corners`; circle `rim`; mesh `center`")
            .note("see below; points must lie inside the outline"),
        /// `sites = "rim"`: equally spaced rim sites, the first on +x
        rim_site_count: usize = 8 => key()
            .between(3.0, 10_000.0, "rim sites around the circle")
            .range_when(when("load.sites", "rim")),
        /// `node_mass_scale`: the payload's 1-based mesh node number
        node: usize = 1 => key()
            .at_least(1.0, "a 1-based mesh node number")
            .range_when(NODE_MASS_SCALE)
            .note("≤ node count: checked by the builder"),
        /// `node_mass_scale`: factor on that node's lumped mass and weight
        mass_scale: f64 = 100.0 => key().positive("a mass factor").range_when(NODE_MASS_SCALE),
    }
}

section! {
    /// `[lines]`: suspension lines, modelled as rods, from each site to the payload.
    pub struct Lines {
        /// unstretched length of each line
        length_m: f64 = 3.0 => key().unit("m").positive("a length"),
        /// rod edges per line
        segments: usize = 10 => key().between(1.0, 10_000.0, "rod edges per line"),
        /// cross-section radius
        radius_m: f64 = 0.001 => key().unit("m").positive("a length"),
        /// Young's modulus
        youngs_modulus_pa: f64 = 55e9 => key().unit("Pa").positive("a stiffness"),
        /// Poisson's ratio
        poisson_ratio: f64 = 0.36 => key().range(
            Bound::Excl(-1.0),
            Bound::Incl(0.5),
            "a stable isotropic material"
        ),
        /// density
        density_kg_m3: f64 = 1440.0 => key().unit("kg/m³").positive("the lines need mass"),
        /// C_D of the lines' isotropic node drag, projected width 2r
        #[serde(skip_serializing_if = "Option::is_none")]
        drag_coefficient: Option<f64> = None => key()
            .non_negative("a drag coefficient")
            .default_doc("`fluid.drag_coefficient`")
            .note("0 disables line drag"),
    }
}

choice! {
    /// Drag law.
    pub enum DragLaw {
        /// f = −½ ρ C_D A |u| u (high Reynolds number).
        Quadratic = "quadratic",
        /// f = −c (A_k / A) u (low Reynolds number), c = `linear_drag_coefficient_n_s_m`.
        Linear = "linear",
    }
}

section! {
    /// `[fluid]`.
    pub struct Fluid {
        /// air density ρ
        density_kg_m3: f64 = 1.225 => key()
            .unit("kg/m³")
            .positive("drag scales with the air density"),
        /// dynamic viscosity μ (Reynolds number Re = ρ v L / μ)
        viscosity_pa_s: f64 = 1.81e-5 => key()
            .unit("Pa·s")
            .positive("the Reynolds number divides by it"),
        /// far-field wind U∞; with a `[wind]` power or log law, the wind at its reference
        /// height
        wind_mps: [f64; 3] = [0.0; 3] => key().unit("m/s"),
        /// drag law
        drag: DragLaw = DragLaw::Quadratic => key(),
        /// C_D: rod drag; shell normal drag; with `shell_drag = "inflation"` or `"incidence"`
        /// the pressure coefficient C_p of Δp = C_p ½ρw²
        drag_coefficient: f64 = 1.75 => key().positive("without drag there is no terminal velocity"),
        /// C_t: shell tangential drag
        tangential_drag_coefficient: f64 = 0.5 => key().non_negative("drag opposes motion"),
        /// shell drag model: `report` (§II.D: normal C_D and tangential C_t per triangle),
        /// `pressure` (DisMech: normal velocity only, C_D), `inflation` (the trapped air's
        /// pressure C_D ½ρw², w the descent speed through the air, on every triangle's inside
        /// normal, plus tangential C_t) or `incidence` (`inflation` plus the windward excess of
        /// a tabulated C_N(α))
        shell_drag: ShellDrag = ShellDrag::Report => key(),
        /// `shell_drag = "inflation"`: the descent speed w of the pressure, each triangle's
        /// own (`panel`) or the canopy's, held over each step (`canopy`; a packed or tilted
        /// canopy, docs/aero.md §InflationPressure)
        #[serde(skip_serializing_if = "Option::is_none")]
        inflation_speed: Option<InflationSpeed> = None => key()
            .only_with(when("fluid.shell_drag", "inflation"), "")
            .default_doc("`\"panel\"`"),
        /// `shell_drag = "incidence"`: angles of attack α of the normal-force table, from
        /// −90° to 90°, increasing
        #[serde(skip_serializing_if = "Option::is_none")]
        incidence_alpha_deg: Option<Vec<f64>> = None => key()
            .unit("deg")
            .only_with(INCIDENCE, "")
            .required_with(INCIDENCE, "needs the canopy's C_N(α) table: its angles (deg)")
            .note("cover −90° to 90°, strictly increasing"),
        /// `shell_drag = "incidence"`: the whole canopy's normal-force coefficient C_N at each
        /// angle (on S₀, positive when it opposes the sideways motion)
        #[serde(skip_serializing_if = "Option::is_none")]
        incidence_cn: Option<Vec<f64>> = None => key()
            .only_with(INCIDENCE, "")
            .required_with(INCIDENCE, "needs the canopy's C_N(α) table: its coefficients")
            .note("one per angle; odd, C_N(−α) = −C_N(α)"),
        /// `drag = "linear"`: whole-canopy coefficient c; node k gets −c (A_k/A) u_rel,k, so a
        /// flat rigid canopy falls at W/c
        #[serde(skip_serializing_if = "Option::is_none")]
        linear_drag_coefficient_n_s_m: Option<f64> = None => key()
            .unit("N·s/m")
            .positive("drag opposes motion")
            .required_with(
                when("fluid.drag", "linear"),
                "needs the whole-canopy coefficient c (N·s/m)"
            ),
        /// gravitational acceleration g
        gravity_mps2: f64 = 9.81 => key().unit("m/s²").positive("gravity points down, −z"),
        /// the air's added mass on the canopy: its mean motion carries the potential-flow
        /// mass (8/3) ρ a³ of the disc of its projected area, in every direction (docs/aero.md
        /// §AddedMass)
        #[serde(skip_serializing_if = "Option::is_none")]
        added_mass: Option<bool> = None => key()
            .only_with(SHELL, ADDED_MASS_SHELL)
            .default_doc("false")
            .note("not with `[wind]`"),
    }
}

/// Why added mass needs a shell canopy.
const ADDED_MASS_SHELL: &str =
    " (the added mass needs the canopy's projected area, which a rod strip does not have)";

choice! {
    /// How the air varies with height.
    pub enum AtmosphereModel {
        /// `fluid.density_kg_m3` and `fluid.viscosity_pa_s` at every height.
        Constant = "constant",
        /// The U.S. Standard Atmosphere 1976 (0–86 km) at each element's altitude.
        Isa1976 = "isa1976",
    }
}

section! {
    /// `[atmosphere]`: the air's variation with height, and the ground.
    pub struct Atmosphere {
        /// `constant`: `fluid.density_kg_m3` and `fluid.viscosity_pa_s` everywhere;
        /// `isa1976`: the U.S. Standard Atmosphere 1976 (density, viscosity by Sutherland's
        /// law) at each drag element's own altitude
        model: AtmosphereModel = AtmosphereModel::Constant => key()
            .note("with `isa1976`, `fluid.density_kg_m3` and `fluid.viscosity_pa_s` are not used (one warning when a scenario sets them)"),
        /// geometric altitude of the model's z = 0, where the flat canopy starts
        altitude_m: f64 = 0.0 => key()
            .unit("m")
            .between(0.0, 86_000.0, "the 1976 standard atmosphere is defined from 0 to 86 km")
            .range_when(ISA),
        /// geometric altitude of the ground: the run ends, complete, when the payload (without
        /// one, the lowest canopy node) reaches it
        #[serde(skip_serializing_if = "Option::is_none")]
        ground_altitude_m: Option<f64> = None => key()
            .unit("m")
            .between(0.0, 86_000.0, "the 1976 standard atmosphere is defined from 0 to 86 km")
            .range_when(ISA)
            .default_doc("absent: no ground")
            .note("below `altitude_m` and below the payload's (or lowest node's) start"),
    }
}

section! {
    /// `[output]`.
    pub struct Output {
        /// time between ParaView frames
        frame_interval_s: f64 = 0.05 => key()
            .unit("s")
            .positive("a time interval")
            .note("≥ `time.dt_s`"),
        /// times of snapshot pictures; `[]` for none
        snapshots_s: Vec<f64> = Vec::new() => key()
            .unit("s")
            .non_negative("times after time.duration_s are skipped")
            .default_doc("30 %, 60 %, 90 % of `time.duration_s`")
            .note("times after `time.duration_s` are skipped with a warning in the summary; files are named to the millisecond, and two times sharing a name are warned about"),
    }
}

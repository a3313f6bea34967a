//! Scenarios: the TOML input of a simulation, parsed into typed, validated structs.
//!
//! The format is the contract in `DESIGN.md` §Scenario file; every key, its unit, default and
//! allowed range is documented in `docs/scenarios.md`. Loading runs these stages, each of
//! which reports the first problem with its key and origin (file line or `--set`):
//! 1. [`source`]: TOML syntax, and the line of every key;
//! 2. [`overrides`]: `--set section.key=value` applied to the raw tree;
//! 3. [`schema`]: unknown keys ("did you mean") and value types;
//! 4. context-dependent defaults (name, load sites, snapshot times), then serde conversion;
//! 5. [`validate`]: physical ranges and cross-key consistency.
//!
//! Coordinates: the canopy lies flat in the plane z = 0, centred on the origin. A rectangle
//! (and a rod strip) spans x ∈ [−span/2, span/2], y ∈ [−width/2, width/2]; a hexagon has its
//! corners at angles 0°, 60°, …, 300° on the circle of radius `radius_m`; a circle has radius
//! `radius_m`. Load-site coordinates `[x, y]` are in this frame (m).

pub mod derived;
pub mod error;
pub mod overrides;
mod parse;
pub mod schema;
pub mod source;
pub mod validate;

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

pub use error::{Origin, ScenarioError};
/// The absolute directory against which a file's relative paths resolve.
pub use parse::base_dir as source_dir;

/// A complete, validated scenario with every default filled in.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    /// Run name, used for the default output directory `runs/<name>`; default: file stem.
    pub name: String,
    /// Which structural model represents the canopy.
    pub model: ModelSection,
    /// Canopy geometry.
    #[serde(default)]
    pub canopy: Canopy,
    /// Canopy material.
    #[serde(default)]
    pub material: Material,
    /// The load the canopy carries.
    #[serde(default)]
    pub load: Load,
    /// Suspension lines (payload mode).
    #[serde(default)]
    pub lines: Lines,
    /// Air and drag law.
    #[serde(default)]
    pub fluid: Fluid,
    /// Time stepping.
    #[serde(default)]
    pub time: Time,
    /// What to write.
    #[serde(default)]
    pub output: Output,
}

/// `[model]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModelSection {
    /// `rod` (a DER strip) or `shell` (a discrete-shell membrane). Required.
    pub kind: ModelKind,
}

/// Structural model of the canopy.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ModelKind {
    /// Discrete elastic rod along the span (report §II.A–B).
    Rod,
    /// Discrete shell (report §II.C–D).
    Shell,
}

/// Canopy outline.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CanopyShape {
    /// `span_m × width_m`.
    Rectangle,
    /// Regular hexagon of circumradius `radius_m`.
    Hexagon,
    /// Disc of radius `radius_m`.
    Circle,
    /// Imported from `mesh_file`.
    Mesh,
}

/// `[canopy]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Canopy {
    /// Outline; default `rectangle`.
    pub shape: CanopyShape,
    /// Length along x (m); for a rod, the rod's length. Default 6.
    pub span_m: f64,
    /// Width along y (m); for a rod, the strip width (drag area and bending). Default 3.
    pub width_m: f64,
    /// Thickness (m). Default 0.002.
    pub thickness_m: f64,
    /// Rod: nodes along the span (≥ 3). Default 61.
    pub nodes: usize,
    /// Shell: target edge length of the generated mesh (m). Default 0.25.
    pub edge_length_m: f64,
    /// `shape = "mesh"`: DisMech `.txt` or Wavefront `.obj`, resolved against the scenario's
    /// directory (stored absolute).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mesh_file: Option<PathBuf>,
    /// Hexagon circumradius or circle radius (m). Default 1.
    pub radius_m: f64,
    /// Shell: amplitude of the initial out-of-plane perturbation (m), the fixed asymmetric mode
    /// of [`crate::build`]'s `imperfection` (docs/scenarios.md). Default 0: a flat start (and
    /// then not written to the resolved scenario, which stays as before the key existed).
    #[serde(skip_serializing_if = "is_zero")]
    pub imperfection_m: f64,
}

fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

impl Default for Canopy {
    fn default() -> Self {
        Self {
            shape: CanopyShape::Rectangle,
            span_m: 6.0,
            width_m: 3.0,
            thickness_m: 0.002,
            nodes: 61,
            edge_length_m: 0.25,
            mesh_file: None,
            radius_m: 1.0,
            imperfection_m: 0.0,
        }
    }
}

/// `[material]` of the canopy.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Material {
    /// Young's modulus E (Pa). Default 55e9 (Kevlar, report §II.F).
    pub youngs_modulus_pa: f64,
    /// Poisson's ratio ν (−). Default 0.36.
    pub poisson_ratio: f64,
    /// Density ρ (kg/m³). Default 1440.
    pub density_kg_m3: f64,
}

impl Default for Material {
    fn default() -> Self {
        Self {
            youngs_modulus_pa: 55e9,
            poisson_ratio: 0.36,
            density_kg_m3: 1440.0,
        }
    }
}

/// How the load is applied.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LoadMode {
    /// Constant downward forces W/n at the n sites (the report's model).
    Force,
    /// A payload node of mass W/g hanging on suspension lines from the sites.
    Payload,
    /// Point masses W/(g n) added at the n sites.
    Mass,
    /// Mesh input: mesh node `node` (1-based) gets its lumped mass and weight × `mass_scale`
    /// (the DisMech hexagonal-parachute convention); `weight_n` and `sites` are unused.
    NodeMassScale,
}

/// Named load-site sets.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SiteSet {
    /// Rod: its two end nodes.
    Ends,
    /// Rectangle: the 4 corners; hexagon: the 6 corners.
    Corners,
    /// Rectangle: the 4 corners and the 2 mid-points of the long (span) edges.
    CornersAndMidspan,
    /// The node nearest the origin.
    Center,
    /// Circle: `rim_site_count` equally spaced rim points, the first on +x.
    Rim,
}

/// Load sites: a named set, or explicit `[x, y]` points (m) resolved by the builder to the
/// nearest canopy node.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Sites {
    /// A named set.
    Named(SiteSet),
    /// Explicit points in the canopy plane (m).
    Points(Vec<[f64; 2]>),
}

/// `[load]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Load {
    /// Total load W (N). Default 200.
    pub weight_n: f64,
    /// How the load is applied. Default `force`.
    pub mode: LoadMode,
    /// Where; default by model and shape: rod `ends`, rectangle and hexagon `corners`, circle
    /// `rim`, mesh `center`.
    pub sites: Sites,
    /// `sites = "rim"`: number of rim sites (≥ 3). Default 8.
    pub rim_site_count: usize,
    /// `mode = "node_mass_scale"`: the 1-based mesh node that is the payload. Default 1.
    pub node: usize,
    /// `mode = "node_mass_scale"`: factor on that node's mass and weight. Default 100.
    pub mass_scale: f64,
}

impl Default for Load {
    fn default() -> Self {
        Self {
            weight_n: 200.0,
            mode: LoadMode::Force,
            sites: Sites::Named(SiteSet::Ends),
            rim_site_count: 8,
            node: 1,
            mass_scale: 100.0,
        }
    }
}

/// `[lines]`: suspension lines, modelled as rods, from each site to the payload.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Lines {
    /// Unstretched length of each line (m). Default 3.
    pub length_m: f64,
    /// Rod edges per line (≥ 1). Default 10.
    pub segments: usize,
    /// Line cross-section radius (m). Default 0.001.
    pub radius_m: f64,
    /// Young's modulus (Pa). Default 55e9.
    pub youngs_modulus_pa: f64,
    /// Poisson's ratio (−). Default 0.36.
    pub poisson_ratio: f64,
    /// Density (kg/m³). Default 1440.
    pub density_kg_m3: f64,
    /// Drag coefficient of the lines' isotropic node drag (−); default `fluid.drag_coefficient`;
    /// 0 disables line drag (e.g. to compare with a peer code that has none).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub drag_coefficient: Option<f64>,
}

impl Default for Lines {
    fn default() -> Self {
        Self {
            length_m: 3.0,
            segments: 10,
            radius_m: 0.001,
            youngs_modulus_pa: 55e9,
            poisson_ratio: 0.36,
            density_kg_m3: 1440.0,
            drag_coefficient: None,
        }
    }
}

/// Drag law.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DragLaw {
    /// f = −½ ρ C_D A |u| u (high Reynolds number).
    Quadratic,
    /// f = −c (A_k / A) u (low Reynolds number), c = `linear_drag_coefficient_n_s_m`.
    Linear,
}

/// Shell drag model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ShellDrag {
    /// Report §II.D: normal (C_D) and tangential (C_t) quadratic drag per triangle.
    Report,
    /// DisMech-style pressure drag on the normal velocity only, coefficient C_D.
    Pressure,
}

/// `[fluid]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Fluid {
    /// Air density ρ (kg/m³). Default 1.225.
    pub density_kg_m3: f64,
    /// Dynamic viscosity μ (Pa·s), for the Reynolds number. Default 1.81e-5.
    pub viscosity_pa_s: f64,
    /// Far-field wind U∞ (m/s). Default [0, 0, 0].
    pub wind_mps: [f64; 3],
    /// Drag law. Default `quadratic`.
    pub drag: DragLaw,
    /// C_D: rod drag and shell normal drag (−). Default 1.75.
    pub drag_coefficient: f64,
    /// C_t: shell tangential drag (−). Default 0.5.
    pub tangential_drag_coefficient: f64,
    /// Shell drag model. Default `report`.
    pub shell_drag: ShellDrag,
    /// Linear drag: whole-canopy coefficient c (N·s/m); required when `drag = "linear"`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub linear_drag_coefficient_n_s_m: Option<f64>,
    /// Gravitational acceleration g (m/s²). Default 9.81.
    pub gravity_mps2: f64,
}

impl Default for Fluid {
    fn default() -> Self {
        Self {
            density_kg_m3: 1.225,
            viscosity_pa_s: 1.81e-5,
            wind_mps: [0.0; 3],
            drag: DragLaw::Quadratic,
            drag_coefficient: 1.75,
            tangential_drag_coefficient: 0.5,
            shell_drag: ShellDrag::Report,
            linear_drag_coefficient_n_s_m: None,
            gravity_mps2: 9.81,
        }
    }
}

/// `[time]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Time {
    /// Implicit Euler step (s). Default 1e-3 (report §II.E).
    pub dt_s: f64,
    /// Simulated time (s). Default 10.
    pub duration_s: f64,
    /// Newton iterations allowed per step. Default 25.
    pub newton_max_iterations: usize,
    /// Absolute Newton tolerance on the residual force (N); default: the engine's
    /// mass-scaled tolerance.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub newton_tolerance_n: Option<f64>,
    /// Newton tolerance relative to the first residual of a step (‖R‖∞ ≤ rel · ‖R₀‖∞ also
    /// converges); default: the engine's 1e-10.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub newton_relative_tolerance: Option<f64>,
    /// Newton step tolerance (m or rad): an update with ‖Δq‖∞ below it converges (while
    /// ‖R‖∞ is within 1e3 × the force tolerance); default: the engine's 1e-12.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub newton_step_tolerance_m: Option<f64>,
    /// Adaptive step with local-error control; `dt_s` is then the first step. Default false
    /// (and then not written to the resolved scenario, which stays as before the key existed).
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub adaptive: bool,
    /// Adaptive: tolerance on the local position error per step (m). Filled with
    /// [`DEFAULT_ERROR_TOLERANCE_M`] when `adaptive` and absent; only allowed with `adaptive`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error_tolerance_m: Option<f64>,
    /// Adaptive: smallest step (s); default `dt_s / 1024`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dt_min_s: Option<f64>,
    /// Adaptive: largest step (s); default `min(100 dt_s, output.frame_interval_s)`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dt_max_s: Option<f64>,
}

/// Default `time.error_tolerance_m` (m per step): at the start of a fall (a = g) it allows
/// `h = √(2 tol/g) ≈ 1.4 ms`, the report's 1 ms step with its local error `g dt²/2 ≈ 5 µm`,
/// so an adaptive run is at least as accurate as the report's fixed step in the transient and
/// only takes longer steps where the acceleration has decayed (docs/adaptive-dt.md).
pub const DEFAULT_ERROR_TOLERANCE_M: f64 = 1e-5;

impl Default for Time {
    fn default() -> Self {
        Self {
            dt_s: 1e-3,
            duration_s: 10.0,
            newton_max_iterations: 25,
            newton_tolerance_n: None,
            newton_relative_tolerance: None,
            newton_step_tolerance_m: None,
            adaptive: false,
            error_tolerance_m: None,
            dt_min_s: None,
            dt_max_s: None,
        }
    }
}

/// The error-control settings of an adaptive scenario (all filled in by the loader).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AdaptiveSettings {
    /// Local position error per step (m).
    pub error_tolerance_m: f64,
    /// Smallest step (s).
    pub dt_min_s: f64,
    /// Largest step (s).
    pub dt_max_s: f64,
}

impl Scenario {
    /// The adaptive settings, or `None` for a fixed step. The loader fills every absent key
    /// when `time.adaptive = true`; the same defaults apply here to hand-built structs.
    pub fn adaptive_settings(&self) -> Option<AdaptiveSettings> {
        let t = &self.time;
        if !t.adaptive {
            return None;
        }
        Some(AdaptiveSettings {
            error_tolerance_m: t.error_tolerance_m.unwrap_or(DEFAULT_ERROR_TOLERANCE_M),
            dt_min_s: t.dt_min_s.unwrap_or(t.dt_s / 1024.0),
            dt_max_s: t
                .dt_max_s
                .unwrap_or((100.0 * t.dt_s).min(self.output.frame_interval_s)),
        })
    }
}

/// `[output]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Output {
    /// Time between ParaView frames (s, ≥ dt). Default 0.05.
    pub frame_interval_s: f64,
    /// Times of snapshot pictures (s); default 30 %, 60 % and 90 % of the duration.
    pub snapshots_s: Vec<f64>,
}

impl Default for Output {
    fn default() -> Self {
        Self {
            frame_interval_s: 0.05,
            snapshots_s: Vec::new(),
        }
    }
}

impl Scenario {
    /// Read, override and validate a scenario file. Relative paths inside it (`mesh_file`)
    /// resolve against the file's directory.
    pub fn load(path: &Path, overrides: &[String]) -> Result<Scenario, ScenarioError> {
        let text = std::fs::read_to_string(path).map_err(|e| ScenarioError::Read {
            path: path.to_path_buf(),
            reason: e.to_string(),
        })?;
        let file = path.display().to_string();
        parse::parse_scenario(&text, &file, &parse::base_dir(path), overrides)
    }

    /// Parse scenario text. `name_for_errors` is used in messages; its stem is the default
    /// `name` and its directory (or the working directory) resolves relative paths.
    pub fn from_str_with_name(
        text: &str,
        name_for_errors: &str,
        overrides: &[String],
    ) -> Result<Scenario, ScenarioError> {
        let base = parse::base_dir(Path::new(name_for_errors));
        parse::parse_scenario(text, name_for_errors, &base, overrides)
    }

    /// The fully resolved scenario as TOML (every default filled in), as written to
    /// `scenario.resolved.toml`; parsing it gives back an equal scenario.
    pub fn to_toml(&self) -> String {
        let body =
            toml::to_string(self).unwrap_or_else(|e| format!("# serialisation failed: {e}\n"));
        format!("# Fully resolved chute scenario: every default filled in.\n{body}")
    }

    /// Canopy planform area (m²) of the flat canopy, or `None` for an imported mesh (known
    /// only once the builder has read it).
    pub fn planform_area_m2(&self) -> Option<f64> {
        let c = &self.canopy;
        match (self.model.kind, c.shape) {
            (ModelKind::Rod, _) | (_, CanopyShape::Rectangle) => Some(c.span_m * c.width_m),
            (_, CanopyShape::Hexagon) => Some(1.5 * 3f64.sqrt() * c.radius_m * c.radius_m),
            (_, CanopyShape::Circle) => Some(std::f64::consts::PI * c.radius_m * c.radius_m),
            (_, CanopyShape::Mesh) => None,
        }
    }
}

//! Scenarios: the TOML input of a simulation, parsed into typed, validated structs.
//!
//! Every key is declared once in [`sections`] (the language is [`keys`]); its unit, default
//! and allowed range are documented in `docs/scenarios.md`, whose key tables are generated
//! from the declarations ([`docs`]). docs/architecture.md §How a scenario key flows has the
//! whole path. Loading runs these stages, each of which reports the first problem with its
//! key and origin (file line or `--set`):
//! 1. [`source`]: TOML syntax, and the line of every key;
//! 2. [`overrides`]: `--set section.key=value` applied to the raw tree;
//! 3. [`schema`]: unknown keys ("did you mean"), value types, required keys;
//! 4. context-dependent defaults (name, load sites, snapshot times, declared conditional
//!    defaults), then serde conversion;
//! 5. [`validate`]: the declared per-key rules (ranges, "only with", "required with"), then
//!    the hand-written cross-key consistency checks.
//!
//! Coordinates: the canopy lies flat in the plane z = 0, centred on the origin. A rectangle
//! (and a rod strip) spans x ∈ [−span/2, span/2], y ∈ [−width/2, width/2]; a hexagon has its
//! corners at angles 0°, 60°, …, 300° on the circle of radius `radius_m`; a circle has radius
//! `radius_m`. Load-site coordinates `[x, y]` are in this frame (m).

/// Halvings of `time.dt_s` after which a failing step stops a fixed-step run; `dt_s` over
/// `2^MIN_STEP_HALVINGS` (1024) is also the default `time.dt_min_s` of an adaptive one.
pub const MIN_STEP_HALVINGS: i32 = 10;

/// The smallest step of a run of step `dt_s` ([`MIN_STEP_HALVINGS`] halvings of it).
pub fn min_step(dt_s: f64) -> f64 {
    dt_s / 2f64.powi(MIN_STEP_HALVINGS)
}

pub mod control;
pub mod derived;
pub mod docs;
pub mod error;
mod incidence;
pub mod keys;
pub mod limits;
mod opening;
pub mod overrides;
mod parse;
pub mod plausibility;
pub mod round;
mod rules;
pub mod schema;
pub mod sections;
pub mod source;
pub mod validate;
pub mod wind;
pub mod wrinkle;

#[cfg(test)]
mod tests;

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

pub use error::{Origin, ScenarioError};
pub use incidence::incidence_curve;
/// The absolute directory against which a file's relative paths resolve.
pub use parse::base_dir as source_dir;
pub use sections::{
    Atmosphere, AtmosphereModel, Bending, Canopy, CanopyProfile, CanopyShape, Contact, Control,
    DragLaw, Fluid, Guidance, InflationSpeed, Lines, Load, LoadMode, Material, Membrane,
    MeshPattern, ModelKind, ModelSection, Opening, Output, Packing, PullSide, Sensor, SensorKind,
    Shell, ShellDrag, SiteSet, Sites, Time, Wind, WindLaw, DEFAULT_ERROR_TOLERANCE_M,
};

/// `--set` overrides that turn the bundled report shells (`scenarios/report-shell-*.toml`,
/// which ship the converged continuum shell at dt = 4 ms) back into the report's own model:
/// edge springs, dihedral hinges, dt = 1 ms. Benchmarks and checks whose reference is that
/// model (`flight-1k`, `cross-613`, the symmetry and balance checks) apply them.
pub const REPORT_SHELL_MODEL: [&str; 3] = [
    "shell.membrane=springs",
    "shell.bending=hinge",
    "time.dt_s=1e-3",
];

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
    /// The shell's laws (shell canopies).
    #[serde(default)]
    pub shell: Shell,
    /// The load the canopy carries.
    #[serde(default)]
    pub load: Load,
    /// Suspension lines (payload mode).
    #[serde(default)]
    pub lines: Lines,
    /// Air and drag law.
    #[serde(default)]
    pub fluid: Fluid,
    /// The air's variation with height, and the ground.
    #[serde(default)]
    pub atmosphere: Atmosphere,
    /// A wind that varies with height (absent: `fluid.wind_mps` everywhere).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wind: Option<Wind>,
    /// Self-contact of the canopy and its lines (absent: none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact: Option<Contact>,
    /// A canopy that starts packed at line stretch (absent: flat).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub opening: Option<Opening>,
    /// Time stepping.
    #[serde(default)]
    pub time: Time,
    /// What to write.
    #[serde(default)]
    pub output: Output,
    /// Sensors that can start pulls (`[[sensor]]`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub sensor: Vec<Sensor>,
    /// Scheduled or sensor-started line pulls (`[[control]]`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub control: Vec<Control>,
    /// Guidance to a target by line pulls.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub guidance: Option<Guidance>,
    /// What the loader noticed about how the scenario was written (keys set but not used);
    /// not part of the scenario itself: never serialised, and equal for any two scenarios.
    #[serde(skip)]
    pub notes: LoadNotes,
    /// What the loader read from the scenario's input files (compared by digest, in the
    /// run's record, not by equality: [`Loaded`] is equal for any two scenarios).
    #[serde(skip)]
    pub loaded: Loaded,
}

/// The contents of the input files a scenario names, as the loader read them.
#[derive(Debug, Clone, Default)]
pub struct Loaded {
    /// The table of `wind.file` (`wind.profile = "table"`).
    pub wind: Option<std::sync::Arc<wind::WindFile>>,
}

impl PartialEq for Loaded {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

/// Warnings of the loader about the text a scenario came from (e.g. keys that are set but
/// not used). They describe the text, not the scenario, so they take no part in equality:
/// a scenario and its re-parsed resolved TOML are equal.
#[derive(Debug, Clone, Default)]
pub struct LoadNotes(pub Vec<String>);

impl PartialEq for LoadNotes {
    fn eq(&self, _: &Self) -> bool {
        true
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
    /// Norm of the local error estimate.
    pub error_norm: engine::ErrorNorm,
    /// Filter the estimate through the step's Newton matrix.
    pub error_filter: bool,
}

/// The text of the scenario file `path`, read up to [`MAX_SCENARIO_BYTES`]: a device is
/// refused (`/dev/zero` never ends), a pipe read (`chute check <(…)`) but never past the limit.
fn read_bounded(path: &Path) -> Result<String, String> {
    use std::io::Read;
    use std::os::unix::fs::FileTypeExt;
    let kind = std::fs::metadata(path).map(|m| m.file_type());
    if kind.is_ok_and(|t| t.is_char_device() || t.is_block_device() || t.is_socket()) {
        return Err("it is a device, not a scenario file".into());
    }
    let mut text = String::new();
    std::fs::File::open(path)
        .and_then(|f| f.take(MAX_SCENARIO_BYTES + 1).read_to_string(&mut text))
        .map_err(|e| e.to_string())?;
    if text.len() as u64 > MAX_SCENARIO_BYTES {
        return Err(format!(
            "it is longer than {MAX_SCENARIO_BYTES} bytes, the most a scenario file may hold"
        ));
    }
    Ok(text)
}

/// The key of the imported mesh file, an input file a run records by digest.
pub const MESH_FILE_KEY: &str = "canopy.mesh_file";
/// The key of a packed start's mesh file (`[opening] pack = "mesh"`).
pub const START_MESH_FILE_KEY: &str = "opening.mesh_file";

/// Largest scenario file read (bytes, 16 MiB): scenarios are short text files; a larger one
/// is refused before it is read into memory.
pub const MAX_SCENARIO_BYTES: u64 = 16 << 20;

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
            dt_min_s: t.dt_min_s.unwrap_or(min_step(t.dt_s)),
            dt_max_s: t
                .dt_max_s
                .unwrap_or((100.0 * t.dt_s).min(self.output.frame_interval_s)),
            error_norm: match t.error_norm {
                Some(sections::ErrorNorm::Max) => engine::ErrorNorm::Max,
                _ => engine::ErrorNorm::MassRms,
            },
            error_filter: t.error_filter.unwrap_or(true),
        })
    }
}

impl Scenario {
    /// Read, override and validate a scenario file. Relative paths inside it (`mesh_file`)
    /// resolve against the file's directory.
    pub fn load(path: &Path, overrides: &[String]) -> Result<Scenario, ScenarioError> {
        let read = |reason: String| ScenarioError::Read {
            path: path.to_path_buf(),
            reason,
        };
        let text = read_bounded(path).map_err(read)?;
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

    /// Every file the scenario reads besides itself, with the key that names it: what a run
    /// records by digest, so that a resume or a study never continues with other contents
    /// under the same name (docs/reliability.md §5). A key that names a file but is not used
    /// (a `mesh_file` with another `canopy.shape`) is not an input.
    pub fn input_files(&self) -> Vec<(&'static str, PathBuf)> {
        let mut files = Vec::new();
        if let (CanopyShape::Mesh, Some(p)) = (self.canopy.shape, &self.canopy.mesh_file) {
            files.push((MESH_FILE_KEY, p.clone()));
        }
        if let Some(Wind {
            profile: WindLaw::Table,
            file: Some(p),
            ..
        }) = &self.wind
        {
            files.push((wind::WIND_FILE_KEY, p.clone()));
        }
        if let Some(p) = self.opening.as_ref().and_then(|o| o.mesh_file.as_ref()) {
            files.push((START_MESH_FILE_KEY, p.clone()));
        }
        files
    }

    /// Canopy planform area (m²) of the flat canopy (a round canopy's constructed surface, vent
    /// included), or `None` for an imported mesh (known only once the builder has read it).
    pub fn planform_area_m2(&self) -> Option<f64> {
        let c = &self.canopy;
        match (self.model.kind, c.shape) {
            (ModelKind::Rod, _) | (_, CanopyShape::Rectangle) => Some(c.span_m * c.width_m),
            (_, CanopyShape::Hexagon) => Some(1.5 * 3f64.sqrt() * c.radius_m * c.radius_m),
            (_, CanopyShape::Circle) => Some(crate::mesh::constructed::nominal_area(
                round::profile(&self.canopy),
                c.radius_m,
            )),
            (_, CanopyShape::Mesh) => None,
        }
    }
}

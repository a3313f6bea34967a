//! Resolve: a validated [`Scenario`] as the typed, fully defaulted description a run is made
//! of. [`ModelSpec`] is what the builders take; [`RunConfig`] (stepping, the solver's options
//! as the engine's own type, the air, the outputs, the controllers) is what the runner takes.
//! Every default that depends on other keys is derived here, once; neither the builders nor
//! the runner read the scenario.

use crate::mesh::constructed::Profile;
use crate::runner::{Outputs, RunConfig, Stepping};
use crate::scenario::{
    Bending, Canopy, Control, DragLaw, Fluid, Guidance, Lines, Load, Material, Membrane, ModelKind,
    Scenario, SiteSet, Sites,
};
use engine::aero::incidence::IncidenceCurve;
use engine::aero::Fabric;
use engine::shell::Orthotropic;

/// What the builders make a model of: the scenario's model sections with every derived
/// default filled in.
#[derive(Debug, Clone)]
pub struct ModelSpec {
    /// Rod or shell canopy (`model.kind`).
    pub kind: ModelKind,
    /// Canopy geometry (`[canopy]`).
    pub canopy: Canopy,
    /// The round canopy's gore profile (flat for every other shape).
    pub profile: Profile,
    /// Canopy material (`[material]`).
    pub material: Material,
    /// The shell's membrane law (`shell.membrane`; default: the report's edge springs).
    pub membrane: Membrane,
    /// The shell's bending law (`shell.bending`; default: the report's hinges).
    pub bending: Bending,
    /// The orthotropic fabric law (`shell.membrane = "fabric"` with its four constants).
    pub fabric_law: Option<Orthotropic>,
    /// Unit warp direction in the rest plane (`material.warp_direction_deg`, default +x).
    pub warp: [f64; 3],
    /// The no-compression regularisation strain ε_r, when the fabric carries no compression.
    pub wrinkle_strain: Option<f64>,
    /// The fabric's permeability (`permeability_m2` or `air_permeability_cfm`), if any.
    pub permeability: Option<Fabric>,
    /// The load (`[load]`).
    pub load: Load,
    /// Equally spaced rim sites the circle's rim must hold as nodes (1: none).
    pub rim_sites: usize,
    /// Suspension lines (`[lines]`).
    pub lines: Lines,
    /// The lines' drag coefficient (`lines.drag_coefficient`, default the canopy's).
    pub line_drag_coefficient: f64,
    /// The drag law and its coefficients (`[fluid]`).
    pub fluid: Fluid,
    /// The air at every height.
    pub air: engine::aero::Fluid,
    /// The incidence law's C_N(α) (`fluid.shell_drag = "incidence"`).
    pub incidence: Option<IncidenceCurve>,
    /// Gravitational acceleration (m/s²).
    pub gravity_mps2: f64,
    /// Scheduled and sensor-started line pulls (`[[control]]`).
    pub control: Vec<Control>,
    /// Guidance by line pulls (`[guidance]`).
    pub guidance: Option<Guidance>,
    /// Velocity of every node at t = 0 (m/s; `canopy.initial_velocity_mps`, default at rest).
    pub initial_velocity: [f64; 3],
    /// Horizontal position of the canopy's centre at t = 0 (m; `canopy.release_point_m`).
    pub release_point: [f64; 2],
    /// Self-contact (`[contact]`), its activation distance resolved (m).
    pub contact: Option<(f64, crate::scenario::Contact)>,
    /// The packed start (`[opening]`), its radius resolved.
    pub pack: Option<crate::build::packing::Pack>,
}

impl ModelSpec {
    /// The model description of `s`.
    pub fn of(s: &Scenario) -> Self {
        let m = &s.material;
        let angle = m.warp_direction_deg.unwrap_or(0.0).to_radians();
        let air = air(s);
        Self {
            kind: s.model.kind,
            canopy: s.canopy.clone(),
            profile: crate::scenario::round::profile(&s.canopy),
            material: m.clone(),
            membrane: s.shell.membrane.unwrap_or(Membrane::Springs),
            bending: s.shell.bending.unwrap_or(Bending::Hinge),
            fabric_law: s.fabric_law(),
            warp: [angle.cos(), angle.sin(), 0.0],
            wrinkle_strain: (m.no_compression == Some(true)).then(|| {
                m.wrinkle_strain
                    .unwrap_or(crate::scenario::wrinkle::DEFAULT_WRINKLE_STRAIN)
            }),
            permeability: crate::build::drag::fabric(m, s.canopy.thickness_m),
            load: s.load.clone(),
            rim_sites: match s.load.sites {
                Sites::Named(SiteSet::Rim) => s.load.rim_site_count.max(1),
                _ => 1,
            },
            lines: s.lines.clone(),
            line_drag_coefficient: s.lines.drag_coefficient.unwrap_or(s.fluid.drag_coefficient),
            fluid: s.fluid.clone(),
            initial_velocity: initial_velocity(s, &air),
            air,
            incidence: crate::scenario::incidence_curve(s),
            gravity_mps2: s.fluid.gravity_mps2,
            control: s.control.clone(),
            guidance: s.guidance.clone(),
            release_point: s.canopy.release_point_m.unwrap_or([0.0; 2]),
            contact: s.contact.clone().map(|c| {
                let d = c.distance_m.unwrap_or(
                    s.canopy.edge_length_m * crate::scenario::sections::DISTANCE_PER_EDGE,
                );
                (d, c)
            }),
            pack: s.opening.as_ref().map(|o| crate::build::packing::Pack {
                packing: o.pack,
                radius_m: s.canopy.radius_m,
                packed_radius_m: o.packed_radius_m.unwrap_or(
                    s.canopy.radius_m * crate::scenario::sections::PACKED_RADIUS_PER_RADIUS,
                ),
                mesh_file: o.mesh_file.clone(),
                attitude_rad: o.attitude_deg.to_radians(),
            }),
        }
    }

    /// Whether the lines get rest-length schedules (pulls or guidance).
    pub fn pulled(&self) -> bool {
        !self.control.is_empty() || self.guidance.is_some()
    }
}

/// Every node's velocity at t = 0: `canopy.initial_velocity_mps`, or the wind at the
/// canopy's start height (model z = 0) when `canopy.released_with_wind`, or rest.
fn initial_velocity(s: &Scenario, air: &engine::aero::Fluid) -> [f64; 3] {
    match (s.canopy.released_with_wind, s.canopy.initial_velocity_mps) {
        (true, _) => air.wind_at(0.0).velocity,
        (false, v) => v.unwrap_or([0.0; 3]),
    }
}

/// The engine's air of scenario `s`: `[fluid]` density and viscosity everywhere
/// (`atmosphere.model = "constant"`), or the 1976 standard atmosphere with z = 0 at
/// `atmosphere.altitude_m`; the wind of `[fluid]` and `[wind]` either way.
pub fn air(s: &Scenario) -> engine::aero::Fluid {
    use crate::scenario::AtmosphereModel;
    let f = &s.fluid;
    let wind = crate::scenario::wind::profile(s, s.loaded.wind.as_deref());
    match s.atmosphere.model {
        AtmosphereModel::Constant => engine::aero::Fluid {
            density: f.density_kg_m3,
            viscosity: f.viscosity_pa_s,
            wind: f.wind_mps,
            profile: engine::aero::Profile::Uniform,
            wind_profile: wind,
        },
        AtmosphereModel::Isa1976 => engine::aero::Fluid {
            wind: f.wind_mps,
            wind_profile: wind,
            ..engine::aero::Fluid::isa1976(s.atmosphere.altitude_m)
        },
    }
}

/// The solver's options of scenario `s`, as the engine takes them.
pub fn newton(s: &Scenario) -> engine::NewtonOptions {
    let t = &s.time;
    let default = engine::NewtonOptions::default();
    engine::NewtonOptions {
        max_iterations: t.newton_max_iterations,
        force_tol_abs: t.newton_tolerance_n,
        // The default absolute tolerance is 1e-9 of the total weight (+ 1 N).
        reference_acceleration: s.fluid.gravity_mps2,
        force_tol_rel: t.newton_relative_tolerance.unwrap_or(default.force_tol_rel),
        step_tol: t.newton_step_tolerance_m.unwrap_or(default.step_tol),
        continuation: t.newton_rescue_stages,
        step_homotopy: t.newton_rescue_stages,
        // The held stage, chord iterations, the divergence limit, the adaptive predictor
        // and the accuracy-based tolerance (docs/engine.md §The step solver).
        ..engine::NewtonOptions::recommended()
    }
    // The accuracy-based test replaces the default tolerance only: a scenario that sets
    // `time.newton_tolerance_n` (e.g. a peer's tolerances) gets exactly that one, with the
    // recommended factors; `newton_strict` also solves with double-precision factors.
    .without_accuracy_test_if(t.newton_tolerance_n.is_some())
    .strict_if(t.newton_strict)
}

/// The run loop's settings for scenario `s`.
pub fn run_config(s: &Scenario, progress: bool) -> RunConfig {
    let adaptive = s.adaptive_settings();
    // Model height of the ground, when the run ends there.
    let ground_z = s
        .atmosphere
        .ground_altitude_m
        .map(|g| g - s.atmosphere.altitude_m);
    RunConfig {
        name: s.name.clone(),
        stepping: Stepping {
            dt_s: s.time.dt_s,
            // Fixed step: ten halvings after failed Newton solves; adaptive: time.dt_min_s.
            min_dt_s: adaptive.map_or(crate::scenario::min_step(s.time.dt_s), |a| a.dt_min_s),
            adaptive,
            duration_s: s.time.duration_s,
        },
        outputs: Outputs {
            frame_interval_s: s.output.frame_interval_s,
            // The loader fills the default times; an empty list means none.
            snapshots_s: s.output.snapshots_s.clone(),
        },
        newton: newton(s),
        quadratic_drag: s.fluid.drag == DragLaw::Quadratic,
        air: air(s),
        altitude_m: s.atmosphere.altitude_m,
        ground_z_m: ground_z,
        gravity_mps2: s.fluid.gravity_mps2,
        guidance: ground_z.zip(s.guidance.as_ref()).and_then(|(z, g)| {
            crate::control::Controller::new(g, s.canopy.shape, s.fluid.shell_drag, z)
        }),
        triggers: ground_z.and_then(|z| crate::control::Triggers::new(&s.sensor, &s.control, z)),
        scenario_warnings: s.notes.0.clone(),
        progress,
    }
}

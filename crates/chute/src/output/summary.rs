//! `summary.json`: the headline results and bookkeeping of a run, written atomically.

use std::io;
use std::path::Path;

use crate::metrics::descent::Recovery;
use crate::metrics::Metrics;

/// Version of the `summary.json` layout; bump when a field changes meaning or is removed.
pub const SUMMARY_VERSION: u32 = 2;

/// Bookkeeping of a run that does not come from the time series.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RunInfo {
    /// Scenario name (from the scenario file).
    pub scenario_name: String,
    /// Whether the run reached its requested end time, or the ground.
    pub complete: bool,
    /// Why the run stopped before its end time (e.g. "Newton failed at t = 1.2 s"; "ground"
    /// for a complete run that landed), `None` if it ran to the end.
    pub stop_reason: Option<String>,
    /// Simulated time reached (s).
    pub simulated_time_s: f64,
    /// Accepted time steps.
    pub steps: u64,
    /// Total Newton iterations over all steps.
    pub newton_iterations: u64,
    /// Wall-clock time of the run (s).
    pub wall_time_s: f64,
    /// Number of degrees of freedom (3 per node + 1 twist per rod edge + 1 angle per shell
    /// edge with mid-edge bending).
    pub dofs: usize,
    /// Time-stepping settings and statistics.
    pub stepping: Stepping,
    /// What the Newton solves did over the whole run; `None` when it is not known for the
    /// whole run (resumed from a checkpoint that did not record it; a warning says so).
    pub solver: Option<SolverCounters>,
    /// Warnings raised by the run loop (they precede the metric warnings in the summary).
    pub warnings: Vec<String>,
    /// The canopy's own weight within W (N): the rest is the load and the lines.
    pub canopy_weight_n: Option<f64>,
}

/// How a run stepped in time: its settings and the steps it took (fields of
/// `summary.json`, docs/outputs.md).
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Stepping {
    /// `time.dt_s`: the step (fixed) or the first step (adaptive) (s).
    pub dt_s: f64,
    /// Whether the step size was error-controlled (`time.adaptive`).
    pub adaptive: bool,
    /// Adaptive: the local position error allowed per step (m); null for a fixed step.
    pub error_tolerance_m: Option<f64>,
    /// Smallest step allowed (s): adaptive `time.dt_min_s`; fixed `dt_s/1024`, the floor of
    /// the halvings after failed Newton solves.
    pub dt_min_s: f64,
    /// Largest step allowed (s): adaptive `time.dt_max_s`; fixed `dt_s`.
    pub dt_max_s: f64,
    /// Steps rejected for a local error above the tolerance (and retried smaller).
    pub rejected_steps_error: u64,
    /// Steps rejected because Newton failed (and retried with half the step).
    pub rejected_steps_newton: u64,
    /// Smallest accepted step (s); null before the first step.
    pub dt_used_min_s: Option<f64>,
    /// Mean accepted step (s): the sum of the accepted steps / their number.
    pub dt_used_mean_s: Option<f64>,
    /// Largest accepted step (s).
    pub dt_used_max_s: Option<f64>,
}

/// What the step solves of a run did: the stepper's [`engine::Counters`] accumulated over
/// the whole run, across checkpoint and resume (the object `solver` of `summary.json`,
/// docs/outputs.md). The counts of an interrupted and resumed run equal the uninterrupted
/// run's; the times are wall time and differ from run to run.
pub type SolverCounters = engine::Counters;

/// Contents of `summary.json`. SI units; field names carry the unit suffix. See
/// `docs/outputs.md` for the definitions (they are those of [`crate::metrics::compute`]).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Summary {
    /// Layout version ([`SUMMARY_VERSION`]).
    pub summary_version: u32,
    /// Scenario name.
    pub scenario_name: String,
    /// Whether the run reached its requested end time.
    pub complete: bool,
    /// Why the run stopped early; null if complete.
    pub stop_reason: Option<String>,
    /// Simulated time reached (s).
    #[serde(deserialize_with = "null_as_nan")]
    pub simulated_time_s: f64,
    /// Mean vz over the final 20 % of the run (m/s, signed; negative = descending).
    #[serde(deserialize_with = "null_as_nan")]
    pub terminal_velocity_mps: f64,
    /// Standard deviation of vz over the final window (m/s).
    #[serde(deserialize_with = "null_as_nan")]
    pub terminal_velocity_std_mps: f64,
    /// Change of vz across the final window along its least-squares line (m/s).
    #[serde(deserialize_with = "null_as_nan")]
    pub terminal_velocity_trend_mps: f64,
    /// Whether the final window is a steady descent.
    pub reached_terminal: bool,
    /// First time after which vz stays within ±2 % of v_t (s); null when not reached.
    pub time_to_terminal_s: Option<f64>,
    /// Start of the final window (s).
    #[serde(deserialize_with = "null_as_nan")]
    pub final_window_start_s: f64,
    /// Maximum extended height over the run (m).
    #[serde(deserialize_with = "null_as_nan")]
    pub max_extended_height_m: f64,
    /// Extended height at the end of the run (m).
    #[serde(deserialize_with = "null_as_nan")]
    pub final_extended_height_m: f64,
    /// Total weight W of the system (N).
    #[serde(deserialize_with = "null_as_nan")]
    pub total_weight_n: f64,
    /// The canopy's own weight within W (N), so that W is not read as the load alone; null
    /// in summaries of an older chute.
    #[serde(default)]
    pub canopy_weight_n: Option<f64>,
    /// Mean drag along z over the final window (N).
    #[serde(deserialize_with = "null_as_nan")]
    pub mean_drag_z_n: f64,
    /// C_D·A_eff = 2W/(ρ v_t²) (m²); null when v_t ≈ 0.
    pub drag_area_m2: Option<f64>,
    /// |mean drag_z − W| / W over the final window (dimensionless).
    #[serde(deserialize_with = "null_as_nan")]
    pub force_balance_error: f64,
    /// Mean [vx, vy] over the final window (m/s).
    #[serde(deserialize_with = "nulls_as_nan")]
    pub horizontal_velocity_mps: [f64; 2],
    /// Glide angle atan(|v_h| / |v_t|) from the vertical over the final window (degrees).
    #[serde(deserialize_with = "null_as_nan")]
    pub glide_angle_deg: f64,
    /// ρ |v_t| L / μ (dimensionless).
    #[serde(deserialize_with = "null_as_nan")]
    pub reynolds_number: f64,
    /// Recovery-system results: loads, settling, atmosphere, landing (their fields appear at
    /// this level; null when not defined; docs/engineering.md).
    #[serde(flatten)]
    pub recovery: Recovery,
    /// Accepted time steps.
    pub steps: u64,
    /// Total Newton iterations.
    pub newton_iterations: u64,
    /// Wall-clock time (s).
    #[serde(deserialize_with = "null_as_nan")]
    pub wall_time_s: f64,
    /// Degrees of freedom.
    pub dofs: usize,
    /// Time-stepping settings and statistics (their fields appear at this level).
    #[serde(flatten)]
    pub stepping: Stepping,
    /// The Newton solves' counters and times over the whole run (the object `solver`);
    /// null when they are not known for the whole run (a warning says why). Absent from
    /// summaries written before it existed, which read back as `None`.
    #[serde(default)]
    pub solver: Option<SolverCounters>,
    /// The sensor-started pulls: when and at what reading each fired (absent without one).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub triggers: Vec<crate::control::TriggerRecord>,
    /// Run-loop warnings followed by metric warnings.
    pub warnings: Vec<String>,
}

/// serde_json writes a non-finite float as `null` (the metrics of a run that could not judge
/// them are NaN); read `null` back as NaN so every summary.json parses into a [`Summary`].
fn null_as_nan<'de, D: serde::Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    use serde::Deserialize;
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
}

/// [`null_as_nan`] for a pair.
fn nulls_as_nan<'de, D: serde::Deserializer<'de>>(d: D) -> Result<[f64; 2], D::Error> {
    use serde::Deserialize;
    let [a, b] = <[Option<f64>; 2]>::deserialize(d)?;
    Ok([a.unwrap_or(f64::NAN), b.unwrap_or(f64::NAN)])
}

impl Summary {
    /// Combine run bookkeeping and metrics. An incomplete run gets an extra warning so that
    /// nobody reads its terminal velocity as final.
    pub fn new(run: RunInfo, m: &Metrics) -> Self {
        let mut warnings = run.warnings;
        if !run.complete {
            warnings.push(format!(
                "run incomplete: {}",
                run.stop_reason
                    .as_deref()
                    .unwrap_or("stopped before the end time")
            ));
        }
        warnings.extend(m.warnings.iter().cloned());
        Self {
            summary_version: SUMMARY_VERSION,
            scenario_name: run.scenario_name,
            complete: run.complete,
            stop_reason: run.stop_reason,
            simulated_time_s: run.simulated_time_s,
            terminal_velocity_mps: m.terminal_velocity_mps,
            terminal_velocity_std_mps: m.terminal_velocity_std_mps,
            terminal_velocity_trend_mps: m.terminal_velocity_trend_mps,
            reached_terminal: m.reached_terminal,
            time_to_terminal_s: m.time_to_terminal_s,
            final_window_start_s: m.window_start_s,
            max_extended_height_m: m.max_extended_height_m,
            final_extended_height_m: m.final_extended_height_m,
            total_weight_n: m.total_weight_n,
            canopy_weight_n: run.canopy_weight_n,
            mean_drag_z_n: m.mean_drag_z_n,
            drag_area_m2: m.drag_area_m2,
            force_balance_error: m.force_balance_error,
            horizontal_velocity_mps: m.horizontal_velocity_mps,
            glide_angle_deg: crate::metrics::glide_angle_deg(
                m.horizontal_velocity_mps,
                m.terminal_velocity_mps,
            ),
            reynolds_number: m.reynolds_number,
            recovery: Recovery::default(),
            steps: run.steps,
            newton_iterations: run.newton_iterations,
            wall_time_s: run.wall_time_s,
            dofs: run.dofs,
            stepping: run.stepping,
            solver: run.solver,
            triggers: Vec::new(),
            warnings,
        }
    }

    /// The same summary with the sensor-started pulls' records.
    pub fn with_triggers(mut self, triggers: Vec<crate::control::TriggerRecord>) -> Self {
        self.triggers = triggers;
        self
    }

    /// The same summary with the recovery-system results `r`.
    pub fn with_recovery(mut self, r: Recovery) -> Self {
        self.recovery = r;
        self
    }

    /// Pretty JSON (with a trailing newline).
    pub fn to_json(&self) -> String {
        // Serialising plain numbers/strings cannot fail; non-finite floats become null.
        let mut s = serde_json::to_string_pretty(self).expect("Summary serialises");
        s.push('\n');
        s
    }

    /// Write `path` (normally `<out>/summary.json`) atomically.
    pub fn write(&self, path: &Path) -> io::Result<()> {
        super::write_atomic(path, self.to_json().as_bytes())
    }
}

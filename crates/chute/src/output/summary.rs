//! `summary.json`: the headline results and bookkeeping of a run, written atomically.

use std::io;
use std::path::Path;

use crate::metrics::descent::Recovery;
use crate::metrics::Metrics;

/// Version of the `summary.json` layout; bump when a field changes meaning or is removed.
pub const SUMMARY_VERSION: u32 = 1;

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

/// What the Newton solves of a run did: the stepper's [`engine::Timings`] accumulated over
/// the whole run, across checkpoint and resume (the object `solver` of `summary.json`,
/// docs/outputs.md). The counts of an interrupted and resumed run equal the uninterrupted
/// run's; the times are wall time and differ from run to run.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SolverCounters {
    /// Residual evaluations (each one a full pass over the elements).
    pub evaluations: u64,
    /// Of those, evaluations that also assembled the Jacobian.
    pub jacobian_evaluations: u64,
    /// Numeric factorisations of every kind (Cholesky, LBLᵀ, LU).
    pub factorizations: u64,
    /// Of those, LU factorisations of the non-symmetric Jacobian: the later stages of an
    /// exact retry, after the symmetric approximation (Krylov-corrected) failed the solve.
    pub lu_factorizations: u64,
    /// Of those, LBLᵀ factorisations: the symmetric matrix was not positive definite.
    pub lblt_factorizations: u64,
    /// Newton iterations (linear solves), failed and rejected attempts included.
    pub iterations: u64,
    /// Newton solves: attempted time steps, failed and rejected ones included.
    pub solves: u64,
    /// Updates with a reused factorisation that were undone (non-finite residual).
    pub rejected: u64,
    /// Solves whose symmetric-approximation updates were corrected by BiCGStab towards the
    /// exact Newton update (the approximation was poor).
    pub approx_fallbacks: u64,
    /// BiCGStab iterations of those corrections.
    pub krylov_iterations: u64,
    /// Corrections that did not converge (the approximate update was kept).
    pub krylov_failures: u64,
    /// Solves that failed on the reused or approximate path and were retried with exact
    /// Newton, before the step was halved.
    pub exact_retries: u64,
    /// Of those, retries that converged (a halving saved).
    pub exact_retries_converged: u64,
    /// Retries that reached their pseudo-transient continuation stage.
    pub continuations: u64,
    /// Of those, continuations that converged.
    pub continuations_converged: u64,
    /// Retries that reached their step-size homotopy stage (continuation failed too).
    pub homotopies: u64,
    /// Of those, homotopies that converged (the step was taken whole instead of halved).
    pub homotopies_converged: u64,
    /// Solves that converged on the accuracy-based test rather than the force tolerance.
    pub accuracy_accepts: u64,
    /// Local error estimates filtered through the step's factors (`time.error_filter`).
    pub error_filters: u64,
    /// Estimates left unfiltered (no factors for the step's own dt, or not finite).
    pub error_filter_fallbacks: u64,
    /// Failed solves not retried: failed solves had already cost more factorisations than
    /// successful ones since the last sync point (the retry ledger, docs/engine.md §Exact
    /// retry). Counted since checkpoint format 6 (0 when resumed from an older one).
    pub exact_retries_skipped: u64,
    /// Wall time of element evaluation and assembly (s).
    pub assembly_s: f64,
    /// Wall time of the line search's energy evaluations (s).
    pub merit_s: f64,
    /// Wall time of the numeric factorisations (s).
    pub factor_s: f64,
    /// Wall time of the triangular solves and Krylov corrections (s).
    pub solve_s: f64,
}

impl SolverCounters {
    /// Number of counts ([`SolverCounters::counts`]).
    pub const COUNTS: usize = 21;
    /// Number of times ([`SolverCounters::seconds`]).
    pub const TIMES: usize = 4;

    /// The counters of a stepper's [`engine::Timings`].
    pub fn from_timings(t: &engine::Timings) -> Self {
        // Destructured without `..`: a counter added to the engine must be added here.
        let engine::Timings {
            assembly_s,
            merit_s,
            factor_s,
            solve_s,
            evaluations,
            jacobian_evaluations,
            factorizations,
            lu_factorizations,
            lblt_factorizations,
            iterations,
            solves,
            rejected,
            approx_fallbacks,
            krylov_iterations,
            krylov_failures,
            exact_retries,
            exact_retries_converged,
            continuations,
            continuations_converged,
            homotopies,
            homotopies_converged,
            accuracy_accepts,
            error_filters,
            error_filter_fallbacks,
            exact_retries_skipped,
        } = *t;
        Self {
            evaluations,
            jacobian_evaluations,
            factorizations,
            lu_factorizations,
            lblt_factorizations,
            iterations,
            solves,
            rejected,
            approx_fallbacks,
            krylov_iterations,
            krylov_failures,
            exact_retries,
            exact_retries_converged,
            continuations,
            continuations_converged,
            homotopies,
            homotopies_converged,
            accuracy_accepts,
            error_filters,
            error_filter_fallbacks,
            exact_retries_skipped,
            assembly_s,
            merit_s,
            factor_s,
            solve_s,
        }
    }

    /// The counts, in field order (the order of a checkpoint).
    pub fn counts(&self) -> [u64; Self::COUNTS] {
        [
            self.evaluations,
            self.jacobian_evaluations,
            self.factorizations,
            self.lu_factorizations,
            self.lblt_factorizations,
            self.iterations,
            self.solves,
            self.rejected,
            self.approx_fallbacks,
            self.krylov_iterations,
            self.krylov_failures,
            self.exact_retries,
            self.exact_retries_converged,
            self.continuations,
            self.continuations_converged,
            self.homotopies,
            self.homotopies_converged,
            self.accuracy_accepts,
            self.error_filters,
            self.error_filter_fallbacks,
            self.exact_retries_skipped,
        ]
    }

    /// The times (s), in field order.
    pub fn seconds(&self) -> [f64; Self::TIMES] {
        [self.assembly_s, self.merit_s, self.factor_s, self.solve_s]
    }

    /// The counters of [`SolverCounters::counts`] and [`SolverCounters::seconds`] (their
    /// inverse).
    pub fn from_parts(c: [u64; Self::COUNTS], s: [f64; Self::TIMES]) -> Self {
        Self {
            evaluations: c[0],
            jacobian_evaluations: c[1],
            factorizations: c[2],
            lu_factorizations: c[3],
            lblt_factorizations: c[4],
            iterations: c[5],
            solves: c[6],
            rejected: c[7],
            approx_fallbacks: c[8],
            krylov_iterations: c[9],
            krylov_failures: c[10],
            exact_retries: c[11],
            exact_retries_converged: c[12],
            continuations: c[13],
            continuations_converged: c[14],
            homotopies: c[15],
            homotopies_converged: c[16],
            accuracy_accepts: c[17],
            error_filters: c[18],
            error_filter_fallbacks: c[19],
            exact_retries_skipped: c[20],
            assembly_s: s[0],
            merit_s: s[1],
            factor_s: s[2],
            solve_s: s[3],
        }
    }

    /// The sum of `self` (an earlier part of the run) and `later`, field by field.
    pub fn plus(&self, later: &Self) -> Self {
        let (a, b) = (self.counts(), later.counts());
        let (x, y) = (self.seconds(), later.seconds());
        Self::from_parts(
            std::array::from_fn(|i| a[i] + b[i]),
            std::array::from_fn(|i| x[i] + y[i]),
        )
    }
}

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
            warnings,
        }
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

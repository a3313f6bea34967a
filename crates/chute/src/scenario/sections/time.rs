//! The `[time]` keys: the implicit Euler step, fixed or error-controlled (docs/adaptive-dt.md).

use super::super::keys::{choice, key, section, when, Bound, Cond};

/// The condition of the error-control keys.
const ADAPTIVE: Cond = when("time.adaptive", "true");
/// The rest of their "only used with" message.
const ADAPTIVE_ONLY: &str =
    " (an error-controlled step); set that, or remove this key (a fixed step uses time.dt_s)";

/// Default `time.error_tolerance_m` (m per step): at the start of a fall (a = g) it allows
/// `h = √(2 tol/g) ≈ 1.4 ms`, the report's 1 ms step with its local error `g dt²/2 ≈ 5 µm`,
/// so an adaptive run is at least as accurate as the report's fixed step in the transient and
/// only takes longer steps where the acceleration has decayed (docs/adaptive-dt.md).
pub const DEFAULT_ERROR_TOLERANCE_M: f64 = 1e-5;

choice! {
    /// Norm of an adaptive step's local error estimate.
    pub enum ErrorNorm {
        /// Mass-weighted RMS over the nodes.
        MassRms = "mass_rms",
        /// The largest component at any node.
        Max = "max",
    }
}

section! {
    /// `[time]`.
    pub struct Time {
        /// implicit Euler time step; with `adaptive = true` the first step
        dt_s: f64 = 1e-3 => key()
            .unit("s")
            .positive("a time step")
            .note("≤ `duration_s`, ≤ 10⁸ steps"),
        /// simulated time
        duration_s: f64 = 10.0 => key().unit("s").positive("a duration"),
        /// Newton iterations per step
        newton_max_iterations: usize = 25 => key()
            .between(1.0, 1000.0, "Newton iterations per step"),
        /// absolute tolerance on the residual force ‖R‖∞
        #[serde(skip_serializing_if = "Option::is_none")]
        newton_tolerance_n: Option<f64> = None => key()
            .unit("N")
            .positive("a residual force tolerance")
            .default_doc("engine default 1e-9 (1 + Σm·g)"),
        /// a step also converges when ‖R‖∞ ≤ this × the step's first residual
        #[serde(skip_serializing_if = "Option::is_none")]
        newton_relative_tolerance: Option<f64> = None => key()
            .range(Bound::Excl(0.0), Bound::Excl(1.0), "a fraction of the step's first residual")
            .default_doc("engine default 1e-10"),
        /// a step also converges when a Newton update has ‖Δq‖∞ below this (and ‖R‖∞ ≤ 1e3 ×
        /// the force tolerance)
        #[serde(skip_serializing_if = "Option::is_none")]
        newton_step_tolerance_m: Option<f64> = None => key()
            .unit("m (rad for twists)")
            .positive("a step tolerance")
            .default_doc("engine default 1e-12"),
        /// converge on the force tolerances alone, without the accuracy-based test (a step
        /// converges when its residual moves the state by ≤ 0.1 % of its local error, or each
        /// DOF's residual is ≤ 1e-4 of its weight; off too when `newton_tolerance_n` is set),
        /// with double-precision factors; for references and tests (written to the resolved
        /// scenario only when true)
        #[serde(skip_serializing_if = "std::ops::Not::not")]
        newton_strict: bool = false => key(),
        /// after a failed Newton stage, try the continuation and homotopy stages before the step
        /// is halved (false: halve at once; the retry ledger already bounds what they cost;
        /// written to the resolved scenario only when false)
        #[serde(skip_serializing_if = "Clone::clone")]
        newton_rescue_stages: bool = true => key().default_doc("`true`"),
        /// choose each step from its local error estimate instead of a fixed `dt_s` (written
        /// to the resolved scenario only when true)
        #[serde(skip_serializing_if = "std::ops::Not::not")]
        adaptive: bool = false => key(),
        /// `adaptive`: tolerance on the local position error per step, `(h/2)|v_{n+1} − v_n|`
        /// filtered through the step's Newton matrix (`error_filter`), in the norm
        /// `error_norm` (default: the mass-weighted RMS over the nodes, not the worst node)
        #[serde(skip_serializing_if = "Option::is_none")]
        error_tolerance_m: Option<f64> = None => key()
            .unit("m")
            .positive("a position error per step")
            .only_with(ADAPTIVE, ADAPTIVE_ONLY)
            .default_with(ADAPTIVE, DEFAULT_ERROR_TOLERANCE_M),
        /// `adaptive`: norm of the local error: `mass_rms` (√(Σ m_i |e_i|² / Σ m_i) over the
        /// nodes) or `max` (the worst node's component)
        #[serde(skip_serializing_if = "Option::is_none")]
        error_norm: Option<ErrorNorm> = None => key()
            .only_with(ADAPTIVE, ADAPTIVE_ONLY)
            .default_doc("`mass_rms`"),
        /// `adaptive`: filter the local error through the step's Newton matrix, (M + h D +
        /// h² K)⁻¹ M e, so that stiff modes that implicit Euler damps anyway do not limit the
        /// step (RADAU5's estimate; `false`: the raw estimate)
        #[serde(skip_serializing_if = "Option::is_none")]
        error_filter: Option<bool> = None => key()
            .only_with(ADAPTIVE, ADAPTIVE_ONLY)
            .default_doc("`true`"),
        /// `adaptive`: smallest step (a step this small is accepted whatever its error, with a
        /// warning; Newton failing below it stops the run)
        #[serde(skip_serializing_if = "Option::is_none")]
        dt_min_s: Option<f64> = None => key()
            .unit("s")
            .positive("a time step")
            .only_with(ADAPTIVE, ADAPTIVE_ONLY)
            .default_doc("`dt_s / 1024`")
            .note("≤ `dt_s`"),
        /// `adaptive`: largest step
        #[serde(skip_serializing_if = "Option::is_none")]
        dt_max_s: Option<f64> = None => key()
            .unit("s")
            .positive("a time step")
            .only_with(ADAPTIVE, ADAPTIVE_ONLY)
            .default_doc("min(100 `dt_s`, `output.frame_interval_s`)")
            .note("≥ `dt_s`, ≤ `output.frame_interval_s` (steps end on every frame time, so a longer one is never taken)"),
    }
}

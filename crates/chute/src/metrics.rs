//! Run metrics from the (decimated) time series: terminal velocity, time to terminal,
//! steadiness, force balance, drag area and Reynolds number; the recovery-system metrics
//! (loads, settling, atmosphere, landing) are in [`descent`], [`loads`] and [`landing`].
//!
//! All window statistics are time-weighted with trapezoid weights (wᵢ = half the time span
//! of the two intervals around sample i), so they do not depend on step-size changes or on the
//! decimation of [`crate::output::DecimatedSeries`]; the weighted mean equals the trapezoid
//! integral ∫f dt / Δt over the window. Definitions are in `docs/outputs.md`.

pub mod descent;
pub mod landing;
pub mod loads;
pub mod opening;

/// Fraction of the run (by time, measured from the first sample) forming the final window.
pub const FINAL_WINDOW_FRACTION: f64 = 0.2;
/// Half-width of the terminal band, relative to |v_t| (time to terminal: ±2 %).
pub const TERMINAL_BAND: f64 = 0.02;
/// Steadiness tolerance relative to |v_t| for both the std and the trend over the window.
pub const STEADY_TOLERANCE: f64 = 0.01;
/// Fewer samples than this in the final window: too short to judge steadiness.
pub const MIN_WINDOW_SAMPLES: usize = 10;
/// Below this Reynolds number quadratic (Newtonian, high-Re) drag is not a valid model.
pub const RE_QUADRATIC_MIN: f64 = 1000.0;
/// Force balance errors above this, in a steady descent, are flagged.
pub const FORCE_BALANCE_WARN: f64 = 0.05;
/// Speeds below this (m/s) count as zero: relative criteria and C_D·A are undefined there.
const V_ZERO: f64 = 1e-9;
/// Lateral growth: the running maximum of the lateral speed must grow by at least this factor
/// across the final window along an exponential fit …
pub const LATERAL_GROWTH_FACTOR: f64 = 10.0;
/// … that explains at least this fraction of the variance of its logarithm (R²).
pub const LATERAL_GROWTH_R2: f64 = 0.9;
/// A lateral speed above this fraction of |v_t| is visible (the steadiness tolerance).
pub const LATERAL_VISIBLE: f64 = STEADY_TOLERANCE;

/// Columns of the time series (equal lengths, times non-decreasing). SI units.
#[derive(Debug, Clone, Copy)]
pub struct Series<'a> {
    /// Simulated time (s).
    pub t_s: &'a [f64],
    /// Canopy mean vertical velocity (m/s; negative = descending).
    pub vz_mps: &'a [f64],
    /// Canopy mean x velocity (m/s).
    pub vx_mps: &'a [f64],
    /// Canopy mean y velocity (m/s).
    pub vy_mps: &'a [f64],
    /// Extended height, max z − min z over canopy nodes (m).
    pub extended_height_m: &'a [f64],
    /// Total drag along z (N; positive = upward).
    pub drag_z_n: &'a [f64],
    /// Exact maximum extended height over all steps, when the columns are decimated (m).
    pub exact_max_extended_height_m: Option<f64>,
}

/// Physical parameters needed by the metrics.
#[derive(Debug, Clone, Copy)]
pub struct Params {
    /// Total weight W = (Σ m) g of everything that falls (N), > 0.
    pub total_weight_n: f64,
    /// Air density ρ (kg/m³), > 0.
    pub air_density_kg_m3: f64,
    /// Air dynamic viscosity μ (Pa·s), > 0.
    pub air_viscosity_pa_s: f64,
    /// Reference length L for Re, e.g. the nominal canopy diameter (m), > 0.
    pub reference_length_m: f64,
    /// Whether the drag model is quadratic in speed (enables the low-Re warning).
    pub quadratic_drag: bool,
    /// Wind velocity U∞ (m/s): the Mach warning judges the canopy's speed through the air,
    /// `v − U∞`, which is what the drag laws see.
    pub wind_mps: [f64; 3],
}

/// Metrics of a run. Velocities in m/s, forces in N, lengths in m, times in s.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Metrics {
    /// v_t: time-weighted mean vz over the final window (signed; negative = descending).
    pub terminal_velocity_mps: f64,
    /// Time-weighted standard deviation of vz over the final window.
    pub terminal_velocity_std_mps: f64,
    /// Change of vz across the final window along its weighted least-squares line.
    pub terminal_velocity_trend_mps: f64,
    /// Steady descent: see [`compute`] for the four conditions.
    pub reached_terminal: bool,
    /// First time after which |vz − v_t| ≤ 2 % |v_t| for the rest of the run; `None` unless
    /// `reached_terminal`.
    pub time_to_terminal_s: Option<f64>,
    /// Maximum extended height over the run.
    pub max_extended_height_m: f64,
    /// Extended height at the last sample.
    pub final_extended_height_m: f64,
    /// W, as given.
    pub total_weight_n: f64,
    /// Time-weighted mean drag_z over the final window.
    pub mean_drag_z_n: f64,
    /// |mean drag_z − W| / W over the final window (dimensionless).
    pub force_balance_error: f64,
    /// C_D·A_eff = 2W / (ρ v_t²) (m²); `None` when |v_t| ≈ 0.
    pub drag_area_m2: Option<f64>,
    /// Time-weighted mean [vx, vy] over the final window.
    pub horizontal_velocity_mps: [f64; 2],
    /// Re = ρ |v_t| L / μ (dimensionless).
    pub reynolds_number: f64,
    /// Start of the final window.
    pub window_start_s: f64,
    /// End of the final window (time of the last sample).
    pub window_end_s: f64,
    /// Samples in the final window (including an interpolated point at its start).
    pub window_samples: usize,
    /// Exponential growth of the lateral speed over the final window (an instability of the
    /// descent), when detected: see [`compute`].
    pub lateral_growth: Option<LateralGrowth>,
    /// Human-readable caveats (short run, not steady, low Re, …).
    pub warnings: Vec<String>,
}

/// A lateral speed |v_h| = |(vx, vy)| growing exponentially: the descent is leaving an unstable
/// equilibrium, however steady vz still looks.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct LateralGrowth {
    /// Fitted growth rate σ of |v_h| ∝ e^{σ t} over the final window (1/s); e-folding time 1/σ.
    pub rate_per_s: f64,
    /// |v_h| at the last sample (m/s).
    pub final_speed_mps: f64,
    /// Start of the last stretch above [`LATERAL_VISIBLE`] |v_t| (interpolated); `None` while
    /// it is still below.
    pub visible_from_s: Option<f64>,
}

impl Metrics {
    /// Metrics of a run too short to measure anything (NaN values serialise as `null`).
    pub fn undefined(total_weight_n: f64) -> Self {
        Self {
            terminal_velocity_mps: f64::NAN,
            terminal_velocity_std_mps: f64::NAN,
            terminal_velocity_trend_mps: f64::NAN,
            reached_terminal: false,
            time_to_terminal_s: None,
            max_extended_height_m: f64::NAN,
            final_extended_height_m: f64::NAN,
            total_weight_n,
            mean_drag_z_n: f64::NAN,
            force_balance_error: f64::NAN,
            drag_area_m2: None,
            horizontal_velocity_mps: [f64::NAN; 2],
            reynolds_number: f64::NAN,
            window_start_s: f64::NAN,
            window_end_s: f64::NAN,
            window_samples: 0,
            lateral_growth: None,
            warnings: Vec::new(),
        }
    }
}

/// Invalid input to [`compute`].
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum MetricsError {
    /// No samples.
    #[error("the time series is empty")]
    Empty,
    /// Columns differ in length.
    #[error("time series columns have different lengths")]
    LengthMismatch,
    /// A NaN or infinite value at the given sample.
    #[error("non-finite value in the time series at sample {0}")]
    NonFinite(usize),
    /// Times decrease at the given sample.
    #[error("time decreases at sample {0}")]
    NonMonotonicTime(usize),
    /// A parameter that must be positive is not.
    #[error("parameter {0} must be positive and finite")]
    BadParameter(&'static str),
    /// The series ends at the time it starts (a run that stopped at its first step): no
    /// quantity was measured, and none is reported as if it had been (not 0, but null).
    #[error("no time elapsed (the series ends at its start, t = {0} s): nothing was measured")]
    NoTimeElapsed(f64),
}

/// Window samples: time and the averaged quantities (vz, drag_z, vx, vy).
struct Window {
    t: Vec<f64>,
    vals: Vec<[f64; 4]>,
    w: Vec<f64>,
}

/// Compute the run metrics.
///
/// - final window: [t_end − 0.2 (t_end − t_0), t_end], with a linearly interpolated sample at
///   its start;
/// - v_t, its std and trend, mean drag_z and mean [vx, vy]: trapezoid-weighted over the window;
/// - `reached_terminal` ⇔ (i) ≥ [`MIN_WINDOW_SAMPLES`] window samples, (ii) v_t < 0
///   (descending), (iii) std < 1 % |v_t| and |trend| < 1 % |v_t|, (iv) the ±2 % band holds over
///   the whole window, i.e. time to terminal ≤ window start, and (v) the lateral speed
///   |(vx, vy)| is not growing exponentially: its running maximum over the window does not
///   gain [`LATERAL_GROWTH_FACTOR`] along a fit ln M = a + σ t with R² ≥
///   [`LATERAL_GROWTH_R2`] while still at its maximum at the end (speeds below
///   1e3 ε (|v_t| + 1 m/s) are round-off and clamped to it);
/// - time to terminal: the last sample outside the ±2 % band and its successor are linearly
///   interpolated to find the band crossing (the first sample's time if none is outside).
pub fn compute(s: &Series<'_>, p: &Params) -> Result<Metrics, MetricsError> {
    validate(s, p)?;
    let n = s.t_s.len();
    let (t0, t_end) = (s.t_s[0], s.t_s[n - 1]);
    let window_start = t_end - FINAL_WINDOW_FRACTION * (t_end - t0);
    let win = final_window(s, window_start);
    let [v_t, drag_z, vx, vy] = weighted_means(&win);
    let std = weighted_std(&win, v_t);
    let trend = weighted_trend(&win);
    let speed = v_t.abs();
    let band_entry = band_entry_time(s.t_s, s.vz_mps, v_t);
    let slice_max = s
        .extended_height_m
        .iter()
        .copied()
        .fold(f64::NEG_INFINITY, f64::max);
    let mut m = Metrics {
        terminal_velocity_mps: v_t,
        terminal_velocity_std_mps: std,
        terminal_velocity_trend_mps: trend,
        reached_terminal: false,
        time_to_terminal_s: None,
        max_extended_height_m: slice_max.max(s.exact_max_extended_height_m.unwrap_or(slice_max)),
        final_extended_height_m: s.extended_height_m[n - 1],
        total_weight_n: p.total_weight_n,
        mean_drag_z_n: drag_z,
        force_balance_error: (drag_z - p.total_weight_n).abs() / p.total_weight_n,
        drag_area_m2: (speed > V_ZERO)
            .then(|| 2.0 * p.total_weight_n / (p.air_density_kg_m3 * v_t * v_t)),
        horizontal_velocity_mps: [vx, vy],
        reynolds_number: p.air_density_kg_m3 * speed * p.reference_length_m / p.air_viscosity_pa_s,
        window_start_s: window_start,
        window_end_s: t_end,
        window_samples: win.t.len(),
        lateral_growth: lateral_growth(s, &win, v_t),
        warnings: Vec::new(),
    };
    judge_steadiness(&mut m, band_entry, p);
    m.warnings
        .extend(mach_warning(peak_airspeed_mps(s, p.wind_mps)));
    Ok(m)
}

/// Glide angle (degrees from the vertical) of a descent with horizontal velocity `v_h` and
/// vertical velocity `v_z`: atan(|v_h| / |v_z|); 90° when not descending, NaN when unknown.
pub fn glide_angle_deg(v_h: [f64; 2], v_z: f64) -> f64 {
    v_h[0].hypot(v_h[1]).atan2(v_z.abs()).to_degrees()
}

/// Speed of sound (m/s) in the standard sea-level atmosphere (15 °C), until the atmosphere
/// model gives a local one.
pub const SPEED_OF_SOUND_MPS: f64 = 340.3;
/// Mach number above which air is compressible: the quadratic drag law (constant C_D,
/// incompressible flow) no longer holds.
pub const MACH_INCOMPRESSIBLE_MAX: f64 = 0.3;

/// Largest canopy airspeed |(vx, vy, vz) − U∞| of the series (m/s), or 0 when the first
/// sample's is larger than every later one: a canopy starting at rest in a strong wind is fastest through the air
/// at the start, which `chute check`'s warning (scenario::limits) already names, and the run
/// then only slows it down.
fn peak_airspeed_mps(s: &Series<'_>, wind: [f64; 3]) -> f64 {
    let speed = |i: usize| {
        let c = |col: &[f64], k: usize| col.get(i).copied().unwrap_or(0.0) - wind[k];
        (c(s.vx_mps, 0).powi(2) + c(s.vy_mps, 1).powi(2) + c(s.vz_mps, 2).powi(2)).sqrt()
    };
    let first = speed(0);
    let later = (1..s.t_s.len()).map(speed).fold(0.0, f64::max);
    if later >= first {
        later
    } else {
        0.0
    }
}

/// The warning for a canopy whose airspeed reached `peak_speed_mps`, when that is above Mach
/// [`MACH_INCOMPRESSIBLE_MAX`].
pub fn mach_warning(peak_speed_mps: f64) -> Option<String> {
    let mach = peak_speed_mps / SPEED_OF_SOUND_MPS;
    (mach > MACH_INCOMPRESSIBLE_MAX).then(|| {
        format!(
            "the canopy reached {peak_speed_mps:.1} m/s through the air, Mach {mach:.2} (speed of sound {SPEED_OF_SOUND_MPS} m/s): \
             above Mach {MACH_INCOMPRESSIBLE_MAX} air is compressible and the drag law does not hold; check the load and the material"
        )
    })
}

/// Decide `reached_terminal`/`time_to_terminal_s` and collect the warnings.
fn judge_steadiness(m: &mut Metrics, band_entry: Option<f64>, p: &Params) {
    let speed = m.terminal_velocity_mps.abs();
    let long_enough = m.window_samples >= MIN_WINDOW_SAMPLES;
    let descending = m.terminal_velocity_mps < -V_ZERO;
    let steady = m.terminal_velocity_std_mps < STEADY_TOLERANCE * speed
        && m.terminal_velocity_trend_mps.abs() < STEADY_TOLERANCE * speed;
    let in_band = band_entry.is_some_and(|t| t <= m.window_start_s);
    let growing = m.lateral_growth.is_some();
    m.reached_terminal = long_enough && descending && steady && in_band && !growing;
    m.time_to_terminal_s = if m.reached_terminal { band_entry } else { None };
    let w = &mut m.warnings;
    if !long_enough {
        w.push(format!(
            "run too short to judge terminal velocity: {} samples in the final {:.0} % window \
             (need at least {MIN_WINDOW_SAMPLES})",
            m.window_samples,
            FINAL_WINDOW_FRACTION * 100.0
        ));
    }
    if !descending {
        w.push(format!(
            "canopy is not descending over the final window (mean vz = {:.6} m/s)",
            m.terminal_velocity_mps
        ));
    }
    if let Some(g) = m.lateral_growth {
        w.push(growth_warning(&g, speed, m.window_end_s));
    } else if long_enough && descending && !m.reached_terminal {
        w.push(format!(
            "terminal velocity not reached: over the final window std(vz) = {:.3} % and trend = \
             {:.3} % of |v_t| (limits {:.0} % each), ±{:.0} % band {} the whole window",
            100.0 * m.terminal_velocity_std_mps / speed,
            100.0 * m.terminal_velocity_trend_mps.abs() / speed,
            100.0 * STEADY_TOLERANCE,
            100.0 * TERMINAL_BAND,
            if in_band {
                "holds over"
            } else {
                "does not hold over"
            }
        ));
    }
    if m.reached_terminal && m.force_balance_error > FORCE_BALANCE_WARN {
        w.push(format!(
            "steady descent but drag_z differs from the weight by {:.2} % (> {:.0} %)",
            100.0 * m.force_balance_error,
            100.0 * FORCE_BALANCE_WARN
        ));
    }
    if p.quadratic_drag && m.reynolds_number < RE_QUADRATIC_MIN {
        w.push(format!(
            "Reynolds number {:.3e} < {RE_QUADRATIC_MIN}: quadratic drag is not valid at low Re",
            m.reynolds_number
        ));
    }
}

fn growth_warning(g: &LateralGrowth, speed: f64, t_end: f64) -> String {
    let seen = match g.visible_from_s {
        Some(t) => format!(
            "it became visible (> {:.0} % of |v_t|) at t = {t:.2} s",
            100.0 * LATERAL_VISIBLE
        ),
        None => {
            let at = t_end + (LATERAL_VISIBLE * speed / g.final_speed_mps).ln() / g.rate_per_s;
            format!(
                "it is still below {:.0} % of |v_t| and would pass it at t ≈ {at:.1} s",
                100.0 * LATERAL_VISIBLE
            )
        }
    };
    format!(
        "lateral velocity grows exponentially: |(vx, vy)| = {:.3e} m/s at t = {t_end:.2} s, \
         growth rate {:.3} /s (e-folding every {:.3} s) over the final window; {seen}. The \
         descent is leaving an unstable equilibrium: terminal velocity not reached",
        g.final_speed_mps,
        g.rate_per_s,
        1.0 / g.rate_per_s
    )
}

/// Exponential growth of the lateral speed u = |(vx, vy)| over the final window: the running
/// maximum M of u (so that a growing oscillation counts by its envelope) is fitted by
/// ln M = a + σ t (trapezoid weights); growth when the fit gains at least
/// [`LATERAL_GROWTH_FACTOR`] across the window with R² ≥ [`LATERAL_GROWTH_R2`] and u is still
/// at its maximum at the end (≥ ½ M). Speeds below 1e3 ε (|v_t| + 1 m/s) are round-off and
/// clamped to it, so noise at the level of the last digit is never "growth".
fn lateral_growth(s: &Series<'_>, win: &Window, v_t: f64) -> Option<LateralGrowth> {
    let floor = 1e3 * f64::EPSILON * (v_t.abs() + 1.0);
    let mut running = 0.0f64;
    let y: Vec<f64> = win
        .vals
        .iter()
        .map(|v| {
            running = running.max(v[2].hypot(v[3]));
            running.max(floor).ln()
        })
        .collect();
    let (sigma, r2) = weighted_line(&win.t, &y, &win.w)?;
    let duration = win.t[win.t.len() - 1] - win.t[0];
    let last = win.vals[win.vals.len() - 1];
    let u_end = last[2].hypot(last[3]);
    let grows = win.t.len() >= MIN_WINDOW_SAMPLES
        && sigma > 0.0
        && sigma * duration >= LATERAL_GROWTH_FACTOR.ln()
        && r2 >= LATERAL_GROWTH_R2
        && u_end >= 0.5 * running;
    if !grows {
        return None;
    }
    let threshold = LATERAL_VISIBLE * v_t.abs();
    let u = |i: usize| s.vx_mps[i].hypot(s.vy_mps[i]);
    let n = s.t_s.len();
    let visible_from_s =
        (u(n - 1) > threshold).then(|| match (0..n).rev().find(|&i| u(i) <= threshold) {
            None => s.t_s[0],
            Some(i) => {
                let a = (threshold - u(i)) / (u(i + 1) - u(i));
                s.t_s[i] + a * (s.t_s[i + 1] - s.t_s[i])
            }
        });
    Some(LateralGrowth {
        rate_per_s: sigma,
        final_speed_mps: u_end,
        visible_from_s,
    })
}

/// Weighted least-squares slope of y(t) and its R² (1 when y is exactly linear; also 1 for
/// a constant y). `None` for a zero-length window.
fn weighted_line(t: &[f64], y: &[f64], w: &[f64]) -> Option<(f64, f64)> {
    let w_sum: f64 = w.iter().sum();
    let mean = |v: &[f64]| w.iter().zip(v).map(|(w, x)| w * x).sum::<f64>() / w_sum;
    let (tm, ym) = (mean(t), mean(y));
    let (mut sty, mut stt, mut syy) = (0.0, 0.0, 0.0);
    for ((w, t), y) in w.iter().zip(t).zip(y) {
        sty += w * (t - tm) * (y - ym);
        stt += w * (t - tm).powi(2);
        syy += w * (y - ym).powi(2);
    }
    if stt <= 0.0 {
        return None;
    }
    let slope = sty / stt;
    let r2 = if syy > 0.0 { slope * sty / syy } else { 1.0 };
    Some((slope, r2))
}

fn validate(s: &Series<'_>, p: &Params) -> Result<(), MetricsError> {
    let n = s.t_s.len();
    if n == 0 {
        return Err(MetricsError::Empty);
    }
    let cols = [
        s.vz_mps,
        s.vx_mps,
        s.vy_mps,
        s.extended_height_m,
        s.drag_z_n,
    ];
    if cols.iter().any(|c| c.len() != n) {
        return Err(MetricsError::LengthMismatch);
    }
    for i in 0..n {
        if !s.t_s[i].is_finite() || cols.iter().any(|c| !c[i].is_finite()) {
            return Err(MetricsError::NonFinite(i));
        }
        if i > 0 && s.t_s[i] < s.t_s[i - 1] {
            return Err(MetricsError::NonMonotonicTime(i));
        }
    }
    if s.t_s[n - 1] <= s.t_s[0] {
        return Err(MetricsError::NoTimeElapsed(s.t_s[0]));
    }
    let positive = |x: f64| x.is_finite() && x > 0.0;
    for (name, x) in [
        ("total_weight_n", p.total_weight_n),
        ("air_density_kg_m3", p.air_density_kg_m3),
        ("air_viscosity_pa_s", p.air_viscosity_pa_s),
        ("reference_length_m", p.reference_length_m),
    ] {
        if !positive(x) {
            return Err(MetricsError::BadParameter(name));
        }
    }
    Ok(())
}

/// Samples with t ≥ `start`, preceded by a linearly interpolated sample at `start` when it
/// falls strictly between two samples; trapezoid weights attached.
fn final_window(s: &Series<'_>, start: f64) -> Window {
    let first = s.t_s.partition_point(|&t| t < start);
    let at = |i: usize| [s.vz_mps[i], s.drag_z_n[i], s.vx_mps[i], s.vy_mps[i]];
    let mut t = Vec::with_capacity(s.t_s.len() - first + 1);
    let mut vals = Vec::with_capacity(t.capacity());
    if first > 0 && s.t_s[first] > start {
        let (ta, tb) = (s.t_s[first - 1], s.t_s[first]);
        let a = (start - ta) / (tb - ta);
        let (fa, fb) = (at(first - 1), at(first));
        t.push(start);
        vals.push(std::array::from_fn(|k| fa[k] + a * (fb[k] - fa[k])));
    }
    for i in first..s.t_s.len() {
        t.push(s.t_s[i]);
        vals.push(at(i));
    }
    let m = t.len();
    let mut w = vec![0.0; m];
    for i in 0..m.saturating_sub(1) {
        let half = 0.5 * (t[i + 1] - t[i]);
        w[i] += half;
        w[i + 1] += half;
    }
    // A zero-length window (single sample or repeated times): fall back to equal weights.
    if w.iter().sum::<f64>() <= 0.0 {
        w.fill(1.0);
    }
    Window { t, vals, w }
}

fn weighted_means(win: &Window) -> [f64; 4] {
    let w_sum: f64 = win.w.iter().sum();
    std::array::from_fn(|k| {
        win.w
            .iter()
            .zip(&win.vals)
            .map(|(w, v)| w * v[k])
            .sum::<f64>()
            / w_sum
    })
}

/// sqrt(Σ wᵢ (vzᵢ − mean)² / Σ wᵢ).
fn weighted_std(win: &Window, mean: f64) -> f64 {
    let w_sum: f64 = win.w.iter().sum();
    let var = win
        .w
        .iter()
        .zip(&win.vals)
        .map(|(w, v)| w * (v[0] - mean).powi(2))
        .sum::<f64>();
    (var / w_sum).sqrt()
}

/// Weighted least-squares slope of vz(t) times the window duration: the change of vz across
/// the window along the fitted line (m/s). Zero for a zero-length window.
fn weighted_trend(win: &Window) -> f64 {
    let w_sum: f64 = win.w.iter().sum();
    let t_mean = win.w.iter().zip(&win.t).map(|(w, t)| w * t).sum::<f64>() / w_sum;
    let v_mean = weighted_means(win)[0];
    let (mut stv, mut stt) = (0.0, 0.0);
    for ((w, t), v) in win.w.iter().zip(&win.t).zip(&win.vals) {
        stv += w * (t - t_mean) * (v[0] - v_mean);
        stt += w * (t - t_mean).powi(2);
    }
    let duration = win.t[win.t.len() - 1] - win.t[0];
    if stt > 0.0 {
        stv / stt * duration
    } else {
        0.0
    }
}

/// First time after which |vz − v_t| ≤ 2 % |v_t| for the rest of the series, or `None` when the
/// last sample is outside the band. The crossing between the last outside sample and its
/// successor is found by linear interpolation.
pub fn band_entry_time(t: &[f64], vz: &[f64], v_t: f64) -> Option<f64> {
    let band = TERMINAL_BAND * v_t.abs();
    let outside = |v: f64| (v - v_t).abs() > band;
    let Some(i) = vz.iter().rposition(|&v| outside(v)) else {
        return t.first().copied();
    };
    if i + 1 == vz.len() {
        return None;
    }
    let edge = if vz[i] > v_t { v_t + band } else { v_t - band };
    let a = (edge - vz[i]) / (vz[i + 1] - vz[i]);
    Some(t[i] + a * (t[i + 1] - t[i]))
}

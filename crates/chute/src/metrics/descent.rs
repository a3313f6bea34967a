//! Recovery-system metrics of a descent: the handbook's canopy loading, the dynamic pressure
//! and nominal drag coefficient of the terminal descent, the settling time of the drag area,
//! the equivalent sea-level descent rate, the final altitude, and (with [`super::loads`] and
//! [`super::landing`]) the payload loads and the landing. Window statistics are
//! time-weighted like those of [`super::compute`], over the same final window. Definitions
//! and formulas in docs/engineering.md.

use engine::aero::Fluid;

use super::landing::Landing;
use super::loads;

/// Sea-level density of the 1976 standard atmosphere (kg/m³): the reference of the
/// equivalent sea-level descent rate.
pub const SEA_LEVEL_DENSITY: f64 = 1.225;
/// Half-width of the settling band, relative to the final drag area (±2 %).
pub const SETTLING_BAND: f64 = 0.02;
/// Speeds below this (m/s) give no drag area.
const V_ZERO: f64 = 1e-9;

/// The columns and exact peaks the recovery metrics use (equal lengths, SI units).
#[derive(Debug, Clone, Copy)]
pub struct RecoverySeries<'a> {
    /// Time (s).
    pub t_s: &'a [f64],
    /// Canopy mean vertical velocity (m/s).
    pub vz_mps: &'a [f64],
    /// Total drag along z (N).
    pub drag_z_n: &'a [f64],
    /// Canopy mean height (m, model frame).
    pub z_m: &'a [f64],
    /// Payload height (m; the canopy's without a payload).
    pub z_payload_m: &'a [f64],
    /// Line tension on the payload (N).
    pub line_tension_n: &'a [f64],
    /// Payload–canopy axis angle from the vertical (degrees).
    pub axis_angle_deg: &'a [f64],
    /// Projected canopy diameter (m).
    pub canopy_diameter_m: &'a [f64],
    /// Exact peak line tension over every step: (time (s), tension (N)).
    pub peak_line_tension: (f64, f64),
    /// Exact peak payload acceleration over every step (m/s²).
    pub peak_payload_acceleration_mps2: f64,
}

/// What the recovery metrics need besides the series.
#[derive(Debug, Clone)]
pub struct RecoveryParams {
    /// Total weight W (N).
    pub total_weight_n: f64,
    /// Flat canopy area S₀ (m²).
    pub planform_area_m2: f64,
    /// The air (density at each height).
    pub fluid: Fluid,
    /// Geometric altitude of the model's z = 0 (m).
    pub altitude_m: f64,
    /// Gravitational acceleration (m/s²).
    pub gravity_mps2: f64,
    /// Whether the load hangs on lines (payload loads are reported).
    pub payload: bool,
    /// Horizontal position of the canopy's centre at t = 0 (m).
    pub release_point_m: [f64; 2],
    /// The opening of a packed canopy (`[opening]`; `None` for a flat start).
    pub opening: Option<super::opening::OpeningParams>,
}

/// The recovery fields of `summary.json` (null when not defined).
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct Recovery {
    /// W/S₀ (Pa).
    pub canopy_loading_pa: Option<f64>,
    /// ½ ρ v_t² with ρ at the final window's mean height (Pa).
    pub terminal_dynamic_pressure_pa: Option<f64>,
    /// C_D0 = drag area / S₀.
    pub drag_coefficient_nominal: Option<f64>,
    /// First time after which the drag area stays within ±2 % of its final-window mean (s).
    pub settling_time_s: Option<f64>,
    /// Mean over the final window of vz √(ρ(z)/ρ_SL) (m/s, signed like v_t).
    pub equivalent_sea_level_descent_mps: Option<f64>,
    /// Geometric altitude of the payload (the canopy without one) at the end (m).
    pub altitude_m: Option<f64>,
    /// Largest line tension (N).
    pub peak_line_tension_n: Option<f64>,
    /// Time of the largest line tension (s).
    pub time_of_peak_line_tension_s: Option<f64>,
    /// Peak over steady line tension.
    pub load_factor: Option<f64>,
    /// Largest payload acceleration (g).
    pub peak_payload_acceleration_g: Option<f64>,
    /// Amplitude of the payload–canopy axis angle over the final window (degrees).
    pub oscillation_angle_deg: Option<f64>,
    /// Payload vertical velocity at touchdown (m/s).
    pub landing_velocity_mps: Option<f64>,
    /// Time of touchdown (s).
    pub flight_time_s: Option<f64>,
    /// [x, y] of touchdown (m).
    pub landing_point_m: Option<[f64; 2]>,
    /// Horizontal distance from the release point to the touchdown (m).
    pub drift_m: Option<f64>,
    /// Distance from the touchdown to `guidance.target_m` (m); null without guidance or
    /// landing.
    pub landing_miss_m: Option<f64>,
    /// Opening shock: the largest force of the lines on the payload (N); null without
    /// `[opening]`.
    pub opening_peak_force_n: Option<f64>,
    /// `opening_peak_force_n` over the steady drag area times the dynamic pressure at line
    /// stretch (Knacke's C_x X₁); null without `[opening]` or a steady descent.
    pub opening_load_factor: Option<f64>,
    /// From line stretch to the projected diameter's first reaching 95 % of its steady value
    /// (s); null without `[opening]` or a steady descent.
    pub opening_fill_time_s: Option<f64>,
    /// The canopy's fall over the fill time, in nominal diameters √(4 S₀/π); null like the
    /// fill time.
    pub opening_fill_distance_diameters: Option<f64>,
}

/// Start of the final window of [`super::compute`] for the times `t` (s).
pub fn window_start(t: &[f64]) -> f64 {
    let (t0, t_end) = (t[0], t[t.len() - 1]);
    t_end - super::FINAL_WINDOW_FRACTION * (t_end - t0)
}

/// The air at the time-weighted mean canopy height over the final window: what the
/// terminal-velocity metrics (drag area, Reynolds number) use; the fluid's own values for
/// a uniform fluid.
pub fn window_air(t: &[f64], z: &[f64], fluid: &Fluid) -> engine::aero::LocalFluid {
    if fluid.is_uniform() || t.is_empty() {
        return fluid.at(0.0);
    }
    fluid.at(window_mean(t, z, window_start(t)))
}

/// Time-weighted (trapezoid) mean of `f(t)` over `[start, t_end]`, with the value at `start`
/// interpolated; the plain mean of a zero-length window.
pub fn window_mean(t: &[f64], f: &[f64], start: f64) -> f64 {
    let first = t.partition_point(|&x| x < start);
    let mut pts: Vec<(f64, f64)> = Vec::with_capacity(t.len() - first + 1);
    if first > 0 && first < t.len() && t[first] > start {
        let a = (start - t[first - 1]) / (t[first] - t[first - 1]);
        pts.push((start, f[first - 1] + a * (f[first] - f[first - 1])));
    }
    pts.extend((first..t.len()).map(|i| (t[i], f[i])));
    let (mut area, mut span) = (0.0, 0.0);
    for w in pts.windows(2) {
        let dt = w[1].0 - w[0].0;
        area += 0.5 * dt * (w[0].1 + w[1].1);
        span += dt;
    }
    if span > 0.0 {
        area / span
    } else {
        pts.iter().map(|p| p.1).sum::<f64>() / pts.len().max(1) as f64
    }
}

/// First time after which `f` stays within `±band·|mean|` of `mean`, the crossing from the
/// last sample outside interpolated linearly; `None` when the last sample is outside. A
/// non-finite sample is outside.
pub fn settles_at(t: &[f64], f: &[f64], mean: f64, band: f64) -> Option<f64> {
    let half = band * mean.abs();
    let outside = |x: f64| !x.is_finite() || (x - mean).abs() > half;
    let Some(i) = f.iter().rposition(|&x| outside(x)) else {
        return t.first().copied();
    };
    if i + 1 == f.len() {
        return None;
    }
    if !f[i].is_finite() {
        return Some(t[i + 1]);
    }
    let edge = if f[i] > mean {
        mean + half
    } else {
        mean - half
    };
    let a = (edge - f[i]) / (f[i + 1] - f[i]);
    Some(t[i] + a * (t[i + 1] - t[i]))
}

/// The recovery metrics of `s`, given the terminal velocity `v_t` (m/s) and drag area (m²)
/// of [`super::compute`] and the landing, if the run reached the ground.
pub fn compute(
    s: &RecoverySeries<'_>,
    p: &RecoveryParams,
    v_t: f64,
    drag_area_m2: Option<f64>,
    landing: Option<Landing>,
) -> Recovery {
    let n = s.t_s.len();
    let mut r = Recovery {
        canopy_loading_pa: Some(p.total_weight_n / p.planform_area_m2),
        drag_coefficient_nominal: drag_area_m2.map(|a| a / p.planform_area_m2),
        landing_velocity_mps: landing.map(|l| l.velocity_mps),
        flight_time_s: landing.map(|l| l.flight_time_s),
        landing_point_m: landing.map(|l| l.point_m),
        drift_m: landing.map(|l| {
            let r = p.release_point_m;
            (l.point_m[0] - r[0]).hypot(l.point_m[1] - r[1])
        }),
        ..Default::default()
    };
    if n == 0 {
        return r;
    }
    let start = window_start(s.t_s);
    let rho = |z: f64| p.fluid.at(z).density;
    let air = window_air(s.t_s, s.z_m, &p.fluid);
    r.terminal_dynamic_pressure_pa = v_t.is_finite().then_some(0.5 * air.density * v_t * v_t);
    // Instantaneous drag area 2 drag_z / (ρ(z) vz²) while descending.
    let cda: Vec<f64> = (0..n)
        .map(|i| {
            let v = s.vz_mps[i];
            if v < -V_ZERO {
                2.0 * s.drag_z_n[i] / (rho(s.z_m[i]) * v * v)
            } else {
                f64::NAN
            }
        })
        .collect();
    let in_window = |i: usize| s.t_s[i] >= start;
    if (0..n).filter(|&i| in_window(i)).all(|i| cda[i].is_finite()) {
        let mean = window_mean(s.t_s, &cda, start);
        r.settling_time_s = settles_at(s.t_s, &cda, mean, SETTLING_BAND);
    }
    let equivalent: Vec<f64> = (0..n)
        .map(|i| s.vz_mps[i] * (rho(s.z_m[i]) / SEA_LEVEL_DENSITY).sqrt())
        .collect();
    r.equivalent_sea_level_descent_mps = Some(window_mean(s.t_s, &equivalent, start));
    r.altitude_m = Some(p.altitude_m + s.z_payload_m[n - 1]);
    if p.payload {
        if let Some(l) = loads::compute(s, start, p.gravity_mps2) {
            r.peak_line_tension_n = Some(l.peak_line_tension_n);
            r.time_of_peak_line_tension_s = Some(l.time_of_peak_line_tension_s);
            r.load_factor = l.load_factor;
            r.peak_payload_acceleration_g = Some(l.peak_payload_acceleration_g);
            r.oscillation_angle_deg = Some(l.oscillation_angle_deg);
        }
    }
    if let Some(op) = &p.opening {
        let series = (s.t_s, s.z_m, s.canopy_diameter_m);
        let peak = r.peak_line_tension_n;
        let o = super::opening::compute(series, peak, drag_area_m2, start, op);
        r.opening_peak_force_n = o.peak_force_n;
        r.opening_load_factor = o.load_factor;
        r.opening_fill_time_s = o.fill_time_s;
        r.opening_fill_distance_diameters = o.fill_distance_diameters;
    }
    r
}

//! Loads on the payload in payload mode: the confluence load (the resultant force of the
//! suspension lines on the payload), its peak over the transition from the flat start to
//! steady descent, the load factor, the payload's peak acceleration and the oscillation of
//! the payload–canopy axis. Definitions in docs/engineering.md.

use super::descent::{window_mean, RecoverySeries};

/// Payload loads of a run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Loads {
    /// Largest line tension of the run (N).
    pub peak_line_tension_n: f64,
    /// When it occurred (s).
    pub time_of_peak_line_tension_s: f64,
    /// Peak over the steady line tension (the time-weighted mean over the final window).
    pub load_factor: Option<f64>,
    /// Largest payload acceleration of the run in units of g.
    pub peak_payload_acceleration_g: f64,
    /// Largest angle between the vertical and the payload–canopy axis over the final window
    /// (degrees): the amplitude of a swing (or the half-angle of a coning motion).
    pub oscillation_angle_deg: f64,
}

/// The loads of `s` with the final window starting at `window_start_s` (s) and gravity
/// `gravity_mps2`; `None` for an empty series.
pub fn compute(s: &RecoverySeries<'_>, window_start_s: f64, gravity_mps2: f64) -> Option<Loads> {
    let (t_peak, peak) = s.peak_line_tension;
    if s.t_s.is_empty() || !peak.is_finite() {
        return None;
    }
    let steady = window_mean(s.t_s, s.line_tension_n, window_start_s);
    let oscillation = s
        .t_s
        .iter()
        .zip(s.axis_angle_deg)
        .filter(|(&t, _)| t >= window_start_s)
        .map(|(_, &a)| a)
        .fold(0.0, f64::max);
    Some(Loads {
        peak_line_tension_n: peak,
        time_of_peak_line_tension_s: t_peak,
        load_factor: (steady > 0.0).then(|| peak / steady),
        peak_payload_acceleration_g: s.peak_payload_acceleration_mps2 / gravity_mps2,
        oscillation_angle_deg: oscillation,
    })
}

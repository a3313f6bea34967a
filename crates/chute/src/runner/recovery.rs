//! What the run loop hands the recovery metrics: the air of the final window and the
//! parameters of [`crate::metrics::descent::compute`].

use super::RunConfig;
use crate::build::Built;
use crate::metrics::descent::{self, RecoveryParams};
use crate::output::timeseries::DecimatedSeries;

/// (ρ, μ) of the summary's one-density metrics: the fluid's constants when it is uniform,
/// otherwise the air at the time-weighted mean canopy height of the final window.
pub(super) fn window_air(dec: &DecimatedSeries, cfg: &RunConfig) -> (f64, f64) {
    if cfg.air.is_uniform() {
        return (cfg.air.density, cfg.air.viscosity);
    }
    let air = descent::window_air(&dec.t_s, &dec.z_m, &cfg.air);
    (air.density, air.viscosity)
}

/// The recovery metrics' parameters of model `b` run with `cfg`.
pub(super) fn params(b: &Built, cfg: &RunConfig) -> RecoveryParams {
    RecoveryParams {
        total_weight_n: b.total_weight_n,
        planform_area_m2: b.planform_area_m2,
        fluid: cfg.air.clone(),
        altitude_m: cfg.altitude_m,
        gravity_mps2: cfg.gravity_mps2,
        payload: b.payload_node.is_some(),
        release_point_m: b.release_point_m,
        opening: b
            .opening_speed_mps
            .map(|v| crate::metrics::opening::OpeningParams {
                nominal_diameter_m: (4.0 * b.planform_area_m2 / std::f64::consts::PI).sqrt(),
                line_stretch_pressure_pa: 0.5 * cfg.air.at(0.0).density * v * v,
            }),
    }
}

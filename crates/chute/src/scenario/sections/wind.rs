//! `[wind]`: a wind that varies with height (docs/aero.md §Wind that varies with height). Absent, the wind is
//! `fluid.wind_mps` at every height.

use std::path::PathBuf;

use super::super::keys::{choice, key, section, when, Cond};

/// The condition of the power law's key.
const POWER: Cond = when("wind.profile", "power");
/// The condition of the logarithmic law's key.
const LOG: Cond = when("wind.profile", "log");
/// The condition of the table's key.
const TABLE: Cond = when("wind.profile", "table");

choice! {
    /// How the wind varies with height.
    pub enum WindLaw {
        /// `U = U_ref (h/h_ref)^α` of the height h above the ground.
        Power = "power",
        /// `U = U_ref ln(h/z₀)/ln(h_ref/z₀)`.
        Log = "log",
        /// Horizontal winds against altitude, from a CSV file.
        Table = "table",
    }
}

section! {
    /// `[wind]`: how the wind varies with height.
    pub struct Wind {
        /// `power`, `log`: `fluid.wind_mps` is the wind at `reference_height_m` above the
        /// ground (`atmosphere.ground_altitude_m`, or altitude 0 without one); `table`: the
        /// winds of `file`
        profile: WindLaw = WindLaw::Power => key()
            .required("say how the wind varies: `profile = \"power\"`, `\"log\"` or `\"table\"`"),
        /// `power`, `log`: height above the ground where the wind is `fluid.wind_mps` (10 m:
        /// the standard anemometer height)
        reference_height_m: f64 = 10.0 => key().unit("m").positive("a height"),
        /// `power`: exponent α (about 1/7 over open country, more over towns)
        #[serde(skip_serializing_if = "Option::is_none")]
        exponent: Option<f64> = None => key()
            .between(0.0, 1.0, "a boundary-layer exponent")
            .only_with(POWER, "")
            .required_with(POWER, "needs the exponent α, e.g. `exponent = 0.143`"),
        /// `log`: roughness length z₀ (about 0.03 m over open grass, 1 m over towns)
        #[serde(skip_serializing_if = "Option::is_none")]
        roughness_m: Option<f64> = None => key()
            .unit("m")
            .positive("a length")
            .only_with(LOG, "")
            .required_with(LOG, "needs the roughness length z₀, e.g. `roughness_m = 0.03`")
            .note("< `reference_height_m`"),
        /// `table`: CSV with the header `altitude_m,vx_mps,vy_mps` (geometric altitude, as
        /// `atmosphere.altitude_m`); between rows the wind follows a monotone cubic, beyond
        /// the first and last it is held; relative paths resolve against the scenario file
        #[serde(skip_serializing_if = "Option::is_none")]
        file: Option<PathBuf> = None => key()
            .only_with(TABLE, "")
            .required_with(TABLE, "needs the CSV of winds, e.g. `file = \"winds.csv\"`")
            .note("2–10⁴ rows, altitudes increasing; `fluid.wind_mps` must then be zero"),
    }
}

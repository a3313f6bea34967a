//! The line-pull keys: `[[sensor]]` (instruments that can start a pull), `[[control]]`
//! (scheduled or sensor-started pulls) and `[guidance]` (steering to a target), all
//! payload-mode only (docs/control.md).

use super::super::keys::{choice, key, section};

section! {
    /// One `[[control]]` entry: a scheduled pull on suspension lines (docs/control.md).
    pub struct Control {
        /// pulled lines: 0-based indices in the order of the load sites (`rim`:
        /// counter-clockwise from +x)
        lines: Vec<usize> = Vec::new() => key()
            .required("say which suspension lines to pull, e.g. `lines = [0, 1]`")
            .note("< the number of lines, no repeats; pulls on one line may not overlap in time"),
        /// start of the ramp
        start_s: f64 = 0.0 => key().unit("s").non_negative("a time"),
        /// duration of the linear ramp; 0 = a step
        ramp_s: f64 = 0.0 => key().unit("s").non_negative("a ramp duration"),
        /// shortening of each pulled line when fully applied; negative lengthens
        shorten_m: f64 = 0.0 => key()
            .unit("m")
            .required("say how far to pull, e.g. `shorten_m = 0.3`")
            .note("leaves every pulled line ≥ 10 % of its length"),
        /// time held fully applied before the release over the same ramp
        #[serde(skip_serializing_if = "Option::is_none")]
        hold_s: Option<f64> = None => key()
            .unit("s")
            .non_negative("a hold time")
            .default_doc("absent: never released"),
        /// the `[[sensor]]` (by name) whose reading starts the pull instead of the clock;
        /// `start_s` is then the time from which it may fire
        #[serde(skip_serializing_if = "Option::is_none")]
        sensor: Option<String> = None => key()
            .default_doc("absent: the clock starts it at `start_s`")
            .note("a `sensor.name`; needs `below_m`"),
        /// the pull starts when the sensor reads this or less (after its latency)
        #[serde(skip_serializing_if = "Option::is_none")]
        below_m: Option<f64> = None => key()
            .unit("m")
            .default_doc("absent")
            .note("with `sensor` only, and then required"),
    }
}

choice! {
    /// What a sensor reads.
    pub enum SensorKind {
        /// The height of the landing body (the payload) above the ground: an altimeter, or a
        /// proximity sensor looking down.
        Height = "height",
    }
}

section! {
    /// One `[[sensor]]` entry: an instrument on the payload whose readings can start a pull
    /// (`control[i].sensor`, docs/control.md).
    pub struct Sensor {
        /// its name, for `control[i].sensor`
        name: String = String::new() => key()
            .required("name the sensor, e.g. `name = \"altimeter\"`")
            .note("unique among the sensors; no leading or trailing space"),
        /// what it reads
        reads: SensorKind = SensorKind::Height => key(),
        /// samples per second; the first at t = 0
        rate_hz: f64 = 20.0 => key()
            .unit("Hz")
            .positive("a sampling rate")
            .note("at most 1e8 samples over `time.duration_s`"),
        /// delay from a sample to the pull it fires
        latency_s: f64 = 0.0 => key().unit("s").non_negative("a latency"),
        /// standard deviation of the reading's Gaussian noise
        noise_m: f64 = 0.0 => key().unit("m").non_negative("a standard deviation"),
        /// seed of the noise: sample k's noise depends only on (seed, k)
        seed: usize = 0 => key().note("an integer from 0 to 2⁶³ − 1 (TOML's integers)"),
    }
}

choice! {
    /// Which lines guidance pulls to glide towards a point.
    pub enum PullSide {
        /// The lines facing it: a canopy that glides towards its pulled side (a flat one).
        Towards = "towards",
        /// The lines facing away: a canopy that glides away from its pulled side (the round
        /// canopy of this model, docs/control.md).
        Away = "away",
        /// The measured response of the canopy's outline (`control::response`): a rectangle
        /// glides towards its pulled side, a circle away from it; none is measured for a
        /// hexagon or an imported mesh.
        Shape = "shape",
    }
}

section! {
    /// `[guidance]`: steer to a target by pulling lines (docs/control.md).
    pub struct Guidance {
        /// target point `[x, y]` on the ground
        target_m: Vec<f64> = Vec::new() => key()
            .unit("m")
            .required("say where to land, e.g. `target_m = [20.0, 0.0]`")
            .note("two numbers"),
        /// largest shortening of any line
        max_pull_m: f64 = 0.0 => key()
            .unit("m")
            .positive("a pull")
            .required("say how far a line may be pulled, e.g. `max_pull_m = 0.3`")
            .note("leaves every line ≥ 10 % of its length (with `[[control]]` pulls)"),
        /// which lines to pull to glide towards the target: by the canopy outline's measured
        /// response (`shape`), or those facing it or facing away (measure how a canopy
        /// responds with a `[[control]]` pull)
        pull_side: PullSide = PullSide::Shape => key()
            .note("`shape`: rectangle or circle canopies only"),
        /// pull per metre of predicted miss (proportional gain)
        gain: f64 = 0.05 => key().unit("m/m").positive("a gain"),
        /// time between the controller's decisions
        update_s: f64 = 0.5 => key().unit("s").positive("a time interval"),
        /// ramp from one decision's pulls to the next
        ramp_s: f64 = 0.25 => key()
            .unit("s")
            .non_negative("a ramp duration")
            .note("≤ `update_s`"),
    }
}

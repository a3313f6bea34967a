//! Pulls started by a sensor (`[[control]]` with `sensor` and `below_m`).
//!
//! After every accepted step each sensor's samples taken within the step are read
//! ([`super::sensor`]); a pull that has not fired fires at the first sample at or after its
//! `start_s` whose reading is at or below its `below_m`. Its ramp then starts at the sample's
//! time plus the sensor's latency, or at the end of the step that took the sample if that is
//! later (a pull cannot start inside a step already taken: with `dt` above the latency, the
//! start is late by less than one step). The firing (start, the sample's time and reading) is
//! written into the lines' stretching family's history, which every checkpoint saves: a
//! resumed run fires exactly as the uninterrupted one, and the trigger holds no other state
//! than the previous accepted state it interpolates from.
use serde::{Deserialize, Serialize};

use super::sensor::HeightSensor;
use crate::build::control::Lines;
use crate::metrics::landing::BodyState;
use crate::scenario::{Control, Sensor};
use engine::rod::{Firing, StretchHistory};
use engine::Model;

/// One sensor-started pull.
#[derive(Debug, Clone, PartialEq)]
struct SensorPull {
    /// Its `[[control]]` index.
    control: usize,
    /// Index of its sensor in [`Triggers::sensors`].
    sensor: usize,
    /// The reading at or below which it fires (m).
    below_m: f64,
    /// The time from which it may fire (`start_s`) (s).
    armed_s: f64,
}

/// The sensor-started pulls of a run and their sensors.
#[derive(Debug, Clone, PartialEq)]
pub struct Triggers {
    sensors: Vec<HeightSensor>,
    pulls: Vec<SensorPull>,
    ground_z: f64,
    /// Time and height of the landing body at the last accepted state.
    last: Option<(f64, f64)>,
}

/// `summary.json`'s record of one sensor-started pull (the list `triggers`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TriggerRecord {
    /// Its `[[control]]` index.
    pub control: usize,
    /// The sensor's name.
    pub sensor: String,
    /// The reading at or below which it fires (m).
    pub below_m: f64,
    /// Time of the sample that fired it (s); null when it did not fire.
    pub reading_time_s: Option<f64>,
    /// That sample's reading (m).
    pub reading_m: Option<f64>,
    /// Start of the pull's ramp (s).
    pub pull_start_s: Option<f64>,
}

impl Triggers {
    /// The triggers of the `sensor`-started pulls of `control` for ground at model height
    /// `ground_z` (m); `None` without a sensor-started pull.
    pub fn new(sensor: &[Sensor], control: &[Control], ground_z: f64) -> Option<Self> {
        let sensors: Vec<HeightSensor> = sensor.iter().map(HeightSensor::new).collect();
        let pulls: Vec<SensorPull> = control
            .iter()
            .enumerate()
            .filter_map(|(i, c)| {
                let name = c.sensor.as_ref()?;
                Some(SensorPull {
                    control: i,
                    sensor: sensors.iter().position(|x| &x.name == name)?,
                    below_m: c.below_m?,
                    armed_s: c.start_s,
                })
            })
            .collect();
        (!pulls.is_empty()).then_some(Self {
            sensors,
            pulls,
            ground_z,
            last: None,
        })
    }

    /// At the start of a flight (fresh or resumed) with the landing body at `body`: remember
    /// it, and on a fresh start (t = 0) read sample 0 there.
    pub fn start(&mut self, body: &BodyState, lines: &Lines, model: &mut Model) {
        let now = (body.t_s, body.x_m[2] - self.ground_z);
        self.last = Some(now);
        if body.t_s == 0.0 {
            for s in 0..self.sensors.len() {
                self.read_sensor(s, 0..1, now, now, lines, model);
            }
        }
    }

    /// After an accepted step that ended with the landing body at `body`: read the samples
    /// taken in the step and fire the pulls they trigger.
    pub fn after_step(&mut self, body: &BodyState, lines: &Lines, model: &mut Model) {
        let now = (body.t_s, body.x_m[2] - self.ground_z);
        let before = self.last.unwrap_or(now);
        self.last = Some(now);
        for s in 0..self.sensors.len() {
            let samples = self.sensors[s].samples_in(before.0, now.0);
            self.read_sensor(s, samples, before, now, lines, model);
        }
    }

    /// Read sensor `s`'s `samples` between the states `a` and `b` (time, height) and fire the
    /// unfired pulls on it that they trigger.
    fn read_sensor(
        &self,
        s: usize,
        samples: std::ops::Range<u64>,
        a: (f64, f64),
        b: (f64, f64),
        lines: &Lines,
        model: &mut Model,
    ) {
        let sensor = &self.sensors[s];
        let mut h = lines.history(model);
        let sources = lines.firing_sources();
        let mut waiting: Vec<&SensorPull> = self
            .pulls
            .iter()
            .filter(|p| p.sensor == s && !fired(&h, &sources, p.control))
            .collect();
        if waiting.is_empty() {
            return;
        }
        for k in samples {
            let t_k = sensor.sample_time(k);
            let reading = sensor.reading(k, a, b);
            waiting.retain(|p| {
                let fires = t_k >= p.armed_s && reading <= p.below_m;
                if fires {
                    let f = Firing {
                        start: (t_k + sensor.latency_s).max(b.0),
                        reading_t: t_k,
                        reading,
                    };
                    for (slot, &src) in h.firings.iter_mut().zip(&sources) {
                        if src == p.control {
                            *slot = Some(f);
                        }
                    }
                }
                !fires
            });
            if waiting.is_empty() {
                break;
            }
        }
        lines.set_history(model, &h);
    }

    /// The record of every sensor-started pull under the history of `model`'s lines.
    pub fn records(&self, lines: &Lines, model: &Model) -> Vec<TriggerRecord> {
        let h = lines.history(model);
        let sources = lines.firing_sources();
        self.pulls
            .iter()
            .map(|p| {
                let f = sources
                    .iter()
                    .position(|&src| src == p.control)
                    .and_then(|i| h.firings[i]);
                TriggerRecord {
                    control: p.control,
                    sensor: self.sensors[p.sensor].name.clone(),
                    below_m: p.below_m,
                    reading_time_s: f.map(|f| f.reading_t),
                    reading_m: f.map(|f| f.reading),
                    pull_start_s: f.map(|f| f.start),
                }
            })
            .collect()
    }

    /// The warnings of a run that ended at `t` (s): a pull that did not fire (saying whether
    /// it was armed), and one that fired but whose ramp was to start after the end.
    pub fn warnings(&self, records: &[TriggerRecord], t: f64) -> Vec<String> {
        records
            .iter()
            .filter_map(|r| {
                let armed = self
                    .pulls
                    .iter()
                    .find(|p| p.control == r.control)
                    .map_or(0.0, |p| p.armed_s);
                let head = format!("control[{}]: sensor `{}`", r.control, r.sensor);
                match r.pull_start_s {
                    None if armed > 0.0 => Some(format!(
                        "{head} never read ≤ {} m between its start_s = {armed} s and the end \
                         (t = {t:.3} s): the pull did not start",
                        r.below_m
                    )),
                    None => Some(format!(
                        "{head} never read ≤ {} m by the end (t = {t:.3} s): the pull did not \
                         start",
                        r.below_m
                    )),
                    Some(start) if start >= t => Some(format!(
                        "{head} fired (reading {:.4} m at {:.4} s), but its ramp was to start at \
                         {start:.4} s, after the end (t = {t:.3} s): the pull did not act",
                        r.reading_m.unwrap_or(f64::NAN),
                        r.reading_time_s.unwrap_or(f64::NAN),
                    )),
                    Some(_) => None,
                }
            })
            .collect()
    }
}

/// Whether the pull of `[[control]]` entry `control` has fired in `h`.
fn fired(h: &StretchHistory, sources: &[usize], control: usize) -> bool {
    sources
        .iter()
        .zip(&h.firings)
        .any(|(&src, f)| src == control && f.is_some())
}

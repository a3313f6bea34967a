//! Pulls started by a height sensor (`[[sensor]]`, `control[i].sensor`): the sample that
//! fires, the reading it fires at and the start of the ramp, recomputed here from the
//! accepted states of the flight (linear interpolation at the sample times, the latency, the
//! step granularity); the noise's reproducibility; a threshold never reached; and a resumed
//! run firing as the uninterrupted one.
//!
//! The drop is the soft-landing scenario's cargo drop from 15 m on its coarsest mesh (0.3 m)
//! at dt = 10 ms (it lands after about 3 s).
use crate::common::*;

use chute::app::run_config;
use chute::build::build;
use chute::control::sensor::HeightSensor;
use chute::control::TriggerRecord;
use chute::output::Summary;
use chute::runner::Session;
use chute::scenario::Scenario;

const RATE_HZ: f64 = 20.0;
const LATENCY_S: f64 = 0.05;

/// The 15 m drop with sensor `alt` (20 Hz, 50 ms latency, `noise`) and the pulls `pulls`.
fn drop(noise: &str, pulls: &str) -> Scenario {
    let set = [
        "atmosphere.altitude_m=15".to_string(),
        // Coarse and short steps keep each flight to seconds; the firing logic is the same.
        "canopy.edge_length_m=0.3".into(),
        "time.dt_s=0.01".into(),
        format!(
            "sensor=[{{name = \"alt\", rate_hz = {RATE_HZ}, latency_s = {LATENCY_S}, {noise}}}]"
        ),
        format!("control=[{pulls}]"),
        "output.frame_interval_s=0.5".into(),
    ];
    Scenario::load(&repo().join("scenarios/control-soft-landing.toml"), &set).unwrap()
}

/// All 12 lines.
const ALL: &str = "0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11";

/// A pull of `lines` by 1.5 m over 0.3 s when `alt` reads ≤ `below` m from `armed` s.
fn pull_on(lines: &str, below: f64, armed: f64) -> String {
    pull_by(lines, below, armed, 1.5)
}

/// A pull of `lines` by `shorten` m over 0.3 s when `alt` reads ≤ `below` m from `armed` s.
fn pull_by(lines: &str, below: f64, armed: f64, shorten: f64) -> String {
    format!(
        "{{lines = [{lines}], sensor = \"alt\", below_m = {below}, start_s = {armed}, \
         ramp_s = 0.3, shorten_m = {shorten}}}"
    )
}

/// Fly `s` to the ground: the summary and the payload's height above the ground after every
/// accepted step, `(t, h)`, from t = 0.
fn fly(s: &Scenario) -> (Summary, Vec<(f64, f64)>) {
    let (sum, states, _) = fly_lines(s);
    (sum, states)
}

/// [`fly`], and each line's rest length at the end (m), as `lines.csv` reports it.
fn fly_lines(s: &Scenario) -> (Summary, Vec<(f64, f64)>, Vec<f64>) {
    let mut session = Session::new(build(s).unwrap(), run_config(s, false)).unwrap();
    let height = |session: &Session| {
        let b = session.built();
        let p = b.payload_node.unwrap();
        (b.state.t, b.state.q[3 * p + 2] + s.atmosphere.altitude_m)
    };
    let mut states = vec![height(&session)];
    while let Ok(Some(_)) = session.step() {
        states.push(height(&session));
    }
    assert!(session.finished());
    assert_eq!(session.stop_reason(), Some(chute::runner::GROUND));
    let b = session.built();
    let lines = b.lines.as_ref().unwrap();
    let rows = lines.sample(&b.state.q, b.state.t, &lines.history(&b.model));
    let rest = rows.iter().map(|r| r[0]).collect();
    (session.summary(), states, rest)
}

/// The firing that the states predict: the first sample `k` at or after `armed` whose
/// reading (the height interpolated linearly between the states around `t_k`, plus
/// `noise(k)`) is ≤ `below`; its time, its reading and the ramp's start, `t_k` plus the
/// latency or the end of the step that took the sample if later.
fn predicted(
    states: &[(f64, f64)],
    below: f64,
    armed: f64,
    noise: impl Fn(u64) -> f64,
) -> Option<(f64, f64, f64)> {
    (0u64..)
        .map_while(|k| {
            let t = k as f64 / RATE_HZ;
            let j = states.iter().position(|&(ts, _)| ts >= t - 1e-12)?;
            let ((ta, ha), (tb, hb)) = (states[j.saturating_sub(1)], states[j]);
            let w = if tb > ta {
                ((t - ta) / (tb - ta)).clamp(0.0, 1.0)
            } else {
                1.0
            };
            Some((t, ha + w * (hb - ha) + noise(k), tb))
        })
        .find(|&(t, h, _)| t >= armed && h <= below)
        .map(|(t, h, tb)| (t, h, (t + LATENCY_S).max(tb)))
}

fn record(s: &Summary, control: usize) -> &TriggerRecord {
    s.triggers.iter().find(|r| r.control == control).unwrap()
}

fn assert_fired_as_predicted(r: &TriggerRecord, want: (f64, f64, f64)) {
    let got = (
        r.reading_time_s.unwrap(),
        r.reading_m.unwrap(),
        r.pull_start_s.unwrap(),
    );
    assert_eq!(got.0, want.0, "sample time: {got:?} vs {want:?}");
    assert!(
        (got.1 - want.1).abs() < 1e-12,
        "reading: {got:?} vs {want:?}"
    );
    assert_eq!(got.2, want.2, "ramp start: {got:?} vs {want:?}");
}

/// The pull fires at the first 20 Hz sample after arming that reads ≤ 5 m, starts 50 ms
/// later (dt = 10 ms ≤ latency: never late), and a pull armed later waits for its arming
/// although the sensor has read below its threshold since. A threshold never reached leaves
/// its pull unfired with a warning.
#[test]
fn a_sensor_pull_fires_at_the_sample_the_states_predict() {
    let pulls = [
        pull_by("1, 2, 3, 4, 5, 6", 5.0, 0.0, 0.3),
        pull_by("0", -1.0, 0.0, 0.3),
        pull_by("7, 8, 9, 10, 11", 12.0, 1.234, 0.3),
    ]
    .join(", ");
    let (sum, states, rest) = fly_lines(&drop("noise_m = 0.0", &pulls));
    let none = |_| 0.0;
    let want = predicted(&states, 5.0, 0.0, none).expect("the drop reads 5 m");
    assert_fired_as_predicted(record(&sum, 0), want);
    let want = predicted(&states, 12.0, 1.234, none).unwrap();
    // Armed at 1.234 s, it fires at the first sample after (1.25 s), already below 12 m.
    assert_eq!(want.0, 1.25);
    assert!(states.iter().any(|&(t, h)| t < 1.0 && h < 12.0));
    assert_fired_as_predicted(record(&sum, 2), want);
    let idle = record(&sum, 1);
    assert_eq!((idle.reading_time_s, idle.pull_start_s), (None, None));
    // The lines' rest lengths at the end follow each firing's ramp (0.3 m over 0.3 s from
    // its start; 4 m lines), the unfired line's none.
    let t_end = states.last().unwrap().0;
    let pulled = |c: usize| {
        let start = record(&sum, c).pull_start_s.unwrap();
        4.0 - 0.3 * ((t_end - start) / 0.3).clamp(0.0, 1.0)
    };
    for (line, want) in [(1, pulled(0)), (6, pulled(0)), (0, 4.0), (7, pulled(2))] {
        assert!(
            (rest[line] - want).abs() < 1e-12,
            "line {line}: {} vs {want}",
            rest[line]
        );
    }
    assert!(
        sum.warnings
            .iter()
            .any(|w| w.contains("control[1]") && w.contains("never read")),
        "{:?}",
        sum.warnings
    );
}

/// Noise of 0.5 m: the firing reading is the interpolated height plus exactly the sensor's
/// noise of that sample, the same seed fires identically, another seed elsewhere.
#[test]
fn a_noisy_sensor_fires_reproducibly_from_its_seed() {
    let pull = pull_on(ALL, 5.0, 0.0);
    let noisy = |seed: u64| fly(&drop(&format!("noise_m = 0.5, seed = {seed}"), &pull));
    let (a, states) = noisy(3);
    let sensor = HeightSensor {
        name: "alt".into(),
        rate_hz: RATE_HZ,
        latency_s: LATENCY_S,
        noise_m: 0.5,
        seed: 3,
    };
    // Before the pull starts the flight is the noise-free one: its states predict it.
    let want = predicted(&states, 5.0, 0.0, |k| sensor.noise(k)).unwrap();
    assert_fired_as_predicted(record(&a, 0), want);
    let (again, _) = noisy(3);
    assert_eq!(a.triggers, again.triggers);
    let (other, _) = noisy(4);
    assert_ne!(a.triggers[0].reading_m, other.triggers[0].reading_m);
}

/// A run stopped after one pull has fired and before the other, and resumed, writes the
/// uninterrupted run's files bit for bit (the firings are checkpointed history).
#[test]
fn a_resumed_run_fires_as_the_uninterrupted_one() {
    // Half the lines each, by 0.3 m: a gentle tilt, then its mirror.
    let pulls = [
        pull_by("0, 1, 2, 3, 4, 5", 10.0, 0.0, 0.3),
        pull_by("6, 7, 8, 9, 10, 11", 4.0, 0.0, 0.3),
    ]
    .join(", ");
    let s = drop("noise_m = 0.2, seed = 9", &pulls);
    let (sum, _) = fly(&s);
    let (first, second) = (
        record(&sum, 0).pull_start_s.unwrap(),
        record(&sum, 1).pull_start_s.unwrap(),
    );
    assert!(first + 0.5 < second, "{first} {second}");
    crate::resume::stop_and_resume(&s, (first + second) / 2.0, Some(0.1));
}

//! `[[control]]` and `[guidance]`: parsed, defaulted, overridden entry by entry and as a
//! whole array, written back, and every bad input refused naming the entry (docs/control.md).
use chute::scenario::{Scenario, ScenarioError};

use crate::common::repo;

const PULLS: &str = "control=[{lines = [0, 1], start_s = 1.0, ramp_s = 0.5, shorten_m = 0.3}, \
                     {lines = [6], start_s = 2.0, shorten_m = -0.2, hold_s = 1.5}]";

fn round(set: &[&str]) -> Result<Scenario, ScenarioError> {
    let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
    Scenario::load(&repo().join("scenarios/round-parachute.toml"), &set)
}

fn refused(set: &[&str], key: &str, want: &str) {
    let e = round(set).expect_err("accepted");
    let msg = e.to_string();
    assert_eq!(e.key(), Some(key), "{msg}");
    assert!(msg.contains(want), "want `{want}` in: {msg}");
    assert!(msg.contains("from `--set"), "{msg}");
}

#[test]
fn pulls_parse_with_defaults_and_round_trip() {
    let s = round(&[PULLS]).unwrap();
    assert_eq!(s.control.len(), 2);
    let (a, b) = (&s.control[0], &s.control[1]);
    assert_eq!(
        (a.lines.clone(), a.start_s, a.ramp_s, a.shorten_m, a.hold_s),
        (vec![0, 1], 1.0, 0.5, 0.3, None)
    );
    assert_eq!((b.ramp_s, b.shorten_m, b.hold_s), (0.0, -0.2, Some(1.5)));
    let back = Scenario::from_str_with_name(&s.to_toml(), "r.toml", &[]).unwrap();
    assert_eq!(back, s);
    // No pulls: nothing written back, nothing changed.
    let plain = round(&[]).unwrap();
    assert!(plain.control.is_empty() && plain.guidance.is_none());
    assert!(!plain.to_toml().contains("control"));
}

#[test]
fn one_field_of_one_entry_is_overridden_by_index() {
    let s = round(&[PULLS, "control[1].start_s=2.5", "control[0].lines=[3]"]).unwrap();
    assert_eq!(s.control[1].start_s, 2.5);
    assert_eq!(s.control[0].lines, vec![3]);
    assert_eq!(s.control[0].shorten_m, 0.3);
    // Index = number of entries appends one (its required keys then apply).
    let e = round(&[PULLS, "control[2].start_s=1"]).unwrap_err();
    assert_eq!(e.key(), Some("control[2].lines"), "{e}");
}

#[test]
fn bad_pulls_name_the_entry() {
    refused(
        &[PULLS, "control[1].lines=[12]"],
        "control[1].lines",
        "line 12 does not exist",
    );
    refused(
        &[PULLS, "control[1].lines=[2, 2]"],
        "control[1].lines",
        "named twice",
    );
    refused(
        &[PULLS, "control[0].lines=[]"],
        "control[0].lines",
        "at least one line",
    );
    refused(
        &[PULLS, "control[0].shorten_m=2.8"],
        "control[0].shorten_m",
        "10 %",
    );
    refused(
        &[PULLS, "control[0].ramp_s=-1"],
        "control[0].ramp_s",
        "must not be negative",
    );
    refused(
        &[PULLS, "control[1].hold_s=-0.5"],
        "control[1].hold_s",
        "must not be negative",
    );
    refused(
        &[PULLS, "control[1].start_s=-0.5"],
        "control[1].start_s",
        "must not be negative",
    );
    // Line 6 is held from 2 s until 3.5 s; a second pull on it inside that time overlaps.
    let set = [
        PULLS,
        "control[2].lines=[5, 6]",
        "control[2].start_s=3.0",
        "control[2].shorten_m=0.1",
    ];
    refused(&set, "control[2].start_s", "overlaps control[1]");
    // Right after the release ends it is a sequence, not an overlap.
    let ok = [
        PULLS,
        "control[2].lines=[6]",
        "control[2].start_s=3.5",
        "control[2].shorten_m=0.1",
    ];
    round(&ok).unwrap();
    // A pull without hold lasts to the end: any later pull on its lines overlaps.
    let set = [
        PULLS,
        "control[2].lines=[1]",
        "control[2].start_s=9",
        "control[2].shorten_m=0.1",
    ];
    refused(&set, "control[2].start_s", "never released");
}

#[test]
fn pulls_and_guidance_need_suspension_lines() {
    let e = round(&[PULLS, "load.mode=mass"]).unwrap_err();
    assert!(e.key().is_some_and(|k| k.starts_with("control")), "{e}");
    assert!(e.to_string().contains("load.mode = \"payload\""), "{e}");
    let g = ["guidance.target_m=[10, 0]", "guidance.max_pull_m=0.3"];
    let e = round(&[g[0], g[1], "load.mode=force"]).unwrap_err();
    assert_eq!(e.key(), Some("guidance"), "{e}");
    assert!(e.to_string().contains("suspension lines"), "{e}");
}

#[test]
fn guidance_is_checked() {
    let ground = [
        "atmosphere.model=isa1976",
        "atmosphere.altitude_m=30",
        "atmosphere.ground_altitude_m=0",
    ];
    fn with<'a>(ground: &[&'a str], extra: &[&'a str]) -> Vec<&'a str> {
        let mut v = vec!["guidance.target_m=[10, 0]", "guidance.max_pull_m=0.3"];
        v.extend_from_slice(ground);
        v.extend_from_slice(extra);
        v
    }
    let s = round(&with(&ground, &[])).unwrap();
    let g = s.guidance.as_ref().unwrap();
    assert_eq!((g.target_m.clone(), g.max_pull_m), (vec![10.0, 0.0], 0.3));
    assert_eq!(g.pull_side, chute::scenario::PullSide::Shape);
    assert_eq!(
        Scenario::from_str_with_name(&s.to_toml(), "r.toml", &[]).unwrap(),
        s
    );
    // One bad entry at a time: (override, the key named, what the message says).
    for (set, key, want) in [
        (
            "guidance.target_m=[1, 2, 3]",
            "guidance.target_m",
            "two numbers",
        ),
        ("guidance.max_pull_m=2.9", "guidance.max_pull_m", "10 %"),
        (
            "guidance.max_pull_m=-1",
            "guidance.max_pull_m",
            "must be positive",
        ),
        ("guidance.ramp_s=2", "guidance.ramp_s", "update_s"),
        ("guidance.pull_side=sideways", "guidance.pull_side", "shape"),
    ] {
        refused(&with(&ground, &[set]), key, want);
    }
    // `shape` has no measured response for a hexagon; `away` is accepted there.
    let hexagon = [
        "canopy.shape=hexagon",
        "load.sites=corners",
        "guidance.pull_side=shape",
    ];
    refused(&with(&ground, &hexagon), "guidance.pull_side", "towards");
    let hexagon = [
        "canopy.shape=hexagon",
        "load.sites=corners",
        "guidance.pull_side=away",
    ];
    assert!(round(&with(&ground, &hexagon)).is_ok());
    // Under the inflation pressure the round canopy's response is measured, the square's not.
    let inflated = ["fluid.shell_drag=\"inflation\"", "guidance.pull_side=shape"];
    assert!(round(&with(&ground, &inflated)).is_ok());
    let square = [
        "fluid.shell_drag=\"inflation\"",
        "guidance.pull_side=shape",
        "canopy.shape=rectangle",
        "canopy.span_m=3",
        "canopy.width_m=3",
        "load.sites=corners",
    ];
    refused(&with(&ground, &square), "guidance.pull_side", "inflation");
    let e = round(&["guidance.target_m=[10, 0]", "guidance.max_pull_m=0.3"]).unwrap_err();
    assert_eq!(e.key(), Some("guidance.target_m"), "{e}");
    assert!(e.to_string().contains("ground_altitude_m"), "{e}");
    let e = round(&["guidance.max_pull_m=0.3"]).unwrap_err();
    assert_eq!(e.key(), Some("guidance.target_m"), "{e}");
}

/// A sensor and a pull it starts, over the round parachute with a ground.
const SENSED: [&str; 5] = [
    "atmosphere.model=isa1976",
    "atmosphere.altitude_m=30",
    "atmosphere.ground_altitude_m=0",
    "sensor=[{name = \"alt\", rate_hz = 50, latency_s = 0.02, noise_m = 0.1, seed = 4}]",
    "control=[{lines = [0, 1], sensor = \"alt\", below_m = 3.0, ramp_s = 0.2, shorten_m = 0.5}]",
];

#[test]
fn sensor_pulls_parse_round_trip_and_refuse_bad_input() {
    let s = round(&SENSED).unwrap();
    let sn = &s.sensor[0];
    assert_eq!(
        (
            sn.name.as_str(),
            sn.rate_hz,
            sn.latency_s,
            sn.noise_m,
            sn.seed
        ),
        ("alt", 50.0, 0.02, 0.1, 4)
    );
    assert_eq!(sn.reads, chute::scenario::SensorKind::Height);
    assert_eq!(
        (s.control[0].sensor.as_deref(), s.control[0].below_m),
        (Some("alt"), Some(3.0))
    );
    let back = Scenario::from_str_with_name(&s.to_toml(), "r.toml", &[]).unwrap();
    assert_eq!(back, s);
    let with = |extra: &[&'static str]| -> Vec<&'static str> {
        SENSED.iter().chain(extra).copied().collect()
    };
    for (extra, key, want) in [
        (
            &["control[0].sensor=\"altimeter\""][..],
            "control[0].sensor",
            "no sensor has this name: the sensors are [\"alt\"]",
        ),
        (
            &["sensor=[]"][..],
            "control[0].sensor",
            "no `[[sensor]]` is declared",
        ),
        (
            &["control=[{lines = [0], sensor = \"alt\", shorten_m = 0.5}]"][..],
            "control[0].sensor",
            "below_m = 10.0",
        ),
        (
            &["control=[{lines = [0], below_m = 3.0, shorten_m = 0.5}]"][..],
            "control[0].below_m",
            "only used with `sensor`",
        ),
        (
            &["sensor[1].name=\"alt\""][..],
            "sensor[1].name",
            "sensor[0] has this name already",
        ),
        (
            &["sensor[0].rate_hz=0"][..],
            "sensor[0].rate_hz",
            "must be positive",
        ),
        (
            &["sensor[0].latency_s=-0.1"][..],
            "sensor[0].latency_s",
            "must not be negative",
        ),
        (
            &["sensor[0].noise_m=-1"][..],
            "sensor[0].noise_m",
            "must not be negative",
        ),
        (
            &["sensor[0].reads=\"speed\""][..],
            "sensor[0].reads",
            "height",
        ),
        // A rate typed with extra zeros would sample for ever: bounded like the steps.
        (
            &["sensor[0].rate_hz=1e308"][..],
            "sensor[0].rate_hz",
            "samples over time.duration_s",
        ),
        (
            &["sensor[0].name=\"alt \"", "control[0].sensor=\"alt \""][..],
            "sensor[0].name",
            "no leading or trailing space",
        ),
        // An emptied name is the sensor's error, not its pull's reference.
        (
            &["sensor[0].name=\"\""][..],
            "sensor[0].name",
            "name the sensor",
        ),
        // A sensor's pull may start at any time: another pull on its lines overlaps it.
        (
            &[
                "control=[{lines = [1], sensor = \"alt\", below_m = 3.0, shorten_m = 0.5}, \
               {lines = [1], start_s = 20, shorten_m = 0.1}]",
            ][..],
            "control[1].start_s",
            "whenever sensor `alt` fires it",
        ),
    ] {
        refused(&with(extra), key, want);
    }
    // A height needs the ground.
    let no_ground: Vec<&str> = SENSED[3..].to_vec();
    refused(&no_ground, "sensor[0].reads", "ground_altitude_m");
    // A sensor no pull reads is a warning, not an error.
    let unused = round(&with(&["control=[]"])).unwrap();
    let warnings = chute::scenario::plausibility::warnings(&unused);
    assert!(
        warnings.iter().any(|w| w.contains("sensor[0] `alt`")),
        "{warnings:?}"
    );
    // Thresholds that fire at once (at or above the 30 m release) or never (below ground).
    for (below, noise, want) in [
        ("30", "0", Some("at or above the release height")),
        ("-1", "0", Some("never fires it")),
        ("-1", "0.1", None),
        ("3", "0", None),
    ] {
        let b = format!("control[0].below_m={below}");
        let n = format!("sensor[0].noise_m={noise}");
        let s = round(&with(&[b.leak(), n.leak()])).unwrap();
        let w = chute::scenario::plausibility::warnings(&s);
        let hit = w.iter().find(|w| w.contains("control[0].below_m"));
        match want {
            Some(text) => assert!(hit.is_some_and(|w| w.contains(text)), "{below}: {w:?}"),
            None => assert!(hit.is_none(), "{below}, noise {noise}: {w:?}"),
        }
    }
}

/// The end-of-run warnings of sensor pulls: not fired (saying when it was armed), and fired
/// with a ramp that was to start after the end.
#[test]
fn sensor_pull_warnings_say_why_a_pull_did_not_act() {
    let set: Vec<&str> = SENSED
        .iter()
        .copied()
        .chain(["control[0].start_s=1.6"])
        .collect();
    let s = round(&set).unwrap();
    let tr = chute::control::Triggers::new(&s.sensor, &s.control, -30.0).unwrap();
    let record = |start: Option<f64>| chute::control::TriggerRecord {
        control: 0,
        sensor: "alt".into(),
        below_m: 3.0,
        reading_time_s: start.map(|t| t - 0.02),
        reading_m: start.map(|_| 2.99),
        pull_start_s: start,
    };
    let w = tr.warnings(&[record(None)], 2.5);
    assert!(
        w[0].contains("between its start_s = 1.6 s and the end"),
        "{w:?}"
    );
    let w = tr.warnings(&[record(Some(2.6))], 2.5);
    assert!(
        w[0].contains("after the end (t = 2.500 s): the pull did not act"),
        "{w:?}"
    );
    assert!(tr.warnings(&[record(Some(2.4))], 2.5).is_empty());
}

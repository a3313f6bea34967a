//! Round trips, old formats and refusals of `checkpoint.bin`.
use super::*;

fn sample() -> Checkpoint {
    Checkpoint {
        scenario_toml: "name = \"x\"\n".into(),
        synced: true,
        t: 0.128,
        q: vec![1.0, 2.0, -3.5],
        v: vec![0.0, -0.25, 1e-300],
        histories: vec![vec![], vec![0.5, 0.25]],
        dt: 2.5e-3,
        streak: 3,
        dt_cap: f64::INFINITY,
        rejected_error: 7,
        rejected_newton: 2,
        steps: 99,
        newton_iterations: 250,
        wall_time_s: 1.5,
        ts_rows: 100,
        frame_times: vec![0.0, 0.05, 0.1],
        next_frame: 0.15,
        snap_idx: 1,
        next_sync: 2,
        warnings: vec![
            "step rejected at t = 0.01 s (x); dt halved to 5e-4 s".into(),
            "other".into(),
        ],
        checkpoint_every_s: Some(0.25),
        solver: Some(SolverCounters {
            iterations: 7,
            factorizations: 3,
            factor_s: 0.125,
            held: engine::StageCounts {
                runs: 5,
                converged: 4,
            },
            ..SolverCounters::default()
        }),
    }
}

/// Bytes of `c`'s solver counters (this version: flag, length, JSON) at the end of the
/// body.
fn solver_bytes(c: &Checkpoint) -> usize {
    let json = serde_json::to_string(&c.solver.unwrap_or_default()).unwrap();
    16 + json.len()
}

/// The sample and its encoding in the version-3 layout: without the solver's counters (the
/// checksum's 8 bytes left as they were).
fn version_3() -> (Checkpoint, Vec<u8>) {
    let c = sample();
    let v4 = c.encode();
    let v3 = [&v4[..v4.len() - 8 - solver_bytes(&c)], &v4[v4.len() - 8..]].concat();
    (c, v3)
}

#[test]
fn round_trips_bit_for_bit() {
    let c = sample();
    assert_eq!(Checkpoint::decode(&c.encode()).unwrap(), c);
}

/// Re-seal `body` (bytes without a checksum) as a file of format `version`.
fn reseal(mut body: Vec<u8>, version: u32) -> Vec<u8> {
    body[8..12].copy_from_slice(&version.to_le_bytes());
    let sum = fnv1a(&body);
    body.extend_from_slice(&sum.to_le_bytes());
    body
}

/// Unknown counters (a run resumed from an older checkpoint) stay unknown.
#[test]
fn unknown_solver_counters_round_trip() {
    let c = Checkpoint {
        solver: None,
        ..sample()
    };
    assert_eq!(Checkpoint::decode(&c.encode()).unwrap(), c);
}

/// A known flag other than 0 or 1 (with a valid checksum) is refused, not guessed.
#[test]
fn refuses_a_bad_solver_counters_flag() {
    let mut body = sample().encode();
    body.truncate(body.len() - 8);
    let at = body.len() - solver_bytes(&sample());
    body[at..at + 8].copy_from_slice(&2u64.to_le_bytes());
    let e = Checkpoint::decode(&reseal(body, FORMAT_VERSION)).unwrap_err();
    assert!(e.contains("solver-counters flag 2"), "{e}");
}

/// Files of versions 4 to 6 (the earlier solver's 18, 20 or 21 counts and 4 times) read
/// with their counters unknown and every other field in its place.
#[test]
fn reads_versions_4_to_6_without_their_counters() {
    let c = sample();
    let body = c.encode();
    let head = &body[..body.len() - 8 - solver_bytes(&c)];
    for (version, counts) in [(4u32, 18usize), (5, 20), (6, 21)] {
        let mut old = head.to_vec();
        old.extend_from_slice(&1u64.to_le_bytes());
        old.extend(std::iter::repeat_n(0u8, 8 * (counts + OLD_TIMES)));
        let old = Checkpoint::decode(&reseal(old, version)).unwrap();
        assert_eq!(old.solver, None, "version {version}");
        assert_eq!((&old.q, old.t, &old.warnings), (&c.q, c.t, &c.warnings));
    }
}

/// A version-3 file (before the solver counters) still reads, without counters.
#[test]
fn reads_version_3() {
    let c = sample();
    let v4 = c.encode();
    let old = reseal(v4[..v4.len() - 8 - solver_bytes(&c)].to_vec(), 3);
    let old = Checkpoint::decode(&old).unwrap();
    assert_eq!(old.solver, None);
    assert_eq!(old.checkpoint_every_s, c.checkpoint_every_s);
    assert_eq!((old.q, old.warnings), (c.q, c.warnings));
}

/// A version-2 file (before `chute resume`: no checkpoint interval) still reads.
#[test]
fn reads_version_2() {
    let (c, v3) = version_3();
    let old = Checkpoint::decode(&reseal(v3[..v3.len() - 8 - 8].to_vec(), 2)).unwrap();
    assert_eq!(old.checkpoint_every_s, None);
    assert_eq!(
        (old.dt_cap, old.rejected_error),
        (c.dt_cap, c.rejected_error)
    );
}

/// A version-1 file (before adaptive steps: no cap, no rejection counters) still reads.
#[test]
fn reads_version_1() {
    let (c, v3) = version_3();
    // Version 1 = version 3 without the 32 trailing bytes of the newer fields.
    let old = Checkpoint::decode(&reseal(v3[..v3.len() - 8 - 32].to_vec(), 1)).unwrap();
    assert_eq!((old.dt_cap, old.checkpoint_every_s), (f64::INFINITY, None));
    assert_eq!((old.rejected_error, old.rejected_newton), (0, 1));
    assert_eq!((old.q, old.dt, old.warnings), (c.q, c.dt, c.warnings));
    // A future version is refused with both numbers.
    let next = FORMAT_VERSION + 1;
    let v4 = sample().encode();
    let e = Checkpoint::decode(&reseal(v4[..v4.len() - 8].to_vec(), next)).unwrap_err();
    assert!(
        e.contains(&format!("format version {next}"))
            && e.contains(&format!("1 to {FORMAT_VERSION}")),
        "{e}"
    );
}

#[test]
fn non_positive_step_is_refused() {
    let mut c = sample();
    c.dt = 0.0;
    assert!(c.check_shape(3, 2).unwrap_err().contains("step size"));
    let mut c = sample();
    c.dt_cap = f64::NAN;
    assert!(c.check_shape(3, 2).is_err());
    assert!(sample().check_shape(3, 2).is_ok());
}

/// A time series shorter than the checkpoint's row count is named as not matching the
/// checkpoint (the checkpoint itself is fine).
#[test]
fn a_short_time_series_does_not_match_the_checkpoint() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("timeseries.csv");
    std::fs::write(&path, format!("{}\n0,1", crate::output::timeseries::HEADER)).unwrap();
    let e = truncate_timeseries(&path, 1).unwrap_err();
    assert!(matches!(e, CheckpointError::Mismatch { .. }), "{e}");
    let msg = e.to_string();
    assert!(msg.contains("does not match the run's checkpoint"), "{msg}");
    assert!(
        msg.contains("has 0 complete rows, the checkpoint needs 1"),
        "{msg}"
    );
}

/// The counters are self-describing: a counter the writer did not have (absent from its
/// JSON) reads as 0, so adding one needs no new format; one this build does not know is
/// refused.
#[test]
fn counters_missing_from_a_checkpoint_read_as_zero() {
    let c = sample();
    let full = serde_json::to_string(&c.solver.unwrap()).unwrap();
    let mut j: serde_json::Value = serde_json::from_str(&full).unwrap();
    j.as_object_mut().unwrap().remove("iterations");
    let older = j.to_string();
    let bytes = c.encode();
    let at = bytes
        .windows(full.len())
        .rposition(|w| w == full.as_bytes())
        .expect("the counters' JSON in the file");
    // Rebuild the file with the shorter JSON and its length.
    let mut body = bytes[..at - 8].to_vec();
    body.extend_from_slice(&(older.len() as u64).to_le_bytes());
    body.extend_from_slice(older.as_bytes());
    body.extend_from_slice(&bytes[at + full.len()..bytes.len() - 8]);
    let read = Checkpoint::decode(&reseal(body, FORMAT_VERSION)).unwrap();
    let want = SolverCounters {
        iterations: 0,
        ..c.solver.unwrap()
    };
    assert_eq!(read.solver, Some(want));
    assert_ne!(c.solver.unwrap().iterations, 0, "the sample must set it");
    let unknown = full.replacen('{', "{\"no_such_counter\":1,", 1);
    assert!(serde_json::from_str::<SolverCounters>(&unknown).is_err());
}

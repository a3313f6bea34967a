//! Atomic writes, the streamed CSV, the decimated in-memory series and summary.json.

use std::fs;

use chute::metrics::{compute, Params};
use chute::output::summary::SolverCounters;
use chute::output::timeseries::HEADER;
use chute::output::{
    canopy_means, write_atomic, DecimatedSeries, RunInfo, Sample, Stepping, Summary,
    TimeSeriesWriter,
};

fn names(dir: &std::path::Path) -> Vec<String> {
    let mut v: Vec<String> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn atomic_write_replaces_and_leaves_no_temp() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("a.json");
    write_atomic(&p, b"first, longer content").unwrap();
    write_atomic(&p, b"second").unwrap();
    assert_eq!(fs::read(&p).unwrap(), b"second");
    assert_eq!(names(dir.path()), vec!["a.json".to_string()]);
    // A missing directory is an error, not a panic, and creates nothing.
    assert!(write_atomic(&dir.path().join("no/such/dir.txt"), b"x").is_err());
    assert_eq!(names(dir.path()), vec!["a.json".to_string()]);
}

fn sample(i: usize) -> Sample {
    let t = i as f64 * 0.01;
    Sample {
        t_s: t,
        z_m: 100.0 - t,
        vz_mps: -1.0 - 0.1 * t,
        vx_mps: 0.25,
        vy_mps: -0.5,
        z_payload_m: 95.0 - t,
        vz_payload_mps: -1.0,
        extended_height_m: 1.5 + (i % 7) as f64 * 1e-3,
        drag_x_n: 0.1,
        drag_y_n: 0.2,
        drag_z_n: 9.81 + t / 3.0,
        newton_iterations: (i % 5) as u32 + 1,
        dt_s: 0.01,
        line_tension_n: 50.0 + (i % 3) as f64,
        payload_acceleration_mps2: 0.5 * (i % 4) as f64,
        axis_angle_deg: (i % 11) as f64,
        canopy_diameter_m: 3.0 - (i % 13) as f64 * 1e-3,
    }
}

#[test]
fn csv_header_and_rows_round_trip() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("timeseries.csv");
    let mut w = TimeSeriesWriter::create(&p).unwrap();
    let n = 2000; // several internal buffer flushes (64 KiB ≈ 500 rows)
    for i in 0..n {
        w.push(&sample(i)).unwrap();
        if i == 1234 {
            // After a flush the file is a valid CSV with exactly the pushed rows.
            w.flush().unwrap();
            let mut r = csv::Reader::from_path(&p).unwrap();
            assert_eq!(r.deserialize::<Sample>().count(), 1235);
        }
    }
    assert_eq!(w.rows(), n as u64);
    w.finish().unwrap();
    let mut r = csv::Reader::from_path(&p).unwrap();
    assert_eq!(
        r.headers().unwrap().iter().collect::<Vec<_>>().join(","),
        HEADER
    );
    let rows: Vec<Sample> = r.deserialize().map(|x| x.unwrap()).collect();
    assert_eq!(rows.len(), n);
    for (i, row) in rows.iter().enumerate() {
        // `{}` formatting of f64 round-trips exactly.
        assert_eq!(*row, sample(i));
    }
    assert_eq!(names(dir.path()), vec!["timeseries.csv".to_string()]);
}

#[test]
fn csv_before_flush_is_a_valid_prefix() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("ts.csv");
    let mut w = TimeSeriesWriter::create(&p).unwrap();
    let n = 2000; // ≈ 80 bytes per row: past the 64 KiB buffer threshold at least twice
    for i in 0..n {
        w.push(&sample(i)).unwrap();
    }
    // Without an explicit flush some rows are on disk (buffer threshold passed), all whole.
    let text = fs::read_to_string(&p).unwrap();
    assert!(text.ends_with('\n'));
    let rows = csv::Reader::from_reader(text.as_bytes())
        .deserialize::<Sample>()
        .count();
    assert!(rows > 0 && rows < n, "{rows}");
    drop(w); // drop flushes
    let rows = csv::Reader::from_path(&p)
        .unwrap()
        .deserialize::<Sample>()
        .count();
    assert_eq!(rows, n);
}

#[test]
fn decimation_bounds_memory_and_keeps_latest_and_max() {
    let cap = 1000;
    let mut d = DecimatedSeries::new(cap);
    let n = 123_457;
    let spike_at = 77_777; // an odd index: dropped by decimation
    for i in 0..n {
        let mut s = sample(i);
        if i == spike_at {
            s.extended_height_m = 42.0;
        }
        d.push(&s);
        assert!(d.len() <= cap + 1);
    }
    assert_eq!(d.pushed(), n as u64);
    // The retained points are uniformly spaced by `stride` steps, then the latest sample.
    let stride = d.stride() as usize;
    assert!(stride > 1 && d.len() >= cap / 2);
    let kept = d.len() - 1;
    for (j, &t) in d.t_s[..kept].iter().enumerate() {
        assert_eq!(t, sample(j * stride).t_s);
    }
    assert_eq!(*d.t_s.last().unwrap(), sample(n - 1).t_s);
    assert!(d.extended_height_m.iter().all(|&h| h < 42.0));
    assert_eq!(d.max_extended_height_m(), 42.0);
    let s = d.series();
    assert_eq!(s.exact_max_extended_height_m, Some(42.0));
    assert_eq!(s.t_s.len(), s.drag_z_n.len());
}

#[test]
fn canopy_means_are_mass_weighted() {
    let x = [[0.0, 0.0, 1.0], [1.0, 0.0, 3.0], [5.0, 5.0, -100.0]];
    let v = [[1.0, 0.0, -2.0], [0.0, 2.0, -5.0], [9.0, 9.0, 9.0]];
    let m = [1.0, 3.0, 7.0];
    let c = canopy_means(&x, &v, &m, &[0, 1]).unwrap();
    assert_eq!(c.z_m, (1.0 + 9.0) / 4.0);
    assert_eq!(c.v_mps, [0.25, 1.5, (-2.0 - 15.0) / 4.0]);
    assert_eq!(c.extended_height_m, 2.0);
    assert!(canopy_means(&x, &v, &m, &[]).is_none());
}

/// The value of field `i` of [`crate::common::SOLVER_FIELDS`] in [`distinct_counters`]:
/// times (`_s`) `(i + 1) / 8` s, stage objects `{runs: 10 i + 1, converged: 10 i}`, counts
/// `10 i + 1`.
fn distinct_value(i: usize, field: &str) -> serde_json::Value {
    if field.ends_with("_s") {
        serde_json::json!((i + 1) as f64 / 8.0)
    } else if ["held", "newton", "continuation", "homotopy"].contains(&field) {
        serde_json::json!({"runs": 10 * i as u64 + 1, "converged": 10 * i as u64})
    } else {
        serde_json::json!(10 * i as u64 + 1)
    }
}

/// Solver counters whose every field differs ([`distinct_value`]).
fn distinct_counters() -> SolverCounters {
    let obj: serde_json::Map<String, serde_json::Value> = crate::common::SOLVER_FIELDS
        .iter()
        .enumerate()
        .map(|(i, f)| (f.to_string(), distinct_value(i, f)))
        .collect();
    serde_json::from_value(serde_json::Value::Object(obj)).expect("every documented field")
}

/// The `solver` object of [`distinct_counters`]: exactly the documented fields
/// (`common::SOLVER_FIELDS`, in the order of docs/outputs.md §solver), each holding its own
/// value.
fn assert_solver_object(solver: &serde_json::Value) {
    let obj = solver.as_object().unwrap();
    let fields = crate::common::SOLVER_FIELDS;
    assert_eq!(obj.len(), fields.len(), "{obj:?}");
    for (i, f) in fields.iter().enumerate() {
        assert_eq!(obj[*f], distinct_value(i, f), "solver.{f}");
    }
}

/// The run record of the summary test: incomplete, adaptive, with every field set.
fn run_info() -> RunInfo {
    RunInfo {
        scenario_name: "round-1m".into(),
        complete: false,
        stop_reason: Some("Newton failed".into()),
        simulated_time_s: 4.99,
        steps: 500,
        newton_iterations: 1500,
        wall_time_s: 0.5,
        dofs: 1234,
        stepping: Stepping {
            dt_s: 1e-2,
            adaptive: true,
            error_tolerance_m: Some(1e-5),
            dt_min_s: 1e-5,
            dt_max_s: 0.05,
            rejected_steps_error: 3,
            rejected_steps_newton: 1,
            dt_used_min_s: Some(1e-3),
            dt_used_mean_s: Some(9.98e-3),
            dt_used_max_s: Some(0.05),
        },
        solver: Some(distinct_counters()),
        warnings: vec!["from the run loop".into()],
        canopy_weight_n: Some(1.5),
    }
}

#[test]
fn summary_json_has_every_documented_field() {
    let mut d = DecimatedSeries::default();
    for i in 0..500 {
        d.push(&sample(i));
    }
    let p = Params {
        total_weight_n: 9.81,
        air_density_kg_m3: 1.225,
        air_viscosity_pa_s: 1.81e-5,
        reference_length_m: 1.0,
        quadratic_drag: true,
        wind_mps: [0.0; 3],
    };
    let m = compute(&d.series(), &p).unwrap();
    let run = run_info();
    let s = Summary::new(run, &m);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("summary.json");
    s.write(&path).unwrap();
    let v: serde_json::Value = serde_json::from_str(&fs::read_to_string(&path).unwrap()).unwrap();
    let obj = v.as_object().unwrap();
    for f in crate::common::SUMMARY_FIELDS {
        assert!(obj.contains_key(f), "missing {f}");
    }
    assert_eq!(
        obj.len(),
        crate::common::SUMMARY_FIELDS.len(),
        "undocumented field? {:?}",
        obj.keys()
    );
    assert_eq!(v["horizontal_velocity_mps"].as_array().unwrap().len(), 2);
    assert_solver_object(&v["solver"]);
    // vz ramps (not steady) ⇒ not reached ⇒ null, and the incomplete run is flagged first.
    assert!(v["time_to_terminal_s"].is_null());
    let warnings = v["warnings"].as_array().unwrap();
    assert_eq!(warnings[0], "from the run loop");
    assert!(warnings[1]
        .as_str()
        .unwrap()
        .starts_with("run incomplete: Newton failed"));
    // The file holds the shortest round-trip decimal of each f64 (serde_json's own parser is
    // only accurate to an ulp without its `float_roundtrip` feature, so check with std).
    let text = fs::read_to_string(&path).unwrap();
    let field = |name: &str| -> f64 {
        let start = text.find(&format!("\"{name}\": ")).unwrap() + name.len() + 4;
        let end = start + text[start..].find([',', '\n']).unwrap();
        text[start..end].parse().unwrap()
    };
    assert_eq!(
        field("terminal_velocity_trend_mps"),
        s.terminal_velocity_trend_mps
    );
    assert_eq!(field("mean_drag_z_n"), s.mean_drag_z_n);
    let back: Summary = serde_json::from_value(v.clone()).unwrap();
    assert_eq!(back.warnings, s.warnings);
    assert_eq!(back.steps, s.steps);
    assert_eq!(back.stepping, s.stepping);
    assert_eq!(back.solver, s.solver);
    // A summary written before `solver` existed still reads (as not known), and so does null.
    let mut old = v.clone();
    old.as_object_mut().unwrap().remove("solver");
    assert_eq!(serde_json::from_value::<Summary>(old).unwrap().solver, None);
    let mut null = v.clone();
    null["solver"] = serde_json::Value::Null;
    assert_eq!(
        serde_json::from_value::<Summary>(null).unwrap().solver,
        None
    );
    assert_eq!(v["rejected_steps_error"], 3);
    assert!(v["error_tolerance_m"].is_number());
    assert_eq!(names(dir.path()), vec!["summary.json".to_string()]);
}

//! `chute study` of a `[dispersion]`: every sample's landing in `dispersion.csv`, the footprint
//! once all have landed, and each sample the same however the study is split.

use std::path::Path;

use crate::common::{bundled, chute_ok};

/// Four samples of the rod canopy dropped 8 m through a drawn wind and weight (a second each).
const VARY: &str =
    "[[dispersion.vary]]\nkey = \"fluid.wind_mps[0]\"\nuniform = { lo = 1.0, hi = 3.0 }\n\
    [[dispersion.vary]]\nkey = \"load.weight_n\"\n\
    normal = { mean = 20.0, std_dev = 2.0, lo = 15.0, hi = 25.0 }\n";

fn study_file(dir: &Path) -> String {
    study_file_varying(dir, VARY)
}

fn study_file_varying(dir: &Path, vary: &str) -> String {
    let text = format!(
        "name = \"d\"\nbase = \"{}\"\n[dispersion]\nsamples = 4\nseed = 3\n{vary}",
        bundled("report-rod-20n.toml")
    );
    let path = dir.join("d.toml");
    std::fs::write(&path, text).unwrap();
    path.display().to_string()
}

const DROP: [&str; 6] = [
    "--set",
    "atmosphere.altitude_m=8",
    "--set",
    "atmosphere.ground_altitude_m=0",
    "--set",
    "time.duration_s=30",
];

/// Run the study into `dir/out`; its standard error.
fn run(dir: &Path, out: &str, extra: &[&str]) -> String {
    run_file(dir, &study_file(dir), out, extra)
}

fn run_file(dir: &Path, file: &str, out: &str, extra: &[&str]) -> String {
    let mut args = vec!["study", file, "--out", out];
    args.extend(DROP);
    args.extend(extra);
    String::from_utf8_lossy(&chute_ok(dir, &args).stderr).to_string()
}

/// The rows of `dispersion.csv` (header first).
fn rows(dir: &Path) -> Vec<Vec<String>> {
    let text = std::fs::read_to_string(dir.join("dispersion.csv")).unwrap();
    text.lines()
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect()
}

#[test]
fn a_dispersion_writes_every_landing_and_its_footprint() {
    let tmp = tempfile::tempdir().unwrap();
    let _ = run(tmp.path(), "all", &["-j", "2"]);
    let out = tmp.path().join("all");
    let rows = rows(&out);
    assert_eq!(rows.len(), 5, "{rows:?}");
    let col = |name: &str| rows[0].iter().position(|h| h == name).unwrap();
    let xs: Vec<f64> = rows[1..]
        .iter()
        .map(|r| r[col("landing_x_m")].parse().unwrap())
        .collect();
    let fp: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("footprint.json")).unwrap())
            .unwrap();
    let mean = xs.iter().sum::<f64>() / 4.0;
    assert!(
        (fp["footprint"]["mean_m"][0].as_f64().unwrap() - mean).abs() < 1e-12,
        "{fp}"
    );
    assert_eq!(fp["footprint"]["samples"], 4);
    let png = std::fs::read(out.join("footprint.png")).unwrap();
    assert!(png.starts_with(b"\x89PNG"), "footprint.png is a PNG");
    // The page draws every landing and the three ellipses of footprint.json.
    let html = std::fs::read_to_string(out.join("footprint.html")).unwrap();
    assert_eq!(html.matches("<circle class=\"landing\"").count(), 4);
    for (k, e) in fp["footprint"]["ellipses"]
        .as_array()
        .unwrap()
        .iter()
        .enumerate()
    {
        let semi = e["semi_major_m"].as_f64().unwrap();
        let path = format!("class=\"sigma-{}\" data-semi-major-m=\"{semi}\"", k + 1);
        assert!(html.contains(&path), "no {path} in {html}");
    }
    // How the footprint settles with N: the last row is the whole footprint.
    let settling = fp["settling"].as_array().unwrap();
    assert_eq!(settling.last().unwrap()["samples"], 4);
    assert_eq!(
        settling.last().unwrap()["mean_m"],
        fp["footprint"]["mean_m"]
    );
    // Every sample landed, with its drawn weight in the case's scenario.
    for r in &rows[1..] {
        let w: f64 = r[col("load.weight_n")].parse().unwrap();
        assert!((15.0..=25.0).contains(&w));
        assert!(r[col("flight_time_s")].parse::<f64>().unwrap() > 1.0);
    }
    // Run again: its own files are recognised, the cases skipped, the files the same.
    let before = std::fs::read(out.join("footprint.json")).unwrap();
    let _ = run(tmp.path(), "all", &[]);
    assert_eq!(std::fs::read(out.join("footprint.json")).unwrap(), before);
}

#[test]
fn a_sample_is_the_same_whether_the_study_runs_whole_or_in_shards() {
    let tmp = tempfile::tempdir().unwrap();
    let _ = run(tmp.path(), "whole", &["-j", "1"]);
    // Half the shards: the other samples are missing, so no footprint yet.
    let said = run(tmp.path(), "shards", &["--shard", "0/2"]);
    let half = tmp.path().join("shards");
    for f in ["footprint.json", "footprint.png", "footprint.html"] {
        assert!(!half.join(f).exists(), "{f}");
    }
    assert!(said.contains("2 of 4 samples have not landed"), "{said}");
    // The other shard's samples share one warning line.
    assert!(
        said.contains("2 cases have not run yet: `sample-00001`, `sample-00003`"),
        "{said}"
    );
    assert!(!said.contains("case `sample-00001`"), "{said}");
    let _ = run(tmp.path(), "shards", &["--shard", "1/2"]);
    assert_eq!(rows(&tmp.path().join("whole")), rows(&half));
    assert!(half.join("footprint.json").exists());
}

#[test]
fn zero_spread_gives_identical_landings() {
    let tmp = tempfile::tempdir().unwrap();
    let vary =
        "[[dispersion.vary]]\nkey = \"fluid.wind_mps[0]\"\nuniform = { lo = 2.0, hi = 2.0 }\n";
    let file = study_file_varying(tmp.path(), vary);
    let release = ["-j", "2", "--set", "canopy.release_point_m=[100.0, 50.0]"];
    let _ = run_file(tmp.path(), &file, "zero", &release);
    // The pictures mark the release point the samples start from.
    let html = std::fs::read_to_string(tmp.path().join("zero/footprint.html")).unwrap();
    assert!(html.contains("class=\"release\" d=\"M100 "), "{html}");
    let rows = rows(&tmp.path().join("zero"));
    assert_eq!(rows.len(), 5);
    for r in &rows[2..] {
        assert_eq!(r[1..], rows[1][1..], "{rows:?}");
    }
    let fp: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(tmp.path().join("zero/footprint.json")).unwrap(),
    )
    .unwrap();
    assert_eq!(fp["footprint"]["cep90_m"], 0.0);
}

/// A canopy released with the uniform wind has no horizontal relative velocity, so drag never
/// acts sideways and it drifts with the wind all the way down, to the solver's tolerance: a
/// residual of ~2e-8 N (1e-9 of the weight) per step on ~2 kg over 1 000 steps of 1 ms moves
/// the mean velocity by at most 1e-8 m/s.
#[test]
fn a_canopy_released_with_the_wind_drifts_with_it() {
    let tmp = tempfile::tempdir().unwrap();
    released_with_wind(
        tmp.path(),
        "report-rod-20n.toml",
        "w",
        "[3.0, 1.0, 0.0]",
        &["time.duration_s=1"],
    );
    let text = std::fs::read_to_string(tmp.path().join("w/timeseries.csv")).unwrap();
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |n: &str| head.iter().position(|h| *h == n).unwrap();
    let (vx, vy, vz) = (col("vx_mps"), col("vy_mps"), col("vz_mps"));
    let mut falling = false;
    for l in lines {
        let r: Vec<f64> = l
            .split(',')
            .map(|c| c.parse().unwrap_or(f64::NAN))
            .collect();
        assert!(
            (r[vx] - 3.0).abs() < 1e-7 && (r[vy] - 1.0).abs() < 1e-7,
            "{l}"
        );
        falling |= r[vz] < -1.0;
    }
    assert!(falling, "the canopy fell");
}

/// Released with a uniform wind, the round canopy lands the wind times its time aloft
/// downwind: no drag acts sideways (its still-air landing point is the origin by symmetry), so
/// the shift is exact to the solver's tolerance (measured 4e-10 of it from 300 m).
#[test]
fn a_uniform_wind_shifts_the_landing_by_the_wind_times_the_time_aloft() {
    let tmp = tempfile::tempdir().unwrap();
    let sets = ["canopy.edge_length_m=0.35", "atmosphere.altitude_m=40"];
    released_with_wind(
        tmp.path(),
        "drop-1000m.toml",
        "u",
        "[4.0, -3.0, 0.0]",
        &sets,
    );
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(tmp.path().join("u/summary.json")).unwrap())
            .unwrap();
    let t = s["flight_time_s"].as_f64().unwrap();
    let p = &s["landing_point_m"];
    let (x, y) = (p[0].as_f64().unwrap(), p[1].as_f64().unwrap());
    assert!(t > 5.0, "{s}");
    assert!((x - 4.0 * t).abs() < 1e-6 * 4.0 * t, "x {x} vs {}", 4.0 * t);
    assert!(
        (y + 3.0 * t).abs() < 1e-6 * 3.0 * t,
        "y {y} vs {}",
        -3.0 * t
    );
}

/// The air varies with height only, so a release point moved sideways moves the landing by
/// the same amount. Not to round-off: the other coordinates round differently, the fluttering
/// fabric amplifies that, and the adaptive steps follow (measured 3e-7 of the drift, 4e-7
/// with fixed steps). Asserted to 1e-5 of the drift, 200 times below the mesh's own error
/// in it (0.2 % from 0.35 to 0.25 m triangles, drop-wind).
#[test]
fn the_release_point_moves_the_landing_by_itself() {
    let tmp = tempfile::tempdir().unwrap();
    let sets = ["canopy.edge_length_m=0.35", "atmosphere.altitude_m=30"];
    let file = bundled("drop-wind.toml");
    let landing = |out: &str, extra: &[&str]| {
        // drop-wind starts with the air (`canopy.released_with_wind`).
        let wind = "fluid.wind_mps=[3.0, 1.0, 0.0]";
        let mut args = vec!["run", file.as_str(), "--out", out, "--set", wind];
        for s in sets.iter().chain(extra) {
            args.extend(["--set", s]);
        }
        chute_ok(tmp.path(), &args);
        let s: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(tmp.path().join(out).join("summary.json")).unwrap(),
        )
        .unwrap();
        let p = &s["landing_point_m"];
        let point = [p[0].as_f64().unwrap(), p[1].as_f64().unwrap()];
        (point, s["drift_m"].as_f64().unwrap())
    };
    let (at_origin, drift) = landing("o", &[]);
    let (moved, drift_moved) = landing("m", &["canopy.release_point_m=[120.0, -40.0]"]);
    assert!(at_origin[0] > 10.0, "it drifted: {at_origin:?}");
    let tol = 1e-5 * drift;
    assert!(
        (drift_moved - drift).abs() < tol,
        "{drift_moved} vs {drift}"
    );
    let shifted = [moved[0] - 120.0, moved[1] + 40.0];
    for k in 0..2 {
        assert!(
            (shifted[k] - at_origin[k]).abs() < tol,
            "{moved:?} vs {at_origin:?}"
        );
    }
}

/// Shards run into directories of their own and collected give the whole study's files.
#[test]
fn collected_shards_give_the_whole_footprint() {
    let tmp = tempfile::tempdir().unwrap();
    let _ = run(tmp.path(), "whole", &["-j", "2"]);
    let _ = run(tmp.path(), "s0", &["--shard", "0/2"]);
    let _ = run(tmp.path(), "s1", &["--shard", "1/2"]);
    // An incomplete set names what it lacks (and `collect` says it is incomplete).
    let partial = crate::common::chute(tmp.path(), &["collect", "s0", "--out", "c0"]);
    assert_eq!(
        partial.status.code(),
        Some(3),
        "an incomplete set is refused"
    );
    let said = String::from_utf8_lossy(&partial.stderr);
    assert!(said.contains("2 of 4 samples have not landed"), "{said}");
    assert!(said.contains("`sample-00001` is missing"), "{said}");
    assert!(!tmp.path().join("c0/footprint.json").exists());
    chute_ok(tmp.path(), &["collect", "s0", "s1", "--out", "c"]);
    let read = |d: &str, f: &str| std::fs::read(tmp.path().join(d).join(f)).unwrap();
    assert_eq!(read("c", "dispersion.csv"), read("whole", "dispersion.csv"));
    assert_eq!(read("c", "footprint.json"), read("whole", "footprint.json"));
    // The study file edited since (another seed): each landing keeps the inputs its run
    // recorded, not the new draws.
    let file = tmp.path().join("d.toml");
    let text = std::fs::read_to_string(&file).unwrap();
    std::fs::write(&file, text.replace("seed = 3", "seed = 4")).unwrap();
    let _ = crate::common::chute(tmp.path(), &["collect", "s0", "s1", "--out", "edited"]);
    assert_eq!(
        read("edited", "dispersion.csv"),
        read("whole", "dispersion.csv")
    );
}

/// Run the bundled `scenario` into `dir/out` in the uniform `wind`, released moving with it.
fn released_with_wind(dir: &Path, scenario: &str, out: &str, wind: &str, sets: &[&str]) {
    let file = bundled(scenario);
    let (w, v) = (
        format!("fluid.wind_mps={wind}"),
        format!("canopy.initial_velocity_mps={wind}"),
    );
    let mut args = vec![
        "run",
        file.as_str(),
        "--out",
        out,
        "--set",
        w.as_str(),
        "--set",
        v.as_str(),
    ];
    for s in sets {
        args.extend(["--set", s]);
    }
    chute_ok(dir, &args);
}

//! `chute steady`: the steady descent agrees with the long flight in a fraction of its
//! time, its modes are written and tabled, and what has no steady descent is refused. The
//! modes against the flights (the report canopy's lateral instability, `round-solid`'s tilt
//! and swing) are `chute validate --case stability`, whose quick suite tests/cli/validate.rs
//! runs.

use crate::common::*;

/// `chute steady scenarios/NAME --set S… --json` in `cwd`, which must succeed: its report and
/// the command's output.
fn steady_json(
    cwd: &std::path::Path,
    name: &str,
    sets: &[&str],
) -> (serde_json::Value, std::process::Output) {
    let file = bundled(name);
    let mut args = vec!["steady", file.as_str(), "--json"];
    for s in sets {
        args.extend(["--set", s]);
    }
    let o = chute_ok(cwd, &args);
    (serde_json::from_str(&stdout(&o)).unwrap(), o)
}

/// The report's rod canopy: the equilibrium after a 2 s transient has the 10 s flight's
/// terminal velocity to 0.1 % (the acceptance check of `chute steady`).
#[test]
fn the_rod_canopy_steady_descent_is_the_long_flights() {
    let tmp = tempfile::tempdir().unwrap();
    let rod = rod_file();
    chute_ok(tmp.path(), &["run", &rod, "--out", "flight", "-q"]);
    let flight = read_json(tmp.path().join("flight/summary.json"));
    let vt = flight["terminal_velocity_mps"].as_f64().unwrap();
    let o = chute_ok(
        tmp.path(),
        &["steady", &rod, "--set", "time.duration_s=2", "--out", "st"],
    );
    let s = read_json(tmp.path().join("st/stability.json"));
    let v = s["terminal_velocity_mps"].as_f64().unwrap();
    assert!(
        (v - vt).abs() < 1e-3 * vt.abs(),
        "steady {v} against the flight's {vt}"
    );
    assert!(s["residual_n"].as_f64().unwrap() < 1e-3);
    let modes = s["modes"].as_array().unwrap();
    assert!(!modes.is_empty());
    for m in modes {
        assert!(m["backward_error"].as_f64().unwrap() <= 1e-8, "{m}");
        let sum: f64 = ["lateral", "vertical", "tilt", "spin", "deformation"]
            .iter()
            .map(|k| m["shares"][k].as_f64().unwrap())
            .sum();
        assert!((sum - 1.0).abs() < 1e-9, "shares {sum}");
    }
    // No mode of the rod canopy grows faster than round-off.
    assert!(
        modes[0]["growth_rate_per_s"].as_f64().unwrap() < 1e-6,
        "{}",
        modes[0]
    );
    let table = stdout(&o);
    assert_contains(
        &table,
        &[
            "steady descent of `report-rod-200n`",
            "growth (1/s)",
            "neutral",
        ],
    );
}

/// `--out` never mixes results: a run directory is refused before anything is computed.
#[test]
fn a_run_directory_is_not_a_steady_output() {
    let tmp = tempfile::tempdir().unwrap();
    let rod = rod_file();
    chute_ok(
        tmp.path(),
        &[
            "run",
            &rod,
            "--out",
            "r",
            "-q",
            "--set",
            "time.duration_s=0.05",
        ],
    );
    let o = chute(tmp.path(), &["steady", &rod, "--out", "r"]);
    assert_refused(&o, &["not a `chute steady` directory"]);
    assert!(!tmp.path().join("r/stability.json").exists());
}

/// A canopy on suspension lines over a payload (the bundled round parachute, coarse): each
/// line's uniform twist costs no energy, and the equilibrium is still found, its residual at
/// the tolerance; the descent-speed mode relaxes at about 2g/V, as a point mass's does.
#[test]
fn a_canopy_on_lines_finds_its_equilibrium() {
    let tmp = tempfile::tempdir().unwrap();
    let sets = [
        "time.duration_s=4",
        "canopy.edge_length_m=0.4",
        "lines.segments=4",
    ];
    let (s, _) = steady_json(tmp.path(), "round-parachute.toml", &sets);
    let v = s["terminal_velocity_mps"].as_f64().unwrap();
    let vt = s["transient_terminal_velocity_mps"].as_f64().unwrap();
    assert!(
        (v - vt).abs() < 1e-3 * vt.abs(),
        "{v} against the transient's {vt}"
    );
    assert!(
        s["residual_n"].as_f64().unwrap() < 1e-6,
        "{}",
        s["residual_n"]
    );
    assert!(s["newton_iterations"].as_u64().unwrap() <= 10);
    // Quadratic drag at speed V: the vertical speed relaxes at 2g/V (a point mass exactly;
    // the canopy's drag area changes a little with speed).
    let heave = s["modes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|m| m["description"].as_str().unwrap().contains("descent-speed"))
        .unwrap_or_else(|| panic!("no descent-speed mode in {}", s["modes"]));
    let rate = -heave["growth_rate_per_s"].as_f64().unwrap();
    let point = 2.0 * 9.81 / v.abs();
    assert!(
        (rate - point).abs() < 0.05 * point,
        "{rate} /s against 2g/V = {point} /s"
    );
}

/// A transient too short for Newton (the rod canopy at 1 s, still slowing down) is flown on
/// for another `time.duration_s`, and the report says how long it flew.
#[test]
fn a_short_transient_is_flown_on_until_an_equilibrium_is_near() {
    let tmp = tempfile::tempdir().unwrap();
    let (s, o) = steady_json(tmp.path(), "report-rod-200n.toml", &["time.duration_s=1"]);
    let t = s["transient_s"].as_f64().unwrap();
    assert!(
        (t - 2.0).abs() < 1e-9 || (t - 3.0).abs() < 1e-9,
        "transient {t} s"
    );
    assert!(s["residual_n"].as_f64().unwrap() < 1e-3);
    assert_contains(&stderr(&o), &["flying `report-rod-200n` for 1 s first"]);
}

/// A descent with ground contact or line pulls has no steady state: refused (status 2)
/// before any flight, naming what interrupts it.
#[test]
fn ground_and_line_pulls_are_refused() {
    let tmp = tempfile::tempdir().unwrap();
    for (name, key) in [
        ("drop-1000m.toml", "atmosphere.ground_altitude_m"),
        ("control-steer.toml", "[[control]]"),
        ("control-guidance.toml", "[guidance]"),
        ("drop-wind.toml", "[wind]"),
    ] {
        let file = bundled(name);
        let o = chute(tmp.path(), &["steady", file.as_str()]);
        assert_refused(&o, &["needs a descent that nothing interrupts", key]);
    }
}

/// Under the incidence law a set tangential drag is not added, and `chute check` says so
/// (once); left at its default, nothing is said.
#[test]
fn a_tangential_drag_under_the_incidence_law_is_warned_about() {
    let tmp = tempfile::tempdir().unwrap();
    let file = bundled("round-solid.toml");
    let warned = |sets: &[&str]| {
        let mut args = vec!["check", file.as_str()];
        for s in sets {
            args.extend(["--set", s]);
        }
        let out = stdout(&chute_ok(tmp.path(), &args));
        out.lines()
            .filter(|l| l.contains("tangential_drag_coefficient ignored"))
            .count()
    };
    assert_eq!(warned(&["fluid.tangential_drag_coefficient=0.5"]), 1);
    assert_eq!(warned(&[]), 0);
}

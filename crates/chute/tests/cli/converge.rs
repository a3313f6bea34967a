//! `chute converge` through the binary: a rod ladder whose answer is analytic, bad input
//! (exit 2, naming the key and the value), a failing level (exit 3) and reuse of finished
//! levels.

use std::path::Path;
use std::process::Output;

use crate::common::*;

fn converge<S: AsRef<std::ffi::OsStr>>(cwd: &Path, args: &[S]) -> Output {
    chute_command()
        .current_dir(cwd)
        .arg("converge")
        .args(args)
        .output()
        .unwrap()
}

/// `chute converge` of the rod over `levels` of `canopy.nodes`, 0.02 s flights, into `cv`
/// of `dir`, with `extra` arguments.
pub(crate) fn short_ladder(dir: &Path, levels: &str, extra: &[&str]) -> Output {
    let rod = rod_file();
    let vary = format!("canopy.nodes={levels}");
    let mut a = vec![
        rod.as_str(),
        "--vary",
        vary.as_str(),
        "--set",
        "time.duration_s=0.02",
        "--out",
        "cv",
    ];
    a.extend(extra);
    converge(dir, &a)
}

/// The arguments of `chute converge` of the rod varying `vary` (`KEY=VALUES`) into `out`, two
/// levels at a time, with short flights ([`FAST`]) and then `extra`.
fn rod_ladder_args(vary: &str, out: &str, extra: &[&str]) -> Vec<String> {
    let head = [&rod_file(), "--vary", vary, "--out", out, "-j", "2"];
    let tail = FAST.iter().chain(extra);
    head.into_iter()
        .chain(tail.copied())
        .map(String::from)
        .collect()
}

/// `chute converge ARGS` in `dir`, which must succeed: the report it wrote to `out`.
fn converged(dir: &Path, args: &[String], out: &str) -> serde_json::Value {
    assert_exit(&converge(dir, args), 0);
    read_json(dir.join(out).join("convergence.json"))
}

/// Short and cheap: 8 s of flight at dt = 1e-2 s (the steady state of implicit Euler does not
/// depend on dt), few frames.
const FAST: [&str; 8] = [
    "--set",
    "time.duration_s=8",
    "--set",
    "time.dt_s=1e-2",
    "--set",
    "output.frame_interval_s=1",
    "--set",
    "output.snapshots_s=[1]",
];

/// The rod's drag is per node with areas summing to span × width whatever the mesh, so its
/// terminal velocity is √(2W/(ρ C_D A)) on every level: the differences are round-off and
/// the extrapolation is the analytic value to within the reported resolution.
#[test]
fn rod_ladder_is_round_off_at_the_analytic_speed() {
    let tmp = tempfile::tempdir().unwrap();
    let args = rod_ladder_args("canopy.nodes=31,61,121", "c", &[]);
    let c = converged(tmp.path(), &args, "c");
    let st = &c["studies"][0];
    assert_eq!(st["key"], "canopy.nodes");
    assert_eq!(st["values"], serde_json::json!([31.0, 61.0, 121.0]));
    let vt = &st["quantities"]["terminal_velocity_mps"];
    for (h, want) in vt["h"].as_array().unwrap().iter().zip([0.2, 0.1, 0.05]) {
        assert!((h.as_f64().unwrap() - want).abs() < 1e-12, "h = {h}");
    }
    assert_eq!(vt["verdict"], "round-off");
    assert!(vt["observed_order"].is_null());
    let w: f64 = 200.0 + 1440.0 * 6.0 * 3.0 * 0.002 * 9.81;
    let analytic = -(2.0 * w / (1.225 * 1.75 * 18.0)).sqrt();
    let ext = vt["extrapolated"].as_f64().unwrap();
    let resolution = vt["gci"].as_f64().unwrap();
    assert!(
        resolution > 0.0 && resolution < 1e-6,
        "resolution {resolution}"
    );
    assert!(
        ((ext - analytic) / analytic).abs() <= resolution,
        "extrapolated {ext} vs analytic {analytic} (resolution {resolution})"
    );
    assert_eq!(st["quantities"]["drag_area_m2"]["verdict"], "round-off");
    // No ground, no drop quantities.
    assert!(st["quantities"]["landing_velocity_mps"].is_null());
    assert!(st["quantities"]["flight_time_s"].is_null());
    assert!(st["quantities"]["drift_m"].is_null());
    for f in [
        "convergence.md",
        "convergence.png",
        "study.csv",
        "nodes-61/summary.json",
    ] {
        assert!(tmp.path().join("c").join(f).is_file(), "{f}");
    }
    // Resumable: a second invocation reuses the three finished levels.
    let o = converge(tmp.path(), &args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        o.status.success() && err.matches("already complete").count() == 3,
        "{err}"
    );
    assert_eq!(
        read_json(tmp.path().join("c/convergence.json"))["studies"],
        c["studies"]
    );
    // Other inputs into the same directory: every level re-run (the study's rule), never
    // reported from the old runs.
    let mut other = args.clone();
    other.extend(["--set".into(), "load.weight_n=20".into()]);
    let o = converge(tmp.path(), &other);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert_eq!(
        err.matches("inputs changed since the recorded run; re-running")
            .count(),
        3,
        "{err}"
    );
    let light = read_json(tmp.path().join("c/convergence.json"));
    assert_ne!(light["studies"], c["studies"]);
}

#[test]
fn bad_ladders_exit_2_naming_key_and_value() {
    let tmp = tempfile::tempdir().unwrap();
    let rod = rod_file();
    let shell = repo()
        .join("scenarios/report-shell-4-sites.toml")
        .display()
        .to_string();
    let cases: [(&str, &str, &[&str]); 9] = [
        (
            &rod,
            "canopy.nodez=31,61",
            &["canopy.nodez", "did you mean `canopy.nodes`"],
        ),
        (
            &rod,
            "canopy.nodes=31",
            &["canopy.nodes", "at least two values", "`31`"],
        ),
        (
            &rod,
            "canopy.nodes=31,121,61",
            &["canopy.nodes", "`61` after `121`", "strictly"],
        ),
        (
            &rod,
            "canopy.nodes=61,61",
            &["canopy.nodes", "`61` after `61`"],
        ),
        (
            &rod,
            "canopy.nodes=2,61",
            &["canopy.nodes=2", "between 3 and"],
        ),
        (
            &rod,
            "time.dt_s=1e-3,abc",
            &["time.dt_s", "`abc` is not a number"],
        ),
        (
            &rod,
            "load.weight_n=20,200",
            &["load.weight_n", "not a discretisation parameter"],
        ),
        (
            &rod,
            "time.error_tolerance_m=1e-4,1e-5",
            &["time.error_tolerance_m=1e-4", "time.adaptive = true"],
        ),
        (
            &shell,
            "canopy.nodes=31,61",
            &["canopy.nodes=61", "does not refine the model"],
        ),
    ];
    for (scenario, vary, want) in cases {
        let o = converge(tmp.path(), &[scenario, "--vary", vary, "--out", "bad"]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{vary}: {err}");
        for w in want {
            assert!(err.contains(w), "{vary}: want `{w}` in {err}");
        }
        assert!(!tmp.path().join("bad").exists(), "{vary}: nothing may run");
    }
}

/// The failing round parachute of FAILING_PULL_SETS (its lines jump shorter at t = 0.2 s;
/// docs/reliability.md's failing run): a level that stops early is named with its reason and
/// left out of the estimate, the ladder is still summarised (no estimate from fewer than two
/// complete levels), and the exit status is 3. (Which dt survives the jump is chaotic; at
/// least one does not.)
#[test]
fn a_failing_level_is_reported_and_exits_3() {
    let tmp = tempfile::tempdir().unwrap();
    let round = crate::common::round_file();
    let args = [
        [
            round.as_str(),
            "--vary",
            "time.dt_s=2e-3,1e-3",
            "--out",
            "f",
            "--set",
            "time.duration_s=0.3",
        ]
        .as_slice(),
        &FAILING_PULL_SETS,
    ]
    .concat();
    let o = converge(tmp.path(), &args);
    assert_exit_says(&o, 3, &["step failed at t = 0.2"]);
    let c = read_json(tmp.path().join("f/convergence.json"));
    let levels = c["studies"][0]["levels"].as_array().unwrap();
    let failed: Vec<_> = levels
        .iter()
        .filter(|l| l["status"] == "incomplete")
        .collect();
    assert!(!failed.is_empty(), "{levels:?}");
    for l in &failed {
        assert_eq!(l["used"], false, "{l}");
    }
    let md = std::fs::read_to_string(tmp.path().join("f/convergence.md")).unwrap();
    assert_contains(&md, &["incomplete", "at least two"]);
}

/// A field of an array-of-tables entry set by index (`--set control[0].start_s=…`)
/// reaches every level of a ladder: each level's resolved scenario has it.
#[test]
fn indexed_control_field_set_reaches_every_level() {
    let tmp = tempfile::tempdir().unwrap();
    let out = converge(
        tmp.path(),
        &[
            &bundled("control-steer.toml"),
            "--vary",
            "time.dt_s=0.02,0.01",
            "--set",
            "control[0].start_s=0.02",
            "--set",
            "time.duration_s=0.06",
            "--out",
            "cv",
            "--jobs",
            "1",
        ],
    );
    assert_exit(&out, 0);
    for level in ["dt_s-0.02", "dt_s-0.01"] {
        let text = std::fs::read_to_string(
            tmp.path()
                .join("cv")
                .join(level)
                .join("scenario.resolved.toml"),
        )
        .unwrap();
        let t: toml::Table = text.parse().unwrap();
        let start = t["control"].as_array().unwrap()[0]["start_s"].as_float();
        assert_eq!(start, Some(0.02), "{level}: {text}");
    }
}

/// An error-tolerance ladder of adaptive runs: h = √tol on every level, the tolerance note,
/// and the rod's analytic steady speed on each level (a steady descent does not depend on the
/// step), so the verdict is round-off.
#[test]
fn tolerance_ladder_of_adaptive_runs_has_h_the_root_of_the_tolerance() {
    let tmp = tempfile::tempdir().unwrap();
    let vary = "time.error_tolerance_m=4e-4,1e-4,2.5e-5";
    let adaptive = rod_ladder_args(vary, "t", &["--set", "time.adaptive=true"]);
    let c = converged(tmp.path(), &adaptive, "t");
    let st = &c["studies"][0];
    assert_eq!(st["key"], "time.error_tolerance_m");
    assert_eq!(st["axis"], "tolerance");
    let vt = &st["quantities"]["terminal_velocity_mps"];
    for (h, tol) in vt["h"].as_array().unwrap().iter().zip([4e-4, 1e-4, 2.5e-5]) {
        let h = h.as_f64().unwrap();
        assert!((h - f64::sqrt(tol)).abs() < 1e-15, "h = {h} for {tol}");
    }
    let notes = st["notes"].to_string();
    assert!(notes.contains("√tol"), "{notes}");
    assert_eq!(vt["verdict"], "round-off", "{vt}");
}

/// A ladder of drops onto the ground also estimates the landing velocity and the flight time:
/// the rod lands 12 s after reaching terminal speed, so it lands at its analytic v_t (the
/// approach to it decays with τ = |v_t|/(2g) ≈ 0.3 s, its slowest bending mode at about 1/s:
/// measured, the landing is off v_t by 1.7e-5 from 40 m and 1.5e-8 from 80 m), and starting
/// from rest it takes longer than H/|v_t| (less the lead its lowest node gains by bending).
#[test]
fn drop_ladder_estimates_landing_velocity_and_flight_time() {
    let tmp = tempfile::tempdir().unwrap();
    let drop = [
        "--set",
        "atmosphere.altitude_m=80",
        "--set",
        "atmosphere.ground_altitude_m=0",
        // An upper bound: the ground ends every level first.
        "--set",
        "time.duration_s=30",
    ];
    let args = rod_ladder_args("canopy.nodes=31,61,121", "d", &drop);
    let c = converged(tmp.path(), &args, "d");
    let q = &c["studies"][0]["quantities"];
    let w: f64 = 200.0 + 1440.0 * 6.0 * 3.0 * 0.002 * 9.81;
    let analytic = -(2.0 * w / (1.225 * 1.75 * 18.0)).sqrt();
    let landing = &q["landing_velocity_mps"];
    for v in landing["results"].as_array().unwrap() {
        let v = v.as_f64().unwrap();
        assert!(
            ((v - analytic) / analytic).abs() < 1e-5,
            "{v} vs {analytic}"
        );
    }
    assert!(landing["gci"].as_f64().unwrap() < 1e-5, "{landing}");
    let flight = &q["flight_time_s"];
    let lead = q["final_extended_height_m"]["extrapolated"]
        .as_f64()
        .unwrap();
    let t = flight["extrapolated"].as_f64().unwrap();
    assert!(t > (80.0 - lead) / analytic.abs(), "flight time {t} s");
    assert!(flight["gci"].as_f64().unwrap() < 1e-3, "{flight}");
    let md = std::fs::read_to_string(tmp.path().join("d/convergence.md")).unwrap();
    assert!(md.contains("| landing velocity (m/s) |"), "{md}");
}

/// A ladder re-run into the directory of another ladder takes over the levels the two share
/// (their records name the new ladder), so `collect` of it knows every level of the ladder
/// that ran last: a level whose shard never ran is reported missing (status 3), not left out.
#[test]
fn a_ladder_rerun_into_another_ladders_directory_does_not_drop_a_level() {
    let tmp = tempfile::tempdir().unwrap();
    let ladder = |levels: &str, shard: Option<&str>| {
        let extra: Vec<&str> = shard.map_or(Vec::new(), |s| vec!["--shard", s]);
        let o = short_ladder(tmp.path(), levels, &extra);
        assert!(
            o.status.code().is_some_and(|c| c == 0 || c == 3),
            "{}",
            String::from_utf8_lossy(&o.stderr)
        );
    };
    ladder("11,21,41", None);
    // The next ladder as an array of three shards, the third of which never runs.
    ladder("21,41,81", Some("0/3"));
    ladder("21,41,81", Some("1/3"));
    let o = chute(tmp.path(), &["collect", "cv", "--out", "t"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_exit_says(&o, 3, &["nodes-81"]);
    // The first ladder's own level is kept, but not as current: the directory's ladder is
    // the second one.
    let csv = std::fs::read_to_string(tmp.path().join("t/study.csv")).unwrap();
    let row = csv.lines().find(|l| l.starts_with("nodes-11,")).unwrap();
    assert!(row.ends_with(",changed"), "{row}");
    assert!(err.contains("a level of an earlier ladder"), "{err}");
}

/// A picture that cannot be written is a warning, as for a run (the numbers are in the
/// reports), and a level whose directory cannot be used is reported with its reason, not as
/// "stopped first".
#[test]
fn an_unwritable_picture_warns_and_an_unusable_level_says_why() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(tmp.path().join("cv/convergence.png")).unwrap();
    std::fs::write(tmp.path().join("cv/nodes-41"), "a file of the user's").unwrap();
    let o = short_ladder(tmp.path(), "11,21,41", &[]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_exit_says(
        &o,
        3,
        &[
            "convergence.png was not written",
            "`cv/nodes-41` is a file, not a directory",
        ],
    );
    assert!(!err.contains("stopped first"), "{err}");
    // The reports say why, as the console does.
    let md = std::fs::read_to_string(tmp.path().join("cv/convergence.md")).unwrap();
    assert!(md.contains("is a file, not a directory"), "{md}");
    // The level's place freed: the ladder completes, the picture still warned of.
    std::fs::remove_file(tmp.path().join("cv/nodes-41")).unwrap();
    let o = short_ladder(tmp.path(), "11,21,41", &[]);
    assert_exit_says(&o, 0, &["convergence.png was not written"]);
}

/// A shard of a ladder reads the other shards' levels from the directory: one left there by
/// an earlier ladder of other inputs (another `--set`) is not this ladder's level, so it is
/// `not run` and out of the fit, never taken as `complete`.
#[test]
fn a_shard_never_takes_an_earlier_ladders_level_as_its_own() {
    let tmp = tempfile::tempdir().unwrap();
    let ladder = |extra: &[&str]| {
        let o = short_ladder(tmp.path(), "11,21,41", extra);
        assert_exit(&o, 0);
    };
    ladder(&["--set", "fluid.drag_coefficient=1.5"]);
    ladder(&["--shard", "0/2"]);
    let report = read_json(tmp.path().join("cv/convergence.json"));
    let levels = report["studies"][0]["levels"].as_array().unwrap();
    let middle = levels.iter().find(|l| l["case"] == "nodes-21").unwrap();
    assert_eq!(middle["status"], "not run", "{middle}");
    assert_eq!(middle["used"], false, "{middle}");
    let vt = &report["studies"][0]["quantities"]["terminal_velocity_mps"]["results"];
    assert!(vt[1].is_null(), "the other ladder's number shown: {vt}");
    // Nor when that level's record is gone: its summary is no number of this ladder.
    std::fs::remove_file(tmp.path().join("cv/nodes-21/done.json")).unwrap();
    ladder(&["--shard", "0/2"]);
    let report = read_json(tmp.path().join("cv/convergence.json"));
    let vt = &report["studies"][0]["quantities"]["terminal_velocity_mps"]["results"];
    assert!(vt[1].is_null(), "an unrecorded level's number shown: {vt}");
}

/// A `--set` of the varied key holds on no level (each level sets its own value): the report
/// does not list it among the overrides on every level.
#[test]
fn the_report_never_lists_a_varied_key_as_set_on_every_level() {
    let tmp = tempfile::tempdir().unwrap();
    let o = short_ladder(tmp.path(), "11,21,41", &["--set", "canopy.nodes=5"]);
    assert_exit(&o, 0);
    let md = std::fs::read_to_string(tmp.path().join("cv/convergence.md")).unwrap();
    let line = md
        .lines()
        .find(|l| l.starts_with("Overrides on every level"))
        .unwrap();
    assert!(
        line.contains("time.duration_s=0.02") && !line.contains("canopy.nodes"),
        "{line}"
    );
}

/// A ladder of another scenario file with the same name is another study: converging it into
/// the first ladder's directory is refused (status 2), the first ladder unchanged.
#[test]
fn a_ladder_of_another_scenario_file_never_replaces_one_of_the_same_name() {
    let tmp = tempfile::tempdir().unwrap();
    let o = short_ladder(tmp.path(), "11,21,41", &[]);
    assert_exit(&o, 0);
    let copy = tmp.path().join("copy.toml");
    let text = std::fs::read_to_string(rod_file())
        .unwrap()
        .replace("weight_n = 200.0", "weight_n = 300.0");
    std::fs::write(&copy, text).unwrap();
    let copy = copy.display().to_string();
    let o = converge(
        tmp.path(),
        &[
            &copy,
            "--vary",
            "canopy.nodes=11,21,41",
            "--set",
            "time.duration_s=0.02",
            "--out",
            "cv",
        ],
    );
    assert_exit_says(&o, 2, &["holds the cases of study"]);
}

/// A level whose run read other bytes of its mesh than the file has now (edited while the
/// ladder ran, then put back) is reported failed, never fitted; here its run's record says so,
/// and the shard that re-reads it reports it with the reason.
#[test]
fn a_level_whose_run_read_another_mesh_is_not_fitted() {
    let tmp = tempfile::tempdir().unwrap();
    hex_project(tmp.path());
    let ladder = |extra: &[&str]| {
        let args = ["hex.toml", "--vary", "time.dt_s=0.01,0.005", "--out", "cv"];
        let args: Vec<&str> = args.iter().chain(extra).copied().collect();
        converge(
            tmp.path(),
            &[&args[..], &["--set", "time.duration_s=0.02"]].concat(),
        )
    };
    assert_eq!(ladder(&[]).status.code(), Some(0));
    // The same ladder through `/dev/stdin` reads the relative mesh next to the real file.
    let o = chute_command()
        .current_dir(tmp.path())
        .args([
            "converge",
            "/dev/stdin",
            "--vary",
            "time.dt_s=0.01,0.005",
            "--out",
            "cs",
        ])
        .args(["--set", "time.duration_s=0.02"])
        .stdin(std::fs::File::open(tmp.path().join("hex.toml")).unwrap())
        .output()
        .unwrap();
    assert_exit(&o, 0);
    forge_input_digest(&tmp.path().join("cv/dt_s-0.005"));
    let o = ladder(&["--shard", "0/2"]);
    let report = std::fs::read_to_string(tmp.path().join("cv/convergence.md")).unwrap();
    assert!(report.contains("its run read canopy.mesh_file"), "{report}");
    assert_exit(&o, 3);
}

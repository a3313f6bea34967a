//! Line pulls on whole (coarse, short) runs: a pull on one side tilts the canopy and makes it
//! glide that way, the mirror pull glides in the mirror direction, pulling every line changes
//! the descent rate the way the drag area of the pulled shape predicts, and a released pull returns
//! the canopy to its free steady descent.
//!
//! The canopy is a 3 m square on four corner lines (the mesh and the sites are mirror
//! symmetric about both axes), 0.5 m elements, dt = 0.01 s: about 3 s of wall time per run.
//! The round canopy under the report's panel law is not used: its model is mirror-symmetric
//! (rim sites on rim nodes), but its free descent is not (the symmetric shape buckles from
//! round-off and glides), and its glide response to a pull depends on the line and turns
//! within seconds (docs/notes/control-2026-12.md). Under the inflation pressure its open-loop
//! response is not repeatable either (it changes with dt), but closed-loop guidance lands it
//! closer on every level measured, and one guidance test flies it.
use crate::common::*;

use chute::app::run_config;
use chute::build::build;
use chute::output::Summary;
use chute::runner::Session;
use chute::scenario::Scenario;

/// Lines are the corners in node-set order: 0 (−x, −y), 1 (+x, −y), 2 (+x, +y), 3 (−x, +y).
fn square(duration: f64, pulls: &str) -> Scenario {
    let set: Vec<String> = SQUARE_ON_CORNERS
        .iter()
        .chain(&[
            "time.dt_s=0.01",
            // Mirror runs agree to round-off only if each step is solved to round-off: the
            // accuracy-based tolerance lets mirrored runs take different Newton paths.
            "time.newton_strict=true",
            "output.frame_interval_s=1",
            "output.snapshots_s=[]",
        ])
        .map(|s| s.to_string())
        .chain([
            format!("time.duration_s={duration}"),
            format!("control=[{pulls}]"),
        ])
        .collect();
    Scenario::load(&repo().join("scenarios/control-steer.toml"), &set).unwrap()
}

/// Run to the end; the summary and the drag area of the final shape (m²): 2 F_z / (ρ U²) of
/// every drag family on the frozen shape moving down at U = 1 m/s, all nodes alike.
fn fly(s: &Scenario) -> (Summary, f64) {
    let mut session = Session::new(build(s).unwrap(), run_config(s, false)).unwrap();
    while let Ok(Some(_)) = session.step() {}
    assert!(session.finished() && session.stop_reason().is_none());
    let b = session.built();
    let q = &b.state.q;
    let n_pos = 3 * b.model.layout.n_nodes;
    let v: Vec<f64> = (0..q.len())
        .map(|d| if d < n_pos && d % 3 == 2 { -1.0 } else { 0.0 })
        .collect();
    let input = engine::EvalInput::outside_step(q, &v, b.state.t, false);
    let mut fz = 0.0;
    for &id in &b.drag_forces {
        let f = b.model.force(id);
        let mut blocks = f.new_blocks();
        f.evaluate(&input, &mut blocks);
        fz += f
            .stencils()
            .iter()
            .zip(&blocks.f)
            .filter(|(&d, _)| d < n_pos && d % 3 == 2)
            .map(|(_, f)| f)
            .sum::<f64>();
    }
    let sum = session.summary();
    assert!(sum.reached_terminal, "not steady: {}", sum.to_json());
    (sum, 2.0 * fz / s.fluid.density_kg_m3)
}

fn pull(lines: &str, shorten: f64) -> String {
    format!("{{lines = [{lines}], start_s = 2.0, ramp_s = 0.5, shorten_m = {shorten}}}")
}

#[test]
fn a_pull_glides_towards_the_pulled_side_and_its_mirror_mirrors() {
    let (free, _) = fly(&square(8.0, ""));
    let [vx0, vy0] = free.horizontal_velocity_mps;
    // The free square falls straight: nothing but round-off across.
    assert!(vx0.hypot(vy0) < 1e-9, "{vx0} {vy0}");
    // Lines 1 and 2 (the +x side, symmetric about the x axis): glide along +x only.
    let (plus_x, _) = fly(&square(8.0, &pull("1, 2", 0.3)));
    let [vx, vy] = plus_x.horizontal_velocity_mps;
    assert!(vx > 0.1 * plus_x.terminal_velocity_mps.abs(), "vx = {vx}");
    // Across, only what the Newton tolerance (1e-9 of the weight W per step) lets through: an
    // asymmetric residual f ≤ tol at terminal speed moves the canopy sideways by
    // f / (∂D/∂v) = f v_t / (2 W) ≤ 1e-9 v_t / 2.
    let across = 1e-9 * plus_x.terminal_velocity_mps.abs();
    assert!(vy.abs() < across, "vy = {vy}");
    assert!(plus_x.glide_angle_deg > 3.0, "{}", plus_x.glide_angle_deg);
    // Their mirror through the y axis (lines 3 and 0, the −x side) glides the mirror way.
    let (minus_x, _) = fly(&square(8.0, &pull("3, 0", 0.3)));
    let [mx, my] = minus_x.horizontal_velocity_mps;
    assert!(
        (mx + vx).abs() < 1e-6 * vx && my.abs() < across,
        "{mx} {my}"
    );
    // One corner, and its mirror through the x axis: towards that corner, mirrored in y.
    let (one, _) = fly(&square(8.0, &pull("1", 0.3)));
    let (two, _) = fly(&square(8.0, &pull("2", 0.3)));
    let [ax, ay] = one.horizontal_velocity_mps;
    let [bx, by] = two.horizontal_velocity_mps;
    assert!(ax > 0.0 && ay < 0.0, "line 1 at (+x, −y): {ax} {ay}");
    assert!(
        (ax - bx).abs() < 1e-6 * ax && (ay + by).abs() < 1e-6 * ax,
        "{bx} {by}"
    );
    // Towards the corner: along the diagonal (the square's symmetry about it).
    assert!((ax + ay).abs() < 1e-6 * ax, "{ax} {ay}");
}

/// Shortening (lengthening) every line by 0.3 m changes the canopy's shape and so its drag
/// area C_D A, measured on the frozen final shape; the steady descent rate changes as
/// v_t = √(2 W / (ρ C_D A)) predicts: in direction, and in size to within 0.5 % of v_t
/// (the canopy in steady descent moves nearly as a rigid body, the measurement's premise).
#[test]
fn pulling_all_lines_changes_the_descent_as_the_drag_area_predicts() {
    let (free, a0) = fly(&square(6.0, ""));
    let v0 = free.terminal_velocity_mps.abs();
    assert!((v0 / (2.0 * free.total_weight_n / (1.225 * a0)).sqrt() - 1.0).abs() < 5e-3);
    for shorten in [0.3, -0.3] {
        let (pulled, a) = fly(&square(6.0, &pull("0, 1, 2, 3", shorten)));
        let [vx, vy] = pulled.horizontal_velocity_mps;
        assert!(vx.hypot(vy) < 1e-9, "a symmetric pull glides: {vx} {vy}");
        let v = pulled.terminal_velocity_mps.abs();
        let predicted = (a0 / a).sqrt();
        let msg = format!("shorten {shorten}: v {v0} → {v}, drag area {a0} → {a}");
        assert!(
            (a / a0 - 1.0).abs() > 1e-3,
            "the pull changed nothing: {msg}"
        );
        assert!((v / v0 - 1.0) * (predicted - 1.0) > 0.0, "{msg}");
        assert!((v / v0 - predicted).abs() < 5e-3, "{msg}");
    }
}

/// A pull held 2 s and released: the canopy comes back to the free descent (within the 1 %
/// steadiness band of the terminal velocity, and gliding at under 1 % of it).
#[test]
fn a_released_pull_returns_to_the_free_steady_descent() {
    let (free, _) = fly(&square(10.0, ""));
    let held = "{lines = [1, 2], start_s = 2.0, ramp_s = 0.5, shorten_m = 0.3, hold_s = 2.0}";
    let (back, _) = fly(&square(10.0, held));
    let v0 = free.terminal_velocity_mps;
    assert!(
        (back.terminal_velocity_mps / v0 - 1.0).abs() < 0.01,
        "{} vs {v0}",
        back.terminal_velocity_mps
    );
    let [vx, vy] = back.horizontal_velocity_mps;
    assert!(vx.hypot(vy) < 0.01 * v0.abs(), "still gliding: {vx} {vy}");
}

/// Run `s` into a fresh directory; the summary as JSON and the directory.
fn run_in_dir(s: &Scenario) -> (serde_json::Value, tempfile::TempDir) {
    let dir = tempfile::tempdir().unwrap();
    let (_, j) = run_complete(s, dir.path());
    (j, dir)
}

/// The 30 m drop of control-guidance.toml towards (5, 12) m at dt = 0.005 s with the
/// `canopy` overrides, uncontrolled (a pull of a nanometre at most, so that its miss is
/// reported too) and guided (0.3 m): the two misses (m), the guided summary and run directory.
fn drop_30m(canopy: &[&str]) -> (f64, f64, serde_json::Value, tempfile::TempDir) {
    let drop = |max_pull: &str| {
        let set: Vec<String> = canopy
            .iter()
            .chain(&[
                "atmosphere.altitude_m=30",
                "guidance.target_m=[5, 12]",
                "time.dt_s=0.005",
                max_pull,
            ])
            .map(|s| s.to_string())
            .collect();
        Scenario::load(&repo().join("scenarios/control-guidance.toml"), &set).unwrap()
    };
    let (free, _) = run_in_dir(&drop("guidance.max_pull_m=1e-9"));
    let (steered, dir) = run_in_dir(&drop("guidance.max_pull_m=0.3"));
    let miss = |j: &serde_json::Value| j["landing_miss_m"].as_f64().unwrap();
    (miss(&free), miss(&steered), steered, dir)
}

/// A 30 m drop of the guidance scenario (1976 atmosphere, ground, a 2 m/s crosswind along +y)
/// with the square canopy on four corner lines, which glides towards its pulled side (the
/// default `pull_side = "shape"` picks that for a rectangle): uncontrolled it drifts to about
/// (0, 9.6) m; guided to (5, 12) m it lands closer (5.5 m → 3.4 m at dt = 0.005 s). The flight is 5.5 s, of which the first
/// two inflate the canopy; dt = 0.01 s does not resolve that transient (the guided run then
/// misses by more: docs/control.md), hence the smaller step here.
#[test]
fn guidance_lands_closer_to_the_target_than_the_uncontrolled_drop() {
    let mut canopy = SQUARE_ON_CORNERS.to_vec();
    canopy.push("fluid.shell_drag=\"report\"");
    let (m0, m1, steered, dir) = drop_30m(&canopy);
    assert!(m1 < m0 - 1.0, "steered miss {m1} m vs uncontrolled {m0} m");
    let p = steered["landing_point_m"].as_array().unwrap();
    let (x, y) = (p[0].as_f64().unwrap(), p[1].as_f64().unwrap());
    assert!((m1 - (x - 5.0).hypot(y - 12.0)).abs() < 1e-12);
    // The outputs of a pulled run: lines.csv (4 lines per frame), track.csv, track.png.
    let lines = std::fs::read_to_string(dir.path().join("lines.csv")).unwrap();
    let mut rows = lines.lines();
    assert_eq!(
        rows.next(),
        Some("t_s,line,rest_length_m,length_m,tension_n")
    );
    let rows: Vec<Vec<f64>> = rows
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len() % 4, 0);
    // Guidance pulls at most 0.3 m: every rest length within [2.7, 3] m.
    assert!(rows
        .iter()
        .all(|r| r[2] <= 3.0 + 1e-12 && r[2] >= 2.7 - 1e-12));
    assert!(rows.iter().any(|r| r[2] < 3.0 - 1e-3), "nothing was pulled");
    assert!(dir.path().join("track.csv").is_file() && dir.path().join("track.png").is_file());
}

/// The round canopy under the inflation pressure (`fluid.shell_drag = "inflation"`) glides
/// towards its pulled side, so guidance steers it too: the 30 m drop of the test above, with
/// the round canopy of control-guidance.toml and its default `pull_side = "shape"`. Measured
/// (docs/control.md): uncontrolled misses 3.1–6.7 m over dt 0.01…0.00125 s and the 0.3, 0.16
/// and 0.12 m meshes (its own spontaneous glide depends on the level), guided 2.1–2.9 m on
/// every level; at dt = 0.005 s 5.3 m against 2.3 m.
#[test]
fn guidance_brings_the_inflated_round_canopy_closer_to_the_target() {
    let (m0, m1, _, _) = drop_30m(&[]);
    assert!(m1 < m0 - 1.0, "steered miss {m1} m vs uncontrolled {m0} m");
}

/// lines.csv of a scheduled pull: line 0's rest length follows the ramp exactly, the others
/// stay at 3 m, and the lines are taut (tension > 0 after the canopy has inflated).
#[test]
fn lines_csv_follows_the_schedule() {
    let s = square(
        3.0,
        "{lines = [1], start_s = 1.0, ramp_s = 0.5, shorten_m = 0.3}",
    );
    let (_, dir) = run_in_dir(&s);
    let text = std::fs::read_to_string(dir.path().join("lines.csv")).unwrap();
    for row in text.lines().skip(1) {
        let r: Vec<f64> = row.split(',').map(|x| x.parse().unwrap()).collect();
        let (t, line, rest) = (r[0], r[1] as usize, r[2]);
        let want = if line == 1 {
            3.0 - 0.3 * ((t - 1.0) / 0.5).clamp(0.0, 1.0)
        } else {
            3.0
        };
        // The line's rest length is L₀ − s(t), L₀ = 3 m to round-off of the segment sum.
        assert!(
            (rest - want).abs() < 1e-12,
            "t = {t}, line {line}: {rest} vs {want}"
        );
        if t >= 1.0 {
            assert!(r[4] > 0.0 && r[3] > rest, "slack line at t = {t}: {row}");
        }
    }
    assert!(dir.path().join("track.png").is_file());
}

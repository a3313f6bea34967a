//! The opening of a packed round canopy (`scenarios/opening.toml`, docs/opening.md): its cloth
//! and lines never pass through each other while it fills, and the run reports the opening
//! shock in the handbook's terms.
use chute::build::build;
use chute::scenario::Scenario;
use engine::contact::intersect::{first_crossing, segments_passing};

use crate::common::{repo, run_complete};

fn opening(set: &[&str]) -> Scenario {
    let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
    Scenario::load(&repo().join("scenarios/opening.toml"), &set).unwrap()
}

/// Both packings start free of intersections with the lines at full length; through the
/// first 60 ms of the opening (the peak force at about 36 ms, the cloth folding as it fills)
/// no edge passes through a triangle and no line through another after any accepted step,
/// and the canopy has filled from its packed diameter to most of its flat one.
#[test]
fn a_packed_canopy_opens_without_passing_through_itself() {
    let s = opening(&["opening.pack=bundle"]);
    let b = build(&s).unwrap();
    assert_eq!(
        first_crossing(b.contact.as_ref().unwrap(), &b.state.q),
        None
    );
    let s = opening(&[]);
    let mut b = build(&s).unwrap();
    let surface = b.contact.clone().unwrap();
    let lines = surface.line_edges.clone();
    let canopy = b.canopy_nodes.clone();
    let diameter = |q: &[f64]| {
        let r = (canopy.iter())
            .map(|&i| q[3 * i].hypot(q[3 * i + 1]))
            .fold(0.0, f64::max);
        2.0 * r
    };
    let d0 = diameter(&b.state.q);
    assert!((d0 - 0.3).abs() < 1e-9, "packed diameter {d0}");
    let rebuilds = step_until(&s, &mut b, 0.06, |t, before, q| {
        assert_eq!(first_crossing(&surface, q), None, "t = {t}");
        assert_eq!(segments_passing(&lines, before, q), None, "t = {t}");
    });
    let d = diameter(&b.state.q);
    assert!(d > 0.6 * 3.0, "diameter {d} m after 60 ms");
    assert!(rebuilds > 0);
}

/// Tilted 30° from the vertical and falling vertically (the flow 30° off its axis): the start
/// is the vertical one turned about the apex (the payload on the tilted axis, the skirt at the
/// packed radius around it), and through the first 60 ms nothing passes through anything
/// while the canopy fills to most of its flat diameter.
#[test]
fn a_tilted_canopy_opens_without_passing_through_itself() {
    let s = opening(&["opening.attitude_deg=30"]);
    let mut b = build(&s).unwrap();
    let (surface, payload) = (b.contact.clone().unwrap(), b.payload_node.unwrap());
    let lines = surface.line_edges.clone();
    let at = |q: &[f64], i: usize| nalgebra::Vector3::new(q[3 * i], q[3 * i + 1], q[3 * i + 2]);
    let q0 = b.state.q.clone();
    let apex = *(b.canopy_nodes.iter())
        .max_by(|&&i, &&j| {
            let d = |k| (at(&q0, k) - at(&q0, payload)).norm();
            d(i).total_cmp(&d(j))
        })
        .unwrap();
    let canopy = b.canopy_nodes.clone();
    // The largest distance of the cloth from the axis through the apex and the payload.
    let radius = |q: &[f64]| {
        let a = at(q, apex);
        let e = (at(q, payload) - a).normalize();
        (canopy.iter())
            .map(|&i| (at(q, i) - a).cross(&e).norm())
            .fold(0.0, f64::max)
    };
    let e = (at(&q0, payload) - at(&q0, apex)).normalize();
    assert!((-e.z - 30f64.to_radians().cos()).abs() < 1e-9, "axis {e}");
    assert!(
        (radius(&q0) - 0.15).abs() < 1e-9,
        "packed radius {}",
        radius(&q0)
    );
    step_until(&s, &mut b, 0.06, |t, before, q| {
        assert_eq!(first_crossing(&surface, q), None, "t = {t}");
        assert_eq!(segments_passing(&lines, before, q), None, "t = {t}");
    });
    let r = radius(&b.state.q);
    assert!(2.0 * r > 0.6 * 3.0, "diameter {} m after 60 ms", 2.0 * r);
}

/// Step `b` to `t_end` as a run does (a failed step halved, then grown back), calling
/// `check(t, q before, q after)` after every accepted step; the pattern rebuilds it took.
fn step_until(
    s: &Scenario,
    b: &mut chute::build::Built,
    t_end: f64,
    mut check: impl FnMut(f64, &[f64], &[f64]),
) -> u64 {
    let mut stepper = engine::ImplicitEuler::new(&b.model, chute::resolve::newton(s)).unwrap();
    let mut dt = s.time.dt_s;
    while b.state.t < t_end {
        let before = b.state.q.clone();
        match stepper.step(&mut b.model, &mut b.state, dt) {
            Ok(_) => dt = s.time.dt_s.min(2.0 * dt),
            Err(e) => {
                dt *= 0.5;
                assert!(dt > 1e-7, "step failed at t = {}: {e}", b.state.t);
                continue;
            }
        }
        check(b.state.t, &before, &b.state.q);
    }
    stepper.counters().pattern_rebuilds
}

/// A whole opening to steady descent: the summary's opening fields are there and physical
/// (the shock well above the weight, the load factor within the acceptance range of
/// (0.05, 5), the fill within the first second), and the console says it.
#[test]
fn the_opening_shock_is_reported() {
    let s = opening(&["time.duration_s=1.6", "output.snapshots_s=[]"]);
    let dir = tempfile::tempdir().unwrap();
    let (b, summary) = run_complete(&s, dir.path());
    let w = b.total_weight_n;
    let peak = summary["opening_peak_force_n"].as_f64().unwrap();
    assert!(peak > 5.0 * w, "peak {peak} N, weight {w} N");
    let factor = summary["opening_load_factor"].as_f64().unwrap();
    assert!(factor > 0.05 && factor < 5.0, "{factor}");
    let t_fill = summary["opening_fill_time_s"].as_f64().unwrap();
    assert!(t_fill > 0.0 && t_fill < 1.0, "{t_fill}");
    let fill = summary["opening_fill_distance_diameters"].as_f64().unwrap();
    // Falling at 25 m/s at most over the fill: 25 t_fill / D₀ at most.
    assert!(fill > 0.0 && fill <= 25.0 * t_fill / 3.0, "{fill}");
    // The factor is the peak over C_D·S q at line stretch.
    let cds = summary["drag_area_m2"].as_f64().unwrap();
    let q = 0.5 * s.fluid.density_kg_m3 * 25.0 * 25.0;
    assert!((factor - peak / (cds * q)).abs() < 1e-12 * factor);
}

/// What an opening needs, refused with exit status 2 naming the key: `[contact]`, a round
/// canopy, a contact distance the packed start leaves room for, a packed radius below half
/// the canopy's, the canopy's speed for a tilted start.
#[test]
fn an_opening_without_what_it_needs_is_refused() {
    use crate::common::{assert_refused, check_bundled, chute};
    let tmp = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(repo().join("scenarios/opening.toml")).unwrap();
    let bare = text.replace("[contact]", "");
    std::fs::write(tmp.path().join("bare.toml"), bare).unwrap();
    let o = chute(tmp.path(), &["check", "bare.toml"]);
    assert_refused(&o, &["opening.pack", "[contact]"]);
    let o = check_bundled(
        "opening.toml",
        &["canopy.shape=hexagon", "load.sites=corners"],
    );
    assert_refused(&o, &["opening.pack", "round canopy"]);
    let o = check_bundled("opening.toml", &["contact.distance_m=0.02"]);
    assert_refused(&o, &["contact.distance_m", "closest parts"]);
    let o = check_bundled("opening.toml", &["opening.packed_radius_m=0.8"]);
    assert_refused(&o, &["opening.packed_radius_m", "radius_m / 2"]);
    let panel = ["opening.attitude_deg=30", "fluid.inflation_speed=\"panel\""];
    let o = check_bundled("opening.toml", &panel);
    assert_refused(
        &o,
        &["opening.attitude_deg", "inflation_speed = \"canopy\""],
    );
}

/// A flat round canopy (round-fabric at 0.3 m, with contact) crumpled by a strong inward
/// load: every canopy node pushed towards the axis by 20 × its weight. Over 0.15 s the cloth
/// folds onto itself (its nodes' mean radius falls below half the flat one's) and no edge passes
/// through a triangle after any accepted step.
#[test]
fn a_canopy_crumpled_by_a_strong_inward_load_never_passes_through_itself() {
    let set: Vec<String> = ["contact.stop_speed_mps=10", "canopy.edge_length_m=0.3"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    let s = Scenario::load(&repo().join("scenarios/round-fabric.toml"), &set).unwrap();
    let mut b = build(&s).unwrap();
    let surface = b.contact.clone().unwrap();
    let q0 = b.state.q.clone();
    let g = s.fluid.gravity_mps2;
    let push: Vec<[f64; 3]> = (b.canopy_nodes.iter())
        .map(|&i| {
            let (x, y) = (q0[3 * i], q0[3 * i + 1]);
            let r = x.hypot(y).max(1e-9);
            let f = 20.0 * b.model.node_mass(i) * g;
            [-f * x / r, -f * y / r, 0.0]
        })
        .collect();
    let nodes = b.canopy_nodes.clone();
    b.model
        .add_force(engine::loads::PointForces::new(&nodes, &push));
    step_until(&s, &mut b, 0.15, |t, _, q| {
        assert_eq!(first_crossing(&surface, q), None, "t = {t}");
    });
    let mean_radius = |q: &[f64]| {
        let (cx, cy) = (q[0], q[1]);
        let sum: f64 = (nodes.iter())
            .map(|&i| (q[3 * i] - cx).hypot(q[3 * i + 1] - cy))
            .sum();
        sum / nodes.len() as f64
    };
    let (flat, crumpled) = (mean_radius(&q0), mean_radius(&b.state.q));
    assert!(
        crumpled < 0.5 * flat,
        "mean radius {crumpled} m, flat {flat} m"
    );
}

/// `pack = "mesh"` takes the folded canopy from a file: the pulled start written as an OBJ
/// (the canopy's nodes in order, its triangles) and read back gives the same start, lines and
/// payload included; a file that is not the canopy's mesh is refused naming the key.
#[test]
fn a_folded_canopy_is_read_from_a_mesh_file() {
    use crate::common::{assert_refused, check_bundled};
    use std::fmt::Write;
    let pulled = build(&opening(&[])).unwrap();
    let mut obj = String::new();
    for &i in &pulled.canopy_nodes {
        let p = &pulled.state.q[3 * i..3 * i + 3];
        writeln!(obj, "v {} {} {}", p[0], p[1], p[2]).unwrap();
    }
    for t in &pulled.triangles {
        writeln!(obj, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1).unwrap();
    }
    let tmp = tempfile::tempdir().unwrap();
    let file = tmp.path().join("folded.obj");
    std::fs::write(&file, &obj).unwrap();
    let set = format!("opening.mesh_file={}", file.display());
    let folded = build(&opening(&["opening.pack=mesh", &set])).unwrap();
    let (a, b) = (&pulled.state.q, &folded.state.q);
    let worst = a
        .iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    assert!(worst < 1e-12, "starts differ by {worst} m");
    // Its first triangle dropped: not the canopy's mesh.
    let cut: String = obj
        .lines()
        .filter(|l| *l != obj.lines().find(|l| l.starts_with('f')).unwrap())
        .map(|l| format!("{l}\n"))
        .collect();
    std::fs::write(&file, cut).unwrap();
    let o = check_bundled("opening.toml", &["opening.pack=mesh", &set]);
    assert_refused(&o, &["opening.mesh_file", "not the canopy mesh"]);
}

//! The round canopy's load pattern has no handedness (docs/scenarios.md): its rim sites sit on
//! nodes at exactly the sites' angles, the built model is mirror-symmetric about every site's
//! plane, and in free descent it neither spins nor drifts.
use std::f64::consts::TAU;

use chute::build::build;
use chute::scenario::Scenario;

use crate::common::{repo, run_complete};

/// The round canopy at 0.3 m (before the fix this put 30 rim nodes every 12°, so the sites
/// at 30°, 90°, … were attached at 24°/36°, 84°/96°, …: chiral), coarse in dt, for the first
/// 0.4 s of the fall. Later (measured between 0.4 and 0.8 s on this mesh) the symmetric
/// shape buckles and the mode that grows from round-off is chiral: the canopy then spins
/// although the model has no handedness (docs/notes/engineering-2026-12.md), so a longer run
/// cannot test the load pattern's symmetry.
fn coarse_round(extra: &[&str]) -> Scenario {
    let mut set: Vec<String> = [
        "canopy.edge_length_m=0.3",
        "time.dt_s=2e-3",
        "time.duration_s=0.4",
        "output.frame_interval_s=0.2",
        "output.snapshots_s=[]",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    set.extend(extra.iter().map(|s| s.to_string()));
    Scenario::load(&repo().join("scenarios/round-parachute.toml"), &set).unwrap()
}

#[test]
fn round_canopy_sites_are_nodes_at_the_site_angles_and_the_model_is_mirror_symmetric() {
    let s = coarse_round(&[]);
    let b = build(&s).unwrap();
    let n = s.load.rim_site_count;
    assert_eq!(b.load_sites.len(), n);
    let q = &b.state.q;
    let at = |i: usize| [q[3 * i], q[3 * i + 1], q[3 * i + 2]];
    for (k, &i) in b.load_sites.iter().enumerate() {
        let a = TAU * k as f64 / n as f64;
        let p = at(i);
        let r = s.canopy.radius_m;
        assert!(
            (p[0] - r * a.cos()).abs() < 1e-12 && (p[1] - r * a.sin()).abs() < 1e-12,
            "site {k} at {p:?}, not at {}°",
            a.to_degrees()
        );
    }
    // Reflect the canopy about each site's plane: nodes onto nodes with equal lumped mass,
    // triangles onto triangles, sites onto sites.
    let nodes = &b.canopy_nodes;
    let image_of = |i: usize, phi: f64| -> Option<usize> {
        let (c, s2) = ((2.0 * phi).cos(), (2.0 * phi).sin());
        let p = at(i);
        let m = [c * p[0] + s2 * p[1], s2 * p[0] - c * p[1], p[2]];
        nodes.iter().copied().find(|&j| {
            let d = at(j);
            (d[0] - m[0]).abs() < 1e-12 && (d[1] - m[1]).abs() < 1e-12 && d[2] == m[2]
        })
    };
    let sorted = |mut f: [usize; 3]| {
        f.sort_unstable();
        f
    };
    let faces: std::collections::BTreeSet<_> = b.triangles.iter().map(|&f| sorted(f)).collect();
    let sites: std::collections::BTreeSet<_> = b.load_sites.iter().copied().collect();
    for k in 0..n {
        let phi = TAU * k as f64 / n as f64;
        let map: std::collections::HashMap<usize, usize> = nodes
            .iter()
            .map(|&i| (i, image_of(i, phi).expect("every node has an image")))
            .collect();
        for (&i, &j) in &map {
            let (mi, mj) = (b.model.node_mass(i), b.model.node_mass(j));
            assert!((mi - mj).abs() <= 1e-12 * mi, "mass {i} {mi} vs {j} {mj}");
        }
        assert!(b
            .triangles
            .iter()
            .all(|&f| faces.contains(&sorted(f.map(|i| map[&i])))));
        assert!(b.load_sites.iter().all(|i| sites.contains(&map[i])));
    }
}

/// Spin rate ω_z about the axis, rim-equivalent speed ω r_g and mean vertical velocity of the
/// canopy at the end of a run of `s`, and the summary.
fn spin_after(s: &Scenario) -> (f64, f64, f64, serde_json::Value) {
    let dir = tempfile::tempdir().unwrap();
    let (b, j) = run_complete(s, dir.path());
    let (q, v) = (&b.state.q, &b.state.v);
    let (mut lz, mut inertia, mut mass, mut vz) = (0.0, 0.0, 0.0, 0.0);
    for &i in &b.canopy_nodes {
        let m = b.model.node_mass(i);
        let (x, y) = (q[3 * i], q[3 * i + 1]);
        lz += m * (x * v[3 * i + 1] - y * v[3 * i]);
        inertia += m * (x * x + y * y);
        mass += m;
        vz += m * v[3 * i + 2];
    }
    let omega = lz / inertia;
    (omega, omega * (inertia / mass).sqrt(), vz / mass, j)
}

#[test]
fn round_canopy_descends_without_spin_or_drift() {
    let (omega, rim_speed, vz, j) = spin_after(&coarse_round(&[]));
    assert!(vz < -1.0, "falling: {vz} m/s");
    // Round-off level (measured ~1e-14 rad/s); 1e-9 of the descent speed at the radius of
    // gyration leaves room for its growth and is far below any forced spin (below).
    assert!(
        rim_speed.abs() < 1e-9 * vz.abs(),
        "spin ω_z = {omega} rad/s"
    );
    for vh in j["horizontal_velocity_mps"].as_array().unwrap() {
        assert!(vh.as_f64().unwrap().abs() < 1e-9 * vz.abs(), "{j}");
    }
    // The same check sees a handed model: the imperfection mode has a twist (odd in x and
    // y), and 1 mm of it spins the canopy far above the bound.
    let (omega, rim_speed, vz, _) = spin_after(&coarse_round(&["canopy.imperfection_m=1e-3"]));
    assert!(
        rim_speed.abs() > 1e-6 * vz.abs(),
        "imperfect canopy: ω_z = {omega} rad/s"
    );
}

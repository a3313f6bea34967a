//! The circle mesh holds its rim load sites as nodes and is mirror-symmetric about the sites'
//! planes: a load pattern with no handedness cannot make the canopy spin.
use chute::mesh::{generate, CanopyMesh};
use std::collections::BTreeSet;
use std::f64::consts::TAU;

/// Node nearest to `p` if it is within `tol` (the generator's round-off), else `None`.
fn node_at(m: &CanopyMesh, p: [f64; 3], tol: f64) -> Option<usize> {
    let d2 = |i: usize| {
        (0..3)
            .map(|c| (m.positions[i][c] - p[c]).powi(2))
            .sum::<f64>()
    };
    let best = (0..m.n_nodes()).min_by(|&a, &b| d2(a).total_cmp(&d2(b)))?;
    (d2(best).sqrt() <= tol).then_some(best)
}

fn sorted(f: [usize; 3]) -> [usize; 3] {
    let mut f = f;
    f.sort_unstable();
    f
}

/// Reflection of the mesh about the vertical plane at polar angle `phi`: every node maps to a
/// node (to `tol`) and every triangle to a triangle.
fn is_mirror_symmetric(m: &CanopyMesh, phi: f64, tol: f64) -> bool {
    let (c, s) = ((2.0 * phi).cos(), (2.0 * phi).sin());
    let map: Option<Vec<usize>> = m
        .positions
        .iter()
        .map(|p| node_at(m, [c * p[0] + s * p[1], s * p[0] - c * p[1], p[2]], tol))
        .collect();
    let Some(map) = map else { return false };
    let faces: BTreeSet<_> = m.faces.iter().map(|&f| sorted(f)).collect();
    m.faces
        .iter()
        .all(|&f| faces.contains(&sorted(f.map(|i| map[i]))))
}

#[test]
fn rim_nodes_lie_exactly_at_every_site_angle() {
    for &(r, edge, sites) in &[(1.5, 0.1, 12), (1.5, 0.2, 12), (1.5, 0.1, 8), (2.0, 0.3, 5)] {
        let m = generate::circle_with_rim_sites(r, edge, sites);
        let rim = m.node_set("rim").unwrap();
        assert_eq!(
            rim.len() % sites,
            0,
            "{sites} sites on {} rim nodes",
            rim.len()
        );
        for k in 0..sites {
            let a = TAU * k as f64 / sites as f64;
            let site = [r * a.cos(), r * a.sin(), 0.0];
            let i = node_at(&m, site, 1e-12 * r)
                .unwrap_or_else(|| panic!("no node at site {k} ({a} rad), edge {edge}"));
            assert!(rim.contains(&i));
        }
        // The ring count stays the nearest admissible one to R / edge.
        let n = rim.len() / 6;
        let q = sites / gcd(sites, 6);
        assert!(
            (n as f64 - r / edge).abs() <= 0.5 * q as f64 + 1e-9,
            "n = {n}"
        );
    }
}

fn gcd(a: usize, b: usize) -> usize {
    if b == 0 {
        a
    } else {
        gcd(b, a % b)
    }
}

#[test]
fn circle_is_mirror_symmetric_about_every_multiple_of_30_degrees() {
    for &(edge, sites) in &[(0.1, 12), (0.25, 12), (0.3, 1), (0.2, 4)] {
        let m = generate::circle_with_rim_sites(1.5, edge, sites);
        m.tri_mesh().expect("consistent, manifold");
        for j in 0..6 {
            let phi = TAU * j as f64 / 12.0;
            assert!(
                is_mirror_symmetric(&m, phi, 1e-12),
                "edge {edge}: not symmetric about {}°",
                30 * j
            );
        }
        // Not about 15°: the check can fail (the D6 mesh is not D12).
        assert!(!is_mirror_symmetric(&m, TAU / 24.0, 1e-12));
    }
}

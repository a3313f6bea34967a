//! The rectangle's three mesh patterns (union-jack, cross, unstructured), as properties over
//! random outlines and resolutions: valid manifold meshes oriented along +z, areas that sum
//! to the rectangle, a minimum angle, the load sites on nodes at their exact places, the rim
//! equal to the boundary, and the same mesh from the same arguments.
use chute::mesh::generate::{rectangle_pattern, Pattern};
use chute::mesh::unstructured::MIN_ANGLE_DEG;
use chute::mesh::CanopyMesh;
use proptest::prelude::*;
use std::collections::BTreeSet;

const PATTERNS: [Pattern; 3] = [Pattern::UnionJack, Pattern::Cross, Pattern::Unstructured];

/// Smallest interior angle of the mesh (degrees).
fn min_angle_deg(m: &CanopyMesh) -> f64 {
    let mut worst = 180.0f64;
    for f in &m.faces {
        for k in 0..3 {
            let [a, b, c] = [f[k], f[(k + 1) % 3], f[(k + 2) % 3]].map(|i| m.positions[i]);
            let (u, v) = ([b[0] - a[0], b[1] - a[1]], [c[0] - a[0], c[1] - a[1]]);
            let cos = (u[0] * v[0] + u[1] * v[1]) / (u[0].hypot(u[1]) * v[0].hypot(v[1]));
            worst = worst.min(cos.clamp(-1.0, 1.0).acos().to_degrees());
        }
    }
    worst
}

/// Check every property of `pattern` on the `span × width` rectangle with `target` edges;
/// structured cells have aspect ratio within [0.6, 1.7] here, hence angles ≥ 30°.
fn check(span: f64, width: f64, target: f64, pattern: Pattern) {
    let m = rectangle_pattern(span, width, target, pattern);
    let tri = m
        .tri_mesh()
        .expect("consistent orientation, edge-manifold, no degenerate face");
    for f in &m.faces {
        let [a, b, c] = f.map(|i| m.positions[i]);
        let z = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        assert!(z > 0.0, "{pattern:?}: face {f:?} not counter-clockwise");
    }
    let area = span * width;
    assert!(
        (tri.area() - area).abs() < 1e-12 * area,
        "{pattern:?}: area {}",
        tri.area()
    );
    let bound = if pattern == Pattern::Unstructured {
        MIN_ANGLE_DEG
    } else {
        30.0
    };
    let worst = min_angle_deg(&m);
    assert!(
        worst >= bound - 1e-9,
        "{pattern:?}: min angle {worst}° < {bound}°"
    );
    let at = |set: &str| -> Vec<[f64; 2]> {
        m.node_set(set)
            .unwrap_or_else(|| panic!("{pattern:?}: no {set}"))
            .iter()
            .map(|&i| [m.positions[i][0], m.positions[i][1]])
            .collect()
    };
    let (hs, hw) = (0.5 * span, 0.5 * width);
    // To round-off of the node formula (1 ulp of the size).
    let same = |set: &str, want: Vec<[f64; 2]>| {
        let got = at(set);
        assert_eq!(got.len(), want.len(), "{pattern:?}: {set}");
        for (g, w) in got.iter().zip(&want) {
            let d = (g[0] - w[0]).abs().max((g[1] - w[1]).abs());
            assert!(
                d <= 1e-14 * span.max(width),
                "{pattern:?}: {set} at {g:?}, not {w:?}"
            );
        }
    };
    same("corners", vec![[-hs, -hw], [hs, -hw], [hs, hw], [-hs, hw]]);
    same("center", vec![[0.0, 0.0]]);
    let mids = if span >= width {
        vec![[0.0, -hw], [0.0, hw]]
    } else {
        vec![[hs, 0.0], [-hs, 0.0]]
    };
    same("long_edge_midpoints", mids);
    let rim: BTreeSet<usize> = m.node_set("rim").unwrap().iter().copied().collect();
    let boundary: BTreeSet<usize> = tri.boundary_nodes.iter().copied().collect();
    assert_eq!(rim, boundary, "{pattern:?}: rim is not the boundary");
    assert_eq!(
        m.node_set("rim").unwrap()[0],
        m.node_set("corners").unwrap()[0]
    );
    assert_eq!(
        m,
        rectangle_pattern(span, width, target, pattern),
        "{pattern:?}: not deterministic"
    );
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, failure_persistence: None, ..ProptestConfig::default() })]
    #[test]
    fn every_pattern_meshes_the_rectangle(
        span in 0.5f64..6.0,
        aspect in 0.5f64..2.0,
        cells in 4usize..24,
    ) {
        let width = span / aspect;
        let target = span.min(width) / cells as f64;
        for pattern in PATTERNS {
            check(span, width, target, pattern);
        }
    }
}

#[test]
fn the_report_canopy_in_every_pattern() {
    for pattern in PATTERNS {
        check(6.0, 3.0, 0.25, pattern);
    }
    // The structured counts of the two patterns: 325 union-jack nodes, 613 with cell centres.
    assert_eq!(
        rectangle_pattern(6.0, 3.0, 0.25, Pattern::UnionJack).n_nodes(),
        325
    );
    assert_eq!(
        rectangle_pattern(6.0, 3.0, 0.25, Pattern::Cross).n_nodes(),
        613
    );
    let u = rectangle_pattern(6.0, 3.0, 0.25, Pattern::Unstructured);
    // Irregular: the node degrees are not the two of a lattice.
    let tri = u.tri_mesh().unwrap();
    let degrees: BTreeSet<usize> = tri.vertex_faces.iter().map(Vec::len).collect();
    assert!(degrees.len() >= 4, "degrees {degrees:?}");
}

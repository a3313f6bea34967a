//! Mesh generators: counts, node sets, orientation, symmetry and lattice regularity.
use chute::mesh::{generate, CanopyMesh};
use std::collections::{BTreeSet, HashMap};

/// Exact key of a point (the generators mirror coordinates exactly).
fn key(p: [f64; 3]) -> [u64; 3] {
    p.map(|x| (x + 0.0).to_bits())
}

/// Map every node to the node at the mirrored position; `None` if some node has no image.
fn mirror_map(m: &CanopyMesh, f: impl Fn([f64; 3]) -> [f64; 3]) -> Option<Vec<usize>> {
    let at: HashMap<[u64; 3], usize> = m
        .positions
        .iter()
        .enumerate()
        .map(|(i, &p)| (key(p), i))
        .collect();
    m.positions
        .iter()
        .map(|&p| at.get(&key(f(p))).copied())
        .collect()
}

fn face_set(faces: impl Iterator<Item = [usize; 3]>) -> BTreeSet<[usize; 3]> {
    faces
        .map(|mut f| {
            f.sort_unstable();
            f
        })
        .collect()
}

fn z_normal(m: &CanopyMesh, f: [usize; 3]) -> f64 {
    let [a, b, c] = f.map(|i| m.positions[i]);
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

#[test]
fn rectangle_is_mirror_symmetric_and_well_formed() {
    for &(span, width, target) in &[(6.0, 3.0, 0.2), (1.0, 1.0, 0.1), (2.0, 5.0, 0.7)] {
        let m = generate::rectangle(span, width, target);
        let tri = m.tri_mesh().expect("consistent, manifold");
        assert!(m.faces.iter().all(|&f| z_normal(&m, f) > 0.0));
        assert!((tri.area() - span * width).abs() < 1e-12 * span * width);
        let faces = face_set(m.faces.iter().copied());
        for flip in [[-1.0, 1.0], [1.0, -1.0]] {
            let map = mirror_map(&m, |p| [flip[0] * p[0], flip[1] * p[1], p[2]])
                .expect("every node has a mirror image");
            let mirrored = face_set(m.faces.iter().map(|f| f.map(|i| map[i])));
            assert_eq!(
                mirrored, faces,
                "triangulation not symmetric under {flip:?}"
            );
        }
        let at = |name: &str| -> Vec<[f64; 3]> {
            m.node_set(name)
                .unwrap()
                .iter()
                .map(|&i| m.positions[i])
                .collect()
        };
        let (hx, hy) = (span / 2.0, width / 2.0);
        assert_eq!(
            at("corners"),
            [
                [-hx, -hy, 0.0],
                [hx, -hy, 0.0],
                [hx, hy, 0.0],
                [-hx, hy, 0.0]
            ]
        );
        assert_eq!(at("center"), [[0.0, 0.0, 0.0]]);
        let mids = at("long_edge_midpoints");
        if span >= width {
            assert_eq!(mids, [[0.0, -hy, 0.0], [0.0, hy, 0.0]]);
        } else {
            assert_eq!(mids, [[hx, 0.0, 0.0], [-hx, 0.0, 0.0]]);
        }
        let rim: BTreeSet<usize> = m.node_set("rim").unwrap().iter().copied().collect();
        assert_eq!(rim, tri.boundary_nodes.iter().copied().collect());
        assert_eq!(rim.len(), m.node_set("rim").unwrap().len());
    }
    // Cell size: span 6 / target 0.2 → 30 cells (even), width 3 → 16 (rounded to even).
    let m = generate::rectangle(6.0, 3.0, 0.2);
    assert_eq!(m.n_nodes(), 31 * 17);
    assert_eq!(m.faces.len(), 2 * 30 * 16);
}

#[test]
fn hexagon_is_the_equilateral_lattice() {
    for n in [1usize, 2, 5] {
        let r = 1.5;
        let m = generate::hexagon(r, r / n as f64);
        assert_eq!(m.n_nodes(), 1 + 3 * n * (n + 1));
        assert_eq!(m.faces.len(), 6 * n * n);
        let tri = m.tri_mesh().unwrap();
        assert!(m.faces.iter().all(|&f| z_normal(&m, f) > 0.0));
        let l = r / n as f64;
        for &[a, b] in &tri.edges {
            let (p, q) = (m.positions[a], m.positions[b]);
            let len = ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt();
            assert!((len - l).abs() < 1e-12, "edge {a}-{b}: {len} vs {l}");
        }
        let area = 1.5 * 3f64.sqrt() * r * r;
        assert!((tri.area() - area).abs() < 1e-12);
        assert_eq!(m.node_set("rim").unwrap().len(), 6 * n);
        assert_eq!(tri.boundary_nodes.len(), 6 * n);
        for (s, &c) in m.node_set("corners").unwrap().iter().enumerate() {
            let a = s as f64 * std::f64::consts::FRAC_PI_3;
            let p = m.positions[c];
            assert!((p[0] - r * a.cos()).abs() < 1e-12 && (p[1] - r * a.sin()).abs() < 1e-12);
        }
        assert_eq!(m.positions[m.node_set("center").unwrap()[0]], [0.0; 3]);
    }
}

#[test]
fn circle_rings_lie_on_the_circle() {
    let (r, n) = (2.0, 8);
    let m = generate::circle(r, r / n as f64);
    let tri = m.tri_mesh().unwrap();
    assert!(m.faces.iter().all(|&f| z_normal(&m, f) > 0.0));
    assert_eq!(m.n_nodes(), 1 + 3 * n * (n + 1));
    for &i in m.node_set("rim").unwrap() {
        let p = m.positions[i];
        assert!(((p[0] * p[0] + p[1] * p[1]).sqrt() - r).abs() < 1e-12);
    }
    // Inner rings are inscribed polygons too, so the mesh area is that of the rim's
    // inscribed 48-gon only up to the small sagitta differences: 0.1 %.
    let m_rim = (6 * n) as f64;
    let polygon = 0.5 * m_rim * r * r * (std::f64::consts::TAU / m_rim).sin();
    assert!(
        (tri.area() - polygon).abs() < 1e-3 * polygon,
        "{} vs {polygon}",
        tri.area()
    );
    let rim: BTreeSet<usize> = m.node_set("rim").unwrap().iter().copied().collect();
    assert_eq!(rim, tri.boundary_nodes.iter().copied().collect());
}

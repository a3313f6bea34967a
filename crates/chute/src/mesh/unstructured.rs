//! Irregular rectangle meshes: the outline divided as the union-jack rectangle's, a seeded,
//! jittered hexagonal point cloud inside, a constrained Delaunay triangulation of both
//! (spade), then Delaunay refinement (Ruppert/Chew: spade's `refine`) inserting points until
//! every angle is at least [`MIN_ANGLE_DEG`] and every area at most [`MAX_AREA`] ×
//! target². The same arguments always give the same mesh (fixed seed, deterministic
//! insertion order).
use super::generate::even_cells;
use super::CanopyMesh;
use spade::{
    AngleLimit, ConstrainedDelaunayTriangulation, Point2, RefinementParameters, Triangulation,
};

/// Smallest angle the refinement guarantees (degrees); 25° is well inside the range
/// where Delaunay refinement terminates (≤ ~30°).
pub const MIN_ANGLE_DEG: f64 = 25.0;
/// Largest triangle area allowed, in units of target²: a right isosceles triangle of the
/// union-jack rectangle has ½; an equilateral one of edge ℓ has 0.43 ℓ².
pub const MAX_AREA: f64 = 0.5;
/// Jitter of the interior points, as a fraction of the target edge (uniform in ±).
const JITTER: f64 = 0.3;
/// Seed of the jitter.
const SEED: u64 = 0x5eed_0017;

/// splitmix64: a small, portable, seeded generator (the mesh must not change with a crate's
/// random-number algorithm).
struct SplitMix(u64);

impl SplitMix {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64
    }
    fn symmetric(&mut self, amp: f64) -> f64 {
        amp * (2.0 * self.next() - 1.0)
    }
}

/// The boundary loop counter-clockwise from `(−span/2, −width/2)`: `nx` points along each
/// long side and `ny` along each short side, as the union-jack rectangle's rim.
fn outline(span: f64, width: f64, nx: usize, ny: usize) -> Vec<[f64; 2]> {
    let (hs, hw) = (0.5 * span, 0.5 * width);
    // Exactly ±span/2, ±width/2 at the ends, so the boundary is recognised by its coordinates.
    let along = |k: usize, n: usize, len: f64| match k {
        0 => -0.5 * len,
        k if k == n => 0.5 * len,
        k => len * (2.0 * k as f64 - n as f64) / (2.0 * n as f64),
    };
    let x = |i: usize| along(i, nx, span);
    let y = |j: usize| along(j, ny, width);
    let mut p: Vec<[f64; 2]> = (0..nx).map(|i| [x(i), -hw]).collect();
    p.extend((0..ny).map(|j| [hs, y(j)]));
    p.extend((1..=nx).rev().map(|i| [x(i), hw]));
    p.extend((1..=ny).rev().map(|j| [-hs, y(j)]));
    p
}

/// Interior points: a hexagonal lattice of spacing `h` (rows `h √3/2` apart, alternate rows
/// shifted by `h/2`), each jittered by up to `JITTER h`, kept when at least `h/2` from the
/// outline and from the centre node.
fn interior(span: f64, width: f64, h: f64, rng: &mut SplitMix) -> Vec<[f64; 2]> {
    let dy = h * 3f64.sqrt() / 2.0;
    let (rows, cols) = ((width / dy).ceil() as i64, (span / h).ceil() as i64);
    let mut out = Vec::new();
    for r in -rows..=rows {
        for c in -cols..=cols {
            let shift = if r.rem_euclid(2) == 1 { 0.5 * h } else { 0.0 };
            let p = [
                c as f64 * h + shift + rng.symmetric(JITTER * h),
                r as f64 * dy + rng.symmetric(JITTER * h),
            ];
            let margin = 0.5 * span - p[0].abs() >= 0.5 * h && 0.5 * width - p[1].abs() >= 0.5 * h;
            if margin && p[0].hypot(p[1]) >= 0.5 * h {
                out.push(p);
            }
        }
    }
    out
}

/// Perimeter parameter of a boundary point, counter-clockwise from `(−span/2, −width/2)`.
fn perimeter(p: [f64; 3], span: f64, width: f64) -> f64 {
    let (hs, hw) = (0.5 * span, 0.5 * width);
    if p[1] == -hw && p[0] < hs {
        p[0] + hs
    } else if p[0] == hs && p[1] < hw {
        span + p[1] + hw
    } else if p[1] == hw && p[0] > -hs {
        span + width + hs - p[0]
    } else {
        2.0 * span + width + hw - p[1]
    }
}

/// An irregular, quality-bounded mesh of the `span × width` rectangle (m) with edges of
/// about `target_edge` (m); node sets as [`super::generate::rectangle`]'s. Sizes are
/// checked by the caller.
///
/// # Panics
/// If the triangulation or its refinement fails (not expected for a rectangle).
pub fn rectangle(span: f64, width: f64, target_edge: f64) -> CanopyMesh {
    let (nx, ny) = (
        even_cells(span, target_edge),
        even_cells(width, target_edge),
    );
    let rim = outline(span, width, nx, ny);
    let n_rim = rim.len();
    let center = n_rim;
    let mut rng = SplitMix(SEED);
    let h = (span / nx as f64).min(width / ny as f64);
    let mut pts = rim;
    pts.push([0.0, 0.0]);
    pts.extend(interior(span, width, h, &mut rng));
    let verts: Vec<Point2<f64>> = pts.iter().map(|p| Point2::new(p[0], p[1])).collect();
    let edges: Vec<[usize; 2]> = (0..n_rim).map(|k| [k, (k + 1) % n_rim]).collect();
    let mut cdt = ConstrainedDelaunayTriangulation::<Point2<f64>>::bulk_load_cdt(verts, edges)
        .expect("the outline and jittered points triangulate");
    let area = MAX_AREA * target_edge * target_edge;
    let result = cdt.refine(
        RefinementParameters::new()
            .exclude_outer_faces(true)
            .with_angle_limit(AngleLimit::from_deg(MIN_ANGLE_DEG))
            .with_max_allowed_area(area)
            .with_max_additional_vertices(20 * pts.len() + 1000),
    );
    assert!(
        result.refinement_complete,
        "Delaunay refinement ran out of points"
    );
    let positions: Vec<[f64; 3]> = cdt
        .vertices()
        .map(|v| [v.position().x, v.position().y, 0.0])
        .collect();
    let excluded: std::collections::HashSet<_> = result.excluded_faces.into_iter().collect();
    let faces: Vec<[usize; 3]> = cdt
        .inner_faces()
        .filter(|f| !excluded.contains(&f.fix()))
        .map(|f| f.vertices().map(|v| v.fix().index()))
        .collect();
    let (hs, hw) = (0.5 * span, 0.5 * width);
    let mut rim_nodes: Vec<usize> = (0..positions.len())
        .filter(|&i| positions[i][0].abs() == hs || positions[i][1].abs() == hw)
        .collect();
    rim_nodes.sort_by(|&a, &b| {
        perimeter(positions[a], span, width).total_cmp(&perimeter(positions[b], span, width))
    });
    let mids = if span >= width {
        vec![nx / 2, nx + ny + nx / 2]
    } else {
        vec![nx + ny / 2, 2 * nx + ny + ny / 2]
    };
    let sets = [
        ("corners", vec![0, nx, nx + ny, 2 * nx + ny]),
        ("long_edge_midpoints", mids),
        ("center", vec![center]),
        ("rim", rim_nodes),
    ];
    CanopyMesh {
        positions,
        faces,
        rod_edges: Vec::new(),
        node_sets: sets.map(|(k, v)| (k.to_string(), v)).into_iter().collect(),
    }
}

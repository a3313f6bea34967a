//! Flat canopy meshes in the z = 0 plane, centred at the origin, triangles counter-
//! clockwise seen from +z (normals +ẑ).
//!
//! - [`rectangle`]: square-ish grid cells split by diagonals alternating like a union-jack
//!   (right isosceles triangles when the cells are square), mirror-symmetric about x = 0
//!   and y = 0. Hinge model on it: `D_eff = ¾ k_b = (√3/2) E h³/12`, bending Poisson
//!   ratio −1/3 (see `engine::shell::Lattice::UnionJack`).
//! - [`rectangle_pattern`]: the same outline in one of three [`Pattern`]s: the union-jack
//!   above, `Cross` (every cell split into four triangles through a node at its centre) or
//!   `Unstructured` (an irregular, quality-bounded Delaunay mesh, [`super::unstructured`]).
//! - [`hexagon`]: the equilateral triangular lattice in concentric hexagonal rings.
//!   `D_eff = E h³/12`, bending Poisson ratio −1/3 (`Lattice::Equilateral`).
//! - [`circle`]: the hexagon's topology with ring `k` placed on a circle of radius
//!   `k R / n` (6k equally spaced nodes): nearly equilateral triangles, mirror-symmetric
//!   about every multiple of 30°; [`circle_with_rim_sites`] picks `n` so that rim load
//!   sites fall on nodes.
//!
//! # Panics
//! All generators panic unless sizes and `target_edge` are positive and finite (the
//! scenario layer validates them first).

use super::CanopyMesh;

fn check(what: &str, x: f64) {
    assert!(
        x.is_finite() && x > 0.0,
        "{what} must be positive and finite, got {x}"
    );
}

/// How a rectangle is triangulated.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Pattern {
    /// Square-ish cells split by one diagonal each, alternating like a union-jack.
    UnionJack,
    /// Cells split into four triangles through a node at the cell centre.
    Cross,
    /// Irregular Delaunay triangulation refined to a minimum angle (seeded, deterministic).
    Unstructured,
}

/// A `span × width` rectangle (m; x along the span) with cells of about `target_edge` (m),
/// union-jack diagonals: [`rectangle_pattern`] with [`Pattern::UnionJack`].
///
/// The cell counts are even, so nodes exist on both symmetry axes. Node sets: "corners"
/// (counter-clockwise from (−span/2, −width/2)), "long_edge_midpoints" (midpoints of the
/// two long edges; of the y = ±width/2 edges when span = width), "center", "rim".
pub fn rectangle(span: f64, width: f64, target_edge: f64) -> CanopyMesh {
    rectangle_pattern(span, width, target_edge, Pattern::UnionJack)
}

/// A `span × width` rectangle (m) triangulated in `pattern`, with the node sets of
/// [`rectangle`]: the corners, the long-edge midpoints and the centre are nodes in every
/// pattern. Union-jack and cross are mirror-symmetric about x = 0 and y = 0.
pub fn rectangle_pattern(span: f64, width: f64, target_edge: f64, pattern: Pattern) -> CanopyMesh {
    check("span", span);
    check("width", width);
    check("target edge", target_edge);
    if pattern == Pattern::Unstructured {
        return super::unstructured::rectangle(span, width, target_edge);
    }
    let (nx, ny) = (
        even_cells(span, target_edge),
        even_cells(width, target_edge),
    );
    let id = |i: usize, j: usize| j * (nx + 1) + i;
    let mut positions = Vec::with_capacity((nx + 1) * (ny + 1));
    // Symmetric formula, so mirrored nodes have exactly negated coordinates.
    let x_of = |i: f64| span * (2.0 * i - nx as f64) / (2.0 * nx as f64);
    let y_of = |j: f64| width * (2.0 * j - ny as f64) / (2.0 * ny as f64);
    for j in 0..=ny {
        for i in 0..=nx {
            positions.push([x_of(i as f64), y_of(j as f64), 0.0]);
        }
    }
    let mut faces = Vec::with_capacity(4 * nx * ny);
    let shift = nx / 2 + ny / 2;
    for j in 0..ny {
        for i in 0..nx {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            if pattern == Pattern::Cross {
                let m = positions.len();
                positions.push([x_of(i as f64 + 0.5), y_of(j as f64 + 0.5), 0.0]);
                faces.extend([[a, b, m], [b, c, m], [c, d, m], [d, a, m]]);
            } else if (i + j + shift) % 2 == 0 {
                // Diagonals alternate, and all eight cells around the centre node point at it.
                faces.extend([[a, b, c], [a, c, d]]);
            } else {
                faces.extend([[a, b, d], [b, c, d]]);
            }
        }
    }
    let mut rim: Vec<usize> = (0..nx).map(|i| id(i, 0)).collect();
    rim.extend((0..ny).map(|j| id(nx, j)));
    rim.extend((1..=nx).rev().map(|i| id(i, ny)));
    rim.extend((1..=ny).rev().map(|j| id(0, j)));
    let mids = if span >= width {
        vec![id(nx / 2, 0), id(nx / 2, ny)]
    } else {
        vec![id(nx, ny / 2), id(0, ny / 2)]
    };
    let sets = [
        ("corners", vec![id(0, 0), id(nx, 0), id(nx, ny), id(0, ny)]),
        ("long_edge_midpoints", mids),
        ("center", vec![id(nx / 2, ny / 2)]),
        ("rim", rim),
    ];
    CanopyMesh {
        positions,
        faces,
        rod_edges: Vec::new(),
        node_sets: sets.map(|(k, v)| (k.to_string(), v)).into_iter().collect(),
    }
}

/// Smallest even count ≥ 2 closest to `len / target` (also the unstructured mesh's
/// boundary division).
pub(super) fn even_cells(len: f64, target: f64) -> usize {
    2 * ((len / (2.0 * target)).round().max(1.0) as usize)
}

/// A regular hexagon of circumradius `circumradius` (m), corners at angles 0°, 60°, …,
/// meshed by the equilateral lattice with `n = round(R / target_edge)` rings (edge R/n).
/// Node sets: "center", "rim", "corners". Nodes: `1 + 3n(n+1)`; triangles: `6n²`.
pub fn hexagon(circumradius: f64, target_edge: f64) -> CanopyMesh {
    check("circumradius", circumradius);
    check("target edge", target_edge);
    let n = rings(circumradius, target_edge);
    let l = circumradius / n as f64;
    let corner = |s: usize| {
        let a = (s % 6) as f64 * std::f64::consts::FRAC_PI_3;
        [a.cos(), a.sin()]
    };
    let mut m = concentric(n, |k, s, i| {
        let (c0, c1) = (corner(s), corner(s + 1));
        let t = i as f64 / k as f64;
        let r = k as f64 * l;
        [
            r * (c0[0] + t * (c1[0] - c0[0])),
            r * (c0[1] + t * (c1[1] - c0[1])),
        ]
    });
    let start = 1 + 3 * n * (n - 1);
    let corners = (0..6).map(|s| start + s * n).collect();
    m.node_sets.insert("corners".into(), corners);
    m
}

/// A disc of radius `radius` (m) in `n = round(R / target_edge)` concentric rings; ring `k`
/// has `6k` equally spaced nodes on the circle of radius `k R/n`, the first on +x. Node sets:
/// "center", "rim". [`circle_with_rim_sites`] with no site constraint.
pub fn circle(radius: f64, target_edge: f64) -> CanopyMesh {
    circle_with_rim_sites(radius, target_edge, 1)
}

/// [`circle`] with a ring count `n` that puts a rim node at every one of `rim_sites`
/// equally spaced polar angles (the first on +x): `n` is the multiple of
/// `rim_sites / gcd(rim_sites, 6)` nearest to `R / target_edge`, so `rim_sites` divides the
/// `6n` rim nodes. The mesh is mirror-symmetric about every plane through the axis at a
/// multiple of 30° (to round-off), so sites whose angles are all
/// multiples of 30° (`rim_sites` dividing 12) make a load pattern with no handedness.
pub fn circle_with_rim_sites(radius: f64, target_edge: f64, rim_sites: usize) -> CanopyMesh {
    check("radius", radius);
    check("target edge", target_edge);
    let n = circle_rings(radius, target_edge, rim_sites);
    concentric(n, |k, s, i| {
        // Node j and node 6k − j of a ring get exactly opposite y (mirror about y = 0).
        let j = s * k + i;
        let (jm, sign) = if 2 * j > 6 * k {
            (6 * k - j, -1.0)
        } else {
            (j, 1.0)
        };
        let a = jm as f64 * std::f64::consts::FRAC_PI_3 / k as f64;
        let r = radius * k as f64 / n as f64;
        [r * a.cos(), sign * r * a.sin()]
    })
}

/// The ring count of [`circle_with_rim_sites`] (it has `6 n²` triangles): the scenario
/// checks it before anything is built.
pub fn circle_rings(radius: f64, target_edge: f64, rim_sites: usize) -> usize {
    let q = rim_sites.max(1) / gcd(rim_sites.max(1), 6);
    let per_q = (radius / target_edge / q as f64).round().max(1.0);
    // Saturating: an absurd ratio is refused by the caller, not wrapped around.
    q.saturating_mul(per_q.min(usize::MAX as f64) as usize)
}

fn gcd(a: usize, b: usize) -> usize {
    if b == 0 {
        a
    } else {
        gcd(b, a % b)
    }
}

fn rings(size: f64, target: f64) -> usize {
    (size / target).round().max(1.0) as usize
}

/// Centre node plus rings `k = 1..=n` of `6k` nodes; node `(k, s, i)` (side `s < 6`,
/// `i < k`) sits at `pos(k, s, i)` and has the angular parameter `s + i/k`. Consecutive
/// rings are stitched by sweeping that parameter, which reproduces the equilateral lattice
/// for the hexagon.
fn concentric(n: usize, pos: impl Fn(usize, usize, usize) -> [f64; 2]) -> CanopyMesh {
    let mut positions = vec![[0.0, 0.0, 0.0]];
    let mut faces = Vec::with_capacity(6 * n * n);
    for k in 1..=n {
        let start = positions.len();
        for s in 0..6 {
            for i in 0..k {
                let [x, y] = pos(k, s, i);
                positions.push([x, y, 0.0]);
            }
        }
        if k == 1 {
            faces.extend((0..6).map(|j| [0, start + j, start + (j + 1) % 6]));
        } else {
            stitch(&mut faces, start - 6 * (k - 1), k - 1, start, k);
        }
    }
    let start = 1 + 3 * n * (n - 1);
    let sets = [
        ("center", vec![0]),
        ("rim", (start..start + 6 * n).collect()),
    ];
    CanopyMesh {
        positions,
        faces,
        rod_edges: Vec::new(),
        node_sets: sets.map(|(k, v)| (k.to_string(), v)).into_iter().collect(),
    }
}

/// Triangles between ring `ki` (first node `inner`) and ring `ko = ki + 1` (first node
/// `outer`), counter-clockwise. The ring edges are taken in the order of their midpoints'
/// angular parameters, each closing a triangle with the current node of the other ring:
/// that order is reversed by a reflection of the parameter, so the strip is mirror-symmetric
/// about every sextant's boundary and middle (and, for the hexagon, it is the lattice). No
/// two midpoints tie, since `ki` and `ki + 1` are coprime.
fn stitch(faces: &mut Vec<[usize; 3]>, inner: usize, ki: usize, outer: usize, ko: usize) {
    let (ni, no) = (6 * ki, 6 * ko);
    // Edge j → j+1 of a ring with k nodes per side has the midpoint parameter (2j+1)/(2k);
    // cross-multiplied by the other ring's k to compare in integers.
    let mid = |j: usize, other: usize| (2 * j + 1) * other;
    let (mut i, mut o) = (0, 0);
    while i < ni || o < no {
        if o == no || (i < ni && mid(i, ko) < mid(o, ki)) {
            faces.push([inner + i % ni, outer + o % no, inner + (i + 1) % ni]);
            i += 1;
        } else {
            faces.push([outer + o % no, outer + (o + 1) % no, inner + i % ni]);
            o += 1;
        }
    }
}

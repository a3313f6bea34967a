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
//!   `k R / n` (6k equally spaced nodes): nearly equilateral triangles.
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
/// has `6k` equally spaced nodes on the circle of radius `k R/n`. Node sets: "center",
/// "rim".
pub fn circle(radius: f64, target_edge: f64) -> CanopyMesh {
    check("radius", radius);
    check("target edge", target_edge);
    let n = rings(radius, target_edge);
    concentric(n, |k, s, i| {
        let a = (s as f64 + i as f64 / k as f64) * std::f64::consts::FRAC_PI_3;
        let r = radius * k as f64 / n as f64;
        [r * a.cos(), r * a.sin()]
    })
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
/// `outer`), counter-clockwise. Ties in the parameter advance the inner ring (lattice).
fn stitch(faces: &mut Vec<[usize; 3]>, inner: usize, ki: usize, outer: usize, ko: usize) {
    let (ni, no) = (6 * ki, 6 * ko);
    let param = |j: usize, k: usize| (j / k) as f64 + (j % k) as f64 / k as f64;
    let (mut i, mut o) = (0, 0);
    while i < ni || o < no {
        let next_in = param(i + 1, ki);
        let next_out = param(o + 1, ko);
        if o == no || (i < ni && next_in <= next_out) {
            faces.push([inner + i % ni, outer + o % no, inner + (i + 1) % ni]);
            i += 1;
        } else {
            faces.push([outer + o % no, outer + (o + 1) % no, inner + i % ni]);
            o += 1;
        }
    }
}

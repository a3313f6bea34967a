//! The broad phase: the pairs of primitives close enough to need their exact distance. Every
//! triangle and edge gets its bounding box, grown by `reach` (the activation distance plus a
//! bound on the motion before the pairs are taken again), in an R*-tree (the `rstar` crate,
//! bulk-loaded); a point–triangle pair is a candidate when the point lies in the triangle's
//! grown box, an edge–edge pair when the two grown boxes overlap. Pairs sharing a node are
//! left out: neighbours touch by construction, and their elastic forces keep them apart.

use super::ad::{node, V};
use super::distance::{edge_edge, point_edge, point_triangle, Pair};
use rstar::primitives::{GeomWithData, Rectangle};
use rstar::{RTree, AABB};

/// The contact primitives of a model, by node index.
#[derive(Debug, Clone, Default)]
pub struct Surface {
    /// Triangles (the canopy's cloth).
    pub triangles: Vec<[usize; 3]>,
    /// Edges (the cloth's and the lines' segments).
    pub edges: Vec<[usize; 2]>,
    /// Points tested against the triangles (the cloth's and the lines' nodes).
    pub points: Vec<usize>,
    /// Line segments whose nodes are also tested against each other's segments (point–edge).
    pub line_edges: Vec<[usize; 2]>,
}

impl Surface {
    /// The surface of a cloth mesh `triangles` and line segments `lines`: every triangle, every
    /// distinct edge of the triangles and every segment as edges, every node of either as a
    /// point, and the segments as lines (point–edge pairs).
    pub fn from_mesh(triangles: &[[usize; 3]], lines: &[[usize; 2]]) -> Self {
        let mut edges: Vec<[usize; 2]> = (triangles.iter())
            .flat_map(|t| [[t[0], t[1]], [t[1], t[2]], [t[2], t[0]]])
            .chain(lines.iter().copied())
            .map(|[a, b]| [a.min(b), a.max(b)])
            .collect();
        edges.sort_unstable();
        edges.dedup();
        let mut points: Vec<usize> = edges.iter().flatten().copied().collect();
        points.sort_unstable();
        points.dedup();
        Self {
            triangles: triangles.to_vec(),
            edges,
            points,
            line_edges: lines.to_vec(),
        }
    }
}

/// A candidate pair: a point–triangle stencil `[p, t0, t1, t2]`, an edge–edge stencil
/// `[a0, a1, b0, b1]` or a point–edge stencil `[p, a, b]`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Candidate {
    /// Point and triangle.
    PointTriangle([usize; 4]),
    /// Two edges.
    EdgeEdge([usize; 4]),
    /// A line's node and a line's edge: the mollified edge–edge energy vanishes for parallel
    /// edges, so parallel lines are held apart by their nodes (IPC's codimensional form).
    PointEdge([usize; 3]),
}

impl Candidate {
    /// The four stencil nodes of the pair (a point–edge pair padded with its edge's first
    /// node, which no formula of the pair reads).
    pub fn nodes(&self) -> [usize; 4] {
        match *self {
            Candidate::PointTriangle(n) | Candidate::EdgeEdge(n) => n,
            Candidate::PointEdge([p, a, b]) => [p, a, b, a],
        }
    }

    /// The feature pair realising the pair's distance at the stencil points `v`, and the
    /// squared distance.
    pub fn feature(&self, v: &[V<f64>; 4]) -> (Pair, f64) {
        match self {
            Candidate::PointTriangle(_) => point_triangle(v),
            Candidate::EdgeEdge(_) => edge_edge(v),
            Candidate::PointEdge(_) => point_edge(v),
        }
    }

    /// The pair's squared distance (m²) at node positions `x` (3 per node).
    pub fn squared_distance(&self, x: &[f64]) -> f64 {
        self.feature(&self.nodes().map(|i| node(x, i))).1
    }
}

type Boxed = GeomWithData<Rectangle<[f64; 3]>, usize>;

/// The box of nodes `ids`, grown by `reach` on every side.
fn grown(x: &[f64], ids: &[usize], reach: f64, index: usize) -> Boxed {
    let (mut lo, mut hi) = ([f64::MAX; 3], [f64::MIN; 3]);
    for &i in ids {
        let p = node(x, i);
        for k in 0..3 {
            lo[k] = lo[k].min(p[k] - reach);
            hi[k] = hi[k].max(p[k] + reach);
        }
    }
    GeomWithData::new(Rectangle::from_corners(lo, hi), index)
}

/// The candidate pairs of `surface` at node positions `x` (3 per node) within `reach` (m),
/// sorted (so the pair set, and what is built from it, does not depend on the tree's order).
pub fn candidates(surface: &Surface, x: &[f64], reach: f64) -> Vec<Candidate> {
    let mut out = Vec::new();
    let tris: Vec<Boxed> = (surface.triangles.iter().enumerate())
        .map(|(i, t)| grown(x, t, reach, i))
        .collect();
    let tree = RTree::bulk_load(tris);
    for &p in &surface.points {
        let at = node(x, p);
        for hit in tree.locate_in_envelope_intersecting(&AABB::from_point(at)) {
            let t = surface.triangles[hit.data];
            if !t.contains(&p) {
                out.push(Candidate::PointTriangle([p, t[0], t[1], t[2]]));
            }
        }
    }
    let edges: Vec<Boxed> = (surface.edges.iter().enumerate())
        .map(|(i, e)| grown(x, e, 0.5 * reach, i))
        .collect();
    let tree = RTree::bulk_load(edges);
    let lines = LineGraph::of(surface);
    for (a, b) in tree.intersection_candidates_with_other_tree(&tree) {
        let (ea, eb) = (surface.edges[a.data], surface.edges[b.data]);
        let shared = ea.iter().any(|n| eb.contains(n));
        if a.data < b.data
            && !shared
            && !(lines.is_line(ea) && lines.is_line(eb) && lines.adjacent(&ea, &eb))
        {
            out.push(Candidate::EdgeEdge([ea[0], ea[1], eb[0], eb[1]]));
        }
    }
    line_pairs(surface, &lines, x, reach, &mut out);
    out.sort_unstable();
    out
}

/// The lines' nodes and their neighbours along the lines. Lines meet by construction at a
/// *junction*, a node of three or more line edges (the payload's confluence), and converge
/// there: line primitives joined through a junction (a junction and its neighbour, or two
/// neighbours of one junction) are not paired, beyond IPC's rule of no shared node, which
/// would leave converging lines in contact next to their confluence, closer there than any
/// activation distance. Along one line (nodes of two edges) IPC's rule alone holds, so a line
/// cannot pass through itself.
struct LineGraph {
    neighbours: std::collections::HashMap<usize, Vec<usize>>,
}

impl LineGraph {
    fn of(surface: &Surface) -> Self {
        let mut neighbours = std::collections::HashMap::<usize, Vec<usize>>::new();
        for &[a, b] in &surface.line_edges {
            neighbours.entry(a).or_default().push(b);
            neighbours.entry(b).or_default().push(a);
        }
        Self { neighbours }
    }

    fn is_junction(&self, i: usize) -> bool {
        self.neighbours.get(&i).is_some_and(|n| n.len() >= 3)
    }

    /// Whether line nodes `i` and `j` are joined through a junction (or are one node).
    fn near(&self, i: usize, j: usize) -> bool {
        let (Some(a), Some(b)) = (self.neighbours.get(&i), self.neighbours.get(&j)) else {
            return false;
        };
        i == j
            || (a.contains(&j) && (self.is_junction(i) || self.is_junction(j)))
            || a.iter().any(|&k| self.is_junction(k) && b.contains(&k))
    }

    fn is_line(&self, [a, b]: [usize; 2]) -> bool {
        self.neighbours.get(&a).is_some_and(|n| n.contains(&b))
    }

    /// Whether line primitives with nodes `a` and `b` are joined through a junction.
    fn adjacent(&self, a: &[usize], b: &[usize]) -> bool {
        a.iter().any(|&i| b.iter().any(|&j| self.near(i, j)))
    }
}

/// The point–edge candidates among the lines: every line node in the grown box of a line edge
/// it is not joined to through a junction ([`LineGraph`]).
fn line_pairs(
    surface: &Surface,
    lines: &LineGraph,
    x: &[f64],
    reach: f64,
    out: &mut Vec<Candidate>,
) {
    if surface.line_edges.is_empty() {
        return;
    }
    let boxes: Vec<Boxed> = (surface.line_edges.iter().enumerate())
        .map(|(i, e)| grown(x, e, reach, i))
        .collect();
    let tree = RTree::bulk_load(boxes);
    let mut nodes: Vec<usize> = surface.line_edges.iter().flatten().copied().collect();
    nodes.sort_unstable();
    nodes.dedup();
    for p in nodes {
        for hit in tree.locate_in_envelope_intersecting(&AABB::from_point(node(x, p))) {
            let e = surface.line_edges[hit.data];
            if !e.contains(&p) && !lines.adjacent(&[p], &e) {
                out.push(Candidate::PointEdge([p, e[0], e[1]]));
            }
        }
    }
}

//! Whether a mesh passes through itself: the invariant contact must keep. A segment crosses a
//! triangle when its ends lie on opposite sides of the triangle's plane (or one on it) and it
//! passes inside all three edges, decided with Shewchuk's adaptive exact `orient3d` (the
//! `robust` crate), so a crossing is never missed or invented by rounding. Segments and
//! triangles that share a node are not tested (they meet at that node by construction).

use robust::{orient3d, Coord3D};
use rstar::primitives::{GeomWithData, Rectangle};
use rstar::{RTree, AABB};

use super::ad::{node, V};
use super::broad::Surface;
use super::distance::edge_edge;

fn c(p: V<f64>) -> Coord3D<f64> {
    Coord3D {
        x: p[0],
        y: p[1],
        z: p[2],
    }
}

fn side(a: V<f64>, b: V<f64>, d: V<f64>, e: V<f64>) -> f64 {
    orient3d(c(a), c(b), c(d), c(e))
}

/// Whether segment `p`–`q` meets triangle `a, b, c` (touching counts).
pub fn segment_crosses_triangle(p: V<f64>, q: V<f64>, [a, b, c]: [V<f64>; 3]) -> bool {
    let (sp, sq) = (side(a, b, c, p), side(a, b, c, q));
    if sp * sq > 0.0 || (sp == 0.0 && sq == 0.0) {
        // Both ends on one side, or the segment lies in the plane (a fold flat on itself is
        // caught by its other segments, which leave the plane).
        return false;
    }
    let s = [side(p, q, a, b), side(p, q, b, c), side(p, q, c, a)];
    s.iter().all(|&v| v >= 0.0) || s.iter().all(|&v| v <= 0.0)
}

/// The first edge of `surface` (by index) that crosses one of its triangles at node positions
/// `x`, with that triangle's index; `None` when the mesh is free of intersections.
pub fn first_crossing(surface: &Surface, x: &[f64]) -> Option<(usize, usize)> {
    let boxes: Vec<GeomWithData<Rectangle<V<f64>>, usize>> = (surface.triangles.iter())
        .enumerate()
        .map(|(i, t)| {
            let [a, b, d] = t.map(|k| node(x, k));
            let lo = std::array::from_fn(|k| a[k].min(b[k]).min(d[k]));
            let hi = std::array::from_fn(|k| a[k].max(b[k]).max(d[k]));
            GeomWithData::new(Rectangle::from_corners(lo, hi), i)
        })
        .collect();
    let tree = RTree::bulk_load(boxes);
    for (ei, e) in surface.edges.iter().enumerate() {
        let (p, q) = (node(x, e[0]), node(x, e[1]));
        let env = AABB::from_corners(p, q);
        let mut hits: Vec<usize> = (tree.locate_in_envelope_intersecting(&env))
            .map(|h| h.data)
            .filter(|&ti| {
                let t = surface.triangles[ti];
                !t.contains(&e[0])
                    && !t.contains(&e[1])
                    && segment_crosses_triangle(p, q, t.map(|k| node(x, k)))
            })
            .collect();
        hits.sort_unstable();
        if let Some(&ti) = hits.first() {
            return Some((ei, ti));
        }
    }
    None
}

/// Whether segments `a` and `b`, each moving in a straight line from `start` to `end`
/// (`[a0, a1, b0, b1]`), pass through each other on the way: the signed volume of the four
/// points changes sign (the two lines meet) at an instant where the meeting point lies
/// inside both segments (their distance vanishes there; lines that are parallel or meet
/// beyond an end keep a distance). The instant is found by bisection of the volume (a cubic
/// in time) between the ends, where Shewchuk's exact `orient3d` decides the signs. A pair whose
/// volume returns to its sign within the motion (two meetings) is not reported.
pub fn segments_pass_through(start: [V<f64>; 4], end: [V<f64>; 4]) -> bool {
    let at = |t: f64| -> [V<f64>; 4] {
        std::array::from_fn(|i| {
            std::array::from_fn(|k| start[i][k] + t * (end[i][k] - start[i][k]))
        })
    };
    let vol = |p: [V<f64>; 4]| side(p[0], p[1], p[2], p[3]);
    let (v0, v1) = (vol(start), vol(end));
    if v0 * v1 > 0.0 || (v0 == 0.0 && v1 == 0.0) {
        return false;
    }
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if vol(at(mid)) * v0 > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    // At that instant the lines meet (unless parallel): the segments do when their own
    // distance is nil to within the bisection's resolution of the motion.
    let meet = at(0.5 * (lo + hi));
    let len2 = |a: V<f64>, b: V<f64>| (0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>();
    let scale = len2(meet[0], meet[1]).max(len2(meet[2], meet[3]));
    edge_edge(&meet).1 <= 1e-18 * scale
}

/// The first two of `segments` (node pairs; by index) that share no node and pass through
/// each other ([`segments_pass_through`]) as the nodes move in straight lines from positions
/// `a` to `b` (3 per node); `None` when no two do.
pub fn segments_passing(segments: &[[usize; 2]], a: &[f64], b: &[f64]) -> Option<(usize, usize)> {
    for (i, e) in segments.iter().enumerate() {
        for (j, f) in segments.iter().enumerate().skip(i + 1) {
            let ids = [e[0], e[1], f[0], f[1]];
            if !e.iter().any(|n| f.contains(n))
                && segments_pass_through(ids.map(|k| node(a, k)), ids.map(|k| node(b, k)))
            {
                return Some((i, j));
            }
        }
    }
    None
}

//! Squared distances between the primitives of a mesh, after Li et al., "Incremental Potential
//! Contact" (SIGGRAPH 2020), §4: the unsigned distance between a point and a triangle, or
//! between two edges, is the smallest distance between a feature of one and a feature of the
//! other. Each feature pair has a smooth formula (`point_point`, `point_line`,
//! `point_plane`, `line_line`, written once over the crate's `Real` scalar); [`point_triangle`] and [`edge_edge`] pick the pair that
//! realises the distance, so the result is the true squared distance, and its gradient and
//! Hessian are those of the smooth formula of the picked pair.
//!
//! All are squared distances (m²): IPC's barrier is a function of d², which keeps the
//! formulas rational.

use super::ad::{cross, dot, sub, Real, V};

/// `|p − a|²`.
pub(crate) fn point_point<T: Real>(p: V<T>, a: V<T>) -> T {
    let d = sub(p, a);
    dot(d, d)
}

/// Squared distance from `p` to the line through `a` and `b`: `|(a − p) × (b − p)|² / |b − a|²`.
pub(crate) fn point_line<T: Real>(p: V<T>, a: V<T>, b: V<T>) -> T {
    let c = cross(sub(a, p), sub(b, p));
    let e = sub(b, a);
    dot(c, c) / dot(e, e)
}

/// Squared distance from `p` to the plane through `a`, `b`, `c`: `((p − a)·n)² / |n|²`,
/// `n = (b − a) × (c − a)`.
pub(crate) fn point_plane<T: Real>(p: V<T>, a: V<T>, b: V<T>, c: V<T>) -> T {
    let n = cross(sub(b, a), sub(c, a));
    let s = dot(sub(p, a), n);
    s * s / dot(n, n)
}

/// Squared distance between the line through `a0`, `a1` and the line through `b0`, `b1`:
/// `((b0 − a0)·(ea × eb))² / |ea × eb|²` (undefined for parallel lines).
pub(crate) fn line_line<T: Real>(a0: V<T>, a1: V<T>, b0: V<T>, b1: V<T>) -> T {
    let n = cross(sub(a1, a0), sub(b1, b0));
    let s = dot(sub(b0, a0), n);
    s * s / dot(n, n)
}

/// Which feature pair realises a distance: the indices are the stencil's points (0 is the
/// point or the first edge's start; a point–triangle stencil is `p, t0, t1, t2`, an
/// edge–edge stencil `a0, a1, b0, b1`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Pair {
    /// Point `i` and point `j`.
    PointPoint(usize, usize),
    /// Point `i` and the line through `j`, `k`.
    PointLine(usize, usize, usize),
    /// Point 0 and the triangle's plane.
    PointPlane,
    /// The two lines.
    LineLine,
}

/// Lines closer to parallel than this (`|ea × eb|² < LINE_LINE_MIN_SIN2 |ea|²|eb|²`) are not
/// measured line to line: the formula's denominator vanishes there, and an endpoint pair
/// realises the distance to within the rounding of the near-parallel formula.
pub const LINE_LINE_MIN_SIN2: f64 = 1e-10;

/// The parameter of the foot of `p` on the segment `a`–`b`: `(p − a)·e / |e|²`.
fn foot(p: V<f64>, a: V<f64>, b: V<f64>) -> f64 {
    let e = sub(b, a);
    dot(sub(p, a), e) / dot(e, e)
}

/// The pair realising the distance from point `p` (index `ip`) to segment `a`–`b`
/// (indices `ia`, `ib`), and the squared distance.
fn point_segment(x: &[V<f64>; 4], ip: usize, ia: usize, ib: usize) -> (Pair, f64) {
    let (p, a, b) = (x[ip], x[ia], x[ib]);
    match foot(p, a, b) {
        t if t <= 0.0 => (Pair::PointPoint(ip, ia), point_point(p, a)),
        t if t >= 1.0 => (Pair::PointPoint(ip, ib), point_point(p, b)),
        _ => (Pair::PointLine(ip, ia, ib), point_line(p, a, b)),
    }
}

/// The pair realising the distance from point 0 to the triangle of points 1, 2, 3, and the
/// squared distance: the plane when the foot of the point lies inside the triangle, else the
/// nearest edge or vertex.
pub fn point_triangle(x: &[V<f64>; 4]) -> (Pair, f64) {
    let [p, a, b, c] = *x;
    let n = cross(sub(b, a), sub(c, a));
    let nn = dot(n, n);
    // Barycentric coordinates of the foot: signed areas of the sub-triangles over |n|².
    let inside = nn > 0.0
        && [(a, b), (b, c), (c, a)]
            .iter()
            .all(|&(u, w)| dot(cross(sub(w, u), sub(p, u)), n) >= 0.0);
    if inside {
        return (Pair::PointPlane, point_plane(p, a, b, c));
    }
    [(1, 2), (2, 3), (3, 1)]
        .into_iter()
        .map(|(i, j)| point_segment(x, 0, i, j))
        .min_by(|u, v| u.1.total_cmp(&v.1))
        .expect("three edges")
}

/// The pair realising the distance from point 0 to the segment of points 1, 2 (point 3 is
/// not used: a point–edge stencil is padded to four points), and the squared distance.
pub fn point_edge(x: &[V<f64>; 4]) -> (Pair, f64) {
    point_segment(x, 0, 1, 2)
}

/// The pair realising the distance between edges 0–1 and 2–3, and the squared distance: the
/// lines when their closest points lie inside both edges (and they are not parallel), else
/// an endpoint against the other edge.
pub fn edge_edge(x: &[V<f64>; 4]) -> (Pair, f64) {
    let [a0, a1, b0, b1] = *x;
    let (ea, eb, r) = (sub(a1, a0), sub(b1, b0), sub(b0, a0));
    let (aa, bb, ab) = (dot(ea, ea), dot(eb, eb), dot(ea, eb));
    let det = aa * bb - ab * ab; // |ea × eb|²
    if det > LINE_LINE_MIN_SIN2 * aa * bb {
        let (ra, rb) = (dot(r, ea), dot(r, eb));
        let s = (ra * bb - rb * ab) / det;
        let t = (ra * ab - rb * aa) / det;
        if (0.0..=1.0).contains(&s) && (0.0..=1.0).contains(&t) {
            return (Pair::LineLine, line_line(a0, a1, b0, b1));
        }
    }
    [(0, 2, 3), (1, 2, 3), (2, 0, 1), (3, 0, 1)]
        .into_iter()
        .map(|(p, i, j)| point_segment(x, p, i, j))
        .min_by(|u, v| u.1.total_cmp(&v.1))
        .expect("four endpoints")
}

/// The squared distance of `pair` at the points `x`, on any `Real` (for its derivatives).
pub(crate) fn of_pair<T: Real>(pair: Pair, x: &[V<T>; 4]) -> T {
    match pair {
        Pair::PointPoint(i, j) => point_point(x[i], x[j]),
        Pair::PointLine(i, j, k) => point_line(x[i], x[j], x[k]),
        Pair::PointPlane => point_plane(x[0], x[1], x[2], x[3]),
        Pair::LineLine => line_line(x[0], x[1], x[2], x[3]),
    }
}

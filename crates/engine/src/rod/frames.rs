//! Frames of Discrete Elastic Rods: parallel transport, reference and material frames,
//! curvature binormal and reference twist (Bergou et al. 2008; Bergou et al. 2010).
//!
//! Every edge `e` carries an orthonormal *reference frame* `(t, a1, a2)`, `a2 = t × a1`
//! (dimensionless unit vectors). Reference frames are initialised by *space-parallel
//! transport* along each rod from a first director, and afterwards advanced in time by
//! *time-parallel transport*: after each accepted step, `a1 ← P(t_old → t_new) a1`, which
//! rotates the frame with the tangent and adds no twist about it. The *material frame* is the
//! reference frame rotated by the edge's twist DOF θ (rad) about `t`.

use super::scalar::{Real, G3};
use crate::vec3::V3;

/// Parallel transport `P(u → t) v` (generic): the minimal rotation taking unit `u` to unit
/// `t`, applied to `v`: `P v = c v + b × v + (b·v) b / (1 + c)`, `b = u × t`, `c = u·t`
/// (Rodrigues' formula with `b = k sin φ`, `c = cos φ`). Singular only for `t = −u`.
#[inline]
pub(crate) fn transport<T: Real>(v: &G3<T>, u: &G3<T>, t: &G3<T>) -> G3<T> {
    let b = u.cross(t);
    let c = u.dot(t);
    v.scale(c) + b.cross(v) + b.scale(b.dot(v) / (c + 1.0))
}

/// Curvature binormal `κb = 2 e0 × e1 / (|e0||e1| + e0·e1)` (1/1, i.e. dimensionless:
/// `|κb| = 2 tan(φ/2)` for the turning angle φ between the edges). Generic.
#[inline]
pub(crate) fn kb<T: Real>(e0: &G3<T>, e1: &G3<T>) -> G3<T> {
    let den = e0.norm() * e1.norm() + e0.dot(e1);
    e0.cross(e1).scale(T::cst(2.0) / den)
}

/// Parallel transport of `v` from unit tangent `t1` to unit tangent `t2`.
///
/// Robust for `t1 ≈ t2` (the formula tends smoothly to the identity) and for `t1 ≈ −t2`
/// (where the minimal rotation is not unique: a half turn about an axis perpendicular to
/// `t1` is used).
pub fn parallel_transport(v: &V3, t1: &V3, t2: &V3) -> V3 {
    let c = t1.dot(t2);
    if c < -1.0 + 1e-12 {
        let k = perpendicular(t1);
        return 2.0 * k * k.dot(v) - v;
    }
    transport::<f64>(&G3::cst(v), &G3::cst(t1), &G3::cst(t2)).val()
}

/// A deterministic unit vector perpendicular to unit `t`: `normalize(a × t)` with `a` the
/// coordinate axis least aligned with `t` (ties go to the later axis, so a rod along x gets
/// `ẑ × x̂ = ŷ`: a horizontal first director for horizontal rods).
pub fn perpendicular(t: &V3) -> V3 {
    let mut axis = 2;
    for k in [1, 0] {
        if t[k].abs() < t[axis].abs() - 1e-12 {
            axis = k;
        }
    }
    let mut a = V3::zeros();
    a[axis] = 1.0;
    a.cross(t).normalize()
}

/// The first director `a1` of a rod whose first edge has unit tangent `t`: the user's
/// `hint` projected onto the plane normal to `t` and normalised, or [`perpendicular`].
/// `None` when the hint is (nearly) parallel to `t`.
pub fn first_director(t: &V3, hint: Option<[f64; 3]>) -> Option<V3> {
    match hint {
        None => Some(perpendicular(t)),
        Some(h) => {
            let h = V3::new(h[0], h[1], h[2]);
            let p = h - t * t.dot(&h);
            (p.norm() > 1e-6 * h.norm()).then(|| p.normalize())
        }
    }
}

/// Space-parallel reference directors `a1` along a chain of unit `tangents`, starting from
/// `d1` (perpendicular to `tangents[0]`).
pub fn space_parallel_frames(tangents: &[V3], d1: &V3) -> Vec<V3> {
    let mut out = Vec::with_capacity(tangents.len());
    let mut a = *d1;
    for (k, t) in tangents.iter().enumerate() {
        if k > 0 {
            a = parallel_transport(&a, &tangents[k - 1], t);
        }
        // Re-orthonormalise so round-off does not accumulate along long rods.
        a = (a - t * t.dot(&a)).normalize();
        out.push(a);
    }
    out
}

/// Material frame `(m1, m2)` from the reference frame `(a1, a2)` and twist angle θ (rad):
/// `m1 = cos θ a1 + sin θ a2`, `m2 = −sin θ a1 + cos θ a2`.
pub fn material_frame(a1: &V3, a2: &V3, theta: f64) -> (V3, V3) {
    let (s, c) = theta.sin_cos();
    (c * a1 + s * a2, -s * a1 + c * a2)
}

/// Curvature binormal `κb = 2 e0 × e1 / (|e0||e1| + e0·e1)` of two consecutive edges.
pub fn curvature_binormal(e0: &V3, e1: &V3) -> V3 {
    kb::<f64>(&G3::cst(e0), &G3::cst(e1)).val()
}

/// Signed angle (rad) from `u` to `v` about `axis` (both perpendicular to `axis`).
pub fn signed_angle(u: &V3, v: &V3, axis: &V3) -> f64 {
    u.cross(v).dot(axis).atan2(u.dot(v))
}

/// `angle + 2πk` closest to `reference`: keeps an angle on the branch of its history.
pub fn wrap_near(angle: f64, reference: f64) -> f64 {
    let tau = std::f64::consts::TAU;
    angle - tau * ((angle - reference) / tau).round()
}

/// Reference twist `m` (rad) at the node between edges 0 and 1: the signed angle about `t1`
/// from `P(t0 → t1) a1_0` to `a1_1`, on the 2π branch nearest `previous`.
pub fn ref_twist(a1_0: &V3, t0: &V3, a1_1: &V3, t1: &V3, previous: f64) -> f64 {
    let p = parallel_transport(a1_0, t0, t1);
    wrap_near(signed_angle(&p, a1_1, t1), previous)
}

/// Reference frames of a set of edges with their history: the tangent and first reference
/// director at the last accepted configuration.
#[derive(Debug, Clone, Default)]
pub struct RodFrames {
    /// Unit tangent `t` of each edge at the last accepted configuration.
    pub tangent: Vec<V3>,
    /// First reference director `a1` of each edge (unit, ⟂ `t`).
    pub a1: Vec<V3>,
}

impl RodFrames {
    /// Frames from tangents and first directors.
    pub fn new(tangent: Vec<V3>, a1: Vec<V3>) -> Self {
        assert_eq!(tangent.len(), a1.len());
        Self { tangent, a1 }
    }
    /// Second reference director `a2 = t × a1` of edge `e`.
    pub fn a2(&self, e: usize) -> V3 {
        self.tangent[e].cross(&self.a1[e])
    }
    /// Time-parallel transport of edge `e`'s frame to the new unit tangent `t`.
    pub fn time_transport(&mut self, e: usize, t: &V3) {
        let a = parallel_transport(&self.a1[e], &self.tangent[e], t);
        self.a1[e] = (a - t * t.dot(&a)).normalize();
        self.tangent[e] = *t;
    }
    /// The reference frame edge `e` would have if its tangent became `t` (time-parallel
    /// transport without committing): `(a1, a2)`.
    pub fn transported(&self, e: usize, t: &V3) -> (V3, V3) {
        let a = parallel_transport(&self.a1[e], &self.tangent[e], t);
        (a, t.cross(&a))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn transport_is_a_rotation_taking_t1_to_t2() {
        let t1 = V3::new(0.3, -0.4, 0.8).normalize();
        for t2 in [
            V3::new(-0.2, 0.9, 0.1).normalize(),
            t1,
            -t1,
            (-t1 + V3::new(1e-9, 0.0, 0.0)).normalize(),
        ] {
            assert!((parallel_transport(&t1, &t1, &t2) - t2).norm() < 1e-7);
            let v = V3::new(0.1, 0.7, -0.2);
            assert!((parallel_transport(&v, &t1, &t2).norm() - v.norm()).abs() < 1e-12);
        }
    }

    #[test]
    fn ref_twist_vanishes_for_space_parallel_frames_and_tracks_branch() {
        let ts = [
            V3::new(1.0, 0.0, 0.0),
            V3::new(0.6, 0.8, 0.0),
            V3::new(0.0, 0.6, 0.8),
        ];
        let a = space_parallel_frames(&ts, &perpendicular(&ts[0]));
        for k in 1..3 {
            assert!(ref_twist(&a[k - 1], &ts[k - 1], &a[k], &ts[k], 0.0).abs() < 1e-12);
        }
        assert!((wrap_near(-3.1, 3.1) - (-3.1 + std::f64::consts::TAU)).abs() < 1e-15);
    }
}

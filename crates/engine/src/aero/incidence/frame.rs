//! The canopy's axis, crossflow and incidence, read from a state once per accepted step.

use crate::aero::fluid::Fluid;
use crate::aero::geometry::{area_vector, centroid_height, centroid_velocity, corners};
use crate::vec3::V3;

/// What the incidence law holds fixed over a step, read from the state that starts it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct CanopyFrame {
    /// Unit axis `ê`, from the mouth to the crown: the direction of the canopy's oriented
    /// vector area `Σ σ N` (exact for any shape whose rim lies in a plane).
    pub axis: V3,
    /// Total angle of attack `α` (rad): between the canopy's velocity through the air and
    /// `−ê` (0 when it falls straight into its mouth).
    pub alpha: f64,
    /// Unit crossflow `ĉ`: the part of the canopy's velocity through the air normal to `ê`
    /// (zero vector at α = 0).
    pub crossflow: V3,
}

/// The canopy's spread about its axis in a frame.
pub(crate) struct Sides {
    /// The area-weighted centroid of the triangles' centroids (m).
    pub centre: V3,
    /// The largest distance `R` of a triangle's centroid from the axis (m).
    pub reach: f64,
    /// `G = Σ σᵢ sᵢ (Nᵢ · ĉ)` (m²), `sᵢ = (rᵢ · ĉ)/R`: the side force per unit `C_1 q` of the
    /// pressure `C_1 q sᵢ`.
    pub side_area: f64,
}

/// [`Sides`] of the triangles `stencils` with orientations `sigma` at `q` in `frame`.
pub(crate) fn sides(
    stencils: &[usize],
    sigma: impl Iterator<Item = f64>,
    q: &[f64],
    frame: &CanopyFrame,
) -> Sides {
    let tri = |st: &[usize]| {
        let x = corners(q, st);
        (area_vector(&x), (x[0] + x[1] + x[2]) / 3.0)
    };
    let (mut area, mut moment) = (0.0, V3::zeros());
    for st in stencils.chunks_exact(9) {
        let (n, c) = tri(st);
        area += n.norm();
        moment += n.norm() * c;
    }
    let centre = moment / area.max(1e-300);
    let e = frame.axis;
    let radial = |c: V3| {
        let d = c - centre;
        d - d.dot(&e) * e
    };
    let (mut reach, mut g) = (0.0_f64, 0.0);
    for (st, sg) in stencils.chunks_exact(9).zip(sigma) {
        let (n, c) = tri(st);
        let r = radial(c);
        reach = reach.max(r.norm());
        g += sg * r.dot(&frame.crossflow) * n.dot(&frame.crossflow);
    }
    Sides {
        centre,
        reach,
        side_area: g / reach.max(1e-300),
    }
}

/// The area-weighted frame of the triangles `stencils` (9 DOFs each) with orientations
/// `sigma` at `(q, v)` in `fluid`'s wind at the canopy's area-weighted mean height;
/// `fallback` is the axis kept when the canopy has no vector area (crumpled flat on itself).
pub(crate) fn frame(
    stencils: &[usize],
    sigma: impl Iterator<Item = f64>,
    q: &[f64],
    v: &[f64],
    fluid: &Fluid,
    fallback: V3,
) -> CanopyFrame {
    let (mut vector_area, mut mean_u, mut area) = (V3::zeros(), V3::zeros(), 0.0);
    let mut mean_z = 0.0;
    for (st, sg) in stencils.chunks_exact(9).zip(sigma) {
        let x = corners(q, st);
        let n = area_vector(&x);
        let u = centroid_velocity(v, st);
        vector_area += sg * n;
        mean_u += n.norm() * u;
        mean_z += n.norm() * centroid_height(&x);
        area += n.norm();
    }
    let scale = vector_area.norm();
    let axis = if scale > 1e-9 * area {
        vector_area / scale
    } else {
        fallback
    };
    let u = if area > 0.0 {
        mean_u / area - V3::from(fluid.wind_at(mean_z / area).velocity)
    } else {
        V3::zeros()
    };
    let along = u.dot(&axis);
    let across = u - along * axis;
    let speed = across.norm();
    if speed <= 1e-12 * (u.norm() + 1e-300) {
        return CanopyFrame {
            axis,
            alpha: 0.0,
            crossflow: V3::zeros(),
        };
    }
    CanopyFrame {
        axis,
        alpha: speed.atan2(-along),
        crossflow: across / speed,
    }
}

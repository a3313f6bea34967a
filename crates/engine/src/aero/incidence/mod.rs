//! A canopy pressure that knows incidence: the inflation pressure plus a windward excess
//! that gives the whole canopy a prescribed normal-force curve `C_N(α)`.
//!
//! A uniform pressure on an open shell pushes along the normal of the rim's plane only
//! (its resultant is `Δp` times the vector area bounded by the rim), so the inflation law
//! ([`InflationPressure`](super::InflationPressure)) gives no normal force and no moment at any
//! incidence, and its canopy cannot swing or glide. Measured round canopies have both: the
//! whole-canopy normal-force coefficient `C_N(α)` of a solid flat circular canopy pushes
//! it further from zero incidence up to a stable trim angle (Knacke, *Parachute Recovery
//! Systems Design Manual*, NWC TP 6575, 1991, ch. 5), and porosity makes it restoring. This
//! law distributes a tabulated `C_N(α)` ([`IncidenceCurve`]) over the panels as a pressure
//! that varies linearly across the canopy towards the crossflow:
//!
//! `Δpᵢ = P(m)`, `m = wᵢ² + kᵢ |uᵢ|²`, `kᵢ = (C_1/C_p) sᵢ`,
//!
//! - `uᵢ` the triangle's mean velocity through the air, `wᵢ = max(0, −uᵢ · ê)` its speed into
//!   the mouth along the canopy axis `ê` (the inflation law's `w` with `ê` for `e_z`);
//! - `P(w) = C_p ½ ρ w²`, or the permeable fabric's pressure at `w`, exactly as in the
//!   inflation law, taken at `√|m|` with the sign of `m` (a leeward panel may be pushed in);
//! - `sᵢ = (rᵢ · ĉ)/R` the centroid's distance `rᵢ` from the axis towards the crossflow `ĉ`,
//!   over the canopy's largest radius `R`;
//! - `C_1 = −C_N(α) S₀ / G` with `G = Σ σᵢ sᵢ (Nᵢ · ĉ)`: then on a uniform flow the excess
//!   `C_1 q sᵢ` gives the whole canopy the side force `−C_N(α) q S₀ ĉ`, the tabulated one.
//!   A canopy too shallow to carry a side force by pressure (`G < 0.05 S₀`,
//!   [`SHALLOW_SIDE_AREA`]; the flat start has `G = 0`) gets an excess that fades linearly to
//!   zero with `G`, and `|C_1| ≤ C_p` (the windward excess never exceeds the mean pressure).
//!
//! At zero incidence `C_1 = 0` and, with the axis vertical, this is the inflation law with
//! the same `C_p`. The axis `ê`, the centroid `x_c` and `K = (C_1/C_p) ĉ / R` are read from
//! the state at the start of each step ([`Element::commit`]) and held over it, like a rod's
//! reference frames, and each triangle takes `kᵢ = rᵢ · K` from its own centroid: its force
//! keeps its 9-DOF stencil and its exact Jacobians in the step's unknowns, and the incidence
//! lags by one step, a first-order error in time like backward Euler's own. The
//! linearisation of a steady state adds the held quantities' own dependence on the state
//! as a rank-9 part ([`Force::lag_coupling`](crate::force::Force::lag_coupling)).
//!
//! Exact Jacobians, with `f = σ Δp N / 3` on each node, `P′ = ∂P/∂(w²)` at `√|m|`:
//! - `∂f/∂v_b = (σ/3) N (P′ ∂m/∂v_b)ᵀ`, `∂m/∂v_b = (2/3)(−w ê + k u)`;
//! - `∂f/∂x_b = (σ/3) (Δp ∂N/∂x_b + N (∂Δp/∂z̄ / 3) e_zᵀ + N (P′ |u|² / 3) K⊥ᵀ)`, `K⊥` the
//!   part of `K` normal to `ê` (`∂kᵢ/∂x_b = K⊥/3`).

mod coupling;
mod curve;
pub(crate) mod frame;

pub use curve::{CurveError, IncidenceCurve};

use super::fluid::Fluid;
use super::geometry::{
    area_vector, area_vector_jacobians, centroid_velocity, corners, same_force_on_nodes, same_rows,
};
use super::inflation::InflationPressureLaw;
use super::permeability::Fabric;
use super::wind::add_shear;
use crate::element::{Element, Family};
use crate::force::{BlockMut, EvalInput, JacobianKind, LagCoupling};
use crate::vec3::{node, outer, V3};
use frame::{frame, sides, CanopyFrame};

/// What the law holds over a step, read from the state that starts it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Held {
    /// Axis, incidence and crossflow.
    pub frame: CanopyFrame,
    /// The canopy's area-weighted centroid `x_c` (m).
    pub centre: V3,
    /// `K = (C_1/C_p) ĉ / R` (1/m): `kᵢ = rᵢ · K`.
    pub kvec: V3,
    /// `C_1` (–).
    pub c1: f64,
}

/// The incidence law: the inflation law it extends, the `C_N(α)` it distributes, the
/// canopy's reference area and what it holds over the current step.
#[derive(Debug, Clone)]
pub struct IncidencePressureLaw {
    base: InflationPressureLaw,
    curve: IncidenceCurve,
    /// Reference area `S₀` (m²): the canopy's constructed (rest) surface area.
    s0: f64,
    held: Held,
}

/// The incidence pressure on a family of triangles (module docs). Each triangle's data is
/// its orientation `σ = ±1`.
pub type IncidencePressure = Family<IncidencePressureLaw>;

/// Length of the history: axis, crossflow, centroid and `K` (3 each), α and `C_1`.
const HISTORY: usize = 14;

impl IncidencePressure {
    /// The incidence pressure with coefficient `cp` and normal-force curve `curve` on
    /// `triangles`, oriented and measured (`S₀`) at the rest positions `q_rest`, in `fluid`.
    /// It starts at zero incidence with the axis along the rest vector area.
    pub fn new(
        triangles: &[[usize; 3]],
        q_rest: &[f64],
        cp: f64,
        curve: IncidenceCurve,
        fluid: &Fluid,
    ) -> Self {
        let base = super::InflationPressure::new(triangles, q_rest, cp, fluid);
        let s0 = triangles
            .iter()
            .map(|t| area_vector(&t.map(|i| node(q_rest, i))).norm())
            .sum();
        let mut law = IncidencePressureLaw {
            base: base.law,
            curve,
            s0,
            held: Held {
                frame: CanopyFrame {
                    axis: V3::z(),
                    alpha: 0.0,
                    crossflow: V3::zeros(),
                },
                centre: V3::zeros(),
                kvec: V3::zeros(),
                c1: 0.0,
            },
        };
        let v = vec![0.0; q_rest.len()];
        law.held = law.hold(&base.stencils, &base.data, q_rest, &v, V3::z());
        Family::from_elements("incidence-pressure", law, base.stencils, base.data)
    }

    /// Let air leak through the fabric, as in the inflation law.
    pub fn with_fabric(mut self, fabric: Fabric) -> Self {
        self.law.base = self.law.base.with_fabric(fabric);
        self
    }
}

impl IncidencePressureLaw {
    /// Total angle of attack `α` (rad) held over the current step.
    pub fn alpha(&self) -> f64 {
        self.held.frame.alpha
    }

    /// `C_1` of the current step: the windward excess pressure coefficient (–).
    pub fn c1(&self) -> f64 {
        self.held.c1
    }

    /// The canopy axis `ê` held over the current step.
    pub fn axis(&self) -> [f64; 3] {
        self.held.frame.axis.into()
    }

    /// Reference area `S₀` (m²).
    pub fn reference_area(&self) -> f64 {
        self.s0
    }

    /// What to hold over a step that starts at `(q, v)` (module docs); `fallback` is the
    /// axis of a canopy without vector area.
    pub(crate) fn hold(
        &self,
        stencils: &[usize],
        sigma: &[f64],
        q: &[f64],
        v: &[f64],
        fallback: V3,
    ) -> Held {
        let fr = frame(
            stencils,
            sigma.iter().copied(),
            q,
            v,
            self.base.fluid(),
            fallback,
        );
        let sd = sides(stencils, sigma.iter().copied(), q, &fr);
        let cn = self.curve.at(fr.alpha);
        let cp = self.base.cp();
        let c1 = if cn == 0.0 || fr.crossflow == V3::zeros() {
            0.0
        } else {
            (-cn * self.s0 * side_share(sd.side_area, self.s0)).clamp(-cp, cp)
        };
        Held {
            frame: fr,
            centre: sd.centre,
            kvec: fr.crossflow * (c1 / (cp * sd.reach.max(1e-300))),
            c1,
        }
    }
}

/// Below this `G/S₀` a canopy is too shallow to carry a side force by pressure (a flat
/// disc has `G = 0`; a 60° spherical cap 0.24): the excess fades out linearly.
pub const SHALLOW_SIDE_AREA: f64 = 0.05;

/// `1/G` (1/m²) where `G ≥ G₀ = SHALLOW_SIDE_AREA · S₀`, `G/G₀²` below: continuous, zero for
/// a flat or inverted canopy, and exact for any canopy deeper than the threshold.
fn side_share(g: f64, s0: f64) -> f64 {
    let g0 = SHALLOW_SIDE_AREA * s0;
    if g >= g0 {
        1.0 / g
    } else {
        g.max(0.0) / (g0 * g0)
    }
}

impl Element for IncidencePressureLaw {
    const STENCIL: usize = 9;
    const KIND: JacobianKind = JacobianKind::GENERAL;
    /// `σ`.
    type Data = f64;

    fn evaluate(&self, &sigma: &f64, st: &[usize], input: &EvalInput<'_>, mut b: BlockMut<'_>) {
        let (q, v) = (input.q, input.v);
        let h = &self.held;
        let e = h.frame.axis;
        let kperp = h.kvec - h.kvec.dot(&e) * e;
        let x = corners(q, st);
        let nv = area_vector(&x);
        let centroid = (x[0] + x[1] + x[2]) / 3.0;
        let air = self.base.fluid().at(centroid.z);
        let wind = self.base.fluid().wind_at(centroid.z);
        let u = centroid_velocity(v, st) - V3::from(wind.velocity);
        let k = (centroid - h.centre).dot(&kperp);
        let w = (-u.dot(&e)).max(0.0);
        let u2 = u.norm_squared();
        let (dp, dp_m, dp_z) = self.base.pressure_of_square(w * w + k * u2, &air);
        let f = (sigma * dp / 3.0) * nv;
        same_force_on_nodes(&f, b.f);
        if b.dfdq.is_empty() {
            return;
        }
        let dm = (2.0 / 3.0) * (k * u - w * e);
        let dv = (sigma * dp_m / 3.0) * outer(&nv, &dm);
        let dn = area_vector_jacobians(&x);
        // Height (ρ(z̄)) and the panel's place across the crossflow (kᵢ) both move with the
        // centroid, a third of each node's motion.
        let dx = (sigma / 9.0) * (outer(&nv, &(dp_m * u2 * kperp)) + dp_z * outer(&nv, &V3::z()));
        let dq = [0, 1, 2].map(|bn| (sigma * dp / 3.0) * dn[bn] + dx);
        same_rows(&dq, &dv, b.dfdq, b.dfdv);
        add_shear(&mut b, 3, wind.shear);
    }

    fn commit(&mut self, els: &mut [f64], stencils: &[usize], q: &[f64], v: &[f64]) {
        self.held = self.hold(stencils, els, q, v, self.held.frame.axis);
    }

    fn history_len(&self, _n_elements: usize) -> usize {
        HISTORY
    }

    fn history(&self, _els: &[f64]) -> Vec<f64> {
        let h = &self.held;
        let f = &h.frame;
        let vecs = [f.axis, f.crossflow, h.centre, h.kvec];
        let mut out: Vec<f64> = vecs.iter().flat_map(|x| x.iter().copied()).collect();
        out.extend([f.alpha, h.c1]);
        out
    }

    fn restore_history(&mut self, _els: &mut [f64], h: &[f64]) {
        let v = |i: usize| V3::new(h[i], h[i + 1], h[i + 2]);
        self.held = Held {
            frame: CanopyFrame {
                axis: v(0),
                crossflow: v(3),
                alpha: h[12],
            },
            centre: v(6),
            kvec: v(9),
            c1: h[13],
        };
    }

    fn lag_coupling(
        &self,
        els: &[f64],
        stencils: &[usize],
        q: &[f64],
        v: &[f64],
    ) -> Option<LagCoupling> {
        Some(coupling::of(self, els, stencils, q, v))
    }
}

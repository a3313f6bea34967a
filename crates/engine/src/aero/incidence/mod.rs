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
//! - `sᵢ = (rᵢ · ĉ)/R` the centroid's distance from the axis towards the crossflow `ĉ`, over
//!   the canopy's largest radius `R` (see [`frame`]);
//! - `C_1 = −C_N(α) S₀ / G` with `G = Σ σᵢ sᵢ (Nᵢ · ĉ)`: then on a uniform flow the excess
//!   `C_1 q sᵢ` gives the whole canopy the side force `−C_N(α) q S₀ ĉ`, the tabulated one.
//!   `|C_1| ≤ C_p` (the windward excess never exceeds the mean pressure; it binds only on a
//!   canopy too flat to carry a side force, such as the flat start).
//!
//! At zero incidence `C_1 = 0` and, with the axis vertical, this is the inflation law with
//! the same `C_p`. The axis, `α`, `ĉ` and the `kᵢ` are read from the state at the start of
//! each step ([`Element::commit`]) and held over it, like a rod's reference frames: each
//! triangle's force keeps its 9-DOF stencil and its exact Jacobians in the step's unknowns,
//! and the incidence lags by one step, a first-order error in time like backward Euler's
//! own (docs/aero.md §Incidence pressure).
//!
//! Exact Jacobians, with `f = σ Δp N / 3` on each node, `P′ = ∂P/∂(w²)` at `√|m|`:
//! - `∂f/∂v_b = (σ/3) N (P′ ∂m/∂v_b)ᵀ`, `∂m/∂v_b = (2/3)(−w ê + k u)`;
//! - `∂f/∂x_b = (σ/3) (Δp ∂N/∂x_b + N (∂Δp/∂z̄ / 3) e_zᵀ)`.

mod curve;
pub(crate) mod frame;

pub use curve::{CurveError, IncidenceCurve};

use super::fluid::Fluid;
use super::geometry::{area_vector, area_vector_jacobians, stencil_vec};
use super::inflation::InflationPressureLaw;
use super::permeability::Fabric;
use crate::element::{node_stencils, Element, Family};
use crate::force::{BlockMut, EvalInput, JacobianKind};
use crate::vec3::{node, outer, V3};
use frame::{frame, sides, CanopyFrame};

/// The incidence law: the inflation law it extends, the `C_N(α)` it distributes, the
/// canopy's reference area and the frame held over the current step.
#[derive(Debug, Clone)]
pub struct IncidencePressureLaw {
    base: InflationPressureLaw,
    curve: IncidenceCurve,
    /// Reference area `S₀` (m²): the canopy's constructed (rest) surface area.
    s0: f64,
    frame: CanopyFrame,
    /// `C_1` of the current step (–).
    c1: f64,
}

/// The incidence pressure on a family of triangles (module docs). Each triangle's data is
/// its orientation `σ = ±1` and its `kᵢ` of the current step.
pub type IncidencePressure = Family<IncidencePressureLaw>;

/// Entries of the history before the per-triangle `kᵢ`: axis (3), crossflow (3), α, C_1.
const HEAD: usize = 8;

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
        let (stencils, sigma) = (base.stencils.clone(), base.data.clone());
        let s0 = triangles
            .iter()
            .map(|t| area_vector(&t.map(|i| node(q_rest, i))).norm())
            .sum();
        let v = vec![0.0; q_rest.len()];
        let fr = frame(
            &stencils,
            sigma.iter().copied(),
            q_rest,
            &v,
            V3::zeros(),
            V3::z(),
        );
        let law = IncidencePressureLaw {
            base: base.law,
            curve,
            s0,
            frame: fr,
            c1: 0.0,
        };
        let data = sigma.iter().map(|&s| (s, 0.0)).collect();
        debug_assert_eq!(node_stencils(triangles), stencils);
        Family::from_elements("incidence-pressure", law, stencils, data)
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
        self.frame.alpha
    }

    /// `C_1` of the current step: the windward excess pressure coefficient (–).
    pub fn c1(&self) -> f64 {
        self.c1
    }

    /// The canopy axis `ê` held over the current step.
    pub fn axis(&self) -> [f64; 3] {
        self.frame.axis.into()
    }

    /// Reference area `S₀` (m²).
    pub fn reference_area(&self) -> f64 {
        self.s0
    }
}

impl Element for IncidencePressureLaw {
    const STENCIL: usize = 9;
    const KIND: JacobianKind = JacobianKind::GENERAL;
    /// `(σ, kᵢ)`.
    type Data = (f64, f64);

    fn evaluate(
        &self,
        &(sigma, k): &(f64, f64),
        st: &[usize],
        input: &EvalInput<'_>,
        b: BlockMut<'_>,
    ) {
        let (q, v) = (input.q, input.v);
        let e = self.frame.axis;
        let x = [0, 1, 2].map(|i| stencil_vec(q, st, i));
        let u =
            [0, 1, 2].map(|i| stencil_vec(v, st, i)).iter().sum::<V3>() / 3.0 - self.base.wind();
        let nv = area_vector(&x);
        let air = self.base.fluid().at((x[0].z + x[1].z + x[2].z) / 3.0);
        let w = (-u.dot(&e)).max(0.0);
        let m = w * w + k * u.norm_squared();
        let (dp, dp_m, dp_z) = self.base.pressure_of_square(m, &air);
        let f = (sigma * dp / 3.0) * nv;
        for i in 0..3 {
            for r in 0..3 {
                b.f[3 * i + r] = f[r];
            }
        }
        if b.dfdq.is_empty() {
            return;
        }
        let dm = (2.0 / 3.0) * (k * u - w * e);
        let dv = (sigma * dp_m / 3.0) * outer(&nv, &dm);
        let dn = area_vector_jacobians(&x);
        let dz = (sigma * dp_z / 9.0) * nv;
        for bn in 0..3 {
            let mut dq = (sigma * dp / 3.0) * dn[bn];
            for r in 0..3 {
                dq[(r, 2)] += dz[r];
            }
            for i in 0..3 {
                for r in 0..3 {
                    for c in 0..3 {
                        b.dfdq[(3 * i + r) * 9 + 3 * bn + c] = dq[(r, c)];
                        b.dfdv[(3 * i + r) * 9 + 3 * bn + c] = dv[(r, c)];
                    }
                }
            }
        }
    }

    fn commit(&mut self, els: &mut [(f64, f64)], stencils: &[usize], q: &[f64], v: &[f64]) {
        let wind = self.base.wind();
        self.frame = frame(
            stencils,
            els.iter().map(|e| e.0),
            q,
            v,
            wind,
            self.frame.axis,
        );
        let cn = self.curve.at(self.frame.alpha);
        if cn == 0.0 || self.frame.crossflow == V3::zeros() {
            self.c1 = 0.0;
            els.iter_mut().for_each(|e| e.1 = 0.0);
            return;
        }
        let sigma: Vec<f64> = els.iter().map(|e| e.0).collect();
        let sd = sides(stencils, &sigma, q, &self.frame);
        let cp = self.base.cp();
        // |C_1| ≤ C_p: the bound binds where |G| < S₀ |C_N| / C_p (module docs).
        self.c1 = -cn * self.s0 / sd.side_area.max(self.s0 * cn.abs() / cp);
        for (e, s) in els.iter_mut().zip(&sd.s) {
            e.1 = self.c1 / cp * s;
        }
    }

    fn history_len(&self, n_elements: usize) -> usize {
        HEAD + n_elements
    }

    fn history(&self, els: &[(f64, f64)]) -> Vec<f64> {
        let f = &self.frame;
        let mut h = Vec::with_capacity(HEAD + els.len());
        h.extend(f.axis.iter().chain(f.crossflow.iter()));
        h.extend([f.alpha, self.c1]);
        h.extend(els.iter().map(|e| e.1));
        h
    }

    fn restore_history(&mut self, els: &mut [(f64, f64)], h: &[f64]) {
        self.frame = CanopyFrame {
            axis: V3::new(h[0], h[1], h[2]),
            crossflow: V3::new(h[3], h[4], h[5]),
            alpha: h[6],
        };
        self.c1 = h[7];
        for (e, k) in els.iter_mut().zip(&h[HEAD..]) {
            e.1 = *k;
        }
    }
}

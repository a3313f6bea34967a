//! Inflation pressure on a canopy: the trapped air's differential pressure, independent of
//! each panel's angle to the flow.
//!
//! The panel laws ([`TriangleDrag`](super::TriangleDrag), [`PressureDrag`](super::PressureDrag))
//! push each triangle along its normal with a weight that vanishes when the panel turns
//! edge-on to the flow, so nothing holds the side of a deep canopy out. An inflated canopy is
//! held open by the air it traps: over the inside the differential pressure is a fraction of
//! the free stream's dynamic pressure that varies little from panel to panel. Prescribing that
//! pressure is how parachute structural codes load a canopy (Sandia's CANO and its successor
//! take "dynamic pressure and pressure distribution" as input; Ludtke, NSWC TR 84-204, 1984;
//! MONSTR runs a constant distribution). This law takes the simplest, a uniform coefficient
//! on the dynamic pressure of the descent:
//!
//! - relative velocity of the triangle `u = (v₀ + v₁ + v₂)/3 − U∞` (m/s);
//! - descent speed through the air `w = max(0, −u_z)` (m/s): the flow into the mouth of a
//!   canopy whose axis is vertical, so a horizontal wind or glide does not inflate it;
//! - current area vector `N = ½ (x₁ − x₀) × (x₂ − x₀)` (m²);
//! - differential pressure `Δp = C_p ½ ρ w²` (Pa), ρ at the centroid's height;
//! - each node receives `f_i = σ Δp N / 3` (N): the pressure on the triangle's current area
//!   along its inside normal. `σ = ±1` per triangle, fixed at construction so that `σ N`
//!   points up (+z) in the rest configuration: the canopy is set up flat, its mouth facing
//!   down towards the payload and the oncoming air of the descent.
//!
//! A flat canopy falling flat sees exactly the report law's normal drag `½ ρ C_D A w²`, so
//! `C_p = C_D` calibrates the same way (a flat plate: `v = √(2 W/(ρ C_p A))`); on a uniform
//! flow the resultant is `σ Δp` times the vector area bounded by the canopy's rim, the
//! projected area, whatever the shape. Limits: the axis is taken vertical (a canopy swinging
//! by α sees `w`, not the `w cos α` along its axis: a second-order error in α), `Δp ≥ 0` (the
//! inside stays the inside), and no dependence on the local incidence, hence no aerodynamic
//! restoring moment of its own. `w²` with `w = max(0, −u_z)` is C¹, so no regularisation is
//! needed.
//!
//! **Permeable fabric** ([`InflationPressure::with_fabric`]): air leaks through the cloth at
//! `u_p`, and the pressure is that of the flow that does not, `Δp = C_p ½ ρ (w − u_p)²`,
//! equal to the fabric's Darcy–Forchheimer drop `h (μ u_p/k + ρ C_F u_p²/√k)`; the same split
//! as the panel laws' ([`super::permeability`]), with `w` the descent speed. Then `Δp(w)` and
//! its partials come from [`leakage`](super::permeability::leakage) and replace `c w²` below (`∂Δp/∂w` for `C_p ρ w`).
//!
//! **The canopy's speed** ([`InflationPressure::with_canopy_speed`]): every triangle takes
//! the canopy's descent speed `w̄ = max(0, −ū_z)`, `ū = Σ sₜ uₜ` the mean of the triangles'
//! velocities through the air weighted by their shares `sₜ` of the rest area (the cloth's
//! centre-of-mass velocity for a uniform fabric; rest weights, unlike the incidence law's
//! current ones, keep `∂w̄/∂v` constant and `∂w̄/∂x` down to the wind's shear). The trapped air's pressure is set by the
//! flow into the mouth, not by a panel's own motion: with each triangle's own `w`, a fold
//! whose inside faces down is pushed harder the faster it moves down (∂f/∂v along its
//! normal ∝ −σ n_z), a negative damping that a packed canopy whose folds are not vertical
//! does not survive (docs/opening.md §Attitude). `w̄` is read from the state that starts each
//! step and held over it, like the incidence law's axis: the triangles keep their 9-DOF
//! stencils, `∂f/∂v = 0`, and the speed lags by one step, a first-order error in time like
//! backward Euler's own; the linearisation of a steady state adds its dependence on the
//! state ([`Element::lag_coupling`]).
//!
//! Exact Jacobians (neither symmetric):
//! - `∂f_i/∂v_b = −σ (∂Δp/∂w / 9) N e_zᵀ` (impermeable: `∂Δp/∂w = C_p ρ w`);
//! - `∂f_i/∂x_b = σ (Δp / 3) ∂N/∂x_b`, plus, in height-dependent air,
//!   `σ (∂Δp/∂z̄ / 9) N e_zᵀ` from `∂z̄/∂z_b = 1/3` (impermeable: `∂Δp/∂z̄ = (ρ′/ρ) Δp`).

use super::fluid::{Fluid, LocalFluid};
use super::geometry::{
    area_vector, area_vector_jacobians, centroid_height, centroid_velocity, corners,
    same_force_on_nodes, same_rows,
};
use super::permeability::{leakage_in, Fabric};
use super::wind::add_shear;
use crate::element::{node_stencils, Element, Family};
use crate::force::{BlockMut, EvalInput, JacobianKind, LagCoupling};
use crate::vec3::{node, outer, M3, V3};

/// The inflation-pressure law: pressure coefficient `C_p`, fluid and wind.
#[derive(Debug, Clone)]
pub struct InflationPressureLaw {
    /// Pressure coefficient C_p: Δp over the descent's dynamic pressure ½ρw².
    cp: f64,
    fluid: Fluid,
    fabric: Option<Fabric>,
    /// Each triangle's share `sₜ` of the canopy's rest area (they sum to 1).
    share: Vec<f64>,
    /// The canopy's descent speed `w̄` (m/s) held over the step, which every triangle
    /// takes ([`InflationPressure::with_canopy_speed`]); `None`: each triangle its own.
    canopy_speed: Option<f64>,
}

/// Uniform-coefficient inflation pressure on a family of triangles (module docs). Each
/// triangle's data is its orientation `σ = ±1`.
pub type InflationPressure = Family<InflationPressureLaw>;

impl InflationPressure {
    /// Inflation pressure with coefficient `cp` on `triangles`, oriented by the rest
    /// positions `q_rest` (σ N points up there; a triangle exactly vertical at rest takes
    /// σ = +1), in `fluid`.
    pub fn new(triangles: &[[usize; 3]], q_rest: &[f64], cp: f64, fluid: &Fluid) -> Self {
        let rest: Vec<V3> = (triangles.iter())
            .map(|t| area_vector(&t.map(|i| node(q_rest, i))))
            .collect();
        let sigma = rest
            .iter()
            .map(|n| if n.z < 0.0 { -1.0 } else { 1.0 })
            .collect();
        let total: f64 = rest.iter().map(|n| n.norm()).sum();
        let law = InflationPressureLaw {
            cp,
            fluid: fluid.clone(),
            fabric: None,
            share: rest.iter().map(|n| n.norm() / total).collect(),
            canopy_speed: None,
        };
        Family::from_elements("inflation-pressure", law, node_stencils(triangles), sigma)
    }

    /// Let air leak through the fabric: the pressure is that of the flow around it (module
    /// docs).
    pub fn with_fabric(mut self, fabric: Fabric) -> Self {
        self.law = self.law.with_fabric(fabric);
        self
    }

    /// Every triangle takes the canopy's descent speed, held over each step (module docs).
    pub fn with_canopy_speed(mut self) -> Self {
        self.law.canopy_speed = Some(0.0);
        self
    }
}

impl InflationPressureLaw {
    /// Let air leak through `fabric`.
    pub(crate) fn with_fabric(mut self, fabric: Fabric) -> Self {
        self.fabric = Some(fabric);
        self
    }

    /// The pressure coefficient `C_p`.
    pub(crate) fn cp(&self) -> f64 {
        self.cp
    }

    /// The fluid.
    pub(crate) fn fluid(&self) -> &Fluid {
        &self.fluid
    }

    /// The pressure at the signed square speed `m` (m²/s²): `sgn(m) Δp(√|m|)`, with
    /// `∂/∂m = Δp′(√|m|)/(2√|m|)` (Pa·s²/m², `c = ½ C_p ρ` at `m = 0`, where the leak
    /// vanishes) and `∂/∂z̄` (Pa/m).
    #[inline]
    pub(crate) fn pressure_of_square(&self, m: f64, air: &LocalFluid) -> (f64, f64, f64) {
        let w = m.abs().sqrt();
        let (p, p_w, p_z) = self.pressure(w, air);
        let p_m = if w > 0.0 {
            p_w / (2.0 * w)
        } else {
            0.5 * self.cp * air.density
        };
        (m.signum() * p, p_m, m.signum() * p_z)
    }

    /// `Δp` (Pa), `∂Δp/∂w` (Pa·s/m) and `∂Δp/∂z̄` (Pa/m) at descent speed `w` (m/s) in the
    /// air `air` at the centroid.
    #[inline]
    fn pressure(&self, w: f64, air: &LocalFluid) -> (f64, f64, f64) {
        let c = 0.5 * self.cp * air.density;
        let dc = 0.5 * self.cp * air.density_gradient;
        let Some(fab) = &self.fabric else {
            return (c * w * w, 2.0 * c * w, dc * w * w);
        };
        leakage_in(w, c, dc, air, fab)
    }
}

impl Element for InflationPressureLaw {
    const STENCIL: usize = 9;
    const KIND: JacobianKind = JacobianKind::GENERAL;
    type Data = f64;

    fn evaluate(&self, &sigma: &f64, st: &[usize], input: &EvalInput<'_>, mut b: BlockMut<'_>) {
        let (q, v) = (input.q, input.v);
        let x = corners(q, st);
        let zc = centroid_height(&x);
        let (air, wind) = (self.fluid.at(zc), self.fluid.wind_at(zc));
        let u = centroid_velocity(v, st) - V3::from(wind.velocity);
        let nv = area_vector(&x);
        let w = self.canopy_speed.unwrap_or((-u.z).max(0.0));
        let (dp, dp_w, dp_z) = self.pressure(w, &air);
        let f = (sigma * dp / 3.0) * nv;
        same_force_on_nodes(&f, b.f);
        if b.dfdq.is_empty() {
            return;
        }
        // Every node's force is the same f, so each 3 × 3 block row repeats.
        // ∂w/∂v_b = −e_z/3 while w > 0 (and dp_w = 0 at w = 0); a held w̄ does not move.
        let dv = match self.canopy_speed {
            Some(_) => M3::zeros(),
            None => (-sigma * dp_w / 9.0) * outer(&nv, &V3::z()),
        };
        let dn = area_vector_jacobians(&x);
        let dz = (sigma * dp_z / 9.0) * outer(&nv, &V3::z());
        let dq = [0, 1, 2].map(|bn| (sigma * dp / 3.0) * dn[bn] + dz);
        same_rows(&dq, &dv, b.dfdq, b.dfdv);
        add_shear(&mut b, 3, wind.shear);
    }

    fn commit(&mut self, _els: &mut [f64], stencils: &[usize], q: &[f64], v: &[f64]) {
        self.begin_step(stencils, q, v);
    }

    fn history_len(&self, _n_elements: usize) -> usize {
        usize::from(self.canopy_speed.is_some())
    }

    fn history(&self, _els: &[f64]) -> Vec<f64> {
        self.canopy_speed.into_iter().collect()
    }

    fn restore_history(&mut self, _els: &mut [f64], h: &[f64]) {
        self.canopy_speed = h.first().copied();
    }

    fn begin_step(&mut self, stencils: &[usize], q: &[f64], v: &[f64]) {
        if self.canopy_speed.is_some() {
            self.canopy_speed = Some(self.canopy_descent(stencils, q, v));
        }
    }

    fn lag_coupling(
        &self,
        sigma: &[f64],
        stencils: &[usize],
        q: &[f64],
        _v: &[f64],
    ) -> Option<LagCoupling> {
        self.canopy_speed
            .map(|w| self.speed_coupling(w, sigma, stencils, q))
    }
}

impl InflationPressureLaw {
    /// The canopy's descent speed `w̄ = max(0, −Σ sₜ uₜ·e_z)` at `(q, v)` (m/s).
    fn canopy_descent(&self, stencils: &[usize], q: &[f64], v: &[f64]) -> f64 {
        let uz: f64 = (stencils.chunks_exact(9).zip(&self.share))
            .map(|(st, s)| {
                let zc = centroid_height(&corners(q, st));
                s * (centroid_velocity(v, st).z - self.fluid.wind_at(zc).velocity[2])
            })
            .sum();
        (-uz).max(0.0)
    }

    /// The coupling through the held `w̄`: `u = ∂F/∂w̄` (each triangle's `σ ∂Δp/∂w N / 3` on
    /// its nodes), `∂w̄/∂v_b = −(sₜ/3) e_z` and `∂w̄/∂z_b = (sₜ/3) ∂U_z/∂z` per corner.
    fn speed_coupling(&self, w: f64, sigma: &[f64], stencils: &[usize], q: &[f64]) -> LagCoupling {
        let mut dofs = stencils.to_vec();
        dofs.sort_unstable();
        dofs.dedup();
        let at = |d: usize| dofs.binary_search(&d).expect("a stencil DOF");
        let (mut u, mut wq, mut wv) = (
            vec![0.0; dofs.len()],
            vec![0.0; dofs.len()],
            vec![0.0; dofs.len()],
        );
        // Clamped at zero, w̄ does not move with the state.
        let moving = w > 0.0;
        for ((st, &sg), &s) in stencils.chunks_exact(9).zip(sigma).zip(&self.share) {
            let x = corners(q, st);
            let zc = centroid_height(&x);
            let (_, dp_w, _) = self.pressure(w, &self.fluid.at(zc));
            let f = (sg * dp_w / 3.0) * area_vector(&x);
            let shear_z = self.fluid.wind_at(zc).shear[2];
            for corner in st.chunks_exact(3) {
                for k in 0..3 {
                    u[at(corner[k])] += f[k];
                }
                if moving {
                    wv[at(corner[2])] -= s / 3.0;
                    wq[at(corner[2])] += s * shear_z / 3.0;
                }
            }
        }
        LagCoupling {
            dofs,
            u: vec![u],
            wq: vec![wq],
            wv: vec![wv],
        }
    }
}

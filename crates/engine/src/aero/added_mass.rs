//! The air's added (apparent) mass on a canopy: a canopy that accelerates must also
//! accelerate the air it carries along.
//!
//! In potential flow a thin flat disc of radius `a` moving broadside carries the added mass
//! `m_a = (8/3) ρ a³`, and none moving edgewise (the circular disc of the added-mass tables,
//! e.g. Newman, *Marine Hydrodynamics*, MIT Press 1977, ch. 4). Spread over the disc's area
//! `π a²`, that is `μ = 8 ρ a / (3π)` per unit area moving along the surface's normal. This
//! law gives every panel of the canopy that share along its own normal:
//!
//! - area vector `N = ½ (x₁ − x₀) × (x₂ − x₀)` (m²), unit normal `n = N/|N|`;
//! - relative velocity `u = (v₀ + v₁ + v₂)/3 − U∞` (m/s);
//! - momentum of the air the panel carries `P = μ |N| n (n·u) = μ N (N·u)/|N|` (kg·m/s);
//! - force on each node `f_i = −(P − P_n) / (3 Δt)` (N), `P_n` the panel's `P` at the start of
//!   the step (its history): backward Euler's `−dP/dt`, which is `−M_a a` on a panel that keeps
//!   its shape and orientation, and adds `−Ṁ_a u` when it turns, stretches or inflates;
//! - `a = √(A_p/π)` the radius of the disc of the canopy's projected area `A_p = |Σ N|`
//!   (the norm of the canopy's vector area; the mesh is consistently oriented) and ρ at its
//!   area-weighted mean height, both taken when a step is accepted: lagged by one step,
//!   so a panel's `P` depends on its own nodes only.
//!
//! A flat disc then carries exactly `(8/3) ρ a³` broadside and nothing edgewise; a curved
//! canopy carries `μ Σ |N| n nᵀ`, the disc value of its projected area in its axis direction.
//! Assumptions: the added mass of an inflated canopy is that of the disc of its projected
//! area in the panels' normal directions (the true shape factor of a cupped canopy is
//! uncertain; the disc's is the potential-flow value of the limit of a flat canopy); still or
//! uniformly moving air (no Froude–Krylov force); potential flow, so the momentum the air
//! loses to the wake is the drag laws' business, not this one's; a panel rotating about the
//! canopy's centre carries its own share only (a disc's rotary added mass is
//! `(16/45) ρ a⁵` in potential flow, this law gives `(2/3) ρ a⁵`).
//!
//! Exact Jacobians of the step's force (the lagged `μ` and `P_n` are constants within it):
//! - `∂f_i/∂v_b = −(μ / (9 Δt)) N Nᵀ/|N|` (symmetric);
//! - `∂f_i/∂x_b = −(1/(3 Δt)) ∂P/∂N ∂N/∂x_b` with
//!   `∂P/∂N = μ [(N·u) I + N uᵀ]/|N| − μ (N·u) N Nᵀ/|N|³`.

use super::fluid::Fluid;
use super::geometry::{area_vector, area_vector_jacobians, stencil_vec};
use crate::element::{node_stencils, Element, Family};
use crate::force::{BlockMut, EvalInput, JacobianKind};
use crate::vec3::{outer, M3, V3};

/// The added-mass law: the lagged added mass per unit area and the fluid.
#[derive(Debug, Clone, Copy)]
pub struct AddedMassLaw {
    /// μ: added mass per unit panel area (kg/m²) in effect for the current step,
    /// `8 ρ a / (3π)` with `a` the radius of the disc of the canopy's projected area.
    mu: f64,
    fluid: Fluid,
    wind: V3,
}

/// One panel's data: the momentum `P_n` (kg·m/s) of the air it carried when the last step
/// was accepted.
#[derive(Debug, Clone, Copy)]
pub struct AddedMassPanel {
    momentum: V3,
}

/// The air's added mass on a family of canopy triangles (module docs).
pub type AddedMass = Family<AddedMassLaw>;

impl AddedMass {
    /// Added mass on `triangles` at rest at `q_rest` (the air at rest too), in `fluid`.
    pub fn new(triangles: &[[usize; 3]], q_rest: &[f64], fluid: &Fluid) -> Self {
        let panels = vec![
            AddedMassPanel {
                momentum: V3::zeros()
            };
            triangles.len()
        ];
        let stencils = node_stencils(triangles);
        let law = AddedMassLaw {
            mu: 0.0,
            fluid: *fluid,
            wind: V3::from(fluid.wind),
        };
        let mut family = Family::from_elements("added-mass", law, stencils, panels);
        family.law.mu = family.law.per_area(&family.stencils, q_rest);
        family
    }

    /// The added mass per unit panel area μ in effect (kg/m²).
    pub fn per_unit_area(&self) -> f64 {
        self.law.mu
    }
}

impl AddedMassLaw {
    /// `8 ρ a / (3π)` at `q`: `a = √(A_p/π)` from the canopy's vector area, ρ at its
    /// area-weighted mean height.
    fn per_area(&self, stencils: &[usize], q: &[f64]) -> f64 {
        let (mut vector_area, mut area, mut height) = (V3::zeros(), 0.0, 0.0);
        for st in stencils.chunks(9) {
            let x = [0, 1, 2].map(|i| stencil_vec(q, st, i));
            let n = area_vector(&x);
            vector_area += n;
            area += n.norm();
            height += n.norm() * (x[0].z + x[1].z + x[2].z) / 3.0;
        }
        let radius = (vector_area.norm() / std::f64::consts::PI).sqrt();
        let rho = self.fluid.at(height / area.max(f64::MIN_POSITIVE)).density;
        8.0 * rho * radius / (3.0 * std::f64::consts::PI)
    }

    /// The panel's air momentum `P` (kg·m/s) with area vector `n` and relative velocity `u`.
    #[inline]
    fn momentum(&self, n: &V3, u: &V3) -> V3 {
        let m = n.norm();
        match m > 0.0 {
            true => (self.mu * n.dot(u) / m) * n,
            false => V3::zeros(),
        }
    }
}

impl Element for AddedMassLaw {
    const STENCIL: usize = 9;
    const KIND: JacobianKind = JacobianKind::GENERAL;
    type Data = AddedMassPanel;

    fn evaluate(&self, el: &AddedMassPanel, st: &[usize], input: &EvalInput<'_>, b: BlockMut<'_>) {
        let x = [0, 1, 2].map(|i| stencil_vec(input.q, st, i));
        let vel = [0, 1, 2].map(|i| stencil_vec(input.v, st, i));
        let u = vel.iter().sum::<V3>() / 3.0 - self.wind;
        let n = area_vector(&x);
        let scale = -1.0 / (3.0 * input.dt);
        let f = scale * (self.momentum(&n, &u) - el.momentum);
        for i in 0..3 {
            b.f[3 * i..3 * i + 3].copy_from_slice(f.as_slice());
        }
        if b.dfdq.is_empty() {
            return;
        }
        let m = n.norm();
        let (dp_dn, dp_du) = match m > 0.0 {
            true => {
                let nu = n.dot(&u);
                let dn = (self.mu / m) * (nu * M3::identity() + outer(&n, &u))
                    - (self.mu * nu / (m * m * m)) * outer(&n, &n);
                (dn, (self.mu / m) * outer(&n, &n))
            }
            false => (M3::zeros(), M3::zeros()),
        };
        // Every node's force is the same, so each 3 × 3 block row repeats; ∂u/∂v_b = I/3.
        let dv = (scale / 3.0) * dp_du;
        let dn = area_vector_jacobians(&x);
        for bn in 0..3 {
            let dq = scale * dp_dn * dn[bn];
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

    /// The accepted step's momenta become the next step's `P_n` (with the `μ` they were
    /// computed with), then `μ` follows the canopy's new projected area.
    fn commit(&mut self, els: &mut [AddedMassPanel], stencils: &[usize], q: &[f64], v: &[f64]) {
        for (el, st) in els.iter_mut().zip(stencils.chunks(9)) {
            let x = [0, 1, 2].map(|i| stencil_vec(q, st, i));
            let vel = [0, 1, 2].map(|i| stencil_vec(v, st, i));
            let u = vel.iter().sum::<V3>() / 3.0 - self.wind;
            el.momentum = self.momentum(&area_vector(&x), &u);
        }
        self.mu = self.per_area(stencils, q);
    }

    fn history_len(&self, n_elements: usize) -> usize {
        1 + 3 * n_elements
    }

    fn history(&self, els: &[AddedMassPanel]) -> Vec<f64> {
        let momenta = els
            .iter()
            .flat_map(|e| [e.momentum.x, e.momentum.y, e.momentum.z]);
        std::iter::once(self.mu).chain(momenta).collect()
    }

    fn restore_history(&mut self, els: &mut [AddedMassPanel], h: &[f64]) {
        self.mu = h[0];
        for (e, p) in els.iter_mut().zip(h[1..].chunks(3)) {
            e.momentum = V3::new(p[0], p[1], p[2]);
        }
    }
}

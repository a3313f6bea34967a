//! The air's added (apparent) mass on a canopy: a canopy that accelerates must also
//! accelerate the air it carries along.
//!
//! In potential flow a thin flat disc of radius `a` moving broadside carries the added mass
//! `M_a = (8/3) ρ a³` (the circular disc of the added-mass tables, e.g. Newman, *Marine
//! Hydrodynamics*, MIT Press 1977, ch. 4). This law puts that mass on the canopy's **mean
//! motion**, in every direction:
//!
//! - vector area `A = Σ_t N_t` of the canopy's triangles (`N_t = ½ (x₁ − x₀) × (x₂ − x₀)`,
//!   the mesh consistently oriented), projected area `A_p = |A|` (m²);
//! - `M_a = (8/3) ρ a³` (kg) with `a = √(A_p/π)`, ρ at the canopy's area-weighted mean height;
//! - node weights `w_j` (Σ w_j = 1): node `j`'s share of the canopy's area (a third of each
//!   triangle it belongs to);
//! - mean velocity relative to the air `V = Σ_j w_j v_j − U∞` (m/s), momentum of the carried
//!   air `P = M_a V` (kg·m/s);
//! - force on node `j`: `f_j = −w_j (P − P_n)/Δt` (N), `P_n` the momentum when the step
//!   began: backward Euler's `−w_j dP/dt`, the force that the kinetic energy `½ M_a |V|²`
//!   puts on a node through Lagrange's equations.
//!
//! `M_a` and `w_j` are taken when a step is accepted (lagged by one step), so within a step
//! the force is linear in the velocities and its Jacobian is exact and of rank three:
//! `∂f_j/∂v_k = −(M_a/Δt) w_j w_k I`, `∂f/∂q = 0`. It couples every canopy node, so it is
//! held as the low-rank part `−(M_a/Δt) Σ_c u_c u_cᵀ`, `u_c = (w_j e_c)_j` for the three
//! axes `e_c` ([`Force::low_rank_dofs`]), not in the sparse pattern.
//!
//! **Why isotropic:** the fluid's force on a body is `−dP/dt` and its moment `−U × P`
//! (Kirchhoff's equations, Lamb, *Hydrodynamics*, §124). With equal added mass in every
//! direction `P ∥ U`, the moment vanishes, so a force on the mean motion alone is the
//! whole potential-flow load and conserves the body's and the air's kinetic energy. An axial
//! mass alone (a flat disc's: none edgewise) needs that moment (the Munk moment) and an axis
//! that turns with the canopy; without them, measured on the 4 m cargo canopy, the descent
//! became a 1.2 s coning motion that the canopy's inertia cannot explain (docs/notes). A
//! cupped canopy does carry air sideways: the air it encloses, `(2/3) π ρ a³ ≈ 2.1 ρ a³` for
//! a hemispherical one, against the disc's `2.7 ρ a³` broadside.
//! **Why the mean motion only:** giving every panel the disc's share along its own normal is
//! exact for a rigid disc but makes a fabric canopy's short-wavelength motions 20–100× too
//! heavy (a ripple of wavelength λ carries about ρλ/(2π) per unit area in potential flow); it
//! broke the bundled canopies' openings (docs/notes).
//! **Assumptions:** the inflated canopy carries the disc of its projected area in every
//! direction (the axial value of a cup is larger, about 4.5 ρ a³ in fitted data, its lateral
//! one uncertain); no rotary added mass (a disc's is `(16/45) ρ a⁵`), no added mass of
//! breathing; not for a flat sheet moving edgewise; still or uniformly moving air (no
//! Froude–Krylov force); potential flow, so the momentum the air loses to the wake is the
//! drag laws' business, not this one's.

use super::fluid::Fluid;
use super::geometry::{area_vector, centroid_height};
use crate::error::HistoryError;
use crate::force::{EvalInput, Force, JacobianKind, LocalBlocks};
use crate::vec3::V3;

/// The air's added mass on the mean motion of a canopy of triangles (module docs).
#[derive(Debug, Clone)]
pub struct AddedMass {
    /// The canopy's triangles (node indices).
    triangles: Vec<[usize; 3]>,
    /// The canopy's nodes, ascending.
    nodes: Vec<usize>,
    /// The three position DOFs of each node of `nodes`: the stencils and the low-rank DOFs.
    dofs: Vec<usize>,
    /// `w_j`: each node's share of the canopy's area, lagged.
    weights: Vec<f64>,
    /// `M_a`: the added mass on the mean motion (kg), lagged.
    added_mass: f64,
    /// `P_n`: the carried air's momentum when the current step began (kg·m/s).
    momentum: V3,
    fluid: Fluid,
    wind: V3,
}

impl AddedMass {
    /// Added mass on the canopy of `triangles` at `q` moving at `v` (all DOFs), in `fluid`:
    /// the air already moves with the canopy (`P_n` from `v`).
    ///
    /// # Panics
    /// With a wind that varies with height: the carried air's velocity would follow the
    /// canopy's height, a term this law does not hold (applications refuse the pair).
    pub fn new(triangles: &[[usize; 3]], q: &[f64], v: &[f64], fluid: &Fluid) -> Self {
        assert!(
            fluid.wind_profile.is_uniform(),
            "added mass needs a uniform wind"
        );
        let mut nodes: Vec<usize> = triangles.iter().flatten().copied().collect();
        nodes.sort_unstable();
        nodes.dedup();
        let dofs = nodes
            .iter()
            .flat_map(|&i| [3 * i, 3 * i + 1, 3 * i + 2])
            .collect();
        let mut am = Self {
            triangles: triangles.to_vec(),
            weights: vec![0.0; nodes.len()],
            nodes,
            dofs,
            added_mass: 0.0,
            momentum: V3::zeros(),
            fluid: fluid.clone(),
            wind: V3::from(fluid.wind),
        };
        am.follow(q);
        am.momentum = am.momentum_at(v);
        am
    }

    /// The added mass `M_a` in effect (kg).
    pub fn added_mass(&self) -> f64 {
        self.added_mass
    }

    /// `M_a` and `w_j` of the canopy at `q`.
    fn follow(&mut self, q: &[f64]) {
        let node = |i: usize| V3::new(q[3 * i], q[3 * i + 1], q[3 * i + 2]);
        let (mut vector_area, mut area, mut height) = (V3::zeros(), 0.0, 0.0);
        self.weights.iter_mut().for_each(|w| *w = 0.0);
        for t in &self.triangles {
            let x = t.map(node);
            let n = area_vector(&x);
            let a = n.norm();
            vector_area += n;
            area += a;
            height += a * centroid_height(&x);
            for i in t {
                let j = self.nodes.binary_search(i).expect("a canopy node");
                self.weights[j] += a / 3.0;
            }
        }
        let inv = 1.0 / area.max(f64::MIN_POSITIVE);
        self.weights.iter_mut().for_each(|w| *w *= inv);
        let radius = (vector_area.norm() / std::f64::consts::PI).sqrt();
        let rho = self.fluid.at(height * inv).density;
        self.added_mass = 8.0 / 3.0 * rho * radius.powi(3);
    }

    /// `V = Σ_j w_j v_j − U∞`: the canopy's mean velocity relative to the air.
    fn mean_velocity(&self, v: &[f64]) -> V3 {
        let mut mean = V3::zeros();
        for (w, d) in self.weights.iter().zip(self.dofs.chunks(3)) {
            mean += *w * V3::new(v[d[0]], v[d[1]], v[d[2]]);
        }
        mean - self.wind
    }

    /// `P = M_a V` at velocities `v`.
    fn momentum_at(&self, v: &[f64]) -> V3 {
        self.added_mass * self.mean_velocity(v)
    }
}

impl Force for AddedMass {
    fn name(&self) -> &str {
        "added-mass"
    }
    fn stencil_size(&self) -> usize {
        3
    }
    fn stencils(&self) -> &[usize] {
        &self.dofs
    }
    /// No blocks in the pattern: the whole Jacobian is the low-rank part.
    fn jacobian_kind(&self) -> JacobianKind {
        JacobianKind::CONSTANT
    }
    fn low_rank_dofs(&self) -> &[usize] {
        &self.dofs
    }
    fn low_rank_rank(&self) -> usize {
        3
    }

    fn evaluate(&self, input: &EvalInput<'_>, out: &mut LocalBlocks) {
        let force = -(self.momentum_at(input.v) - self.momentum) / input.dt;
        for (f, w) in out.f.chunks_mut(3).zip(&self.weights) {
            f.copy_from_slice((*w * force).as_slice());
        }
        if !input.jacobian {
            return;
        }
        let n = self.dofs.len();
        out.low_rank_coef.fill(-self.added_mass / input.dt);
        for (axis, u) in out.low_rank_u.chunks_mut(n).enumerate() {
            u.fill(0.0);
            for (uj, w) in u.chunks_mut(3).zip(&self.weights) {
                uj[axis] = *w;
            }
        }
    }

    /// The accepted step's momentum becomes the next step's `P_n` (with the `M_a` and `w`
    /// it was computed with), then they follow the canopy's new shape.
    fn commit(&mut self, q: &[f64], v: &[f64]) {
        self.momentum = self.momentum_at(v);
        self.follow(q);
    }

    fn history(&self) -> Vec<f64> {
        let p = self.momentum;
        [self.added_mass, p.x, p.y, p.z]
            .into_iter()
            .chain(self.weights.iter().copied())
            .collect()
    }

    fn restore_history(&mut self, h: &[f64]) -> Result<(), HistoryError> {
        let expected = 4 + self.weights.len();
        if h.len() != expected {
            return Err(HistoryError {
                force: self.name().to_string(),
                got: h.len(),
                expected,
            });
        }
        self.added_mass = h[0];
        self.momentum = V3::new(h[1], h[2], h[3]);
        self.weights.copy_from_slice(&h[4..]);
        Ok(())
    }
}

//! A payload hanging on a line under a drag node: the steady descent and the small lateral
//! oscillations of a two-mass pendulum with drag damping, in closed form.
//!
//! Node 0 (the canopy: mass `m₁`, drag area `A₁`) and node 1 (the payload: `m₂`, `A₂`) on a
//! line of rest length `L` and axial stiffness `k` (N), falling under gravity. The steady
//! descent has `V² = 2 g Σm/(ρ C_D ΣA)` and line tension `T = m₂ g − ½ρC_D A₂V²`. Sideways,
//! node drag `−½ρC_D A|u|u` damps each node by `cᵢ = ½ρC_D Aᵢ V` and the tensioned line of
//! length `l` couples them with stiffness `T/l`; with gravity acting along the line only,
//! `det(λ²M + λC + K) = λ·p(λ)`, `p` the cubic
//! `m₁m₂ λ³ + (m₁c₂ + m₂c₁) λ² + (c₁c₂ + (T/l)(m₁ + m₂)) λ + (T/l)(c₁ + c₂)`,
//! once for each horizontal direction.

use crate::aero::{Fluid, NodeDrag};
use crate::loads::Gravity;
use crate::rod::Stretch;
use crate::{DofLayout, Model};
use faer::c64;

/// The pendulum's data.
#[derive(Debug, Clone, Copy)]
pub struct Pendulum {
    /// Canopy and payload masses (kg).
    pub mass: [f64; 2],
    /// Their drag areas (m²).
    pub area: [f64; 2],
    /// Drag coefficient (–).
    pub cd: f64,
    /// Line rest length (m) and axial stiffness (N).
    pub line: [f64; 2],
    /// Gravity (m/s²).
    pub g: f64,
}

impl Pendulum {
    /// A light canopy node over a heavy payload on a stiff 3 m line.
    pub fn example() -> Self {
        Self {
            mass: [0.5, 8.0],
            area: [4.0, 0.1],
            cd: 1.2,
            line: [3.0, 2e4],
            g: 9.81,
        }
    }

    /// The model (node 0 at the origin, node 1 a line length below) in `fluid`.
    pub fn model(&self, fluid: &Fluid) -> (Model, Vec<f64>) {
        let q = vec![0.0, 0.0, 0.0, 0.0, 0.0, -self.line[0]];
        let mut model = Model::new(DofLayout::new(2, 0));
        for (i, &m) in self.mass.iter().enumerate() {
            model.add_node_mass(i, m);
        }
        model.add_force(Gravity::new(&[0, 1], &self.mass, [0.0, 0.0, -self.g]));
        model.add_force(NodeDrag::new(&[0, 1], &self.area, self.cd, fluid));
        model.add_force(Stretch::new("line", &[[0, 1]], &q, vec![self.line[1]]));
        (model, q)
    }

    /// The steady descent speed (m/s) and line tension (N) in air of density `rho`.
    pub fn steady(&self, rho: f64) -> (f64, f64) {
        let (m, a) = (self.mass, self.area);
        let v = (2.0 * self.g * (m[0] + m[1]) / (rho * self.cd * (a[0] + a[1]))).sqrt();
        (v, m[1] * self.g - 0.5 * rho * self.cd * a[1] * v * v)
    }

    /// The three nonzero lateral eigenvalues (1/s) in air of density `rho`: the roots of the
    /// cubic (module docs), as the eigenvalues of its companion matrix.
    pub fn lateral(&self, rho: f64) -> Vec<c64> {
        let (v, t) = self.steady(rho);
        let l = self.line[0] * (1.0 + t / self.line[1]);
        let (m, k) = (self.mass, t / l);
        let c = self.area.map(|a| 0.5 * rho * self.cd * a * v);
        let lead = m[0] * m[1];
        let p = [
            (m[0] * c[1] + m[1] * c[0]) / lead,
            (c[0] * c[1] + k * (m[0] + m[1])) / lead,
            k * (c[0] + c[1]) / lead,
        ];
        let companion = faer::Mat::from_fn(3, 3, |i, j| match (i, j) {
            (0, _) => -p[j],
            (i, j) if i == j + 1 => 1.0,
            _ => 0.0,
        });
        companion.eigenvalues().expect("a 3 × 3 eigen-solve")
    }
}

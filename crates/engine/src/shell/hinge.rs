//! Hinge bending of discrete shells (Grinspun et al. 2003; DisMech convention).
//!
//! Energy of a hinge with signed dihedral angle θ (see [`super::dihedral`]), rest angle
//! `θ̄` (rad, from the rest shape) and stiffness `k_b` (N·m = J/rad²):
//! `E = ½ k_b (θ − θ̄)²`. Force `f = −k_b (θ − θ̄) ∇θ`; Jacobian
//! `∂f/∂x = −k_b (∇θ ∇θᵀ + (θ − θ̄) ∇²θ)`.
//!
//! For a shell, `k_b = (2/√3) E h³/12`; see [`super::ShellMaterial`] for the effective
//! plate stiffness this gives on each mesh type.

use super::dihedral::{angle, angle_grad, angle_grad_hess};
use super::mesh::Hinge;
use crate::force::{EvalInput, Force, JacobianKind, LocalBlocks};
use crate::vec3::{node, V3};

/// `θ − θ̄` wrapped into `(−π, π]`, so that a rest angle near ±π does not see the
/// branch cut of θ as a jump of 2π.
#[inline]
pub fn wrap_angle(d: f64) -> f64 {
    use std::f64::consts::{PI, TAU};
    if d > PI {
        d - TAU
    } else if d <= -PI {
        d + TAU
    } else {
        d
    }
}

/// A family of bending hinges, stencil `[x0, x1, x2, x3]` (12 DOFs).
pub struct HingeBending {
    name: String,
    stencils: Vec<usize>,
    /// Rest dihedral angle `θ̄` per hinge (rad).
    pub rest_angle: Vec<f64>,
    /// Bending stiffness `k_b` per hinge (N·m).
    pub stiffness: Vec<f64>,
}

/// Hinge vertex positions read from `q` through a 12-DOF stencil.
#[inline]
fn positions(q: &[f64], st: &[usize]) -> [V3; 4] {
    [0, 1, 2, 3].map(|k| node(q, st[3 * k] / 3))
}

impl HingeBending {
    /// Hinges with rest angles measured in `q_rest` and stiffness `k_b` per hinge.
    pub fn new(name: &str, hinges: &[Hinge], q_rest: &[f64], stiffness: Vec<f64>) -> Self {
        let mut s = Self::with_rest_angles(name, hinges, vec![0.0; hinges.len()], stiffness);
        for i in 0..hinges.len() {
            s.rest_angle[i] = s.angle(q_rest, i);
        }
        s
    }

    /// Hinges with explicit rest angles (rad).
    pub fn with_rest_angles(
        name: &str,
        hinges: &[Hinge],
        rest_angle: Vec<f64>,
        stiffness: Vec<f64>,
    ) -> Self {
        assert_eq!(hinges.len(), rest_angle.len());
        assert_eq!(hinges.len(), stiffness.len());
        let stencils = hinges
            .iter()
            .flat_map(|h| h.nodes())
            .flat_map(|n| [3 * n, 3 * n + 1, 3 * n + 2])
            .collect();
        Self {
            name: name.to_string(),
            stencils,
            rest_angle,
            stiffness,
        }
    }

    /// Current dihedral angle θ (rad) of hinge `i` at configuration `q`.
    pub fn angle(&self, q: &[f64], i: usize) -> f64 {
        angle(&positions(q, &self.stencils[12 * i..12 * i + 12]))
    }

    /// Nodes `[x0, x1, x2, x3]` of hinge `i`.
    pub fn nodes(&self, i: usize) -> [usize; 4] {
        [0, 1, 2, 3].map(|k| self.stencils[12 * i + 3 * k] / 3)
    }

    /// Energy ½ k_b (θ − θ̄)² of hinge `i` (J).
    pub fn hinge_energy(&self, q: &[f64], i: usize) -> f64 {
        let d = wrap_angle(self.angle(q, i) - self.rest_angle[i]);
        0.5 * self.stiffness[i] * d * d
    }
}

impl Force for HingeBending {
    fn name(&self) -> &str {
        &self.name
    }
    fn stencil_size(&self) -> usize {
        12
    }
    fn stencils(&self) -> &[usize] {
        &self.stencils
    }
    fn jacobian_kind(&self) -> JacobianKind {
        JacobianKind::ELASTIC
    }
    fn evaluate(&self, input: &EvalInput<'_>, out: &mut LocalBlocks) {
        let q = input.q;
        out.par_for_each(input.jacobian, |b| {
            let i = b.index;
            let x = positions(q, &self.stencils[12 * i..12 * i + 12]);
            let k = self.stiffness[i];
            if b.dfdq.is_empty() {
                let (theta, g) = angle_grad(&x);
                let d = wrap_angle(theta - self.rest_angle[i]);
                for a in 0..12 {
                    b.f[a] = -k * d * g[a];
                }
                return;
            }
            let (theta, g, h) = angle_grad_hess(&x);
            let d = wrap_angle(theta - self.rest_angle[i]);
            for a in 0..12 {
                b.f[a] = -k * d * g[a];
            }
            {
                for r in 0..12 {
                    for c in 0..12 {
                        b.dfdq[r * 12 + c] = -k * (g[r] * g[c] + d * h[(r, c)]);
                    }
                }
            }
        });
    }
    fn conservative(&self) -> bool {
        true
    }
    fn energy(&self, q: &[f64]) -> Option<f64> {
        Some(
            (0..self.rest_angle.len())
                .map(|i| self.hinge_energy(q, i))
                .sum(),
        )
    }
}

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
use crate::element::{node_stencils, Element, Family};
use crate::force::{BlockMut, EvalInput, JacobianKind};
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

/// The hinge-bending law (stateless: everything is per hinge).
#[derive(Debug, Clone, Copy, Default)]
pub struct HingeLaw;

/// Rest angle and stiffness of one hinge.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HingeData {
    /// Rest dihedral angle `θ̄` (rad).
    pub rest_angle: f64,
    /// Bending stiffness `k_b` (N·m).
    pub stiffness: f64,
}

/// A family of bending hinges, stencil `[x0, x1, x2, x3]` (12 DOFs).
pub type HingeBending = Family<HingeLaw>;

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
            s.data[i].rest_angle = s.angle(q_rest, i);
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
        let nodes: Vec<[usize; 4]> = hinges.iter().map(|h| h.nodes()).collect();
        let data = rest_angle
            .iter()
            .zip(&stiffness)
            .map(|(&rest_angle, &stiffness)| HingeData {
                rest_angle,
                stiffness,
            })
            .collect();
        Family::from_elements(name, HingeLaw, node_stencils(&nodes), data)
    }

    /// Current dihedral angle θ (rad) of hinge `i` at configuration `q`.
    pub fn angle(&self, q: &[f64], i: usize) -> f64 {
        angle(&positions(q, self.stencil(i)))
    }

    /// Nodes `[x0, x1, x2, x3]` of hinge `i`.
    pub fn nodes(&self, i: usize) -> [usize; 4] {
        let st = self.stencil(i);
        [0, 1, 2, 3].map(|k| st[3 * k] / 3)
    }

    /// Energy ½ k_b (θ − θ̄)² of hinge `i` (J).
    pub fn hinge_energy(&self, q: &[f64], i: usize) -> f64 {
        let mut e = 0.0;
        HingeLaw.add_energy(&self.data[i], self.stencil(i), q, &mut e);
        e
    }
}

impl Element for HingeLaw {
    const STENCIL: usize = 12;
    const KIND: JacobianKind = JacobianKind::ELASTIC;
    type Data = HingeData;

    fn evaluate(&self, el: &HingeData, st: &[usize], input: &EvalInput<'_>, b: BlockMut<'_>) {
        let x = positions(input.q, st);
        let k = el.stiffness;
        if b.dfdq.is_empty() {
            let (theta, g) = angle_grad(&x);
            let d = wrap_angle(theta - el.rest_angle);
            for a in 0..12 {
                b.f[a] = -k * d * g[a];
            }
            return;
        }
        let (theta, g, h) = angle_grad_hess(&x);
        let d = wrap_angle(theta - el.rest_angle);
        for a in 0..12 {
            b.f[a] = -k * d * g[a];
        }
        for r in 0..12 {
            for c in 0..12 {
                b.dfdq[r * 12 + c] = -k * (g[r] * g[c] + d * h[(r, c)]);
            }
        }
    }

    fn add_energy(&self, el: &HingeData, st: &[usize], q: &[f64], acc: &mut f64) {
        let d = wrap_angle(angle(&positions(q, st)) - el.rest_angle);
        *acc += 0.5 * el.stiffness * d * d;
    }
}

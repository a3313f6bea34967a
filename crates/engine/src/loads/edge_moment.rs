//! A planar end moment that follows its edge: the exact load of the end-moment (pure
//! bending) problem.
use crate::element::{node_stencils, Element, Family};
use crate::force::{BlockMut, EvalInput, JacobianKind};

/// The end-moment law: moment, load scale and the last committed edge angle (history).
#[derive(Debug, Clone, Copy)]
pub struct EdgeMomentLaw {
    moment: f64,
    scale: f64,
    phi_prev: f64,
}

/// A conservative end moment `M` (N·m) about −y on the edge `a → b`, for motion in the x–z
/// plane: potential `−M φ`, `φ = atan2(e_z, e_x)` the edge's angle (unwrapped by history).
/// A planar moment is conservative and follows the edge, so this is the exact load of the
/// end-moment problem (a follower couple of two forces would only approximate it).
///
/// Force on node `b` (x and z components, N): `M ∇φ = M (−e_z, e_x)/|e|²`, the opposite on
/// node `a`; its Jacobian is `M ∇²φ` (symmetric). The moment is planar: the edge's y
/// extent is ignored, so use it for motion confined to the x–z plane.
pub type PlanarEdgeMoment = Family<EdgeMomentLaw>;

impl PlanarEdgeMoment {
    /// Moment `moment` (N·m, about −y: positive turns the edge from +x towards +z) on the
    /// edge from node `a` to node `b`.
    pub fn new(a: usize, b: usize, moment: f64) -> Self {
        let law = EdgeMomentLaw {
            moment,
            scale: 1.0,
            phi_prev: 0.0,
        };
        Family::from_elements(
            "planar-edge-moment",
            law,
            node_stencils(&[[a, b]]),
            vec![()],
        )
    }
}

impl EdgeMomentLaw {
    /// Unwrapped edge angle φ (rad, continued from the last committed angle) and the
    /// edge's x and z components (m).
    fn angle(&self, q: &[f64], st: &[usize]) -> (f64, f64, f64) {
        let ex = q[st[3]] - q[st[0]];
        let ez = q[st[5]] - q[st[2]];
        let raw = ez.atan2(ex);
        let tau = std::f64::consts::TAU;
        (raw - tau * ((raw - self.phi_prev) / tau).round(), ex, ez)
    }
}

impl Element for EdgeMomentLaw {
    const STENCIL: usize = 6;
    const KIND: JacobianKind = JacobianKind::ELASTIC;
    type Data = ();

    fn evaluate(&self, _: &(), st: &[usize], input: &EvalInput<'_>, b: BlockMut<'_>) {
        let (_, x, z) = self.angle(input.q, st);
        let m = self.scale * self.moment;
        let r2 = x * x + z * z;
        // ∇φ in (x, z) and its Hessian.
        let g = [-z / r2, x / r2];
        let h = [
            [2.0 * x * z / (r2 * r2), (z * z - x * x) / (r2 * r2)],
            [(z * z - x * x) / (r2 * r2), -2.0 * x * z / (r2 * r2)],
        ];
        let comp = [0usize, 2];
        b.f.fill(0.0);
        b.dfdq.fill(0.0);
        let jac = !b.dfdq.is_empty();
        for i in 0..2 {
            b.f[3 + comp[i]] = m * g[i];
            b.f[comp[i]] = -m * g[i];
            for j in 0..2 {
                if !jac {
                    break;
                }
                let v = m * h[i][j];
                b.dfdq[(3 + comp[i]) * 6 + 3 + comp[j]] = v;
                b.dfdq[comp[i] * 6 + comp[j]] = v;
                b.dfdq[(3 + comp[i]) * 6 + comp[j]] = -v;
                b.dfdq[comp[i] * 6 + 3 + comp[j]] = -v;
            }
        }
    }

    fn add_energy(&self, _: &(), st: &[usize], q: &[f64], acc: &mut f64) {
        *acc += -self.scale * self.moment * self.angle(q, st).0;
    }

    fn commit(&mut self, _: &mut [()], stencils: &[usize], q: &[f64], _v: &[f64]) {
        self.phi_prev = self.angle(q, stencils).0;
    }

    fn history_len(&self, _: usize) -> usize {
        1
    }

    /// `[φ]`: the last committed edge angle, which picks the branch of the energy.
    fn history(&self, _: &[()]) -> Vec<f64> {
        vec![self.phi_prev]
    }

    fn restore_history(&mut self, _: &mut [()], h: &[f64]) {
        self.phi_prev = h[0];
    }

    fn set_load_scale(&mut self, scale: f64) {
        self.scale = scale;
    }
}

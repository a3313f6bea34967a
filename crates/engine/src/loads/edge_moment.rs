//! A planar end moment that follows its edge: the exact load of the end-moment (pure
//! bending) problem.
use crate::force::{EvalInput, Force, JacobianKind, LocalBlocks};

/// A conservative end moment `M` (N·m) about −y on the edge `a → b`, for motion in the x–z
/// plane: potential `−M φ`, `φ = atan2(e_z, e_x)` the edge's angle (unwrapped by history).
/// A planar moment is conservative and follows the edge, so this is the exact load of the
/// end-moment problem (a follower couple of two forces would only approximate it).
///
/// Force on node `b` (x and z components, N): `M ∇φ = M (−e_z, e_x)/|e|²`, the opposite on
/// node `a`; its Jacobian is `M ∇²φ` (symmetric). The moment is planar: the edge's y
/// extent is ignored, so use it for motion confined to the x–z plane.
pub struct PlanarEdgeMoment {
    st: [usize; 6],
    moment: f64,
    scale: f64,
    phi_prev: f64,
}

impl PlanarEdgeMoment {
    /// Moment `moment` (N·m, about −y: positive turns the edge from +x towards +z) on the
    /// edge from node `a` to node `b`.
    pub fn new(a: usize, b: usize, moment: f64) -> Self {
        Self {
            st: [3 * a, 3 * a + 1, 3 * a + 2, 3 * b, 3 * b + 1, 3 * b + 2],
            moment,
            scale: 1.0,
            phi_prev: 0.0,
        }
    }
    /// Unwrapped edge angle φ (rad, continued from the last committed angle) and the
    /// edge's x and z components (m).
    fn angle(&self, q: &[f64]) -> (f64, f64, f64) {
        let ex = q[self.st[3]] - q[self.st[0]];
        let ez = q[self.st[5]] - q[self.st[2]];
        let raw = ez.atan2(ex);
        let tau = std::f64::consts::TAU;
        (raw - tau * ((raw - self.phi_prev) / tau).round(), ex, ez)
    }
}

impl Force for PlanarEdgeMoment {
    fn name(&self) -> &str {
        "planar-edge-moment"
    }
    fn stencil_size(&self) -> usize {
        6
    }
    fn stencils(&self) -> &[usize] {
        &self.st
    }
    fn jacobian_kind(&self) -> JacobianKind {
        JacobianKind::ELASTIC
    }
    fn evaluate(&self, input: &EvalInput<'_>, out: &mut LocalBlocks) {
        let (_, x, z) = self.angle(input.q);
        let m = self.scale * self.moment;
        let r2 = x * x + z * z;
        // ∇φ in (x, z) and its Hessian.
        let g = [-z / r2, x / r2];
        let h = [
            [2.0 * x * z / (r2 * r2), (z * z - x * x) / (r2 * r2)],
            [(z * z - x * x) / (r2 * r2), -2.0 * x * z / (r2 * r2)],
        ];
        let comp = [0usize, 2];
        out.f.fill(0.0);
        out.dfdq.fill(0.0);
        for i in 0..2 {
            out.f[3 + comp[i]] = m * g[i];
            out.f[comp[i]] = -m * g[i];
            for j in 0..2 {
                let v = m * h[i][j];
                out.dfdq[(3 + comp[i]) * 6 + 3 + comp[j]] = v;
                out.dfdq[comp[i] * 6 + comp[j]] = v;
                out.dfdq[(3 + comp[i]) * 6 + comp[j]] = -v;
                out.dfdq[comp[i] * 6 + 3 + comp[j]] = -v;
            }
        }
    }
    fn conservative(&self) -> bool {
        true
    }
    fn energy(&self, q: &[f64]) -> Option<f64> {
        Some(-self.scale * self.moment * self.angle(q).0)
    }
    fn commit(&mut self, q: &[f64]) {
        self.phi_prev = self.angle(q).0;
    }
    fn set_load_scale(&mut self, s: f64) {
        self.scale = s;
    }
}

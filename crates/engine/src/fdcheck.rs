//! Finite-difference verification of any [`Force`]: the force against `−∇E` and the
//! Jacobians `∂F/∂q`, `∂F/∂v` against central differences of the force.
//!
//! Errors are relative to the largest entry of the analytic quantity (as in fenris), so
//! that tiny entries do not dominate: `max|a − fd| / max(max|a|, floor)`.

use crate::force::{EvalInput, Force};

/// Dense global evaluation of one force: `(F, ∂F/∂q, ∂F/∂v)` with row-major `n × n` matrices.
pub fn dense_eval(force: &dyn Force, q: &[f64], v: &[f64]) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let n = q.len();
    let mut blocks = force.new_blocks();
    force.evaluate(
        &EvalInput {
            q,
            v,
            t: 0.0,
            jacobian: true,
            dt: crate::conformance::CONFORMANCE_DT,
        },
        &mut blocks,
    );
    let k = force.stencil_size();
    let mut f = vec![0.0; n];
    let mut kq = vec![0.0; n * n];
    let mut kv = vec![0.0; n * n];
    for (s, st) in force.stencils().chunks(k).enumerate() {
        for a in 0..k {
            f[st[a]] += blocks.f[s * k + a];
            for b in 0..k {
                let idx = s * k * k + a * k + b;
                if !blocks.dfdq.is_empty() {
                    kq[st[a] * n + st[b]] += blocks.dfdq[idx];
                }
                if !blocks.dfdv.is_empty() {
                    kv[st[a] * n + st[b]] += blocks.dfdv[idx];
                }
            }
        }
    }
    let dofs = force.low_rank_dofs();
    for (c, u) in blocks
        .low_rank_coef
        .iter()
        .zip(blocks.low_rank_u.chunks(dofs.len().max(1)))
    {
        for (&a, ua) in dofs.iter().zip(u) {
            for (&b, ub) in dofs.iter().zip(u) {
                kv[a * n + b] += c * ua * ub;
            }
        }
    }
    (f, kq, kv)
}

/// Result of a finite-difference check (relative errors).
#[derive(Debug, Clone, Copy, Default)]
pub struct FdReport {
    /// Force vs `−∇E` (0 when the force has no energy).
    pub force_vs_energy: f64,
    /// `∂F/∂q` vs central differences of `F`.
    pub dfdq: f64,
    /// `∂F/∂v` vs central differences of `F`.
    pub dfdv: f64,
}

impl FdReport {
    /// Largest of the three errors.
    pub fn max(&self) -> f64 {
        self.force_vs_energy.max(self.dfdq).max(self.dfdv)
    }
}

/// `max|a − b| / max(max|a|, 1e-300)`, 0 when `a == b`.
pub fn rel_err(a: &[f64], b: &[f64]) -> f64 {
    let scale = a.iter().fold(0.0f64, |m, x| m.max(x.abs())).max(1e-300);
    let diff = a
        .iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    if diff == 0.0 {
        0.0
    } else {
        diff / scale
    }
}

/// Check `force` at `(q, v)` with central differences of step `h` (absolute, in DOF units).
pub fn check_force(force: &dyn Force, q: &[f64], v: &[f64], h: f64) -> FdReport {
    let n = q.len();
    let (f0, kq, kv) = dense_eval(force, q, v);
    let mut report = FdReport::default();
    if force.energy(q).is_some() {
        let mut grad = vec![0.0; n];
        let mut qp = q.to_vec();
        for j in 0..n {
            qp[j] = q[j] + h;
            let ep = force.energy(&qp).unwrap();
            qp[j] = q[j] - h;
            let em = force.energy(&qp).unwrap();
            qp[j] = q[j];
            grad[j] = -(ep - em) / (2.0 * h);
        }
        report.force_vs_energy = rel_err(&f0, &grad);
    }
    let kind = force.jacobian_kind();
    if kind.dq {
        let fd = fd_jacobian(force, q, v, h, true);
        report.dfdq = rel_err(&kq, &fd);
    }
    if kind.dv {
        let fd = fd_jacobian(force, q, v, h, false);
        report.dfdv = rel_err(&kv, &fd);
    }
    report
}

/// Central-difference Jacobian of the global force of `force` at `(q, v)` with respect to
/// `q` (`wrt_q`) or `v`, row-major `n × n`, step `h`.
pub fn fd_jacobian(force: &dyn Force, q: &[f64], v: &[f64], h: f64, wrt_q: bool) -> Vec<f64> {
    let n = q.len();
    let mut out = vec![0.0; n * n];
    let mut qp = q.to_vec();
    let mut vp = v.to_vec();
    for j in 0..n {
        let x = if wrt_q { &mut qp } else { &mut vp };
        let x0 = x[j];
        x[j] = x0 + h;
        let (fp, _, _) = dense_eval(force, &qp, &vp);
        let x = if wrt_q { &mut qp } else { &mut vp };
        x[j] = x0 - h;
        let (fm, _, _) = dense_eval(force, &qp, &vp);
        let x = if wrt_q { &mut qp } else { &mut vp };
        x[j] = x0;
        for i in 0..n {
            out[i * n + j] = (fp[i] - fm[i]) / (2.0 * h);
        }
    }
    out
}

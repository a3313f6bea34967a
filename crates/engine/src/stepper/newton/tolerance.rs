//! When a Newton iterate is converged: the residual's max norm, the round-off floor of the
//! inertia term, and the accuracy-based test against backward Euler's local error.

use super::{NewtonCore, Target};
use crate::error::StepError;
use crate::model::Model;
use crate::stepper::options::StepReport;

/// What the convergence tests say of an iterate.
pub(super) enum Verdict {
    /// Converged: the solve ends here.
    Converged,
    /// Not yet: iterate on (the residual's max norm).
    Continue(f64),
}

impl NewtonCore {
    pub(super) fn inf_norm(&self) -> (f64, usize) {
        let mut worst = (0.0, 0);
        for (r, &x) in self.residual.iter().enumerate() {
            // NaN compares false, so a NaN residual is always reported as the worst.
            if x.is_nan() || x.abs() > worst.0 {
                worst = (x.abs(), self.assembler.dof_of[r]);
            }
        }
        worst
    }

    /// The smallest residual (N) the inertia term can resolve: `c_m m (q − q̃)` is computed
    /// from coordinates stored to `ε |q|`, so its round-off is about `ε c_m m |q|`. At tiny
    /// `dt` (large `c_m = 1/dt²`) or far from the origin this exceeds a fixed tolerance, and
    /// Newton would fail on round-off instead of physics; the tolerance never goes below
    /// 16 × this floor (~1e-7 N per kg at dt = 1e-3 s and |q| ≈ 100 m).
    pub(super) fn roundoff_floor(&self, model: &Model, q: &[f64], tg: &Target<'_>) -> f64 {
        let worst = self
            .assembler
            .dof_of
            .iter()
            .map(|&d| model.mass[d] * q[d].abs().max(tg.q_tilde[d].abs()))
            .fold(0.0, f64::max);
        16.0 * f64::EPSILON * tg.c_m * worst
    }

    /// The accuracy-based test ([`accuracy_fraction`](crate::NewtonOptions::accuracy_fraction))
    /// at iterate `q` with the residual in `self.residual`: every
    /// `|R_i| / m_i ≤ max(η c_m ½‖q − q̃‖∞, ε a_ref)`.
    /// `|R_i| / (c_m m_i)` is the displacement the residual left would cause through the
    /// inertia term alone, an upper bound on the Newton correction `J⁻¹ R` where the
    /// stiffness is positive (`J ⪰ c_m M`).
    pub(super) fn accurate(&self, q: &[f64], tg: &Target<'_>) -> bool {
        let eta = self.opts.accuracy_fraction;
        if eta <= 0.0 || tg.c_m <= 0.0 {
            return false;
        }
        let dofs = &self.assembler.dof_of;
        let e = 0.5
            * dofs
                .iter()
                .map(|&d| (q[d] - tg.q_tilde[d]).abs())
                .fold(0.0, f64::max);
        let bound =
            (eta * tg.c_m * e).max(self.opts.accuracy_floor * self.opts.reference_acceleration);
        self.residual
            .iter()
            .zip(&self.inv_mass)
            .all(|(r, im)| r.abs() * im <= bound)
    }

    /// The verdict on iterate `q` (its residual in `self.residual`) against the tolerance
    /// `tol` and the first residual `r0`: converged by the force or the accuracy test, or an
    /// error when the residual is not finite, has diverged or the budget is spent.
    pub(super) fn verdict(
        &mut self,
        q: &[f64],
        tg: &Target<'_>,
        r0: f64,
        tol: f64,
        report: &mut StepReport,
    ) -> Result<Verdict, StepError> {
        let (rinf, worst) = self.inf_norm();
        if !rinf.is_finite() {
            return Err(StepError::NonFinite {
                what: "residual",
                dof: worst,
            });
        }
        report.residual = rinf;
        if rinf <= tol {
            return Ok(Verdict::Converged);
        }
        if self.accurate(q, tg) {
            self.timings.accuracy_accepts += 1;
            return Ok(Verdict::Converged);
        }
        if rinf > self.opts.divergence_limit * r0.max(tol) {
            return Err(StepError::Diverged {
                iterations: report.iterations,
                residual: rinf,
                initial: r0,
                limit: self.opts.divergence_limit,
                worst_dof: worst,
            });
        }
        if report.iterations >= self.budget() {
            return Err(StepError::NotConverged {
                iterations: report.iterations,
                residual: rinf,
                tolerance: tol,
                worst_dof: worst,
            });
        }
        Ok(Verdict::Continue(rinf))
    }
}

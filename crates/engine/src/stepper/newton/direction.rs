//! The Newton direction: the triangular solves with the held factors, the Krylov correction
//! of the symmetric approximation, and the check of how far its update is from the exact
//! Newton update (the skew part of `J`).

use super::{NewtonCore, SKEW_LIMIT};
use crate::error::StepError;
use crate::stepper::options::StepReport;
use std::time::Instant;

impl NewtonCore {
    /// `Δ = −A⁻¹ R` with the held factors `A`.
    pub(super) fn linear_solve(&mut self) {
        for (d, r) in self.delta.iter_mut().zip(&self.residual) {
            *d = -r;
        }
        let t0 = Instant::now();
        self.solver.solve(&mut self.delta);
        self.timings.solve_s += t0.elapsed().as_secs_f64();
    }

    /// Refine `Δ = J_s⁻¹ (−R)` into the solution of `J Δ = −R` (to 1e-3 relative residual,
    /// an inexact-Newton forcing term that keeps the Newton contraction ≤ ~1e-3) by BiCGStab
    /// preconditioned with the held factors of `J_s` (`J` is in `values`: the matrix the
    /// factors were computed from). Returns whether it converged.
    fn krylov_correct(&mut self) -> bool {
        for (b, r) in self.neg_residual.iter_mut().zip(&self.residual) {
            *b = -r;
        }
        // The approximate update, restored by the caller if the correction fails.
        self.delta_approx.copy_from_slice(&self.delta);
        let t0 = Instant::now();
        let rep = self.solver.solve_corrected(
            &self.values,
            &self.neg_residual,
            &mut self.delta,
            1e-3,
            20,
        );
        self.timings.solve_s += t0.elapsed().as_secs_f64();
        self.timings.krylov_iterations += rep.iterations as u64;
        rep.converged && self.delta.iter().all(|d| d.is_finite())
    }

    /// `‖J Δ + R‖∞ / ‖R‖∞` for `Δ` from the symmetric approximation `J_s Δ = −R`: since
    /// `J Δ + R = (J − J_s) Δ`, one product with the skew part (nnz flops) measures how far the
    /// linearised residual is from zero, independently of the problem's nonlinearity. Exact
    /// Newton has 0; a ratio above the reuse contraction means the approximation, not the
    /// nonlinearity, would limit convergence.
    fn skew_ratio(&mut self) -> f64 {
        let a = &self.assembler;
        let y = &mut self.skew_product;
        y.iter_mut().for_each(|x| *x = 0.0);
        for c in 0..a.n_free {
            let dc = self.delta[c];
            for k in a.col_ptr[c]..a.col_ptr[c + 1] {
                y[a.row_idx[k]] += (self.values[k] - self.sym_values[k]) * dc;
            }
        }
        let num = y.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let den = self.residual.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        if den > 0.0 {
            num / den
        } else {
            0.0
        }
    }

    /// The Newton direction into `self.delta` (the held factors' solve, corrected by Krylov
    /// where the symmetric approximation is too far from J) and its max norm; an error if it
    /// is not finite.
    pub(super) fn direction(
        &mut self,
        fresh: bool,
        report: &mut StepReport,
    ) -> Result<f64, StepError> {
        self.linear_solve();
        if self.approx_held
            && !self.corrected
            && !self.krylov_off
            && fresh
            && self.skew_ratio() > SKEW_LIMIT
        {
            // The symmetric approximation is too far from J for this solve (drag strong
            // against M/dt² + K): correct this and every later update of the solve.
            self.corrected = true;
            self.timings.approx_fallbacks += 1;
        }
        if self.approx_held && self.corrected && !self.krylov_correct() {
            // BiCGStab did not converge (J_s⁻¹ J far from I: a wild iterate, or drag
            // dominating M/dt² + K): keep the approximate update. If it does not contract, the
            // Jacobian is refreshed or the step fails and the run loop shortens dt. No LU:
            // its storage is several times the Cholesky factor's (gigabytes at 100k DOFs).
            // Not retried in this solve: a failed correction costs 20 iterations.
            self.timings.krylov_failures += 1;
            self.delta.copy_from_slice(&self.delta_approx);
            self.corrected = false;
            self.krylov_off = true;
        }
        self.timings.iterations += 1;
        report.iterations += 1;
        let mut dmax = 0.0f64;
        for (r, &d) in self.delta.iter().enumerate() {
            if !d.is_finite() {
                return Err(StepError::NonFinite {
                    what: "Newton update",
                    dof: self.assembler.dof_of[r],
                });
            }
            dmax = dmax.max(d.abs());
        }
        Ok(dmax)
    }
}

//! The exact retry ([`crate::NewtonOptions::exact_retry`]): a solve that failed on the
//! modified-Newton path (reused or approximate factors) is tried again with exact Newton,
//! in stages, before the caller shortens the step.

use super::{NewtonCore, Target};
use crate::error::StepError;
use crate::model::Model;
use crate::stepper::options::StepReport;

impl NewtonCore {
    /// Retry a failed solve with exact Newton from the constant-velocity guess `q̃` (the
    /// failed path may have started from an extrapolation that was the problem): the stages
    /// of [`NewtonCore::exact_stages`]; then pseudo-transient continuation
    /// (`newton/continuation.rs`, four times the budget), which converges to the same
    /// solution where Newton's iteration from `q̃` wanders off; last the step-size homotopy
    /// (`newton/homotopy.rs`), which follows the step's solution from half the step up.
    pub(super) fn exact_retry(
        &mut self,
        model: &Model,
        q: &mut [f64],
        tg: &Target<'_>,
    ) -> Result<StepReport, StepError> {
        self.timings.exact_retries += 1;
        let mut res = self.exact_stages(model, q, tg);
        if res.is_err() && self.opts.continuation {
            self.exact = Some(false);
            self.retry_lu = true;
            res = self.continuation(model, q, tg);
            self.exact = None;
        }
        if res.is_err() && self.opts.step_homotopy {
            res = self.step_homotopy(model, q, tg);
        }
        if res.is_ok() {
            self.timings.exact_retries_converged += 1;
        }
        res
    }

    /// Exact Newton from `q̃` (`q` holds the solution on success), in stages that each start
    /// from `q̃` with twice the iteration budget: full steps (a stiff membrane's residual rises
    /// on the first full step and then converges quadratically, where a line search on
    /// `‖R‖₂` creeps) with the symmetric approximation's factors and every update corrected
    /// by BiCGStab; where that fails, full steps with `J` factorised by LU (a correction that
    /// does not converge is what may have failed); then LU with the line search. Without the
    /// approximation (symmetric `J`) the LU stage would repeat the first.
    fn exact_stages(
        &mut self,
        model: &Model,
        q: &mut [f64],
        tg: &Target<'_>,
    ) -> Result<StepReport, StepError> {
        let mut res = Err(StepError::NonFinite {
            what: "exact retry",
            dof: 0,
        });
        let approx = !self.sym_values.is_empty();
        for (search, lu) in [(false, false), (false, true), (true, true)] {
            if (search && !self.opts.line_search) || (lu && !search && !approx) {
                continue;
            }
            q.copy_from_slice(tg.q_tilde);
            res = self.solve_exact(model, q, tg, search, lu);
            if res.is_ok() {
                break;
            }
        }
        res
    }

    /// One exact-Newton solve from `q`: a fresh Jacobian every iteration, with the line
    /// search or not, the symmetric approximation's updates corrected by BiCGStab or `J`
    /// factorised by LU.
    pub(super) fn solve_exact(
        &mut self,
        model: &Model,
        q: &mut [f64],
        tg: &Target<'_>,
        search: bool,
        lu: bool,
    ) -> Result<StepReport, StepError> {
        self.exact = Some(search);
        self.retry_lu = lu;
        let res = self.solve_from(model, q, tg, true);
        self.exact = None;
        res
    }
}

//! Pseudo-transient continuation: the last stage of the exact retry
//! ([`super::NewtonCore::exact_retry`]), for a step whose exact Newton iteration from the
//! constant-velocity guess fails with full steps and with the line search.
//!
//! Each iteration solves `(J + (c_m/τ) M) Δ = −R` with a fresh exact Jacobian `J` at the
//! iterate. The extra diagonal is an added inertia: with `τ` small the update is a short,
//! well-conditioned step along `−M⁻¹R` (a smaller pseudo time step), with `τ → ∞` it is
//! Newton's. An update that lowers `‖R‖₂` is taken and `τ` grows with the residual's fall
//! (switched evolution relaxation, Mulder & van Leer 1985; Kelley & Keyes 1998:
//! `τ ← τ ‖R_{k−1}‖₂ / ‖R_k‖₂`, at least doubled), so the iteration ends quadratically; one
//! that does not is undone and `τ` is quartered (a trust region in the mass metric). The
//! diagonal only changes the path: convergence is judged on `R` itself with the solve's own
//! tolerance, so the result is the implicit-Euler solution of the step.

use super::tolerance::Verdict;
use super::{NewtonCore, Target};
use crate::error::StepError;
use crate::model::Model;
use crate::stepper::options::StepReport;

/// First `τ`: the extra diagonal is `10 c_m M` (the inertia 11×, a pseudo step ~dt/3).
const TAU_START: f64 = 0.1;
/// An update that raises `‖R‖₂` by more than this factor is undone.
const GROWTH_LIMIT: f64 = 10.0;
/// Bounds of `τ` (past the upper one the extra diagonal is below round-off of `c_m M`).
const TAU_MIN: f64 = 1e-8;
const TAU_MAX: f64 = 1e16;

impl NewtonCore {
    /// Pseudo-transient continuation from `q̃` (module docs); `q` holds the solution on
    /// success. Runs with the exact retry's budget; the held factors (of a shifted matrix)
    /// are marked as not reusable afterwards.
    pub(super) fn continuation(
        &mut self,
        model: &Model,
        q: &mut [f64],
        tg: &Target<'_>,
    ) -> Result<StepReport, StepError> {
        let mut report = StepReport::default();
        self.history.clear();
        self.timings.solves += 1;
        self.timings.continuations += 1;
        self.corrected = true;
        self.krylov_off = false;
        q.copy_from_slice(tg.q_tilde);
        let mut norm = self.residual_at(model, q, tg, true);
        let (r0, _) = self.inf_norm();
        let tol =
            self.force_tol_abs + self.opts.force_tol_rel * r0 + self.roundoff_floor(model, q, tg);
        self.history.push(r0);
        let mut tau = TAU_START;
        self.continuing = true;
        let res = loop {
            match self.verdict(q, tg, r0, tol, &mut report) {
                Ok(Verdict::Converged) => break Ok(report),
                Ok(Verdict::Continue(_)) => {}
                Err(e) => break Err(e),
            }
            let shift = tg.c_m / tau;
            for (r, &d) in self.assembler.dof_of.iter().enumerate() {
                self.values[self.assembler.diag[r]] += shift * model.mass[d];
            }
            if let Err(e) = self.factor(tg, &mut report) {
                break Err(e);
            }
            if let Err(e) = self.direction(true, &mut report) {
                break Err(e);
            }
            let trial = self.try_step(model, q, tg, 1.0, true);
            if trial.is_finite() && trial < GROWTH_LIMIT * norm {
                q.copy_from_slice(&self.q_trial);
                tau = (tau * norm / trial.max(f64::MIN_POSITIVE)).clamp(TAU_MIN, TAU_MAX);
                norm = trial;
            } else {
                // Undone: the residual and Jacobian at q again, a shorter pseudo step.
                tau = (0.25 * tau).max(TAU_MIN);
                norm = self.residual_at(model, q, tg, true);
                report.backtracks += 1;
            }
            let (rinf, _) = self.inf_norm();
            self.history.push(rinf);
        };
        self.continuing = false;
        // The factors are of J + (c_m/τ) M, not of this step's Newton matrix.
        self.factored_for = (f64::NAN, f64::NAN);
        if res.is_ok() {
            self.timings.continuations_converged += 1;
        }
        res
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::prelude::*;
    use crate::stepper::options::NewtonOptions;

    /// The 7 × 4-node Kevlar sheet of `tests/solver/exact_retry.rs` (6 m × 3 m) under
    /// gravity, pressure drag and 50 N per corner, flat at rest.
    fn kevlar() -> (Model, State) {
        crate::reference::sheet::kevlar_sheet(7, 4, 6.0, 3.0, 50.0)
    }

    #[test]
    fn continuation_lands_on_the_strict_newton_solution_of_the_step() {
        let (model, state) = kevlar();
        let dt = 1e-2;
        // The second step from rest (the first one defeats line-searched Newton: below).
        let mut st = crate::ImplicitEuler::new(&model, NewtonOptions::recommended()).unwrap();
        let (mut model, mut state) = (model, state);
        st.step(&mut model, &mut state, dt).unwrap();
        let q_tilde: Vec<f64> = state
            .q
            .iter()
            .zip(&state.v)
            .map(|(q, v)| q + dt * v)
            .collect();
        let tg = Target {
            c_m: 1.0 / (dt * dt),
            c_v: 1.0 / dt,
            q_tilde: &q_tilde,
            q_n: &state.q,
            t: state.t + dt,
        };
        let strict = NewtonOptions::default();
        let mut core = NewtonCore::new(&model, strict).unwrap();
        let mut q_newton = q_tilde.clone();
        let newton = core.solve(&model, &mut q_newton, &tg).unwrap();
        let mut q_cont = q_tilde.clone();
        let rep = core.continuation(&model, &mut q_cont, &tg).unwrap();
        // The pseudo time step really changed the path (more iterations than Newton's).
        assert!(rep.iterations > newton.iterations, "{rep:?} {newton:?}");
        assert_eq!(core.timings.continuations_converged, 1);
        // Same solution: both meet ‖R‖∞ ≤ ~1e-9 (1 N + Σm) on a Newton matrix ≥ M/dt²
        // (≥ 1e4 N/m per DOF here), so they agree far below a nanometre.
        let diff = q_newton
            .iter()
            .zip(&q_cont)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        assert!(diff < 1e-9, "continuation and Newton differ by {diff} m");
        // Its factors (of a shifted matrix) are not keyed on the step's (c_m, c_v).
        assert!(core.factored_for.0.is_nan());
    }

    #[test]
    fn a_first_step_line_searched_newton_fails_is_taken_by_the_retry_at_full_dt() {
        // From rest at dt = 1e-2 s, exact Newton with the line search creeps (‖R‖ stuck at
        // ~34 N after 25 iterations, measured); the retry's full-step stage converges.
        let (mut model, state) = kevlar();
        let dt = 1e-2;
        let mut plain = crate::ImplicitEuler::new(&model, NewtonOptions::default()).unwrap();
        assert!(
            plain.try_step(&model, &state, dt).is_err(),
            "line search converged"
        );
        let full = NewtonOptions {
            line_search: false,
            ..NewtonOptions::default()
        };
        let mut strict = crate::ImplicitEuler::new(&model, full).unwrap();
        let q_strict = strict.try_step(&model, &state, dt).unwrap().q().to_vec();
        let mut st =
            crate::ImplicitEuler::new(&model, NewtonOptions::recommended().strict()).unwrap();
        let mut s = state.clone();
        st.step(&mut model, &mut s, dt)
            .expect("taken at the full dt");
        let diff = q_strict
            .iter()
            .zip(&s.q)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        assert!(diff < 1e-9, "{diff} m");
    }
}

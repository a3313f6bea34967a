//! Step-size homotopy: the exact retry's last stage
//! ([`crate::NewtonOptions::step_homotopy`]), for a step whose solution Newton cannot reach
//! from the constant-velocity guess, however it is damped.
//!
//! The implicit-Euler equations of a step of size `s h` from the same state `(q_n, v_n)`,
//! `R_s(q) = M (q − q_n − s h v_n)/(s h)² − F(q, (q − q_n)/(s h)) = 0`, have the solution
//! `q = q_n` at `s = 0` and the step's solution at `s = 1`. Solving them for increasing `s`
//! (first `s = ½`, the step a halving would take, then larger `s`, each solve — exact Newton
//! with full steps — starting from the last solution advanced at `v_n`, the increment
//! doubled after a success and halved after a failure, at most 8 solves)
//! follows the branch of solutions that starts at the current state to
//! `s = 1`. Where that branch folds before `s = 1` (a snap-through within the step), there is
//! no implicit-Euler solution of the full step on it, and the stage fails: the caller then
//! halves the step, which is what the physics asks for. The result is judged on `R` itself
//! with the solve's own tolerance, so it is the implicit-Euler solution of the full step.

use super::{NewtonCore, Target};
use crate::error::StepError;
use crate::model::Model;
use crate::stepper::options::StepReport;

/// Smallest increment of `s` before the stage gives up (the branch folds, or Newton cannot
/// follow it).
const MIN_INCREMENT: f64 = 1.0 / 64.0;
/// Most sub-solves of one homotopy (each with the exact retry's budget of iterations): a
/// branch that cannot be followed is given up at a few times the cost of the retry's other
/// stages.
const MAX_SOLVES: usize = 8;

impl NewtonCore {
    /// Solve the step `tg` by continuation in the step size (module docs); `q` holds the
    /// solution on success.
    pub(super) fn step_homotopy(
        &mut self,
        model: &Model,
        q: &mut [f64],
        tg: &Target<'_>,
    ) -> Result<StepReport, StepError> {
        self.timings.homotopies += 1;
        let mut qt = std::mem::take(&mut self.homotopy_q_tilde);
        let mut done = std::mem::take(&mut self.homotopy_done);
        let res = self.follow(model, q, tg, &mut qt, &mut done);
        self.homotopy_q_tilde = qt;
        self.homotopy_done = done;
        if res.is_ok() {
            self.timings.homotopies_converged += 1;
        }
        res
    }

    /// The path from `s = 0` to `s = 1` (`qt`: the sub-step's `q̃`, `done`: the last
    /// solution).
    fn follow(
        &mut self,
        model: &Model,
        q: &mut [f64],
        tg: &Target<'_>,
        qt: &mut [f64],
        done: &mut [f64],
    ) -> Result<StepReport, StepError> {
        let h = 1.0 / tg.c_v;
        done.copy_from_slice(tg.q_n);
        let (mut s_done, mut ds) = (0.0f64, 0.5f64);
        let mut report = StepReport::default();
        let mut last: Option<Box<StepError>> = None;
        let mut solves = 0;
        for _ in 0..MAX_SOLVES {
            if s_done >= 1.0 || ds < MIN_INCREMENT {
                break;
            }
            let s = (s_done + ds).min(1.0);
            // Start: the last solution advanced at v_n over the added fraction of the step
            // (a secant through the last two solutions was tried: it jumped to another
            // solution of the step's equations on the test sheet).
            for (d, x) in qt.iter_mut().enumerate() {
                *x = tg.q_n[d] + s * (tg.q_tilde[d] - tg.q_n[d]);
                q[d] = done[d] + (s - s_done) * (tg.q_tilde[d] - tg.q_n[d]);
            }
            let sub = Target {
                c_m: tg.c_m / (s * s),
                c_v: tg.c_v / s,
                q_tilde: qt,
                q_n: tg.q_n,
                t: tg.t - (1.0 - s) * h,
            };
            // One stage per size (exact Newton with full steps, the symmetric approximation's
            // updates corrected by BiCGStab): close starts are what the homotopy provides.
            solves += 1;
            match self.solve_exact(model, q, &sub, false, false) {
                Ok(r) => {
                    last = None;
                    report.iterations += r.iterations;
                    report.factorizations += r.factorizations;
                    report.backtracks += r.backtracks;
                    report.residual = r.residual;
                    report.used_cholesky = r.used_cholesky;
                    done.copy_from_slice(q);
                    ds = 2.0 * (s - s_done);
                    s_done = s;
                }
                // Half the increment actually tried (it may have been cut at s = 1).
                Err(e) => {
                    last = Some(Box::new(e));
                    ds = 0.5 * (s - s_done);
                }
            }
        }
        if s_done >= 1.0 {
            Ok(report)
        } else {
            Err(StepError::Homotopy {
                reached: s_done,
                solves,
                last,
            })
        }
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

    /// Exact Newton with two iterations per stage (four in the retry) cannot take the
    /// first 1e-2 s step from rest; followed from half the step, each size's solve starts
    /// close enough to converge within that budget, and the step is taken whole, on the
    /// solution a strict Newton solve with a full budget finds.
    #[test]
    fn a_step_newton_cannot_reach_is_taken_whole_on_the_strict_solution() {
        let (model, state) = kevlar();
        let dt = 1e-2;
        let tight = |homotopy| NewtonOptions {
            max_iterations: 2,
            continuation: false,
            step_homotopy: homotopy,
            ..NewtonOptions::recommended().strict()
        };
        let mut without = crate::ImplicitEuler::new(&model, tight(false)).unwrap();
        assert!(
            without.try_step(&model, &state, dt).is_err(),
            "Newton alone converged"
        );
        let mut with = crate::ImplicitEuler::new(&model, tight(true)).unwrap();
        let q = with.try_step(&model, &state, dt).unwrap().q().to_vec();
        let t = with.timings();
        assert_eq!((t.homotopies, t.homotopies_converged), (1, 1), "{t:?}");
        let full = NewtonOptions {
            line_search: false,
            ..NewtonOptions::default()
        };
        let mut strict = crate::ImplicitEuler::new(&model, full).unwrap();
        let q_strict = strict.try_step(&model, &state, dt).unwrap().q().to_vec();
        // Both meet ‖R‖∞ ≤ ~1e-9 (1 N + Σm) on a Newton matrix ≥ M/dt² (≥ 1e4 N/m per DOF
        // here): they agree far below a nanometre.
        let diff = q
            .iter()
            .zip(&q_strict)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        assert!(diff < 1e-9, "homotopy and Newton differ by {diff} m");
    }

    /// With one iteration per sub-solve no size can be solved: the step fails as a
    /// homotopy that fell short, saying how far it got and why its last sub-solve failed
    /// (not as a non-finite value, which it is not), and pointing at that sub-solve's worst
    /// DOF.
    #[test]
    fn a_homotopy_that_falls_short_says_how_far_it_got_and_why() {
        let (model, state) = kevlar();
        let opts = NewtonOptions {
            max_iterations: 1,
            continuation: false,
            step_homotopy: true,
            ..NewtonOptions::recommended().strict()
        };
        let mut stepper = crate::ImplicitEuler::new(&model, opts).unwrap();
        let Err(err) = stepper.try_step(&model, &state, 1e-2) else {
            panic!("one iteration per sub-solve took the step");
        };
        let StepError::Homotopy {
            reached,
            solves,
            ref last,
        } = err
        else {
            panic!("not a homotopy failure: {err}");
        };
        assert!(reached < 1.0 && (1..=MAX_SOLVES).contains(&solves), "{err}");
        let last = last.as_deref().expect("the last sub-solve failed");
        assert!(
            matches!(
                last,
                StepError::NotConverged { .. } | StepError::Diverged { .. }
            ),
            "{last}"
        );
        assert_eq!(err.dof(), last.dof());
        let text = err.to_string();
        assert!(
            text.starts_with("step homotopy reached") && !text.contains("non-finite"),
            "{text}"
        );
    }
}

//! The homotopy stage: the step's solution followed in the step size, for a step whose
//! solution Newton cannot reach from the constant-velocity guess however it is damped.
//!
//! The implicit-Euler equations of a step of size `s h` from the same state `(q_n, v_n)`,
//! `R_s(q) = M (q − q_n − s h v_n)/(s h)² − F(q, (q − q_n)/(s h)) = 0`, have the solution
//! `q = q_n` at `s = 0` and the step's solution at `s = 1`. Solving them for increasing `s`
//! (first `s = ½`, the step a halving would take, then larger `s`, each solve — the Newton
//! stage — starting from the last solution advanced at `v_n`, the increment doubled after a
//! success and halved after a failure, at most [`MAX_SOLVES`] solves) follows the branch of
//! solutions that starts at the current state to `s = 1`. Where that branch folds before
//! `s = 1` (a snap-through within the step), there is no implicit-Euler solution of the full
//! step on it, and the stage fails: the controller then halves the step, which is what the
//! physics asks for. The result is judged on `R` itself with the same tolerance, so it is the
//! implicit-Euler solution of the full step.

use super::{newton, Ctx};
use crate::error::StepError;
use crate::stepper::options::{Stage, StepReport};
use crate::stepper::workspace::{Target, ITERATE_GAP};

/// Smallest increment of `s` before the stage gives up.
const MIN_INCREMENT: f64 = 1.0 / 64.0;
/// Most sub-solves of one homotopy (each with the Newton stage's budget).
pub(crate) const MAX_SOLVES: usize = 8;

/// Free buffers of the stage: the sub-step's `q̃` and the last solution (all DOFs).
pub(crate) struct HomotopyBuffers {
    q_tilde: Vec<f64>,
    done: Vec<f64>,
}

impl HomotopyBuffers {
    /// Buffers for `n` DOFs.
    pub fn new(n: usize) -> Self {
        Self {
            q_tilde: vec![0.0; n],
            done: vec![0.0; n],
        }
    }
}

/// Solve the step `tg` by continuation in the step size (module docs); `q` holds the
/// solution on success.
pub(crate) fn run(
    cx: &mut Ctx<'_>,
    tg: &Target<'_>,
    q: &mut [f64],
    budget: usize,
    buf: &mut HomotopyBuffers,
) -> Result<StepReport, StepError> {
    let HomotopyBuffers { q_tilde: qt, done } = buf;
    let h = 1.0 / tg.c_v;
    done.copy_from_slice(tg.q_n);
    let (mut s_done, mut ds) = (0.0f64, 0.5f64);
    let mut rep = StepReport {
        stage: Stage::Homotopy,
        ..StepReport::default()
    };
    let mut last: Option<Box<StepError>> = None;
    let mut solves = 0;
    while solves < MAX_SOLVES && s_done < 1.0 && ds >= MIN_INCREMENT {
        let s = (s_done + ds).min(1.0);
        // Start: the last solution advanced at v_n over the added fraction of the step (a
        // secant through the last two solutions jumped to another solution of the step's
        // equations on the test sheet).
        for (d, x) in qt.iter_mut().enumerate() {
            *x = tg.q_n[d] + s * (tg.q_tilde[d] - tg.q_n[d]);
            q[d] = done[d] + (s - s_done) * (tg.q_tilde[d] - tg.q_n[d]);
        }
        cx.ws.bound_move(cx.model, done, q, ITERATE_GAP);
        let sub = Target {
            c_m: tg.c_m / (s * s),
            c_v: tg.c_v / s,
            q_tilde: qt,
            q_n: tg.q_n,
            t: tg.t - (1.0 - s) * h,
        };
        solves += 1;
        match newton::run(cx, &sub, q, budget) {
            Ok(r) => {
                last = None;
                rep.iterations += r.iterations;
                rep.factorizations += r.factorizations;
                rep.backtracks += r.backtracks;
                rep.residual = r.residual;
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
        Ok(rep)
    } else {
        Err(StepError::Homotopy {
            reached: s_done,
            solves,
            last,
        })
    }
}

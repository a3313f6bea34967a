//! When an iterate solves its step: the force tolerance, the accuracy-based test against
//! backward Euler's local error, the round-off floor of the residual, and when a stage has
//! failed (non-finite, diverged, budget spent).
//!
//! **Force tolerance.** `‖R‖∞ ≤ tol_abs + tol_rel ‖R₀‖∞` (`R₀` the residual at the stage's
//! first iterate).
//!
//! **Accuracy test** ([`NewtonOptions::accuracy_fraction`]). For every free DOF
//! `|R_i| / m_i ≤ max(η c_m e, ε a_ref)`, `e = ½ ‖q − q̃‖∞`: the residual left moves the state
//! by at most a fraction `η` of the step's own local error (docs/engine.md §Newton tolerance).
//!
//! **Round-off floor.** A coordinate is stored to `ε |q_j|`: an update smaller than that is
//! lost when it is added, so Newton cannot bring `R_i` below about
//! `ε (c_m m_i |q_i| + Σ_j |∂F_i/∂q_j + c_v ∂F_i/∂v_j| |q_j|)`. For a stiff canopy far from the
//! origin this exceeds any fixed tolerance: the report's Kevlar sheet 90 m below its release
//! has `ε |z| k ≈ 4e-6 N` (k ≈ 2e8 N/m), where Newton stalls for good (docs/performance.md).
//! Every residual within `16 ×` its floor therefore counts as converged (the force part from
//! the last assembled Jacobian; before the first one, the inertia alone). Rows whose
//! coordinates are all near zero have a floor near zero. The estimate is a linearisation: on
//! the main job 90 % of the rows' actual round-off is below it, but a few rows' is up to 100×
//! above it (products of large terms that nearly cancel). So where an iteration stalls, the
//! stage measures the actual round-off once (`Workspace::measure_noise`: one residual at the
//! iterate moved by one unit in the last place) and `4 ×` that counts as zero too.

use super::workspace::{Target, Workspace};
use crate::error::StepError;
use crate::stepper::options::NewtonOptions;

/// Multiple of the estimated round-off of a residual that counts as zero.
const ROUNDOFF_MARGIN: f64 = 16.0;
/// Multiple of the measured round-off (`Workspace::noise`) that counts as zero.
const NOISE_MARGIN: f64 = 4.0;

/// What the tests say of an iterate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Verdict {
    /// Converged: the stage ends here.
    Converged,
    /// Not yet; `‖R‖∞` of the iterate.
    Continue(f64),
}

/// A stalled update (below the step tolerance) ends a solve whose residual is within this
/// factor of the tolerance: the residual is then at the round-off of the forces.
pub(crate) const STALL_FACTOR: f64 = 1e3;

/// The tolerances of one model's solves.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Convergence {
    tol_abs: f64,
    tol_rel: f64,
    eta: f64,
    floor: f64,
    divergence_limit: f64,
    step_tol: f64,
}

/// The tolerance of one stage, fixed at its first iterate.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Tolerance {
    /// `‖R₀‖∞` (N).
    pub r0: f64,
    /// `tol_abs + tol_rel ‖R₀‖∞` (N).
    pub tol: f64,
    /// `16 ε`: times the row's `c_m m_i |q_i| + Σ_j |∂F_i/∂q_j| |q_j|`, its round-off floor.
    roundoff: f64,
}

impl Convergence {
    /// The tolerances of `opts` for a model of total mass `mass` (kg).
    pub fn new(opts: &NewtonOptions, mass: f64) -> Self {
        let a_ref = opts.reference_acceleration;
        Self {
            tol_abs: opts.force_tolerance(mass),
            tol_rel: opts.force_tol_rel,
            eta: opts.accuracy_fraction,
            floor: opts.accuracy_floor * a_ref,
            divergence_limit: opts.divergence_limit,
            step_tol: opts.step_tol,
        }
    }

    /// The tolerance of a stage whose first iterate's residual is in `ws`.
    pub fn start(&self, ws: &Workspace) -> Tolerance {
        let (r0, _) = ws.inf_norm();
        Tolerance {
            r0,
            tol: self.tol_abs + self.tol_rel * r0,
            roundoff: ROUNDOFF_MARGIN * f64::EPSILON,
        }
    }

    /// Whether an update of `‖Δq‖∞ = step` (already taken) ends the solve: it is below the
    /// step tolerance while the residual `rinf` is within 1e3 of the tolerance (a stalled
    /// iteration is not taken for convergence).
    pub fn stalled_at_tolerance(&self, step: f64, rinf: f64, tol: &Tolerance) -> bool {
        step <= self.step_tol && rinf <= STALL_FACTOR * tol.tol
    }

    /// The verdict on iterate `q` (its residual in `ws`) of a stage that has taken
    /// `iterations` of its `budget`.
    pub fn judge(
        &self,
        ws: &mut Workspace,
        q: &[f64],
        tg: &Target<'_>,
        tol: &Tolerance,
        iterations: usize,
        budget: usize,
    ) -> Result<Verdict, StepError> {
        let (rinf, worst) = ws.inf_norm();
        if !rinf.is_finite() {
            return Err(StepError::NonFinite {
                what: "residual",
                dof: worst,
            });
        }
        if rinf <= tol.tol {
            return Ok(Verdict::Converged);
        }
        if self.accurate(ws, q, tg) {
            ws.counters.accuracy_accepts += 1;
            return Ok(Verdict::Converged);
        }
        if self.within_roundoff(ws, q, tg, tol) {
            ws.counters.roundoff_accepts += 1;
            return Ok(Verdict::Converged);
        }
        if rinf > self.divergence_limit * tol.r0.max(tol.tol) {
            return Err(StepError::Diverged {
                iterations,
                residual: rinf,
                initial: tol.r0,
                limit: self.divergence_limit,
                worst_dof: worst,
            });
        }
        if iterations >= budget {
            return Err(StepError::NotConverged {
                iterations,
                residual: rinf,
                tolerance: tol.tol,
                worst_dof: worst,
            });
        }
        Ok(Verdict::Continue(rinf))
    }

    /// The accuracy-based test (module docs) at `q`.
    fn accurate(&self, ws: &Workspace, q: &[f64], tg: &Target<'_>) -> bool {
        if self.eta <= 0.0 || tg.c_m <= 0.0 {
            return false;
        }
        let dofs = &ws.asm.dof_of;
        let e = 0.5
            * dofs
                .iter()
                .map(|&d| (q[d] - tg.q_tilde[d]).abs())
                .fold(0.0, f64::max);
        let bound = (self.eta * tg.c_m * e).max(self.floor);
        ws.residual
            .iter()
            .zip(&ws.mass)
            .all(|(r, m)| r.abs() <= bound * m)
    }

    /// Every `|R_i|` within the tolerance plus its round-off floor (module docs).
    fn within_roundoff(&self, ws: &Workspace, q: &[f64], tg: &Target<'_>, tol: &Tolerance) -> bool {
        ws.asm.dof_of.iter().enumerate().all(|(r, &d)| {
            let change = tg.c_m * ws.mass[r] * q[d].abs() + ws.force_roundoff[r];
            let floor = (tol.roundoff * change).max(NOISE_MARGIN * ws.noise[r]);
            ws.residual[r].abs() <= tol.tol + floor
        })
    }
}

//! Implicit (backward) Euler: `M (q_{n+1} − q_n − h v_n)/h² = F(q_{n+1}, v_{n+1})`,
//! `v_{n+1} = (q_{n+1} − q_n)/h`, solved for `q_{n+1}` by the ladder of
//! `stepper/controller.rs`.
//!
//! Backward Euler is first-order accurate and unconditionally stable; an undamped oscillator
//! of angular frequency ω loses amplitude by the factor `1/√(1 + (ω h)²)` per step, which is
//! the numerical damping users see at large `h` (tested exactly).

use super::options::StepReport;
use crate::model::{Model, State};

/// A solved but not yet committed backward-Euler step (from
/// [`crate::ImplicitEuler::try_step`]): `q_{n+1}`, `v_{n+1}` and the step size, held in the
/// stepper's buffers. The state it was solved from and the forces' history are untouched
/// until [`Trial::commit`]; dropping the trial discards the step (e.g. when its local error
/// is too large), with nothing to undo.
pub struct Trial<'a> {
    pub(super) q: &'a [f64],
    pub(super) v: &'a [f64],
    pub(super) e: &'a [f64],
    pub(super) filtered: bool,
    pub(super) dt: f64,
    pub(super) report: StepReport,
}

impl Trial<'_> {
    /// `q_{n+1}` (m, rad).
    pub fn q(&self) -> &[f64] {
        self.q
    }

    /// `v_{n+1} = (q_{n+1} − q_n)/dt` (m/s, rad/s; zero on fixed DOFs).
    pub fn v(&self) -> &[f64] {
        self.v
    }

    /// The local error estimate of the step (every DOF, m or rad; zero on fixed DOFs):
    /// `(h/2)(v_{n+1} − v_n)`, filtered through the step's Newton matrix when the filter is
    /// on and the step held its factors ([`super::error_control`] module docs).
    pub fn local_error(&self) -> &[f64] {
        self.e
    }

    /// Whether [`Trial::local_error`] is the filtered estimate.
    pub fn error_filtered(&self) -> bool {
        self.filtered
    }

    /// The step size (s).
    pub fn dt(&self) -> f64 {
        self.dt
    }

    /// What the solve did.
    pub fn report(&self) -> StepReport {
        self.report
    }

    /// Accept the step: `state ← (q_{n+1}, v_{n+1}, t + dt)` and every force commits its
    /// history (DER reference frames) at `q_{n+1}`. `state` and `model` must be the ones the
    /// trial was solved from.
    pub fn commit(self, model: &mut Model, state: &mut State) {
        state.q.copy_from_slice(self.q);
        state.v.copy_from_slice(self.v);
        state.t += self.dt;
        for f in model.forces.iter_mut() {
            f.commit(&state.q, &state.v);
        }
    }
}

/// `v_{n+1} = (q_{n+1} − q_n)/h` on the free DOFs, zero on fixed ones.
pub(super) fn velocities(model: &Model, q_n: &[f64], q_new: &[f64], h: f64, v: &mut [f64]) {
    for d in 0..v.len() {
        v[d] = if model.fixed[d] {
            0.0
        } else {
            (q_new[d] - q_n[d]) / h
        };
    }
}

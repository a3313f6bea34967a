//! The first Newton iterate of an implicit-Euler step ([`Predictor`]): the constant-velocity
//! guess `q̃ = q_n + dt v_n`, corrected by extrapolating the mean accelerations of the last
//! committed steps (`a_n = (v_n − v_{n−1}) / h₁`, `a_{n−1} = (v_{n−1} − v_{n−2}) / h₂`).
//!
//! Backward Euler's `(v_{n+1} − v_n) / dt` is the mean acceleration over the new step, i.e.
//! the acceleration near its middle `t_n + dt/2`. Constant acceleration takes `a_n` for it;
//! constant jerk extrapolates the line through `a_{n−1}` (at `t_{n−1} − h₂/2`) and `a_n` (at
//! `t_n − h₁/2`) to the middle of the new step. The guess never changes the converged step
//! (the residual test decides), only the Newton iterations spent on it.

use super::options::Predictor;
use crate::model::{Model, State};

/// The extrapolation order of a guess.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Order {
    Velocity,
    Acceleration,
    Jerk,
}

/// `(c_a, c_1, c_2)` with `dt² a_n = c_a (v_n − v_{n−1})` and the constant-jerk correction
/// `dt² (a_pred − a_n) = c_1 (v_n − v_{n−1}) − c_2 (v_{n−1} − v_{n−2})`, where
/// `a_pred = a_n + (a_n − a_{n−1}) (dt + h₁) / (h₁ + h₂)` (zeros where the history is missing).
pub(super) fn coefficients(dt: f64, h1: Option<f64>, h2: Option<f64>) -> (f64, f64, f64) {
    match (h1, h2) {
        (Some(h1), Some(h2)) => {
            let c = dt * dt * (dt + h1) / (h1 + h2);
            (dt * dt / h1, c / h1, c / h2)
        }
        (Some(h1), None) => (dt * dt / h1, 0.0, 0.0),
        _ => (0.0, 0.0, 0.0),
    }
}

/// The velocities of the last committed steps and the current step's guess corrections.
pub(super) struct PredictorState {
    /// `v_{n−1}` and `v_{n−2}` of the committed steps.
    v1: Vec<f64>,
    v2: Vec<f64>,
    /// `h₁ = dt_{n−1}`, `h₂ = dt_{n−2}`; `None` on the first steps and after a sync point.
    h1: Option<f64>,
    h2: Option<f64>,
    /// The start velocity `v_n` of the last trial (it becomes `v1` if that trial is committed).
    v_start: Vec<f64>,
    /// The last trial: its end time, `dt` and the adaptive choice for the step after it. A
    /// trial is known to be committed when the next one starts at its end time.
    pending: Option<(f64, f64, Order)>,
    /// `dt² a_n` of the current step.
    accel: Vec<f64>,
    /// `dt² (a_pred − a_n)` of the current step (on top of `accel`).
    jerk: Vec<f64>,
    /// [`Predictor::Adaptive`]: the order of the guess to use (see [`PredictorState::judge`]).
    order: Order,
}

impl PredictorState {
    pub fn new(n: usize) -> Self {
        Self {
            v1: vec![0.0; n],
            v2: vec![0.0; n],
            h1: None,
            h2: None,
            v_start: vec![0.0; n],
            pending: None,
            accel: vec![0.0; n],
            jerk: vec![0.0; n],
            order: Order::Jerk,
        }
    }

    /// Forget the history (a sync point): the next step uses constant velocity, the one after
    /// it constant acceleration at most, and constant jerk only once two steps are committed.
    pub fn reset(&mut self) {
        self.h1 = None;
        self.h2 = None;
        self.pending = None;
        self.order = Order::Jerk;
    }

    /// Take over the last trial's velocity if it was committed (the state now starts at its
    /// end time); a rejected trial leaves the history as it was.
    fn settle(&mut self, state: &State) {
        if let Some((t_end, dt, order)) = self.pending.take() {
            if t_end == state.t {
                // v₂ ← v₁ ← v_start (the old v₂ buffer is reused for the next v_start).
                std::mem::swap(&mut self.v2, &mut self.v1);
                std::mem::swap(&mut self.v1, &mut self.v_start);
                self.h2 = self.h1;
                self.h1 = Some(dt);
                self.order = order;
            }
        }
    }

    /// `q̃ = q_n + dt v_n` into `q_tilde` and the guess of `predictor` into `q_guess`.
    pub fn guess(
        &mut self,
        predictor: Predictor,
        model: &Model,
        state: &State,
        dt: f64,
        q_tilde: &mut [f64],
        q_guess: &mut [f64],
    ) {
        self.settle(state);
        let (ca, c1, c2) = coefficients(dt, self.h1, self.h2);
        let order = match predictor {
            Predictor::ConstantVelocity => Order::Velocity,
            Predictor::ConstantAcceleration => Order::Acceleration,
            Predictor::ConstantJerk => Order::Jerk,
            Predictor::Adaptive => self.order,
        };
        let (wa, wj) = match order {
            Order::Velocity => (0.0, 0.0),
            Order::Acceleration => (1.0, 0.0),
            Order::Jerk => (1.0, 1.0),
        };
        for d in 0..q_tilde.len() {
            let v = if model.fixed[d] { 0.0 } else { state.v[d] };
            self.v_start[d] = v;
            q_tilde[d] = state.q[d] + dt * v;
            let (dv1, dv2) = (v - self.v1[d], self.v1[d] - self.v2[d]);
            self.accel[d] = ca * dv1;
            self.jerk[d] = c1 * dv1 - c2 * dv2;
            q_guess[d] = q_tilde[d] + wa * self.accel[d] + wj * self.jerk[d];
        }
    }

    /// After the step from `t` of size `dt` converged to `q_new`: remember it (committed or
    /// not is known at the next [`PredictorState::guess`]) with the adaptive choice for the
    /// next step — the highest order whose guess was at least 2× closer (‖·‖∞) to `q_new`
    /// than the order below it, each order judged only while the one below won (measured at
    /// no cost; the 2× margin keeps extrapolation off where it only sometimes helps).
    pub fn judge(&mut self, predictor: Predictor, q_new: &[f64], q_tilde: &[f64], t: f64, dt: f64) {
        let mut next = self.order;
        if predictor == Predictor::Adaptive && self.h1.is_some() {
            let (mut e_v, mut e_a, mut e_j) = (0.0f64, 0.0f64, 0.0f64);
            for d in 0..q_new.len() {
                let r = q_new[d] - q_tilde[d];
                e_v = e_v.max(r.abs());
                e_a = e_a.max((r - self.accel[d]).abs());
                e_j = e_j.max((r - self.accel[d] - self.jerk[d]).abs());
            }
            next = if e_a >= 0.5 * e_v {
                Order::Velocity
            } else if self.h2.is_some() && e_j < 0.5 * e_a {
                Order::Jerk
            } else {
                Order::Acceleration
            };
        }
        self.pending = Some((t + dt, dt, next));
    }
}

#[cfg(test)]
mod tests {
    use super::coefficients;
    use rand::{rngs::StdRng, Rng, SeedableRng};

    /// The guesses are exact for the motions they assume, on uneven steps: constant
    /// acceleration for `v = α t`, constant jerk for `v = α t + β t²` (whose mean
    /// accelerations over any interval are `α + 2β` × its midpoint).
    #[test]
    fn extrapolation_is_exact_for_its_motion() {
        let mut rng = StdRng::seed_from_u64(7);
        for _ in 0..100 {
            let (a, b): (f64, f64) = (rng.random_range(-5.0..5.0), rng.random_range(-5.0..5.0));
            let (h2, h1, dt): (f64, f64, f64) = (
                rng.random_range(1e-4..1e-2),
                rng.random_range(1e-4..1e-2),
                rng.random_range(1e-4..1e-2),
            );
            let tn = rng.random_range(0.0..1.0);
            let vel = |t: f64, b: f64| a * t + b * t * t;
            let (ca, c1, c2) = coefficients(dt, Some(h1), Some(h2));
            for (b, jerk) in [(0.0, false), (b, true)] {
                let (v2, v1, v0) = (vel(tn - h1 - h2, b), vel(tn - h1, b), vel(tn, b));
                let mut dq = ca * (v0 - v1);
                if jerk {
                    dq += c1 * (v0 - v1) - c2 * (v1 - v2);
                }
                // Backward Euler's q_{n+1} − q̃ = dt (v_{n+1} − v_n) for the exact v_{n+1}.
                let exact = dt * (vel(tn + dt, b) - v0);
                let scale = dt * (a.abs() + 4.0 * b.abs()) * dt;
                assert!(
                    (dq - exact).abs() <= 1e-12 * scale,
                    "jerk {jerk}: guess {dq:e} against {exact:e}"
                );
            }
        }
    }

    /// Without history the guess is constant velocity; with one step, constant acceleration.
    #[test]
    fn missing_history_drops_the_orders_it_needs() {
        assert_eq!(coefficients(1e-3, None, None), (0.0, 0.0, 0.0));
        let (ca, c1, c2) = coefficients(1e-3, Some(2e-3), None);
        assert_eq!((c1, c2), (0.0, 0.0));
        assert!((ca - 0.5e-3).abs() < 1e-18);
    }
}

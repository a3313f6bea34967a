//! Local-error control for backward Euler: the error estimate of one step and the
//! elementary step-size controller that turns it into the next step size.
//!
//! **Estimate.** A backward-Euler step of size `h` from `(q_n, v_n)` gives `(q_{n+1}, v_{n+1})`
//! with the position update `q_{n+1} = q_n + h v_{n+1}`. The trapezoidal rule, second order,
//! would give `q_n + h (v_n + v_{n+1})/2` from the same velocities. The two differ by
//!
//! ```text
//!     e = (h/2) (v_{n+1} − v_n)   (m),
//! ```
//!
//! which is `h²/2 · a + O(h³)` (`a` the acceleration over the step): the leading term of
//! backward Euler's local position error.
//!
//! **Filter.** A stiff mode (ω h ≫ 1, e.g. a membrane's in-plane vibration) that backward
//! Euler damps anyway carries a large `e` that says nothing about the accuracy of the motion
//! that matters. As in RADAU5 (Hairer & Wanner, *Solving ODEs II*, §IV.8) the estimate is
//! filtered through the step's own Newton matrix `J = M/h² + K + D/h` (K = −∂F/∂q,
//! D = −∂F/∂v), whose factors the step holds:
//!
//! ```text
//!     ê = J⁻¹ (M/h²) e = (M + h D + h² K)⁻¹ M e,
//! ```
//!
//! so a mode of frequency ω is scaled by `1/(1 + ω²h²)`: smooth modes (ω h ≪ 1, rigid motion
//! under gravity) pass unchanged, stiff ones are divided by ≈ (ω h)². It costs one pair of
//! triangular solves. When the step holds no factors for its own `h` (it converged at the
//! predictor, e.g. right after a sync point with a changed `h`) the raw `e` is used
//! ([`crate::Counters::error_filter_fallbacks`] counts it).
//!
//! **Norm.** Over the nodes `i` with free translational DOFs, relative to the user's
//! tolerance `tol` (m per step), by default the mass-weighted RMS
//!
//! ```text
//!     err = √(Σ_i m_i |ê_i|² / Σ_i m_i) / tol      (ErrorNorm::MassRms),
//! ```
//!
//! the error of the body's motion as a whole (a light node, e.g. a canopy corner, counts by
//! its mass, not as the worst node), or the worst component
//! `err = max_i |ê_i| / tol` ([`ErrorNorm::Max`]), so that `err ≤ 1` means no node moved
//! more than `tol` from where a second-order step would have put it. Fixed DOFs are skipped
//! (they do not move). The rod twist angles (rad) are not
//! controlled: they are slaved to the node positions (quasi-static material frames, their
//! inertia is tiny), and an angle has no common scale with a position tolerance in metres.
//! Velocities are not controlled separately: their local error `h²/2 · ȧ` follows the same
//! step size.
//!
//! **Controller.** Backward Euler is order 1, so its local error is `O(h²)`: `err ∝ h²`, and
//! the step that would just meet the tolerance is `h · err^(−1/2)`. The elementary controller
//! (Hairer, Nørsett & Wanner, *Solving ODEs I*, §II.4) proposes
//!
//! ```text
//!     h_new = h · clamp(safety · err^(−1/2), 0.2, 2.0),   safety = 0.9,
//! ```
//!
//! clamped to `[h_min, h_max]`. A step with `err > 1` is rejected and retried with `h_new`
//! (which is then `< 0.9 h`) unless `h` is already `h_min`; otherwise it is accepted and
//! `h_new` is the next step. The factor limits keep one odd estimate from changing `h` by
//! more than 5× down or 2× up.
//!
//! Global error: with `err ≈ 1` every step, `h ≈ √(2 tol / |a|)`, and backward Euler's global
//! error is `O(h) ∝ √tol` — a 4× tighter tolerance halves it (tested against the tanh fall
//! in `tests/solver/error_control.rs`).

use crate::error::{EngineError, InvalidModel};
use crate::model::Model;

/// Safety factor on the proposed step: aim at `err ≈ 0.81`, not 1, so that the next step is
/// rarely rejected.
pub const SAFETY: f64 = 0.9;
/// Largest growth of `h` from one step to the next.
pub const MAX_GROWTH: f64 = 2.0;
/// Largest reduction of `h` from one step (or rejected attempt) to the next.
pub const MAX_SHRINK: f64 = 0.2;

/// The norm of the local error estimate (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ErrorNorm {
    /// `√(Σ m_i |e_i|² / Σ m_i)` over the nodes with free translational DOFs.
    #[default]
    MassRms,
    /// `max |e_d|` over the free translational DOFs.
    Max,
}

/// The raw estimate `e = (h/2)(v_{n+1} − v_n)` into `out` (every DOF, m or rad; zero on fixed
/// DOFs). `h` in s, velocities in m/s (rad/s).
pub fn raw_estimate(model: &Model, v_n: &[f64], v_new: &[f64], h: f64, out: &mut [f64]) {
    for (d, e) in out.iter_mut().enumerate() {
        *e = if model.fixed[d] {
            0.0
        } else {
            0.5 * h * (v_new[d] - v_n[d])
        };
    }
}

/// `err` of the estimate `e` (m per DOF, every DOF of `model`) against `tol_m` (m) in the
/// given norm, over the free translational DOFs (the first `3 n_nodes`; twist angles and
/// fixed DOFs are skipped). Dimensionless; a non-finite estimate gives `+∞` (the step must
/// be rejected). A model with no free node gives 0.
pub fn error_norm(model: &Model, e: &[f64], tol_m: f64, norm: ErrorNorm) -> f64 {
    let (mut worst, mut num, mut den) = (0.0f64, 0.0, 0.0);
    for node in 0..model.layout.n_nodes {
        let (mut e2, mut m, mut free) = (0.0, 0.0f64, false);
        for d in 3 * node..3 * node + 3 {
            if model.fixed[d] {
                continue;
            }
            if !e[d].is_finite() {
                return f64::INFINITY;
            }
            free = true;
            worst = worst.max(e[d].abs());
            e2 += e[d] * e[d];
            m = m.max(model.mass[d]);
        }
        if free {
            num += m * e2;
            den += m;
        }
    }
    match norm {
        ErrorNorm::Max => worst / tol_m,
        ErrorNorm::MassRms if den > 0.0 => (num / den).sqrt() / tol_m,
        ErrorNorm::MassRms => 0.0,
    }
}

/// `err = max_i |(h/2)(v_{n+1,i} − v_{n,i})| / tol_m`: the raw estimate in the max norm
/// ([`error_norm`] with [`ErrorNorm::Max`]), without a buffer. A non-finite velocity gives
/// `+∞`.
pub fn local_error_norm(model: &Model, v_n: &[f64], v_new: &[f64], h: f64, tol_m: f64) -> f64 {
    let n_pos = 3 * model.layout.n_nodes;
    let mut worst: f64 = 0.0;
    for d in 0..n_pos {
        if model.fixed[d] {
            continue;
        }
        let e = (0.5 * h * (v_new[d] - v_n[d])).abs();
        if !e.is_finite() {
            return f64::INFINITY;
        }
        worst = worst.max(e);
    }
    worst / tol_m
}

/// What the controller decided about a step whose error norm it was given.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Decision {
    /// Keep the step; try `next_h` (s) next.
    Accept {
        /// Proposed size of the next step (s).
        next_h: f64,
    },
    /// Discard the step and retry from the same state with `retry_h` (s) `< h`.
    Reject {
        /// Size of the retry (s).
        retry_h: f64,
    },
}

/// The elementary step-size controller for backward Euler (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ErrorController {
    /// Tolerance on the local position error per step, `tol` (m).
    pub tol_m: f64,
    /// Smallest step (s): a step this small is accepted whatever its error.
    pub h_min: f64,
    /// Largest step (s).
    pub h_max: f64,
    /// Safety factor (< 1) on the proposal.
    pub safety: f64,
    /// Norm of the local error estimate ([`ErrorNorm::MassRms`] unless set).
    pub norm: ErrorNorm,
}

impl ErrorController {
    /// A controller with the default [`SAFETY`]. Errors unless `0 < h_min ≤ h_max` and
    /// `tol_m > 0`, all finite.
    pub fn new(tol_m: f64, h_min: f64, h_max: f64) -> Result<Self, EngineError> {
        let ok = |x: f64| x.is_finite() && x > 0.0;
        if !(ok(tol_m) && ok(h_min) && ok(h_max) && h_min <= h_max) {
            return Err(InvalidModel::ErrorController {
                tol_m,
                h_min,
                h_max,
            }
            .into());
        }
        Ok(Self {
            tol_m,
            h_min,
            h_max,
            safety: SAFETY,
            norm: ErrorNorm::default(),
        })
    }

    /// The decision for a step of size `h` (s) with error norm `err` (see the module docs).
    pub fn propose(&self, h: f64, err: f64) -> Decision {
        self.propose_limited(h, err, h)
    }

    /// [`ErrorController::propose`] for a step that was shortened from the planned size
    /// `h_planned` (e.g. to land on an output time): the growth limit then applies to
    /// `max(h, h_planned)`, so a short step does not shrink the step size that follows it
    /// (its small error would otherwise only allow `2 h`).
    pub fn propose_limited(&self, h: f64, err: f64, h_planned: f64) -> Decision {
        // A NaN estimate (a non-finite velocity) must reject, like an infinite one.
        let err = if err.is_nan() { f64::INFINITY } else { err };
        // err^(−1/2) with err = 0 (no acceleration at all) is +∞: growth is limited below.
        let factor = self.safety / err.sqrt();
        if err > 1.0 && h > self.h_min {
            let retry_h = h * factor.clamp(MAX_SHRINK, self.safety);
            return Decision::Reject {
                retry_h: retry_h.clamp(self.h_min, self.h_max),
            };
        }
        let grown = (h * factor).min(MAX_GROWTH * h.max(h_planned));
        let next_h = grown.max(MAX_SHRINK * h);
        Decision::Accept {
            next_h: next_h.clamp(self.h_min, self.h_max),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ctrl() -> ErrorController {
        ErrorController::new(1e-5, 1e-6, 1e-1).unwrap()
    }

    #[test]
    fn accepts_at_or_below_tolerance_with_the_elementary_proposal() {
        let c = ctrl();
        // err = 0.81: the proposal 0.9/√0.81 = 1 keeps h.
        assert_eq!(c.propose(1e-3, 0.81), Decision::Accept { next_h: 1e-3 });
        // err = 1 is still accepted; the next step shrinks by the safety factor.
        match c.propose(1e-3, 1.0) {
            Decision::Accept { next_h } => assert!((next_h - 0.9e-3).abs() < 1e-18),
            d => panic!("{d:?}"),
        }
        // err = 0.25: 0.9/0.5 = 1.8 ×.
        match c.propose(1e-3, 0.25) {
            Decision::Accept { next_h } => assert!((next_h - 1.8e-3).abs() < 1e-15),
            d => panic!("{d:?}"),
        }
    }

    #[test]
    fn rejects_above_tolerance_with_a_smaller_retry() {
        let c = ctrl();
        // err = 4: 0.9/2 = 0.45 ×.
        match c.propose(1e-3, 4.0) {
            Decision::Reject { retry_h } => assert!((retry_h - 0.45e-3).abs() < 1e-15),
            d => panic!("{d:?}"),
        }
        // Just above 1: the retry is still at most 0.9 h, so retries always shrink.
        match c.propose(1e-3, 1.0 + 1e-12) {
            Decision::Reject { retry_h } => assert!(retry_h <= 0.9e-3),
            d => panic!("{d:?}"),
        }
        // A huge error (or NaN, or ∞) shrinks by at most 5×.
        for err in [1e6, f64::INFINITY, f64::NAN] {
            assert_eq!(
                c.propose(1e-3, err),
                Decision::Reject { retry_h: 0.2e-3 },
                "{err}"
            );
        }
    }

    #[test]
    fn growth_is_limited_to_2x_and_clamped_to_h_max() {
        let c = ctrl();
        for err in [0.0, 1e-12, 0.01] {
            assert_eq!(c.propose(1e-3, err), Decision::Accept { next_h: 2e-3 });
        }
        assert_eq!(c.propose(0.08, 0.0), Decision::Accept { next_h: 0.1 });
        assert_eq!(c.propose(0.1, 0.0), Decision::Accept { next_h: 0.1 });
    }

    #[test]
    fn h_min_is_a_floor_and_a_step_there_is_accepted() {
        let c = ctrl();
        // A retry never goes below h_min ...
        assert_eq!(c.propose(2e-6, 100.0), Decision::Reject { retry_h: 1e-6 });
        // ... and at h_min the step is accepted whatever the error (the caller may warn).
        assert_eq!(c.propose(1e-6, 100.0), Decision::Accept { next_h: 1e-6 });
    }

    #[test]
    fn a_shortened_step_grows_from_the_planned_size() {
        let c = ctrl();
        // A 1e-5 s step cut short of a planned 1e-3 s with a tiny error: the next step may
        // return to (up to 2 ×) the planned size, not only 2 × 1e-5.
        assert_eq!(
            c.propose_limited(1e-5, 1e-10, 1e-3),
            Decision::Accept { next_h: 2e-3 }
        );
        // With a real error the estimate itself decides: err = 0.0081 at 1e-5 s means
        // 0.9/0.09 = 10 × → 1e-4 s, below the planned size.
        match c.propose_limited(1e-5, 0.0081, 1e-3) {
            Decision::Accept { next_h } => assert!((next_h - 1e-4).abs() < 1e-15),
            d => panic!("{d:?}"),
        }
        // Rejection is judged on the step actually taken.
        assert!(matches!(
            c.propose_limited(1e-5, 4.0, 1e-3),
            Decision::Reject { .. }
        ));
    }

    #[test]
    fn invalid_settings_are_errors() {
        for (tol, lo, hi) in [
            (0.0, 1e-6, 1e-3),
            (1e-5, 0.0, 1e-3),
            (1e-5, 1e-3, 1e-6),
            (f64::NAN, 1e-6, 1e-3),
            (1e-5, 1e-6, f64::INFINITY),
        ] {
            assert!(
                ErrorController::new(tol, lo, hi).is_err(),
                "{tol} {lo} {hi}"
            );
        }
    }

    #[test]
    fn error_norm_uses_free_positions_only() {
        use crate::DofLayout;
        // Two nodes and one twist; node 0 fixed.
        let mut m = Model::new(DofLayout::new(2, 1));
        m.fix_node(0);
        let v_n = [0.0; 7];
        // Fixed node and twist DOF have huge changes; node 1 z changes by 2 m/s.
        let v_new = [9.0, 9.0, 9.0, 0.0, 0.0, -2.0, 1e9];
        let err = local_error_norm(&m, &v_n, &v_new, 1e-2, 1e-5);
        // (h/2)·2 = 1e-2 m against 1e-5 m.
        assert!((err - 1e3).abs() < 1e-9, "{err}");
        let bad = [0.0, 0.0, 0.0, f64::NAN, 0.0, 0.0, 0.0];
        assert_eq!(local_error_norm(&m, &v_n, &bad, 1e-2, 1e-5), f64::INFINITY);
    }

    #[test]
    fn mass_rms_norm_weights_nodes_by_mass() {
        use crate::DofLayout;
        // Three nodes (0.5 kg, 1.5 kg, fixed) and a twist; only the light node has an error.
        let mut m = Model::new(DofLayout::new(3, 1));
        m.add_node_mass(0, 0.5);
        m.add_node_mass(1, 1.5);
        m.add_node_mass(2, 1.0);
        m.fix_node(2);
        let mut e = [0.0; 10];
        e[0] = 3e-5;
        e[2] = -4e-5; // |e_0| = 5e-5 m
        e[6] = 1.0; // fixed node: skipped
        e[9] = 1e3; // twist: skipped
        let tol = 1e-5;
        // √(0.5 · 25e-10 / 2) = 2.5e-5 m → 2.5; the worst component 4e-5 m → 4.
        let rms = error_norm(&m, &e, tol, ErrorNorm::MassRms);
        assert!((rms - 2.5).abs() < 1e-12, "{rms}");
        assert!((error_norm(&m, &e, tol, ErrorNorm::Max) - 4.0).abs() < 1e-12);
        // The same error on the heavy node instead weighs 3× more: √3 × 2.5.
        e.swap(0, 3);
        e.swap(2, 5);
        let heavy = error_norm(&m, &e, tol, ErrorNorm::MassRms);
        assert!((heavy - 2.5 * 3f64.sqrt()).abs() < 1e-12, "{heavy}");
        e[4] = f64::NAN;
        assert_eq!(error_norm(&m, &e, tol, ErrorNorm::MassRms), f64::INFINITY);
    }
}

//! Tension-field (no-compression) relaxation of a quadratic membrane law, regularised by a
//! logarithmic barrier: the stress of a wrinkling membrane, smooth, with an exact tangent.
//!
//! A membrane that cannot carry compression wrinkles: part of its strain is taken up by
//! out-of-plane waves too fine for the mesh. Writing that wrinkling strain as a positive
//! semi-definite tensor `P` (it can only shorten the elastic strain, `E_el = E + P`), the
//! relaxed energy of a law `ψ(E) = ½ εᵀQε` is `ψ̄(E) = min_{P ⪰ 0} ψ(E + P)` (Pipkin's
//! relaxed energy; taut, wrinkled and slack states are `P = 0`, rank 1 and rank 2). Its
//! stress is never compressive, but it has kinks where the state changes. The barrier
//! regularisation replaces the constraint by
//!
//! ```text
//! ψ_r(E) = min_{P ≻ 0} G(E, P),   G = ½ (ε + p)ᵀ Q (ε + p) − μ ln det P,   μ = ε_r² k_ref
//! ```
//!
//! (`p` the Voigt strain of `P`, `ε_r` the regularisation strain, `k_ref = (Q₁₁ + Q₂₂)/2`).
//! `G` is strictly convex in `P`, so the minimiser is unique and smooth in `E`:
//! - **stress** (envelope theorem) `σ = ∂ψ_r/∂ε = Q (ε + p*)`, and stationarity gives
//!   `σ = μ P*⁻¹ ≻ 0`: the principal stresses are strictly positive — no compression at all;
//! - **tangent** (implicit function theorem on `∂G/∂p = 0`)
//!   `D = ∂σ/∂ε = Q (Q + B)⁻¹ B`, `B = ∂²(−μ ln det P)/∂p²` (positive definite): the
//!   elastic stiffness in series with the barrier's, positive definite, so `ψ_r` is convex in
//!   the Green strain and, with `σ ≻ 0`, the whole element Hessian is positive
//!   semi-definite;
//! - **error**: in 1-D (`k p² + s p = μ`, `s` the elastic stress) the stress is
//!   `σ = ½(s + √(s² + 4kμ))`, a smooth `max(s, 0)` that exceeds it by at most `√(kμ)` =
//!   `ε_r k` (at `s = 0`), by `k ε_r²/|ε|` in compression and by `(ε_r/ε)² σ` in tension.
//!   The regularised membrane is slightly pre-tensioned: at zero strain it carries a
//!   tension of about `ε_r k_ref`.
//!
//! `P*` is found by Newton on `G/μ` (self-concordant: inside `λ < ¼` full steps stay in
//! `P ≻ 0` and converge quadratically; outside, a backtracking line search), started from
//! the exact unregularised (taut, wrinkled or slack) state perturbed in `μ`: closed form
//! for taut and slack, and for a wrinkled triangle the tension-field solution (Mansfield,
//! *The Bending and Stretching of Plates*; Roddeman et al. 1987, *J. Appl. Mech.* 54) whose
//! wrinkling angle solves one scalar equation, by Newton from the minor principal strain
//! direction (exact for an isotropic law). Only when that start is outside the quadratic
//! region (near the transitions, `|ε| ≲ ε_r`) is the exact solution of the decoupled 1-D
//! problems along the principal axes of `Qε` tried too, and the lower `G` wins.

mod linalg;

use super::membrane::{dot, mul, Voigt, Voigt3};
use linalg::{
    barrier_hessian, barrier_hessian_of, bracketed_root, det3, det_grad, inverse_if_pd, root,
    spd_solve, Ldl3,
};

/// Newton iterations after which the inner solve gives up (it takes 2–4 on average and at
/// most ~11 over strains 1e-8–0.3 and ε_r = 1e-8–1e-2).
const MAX_ITERATIONS: usize = 100;
/// Squared Newton decrement (of `G/μ`) below which the full Newton step is taken: for a
/// self-concordant function it stays in the domain and converges quadratically.
const QUADRATIC: f64 = 0.0625;
/// Squared Newton decrement (of `G/μ`) below which the next step is the last: the error
/// after it is O(λ⁴) ≈ 1e-32.
const LAST_STEP: f64 = 1e-16;
/// Newton steps on the wrinkling angle after which [`TensionField::wrinkle_newton`] gives
/// up (and the sampled root search takes over).
const ANGLE_ITERATIONS: usize = 8;
/// Angle step (rad) below which the wrinkling angle has converged: Newton converges
/// quadratically, so the angle after that step is good to ~1e-12 rad, more than the start
/// of the inner solve needs (its error enters as O((ε/ε_r) δθ) in the decrement).
const ANGLE_TOLERANCE: f64 = 1e-6;

/// The barrier-regularised tension-field relaxation for one stiffness `Q`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TensionField {
    /// The stiffness `Q` (N/m) it relaxes.
    pub stiffness: Voigt3,
    /// Regularisation strain `ε_r`.
    pub strain: f64,
    /// Barrier weight `μ = ε_r² (Q₁₁ + Q₂₂)/2` (J/m²).
    pub mu: f64,
    /// `min_P G(0, P)`, subtracted so that `ψ_r(0) = 0`.
    offset: f64,
    /// The compliance `Q⁻¹` (m/N), for the start of the inner solve.
    compliance: Voigt3,
}

/// The relaxed state at one strain.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Relaxed {
    /// Wrinkling strain `p*` (Voigt, `(P₁₁, P₂₂, 2P₁₂)`).
    pub wrinkle: Voigt,
    /// Stress `σ = Q(ε + p*)` (N/m).
    pub stress: Voigt,
    /// Energy `ψ_r(ε)` (J/m²).
    pub energy: f64,
    /// Newton iterations taken.
    pub iterations: usize,
}

/// What the wrinkling strain says of a triangle: its principal values and how many
/// directions are slack.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Wrinkling {
    /// Principal values `λ₁ ≥ λ₂` of the wrinkling strain `P*` (dimensionless): the strain
    /// taken up by wrinkles, along the directions of the principal stresses.
    pub principal: [f64; 2],
    /// Principal directions with `λ > ε_r`: 0 taut, 1 wrinkled, 2 slack. By stationarity
    /// `P* = μ σ⁻¹`, so `λᵢ > ε_r` exactly when the principal stress `σᵢ < ε_r k_ref`, the
    /// regularisation's own pre-tension: a direction that carries no more than the
    /// regularisation puts there is counted slack.
    pub slack_directions: u8,
}

impl TensionField {
    /// The relaxation of `stiffness` with regularisation strain `strain` (> 0).
    pub fn new(stiffness: Voigt3, strain: f64) -> Self {
        let mu = strain * strain * 0.5 * (stiffness[0][0] + stiffness[1][1]);
        let cols = [0, 1, 2].map(|j| {
            let mut e = [0.0; 3];
            e[j] = 1.0;
            spd_solve(&stiffness, &e)
        });
        let compliance = [0, 1, 2].map(|i| [cols[0][i], cols[1][i], cols[2][i]]);
        let mut tf = Self {
            stiffness,
            strain,
            mu,
            offset: 0.0,
            compliance,
        };
        tf.offset = tf.relax(&[0.0; 3]).energy;
        tf
    }

    /// `G(ε, p)`.
    fn objective(&self, eps: &Voigt, p: &Voigt) -> f64 {
        let el = [eps[0] + p[0], eps[1] + p[1], eps[2] + p[2]];
        0.5 * dot(&el, &mul(&self.stiffness, &el)) - self.mu * det_grad(p).0.ln()
    }

    /// The exact minimiser of the 1-D problems along the principal axes of `Qε`.
    fn start(&self, eps: &Voigt) -> Voigt {
        let q = &self.stiffness;
        let s = mul(q, eps);
        let mean = 0.5 * (s[0] + s[1]);
        let half = 0.5 * (s[0] - s[1]);
        let r = half.hypot(s[2]);
        let phi = 0.5 * s[2].atan2(half);
        let (c, sn) = (phi.cos(), phi.sin());
        let mut p = [0.0; 3];
        for (v, sigma) in [([c, sn], mean + r), ([-sn, c], mean - r)] {
            let m = [v[0] * v[0], v[1] * v[1], 2.0 * v[0] * v[1]];
            let pi = root(dot(&m, &mul(q, &m)), sigma, self.mu);
            for k in 0..3 {
                p[k] += pi * m[k];
            }
        }
        p
    }

    /// The start from the exact (unregularised, `μ = 0`) relaxed state, perturbed to first
    /// order in `μ` so that it satisfies `σ = μ P⁻¹` along the axes it does not constrain.
    /// At `μ = 0` exactly one of three states holds (the KKT conditions `σ ⪰ 0`, `P ⪰ 0`,
    /// `σP = 0` are met by one of them, and the problem is convex):
    /// - **taut** when the elastic stress `S = Qε` is positive definite: `P = 0`, so
    ///   `P ≈ μ S⁻¹`;
    /// - **slack** when `−E` is positive definite: `P = −E`, `σ = 0`, so
    ///   `σ ≈ μ (−E)⁻¹` and `p ≈ −ε + Q⁻¹σ`;
    /// - **wrinkled** otherwise: uniaxial tension `s` along `t` with wrinkles `γ n nᵀ` along
    ///   `n ⊥ t`, from [`Self::wrinkle`]; `P ≈ γ n nᵀ + (μ/s) t tᵀ`.
    ///
    /// `None` when the perturbed state is not in `P ≻ 0` (near a transition, where the
    /// 1-D start of [`Self::start`] is as good).
    fn unregularised_start(&self, eps: &Voigt) -> Option<Voigt> {
        self.perturbed(eps, |e| self.wrinkle_newton(e).or_else(|| self.wrinkle(e)))
    }

    /// [`Self::unregularised_start`] with the wrinkling angle by sampling only.
    #[cfg(test)]
    fn unregularised_start_sampled(&self, eps: &Voigt) -> Option<Voigt> {
        self.perturbed(eps, |e| self.wrinkle(e))
    }

    /// [`Self::unregularised_start`] with the wrinkled state from `wrinkle`.
    #[inline]
    fn perturbed(
        &self,
        eps: &Voigt,
        wrinkle: impl Fn(&Voigt) -> Option<(f64, f64, f64, f64)>,
    ) -> Option<Voigt> {
        let mu = self.mu;
        let s = mul(&self.stiffness, eps);
        // `μ T⁻¹` of a stress `T` as a strain (Voigt), or of a strain as a stress.
        let strain_of = |inv: Voigt| [mu * inv[0], mu * inv[1], 2.0 * mu * inv[2]];
        let p = if let Some(inv) = inverse_if_pd(&s) {
            // Taut, then one fixed-point step `P = μ (S + Q p)⁻¹` (error O(μ³)).
            let p = strain_of(inv);
            let sigma = mul(
                &self.stiffness,
                &[eps[0] + p[0], eps[1] + p[1], eps[2] + p[2]],
            );
            inverse_if_pd(&sigma).map_or(p, strain_of)
        } else if let Some(inv) = inverse_if_pd(&[-eps[0], -eps[1], -0.5 * eps[2]]) {
            // Slack, then one fixed-point step `σ = μ (Q⁻¹σ − E)⁻¹`.
            let mut p = [0.0; 3];
            let mut sigma = inv.map(|x| mu * x);
            for pass in 0..2 {
                let e_el = mul(&self.compliance, &sigma);
                p = [0, 1, 2].map(|k| e_el[k] - eps[k]);
                match inverse_if_pd(&[p[0], p[1], 0.5 * p[2]]) {
                    Some(inv) if pass == 0 => sigma = inv.map(|x| mu * x),
                    _ => break,
                }
            }
            p
        } else {
            let (c, sn, tension, gamma) = wrinkle(eps)?;
            let slack = mu / tension;
            [
                gamma * c * c + slack * sn * sn,
                gamma * sn * sn + slack * c * c,
                2.0 * (gamma - slack) * c * sn,
            ]
        };
        (p[0] > 0.0 && det_grad(&p).0 > 0.0).then_some(p)
    }

    /// The unregularised wrinkled state at strain `eps`: wrinkle normal `n = (c, s)`,
    /// uniaxial tension `s_t > 0` along `t = (−s, c)` and wrinkle strain `γ > 0`, with
    /// `ε = s_t Q⁻¹ w(θ) − γ m(θ)` (`m` the Voigt strain of `n nᵀ`, `w` the Voigt stress
    /// of `t tᵀ`). That needs `φ(θ) = det[ε, Q⁻¹w, m] = 0`, a quartic form in
    /// `(cos θ, sin θ)`: its roots are bracketed on 16 samples of `[0, π)` and refined by
    /// regula falsi; of the admissible ones the lowest energy wins.
    fn wrinkle(&self, eps: &Voigt) -> Option<(f64, f64, f64, f64)> {
        const SAMPLES: usize = 16;
        let phi = |theta: f64| {
            let (s, c) = theta.sin_cos();
            let (m, cw) = self.wrinkle_axes(c, s);
            det3(eps, &cw, &m)
        };
        let step = std::f64::consts::PI / SAMPLES as f64;
        let mut best: Option<(f64, (f64, f64, f64, f64))> = None;
        let (mut a, mut fa) = (0.0, phi(0.0));
        for k in 1..=SAMPLES {
            let b = k as f64 * step;
            let fb = phi(b);
            if fa * fb <= 0.0 {
                let theta = bracketed_root(&phi, a, b, fa, fb);
                let (s, c) = theta.sin_cos();
                if let Some((energy, state)) = self.wrinkle_state(eps, c, s) {
                    if best.is_none_or(|(e, _)| energy < e) {
                        best = Some((energy, state));
                    }
                }
            }
            (a, fa) = (b, fb);
        }
        best.map(|(_, state)| state)
    }

    /// `m` and `Q⁻¹ w` for the normal `n = (c, s)`.
    #[inline]
    fn wrinkle_axes(&self, c: f64, s: f64) -> (Voigt, Voigt) {
        let m = [c * c, s * s, 2.0 * c * s];
        let w = [s * s, c * c, -c * s];
        (m, mul(&self.compliance, &w))
    }

    /// The unregularised wrinkled state (as [`Self::wrinkle`]) by scalar Newton on `φ(θ)`,
    /// started from the minor principal direction of the strain `E`. For an isotropic `Q`
    /// that start is the root (tension-field theory: the wrinkles run along the major
    /// principal strain, uniaxial tension along them: Mansfield; Roddeman et al. 1987);
    /// for an orthotropic one the wrinkling angle is the nearby root of this scalar
    /// equation, found in 2–4 steps. `(cos θ, sin θ)` is rotated by `atan δ` for a Newton
    /// step `δ` (rad), without trigonometry (and without normalising it until the end). `None` when it does not converge in
    /// [`ANGLE_ITERATIONS`] or lands on an inadmissible root.
    fn wrinkle_newton(&self, eps: &Voigt) -> Option<(f64, f64, f64, f64)> {
        let half = 0.5 * (eps[0] - eps[1]);
        let off = 0.5 * eps[2];
        let r = (half * half + off * off).sqrt();
        // An eigenvector of the larger principal strain, by the better-conditioned of the
        // two rows of (E − λI) v = 0; its normal is the start.
        let (a, b) = if half >= 0.0 {
            (r + half, off)
        } else {
            (off, r - half)
        };
        let norm = (a * a + b * b).sqrt();
        // (Also refuses a NaN strain.)
        if norm.is_nan() || norm <= 0.0 {
            return None;
        }
        let (mut c, mut s) = (-b / norm, a / norm);
        for _ in 0..ANGLE_ITERATIONS {
            let (m, cw) = self.wrinkle_axes(c, s);
            let (cs2, diff) = (2.0 * c * s, c * c - s * s);
            let dm = [-cs2, cs2, 2.0 * diff];
            let cdw = mul(&self.compliance, &[cs2, -cs2, -diff]);
            let phi = det3(eps, &cw, &m);
            let dphi = det3(eps, &cdw, &m) + det3(eps, &cw, &dm);
            let delta = -phi / dphi;
            if !delta.is_finite() {
                return None;
            }
            // `φ` and `dφ/dθ` are quartic forms in `(c, s)`, so `δ` does not depend on its
            // length: it is normalised once, at the end, off the loop's latency chain.
            (c, s) = (c - s * delta, s + c * delta);
            if delta.abs() < ANGLE_TOLERANCE {
                let k = 1.0 / (c * c + s * s).sqrt();
                return self
                    .wrinkle_state(eps, c * k, s * k)
                    .map(|(_, state)| state);
            }
        }
        None
    }

    /// Energy and state `(c, s, s_t, γ)` of the wrinkled state with normal `n = (c, s)`, if
    /// admissible (`s_t, γ > 0`): `(s_t, γ)` by least squares of `s_t Q⁻¹w − γ m = ε`.
    fn wrinkle_state(&self, eps: &Voigt, c: f64, s: f64) -> Option<(f64, (f64, f64, f64, f64))> {
        let (m, cw) = self.wrinkle_axes(c, s);
        let (aa, ab, bb) = (dot(&cw, &cw), -dot(&cw, &m), dot(&m, &m));
        let (ra, rb) = (dot(&cw, eps), -dot(&m, eps));
        let det = aa * bb - ab * ab;
        let tension = (ra * bb - rb * ab) / det;
        let gamma = (aa * rb - ab * ra) / det;
        if !(tension > 0.0 && gamma > 0.0) {
            return None;
        }
        let el = [0, 1, 2].map(|k| eps[k] + gamma * m[k]);
        Some((dot(&el, &mul(&self.stiffness, &el)), (c, s, tension, gamma)))
    }

    /// `p + t·step` for the first `t = 1, ½, ¼, …` that keeps `P ≻ 0` and decreases `G`
    /// by at least a tenth of the linear prediction `t·decrement` (Armijo). The barrier's
    /// own damped step `1/(1 + λ)` is safe but, far from the minimiser (λ ≫ 1, typical for
    /// small `μ`), takes hundreds of steps; backtracking takes the full Newton step as
    /// soon as it is admissible.
    fn line_search(&self, eps: &Voigt, p: &Voigt, step: &Voigt, decrement: f64) -> Voigt {
        let g0 = self.objective(eps, p);
        let mut t = 1.0;
        loop {
            let trial = [0, 1, 2].map(|k| p[k] + t * step[k]);
            let admissible = trial[0] > 0.0 && det_grad(&trial).0 > 0.0;
            if admissible && self.objective(eps, &trial) <= g0 - 0.1 * t * decrement {
                return trial;
            }
            t *= 0.5;
            if t < 1e-12 {
                // No decrease measurable above round-off: stay.
                return *p;
            }
        }
    }

    /// The Newton step on `G` at `p` and its squared decrement (of `G/μ`).
    #[inline]
    fn newton_step(&self, eps: &Voigt, p: &Voigt) -> (Voigt, f64) {
        let (q, mu) = (&self.stiffness, self.mu);
        let (d, gd) = det_grad(p);
        let el = [eps[0] + p[0], eps[1] + p[1], eps[2] + p[2]];
        let qe = mul(q, &el);
        let a = mu / d;
        let g = [qe[0] - a * gd[0], qe[1] - a * gd[1], qe[2] - a * gd[2]];
        let b = barrier_hessian_of(mu, d, &gd);
        let mut h = *q;
        for r in 0..3 {
            for c in 0..3 {
                h[r][c] += b[r][c];
            }
        }
        let step = spd_solve(&h, &g).map(|x| -x);
        (step, -dot(&g, &step) / mu)
    }

    /// The start of the inner solve and the Newton step there: the perturbed unregularised
    /// state when it exists and is inside the region of quadratic convergence (far from
    /// the transitions, |ε| ≫ ε_r), else the better (lower `G`) of it and the 1-D start.
    fn first_step(&self, eps: &Voigt) -> (Voigt, (Voigt, f64)) {
        let Some(near) = self.unregularised_start(eps) else {
            let p = self.start(eps);
            return (p, self.newton_step(eps, &p));
        };
        let step = self.newton_step(eps, &near);
        if step.1 < QUADRATIC {
            return (near, step);
        }
        let p = self.start(eps);
        if self.objective(eps, &p) < self.objective(eps, &near) {
            (p, self.newton_step(eps, &p))
        } else {
            (near, step)
        }
    }

    /// The relaxed state at strain `eps` (Voigt `(E₁₁, E₂₂, 2E₁₂)`).
    pub fn relax(&self, eps: &Voigt) -> Relaxed {
        let (p, next) = self.first_step(eps);
        self.relax_from(eps, p, next)
    }

    /// The relaxed stress `σ` at strain `eps` (N/m): [`Self::relax`] without the energy.
    pub fn stress(&self, eps: &Voigt) -> Voigt {
        let (p, next) = self.first_step(eps);
        self.stress_at(eps, &self.minimise(eps, p, next).0)
    }

    /// The wrinkling state at `eps` ([`Wrinkling`]).
    pub fn wrinkling(&self, eps: &Voigt) -> Wrinkling {
        let p = self.relax(eps).wrinkle;
        // P as a tensor: (P₁₁, P₂₂, P₁₂ = p₂/2).
        let (mean, half) = (0.5 * (p[0] + p[1]), 0.5 * (p[0] - p[1]));
        let r = (half * half + 0.25 * p[2] * p[2]).sqrt();
        let principal = [mean + r, mean - r];
        let slack_directions = principal.iter().filter(|&&l| l > self.strain).count() as u8;
        Wrinkling {
            principal,
            slack_directions,
        }
    }

    /// The relaxed stress and the tangent (as [`Self::relax_with_tangent`]) without the
    /// energy.
    pub fn stress_and_tangent(&self, eps: &Voigt) -> (Voigt, Voigt3) {
        let (p, next) = self.first_step(eps);
        let p = self.minimise(eps, p, next).0;
        (self.stress_at(eps, &p), self.tangent(&p))
    }

    /// `σ = Q(ε + p)`.
    #[inline]
    fn stress_at(&self, eps: &Voigt, p: &Voigt) -> Voigt {
        mul(
            &self.stiffness,
            &[eps[0] + p[0], eps[1] + p[1], eps[2] + p[2]],
        )
    }

    /// [`Self::minimise`] and the relaxed state it reaches.
    fn relax_from(&self, eps: &Voigt, p: Voigt, next: (Voigt, f64)) -> Relaxed {
        let (p, iterations) = self.minimise(eps, p, next);
        Relaxed {
            wrinkle: p,
            stress: self.stress_at(eps, &p),
            energy: self.objective(eps, &p) - self.offset,
            iterations,
        }
    }

    /// Newton on `G` from `p`, whose Newton step is `next`: the minimiser `p*` and the
    /// iterations taken.
    fn minimise(&self, eps: &Voigt, mut p: Voigt, mut next: (Voigt, f64)) -> (Voigt, usize) {
        let mut iterations = 0;
        let mut previous = f64::INFINITY;
        while iterations < MAX_ITERATIONS {
            iterations += 1;
            let (step, lambda2) = next;
            if !lambda2.is_finite() {
                break;
            }
            if lambda2 < QUADRATIC {
                // Inside the region of quadratic convergence the full step is admissible
                // (self-concordance) and needs no line search (whose test of G would be
                // below G's round-off here).
                for k in 0..3 {
                    p[k] += step[k];
                }
            } else {
                p = self.line_search(eps, &p, &step, lambda2 * self.mu);
            }
            // Converged, or at the round-off floor: after a full step inside the quadratic
            // region the squared decrement must fall by ≥ 9× (λ⁺ ≤ (λ/(1 − λ))²); when it
            // does not, round-off in `P` (whose smaller eigenvalue, ~μ/σ, can be 1e-10 of
            // its larger one) dominates.
            if lambda2 < LAST_STEP || (previous < QUADRATIC && lambda2 > 0.25 * previous) {
                break;
            }
            previous = lambda2;
            next = self.newton_step(eps, &p);
        }
        (p, iterations)
    }

    /// The relaxed state and the tangent `D = ∂σ/∂ε = Q (Q + B)⁻¹ B` (N/m), symmetrised.
    pub fn relax_with_tangent(&self, eps: &Voigt) -> (Relaxed, Voigt3) {
        let r = self.relax(eps);
        let d = self.tangent(&r.wrinkle);
        (r, d)
    }

    /// The tangent `D = Q (Q + B)⁻¹ B` at the relaxed wrinkling strain `p*`, symmetrised.
    fn tangent(&self, p: &Voigt) -> Voigt3 {
        let q = &self.stiffness;
        let b = barrier_hessian(self.mu, p);
        let mut h = *q;
        for i in 0..3 {
            for j in 0..3 {
                h[i][j] += b[i][j];
            }
        }
        // X = (Q + B)⁻¹ B column by column, then D = Q X.
        let chol = Ldl3::new(&h);
        let cols = [0, 1, 2].map(|j| chol.solve(&[b[0][j], b[1][j], b[2][j]]));
        let mut d = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                d[i][j] = q[i][0] * cols[j][0] + q[i][1] * cols[j][1] + q[i][2] * cols[j][2];
            }
        }
        for i in 0..3 {
            for j in 0..i {
                let s = 0.5 * (d[i][j] + d[j][i]);
                d[i][j] = s;
                d[j][i] = s;
            }
        }
        d
    }
}

#[cfg(test)]
#[path = "tension_field_tests.rs"]
mod tests;

//! The settings and reports of the Newton solves ([`NewtonOptions`], [`Predictor`],
//! [`StepReport`], [`Timings`]); the iteration itself is in `newton.rs`.

/// Newton–Raphson settings.
#[derive(Debug, Clone, Copy)]
pub struct NewtonOptions {
    /// Maximum Newton iterations per solve.
    pub max_iterations: usize,
    /// Absolute force tolerance on `‖R‖∞` (N). `None`: `1e-9 × (1 N + Σm · a_ref)` with
    /// `a_ref` = [`NewtonOptions::reference_acceleration`], i.e. 1e-9 of the model's force
    /// scale.
    pub force_tol_abs: Option<f64>,
    /// The acceleration `a_ref` (m/s²) that turns the model's total mass into the force
    /// scale of the default absolute tolerance (see [`NewtonOptions::force_tol_abs`]): the
    /// gravity for a body falling under its weight, a typical acceleration otherwise.
    /// Unused when `force_tol_abs` is set.
    pub reference_acceleration: f64,
    /// Tolerance relative to the first residual.
    pub force_tol_rel: f64,
    /// Step-size tolerance on `‖Δq‖∞` (m or rad).
    pub step_tol: f64,
    /// Backtracking line search on `‖R‖₂`.
    pub line_search: bool,
    /// Maximum number of step halvings in the line search (down to α = 2^−n).
    pub max_backtracks: usize,
    /// Modified Newton: keep the factorised Jacobian across iterations and steps while the
    /// residual contracts by at least `reuse_contraction` per iteration; refactorise when it
    /// does not (and after any `dt` change). The converged state satisfies the same residual
    /// tolerance, so accuracy is unchanged; only the iteration path differs.
    pub reuse_jacobian: bool,
    /// Contraction factor below which a reused Jacobian is kept (0 < c < 1).
    pub reuse_contraction: f64,
    /// When some force's Jacobian is not symmetric (drag), factorise its symmetric part
    /// `J_s = ½ (J + Jᵀ)` by Cholesky (LBLᵀ if indefinite) instead of `J` by LU. The residual
    /// stays exact, so the converged state meets the same tolerance; only the contraction
    /// per iteration changes, by `‖(J − J_s) Δ‖ / ‖R‖` (small when drag is weak against
    /// `M/dt² + K`). That ratio is measured after each fresh factorisation (one sparse
    /// product); above 0.1 every update of the solve is corrected into the exact Newton
    /// update `J Δ = −R` by BiCGStab preconditioned with the held factors
    /// (`linsolve::krylov`). Cholesky is about half the flops of LU, needs no pivoting and no
    /// second symbolic structure (LU's storage is several times the Cholesky factor's). No
    /// effect when `J` is symmetric.
    pub symmetric_approx: bool,
    /// Give up a solve as soon as `‖R‖∞` exceeds this multiple of `max(‖R₀‖∞, tol)`, instead
    /// of spending the rest of the iteration budget on it (the caller can then shorten `dt`
    /// at once). Converging solves of stiff membranes can raise `‖R‖∞` by two orders of
    /// magnitude on the way, failing ones by many more (docs/performance.md has the
    /// measurements behind [`NewtonOptions::recommended`]'s 1e4). `f64::INFINITY` disables
    /// the test.
    pub divergence_limit: f64,
    /// Initial guess of an implicit-Euler step (see [`Predictor`]).
    pub predictor: Predictor,
    /// Accuracy-based convergence of implicit-Euler steps (`η`; 0 turns it off). Besides the
    /// force tolerance above, a step is converged when the residual left would move the state
    /// by at most `η` times backward Euler's own local error: for every free DOF
    /// `|R_i| / m_i ≤ max(η c_m e, ε a_ref)` with `e = ½ ‖q − q̃‖∞` the local error estimate at
    /// the iterate (`(h/2)|v_{n+1} − v_n|`, the one [`super::error_control`] uses) and
    /// `ε = accuracy_floor` (docs/engine.md §Newton tolerance has the derivation). Statics
    /// (`c_m = 0`) keeps the force tolerance alone.
    pub accuracy_fraction: f64,
    /// The floor of the accuracy-based test, as a residual acceleration per DOF relative to
    /// [`NewtonOptions::reference_acceleration`] (`ε`): the local error vanishes in a steady
    /// descent, and there `|R_i| ≤ ε m_i a_ref` bounds the summed residual by `ε` of the total
    /// weight (a relative shift of a drag-balanced terminal velocity of at most `ε/2`).
    pub accuracy_floor: f64,
    /// When a solve using a reused factorisation or the symmetric approximation fails
    /// (diverged, not converged, non-finite), retry the same step once from the
    /// constant-velocity guess with exact Newton: a fresh Jacobian every iteration, first
    /// with every update of the symmetric approximation corrected into the exact update by
    /// BiCGStab, then with LU of `J`, then with the line search (docs/engine.md §Exact
    /// retry). Only if that fails too does the error reach the caller (who shortens `dt`).
    pub exact_retry: bool,
    /// The exact retry's last stage: when exact Newton from `q̃` fails with full steps and
    /// with the line search, solve the step by pseudo-transient continuation (an extra
    /// diagonal `(c_m/τ) M` in the Newton matrix, `τ` growing as the residual falls; the
    /// converged state satisfies the same residual test, so it is the same solution). No
    /// effect without [`NewtonOptions::exact_retry`].
    pub continuation: bool,
    /// The exact retry's very last stage: when continuation fails too, follow the step's
    /// solution in the step size from half the step up to the full step (exact Newton at
    /// each size; `stepper/newton/homotopy.rs`). Where that succeeds, the step is taken
    /// whole instead of halved; the result meets the same residual test. No effect without
    /// [`NewtonOptions::exact_retry`].
    pub step_homotopy: bool,
}

impl NewtonOptions {
    /// The tuned settings for time stepping large models (what `chute run` uses): modified
    /// Newton ([`NewtonOptions::reuse_jacobian`]), Cholesky of the symmetric part for
    /// non-symmetric Jacobians ([`NewtonOptions::symmetric_approx`]), a divergence limit of
    /// 1e4, the [`Predictor::Adaptive`] predictor, the accuracy-based tolerance
    /// ([`NewtonOptions::accuracy_fraction`] 1 %, floor 1e-4 of the weight) and the exact
    /// retry ([`NewtonOptions::exact_retry`]). [`NewtonOptions::strict`] turns the
    /// accuracy-based test off (every step then meets the force tolerance of
    /// [`NewtonOptions::default`]).
    pub fn recommended() -> Self {
        Self {
            reuse_jacobian: true,
            symmetric_approx: true,
            divergence_limit: 1e4,
            predictor: Predictor::Adaptive,
            accuracy_fraction: 0.01,
            accuracy_floor: 1e-4,
            exact_retry: true,
            continuation: true,
            step_homotopy: true,
            ..Self::default()
        }
    }

    /// These options with the accuracy-based test off: converged only on the force
    /// tolerance (references and tests, `time.newton_strict`).
    pub fn strict(self) -> Self {
        Self {
            accuracy_fraction: 0.0,
            ..self
        }
    }

    /// [`NewtonOptions::strict`] when `strict`, else these options unchanged.
    pub fn strict_if(self, strict: bool) -> Self {
        if strict {
            self.strict()
        } else {
            self
        }
    }
}

/// Initial Newton iterate of an implicit-Euler step.
///
/// The converged step satisfies the same residual test whatever the guess; a better guess
/// only saves iterations (and keeps a reused factorisation within its contraction radius).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Predictor {
    /// `q⁰ = q_n + dt v_n`.
    #[default]
    ConstantVelocity,
    /// `q⁰ = q_n + dt v_n + dt² a_n`, `a_n = (v_n − v_{n−1}) / dt_{n−1}` the last step's
    /// mean acceleration: exact to O(dt³) for smooth motion, where constant velocity leaves
    /// the whole `dt² a` to Newton. Falls back to constant velocity on the first step and
    /// after [`crate::ImplicitEuler::invalidate_factorization`].
    ConstantAcceleration,
    /// `q⁰ = q_n + dt v_n + dt² a_pred`: the last two steps' mean accelerations extrapolated
    /// linearly to the middle of the new step (`stepper/predictor.rs`), exact for motion of
    /// constant jerk. Falls back to constant acceleration while only one step is known.
    ConstantJerk,
    /// The highest order (velocity, acceleration, jerk) whose guess of the last step was at
    /// least 2× closer (‖·‖∞) to its solution than the order below it (measured at no cost
    /// once a step has converged). Extrapolation wins for smooth motion and loses for
    /// violent motion at large `dt`; the 2× margin keeps it off where it only sometimes
    /// helps (docs/performance.md §Engine tuning has the measurements).
    Adaptive,
}

/// The plain, exact Newton–Raphson: full Newton with a fresh Jacobian every iteration, LU for
/// non-symmetric Jacobians, constant-velocity predictor, no divergence test. Robust and
/// simple to reason about; [`NewtonOptions::recommended`] is much faster on large models.
impl Default for NewtonOptions {
    fn default() -> Self {
        Self {
            max_iterations: 25,
            force_tol_abs: None,
            reference_acceleration: 1.0,
            force_tol_rel: 1e-10,
            step_tol: 1e-12,
            line_search: true,
            max_backtracks: 8,
            reuse_jacobian: false,
            reuse_contraction: 0.5,
            symmetric_approx: false,
            predictor: Predictor::ConstantVelocity,
            divergence_limit: f64::INFINITY,
            accuracy_fraction: 0.0,
            accuracy_floor: 0.0,
            exact_retry: false,
            continuation: false,
            step_homotopy: false,
        }
    }
}

/// What one solve did.
#[derive(Debug, Clone, Copy, Default)]
pub struct StepReport {
    /// Newton iterations (linear solves) taken.
    pub iterations: usize,
    /// Final `‖R‖∞` (N).
    pub residual: f64,
    /// Line-search halvings, summed over iterations.
    pub backtracks: usize,
    /// Whether the last factorisation was Cholesky.
    pub used_cholesky: bool,
    /// Numeric factorisations performed.
    pub factorizations: usize,
}

/// Where the Newton solves spent their time (seconds of wall time) and what they did,
/// accumulated until the owner resets it (`ImplicitEuler::reset_timings`).
///
/// Measured with `std::time::Instant` around each phase (≈ 20–40 ns per reading, a few
/// readings per iteration), so the instrumentation costs well under 0.1 % of a step.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Timings {
    /// Element evaluation plus scatter of forces (and Jacobian values when wanted) (s).
    pub assembly_s: f64,
    /// Energy evaluations for the line-search merit Φ (s).
    pub merit_s: f64,
    /// Numeric factorisations (LLᵀ, and LU after an LLᵀ failure) (s).
    pub factor_s: f64,
    /// Triangular solves (s).
    pub solve_s: f64,
    /// Residual evaluations (each one a full element pass).
    pub evaluations: u64,
    /// Of those, evaluations that also assembled the Jacobian.
    pub jacobian_evaluations: u64,
    /// Numeric factorisations.
    pub factorizations: u64,
    /// Of those, LU factorisations (non-symmetric J, exact path or approximation fallback).
    pub lu_factorizations: u64,
    /// Of those, LBLᵀ factorisations (symmetric matrix not positive definite).
    pub lblt_factorizations: u64,
    /// Newton iterations (linear solves).
    pub iterations: u64,
    /// Newton solves (time steps, or load steps in statics).
    pub solves: u64,
    /// Updates with a reused factorisation that were undone (non-finite residual).
    pub rejected: u64,
    /// Solves in which the symmetric approximation's updates were corrected towards the
    /// exact Newton update by preconditioned BiCGStab (its linearised residual
    /// `‖(J − J_s) Δ‖∞` exceeded `0.1 ‖R‖∞`).
    pub approx_fallbacks: u64,
    /// BiCGStab iterations of those corrections (each: two products with `J`, two
    /// triangular solves with the held factors; their time is in `solve_s`).
    pub krylov_iterations: u64,
    /// Corrections that did not converge (the approximate update was kept).
    pub krylov_failures: u64,
    /// Solves that failed on the reused or approximate path and were retried with exact
    /// Newton ([`NewtonOptions::exact_retry`]).
    pub exact_retries: u64,
    /// Of those, retries that converged.
    pub exact_retries_converged: u64,
    /// Failed solves not retried because failures had already cost more factorisations
    /// than the successful solves since the last sync point (the retry ledger,
    /// `stepper/retry_ledger.rs`).
    pub exact_retries_skipped: u64,
    /// Retries that reached their pseudo-transient continuation stage.
    pub continuations: u64,
    /// Of those, continuations that converged.
    pub continuations_converged: u64,
    /// Retries that reached their step-size homotopy stage.
    pub homotopies: u64,
    /// Of those, homotopies that converged (the step was taken whole).
    pub homotopies_converged: u64,
    /// Solves that converged on the accuracy-based test (not on the force tolerance).
    pub accuracy_accepts: u64,
    /// Local error estimates filtered through the step's factors
    /// ([`crate::ImplicitEuler::set_error_filter`]).
    pub error_filters: u64,
    /// Estimates left unfiltered because the step held no factors for its own `dt` (it
    /// converged at the predictor) or the filtered estimate was not finite.
    pub error_filter_fallbacks: u64,
}

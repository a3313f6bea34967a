//! The settings of the step solver ([`NewtonOptions`], [`Predictor`]) and what it reports
//! ([`StepReport`], [`Counters`]). The solver itself is the ladder of `controller.rs`.

/// Settings of the step solver. Every field has a documented default;
/// [`NewtonOptions::recommended`] is what `chute run` uses, [`NewtonOptions::default`] is plain
/// Newton (a fresh Jacobian every iteration, no held factors, no accuracy-based test).
#[derive(Debug, Clone, Copy)]
pub struct NewtonOptions {
    /// Iterations of the Newton stage per solve (the continuation stage has four times as
    /// many, the held stage [`NewtonOptions::held_iterations`]). Default 25.
    pub max_iterations: usize,
    /// Absolute force tolerance on `‖R‖∞` (N). `None`: `1e-9 × (1 N + Σm · a_ref)` with
    /// `a_ref` = [`NewtonOptions::reference_acceleration`], i.e. 1e-9 of the model's force
    /// scale.
    pub force_tol_abs: Option<f64>,
    /// The acceleration `a_ref` (m/s²) that turns the model's total mass into a force scale:
    /// of the default absolute tolerance and of the accuracy test's floor (the gravity for a
    /// body falling under its weight). Default 1.
    pub reference_acceleration: f64,
    /// Tolerance relative to the first residual. Default 1e-10.
    pub force_tol_rel: f64,
    /// Step-size tolerance on `‖Δq‖∞` (m or rad): an update this small ends the solve when
    /// the residual is within 1e3 of the tolerance (a stalled iteration is not taken for
    /// convergence). Default 1e-12.
    pub step_tol: f64,
    /// The Newton stage searches along each update for the point where the residual is
    /// orthogonal to it (a Galerkin line search, `stage/newton.rs`). Default `true`.
    pub line_search: bool,
    /// Most trial points of one line search. Default 8.
    pub max_backtracks: usize,
    /// The held stage: a step first iterates with the factors held from earlier steps (if
    /// they are for the same `dt`), accelerated by Anderson mixing, before any new
    /// factorisation (`stage/held.rs`). Default `false`; recommended `true`.
    pub hold_factors: bool,
    /// Iterations the held stage may take before it hands the step to the Newton stage (at
    /// most [`NewtonOptions::max_iterations`]). Default 8.
    pub held_iterations: usize,
    /// Anderson depth of the held stage: how many earlier iterates its mixing combines
    /// (0: the plain chord iteration). Default 4.
    pub anderson_depth: usize,
    /// The mean contraction of `‖R‖∞` per chord iteration (with held factors, in the held
    /// stage or between the Newton stage's factorisations) below which the factors are kept:
    /// a chord run whose residual grew, or shrank by less than `c^k` after `k ≥ 2` iterations,
    /// ends (0 < c < 1; 0: plain Newton, a factorisation every iteration). Default 0;
    /// recommended 0.3.
    pub reuse_contraction: f64,
    /// Give up a stage as soon as `‖R‖∞` exceeds this multiple of `max(‖R₀‖∞, tol)`
    /// (`f64::INFINITY` disables the test). Default ∞; recommended 1e4.
    pub divergence_limit: f64,
    /// Initial guess of an implicit-Euler step (see [`Predictor`]).
    pub predictor: Predictor,
    /// Accuracy-based convergence of implicit-Euler steps (`η`; 0 turns it off): a step is
    /// also converged when for every free DOF `|R_i| / m_i ≤ max(η c_m e, ε a_ref)`, with
    /// `e = ½ ‖q − q̃‖∞` backward Euler's local error estimate at the iterate and
    /// `ε = accuracy_floor` (docs/engine.md §Newton tolerance). Default 0; recommended 0.01.
    pub accuracy_fraction: f64,
    /// The floor `ε` of the accuracy-based test, a residual acceleration per DOF relative to
    /// [`NewtonOptions::reference_acceleration`]. Default 0; recommended 1e-4.
    pub accuracy_floor: f64,
    /// The continuation stage: pseudo-transient continuation from `q̃` where the Newton
    /// stage failed (`stage/continuation.rs`). Default `false`; recommended `true`.
    pub continuation: bool,
    /// The homotopy stage: the step's solution followed in the step size from half the
    /// step up (`stage/homotopy.rs`). Default `false`; recommended `true`.
    pub step_homotopy: bool,
    /// Factorise in single precision (`linsolve/numeric.rs`): half the factor's storage and
    /// memory traffic. The factors only precondition iterations whose residual is in double
    /// precision, so the converged state meets the same test; on the main job the same
    /// counts of factorisations and iterations, 1.35× less wall time (docs/performance.md).
    /// Default `false` (plain Newton keeps exact updates); recommended `true`.
    pub single_precision_factors: bool,
}

impl NewtonOptions {
    /// The absolute force tolerance (N) for a model of total mass `mass` (kg):
    /// [`NewtonOptions::force_tol_abs`], or `1e-9 × (1 N + mass · a_ref)`.
    pub fn force_tolerance(&self, mass: f64) -> f64 {
        self.force_tol_abs
            .unwrap_or(1e-9 * (1.0 + mass * self.reference_acceleration))
    }

    /// The tuned settings for time stepping large models (what `chute run` uses): the held
    /// stage with Anderson mixing, modified Newton in the Newton stage (refactorise below a
    /// 2× contraction), a divergence limit of 1e4, the [`Predictor::Adaptive`] predictor, the
    /// accuracy-based tolerance (1 %, floor 1e-4 of the weight), and the continuation and
    /// homotopy stages. [`NewtonOptions::strict`] turns the accuracy-based test off.
    pub fn recommended() -> Self {
        Self {
            hold_factors: true,
            reuse_contraction: 0.3,
            divergence_limit: 1e4,
            predictor: Predictor::Adaptive,
            accuracy_fraction: 0.001,
            accuracy_floor: 1e-4,
            continuation: true,
            step_homotopy: true,
            single_precision_factors: true,
            ..Self::default()
        }
    }

    /// These options solving each step as exactly as the machine allows: the accuracy-based
    /// test off (converged only on the force tolerance) and double-precision factors, whose
    /// chord iterations contract to far below the tolerance, so that runs that should agree
    /// to round-off (mirror images, references) do (`time.newton_strict`).
    pub fn strict(self) -> Self {
        Self {
            accuracy_fraction: 0.0,
            single_precision_factors: false,
            ..self
        }
    }

    /// These options with the accuracy-based test off when `off` (a caller's own force
    /// tolerance replaces it), the factors unchanged.
    pub fn without_accuracy_test_if(self, off: bool) -> Self {
        Self {
            accuracy_fraction: if off { 0.0 } else { self.accuracy_fraction },
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

/// Plain Newton–Raphson: a fresh Jacobian every iteration, the Galerkin line search, the
/// constant-velocity predictor, no held factors, no accuracy-based test, no later stages.
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
            hold_factors: false,
            held_iterations: 8,
            anderson_depth: 4,
            reuse_contraction: 0.0,
            divergence_limit: f64::INFINITY,
            predictor: Predictor::ConstantVelocity,
            accuracy_fraction: 0.0,
            accuracy_floor: 0.0,
            continuation: false,
            step_homotopy: false,
            single_precision_factors: false,
        }
    }
}

/// Initial Newton iterate of an implicit-Euler step.
///
/// The converged step satisfies the same residual test whatever the guess; a better guess
/// only saves iterations (and keeps held factors within their contraction radius).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Predictor {
    /// `q⁰ = q_n + dt v_n`.
    #[default]
    ConstantVelocity,
    /// `q⁰ = q_n + dt v_n + dt² a_n`, `a_n = (v_n − v_{n−1}) / dt_{n−1}` the last step's
    /// mean acceleration: exact to O(dt³) for smooth motion. Falls back to constant velocity
    /// on the first step and after [`crate::ImplicitEuler::invalidate_factorization`].
    ConstantAcceleration,
    /// `q⁰ = q_n + dt v_n + dt² a_pred`: the last two steps' mean accelerations extrapolated
    /// linearly to the middle of the new step (`stepper/predictor.rs`), exact for motion of
    /// constant jerk. Falls back to constant acceleration while only one step is known.
    ConstantJerk,
    /// The highest order (velocity, acceleration, jerk) whose guess of the last step was at
    /// least 2× closer (‖·‖∞) to its solution than the order below it.
    Adaptive,
}

/// Which stage of the ladder solved a step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Stage {
    /// Iterations on the factors held from earlier steps (`stage/held.rs`).
    Held,
    /// Newton with fresh Jacobians and the Galerkin line search (`stage/newton.rs`).
    #[default]
    Newton,
    /// Pseudo-transient continuation (`stage/continuation.rs`).
    Continuation,
    /// Step-size homotopy (`stage/homotopy.rs`).
    Homotopy,
}

/// What one solve did.
#[derive(Debug, Clone, Copy, Default)]
pub struct StepReport {
    /// Iterations (linear solves) taken, over every stage tried.
    pub iterations: usize,
    /// Final `‖R‖∞` (N).
    pub residual: f64,
    /// Line-search trial points beyond the first, summed over iterations.
    pub backtracks: usize,
    /// Numeric factorisations performed.
    pub factorizations: usize,
    /// The stage that converged.
    pub stage: Stage,
}

/// Runs of one stage of the ladder and how many of them converged.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct StageCounts {
    /// Times the stage was tried.
    pub runs: u64,
    /// Times it solved the step.
    pub converged: u64,
}

impl Counters {
    /// These counters merged with `other`'s, field by field (a run resumed from a checkpoint
    /// adds the counters of the part before it).
    pub fn merge(&self, other: &Self) -> Self {
        // A struct literal: a counter added to the type and not summed here does not compile.
        macro_rules! sum {
            ($($field:ident),*) => { Self { $($field: self.$field + other.$field),* } };
        }
        sum!(
            assembly_s,
            factor_s,
            solve_s,
            evaluations,
            jacobian_evaluations,
            factorizations,
            indefinite_factorizations,
            iterations,
            solves,
            krylov_iterations,
            krylov_failures,
            line_search_points,
            held,
            newton,
            continuation,
            homotopy,
            stages_skipped,
            accuracy_accepts,
            roundoff_accepts,
            noise_probes,
            error_filters,
            error_filter_fallbacks,
            bounded_moves,
            path_rejects,
            pattern_rebuilds,
            pattern_s
        )
    }
}

impl std::ops::Add for StageCounts {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Self {
            runs: self.runs + o.runs,
            converged: self.converged + o.converged,
        }
    }
}

impl StageCounts {
    /// Count one run.
    pub fn record(&mut self, ok: bool) {
        self.runs += 1;
        self.converged += u64::from(ok);
    }
}

/// What the step solver did and where its time went, accumulated until the owner resets it
/// ([`crate::ImplicitEuler::reset_counters`]). Counts are deterministic; the times are wall
/// time (`std::time::Instant` around each phase, well under 0.1 % of a step).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
// Self-describing (JSON names every field): a counter that a file's writer did not have reads
// as 0, so adding one needs no new checkpoint format; an unknown one is refused.
#[cfg_attr(feature = "serde", serde(deny_unknown_fields, default))]
pub struct Counters {
    /// Element evaluation plus scatter of forces (and Jacobian values when wanted) (s).
    pub assembly_s: f64,
    /// Numeric factorisations (s).
    pub factor_s: f64,
    /// Triangular solves and Krylov corrections (s).
    pub solve_s: f64,
    /// Residual evaluations (each one a full element pass).
    pub evaluations: u64,
    /// Of those, evaluations that also assembled the Jacobian.
    pub jacobian_evaluations: u64,
    /// Numeric factorisations (Cholesky LLᵀ, or LBLᵀ where the matrix is indefinite).
    pub factorizations: u64,
    /// Of those, LBLᵀ factorisations (the symmetric matrix was not positive definite).
    pub indefinite_factorizations: u64,
    /// Iterations (linear solves) of every stage.
    pub iterations: u64,
    /// Step solves (time steps attempted, or load steps in statics).
    pub solves: u64,
    /// BiCGStab iterations correcting updates of the symmetric part into Newton updates.
    pub krylov_iterations: u64,
    /// Corrections that did not converge (the symmetric part's update was kept).
    pub krylov_failures: u64,
    /// Line-search trial points beyond the first.
    pub line_search_points: u64,
    /// The held stage.
    pub held: StageCounts,
    /// The Newton stage.
    pub newton: StageCounts,
    /// The continuation stage.
    pub continuation: StageCounts,
    /// The homotopy stage.
    pub homotopy: StageCounts,
    /// Later stages (continuation, homotopy) not tried because failed solves had already
    /// cost more factorisations than successful ones since the last sync point
    /// (`stepper/retry_ledger.rs`).
    pub stages_skipped: u64,
    /// Solves that converged on the accuracy-based test (not on the force tolerance).
    pub accuracy_accepts: u64,
    /// Solves that converged because every residual was within its round-off floor
    /// (`stepper/convergence.rs`).
    pub roundoff_accepts: u64,
    /// Measurements of the residual's round-off where an iteration stalled (one residual
    /// evaluation each, counted in `evaluations` too).
    pub noise_probes: u64,
    /// Local error estimates filtered through the step's factors.
    pub error_filters: u64,
    /// Estimates left unfiltered (no factors for the step's own `dt`, or not finite).
    pub error_filter_fallbacks: u64,
    /// Moves of an iterate shortened by a force's step bound (contact's CCD,
    /// `Force::max_step`).
    pub bounded_moves: u64,
    /// Solved steps refused because the straight path from the step's start to its solution
    /// brought two surfaces together (contact; the step is halved).
    pub path_rejects: u64,
    /// Rebuilds of the sparsity pattern and its symbolic factorisation after a force's
    /// stencils changed (contact pairs).
    pub pattern_rebuilds: u64,
    /// Time spent in those rebuilds (s).
    pub pattern_s: f64,
}

//! Error types of the engine.
use thiserror::Error;

/// Errors raised while building a model or its solver.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum EngineError {
    /// A force referenced a DOF outside the model.
    #[error("force `{force}` references DOF {dof}, but the model has only {n} DOFs")]
    DofOutOfRange {
        /// Name of the force.
        force: String,
        /// The offending DOF.
        dof: usize,
        /// Number of DOFs of the model.
        n: usize,
    },
    /// A free DOF has zero mass, so the dynamic Jacobian could be singular.
    #[error("free DOF {dof} has non-positive mass {mass}")]
    NonPositiveMass {
        /// The DOF.
        dof: usize,
        /// Its mass (kg or kg·m²).
        mass: f64,
    },
    /// The forces' low-rank Jacobian parts have too many terms in all.
    #[error("the forces' low-rank Jacobian parts have {rank} terms, at most {max} are supported")]
    LowRank {
        /// Terms of all low-rank parts.
        rank: usize,
        /// Most terms supported.
        max: usize,
    },
    /// The sparse symbolic analysis failed.
    #[error("sparse symbolic factorisation failed: {0}")]
    Symbolic(SparseError),
    /// Invalid input to a model builder.
    #[error("invalid model: {0}")]
    Invalid(InvalidModel),
}

/// What is wrong with the input of a model builder ([`crate::rod::RodNetwork::install`],
/// [`crate::shell::install`], [`crate::ErrorController::new`]).
#[derive(Debug, Clone, PartialEq, Error)]
pub enum InvalidModel {
    /// The configuration vector does not match the DOF layout.
    #[error("q has {got} entries, layout {expected}")]
    StateLength {
        /// Entries of `q`.
        got: usize,
        /// DOFs of the layout.
        expected: usize,
    },
    /// The layout has too few per-edge DOFs (twist slots) for a rod network or mid-edge shell.
    #[error(
        "needs per-edge DOFs (rod twists, mid-edge angles) {start}..{end}, layout has {available}"
    )]
    TwistDofs {
        /// First twist DOF needed (index among the twists).
        start: usize,
        /// One past the last twist DOF needed.
        end: usize,
        /// Twist DOFs in the layout.
        available: usize,
    },
    /// A rod with fewer than two nodes.
    #[error("rod {rod} has fewer than 2 nodes")]
    RodTooShort {
        /// Index of the rod.
        rod: usize,
    },
    /// A rod references a node outside the layout.
    #[error("rod {rod} uses node {node} of {n_nodes}")]
    NodeOutOfRange {
        /// Index of the rod.
        rod: usize,
        /// The offending node.
        node: usize,
        /// Nodes in the layout.
        n_nodes: usize,
    },
    /// A rod's material constants are out of range.
    #[error("rod {rod}: E and G must be positive, ρ non-negative")]
    Material {
        /// Index of the rod.
        rod: usize,
    },
    /// A rod's cross-section is invalid.
    #[error("rod {rod}: {reason}")]
    Section {
        /// Index of the rod.
        rod: usize,
        /// What is wrong with the section.
        reason: crate::rod::SectionError,
    },
    /// Two consecutive nodes of a rod coincide.
    #[error("rod {rod}: zero-length edge {a}–{b}")]
    ZeroLengthEdge {
        /// Index of the rod.
        rod: usize,
        /// First node of the edge.
        a: usize,
        /// Second node of the edge.
        b: usize,
    },
    /// The requested first material director is parallel to the rod's first edge.
    #[error("rod {rod}: first director parallel to first edge")]
    DirectorParallel {
        /// Index of the rod.
        rod: usize,
    },
    /// A shell mesh has more nodes than the model, or the rest shape is too short.
    #[error("shell mesh with {mesh_nodes} nodes does not fit the model ({model_nodes} nodes, q_rest of length {q_len})")]
    MeshTooLarge {
        /// Nodes of the mesh.
        mesh_nodes: usize,
        /// Nodes of the model.
        model_nodes: usize,
        /// Length of the rest configuration.
        q_len: usize,
    },
    /// Error-controller settings out of range.
    #[error("error controller needs tol > 0 and 0 < h_min ≤ h_max, got tol = {tol_m} m, h_min = {h_min} s, h_max = {h_max} s")]
    ErrorController {
        /// Local error tolerance (m).
        tol_m: f64,
        /// Smallest step (s).
        h_min: f64,
        /// Largest step (s).
        h_max: f64,
    },
    /// Step sizes out of range.
    #[error("step sizes need 0 < min_dt ≤ dt, both finite, got dt = {dt} s, min_dt = {min_dt} s")]
    StepSizing {
        /// Nominal or first step (s).
        dt: f64,
        /// Smallest step (s).
        min_dt: f64,
    },
}

impl From<InvalidModel> for EngineError {
    fn from(e: InvalidModel) -> Self {
        Self::Invalid(e)
    }
}

/// Why a sparse factorisation (symbolic or numeric) failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Error)]
pub enum SparseError {
    /// An index exceeds what the sparse solver's index type can hold.
    #[error("index overflow")]
    IndexOverflow,
    /// The solver could not allocate its storage.
    #[error("out of memory")]
    OutOfMemory,
    /// LU found no pivot: the matrix is singular.
    #[error("singular matrix (no pivot at elimination step {step})")]
    Singular {
        /// Elimination step without a pivot.
        step: usize,
    },
    /// The CSC pattern handed to the solver is malformed (a bug in the caller).
    #[error("invalid CSC pattern: {0}")]
    InvalidPattern(&'static str),
}

/// Why [`crate::Force::restore_history`] refused a history.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[error("{force}: history of {got} values, expected {expected}")]
pub struct HistoryError {
    /// Name of the force.
    pub force: String,
    /// Values given.
    pub got: usize,
    /// Values this force's history has.
    pub expected: usize,
}

/// Why a time step (or a static solve) failed. The state is left unchanged.
#[derive(Debug, Clone, Error)]
pub enum StepError {
    /// Newton did not converge within the iteration limit.
    #[error("Newton did not converge in {iterations} iterations: residual {residual:.3e} N (tolerance {tolerance:.3e} N), worst DOF {worst_dof}")]
    NotConverged {
        /// Iterations taken.
        iterations: usize,
        /// Final `‖R‖∞` (N).
        residual: f64,
        /// Tolerance it had to meet (N).
        tolerance: f64,
        /// DOF with the largest residual.
        worst_dof: usize,
    },
    /// The residual grew beyond `NewtonOptions::divergence_limit` × its initial value.
    #[error("Newton diverged after {iterations} iterations: residual {residual:.3e} N grew beyond {limit:.0e} × the initial {initial:.3e} N, worst DOF {worst_dof}")]
    Diverged {
        /// Iterations taken.
        iterations: usize,
        /// `‖R‖∞` when the solve was abandoned (N).
        residual: f64,
        /// `‖R‖∞` at the first iterate (N).
        initial: f64,
        /// The divergence limit.
        limit: f64,
        /// DOF with the largest residual.
        worst_dof: usize,
    },
    /// A force, residual or solution became NaN or infinite.
    #[error("non-finite value in {what} (DOF {dof})")]
    NonFinite {
        /// Which quantity.
        what: &'static str,
        /// The first offending DOF.
        dof: usize,
    },
    /// The straight path from the step's start to its solution brings two contact surfaces
    /// together (`Force::max_step` below 1 at the path gap): the step is refused.
    #[error("the step's path brings two surfaces together (contact) at {fraction:.3} of the step")]
    Crossing {
        /// The fraction of the step reached before the pair closes.
        fraction: f64,
    },
    /// The sparsity pattern could not be rebuilt after a force's stencils changed.
    #[error("rebuilding the sparsity pattern failed: {0}")]
    Pattern(String),
    /// The sparse factorisation failed (singular Jacobian).
    #[error("linear solve failed: {0}")]
    Linear(SparseError),
    /// The exact retry's step-size homotopy ([`crate::NewtonOptions::step_homotopy`]) could
    /// not follow the solutions from the current state to the full step: it reached the
    /// fraction `reached` of the step in `solves` sub-solves, the last of which ended with
    /// `last` (a converged one when its budget of sub-solves ran out).
    #[error("step homotopy reached {reached:.4} of the step in {solves} sub-solves; last sub-solve: {}", .last.as_ref().map_or_else(|| "converged".to_string(), |e| e.to_string()))]
    Homotopy {
        /// Fraction of the step reached (0 when no sub-step converged).
        reached: f64,
        /// Sub-solves spent.
        solves: usize,
        /// Why the last sub-solve failed, `None` when it converged.
        last: Option<Box<StepError>>,
    },
}

impl StepError {
    /// The DOF the error points at, if any (for a homotopy, its last failed sub-solve's).
    pub fn dof(&self) -> Option<usize> {
        match self {
            Self::NotConverged { worst_dof, .. } | Self::Diverged { worst_dof, .. } => {
                Some(*worst_dof)
            }
            Self::NonFinite { dof, .. } => Some(*dof),
            Self::Linear(_) | Self::Crossing { .. } | Self::Pattern(_) => None,
            Self::Homotopy { last, .. } => last.as_ref().and_then(|e| e.dof()),
        }
    }
}

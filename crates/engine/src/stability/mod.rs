//! The steady descent as an equilibrium, and its modes.
//!
//! A body that falls at a constant velocity `V` with a fixed shape satisfies `F(q, v) = 0` with
//! every node moving at `V` (twist angles at rest): [`steady_descent`] solves it by Newton in the
//! frame that falls with the body (one node's position held, `V` unknown). Its small motions
//! obey the linearised equations `M δ̈ = K δ + C δ̇` with `K = ∂F/∂q` and `C = ∂F/∂v` (the exact
//! Jacobians the step solver assembles), whose modes `δ = φ e^{λt}` solve the quadratic
//! eigenproblem `(λ² M − λ C − K) φ = 0`. [`modes`] finds those with the largest real parts by
//! a Cayley transform of its companion form and faer's Krylov–Schur iteration
//! (`faer::matrix_free::eigen::partial_eigen`); every application costs one sparse LU solve
//! with `P(σ) = σ² M − σ C − K` (Tisseur & Meerbergen, "The quadratic eigenvalue problem",
//! SIAM Review 43, 2001; Meerbergen & Roose, IMA J. Numer. Anal. 16, 1996).
//!
//! Forces that act through a step's change of momentum (the air's added mass) give no force
//! and no Jacobian outside a step ([`crate::force::NO_STEP`]), so they are not in `K` or `C`.
//! Forces that hold quantities over a step (the incidence law's axis and windward excess)
//! keep those of the model's last commit while Newton finds the equilibrium (a transient's
//! end, near it), and [`Linearized::at`] adds their dependence on the state
//! ([`crate::force::Force::lag_coupling`]).

mod linearize;
mod modes;
mod steady;
#[cfg(test)]
mod tests;

pub use linearize::{Coupling, Linearized, PencilSolver};
pub use modes::{modes, Mode, ModeOptions, DENSE_UP_TO, NEUTRAL_RATE, NEUTRAL_SHOWN};
pub use steady::{steady_descent, Steady, SteadyOptions};

/// Why an equilibrium or its modes could not be computed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum StabilityError {
    /// The model holds some DOFs fixed: it cannot fall as a whole.
    #[error("the model fixes {0} DOFs: a steady descent needs every node free")]
    FixedDofs(usize),
    /// A sparse LU factorisation failed (a singular or non-finite matrix).
    #[error("the linearised equations are singular at this state ({0})")]
    Singular(String),
    /// Newton did not reach the tolerance.
    #[error(
        "no steady descent found: ‖R‖∞ = {residual:.3e} N after {iterations} Newton iterations (tolerance {tolerance:.3e} N); start nearer to it (a longer flight first)"
    )]
    NotConverged {
        /// Iterations done.
        iterations: usize,
        /// The last residual (N).
        residual: f64,
        /// The tolerance asked for (N).
        tolerance: f64,
    },
    /// The held node is not a node of the model.
    #[error("node {node} is not a node of the model ({n_nodes} nodes)")]
    NoSuchNode {
        /// The node asked for.
        node: usize,
        /// Nodes of the model.
        n_nodes: usize,
    },
}

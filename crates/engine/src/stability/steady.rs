//! The steady descent: positions `q` and one velocity `V` of every node with `F(q, v(V)) = 0`,
//! solved by Newton with one node's position held (the frame falls with the body).
//!
//! Unknowns: every free DOF but the held node's three, and `V` (three). Equations: `F = 0` on
//! every free DOF. The system is square; its Jacobian has `K`'s columns for the positions and,
//! for `V_c`, the sum of `C`'s columns over the DOFs of coordinate `c` (a uniform velocity
//! change), factorised by sparse LU.

use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::{Lu, SymbolicLu};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::Col;

use super::{Linearized, StabilityError};
use crate::model::Model;

/// How the equilibrium is solved.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SteadyOptions {
    /// Converged when `‖F‖∞` on the free DOFs is at most this (N).
    pub tolerance_n: f64,
    /// Newton iterations at most.
    pub max_iterations: usize,
    /// The node whose position is held (the payload, or any node of the canopy).
    pub hold: usize,
}

impl SteadyOptions {
    /// The step solver's default tolerance, `10⁻⁹ (1 N + m g)` for total mass `m`, 50
    /// iterations, holding `hold`.
    pub fn recommended(model: &Model, gravity: f64, hold: usize) -> Self {
        Self {
            tolerance_n: 1e-9 * (1.0 + model.total_mass() * gravity),
            max_iterations: 50,
            hold,
        }
    }
}

/// A steady descent.
#[derive(Debug, Clone, PartialEq)]
pub struct Steady {
    /// Positions (the held node where it was given).
    pub q: Vec<f64>,
    /// Velocities: `V` on every node, twist rates 0.
    pub v: Vec<f64>,
    /// The common velocity `V` of the nodes (m/s).
    pub velocity: [f64; 3],
    /// `‖F‖∞` on the free DOFs at the solution (N).
    pub residual_n: f64,
    /// Newton iterations taken.
    pub iterations: usize,
}

/// Every node moving at `vel`, twist angles at rest.
fn uniform(n_dofs: usize, n_translational: usize, vel: [f64; 3]) -> Vec<f64> {
    (0..n_dofs)
        .map(|d| if d < n_translational { vel[d % 3] } else { 0.0 })
        .collect()
}

/// `‖F‖∞` over the free DOFs of `lin`.
fn residual(lin: &Linearized) -> f64 {
    lin.dof_of
        .iter()
        .map(|&d| lin.force[d].abs())
        .fold(0.0, f64::max)
}

/// The Newton matrix of the unknowns (module docs): its pattern (fixed) and values.
struct Bordered {
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    /// Per unknown position column: the free DOF it is.
    position_cols: Vec<usize>,
}

impl Bordered {
    fn new(lin: &Linearized, held: &[usize; 3]) -> Self {
        let n = lin.n_free;
        let position_cols: Vec<usize> = (0..n).filter(|r| !held.contains(r)).collect();
        let (mut col_ptr, mut row_idx) = (vec![0], Vec::new());
        for &r in &position_cols {
            row_idx.extend_from_slice(&lin.row_idx[lin.col_ptr[r]..lin.col_ptr[r + 1]]);
            col_ptr.push(row_idx.len());
        }
        for _ in 0..3 {
            row_idx.extend(0..n);
            col_ptr.push(row_idx.len());
        }
        Self {
            col_ptr,
            row_idx,
            position_cols,
        }
    }

    fn pattern(&self, n: usize) -> SymbolicSparseColMatRef<'_, usize> {
        SymbolicSparseColMatRef::new_checked(n, n, &self.col_ptr, None, &self.row_idx)
    }

    /// The values at `lin`: `K`'s columns, then `Σ C[:, r]` over each coordinate's DOFs.
    fn values(&self, lin: &Linearized) -> Vec<f64> {
        let mut vals = Vec::with_capacity(self.row_idx.len());
        for &r in &self.position_cols {
            vals.extend_from_slice(&lin.k[lin.col_ptr[r]..lin.col_ptr[r + 1]]);
        }
        let mut dense = vec![0.0; 3 * lin.n_free];
        for (col, &d) in lin.dof_of.iter().enumerate() {
            if d >= lin.n_translational {
                continue;
            }
            let out = &mut dense[(d % 3) * lin.n_free..][..lin.n_free];
            for k in lin.col_ptr[col]..lin.col_ptr[col + 1] {
                out[lin.row_idx[k]] += lin.c[k];
            }
        }
        vals.extend_from_slice(&dense);
        vals
    }
}

/// The steady descent of `model` nearest to positions `q` and common node velocity
/// `velocity` (a run's state near terminal speed), at time `t`.
pub fn steady_descent(
    model: &Model,
    q: &[f64],
    velocity: [f64; 3],
    t: f64,
    opts: &SteadyOptions,
) -> Result<Steady, StabilityError> {
    let fixed = model.fixed.iter().filter(|&&f| f).count();
    if fixed > 0 {
        return Err(StabilityError::FixedDofs(fixed));
    }
    let n_nodes = model.layout.n_nodes;
    if opts.hold >= n_nodes {
        return Err(StabilityError::NoSuchNode {
            node: opts.hold,
            n_nodes,
        });
    }
    let nt = 3 * n_nodes;
    let (mut q, mut vel) = (q.to_vec(), velocity);
    let mut lin = Linearized::at(model, &q, &uniform(q.len(), nt, vel), t);
    let row_of = |lin: &Linearized, d: usize| lin.dof_of.iter().position(|&x| x == d);
    let held = [0, 1, 2].map(|k| row_of(&lin, 3 * opts.hold + k).unwrap_or(usize::MAX));
    let bordered = Bordered::new(&lin, &held);
    let n = lin.n_free;
    let symbolic = SymbolicLu::try_new(bordered.pattern(n))
        .map_err(|e| StabilityError::Singular(e.to_string()))?;
    let mut res = residual(&lin);
    for it in 0..opts.max_iterations {
        if res <= opts.tolerance_n {
            return Ok(done(q, vel, nt, res, it));
        }
        let vals = bordered.values(&lin);
        let mat = SparseColMatRef::new(bordered.pattern(n), &vals);
        let lu = Lu::try_new_with_symbolic(symbolic.clone(), mat)
            .map_err(|e| StabilityError::Singular(format!("{e:?}")))?;
        // J Δ = −F: J = ∂F/∂(unknowns).
        let mut delta = Col::<f64>::from_fn(n, |r| -lin.force[lin.dof_of[r]]);
        lu.solve_in_place(delta.as_mat_mut());
        let mut step = 1.0;
        loop {
            let mut q_try = q.clone();
            for (j, &r) in bordered.position_cols.iter().enumerate() {
                q_try[lin.dof_of[r]] += step * delta[j];
            }
            let m = bordered.position_cols.len();
            let v_try = [0, 1, 2].map(|c| vel[c] + step * delta[m + c]);
            let trial = Linearized::at(model, &q_try, &uniform(q.len(), nt, v_try), t);
            let r_try = residual(&trial);
            if r_try < res || step < 1e-3 {
                (q, vel, lin, res) = (q_try, v_try, trial, r_try);
                break;
            }
            step *= 0.5;
        }
    }
    if res <= opts.tolerance_n {
        return Ok(done(q, vel, nt, res, opts.max_iterations));
    }
    Err(StabilityError::NotConverged {
        iterations: opts.max_iterations,
        residual: res,
        tolerance: opts.tolerance_n,
    })
}

fn done(q: Vec<f64>, velocity: [f64; 3], nt: usize, residual_n: f64, iterations: usize) -> Steady {
    let v = uniform(q.len(), nt, velocity);
    Steady {
        q,
        v,
        velocity,
        residual_n,
        iterations,
    }
}

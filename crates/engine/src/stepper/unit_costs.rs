//! Warm unit costs of the step solver's parts at a given state (`chute bench --units`): what
//! one residual, one Jacobian assembly, one factorisation and one pair of triangular solves
//! cost, measured on the model's own Newton matrix.

use std::time::Instant;

use faer::Par;

use super::controller::ImplicitEuler;
use crate::assembly::Coefficients;
use crate::force::EvalInput;
use crate::model::{Model, State};

/// Median wall times (ms) of the solver's unit operations at one state.
#[derive(Debug, Clone, Copy, Default)]
pub struct UnitCosts {
    /// Residual (forces only).
    pub residual_ms: f64,
    /// Forces and Jacobian values.
    pub jacobian_ms: f64,
    /// Symmetric part `½ (J + Jᵀ)`.
    pub symmetric_part_ms: f64,
    /// LLᵀ (or LBLᵀ) on one thread.
    pub llt_ms: f64,
    /// LLᵀ on rayon's pool.
    pub llt_par_ms: f64,
    /// One pair of triangular solves.
    pub solve_ms: f64,
    /// One sparse product `J x`.
    pub spmv_ms: f64,
    /// Stored entries of the Cholesky factor.
    pub factor_entries: usize,
    /// Stored entries of J.
    pub nnz: usize,
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.partial_cmp(b).unwrap());
    v[v.len() / 2]
}

fn time(reps: usize, mut f: impl FnMut()) -> f64 {
    f();
    median(
        (0..reps)
            .map(|_| {
                let t = Instant::now();
                f();
                1e3 * t.elapsed().as_secs_f64()
            })
            .collect(),
    )
}

impl ImplicitEuler {
    /// Measure [`UnitCosts`] at `state` for a step of `dt` (each operation `reps` times after
    /// one warm-up; medians).
    pub fn unit_costs(&mut self, model: &Model, state: &State, dt: f64, reps: usize) -> UnitCosts {
        let (ws, lin) = self.parts();
        let n = state.q.len();
        let v: Vec<f64> = vec![0.0; n];
        let mut force = vec![0.0; n];
        let mut values = vec![0.0; ws.asm.nnz()];
        let c = Coefficients {
            c_m: 1.0 / (dt * dt),
            c_q: 1.0,
            c_v: 1.0 / dt,
        };
        let mk = |jac| EvalInput {
            q: &state.q,
            v: &v,
            t: state.t,
            jacobian: jac,
            dt,
        };
        let mut out = UnitCosts {
            nnz: ws.asm.nnz(),
            ..UnitCosts::default()
        };
        out.residual_ms = time(reps, || {
            ws.asm.assemble(model, &mk(false), &mut force, None)
        });
        out.jacobian_ms = time(reps, || {
            ws.asm
                .assemble(model, &mk(true), &mut force, Some((&mut values, c)))
        });
        let mut sym = vec![0.0; values.len()];
        out.symmetric_part_ms = time(reps, || ws.asm.symmetric_part(&values, &mut sym));
        let solver = lin.solver_mut();
        let par = solver.par;
        solver.par = Par::Seq;
        out.llt_ms = time(reps, || {
            solver.factor(&sym);
        });
        solver.par = Par::rayon(0);
        out.llt_par_ms = time(reps, || {
            solver.factor(&sym);
        });
        solver.par = Par::Seq;
        let mut x = vec![1.0; ws.asm.n_free];
        out.solve_ms = time(reps, || solver.solve(&mut x));
        out.factor_entries = solver.factor_entries();
        let a = &ws.asm;
        let mut y = vec![0.0; a.n_free];
        out.spmv_ms = time(reps, || {
            y.iter_mut().for_each(|e| *e = 0.0);
            for col in 0..a.n_free {
                let xc = x[col];
                for k in a.col_ptr[col]..a.col_ptr[col + 1] {
                    y[a.row_idx[k]] += values[k] * xc;
                }
            }
        });
        solver.par = par;
        lin.invalidate();
        out
    }
}

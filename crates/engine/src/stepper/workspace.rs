//! The buffers every stage of the step solver works in, the residual of one step and its
//! evaluation (all allocated once, when the stepper is built).
//!
//! A step solves `R(q) = c_m M (q − q̃) − F(q, c_v (q − q_n)) = 0` over the free DOFs
//! ([`Target`]): implicit Euler has `c_m = 1/h²`, `q̃ = q_n + h v_n`, `c_v = 1/h`; statics has
//! `c_m = c_v = 0`. Its Jacobian is `J = c_m M − ∂F/∂q − c_v ∂F/∂v`.

use std::time::Instant;

use crate::assembly::{Assembler, Coefficients};
use crate::force::EvalInput;
use crate::model::Model;
use crate::stepper::options::Counters;

/// The target of one solve.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Target<'a> {
    /// Mass coefficient `c_m` (1/s²).
    pub c_m: f64,
    /// Velocity coefficient `c_v` (1/s).
    pub c_v: f64,
    /// `q̃`, where the inertia term vanishes (all DOFs).
    pub q_tilde: &'a [f64],
    /// `q_n`, the state the step starts from (all DOFs).
    pub q_n: &'a [f64],
    /// Time at the end of the step (s).
    pub t: f64,
}

/// Buffers and the residual evaluation shared by the stages.
pub(crate) struct Workspace {
    /// The sparse pattern and scatter maps (free DOFs only).
    pub asm: Assembler,
    /// Values of `J` in the pattern, from the last evaluation with a Jacobian.
    pub values: Vec<f64>,
    /// Total force `F` (all DOFs).
    force: Vec<f64>,
    /// `R` at the last evaluated iterate (free DOFs).
    pub residual: Vec<f64>,
    /// Velocities `c_v (q − q_n)` of the last evaluation (all DOFs).
    v: Vec<f64>,
    /// The current update `Δ` (free DOFs).
    pub delta: Vec<f64>,
    /// A trial iterate (all DOFs).
    pub q_trial: Vec<f64>,
    /// `Σ_j |∂F_i/∂q_j + c_v ∂F_i/∂v_j| |q_j|` per free row at the last Jacobian (N): how much
    /// `R_i` changes when every coordinate moves by its own relative round-off, which sets
    /// the row's round-off floor (`convergence.rs`).
    pub force_roundoff: Vec<f64>,
    /// `|R_i(q ⊕ 1 ulp) − R_i(q)|` per free row, measured where an iteration stalled
    /// ([`Workspace::measure_noise`]; zero until then): the residual's actual round-off.
    pub noise: Vec<f64>,
    /// The residual kept across a noise measurement.
    saved: Vec<f64>,
    /// Mass of each free DOF.
    pub mass: Vec<f64>,
    /// `‖R‖∞` after each iteration of the last solve (the predictor first).
    pub history: Vec<f64>,
    /// A move of an iterate (all DOFs), for the forces' step bound.
    dir: Vec<f64>,
    /// What the solves did.
    pub counters: Counters,
}

/// A move of an iterate keeps every contact pair above this fraction of its distance
/// (`Force::max_step`; IPC's line search keeps 0.1–0.2, Li et al. 2021, Algorithm 1).
pub const ITERATE_GAP: f64 = 0.1;
/// A step's solution is accepted only if the straight path to it from the step's start
/// keeps every contact pair above this fraction of its distance: no surface passed through
/// another during the step, whichever stage solved it.
pub const PATH_GAP: f64 = 1e-3;

impl Workspace {
    /// Allocate every buffer for `model` (its pattern is analysed here, once).
    pub fn new(model: &Model, max_history: usize) -> Self {
        let asm = Assembler::new(model);
        let (n, nf) = (model.n_dofs(), asm.n_free);
        Self {
            values: vec![0.0; asm.nnz()],
            force: vec![0.0; n],
            residual: vec![0.0; nf],
            v: vec![0.0; n],
            delta: vec![0.0; nf],
            q_trial: vec![0.0; n],
            force_roundoff: vec![0.0; nf],
            noise: vec![0.0; nf],
            saved: vec![0.0; nf],
            mass: asm.dof_of.iter().map(|&d| model.mass[d]).collect(),
            history: Vec::with_capacity(max_history),
            dir: if model.bounds_steps() {
                vec![0.0; n]
            } else {
                Vec::new()
            },
            counters: Counters::default(),
            asm,
        }
    }

    /// Number of free DOFs.
    pub fn n_free(&self) -> usize {
        self.asm.n_free
    }

    /// Evaluate `R(q)` into [`Workspace::residual`] (and `J` into [`Workspace::values`] when
    /// `jac`); returns `‖R‖₂`.
    pub fn evaluate(&mut self, model: &Model, q: &[f64], tg: &Target<'_>, jac: bool) -> f64 {
        for d in 0..q.len() {
            self.v[d] = tg.c_v * (q[d] - tg.q_n[d]);
        }
        let input = EvalInput {
            q,
            v: &self.v,
            t: tg.t,
            jacobian: jac,
            dt: 1.0 / tg.c_v,
        };
        let coeffs = Coefficients {
            c_m: tg.c_m,
            c_q: 1.0,
            c_v: tg.c_v,
        };
        let values = jac.then_some((&mut self.values[..], coeffs));
        let t0 = Instant::now();
        self.asm.assemble(model, &input, &mut self.force, values);
        self.counters.assembly_s += t0.elapsed().as_secs_f64();
        self.counters.evaluations += 1;
        self.counters.jacobian_evaluations += u64::from(jac);
        if jac {
            self.record_roundoff(q, tg.c_m);
        }
        let mut norm2 = 0.0;
        for (r, &d) in self.asm.dof_of.iter().enumerate() {
            let x = tg.c_m * self.mass[r] * (q[d] - tg.q_tilde[d]) - self.force[d];
            self.residual[r] = x;
            norm2 += x * x;
        }
        norm2.sqrt()
    }

    /// [`Workspace::force_roundoff`] of the Jacobian just assembled at `q` (the inertia term
    /// taken out of the diagonal: it is added with the current `c_m` when judged).
    fn record_roundoff(&mut self, q: &[f64], c_m: f64) {
        let a = &self.asm;
        self.force_roundoff.iter_mut().for_each(|x| *x = 0.0);
        for c in 0..a.n_free {
            let qc = q[a.dof_of[c]].abs();
            for k in a.col_ptr[c]..a.col_ptr[c + 1] {
                let r = a.row_idx[k];
                let inertia = if r == c { c_m * self.mass[r] } else { 0.0 };
                self.force_roundoff[r] += (self.values[k] - inertia).abs() * qc;
            }
        }
        for (gamma, u) in a.low_rank.terms() {
            let s: f64 = (u.iter().zip(&a.dof_of))
                .map(|(u, &d)| (u * q[d]).abs())
                .sum();
            for (x, u) in self.force_roundoff.iter_mut().zip(u) {
                *x += (gamma * u).abs() * s;
            }
        }
    }

    /// Measure the residual's round-off at `q` (its residual in [`Workspace::residual`], which
    /// is kept): every free coordinate moved by one unit in the last place (up on even rows,
    /// down on odd ones, so the probe is the same in every run), `R` evaluated there, and
    /// [`Workspace::noise`] raised to the change of each row. One residual evaluation.
    pub fn measure_noise(&mut self, model: &Model, q: &[f64], tg: &Target<'_>) {
        self.saved.copy_from_slice(&self.residual);
        self.q_trial.copy_from_slice(q);
        for (r, &d) in self.asm.dof_of.iter().enumerate() {
            let x = q[d];
            self.q_trial[d] = if r % 2 == 0 {
                x.next_up()
            } else {
                x.next_down()
            };
        }
        let qt = std::mem::take(&mut self.q_trial);
        self.evaluate(model, &qt, tg, false);
        self.q_trial = qt;
        for ((n, r), s) in self.noise.iter_mut().zip(&self.residual).zip(&self.saved) {
            *n = n.max((r - s).abs());
        }
        self.residual.copy_from_slice(&self.saved);
        self.counters.noise_probes += 1;
    }

    /// Keep the residual of the current iterate aside (one slot; [`Workspace::measure_noise`]
    /// uses the same slot).
    pub fn save_residual(&mut self) {
        self.saved.copy_from_slice(&self.residual);
    }

    /// The residual kept by [`Workspace::save_residual`], back in [`Workspace::residual`].
    pub fn restore_residual(&mut self) {
        self.residual.copy_from_slice(&self.saved);
    }

    /// Forget the measured noise (a new run segment: sync point).
    pub fn forget_noise(&mut self) {
        self.noise.iter_mut().for_each(|x| *x = 0.0);
    }

    /// `‖R‖∞` and the DOF where it is reached (a NaN residual is always the worst).
    pub fn inf_norm(&self) -> (f64, usize) {
        let mut worst = (0.0, 0);
        for (r, &x) in self.residual.iter().enumerate() {
            if x.is_nan() || x.abs() > worst.0 {
                worst = (x.abs(), self.asm.dof_of[r]);
            }
        }
        worst
    }

    /// `R · Δ`: the slope of the step's merit along the update (`stage/newton.rs`).
    pub fn slope(&self) -> f64 {
        self.residual
            .iter()
            .zip(&self.delta)
            .map(|(r, d)| r * d)
            .sum()
    }

    /// `‖Δ‖∞`, or the first DOF where `Δ` is not finite.
    pub fn delta_max(&self) -> Result<f64, usize> {
        let mut m = 0.0f64;
        for (r, &d) in self.delta.iter().enumerate() {
            if !d.is_finite() {
                return Err(self.asm.dof_of[r]);
            }
            m = m.max(d.abs());
        }
        Ok(m)
    }

    /// Evaluate `R` at `q + α Δ` (into [`Workspace::q_trial`] and the residual); `‖R‖₂`.
    pub fn try_update(
        &mut self,
        model: &Model,
        q: &[f64],
        tg: &Target<'_>,
        alpha: f64,
        jac: bool,
    ) -> f64 {
        self.q_trial.copy_from_slice(q);
        for (r, &d) in self.asm.dof_of.iter().enumerate() {
            self.q_trial[d] += alpha * self.delta[r];
        }
        let qt = std::mem::take(&mut self.q_trial);
        let norm = self.evaluate(model, &qt, tg, jac);
        self.q_trial = qt;
        norm
    }

    /// Shorten the move from `from` to `to` (all DOFs) to the fraction the model's forces
    /// admit (`Force::max_step` with `gap`); returns that fraction (1: `to` unchanged).
    pub fn bound_move(&mut self, model: &Model, from: &[f64], to: &mut [f64], gap: f64) -> f64 {
        if self.dir.is_empty() {
            return 1.0;
        }
        for (d, (a, b)) in self.dir.iter_mut().zip(from.iter().zip(to.iter())) {
            *d = b - a;
        }
        let t = model.max_step(from, &self.dir, gap);
        if t < 1.0 {
            for (x, (a, d)) in to.iter_mut().zip(from.iter().zip(&self.dir)) {
                *x = a + t * d;
            }
            self.counters.bounded_moves += 1;
        }
        t
    }

    /// The largest `α ≤ 1` the model's forces admit for the update `q + α Δ` (1 for a model
    /// without step bounds).
    pub fn max_alpha(&mut self, model: &Model, q: &[f64]) -> f64 {
        if self.dir.is_empty() {
            return 1.0;
        }
        self.dir.iter_mut().for_each(|x| *x = 0.0);
        self.scatter_delta();
        let t = model.max_step(q, &self.dir, ITERATE_GAP);
        if t < 1.0 {
            self.counters.bounded_moves += 1;
        }
        t
    }

    fn scatter_delta(&mut self) {
        for (r, &d) in self.asm.dof_of.iter().enumerate() {
            self.dir[d] = self.delta[r];
        }
    }

    /// The free DOFs of `q` into `x`.
    pub fn gather(&self, q: &[f64], x: &mut [f64]) {
        for (r, &d) in self.asm.dof_of.iter().enumerate() {
            x[r] = q[d];
        }
    }

    /// `x` into the free DOFs of `q`.
    pub fn scatter(&self, x: &[f64], q: &mut [f64]) {
        for (r, &d) in self.asm.dof_of.iter().enumerate() {
            q[d] = x[r];
        }
    }
}

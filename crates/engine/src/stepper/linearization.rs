//! The linearisation the stages solve with: which matrix is factorised, when it was, and how
//! its factors turn a residual into an update.
//!
//! **What is factorised.** The symmetric part `J_s = ½ (J + Jᵀ)` of the step's Jacobian (it
//! is `J` itself unless drag makes `J` non-symmetric), optionally shifted by `σ W` (the
//! descent shift and the continuation stage; [`Linearization::refresh`]), by Cholesky LLᵀ,
//! or LBLᵀ on the same structure where it is indefinite. Never LU: on the bundled shells an
//! LU costs about 8 LLᵀ and needs its own structure several times the Cholesky factor's size
//! (docs/performance.md).
//!
//! **Updates.** The *chord* update `Δ = −J_s⁻¹ R` needs only the held factors (the held
//! stage, and modified-Newton iterations). The *Newton* update solves `J Δ = −R` with the
//! Jacobian the factors were computed from: since `J Δ + R = (J − J_s) Δ` for the chord
//! update, one product with the skew part measures how far it is from Newton's. Where that
//! relative linearised residual exceeds the forcing term `η` the stage asks for, the update is
//! corrected by BiCGStab to `η`, preconditioned with the held factors (`linsolve/krylov.rs`),
//! which converges in a few iterations because `J_s⁻¹ J = I + J_s⁻¹ (J − J_s)` is a small
//! perturbation of the identity. An inexact Newton iteration with `η_k ∝ ‖R_k‖` converges
//! quadratically like the exact one (Dembo, Eisenstat & Steihaug, SIAM J. Numer. Anal. 19(2),
//! 1982).
//!
//! **Precision.** Single-precision factors solve `J_s` only to about `ε₃₂ κ`; that is the
//! chord iteration's business (it contracts or it does not), but a Newton update must meet
//! its forcing term. With `f32` factors the Newton update is therefore always checked against
//! the full `J` (`‖J Δ + R‖ ≤ η ‖R‖`) and corrected by BiCGStab; where even the correction
//! fails (κ beyond `1/ε₃₂`: the 10,000-node rod's edges of 0.6 mm), the factors switch to
//! double precision for the rest of the run and the update is computed again.
//!
//! **Low-rank part.** A force's low-rank velocity Jacobian is not in the pattern: the factors
//! are completed with it by Sherman–Morrison–Woodbury (`linsolve/low_rank.rs`, one more solve
//! per term), and every product with `J` includes it.
//!
//! Models with a low-rank part always factorise in double precision: where the part
//! dominates (an added mass many times the canopy's own), single-precision factors made the
//! chord and Newton iterations stall near the tolerance. Measured on the 3 m canopy's opening
//! at 0.25 m (1 s, CST membrane, the law's first, axial-only version): 40 s with `f32` factors
//! against 2.4 s with `f64` (docs/notes/added-mass-2026-12-07.md).
//!
//! **Keys.** The factors are valid for one `(c_m, c_v, σ)`: a step of another size, or a
//! shifted matrix, needs new ones. Whether held factors from earlier steps are still good
//! enough is not known in advance; the stages measure it by the contraction they achieve.

use std::time::Instant;

use super::workspace::{Target, Workspace};
use crate::error::EngineError;
use crate::linsolve::{Factorization, LinearSolver, Precision};

/// Most BiCGStab iterations of one correction (each: two products with `J`, two pairs of
/// triangular solves).
const KRYLOV_MAX: usize = 20;

/// The factor precision `opts` ask for.
pub(crate) fn precision(opts: &crate::stepper::options::NewtonOptions) -> Precision {
    if opts.single_precision_factors {
        Precision::Single
    } else {
        Precision::Double
    }
}

/// The held factorisation and what it was computed for.
pub(crate) struct Linearization {
    solver: LinearSolver,
    /// `J_s` (+ `σ W`) in the pattern's values (empty when `J` is symmetric).
    sym: Vec<f64>,
    /// `J Δ + R`, the linearised residual of an update (free DOFs).
    linear_residual: Vec<f64>,
    /// `−R` for the Krylov correction, and the chord update kept in case it fails.
    rhs: Vec<f64>,
    chord: Vec<f64>,
    /// `(c_m, c_v, σ)` of the held factors.
    key: Option<(f64, f64, f64)>,
    /// The held factors are of the Jacobian now in the workspace's values (a Newton update
    /// can be corrected against it).
    current: bool,
    /// `μ` of the shift `μ W` already in the workspace's values (since the last evaluation
    /// with a Jacobian).
    values_shift: f64,
    /// The shift's diagonal metric `W_r = max(c_m m_r, −J_rr)` (free DOFs), taken from the
    /// unshifted Jacobian when it is first shifted ([`Linearization::refresh`]).
    metric: Vec<f64>,
    /// The held factors are not completed with the Jacobian's low-rank part (its Woodbury
    /// matrix was singular): a Newton update must be checked against the full `J`.
    incomplete: bool,
}

impl Linearization {
    /// The symbolic analysis of the workspace's pattern (done once).
    pub fn new(ws: &Workspace, precision: Precision) -> Result<Self, EngineError> {
        let a = &ws.asm;
        // A low-rank part is factorised in double precision (module docs, §Precision).
        let precision = match a.low_rank_terms > 0 {
            true => Precision::Double,
            false => precision,
        };
        let solver = if a.ordered {
            LinearSolver::new_ordered(a.n_free, &a.col_ptr, &a.row_idx, precision)?
        } else {
            LinearSolver::new(a.n_free, &a.col_ptr, &a.row_idx)?
        };
        let sym = if a.symmetric {
            Vec::new()
        } else {
            vec![0.0; a.nnz()]
        };
        Ok(Self {
            solver,
            sym,
            linear_residual: vec![0.0; a.n_free],
            rhs: vec![0.0; a.n_free],
            chord: vec![0.0; a.n_free],
            key: None,
            current: false,
            values_shift: 0.0,
            metric: vec![0.0; a.n_free],
            incomplete: false,
        })
    }

    /// Whether the held factors are of the unshifted Newton matrix of `tg`'s step size.
    pub fn held_for(&self, tg: &Target<'_>) -> bool {
        self.key == Some((tg.c_m, tg.c_v, 0.0))
    }

    /// Forget the held factors.
    pub fn invalidate(&mut self) {
        self.key = None;
        self.current = false;
        self.solver.invalidate();
    }

    /// The Jacobian in the workspace's values changed (a new evaluation with a Jacobian): the
    /// held factors are no longer of it, and it carries no added inertia.
    pub fn jacobian_changed(&mut self) {
        self.current = false;
        self.values_shift = 0.0;
    }

    /// Factorise `J_s + σ W` from the Jacobian in `ws.values`, which is shifted in place to
    /// `J + σ W` (so that a Newton update solves the shifted system; a later call with another
    /// `σ` on the same Jacobian adds only the difference). `W = max(c_m M, −diag J)` per DOF:
    /// the inertia, or the diagonal's own negative curvature where that is larger, so that no
    /// diagonal entry of `J + σW` is negative for `σ ≥ 1`. A mass metric alone cannot shift a
    /// DOF of negligible inertia (mid-edge bending's edge angle, whose energy is concave in a
    /// sharp fold: docs/engine.md §Descent); where the diagonal is positive (stiffness, drag)
    /// the shift stays the inertia's, which a stronger one would only slow.
    pub fn refresh(&mut self, ws: &mut Workspace, tg: &Target<'_>, shift: f64) -> Factorization {
        let extra = shift - self.values_shift;
        if extra != 0.0 {
            let a = &ws.asm;
            if self.values_shift == 0.0 {
                for ((w, &k), &m) in self.metric.iter_mut().zip(&a.diag).zip(&ws.mass) {
                    *w = (tg.c_m * m).max(-ws.values[k]);
                }
            }
            for (&k, &w) in a.diag.iter().zip(&self.metric) {
                ws.values[k] += extra * w;
            }
            self.values_shift = shift;
        }
        if !self.sym.is_empty() {
            ws.asm.symmetric_part(&ws.values, &mut self.sym);
        }
        let fac = self.factor(ws);
        self.key = Some((tg.c_m, tg.c_v, shift));
        self.current = true;
        fac
    }

    /// Factorise the symmetric matrix of the Jacobian in the workspace (`self.sym`, or the
    /// values themselves when `J` is symmetric), completed with its low-rank part.
    fn factor(&mut self, ws: &mut Workspace) -> Factorization {
        let t0 = Instant::now();
        let spd = if self.sym.is_empty() {
            &ws.values
        } else {
            &self.sym
        };
        let fac = self.solver.factor(spd);
        let part = &ws.asm.low_rank;
        self.incomplete = part.rank() > 0 && !self.solver.complete(part);
        let c = &mut ws.counters;
        c.factor_s += t0.elapsed().as_secs_f64();
        c.factorizations += 1;
        c.indefinite_factorizations += u64::from(fac == Factorization::Lblt);
        fac
    }

    /// `x ← A⁻¹ x` with the held factors `A`.
    pub fn apply(&mut self, ws: &mut Workspace, x: &mut [f64]) {
        let t0 = Instant::now();
        self.solver.solve(x);
        ws.counters.solve_s += t0.elapsed().as_secs_f64();
    }

    /// The chord update `Δ = −A⁻¹ R` into `ws.delta` (one iteration).
    pub fn chord(&mut self, ws: &mut Workspace) {
        self.apply_chord(ws);
        ws.counters.iterations += 1;
    }

    fn apply_chord(&mut self, ws: &mut Workspace) {
        let mut delta = std::mem::take(&mut ws.delta);
        for (d, r) in delta.iter_mut().zip(&ws.residual) {
            *d = -r;
        }
        self.apply(ws, &mut delta);
        ws.delta = delta;
    }

    /// The Newton update `J Δ = −R` into `ws.delta` to the relative linearised residual
    /// `eta` (the forcing term): the chord update, corrected by BiCGStab where the skew part
    /// of `J`, or the rounding of single-precision factors, makes it too far from Newton's
    /// (module docs). Only the chord update when the factors are not of the Jacobian in
    /// `ws.values`.
    pub fn newton(&mut self, ws: &mut Workspace, eta: f64) {
        self.chord(ws);
        let single = self.solver.precision() == Precision::Single;
        if !self.current || (self.sym.is_empty() && !single && !self.incomplete) {
            return;
        }
        if self.linear_residual_ratio(ws) <= eta || self.correct(ws, eta) {
            return;
        }
        if single {
            // The factors are too coarse to precondition this matrix: double precision from
            // now on (module docs), and the update again.
            self.solver.set_precision(Precision::Double);
            self.factor(ws);
            self.apply_chord(ws);
            if self.linear_residual_ratio(ws) > eta {
                self.correct(ws, eta);
            }
        }
    }

    /// BiCGStab from the chord update in `ws.delta` to `eta`; whether it converged (if not,
    /// the chord update is kept and the stage's contraction test decides).
    fn correct(&mut self, ws: &mut Workspace, eta: f64) -> bool {
        for (b, r) in self.rhs.iter_mut().zip(&ws.residual) {
            *b = -r;
        }
        self.chord.copy_from_slice(&ws.delta);
        let t0 = Instant::now();
        let rep =
            self.solver
                .solve_corrected(&ws.values, &self.rhs, &mut ws.delta, eta, KRYLOV_MAX);
        let c = &mut ws.counters;
        c.solve_s += t0.elapsed().as_secs_f64();
        c.krylov_iterations += rep.iterations as u64;
        let ok = rep.converged && ws.delta.iter().all(|d| d.is_finite());
        if !ok {
            c.krylov_failures += 1;
            ws.delta.copy_from_slice(&self.chord);
        }
        ok
    }

    /// `‖J Δ + R‖∞ / ‖R‖∞` for the update in `ws.delta`, `J` the (shifted) Jacobian in
    /// `ws.values`: zero for exact factors of a symmetric `J`, `‖(J − J_s) Δ‖∞ / ‖R‖∞` for
    /// exact factors of its symmetric part.
    fn linear_residual_ratio(&mut self, ws: &Workspace) -> f64 {
        let a = &ws.asm;
        let y = &mut self.linear_residual;
        y.copy_from_slice(&ws.residual);
        for c in 0..a.n_free {
            let dc = ws.delta[c];
            for k in a.col_ptr[c]..a.col_ptr[c + 1] {
                y[a.row_idx[k]] += ws.values[k] * dc;
            }
        }
        a.low_rank.apply_add(&ws.delta, y);
        let num = y.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let den = ws.residual.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        if den > 0.0 {
            num / den
        } else {
            0.0
        }
    }

    /// Whether the factors are single precision (module docs, §Precision).
    pub fn single_precision(&self) -> bool {
        self.solver.precision() == Precision::Single
    }

    /// Memory of the factors and their scratch (bytes).
    pub fn memory_bytes(&self) -> (usize, usize) {
        self.solver.memory_bytes()
    }

    /// The solver itself (unit-cost measurements).
    pub fn solver_mut(&mut self) -> &mut LinearSolver {
        &mut self.solver
    }
}

//! The one trait every force implements.
//!
//! A [`Force`] is a *family* of elements of the same kind (all stretching springs, all hinges,
//! gravity on all nodes …). Each element acts on a fixed *stencil* of global DOFs of the same
//! size `k`. For every stencil the force writes a dense local force vector `f` (length `k`)
//! and, when it has them, the local Jacobians `∂f/∂q` and `∂f/∂v` (`k × k`, row-major:
//! entry `[a k + b]` is `∂f_a/∂q_b`). The assembler scatters these blocks into the global
//! sparse system through indices computed once, so adding a force never touches the stepper.
//!
//! Forces made of identical fixed-size elements implement [`crate::element::Element`]
//! instead and get this trait from [`crate::element::Family`].

use crate::error::HistoryError;
use rayon::prelude::*;

/// What the stepper passes to a force: the trial configuration and velocity.
#[derive(Debug, Clone, Copy)]
pub struct EvalInput<'a> {
    /// Generalised coordinates `q` (m for positions, rad for twists).
    pub q: &'a [f64],
    /// Generalised velocities `v = (q − q_n)/dt` (m/s, rad/s).
    pub v: &'a [f64],
    /// Time at the end of the step (s).
    pub t: f64,
    /// Length of the step that ends at `q` (s), or [`NO_STEP`] where there is none (statics,
    /// observers reading a state): a force that acts through the step's change of momentum
    /// (the air's added mass) then gives none.
    pub dt: f64,
    /// Whether the Jacobian blocks are wanted. When false, elements may skip computing them
    /// (the assembler will not read them); the force vector must always be written.
    pub jacobian: bool,
}

/// [`EvalInput::dt`] where no step is taken.
pub const NO_STEP: f64 = f64::INFINITY;

impl<'a> EvalInput<'a> {
    /// An evaluation at `(q, v)` and time `t` that no time step leads to ([`NO_STEP`]):
    /// statics, observers reading a state, tests of a law.
    pub fn outside_step(q: &'a [f64], v: &'a [f64], t: f64, jacobian: bool) -> Self {
        Self {
            q,
            v,
            t,
            dt: NO_STEP,
            jacobian,
        }
    }
}

/// Which Jacobians a force provides.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct JacobianKind {
    /// The force depends on positions (`∂f/∂q` blocks are written).
    pub dq: bool,
    /// The force depends on velocities (`∂f/∂v` blocks are written).
    pub dv: bool,
    /// Both Jacobians are symmetric (true for conservative forces and isotropic drag).
    pub symmetric: bool,
}

impl JacobianKind {
    /// A force that depends on positions (`dq`) and velocities (`dv`), with symmetric
    /// Jacobians or not.
    pub const fn new(dq: bool, dv: bool, symmetric: bool) -> Self {
        Self { dq, dv, symmetric }
    }
    /// A conservative elastic force: symmetric `∂f/∂q`, no velocity dependence.
    pub const ELASTIC: Self = Self::new(true, false, true);
    /// A force on velocities only with symmetric `∂f/∂v` (isotropic drag on nodes).
    pub const VISCOUS: Self = Self::new(false, true, true);
    /// A force on positions and velocities with non-symmetric Jacobians (drag on deforming
    /// triangles).
    pub const GENERAL: Self = Self::new(true, true, false);
    /// A constant force: no Jacobian at all.
    pub const CONSTANT: Self = Self::new(false, false, true);
}

/// Dense local output of a force: one block per stencil.
#[derive(Debug, Clone, Default)]
pub struct LocalBlocks {
    /// Stencil size `k`.
    pub k: usize,
    /// Number of stencils.
    pub n: usize,
    /// Local forces, `n × k`.
    pub f: Vec<f64>,
    /// Local `∂f/∂q`, `n × k × k` (empty if not provided).
    pub dfdq: Vec<f64>,
    /// Local `∂f/∂v`, `n × k × k` (empty if not provided).
    pub dfdv: Vec<f64>,
    /// Evaluate the blocks on the calling thread, without rayon: set by the assembler for
    /// models too small to pay for waking the pool (docs/performance.md §Engine tuning).
    pub serial: bool,
    /// The force's own working memory, sized by its [`Force::new_blocks`] and never read by
    /// the assembler: quantities shared by several stencils (mid-edge bending keeps each
    /// edge's dihedral angle and derivatives here), so that an evaluation allocates nothing.
    /// Empty for most forces.
    pub scratch: Vec<f64>,
    /// The low-rank part of `∂f/∂v` ([`Force::low_rank_dofs`]): `∂F/∂v ⊇ Σ_j c_j u_j u_jᵀ`
    /// with `u_j` over the force's low-rank DOFs, stored one after another
    /// (`rank × n_dofs`). Empty for almost every force.
    pub low_rank_u: Vec<f64>,
    /// The coefficients `c_j` of [`LocalBlocks::low_rank_u`] (1/s · kg: N per m/s).
    pub low_rank_coef: Vec<f64>,
}

/// One stencil's mutable output.
pub struct BlockMut<'a> {
    /// Stencil index.
    pub index: usize,
    /// Local force (length `k`).
    pub f: &'a mut [f64],
    /// Local `∂f/∂q` (`k × k`, row-major) or empty.
    pub dfdq: &'a mut [f64],
    /// Local `∂f/∂v` (`k × k`, row-major) or empty.
    pub dfdv: &'a mut [f64],
}

impl LocalBlocks {
    /// Buffers for `n` stencils of size `k` with the given Jacobians.
    pub fn new(k: usize, n: usize, kind: JacobianKind) -> Self {
        Self {
            k,
            n,
            f: vec![0.0; n * k],
            dfdq: if kind.dq {
                vec![0.0; n * k * k]
            } else {
                Vec::new()
            },
            dfdv: if kind.dv {
                vec![0.0; n * k * k]
            } else {
                Vec::new()
            },
            serial: false,
            scratch: Vec::new(),
            low_rank_u: Vec::new(),
            low_rank_coef: Vec::new(),
        }
    }

    /// Visit every block, in parallel (rayon) when there are enough of them to pay for the
    /// threads' wake-up. Blocks are *not* zeroed: the closure must overwrite `f` and every
    /// Jacobian slice it is given. When `jacobian` is false the closure gets empty `dfdq` /
    /// `dfdv` slices and should skip computing them.
    pub fn par_for_each<F>(&mut self, jacobian: bool, func: F)
    where
        F: Fn(BlockMut<'_>) + Sync + Send,
    {
        let k = self.k;
        let kk = k * k;
        let has_q = jacobian && !self.dfdq.is_empty();
        let has_v = jacobian && !self.dfdv.is_empty();
        let n = self.n;
        // Chunk all three arrays consistently; missing Jacobians get empty slices.
        let fq = &mut self.dfdq;
        let fv = &mut self.dfdv;
        let f = &mut self.f;
        if n == 0 {
            return;
        }
        if self.serial {
            for i in 0..n {
                let q = if has_q {
                    &mut fq[i * kk..(i + 1) * kk]
                } else {
                    &mut [][..]
                };
                let v = if has_v {
                    &mut fv[i * kk..(i + 1) * kk]
                } else {
                    &mut [][..]
                };
                func(BlockMut {
                    index: i,
                    f: &mut f[i * k..(i + 1) * k],
                    dfdq: q,
                    dfdv: v,
                });
            }
            return;
        }
        let min_len = task_len(n);
        type Item<'a> = (usize, (&'a mut [f64], (&'a mut [f64], &'a mut [f64])));
        let body = |(i, (f, (q, v))): Item<'_>| {
            func(BlockMut {
                index: i,
                f,
                dfdq: q,
                dfdv: v,
            })
        };
        match (has_q, has_v) {
            (true, true) => f
                .par_chunks_mut(k)
                .zip(fq.par_chunks_mut(kk).zip(fv.par_chunks_mut(kk)))
                .enumerate()
                .with_min_len(min_len)
                .for_each(body),
            (true, false) => f
                .par_chunks_mut(k)
                .zip(fq.par_chunks_mut(kk))
                .enumerate()
                .with_min_len(min_len)
                .for_each(|(i, (f, q))| body((i, (f, (q, &mut [][..]))))),
            (false, true) => f
                .par_chunks_mut(k)
                .zip(fv.par_chunks_mut(kk))
                .enumerate()
                .with_min_len(min_len)
                .for_each(|(i, (f, v))| body((i, (f, (&mut [][..], v))))),
            (false, false) => f
                .par_chunks_mut(k)
                .enumerate()
                .with_min_len(min_len)
                .for_each(|(i, f)| body((i, (f, (&mut [][..], &mut [][..]))))),
        }
    }
}

/// Items per rayon task when `n` items are visited in parallel: about a quarter of the
/// family per thread (the assembler evaluates the families concurrently inside one region of
/// the pool, so stealing balances them), but not below `MIN_TASK` items, nor above `MIN_PAR`:
/// below that many stencils per task, the threads' bookkeeping costs more than the elements
/// (docs/performance.md §Engine tuning).
pub(crate) fn task_len(n: usize) -> usize {
    const MIN_TASK: usize = 256;
    const MIN_PAR: usize = 2048;
    n.div_ceil(2 * rayon::current_num_threads())
        .clamp(MIN_TASK, MIN_PAR)
}

/// The dependence of a force on the state through quantities `h` it holds over a step
/// (read at [`Force::commit`]): `∂F/∂q ⊇ Σ_j u_j wq_jᵀ`, `∂F/∂v ⊇ Σ_j u_j wv_jᵀ`, with
/// `u_j = ∂F/∂h_j` and `wq_j`, `wv_j` the derivatives of `h_j` with respect to `q` and `v`,
/// all over [`LagCoupling::dofs`].
#[derive(Debug, Clone, Default, PartialEq)]
pub struct LagCoupling {
    /// Global DOFs the vectors run over, ascending.
    pub dofs: Vec<usize>,
    /// `u_j = ∂F/∂h_j`, one vector per held quantity.
    pub u: Vec<Vec<f64>>,
    /// `∂h_j/∂q`.
    pub wq: Vec<Vec<f64>>,
    /// `∂h_j/∂v`.
    pub wv: Vec<Vec<f64>>,
}

/// A family of force elements. See the module docs for the contract.
pub trait Force: Send + Sync {
    /// Short name for diagnostics (e.g. `"rod-stretch"`).
    fn name(&self) -> &str;
    /// Number of DOFs in every stencil.
    fn stencil_size(&self) -> usize;
    /// Global DOF indices of all stencils, flattened (`stencil_size()` per stencil).
    fn stencils(&self) -> &[usize];
    /// Which Jacobians [`Force::evaluate`] writes.
    fn jacobian_kind(&self) -> JacobianKind;
    /// Overwrite `out` with the local forces (and Jacobians) of every stencil.
    fn evaluate(&self, input: &EvalInput<'_>, out: &mut LocalBlocks);
    /// Potential energy (J) at `q` when the force is conservative, else `None`.
    fn energy(&self, _q: &[f64]) -> Option<f64> {
        None
    }
    /// True when [`Force::energy`] is always `Some` and the force is `−∇E` (no velocity
    /// dependence): the conformance checks then test the force against the energy.
    fn conservative(&self) -> bool {
        false
    }
    /// Called once per accepted time step with the new configuration and velocities, so
    /// that elements with history (DER reference frames, the air's momentum) can update it.
    /// Not called for rejected steps.
    fn commit(&mut self, _q: &[f64], _v: &[f64]) {}
    /// The history that [`Force::commit`] advances, flattened to numbers, for checkpoints:
    /// restoring it with [`Force::restore_history`] on a freshly built force must make every
    /// later evaluation bit-identical. Empty for forces without history.
    fn history(&self) -> Vec<f64> {
        Vec::new()
    }
    /// Restore a history produced by [`Force::history`] on an identically built force.
    /// Errors when `h` has the wrong length for this force.
    fn restore_history(&mut self, h: &[f64]) -> Result<(), HistoryError> {
        if h.is_empty() {
            Ok(())
        } else {
            Err(HistoryError {
                force: self.name().to_string(),
                got: h.len(),
                expected: 0,
            })
        }
    }
    /// Scale applied to external loads (gravity, point loads) by load-stepping solvers;
    /// elastic and drag forces ignore it.
    fn set_load_scale(&mut self, _scale: f64) {}
    /// Number of stencils.
    fn n_stencils(&self) -> usize {
        self.stencils()
            .len()
            .checked_div(self.stencil_size())
            .unwrap_or(0)
    }
    /// The global DOFs of the force's low-rank velocity Jacobian, for a force that couples
    /// every node of a body through a few collective quantities (the air's added mass on a
    /// canopy's mean motion): its `∂F/∂v` is `Σ_j c_j u_j u_jᵀ` over these DOFs, beside
    /// the stencils' blocks, written by [`Force::evaluate`] into
    /// [`LocalBlocks::low_rank_u`] when Jacobians are asked for. Held as vectors, it keeps
    /// the sparse pattern free of a dense block; the linear solver applies it by
    /// Sherman–Morrison–Woodbury (`linsolve/low_rank.rs`). Empty for almost every force.
    fn low_rank_dofs(&self) -> &[usize] {
        &[]
    }
    /// The number of terms `u_j` of the low-rank part (0 without one).
    fn low_rank_rank(&self) -> usize {
        0
    }
    /// The part of the linearisation at `(q, v)` that runs through what the force holds
    /// over a step (see [`LagCoupling`]), for forces whose held quantities stand for a
    /// function of the state (a canopy's incidence), not a history of its path (a rod's
    /// reference frame). The step solver never uses it. `None` for almost every force.
    fn lag_coupling(&self, _q: &[f64], _v: &[f64]) -> Option<LagCoupling> {
        None
    }
    /// Called before each step is solved, with the state `(q, v)` it starts from and its
    /// length `dt` (s): a force whose stencils follow the state (contact pairs, taken by a
    /// broad phase) takes them here. Returns true when its stencils changed, so that the step
    /// solver rebuilds its sparsity pattern; false (the default) keeps it.
    fn begin_step(&mut self, _q: &[f64], _v: &[f64], _dt: f64) -> bool {
        false
    }
    /// Whether [`Force::max_step`] can return less than 1 (contact): the step solver then
    /// bounds every move of an iterate by it.
    fn bounds_steps(&self) -> bool {
        false
    }
    /// The largest fraction `t ≤ 1` of the move `dq` from `q` (all DOFs) that the force
    /// admits: along `q + s dq`, `s ∈ [0, t]`, nothing it guards closes below `gap` times its
    /// distance at `q` (contact: no two surfaces meet). 1 (the default) for forces without
    /// such a bound.
    fn max_step(&self, _q: &[f64], _dq: &[f64], _gap: f64) -> f64 {
        1.0
    }
    /// Fresh output buffers for this force (with the [`LocalBlocks::scratch`] it uses, if
    /// any, and room for its low-rank part).
    fn new_blocks(&self) -> LocalBlocks {
        let mut b = LocalBlocks::new(self.stencil_size(), self.n_stencils(), self.jacobian_kind());
        let rank = self.low_rank_rank();
        b.low_rank_u = vec![0.0; rank * self.low_rank_dofs().len()];
        b.low_rank_coef = vec![0.0; rank];
        b
    }
}

//! Global sparse system: the pattern is built once from the forces' stencils; every force's
//! local blocks are scattered into it through precomputed value indices.
//!
//! Only free DOFs appear in the system (fixed DOFs are eliminated). The matrix assembled is
//! `J = diag(m) c_m − c_q ∂F/∂q − c_v ∂F/∂v` with coefficients chosen by the solver
//! (implicit Euler: `c_m = 1/dt²`, `c_q = 1`, `c_v = 1/dt`; statics: `c_m = 0`, `c_q = 1`,
//! `c_v = 0`). The force vector `F` is assembled over all DOFs.
//!
//! One assembly is one parallel region (rayon): the forces are evaluated concurrently (each
//! family's elements in parallel tasks, `LocalBlocks::par_for_each`), then the force vector
//! and the matrix values are scattered by chunks of the output, each summed in the serial
//! order (module `plan`): the results are bitwise the same for any number of threads.
//!
//! A force's low-rank velocity Jacobian (`Force::low_rank_dofs`) is not scattered into the
//! pattern: it is gathered into [`Assembler::low_rank`], which the linear solver applies by
//! Sherman–Morrison–Woodbury.

use crate::force::{EvalInput, LocalBlocks};
use crate::linsolve::LowRank;
use crate::model::Model;
use rayon::prelude::*;

mod plan;
#[cfg(test)]
mod tests;

use plan::Chunks;

/// Sentinel for "this local entry touches a fixed DOF" (never inside a scatter chunk).
const NONE: u32 = u32::MAX;

/// Coefficients of the assembled matrix `J = c_m M − c_q ∂F/∂q − c_v ∂F/∂v`.
#[derive(Debug, Clone, Copy)]
pub struct Coefficients {
    /// Mass coefficient (1/s²).
    pub c_m: f64,
    /// Position-Jacobian coefficient.
    pub c_q: f64,
    /// Velocity-Jacobian coefficient (1/s).
    pub c_v: f64,
}

/// Compressed-sparse-column pattern of the free-DOF system with scatter maps.
pub struct Assembler {
    /// Number of free DOFs (matrix size).
    pub n_free: usize,
    /// `dof_of[r]` = global DOF of system row `r`.
    pub dof_of: Vec<usize>,
    /// CSC column pointers.
    pub col_ptr: Vec<usize>,
    /// CSC row indices (sorted within each column).
    pub row_idx: Vec<usize>,
    /// Position of the diagonal entry of each column in `values`.
    pub diag: Vec<usize>,
    /// Per force: value index of each local `k × k` entry (or `NONE`).
    maps: Vec<Vec<u32>>,
    /// Per force: output buffers.
    pub blocks: Vec<LocalBlocks>,
    /// Whether every force reports a symmetric Jacobian.
    pub symmetric: bool,
    /// `transpose[k]` = value index of the mirror entry `(c, r)` of entry `k = (r, c)` (the
    /// pattern is structurally symmetric: every stencil couples all its DOFs both ways).
    pub transpose: Vec<u32>,
    /// The free DOFs are numbered in the fill-reducing (AMD) order of the pattern: a
    /// Cholesky factorisation of it needs no ordering of its own.
    pub ordered: bool,
    /// Chunks of the matrix values (at column boundaries) for the parallel scatter.
    val_chunks: Chunks,
    /// Chunks of the force vector (all DOFs).
    dof_chunks: Chunks,
    /// The model is too small for the pool ([`SERIAL_BELOW`]): everything runs on the
    /// calling thread.
    pub serial: bool,
    /// Per force: the system row of each of its low-rank DOFs (or `NONE`).
    low_rank_rows: Vec<Vec<u32>>,
    /// The low-rank part of `J` (`−c_v` times the forces' low-rank `∂F/∂v`, free DOFs), from
    /// the last assembly with a Jacobian.
    pub low_rank: LowRank,
    /// Terms of the forces' low-rank parts (0 for almost every model).
    pub low_rank_terms: usize,
}

/// Models whose Jacobian has fewer stored entries than this are assembled on the calling
/// thread: waking rayon's pool (a few tens of µs per assembly, measured) costs more than
/// the second thread saves (docs/performance.md §Engine tuning).
pub const SERIAL_BELOW: usize = 30_000;

impl Assembler {
    /// Build the pattern from the model's forces (plus the diagonal), with scatter chunks
    /// for the threads of rayon's pool.
    /// A model whose Jacobian has fewer than [`SERIAL_BELOW`] entries is assembled on the
    /// calling thread.
    pub fn new(model: &Model) -> Self {
        Self::build(model, plan::chunk_count(rayon::current_num_threads()), true)
    }

    /// [`Assembler::new`] with the scatter cut into at most `n_chunks` chunks (results do
    /// not depend on it), in rayon's pool whatever the size.
    #[cfg(test)]
    pub(crate) fn with_chunks(model: &Model, n_chunks: usize) -> Self {
        Self::build(model, n_chunks, false)
    }

    fn build(model: &Model, n_chunks: usize, allow_serial: bool) -> Self {
        let n = model.n_dofs();
        let mut free_of = vec![NONE; n];
        let mut dof_of = Vec::new();
        for d in 0..n {
            if !model.fixed[d] {
                free_of[d] = dof_of.len() as u32;
                dof_of.push(d);
            }
        }
        let n_free = dof_of.len();
        // Number the free DOFs in the fill-reducing order of the factorisation.
        let (ordered, col_ptr, row_idx) = amd_numbering(model, &mut free_of, &mut dof_of);
        let find = |r: usize, c: usize| -> u32 {
            let s = &row_idx[col_ptr[c]..col_ptr[c + 1]];
            (col_ptr[c] + s.binary_search(&r).expect("entry in pattern")) as u32
        };
        let diag: Vec<usize> = (0..n_free).map(|c| find(c, c) as usize).collect();
        let serial = allow_serial && row_idx.len() < SERIAL_BELOW;
        let n_chunks = if serial {
            1
        } else {
            n_chunks.clamp(1, plan::MAX_CHUNKS)
        };
        let mut maps = Vec::with_capacity(model.forces.len());
        let mut blocks = Vec::with_capacity(model.forces.len());
        let mut symmetric = true;
        for f in &model.forces {
            let kind = f.jacobian_kind();
            symmetric &= kind.symmetric;
            let k = f.stencil_size();
            let mut map = Vec::new();
            if kind.dq || kind.dv {
                map.reserve(f.stencils().len() * k);
                for st in f.stencils().chunks(k) {
                    for &a in st {
                        for &b in st {
                            let (r, c) = (free_of[a], free_of[b]);
                            map.push(if r == NONE || c == NONE {
                                NONE
                            } else {
                                find(r as usize, c as usize)
                            });
                        }
                    }
                }
            }
            maps.push(map);
            let mut b = f.new_blocks();
            b.serial = serial;
            blocks.push(b);
        }
        let mut transpose = vec![0u32; row_idx.len()];
        for c in 0..n_free {
            for k in col_ptr[c]..col_ptr[c + 1] {
                transpose[k] = find(c, row_idx[k]);
            }
        }
        let val_chunks = value_chunks(model, &col_ptr, &maps, n_chunks);
        let dof_chunks = force_chunks(model, n_chunks);
        let low_rank_rows: Vec<Vec<u32>> = model
            .forces
            .iter()
            .map(|f| f.low_rank_dofs().iter().map(|&d| free_of[d]).collect())
            .collect();
        let rank = model.forces.iter().map(|f| f.low_rank_rank()).sum();
        Self {
            low_rank_rows,
            low_rank: LowRank::with_capacity(n_free, rank),
            low_rank_terms: rank,
            serial,
            ordered,
            val_chunks,
            dof_chunks,
            transpose,
            n_free,
            dof_of,
            col_ptr,
            row_idx,
            diag,
            maps,
            blocks,
            symmetric,
        }
    }

    /// Write the symmetric part `½ (J + Jᵀ)` of `values` into `sym`.
    pub fn symmetric_part(&self, values: &[f64], sym: &mut [f64]) {
        for ((s, &v), &t) in sym.iter_mut().zip(values).zip(&self.transpose) {
            *s = 0.5 * (v + values[t as usize]);
        }
    }

    /// Number of stored nonzeros.
    pub fn nnz(&self) -> usize {
        self.row_idx.len()
    }

    /// Evaluate every force at `input`; accumulate the total force into `force` (all DOFs,
    /// overwritten) and, if `values` is given, the matrix `J` (overwritten).
    pub fn assemble(
        &mut self,
        model: &Model,
        input: &EvalInput<'_>,
        force: &mut [f64],
        values: Option<(&mut [f64], Coefficients)>,
    ) {
        let blocks = &mut self.blocks;
        let (vc, dc) = (&self.val_chunks, &self.dof_chunks);
        let (maps, forces) = (&self.maps, &model.forces[..]);
        let (dof_of, diag) = (&self.dof_of, &self.diag);
        let serial = self.serial;
        let evaluate = |blocks: &mut [LocalBlocks]| {
            if serial {
                forces
                    .iter()
                    .zip(blocks)
                    .for_each(|(f, b)| f.evaluate(input, b));
            } else {
                forces
                    .par_iter()
                    .zip(blocks.par_iter_mut())
                    .for_each(|(f, b)| f.evaluate(input, b));
            }
        };
        let scatter = |blocks: &[LocalBlocks], force: &mut [f64], values| {
            let mut scatter_f = || {
                dc.run(force, |t, lo, out| {
                    plan::force_chunk(dc, t, lo, out, forces, blocks)
                })
            };
            let Some((values, c)) = values else {
                return scatter_f();
            };
            let scatter_j = || {
                vc.run(values, |t, lo, out| {
                    jacobian_chunk(vc, t, lo, out, (maps, blocks), (dof_of, diag), model, c)
                })
            };
            if serial {
                scatter_f();
                scatter_j();
            } else {
                rayon::join(scatter_f, scatter_j);
            }
        };
        let c_v = values.as_ref().map(|(_, c)| c.c_v);
        if serial {
            evaluate(blocks);
            scatter(blocks, force, values);
        } else {
            // One region of the pool for the whole assembly (every `par_*` inside runs on its
            // workers without another wake-up).
            rayon::scope(|_| {
                evaluate(blocks);
                scatter(blocks, force, values);
            });
        }
        if let Some(c_v) = c_v {
            self.gather_low_rank(c_v);
        }
    }

    /// [`Assembler::low_rank`] from the blocks just evaluated: the term `c u uᵀ` of a force's
    /// `∂F/∂v` enters `J` as `−c_v c u uᵀ` (terms that vanish are left out).
    fn gather_low_rank(&mut self, c_v: f64) {
        self.low_rank.clear();
        for (rows, b) in self.low_rank_rows.iter().zip(&self.blocks) {
            let u_all = b.low_rank_u.chunks(rows.len().max(1));
            for (&coef, u) in b.low_rank_coef.iter().zip(u_all) {
                let gamma = -c_v * coef;
                if gamma == 0.0 {
                    continue;
                }
                let col = self.low_rank.push(gamma);
                for (&r, &x) in rows.iter().zip(u) {
                    if r != NONE {
                        col[r as usize] += x;
                    }
                }
            }
        }
    }
}

/// Renumber the free DOFs in the AMD order of their pattern (so that the factorisation needs
/// no permutation, [`Assembler::ordered`]); returns whether it did and the pattern in the
/// final numbering.
fn amd_numbering(
    model: &Model,
    free_of: &mut [u32],
    dof_of: &mut Vec<usize>,
) -> (bool, Vec<usize>, Vec<usize>) {
    let n_free = dof_of.len();
    let (col_ptr, row_idx) = pattern(model, free_of, n_free);
    let Some(fwd) = crate::linsolve::amd_order(n_free, &col_ptr, &row_idx) else {
        return (false, col_ptr, row_idx);
    };
    *dof_of = fwd.iter().map(|&r| dof_of[r]).collect();
    for (r, &d) in dof_of.iter().enumerate() {
        free_of[d] = r as u32;
    }
    let (col_ptr, row_idx) = pattern(model, free_of, n_free);
    (true, col_ptr, row_idx)
}

/// The CSC pattern (sorted rows) of the free-DOF system with free numbers `free_of`: the
/// diagonal and every pair of free DOFs of a stencil of a force with a Jacobian.
fn pattern(model: &Model, free_of: &[u32], n_free: usize) -> (Vec<usize>, Vec<usize>) {
    // Collect (col, row) pairs as u64 keys, sort, dedup.
    let mut keys: Vec<u64> = (0..n_free as u64).map(|r| (r << 32) | r).collect();
    for f in &model.forces {
        let kind = f.jacobian_kind();
        if !(kind.dq || kind.dv) {
            continue;
        }
        let k = f.stencil_size();
        for st in f.stencils().chunks(k) {
            for &a in st {
                let ra = free_of[a];
                if ra == NONE {
                    continue;
                }
                for &b in st {
                    let cb = free_of[b];
                    if cb != NONE {
                        keys.push(((cb as u64) << 32) | ra as u64);
                    }
                }
            }
        }
    }
    keys.sort_unstable();
    keys.dedup();
    let mut col_ptr = vec![0usize; n_free + 1];
    let mut row_idx = Vec::with_capacity(keys.len());
    for &key in &keys {
        col_ptr[(key >> 32) as usize + 1] += 1;
        row_idx.push((key & 0xffff_ffff) as usize);
    }
    for c in 0..n_free {
        col_ptr[c + 1] += col_ptr[c];
    }
    (col_ptr, row_idx)
}

/// Values `lo..lo + out.len()` (chunk `t` of `vc`) of `J = c_m M − c_q ∂F/∂q − c_v ∂F/∂v`:
/// zero, the mass diagonal, then every force's blocks in serial order.
#[allow(clippy::too_many_arguments)]
fn jacobian_chunk(
    vc: &Chunks,
    t: usize,
    lo: usize,
    out: &mut [f64],
    (maps, blocks): (&[Vec<u32>], &[LocalBlocks]),
    (dof_of, diag): (&[usize], &[usize]),
    model: &Model,
    c: Coefficients,
) {
    out.iter_mut().for_each(|x| *x = 0.0);
    let hi = lo + out.len();
    // Columns of the chunk are contiguous, and so are their diagonal entries.
    let first = diag.partition_point(|&k| k < lo);
    for (r, &k) in diag.iter().enumerate().skip(first) {
        if k >= hi {
            break;
        }
        out[k - lo] += c.c_m * model.mass[dof_of[r]];
    }
    for (fi, (map, b)) in maps.iter().zip(blocks).enumerate() {
        let elems = &vc.elems[t][fi];
        let kk = b.k * b.k;
        if !b.dfdq.is_empty() && c.c_q != 0.0 {
            plan::scatter_chunk(out, lo, elems, kk, map, &b.dfdq, -c.c_q);
        }
        if !b.dfdv.is_empty() && c.c_v != 0.0 {
            plan::scatter_chunk(out, lo, elems, kk, map, &b.dfdv, -c.c_v);
        }
    }
}

/// Chunks of the values at column starts, balanced by the number of additions per value.
fn value_chunks(model: &Model, col_ptr: &[usize], maps: &[Vec<u32>], n_chunks: usize) -> Chunks {
    let nnz = *col_ptr.last().unwrap_or(&0);
    let mut weight = vec![1u32; nnz];
    for &m in maps.iter().flatten() {
        if m != NONE {
            weight[m as usize] += 1;
        }
    }
    let mut col_start = vec![false; nnz + 1];
    for &p in col_ptr {
        col_start[p] = true;
    }
    let mut ch = Chunks::cut(nnz, n_chunks, &weight, |i| col_start[i], maps.len());
    for (fi, (f, map)) in model.forces.iter().zip(maps).enumerate() {
        let kk = f.stencil_size() * f.stencil_size();
        for (e, m) in map.chunks(kk.max(1)).enumerate() {
            ch.add(fi, e, m.iter().filter(|&&m| m != NONE).map(|&m| m as usize));
        }
    }
    ch
}

/// Chunks of the force vector (all DOFs), balanced by the number of additions per DOF.
fn force_chunks(model: &Model, n_chunks: usize) -> Chunks {
    let n = model.n_dofs();
    let mut weight = vec![1u32; n];
    for f in &model.forces {
        for &d in f.stencils() {
            weight[d] += 1;
        }
    }
    let mut ch = Chunks::cut(n, n_chunks, &weight, |_| true, model.forces.len());
    for (fi, f) in model.forces.iter().enumerate() {
        let k = f.stencil_size().max(1);
        for (e, st) in f.stencils().chunks(k).enumerate() {
            ch.add(fi, e, st.iter().copied());
        }
    }
    ch
}

//! Global sparse system: the pattern is built once from the forces' stencils; every force's
//! local blocks are scattered into it through precomputed value indices.
//!
//! Only free DOFs appear in the system (fixed DOFs are eliminated). The matrix assembled is
//! `J = diag(m) c_m − c_q ∂F/∂q − c_v ∂F/∂v` with coefficients chosen by the solver
//! (implicit Euler: `c_m = 1/dt²`, `c_q = 1`, `c_v = 1/dt`; statics: `c_m = 0`, `c_q = 1`,
//! `c_v = 0`). The force vector `F` is assembled over all DOFs.

use crate::force::{EvalInput, LocalBlocks};
use crate::model::Model;

/// Sentinel for "this local entry touches a fixed DOF".
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
}

impl Assembler {
    /// Build the pattern from the model's forces (plus the diagonal).
    pub fn new(model: &Model) -> Self {
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
        let find = |r: usize, c: usize| -> u32 {
            let s = &row_idx[col_ptr[c]..col_ptr[c + 1]];
            (col_ptr[c] + s.binary_search(&r).expect("entry in pattern")) as u32
        };
        let diag: Vec<usize> = (0..n_free).map(|c| find(c, c) as usize).collect();
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
            blocks.push(f.new_blocks());
        }
        let mut transpose = vec![0u32; row_idx.len()];
        for c in 0..n_free {
            for k in col_ptr[c]..col_ptr[c + 1] {
                transpose[k] = find(c, row_idx[k]);
            }
        }
        Self {
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
        force.iter_mut().for_each(|x| *x = 0.0);
        for (f, blocks) in model.forces.iter().zip(self.blocks.iter_mut()) {
            f.evaluate(input, blocks);
        }
        for (fi, f) in model.forces.iter().enumerate() {
            let k = f.stencil_size();
            let b = &self.blocks[fi];
            for (st, loc) in f.stencils().chunks(k).zip(b.f.chunks(k)) {
                for (&d, &x) in st.iter().zip(loc) {
                    force[d] += x;
                }
            }
        }
        let Some((values, c)) = values else { return };
        values.iter_mut().for_each(|x| *x = 0.0);
        for (r, &d) in self.dof_of.iter().enumerate() {
            values[self.diag[r]] += c.c_m * model.mass[d];
        }
        for (map, b) in self.maps.iter().zip(&self.blocks) {
            if !b.dfdq.is_empty() && c.c_q != 0.0 {
                scatter(values, map, &b.dfdq, -c.c_q);
            }
            if !b.dfdv.is_empty() && c.c_v != 0.0 {
                scatter(values, map, &b.dfdv, -c.c_v);
            }
        }
    }
}

#[inline]
fn scatter(values: &mut [f64], map: &[u32], local: &[f64], scale: f64) {
    for (&m, &x) in map.iter().zip(local) {
        if m != NONE {
            values[m as usize] += scale * x;
        }
    }
}

//! The parallel scatter: the matrix values and the force vector are cut into contiguous
//! chunks (of value indices at column boundaries, and of DOFs), one per task, and each task
//! adds, for every force in order, the entries of the elements that touch its chunk, in
//! the elements' order. Every value and every force component therefore receives exactly
//! the same additions in exactly the same order as in a serial pass over all elements:
//! the result is bitwise independent of the number of chunks (tested in `tests.rs`).

use crate::force::{Force, LocalBlocks};
use rayon::prelude::*;

/// Contiguous ranges of the output and, per force, the elements that write into each.
#[derive(Debug, Default)]
pub(super) struct Chunks {
    /// Boundaries: chunk `t` covers `bounds[t]..bounds[t + 1]` (`len` = chunks + 1).
    pub bounds: Vec<usize>,
    /// `elems[t][f]`: elements of force `f` with an entry in chunk `t`, ascending.
    pub elems: Vec<Vec<Vec<u32>>>,
}

impl Chunks {
    /// Cut `0..n` into at most `n_chunks` non-empty ranges of about equal `weight` (per
    /// index), starting only where `allowed(i)` (column starts for the values); no elements
    /// listed yet ([`Chunks::add`]).
    pub fn cut(
        n: usize,
        n_chunks: usize,
        weight: &[u32],
        allowed: impl Fn(usize) -> bool,
        forces: usize,
    ) -> Self {
        let total: u64 = weight.iter().map(|&w| u64::from(w)).sum();
        let mut bounds = vec![0];
        let mut acc = 0u64;
        for i in 0..n {
            let t = bounds.len() as u64;
            let last = *bounds.last().expect("starts with 0");
            if t < n_chunks as u64 && i > last && allowed(i) && acc * n_chunks as u64 >= t * total {
                bounds.push(i);
            }
            acc += u64::from(weight[i]);
        }
        bounds.push(n);
        let elems = vec![vec![Vec::new(); forces]; bounds.len() - 1];
        Self { bounds, elems }
    }

    /// Record that element `e` of force `f` writes into the indices `idx` (elements must be
    /// added in ascending order per force).
    pub fn add(&mut self, f: usize, e: usize, idx: impl IntoIterator<Item = usize>) {
        for i in idx {
            let t = self.bounds.partition_point(|&b| b <= i) - 1;
            let list = &mut self.elems[t][f];
            if list.last() != Some(&(e as u32)) {
                list.push(e as u32);
            }
        }
    }

    /// Number of chunks.
    pub fn len(&self) -> usize {
        self.bounds.len() - 1
    }

    /// Split `out` into the chunks' slices and run `work(t, offset, slice)` on each, in
    /// parallel when there is more than one.
    pub fn run(&self, out: &mut [f64], work: impl Fn(usize, usize, &mut [f64]) + Sync) {
        if self.len() == 1 {
            work(0, 0, out);
            return;
        }
        let mut parts: [&mut [f64]; MAX_CHUNKS] = Default::default();
        let mut rest = out;
        for t in 0..self.len() {
            let (a, b) = rest.split_at_mut(self.bounds[t + 1] - self.bounds[t]);
            parts[t] = a;
            rest = b;
        }
        parts[..self.len()]
            .par_iter_mut()
            .enumerate()
            .for_each(|(t, p)| work(t, self.bounds[t], p));
    }
}

/// Most chunks a scatter is cut into (the slices are held in a fixed array: no allocation
/// per assembly).
pub(super) const MAX_CHUNKS: usize = 16;

/// Chunks for `threads` threads: two per thread (some balance against an unequal machine),
/// one when there is a single thread.
pub(super) fn chunk_count(threads: usize) -> usize {
    if threads <= 1 {
        1
    } else {
        (2 * threads).min(MAX_CHUNKS)
    }
}

/// Add, for chunk `t` of the force vector (`out` = `force[lo..]`), every force's local
/// forces in serial order.
pub(super) fn force_chunk(
    chunks: &Chunks,
    t: usize,
    lo: usize,
    out: &mut [f64],
    forces: &[Box<dyn Force>],
    blocks: &[LocalBlocks],
) {
    out.iter_mut().for_each(|x| *x = 0.0);
    let hi = lo + out.len();
    for (fi, f) in forces.iter().enumerate() {
        let k = f.stencil_size();
        let (st, loc) = (f.stencils(), &blocks[fi].f);
        for &e in &chunks.elems[t][fi] {
            let e = e as usize;
            for (&d, &x) in st[e * k..e * k + k].iter().zip(&loc[e * k..e * k + k]) {
                if (lo..hi).contains(&d) {
                    out[d - lo] += x;
                }
            }
        }
    }
}

/// Add `scale ·` the local `k × k` blocks of the listed elements into the values of chunk
/// `lo..lo + out.len()`, through `map` (value index of each local entry, or `NONE`).
#[inline]
pub(super) fn scatter_chunk(
    out: &mut [f64],
    lo: usize,
    elems: &[u32],
    kk: usize,
    map: &[u32],
    local: &[f64],
    scale: f64,
) {
    let hi = lo + out.len();
    for &e in elems {
        let r = e as usize * kk..(e as usize + 1) * kk;
        for (&m, &x) in map[r.clone()].iter().zip(&local[r]) {
            let m = m as usize;
            // `NONE` (u32::MAX) is never inside a chunk.
            if (lo..hi).contains(&m) {
                out[m - lo] += scale * x;
            }
        }
    }
}

//! The per-edge pass of mid-edge bending: the dihedral angle `θ` of every interior edge, its
//! gradient and, for a Jacobian, its Hessian, computed once per evaluation (in parallel, each
//! task writing its own edges' slots of the force's [`LocalBlocks::scratch`]) and then read
//! by both faces of the edge ([`EdgeAngle`]).
//!
//! [`LocalBlocks::scratch`]: crate::force::LocalBlocks::scratch

use rayon::prelude::*;

use super::super::dihedral::{angle_grad, angle_grad_hess_into};
use crate::force::task_len;
use crate::vec3::node;

/// Doubles per edge in the scratch: `θ`, `∇θ` (12), `∇²θ` (144, column-major).
pub(super) const SLOT: usize = 1 + 12 + 144;

/// Offset of the gradient in a slot.
const GRAD: usize = 1;
/// Offset of the Hessian in a slot.
const HESS: usize = 13;

/// Write `θ` and `∇θ` of every hinge `nodes[e]` (`[x0, x1, x2, x3]`, as
/// [`crate::shell::Hinge::nodes`]) at `q` into slot `e` of `scratch`, and `∇²θ` if `hess`
/// (else the Hessians are left as they were: the force-only path computes none); on the
/// calling thread when `serial` ([`crate::force::LocalBlocks::serial`]).
pub(super) fn fill(nodes: &[[usize; 4]], q: &[f64], hess: bool, serial: bool, scratch: &mut [f64]) {
    let one = |(slot, n): (&mut [f64], &[usize; 4])| {
        let x = n.map(|k| node(q, k));
        let (theta, g) = if hess {
            angle_grad_hess_into(&x, &mut slot[HESS..])
        } else {
            angle_grad(&x)
        };
        slot[0] = theta;
        slot[GRAD..HESS].copy_from_slice(g.as_slice());
    };
    if serial {
        scratch.chunks_mut(SLOT).zip(nodes).for_each(one);
        return;
    }
    scratch
        .par_chunks_mut(SLOT)
        .zip(nodes.par_iter())
        .with_min_len(task_len(nodes.len()))
        .for_each(one);
}

/// One face's view of one of its interior edges' slot, in the face's hinge order
/// `[v_{i+1}, v_{i+2}, v_i, o_i]`: the edge's first face (`Hinge::faces[0]`) sees the stored
/// order `[x0, x1, x2, x3]`, its second face `[x1, x0, x3, x2]` (the same `θ`: swapping the
/// two wings and the edge's direction leaves it unchanged).
#[derive(Clone, Copy)]
pub(super) struct EdgeAngle<'a> {
    slot: &'a [f64],
    /// 1 when the face is the edge's second face (local node `r` is stored node `r ^ 1`).
    swap: usize,
}

impl<'a> EdgeAngle<'a> {
    /// Slot `e` of `scratch`, seen from the edge's first face (`second == false`) or second.
    #[inline]
    pub(super) fn new(scratch: &'a [f64], e: usize, second: bool) -> Self {
        Self {
            slot: &scratch[SLOT * e..SLOT * (e + 1)],
            swap: usize::from(second),
        }
    }

    /// `θ` (rad).
    #[inline]
    pub(super) fn theta(&self) -> f64 {
        self.slot[0]
    }

    /// `∂θ/∂x_r` (rad/m) of the face's local hinge node `r`.
    #[inline]
    pub(super) fn grad(&self, r: usize) -> [f64; 3] {
        let o = GRAD + 3 * (r ^ self.swap);
        [self.slot[o], self.slot[o + 1], self.slot[o + 2]]
    }

    /// Column `3c + d` of `∇²θ` restricted to the rows of local node `r` (rad/m²): its 3
    /// entries `∂²θ/∂x_r ∂(x_c)_d`.
    #[inline]
    pub(super) fn hess(&self, r: usize, c: usize, d: usize) -> &'a [f64] {
        let o = HESS + 12 * (3 * (c ^ self.swap) + d) + 3 * (r ^ self.swap);
        &self.slot[o..o + 3]
    }
}

//! Self-contact as a force family: IPC's barrier on every candidate pair of the broad phase
//! (Li et al., SIGGRAPH 2020, §4; Li, Kaufman & Jiang 2021 for cloth and rods).
//!
//! **Pairs follow the state, the pattern does not each step.** A pair not held was farther
//! apart than the reach when the pairs were taken, so the held pairs cover every pair that
//! can come within `√d̂` until the surface has moved, relative to itself (a rigid translation
//! does not count), by half the margin between the reach and `√d̂`. Before each step
//! ([`Force::begin_step`]) that margin is compared with the motion so far plus twice the
//! step's fastest relative motion `|v| dt`; when it no longer covers them, the pairs are taken
//! afresh by the broad phase within three times `√d̂` plus that motion (hysteresis: held pairs
//! beyond `√d̂` cost a distance each and add nothing), and the step solver rebuilds its
//! sparsity pattern if they differ from those held.
//!
//! **No iterate passes through** ([`Force::max_step`]): every move of an iterate is bounded
//! by additive CCD over the held pairs (`contact/ccd.rs`), and where the move reaches beyond
//! what the held pairs cover (the nodes moved more than half their margin since the step
//! started), over pairs taken afresh around the move.

use super::ad::{dot, node, norm, sub, V};
use super::barrier::{self, Barrier};
use super::broad::{self, Candidate, Surface};
use super::ccd::{self, Stencil};
use crate::error::HistoryError;
use crate::force::{EvalInput, Force, JacobianKind, LocalBlocks};

/// The held pairs are taken within this many times the reach a step needs (`√d̂` plus the
/// step's motion): the pattern changes once the surface has moved about that reach relative
/// to itself.
pub const HYSTERESIS: f64 = 3.0;
/// IPC's edge–edge mollifier threshold: `εx = MOLLIFIER |ea|²|eb|²` at rest (§4.3).
const MOLLIFIER: f64 = 1e-3;

/// Self-contact between the triangles, edges and line segments of a [`Surface`].
pub struct SelfContact {
    name: String,
    surface: Surface,
    barrier: Barrier,
    /// Project each pair's Hessian to positive semi-definite (the step solver's setting);
    /// false gives the exact Hessian (derivative checks).
    project: bool,
    /// Rest positions (all DOFs): the edge–edge mollifier's edge lengths.
    rest: Vec<f64>,
    /// The positions the held pairs were taken at (all DOFs).
    taken_at: Vec<f64>,
    /// The held pairs, sorted.
    pairs: Vec<Candidate>,
    /// 12 DOFs per held pair (a point–edge pair padded with its edge's first node).
    stencils: Vec<usize>,
    /// The reach (m) the held pairs were taken within.
    reach: f64,
}

impl SelfContact {
    /// Contact of `surface` (node indices of the model: node `i` has DOFs `3i..3i+3`) with
    /// the barrier `barrier`, at rest positions `q` (every DOF); the pairs are held within
    /// `reach` (m) of `q` until the first step takes them.
    pub fn new(
        name: &str,
        surface: Surface,
        barrier: Barrier,
        q: &[f64],
        reach: f64,
        project: bool,
    ) -> Self {
        let mut c = Self {
            name: name.to_string(),
            surface,
            barrier,
            project,
            rest: q.to_vec(),
            taken_at: q.to_vec(),
            pairs: Vec::new(),
            stencils: Vec::new(),
            reach: 0.0,
        };
        c.take_pairs(q, reach.max(barrier.d_hat.sqrt()));
        c
    }

    /// The barrier.
    pub fn barrier(&self) -> &Barrier {
        &self.barrier
    }

    /// The pairs held.
    pub fn pairs(&self) -> &[Candidate] {
        &self.pairs
    }

    /// The surface it guards.
    pub fn surface(&self) -> &Surface {
        &self.surface
    }

    fn take_pairs(&mut self, q: &[f64], reach: f64) {
        self.pairs = broad::candidates(&self.surface, q, reach);
        self.stencils = self.pairs.iter().flat_map(|c| dofs(c.nodes())).collect();
        self.taken_at.copy_from_slice(q);
        self.reach = reach;
    }

    fn nodes(&self) -> impl Iterator<Item = usize> + '_ {
        let s = &self.surface;
        (s.points.iter().copied()).chain(s.line_edges.iter().flatten().copied())
    }

    /// The largest of `|f(i) − mean f|` over the surface's nodes: how far a node moves
    /// relative to the surface's mean motion when it moves by `f(i)` (a rigid translation
    /// moves no pair closer, so it does not count).
    fn spread(&self, f: impl Fn(usize) -> V<f64>) -> f64 {
        let (mut mean, mut n) = ([0.0; 3], 0.0);
        for i in self.nodes() {
            let m = f(i);
            (0..3).for_each(|k| mean[k] += m[k]);
            n += 1.0;
        }
        let mean = mean.map(|m| m / f64::max(n, 1.0));
        self.nodes()
            .map(|i| norm(sub(f(i), mean)))
            .fold(0.0, f64::max)
    }

    /// The surface's relative motion ([`SelfContact::spread`]) from where its pairs were
    /// taken to `q + s dq`, largest over `s ∈ [0, 1]`: at an end, the motion being affine in
    /// `s` and its norm convex.
    fn drift(&self, q: &[f64], dq: &[f64]) -> f64 {
        let at = |s: f64| {
            move |i: usize| -> V<f64> {
                let (t, x, d) = (node(&self.taken_at, i), node(q, i), node(dq, i));
                std::array::from_fn(|k| x[k] + s * d[k] - t[k])
            }
        };
        self.spread(at(0.0)).max(self.spread(at(1.0)))
    }

    /// How far (m) the surface may move relative to itself from where the pairs were taken
    /// before a pair that is not held can come within `√d̂`: a pair not held was farther than
    /// the reach apart, and each of its sides moves by at most this.
    fn covered(&self) -> f64 {
        0.5 * (self.reach - self.barrier.d_hat.sqrt())
    }

    /// Energy, gradient and Hessian of held pair `i` at `q` (`None` when inactive).
    fn pair_terms(&self, c: &Candidate, q: &[f64]) -> Option<(f64, [f64; 12], [f64; 144])> {
        let ids = c.nodes();
        let x: [f64; 12] = std::array::from_fn(|k| q[3 * ids[k / 3] + k % 3]);
        let v: [V<f64>; 4] = ids.map(|i| node(q, i));
        let (kind, d) = c.feature(&v);
        if d >= self.barrier.d_hat || d <= 0.0 {
            return None;
        }
        let mollifier = matches!(c, Candidate::EdgeEdge(_)).then(|| {
            let r: [V<f64>; 4] = ids.map(|i| node(&self.rest, i));
            let (a, b) = (sub(r[1], r[0]), sub(r[3], r[2]));
            MOLLIFIER * dot(a, a) * dot(b, b)
        });
        barrier::pair(&self.barrier, kind, &x, mollifier)
    }
}

fn dofs(n: [usize; 4]) -> impl Iterator<Item = usize> {
    n.into_iter().flat_map(|i| [3 * i, 3 * i + 1, 3 * i + 2])
}

fn stencil_kind(c: &Candidate) -> Stencil {
    match c {
        Candidate::PointTriangle(_) => Stencil::PointTriangle,
        Candidate::EdgeEdge(_) => Stencil::EdgeEdge,
        Candidate::PointEdge(_) => Stencil::PointEdge,
    }
}

/// The smallest CCD step of `pairs` along `dq` from `q`.
fn ccd_bound(pairs: &[Candidate], q: &[f64], dq: &[f64], gap: f64) -> f64 {
    let mut t = 1.0f64;
    for c in pairs {
        let ids = c.nodes();
        let (x, dx) = (ids.map(|i| node(q, i)), ids.map(|i| node(dq, i)));
        t = ccd::max_step(stencil_kind(c), &x, &dx, gap, t);
        if t == 0.0 {
            break;
        }
    }
    t
}

impl Force for SelfContact {
    fn name(&self) -> &str {
        &self.name
    }
    fn stencil_size(&self) -> usize {
        12
    }
    fn stencils(&self) -> &[usize] {
        &self.stencils
    }
    fn jacobian_kind(&self) -> JacobianKind {
        JacobianKind::ELASTIC
    }
    fn conservative(&self) -> bool {
        true
    }
    fn energy(&self, q: &[f64]) -> Option<f64> {
        Some(
            (self.pairs.iter())
                .filter_map(|c| self.pair_terms(c, q).map(|t| t.0))
                .sum(),
        )
    }
    fn evaluate(&self, input: &EvalInput<'_>, out: &mut LocalBlocks) {
        let q = input.q;
        out.par_for_each(input.jacobian, |b| {
            b.f.iter_mut().for_each(|x| *x = 0.0);
            b.dfdq.iter_mut().for_each(|x| *x = 0.0);
            let Some((_, g, mut h)) = self.pair_terms(&self.pairs[b.index], q) else {
                return;
            };
            for (f, g) in b.f.iter_mut().zip(g) {
                *f = -g;
            }
            if !b.dfdq.is_empty() {
                if self.project {
                    barrier::project_psd(&mut h);
                }
                for (j, h) in b.dfdq.iter_mut().zip(h) {
                    *j = -h;
                }
            }
        });
    }
    fn begin_step(&mut self, q: &[f64], v: &[f64], dt: f64) -> bool {
        let motion = if dt.is_finite() {
            // Twice the fastest relative speed over the step.
            2.0 * dt * self.spread(|i| node(v, i))
        } else {
            0.0
        };
        let so_far = self.spread(|i| sub(node(q, i), node(&self.taken_at, i)));
        if so_far + motion < self.covered() {
            return false;
        }
        let held = std::mem::take(&mut self.pairs);
        self.take_pairs(q, HYSTERESIS * (self.barrier.d_hat.sqrt() + motion));
        // Taken afresh from here; the pattern changes only if the pairs did.
        self.pairs != held
    }
    fn bounds_steps(&self) -> bool {
        true
    }
    /// The held pairs follow from where and within what reach they were taken: the reach,
    /// then those positions (so a resumed run holds the same pairs in the same order).
    fn history(&self) -> Vec<f64> {
        std::iter::once(self.reach)
            .chain(self.taken_at.iter().copied())
            .collect()
    }
    fn restore_history(&mut self, h: &[f64]) -> Result<(), HistoryError> {
        if h.len() != 1 + self.taken_at.len() {
            return Err(HistoryError {
                force: self.name.clone(),
                got: h.len(),
                expected: 1 + self.taken_at.len(),
            });
        }
        let q = h[1..].to_vec();
        self.take_pairs(&q, h[0]);
        Ok(())
    }
    fn max_step(&self, q: &[f64], dq: &[f64], gap: f64) -> f64 {
        if self.drift(q, dq) < self.covered() {
            return ccd_bound(&self.pairs, q, dq, gap);
        }
        // The move leaves what the held pairs cover: take the pairs around it.
        let far = self.nodes().map(|i| norm(node(dq, i))).fold(0.0, f64::max);
        let around = broad::candidates(&self.surface, q, self.barrier.d_hat.sqrt() + 2.0 * far);
        ccd_bound(&around, q, dq, gap)
    }
}

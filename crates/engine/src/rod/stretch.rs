//! Axial stretching of edges, shared by rods and shell edges.
//!
//! Energy of an edge `e = x₁ − x₀` with rest length `l̄` and axial stiffness `k` (N):
//! `E = ½ k ε² l̄`, `ε = |e|/l̄ − 1`. With `ê = e/|e|`:
//! - force on node 1: `f₁ = −k ε ê`, on node 0: `f₀ = +k ε ê`;
//! - `∂f₁/∂x₁ = −H`, `H = (k/l̄) ê êᵀ + (k ε/|e|)(I − ê êᵀ)`; `∂f₀/∂x₁ = +H`.
//!
//! For a rod `k = E A`; for a shell edge `k = k_s = (√3/2) E h |ē|` (see `shell`).

use crate::force::{EvalInput, Force, JacobianKind, LocalBlocks};
use crate::vec3::{node, outer, M3, V3};

/// A family of edge springs.
pub struct Stretch {
    name: String,
    stencils: Vec<usize>,
    /// Rest length `l̄` per edge (m).
    pub rest_len: Vec<f64>,
    /// Axial stiffness `k` per edge (N).
    pub stiffness: Vec<f64>,
}

impl Stretch {
    /// Springs on `edges` (node pairs) with rest lengths from `q_rest` and stiffness `k`.
    pub fn new(name: &str, edges: &[[usize; 2]], q_rest: &[f64], stiffness: Vec<f64>) -> Self {
        let rest_len = edges
            .iter()
            .map(|&[a, b]| (node(q_rest, b) - node(q_rest, a)).norm())
            .collect();
        Self::with_rest_lengths(name, edges, rest_len, stiffness)
    }

    /// Springs with explicit rest lengths.
    pub fn with_rest_lengths(
        name: &str,
        edges: &[[usize; 2]],
        rest_len: Vec<f64>,
        stiffness: Vec<f64>,
    ) -> Self {
        assert_eq!(edges.len(), rest_len.len());
        assert_eq!(edges.len(), stiffness.len());
        let stencils = edges
            .iter()
            .flat_map(|&[a, b]| [3 * a, 3 * a + 1, 3 * a + 2, 3 * b, 3 * b + 1, 3 * b + 2])
            .collect();
        Self {
            name: name.to_string(),
            stencils,
            rest_len,
            stiffness,
        }
    }

    /// Node indices of edge `i`.
    pub fn edge(&self, i: usize) -> [usize; 2] {
        [self.stencils[6 * i] / 3, self.stencils[6 * i + 3] / 3]
    }
}

/// Edge vector, length and strain of edge `i`.
#[inline]
fn kinematics(q: &[f64], st: &[usize], rest: f64) -> (V3, f64, f64) {
    let e = node(q, st[3] / 3) - node(q, st[0] / 3);
    let l = e.norm();
    (e, l, l / rest - 1.0)
}

impl Force for Stretch {
    fn name(&self) -> &str {
        &self.name
    }
    fn stencil_size(&self) -> usize {
        6
    }
    fn stencils(&self) -> &[usize] {
        &self.stencils
    }
    fn jacobian_kind(&self) -> JacobianKind {
        JacobianKind::ELASTIC
    }
    fn evaluate(&self, input: &EvalInput<'_>, out: &mut LocalBlocks) {
        let q = input.q;
        out.par_for_each(input.jacobian, |b| {
            let i = b.index;
            let st = &self.stencils[6 * i..6 * i + 6];
            let (k, rest) = (self.stiffness[i], self.rest_len[i]);
            let (e, l, eps) = kinematics(q, st, rest);
            let t = e / l;
            let f1 = -k * eps * t;
            for c in 0..3 {
                b.f[c] = -f1[c];
                b.f[3 + c] = f1[c];
            }
            if b.dfdq.is_empty() {
                return;
            }
            let tt = outer(&t, &t);
            let h: M3 = tt * (k / rest) + (M3::identity() - tt) * (k * eps / l);
            for r in 0..3 {
                for c in 0..3 {
                    let x = h[(r, c)];
                    b.dfdq[r * 6 + c] = -x;
                    b.dfdq[r * 6 + 3 + c] = x;
                    b.dfdq[(3 + r) * 6 + c] = x;
                    b.dfdq[(3 + r) * 6 + 3 + c] = -x;
                }
            }
        });
    }
    fn conservative(&self) -> bool {
        true
    }
    fn energy(&self, q: &[f64]) -> Option<f64> {
        let mut e = 0.0;
        for (i, st) in self.stencils.chunks(6).enumerate() {
            let (_, _, eps) = kinematics(q, st, self.rest_len[i]);
            e += 0.5 * self.stiffness[i] * eps * eps * self.rest_len[i];
        }
        Some(e)
    }
}

//! Axial stretching of edges, shared by rods and shell edges.
//!
//! Energy of an edge `e = x₁ − x₀` with rest length `l̄` and axial stiffness `k` (N):
//! `E = ½ k ε² l̄`, `ε = |e|/l̄ − 1`. With `ê = e/|e|`:
//! - force on node 1: `f₁ = −k ε ê`, on node 0: `f₀ = +k ε ê`;
//! - `∂f₁/∂x₁ = −H`, `H = (k/l̄) ê êᵀ + (k ε/|e|)(I − ê êᵀ)`; `∂f₀/∂x₁ = +H`.
//!
//! For a rod `k = E A`; for a shell edge `k = k_s = (√3/2) E h |ē|` (see `shell`).

use crate::element::{node_stencils, Element, Family};
use crate::force::{BlockMut, EvalInput, JacobianKind};
use crate::vec3::{node, outer, M3, V3};

/// The edge-spring law (stateless: everything is per edge).
#[derive(Debug, Clone, Copy, Default)]
pub struct StretchLaw;

/// Rest length and stiffness of one edge spring.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EdgeSpring {
    /// Rest length `l̄` (m).
    pub rest_len: f64,
    /// Axial stiffness `k` (N).
    pub stiffness: f64,
}

/// A family of edge springs.
pub type Stretch = Family<StretchLaw>;

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
        let data = rest_len
            .iter()
            .zip(&stiffness)
            .map(|(&rest_len, &stiffness)| EdgeSpring {
                rest_len,
                stiffness,
            })
            .collect();
        Family::from_elements(name, StretchLaw, node_stencils(edges), data)
    }

    /// Node indices of edge `i`.
    pub fn edge(&self, i: usize) -> [usize; 2] {
        let st = self.stencil(i);
        [st[0] / 3, st[3] / 3]
    }
}

/// Edge vector, length and strain of the edge on stencil `st`.
#[inline]
fn kinematics(q: &[f64], st: &[usize], rest: f64) -> (V3, f64, f64) {
    let e = node(q, st[3] / 3) - node(q, st[0] / 3);
    let l = e.norm();
    (e, l, l / rest - 1.0)
}

impl Element for StretchLaw {
    const STENCIL: usize = 6;
    const KIND: JacobianKind = JacobianKind::ELASTIC;
    const CONSERVATIVE: bool = true;
    type Data = EdgeSpring;

    fn evaluate(&self, el: &EdgeSpring, st: &[usize], input: &EvalInput<'_>, b: BlockMut<'_>) {
        let (k, rest) = (el.stiffness, el.rest_len);
        let (e, l, eps) = kinematics(input.q, st, rest);
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
    }

    fn add_energy(&self, el: &EdgeSpring, st: &[usize], q: &[f64], acc: &mut f64) {
        let (_, _, eps) = kinematics(q, st, el.rest_len);
        *acc += 0.5 * el.stiffness * eps * eps * el.rest_len;
    }
}

//! The bend–twist force family of Discrete Elastic Rods (one element per pair of edges
//! meeting at a node), with its reference-frame history.
//!
//! Bending and twisting share the stencil `[x_{i−1}, x_i, x_{i+1}, θ_{e0}, θ_{e1}]` (11 DOFs)
//! and the frame history, so they are one family: per element the energy (J) is
//!
//! `E = ½ [EI2 (κ1 − κ̄1)² + EI1 (κ2 − κ̄2)² + GJ (τ − τ̄)²] / l̄`
//!
//! with `κ1`, `κ2` from `bend`, `τ` from `twist`, `EI1`/`EI2` the bending stiffnesses about
//! the material directors `d1 = m1` / `d2 = m2` (N·m²), `GJ` the torsional stiffness (N·m²)
//! and `l̄` the Voronoi length (m). Natural curvatures `κ̄` and twist `τ̄` are those of the rest
//! shape with zero twist angles.
//!
//! **Frames within a step.** The reference frame of each edge is a function of the current
//! edge: `a1(e) = P(u → e/|e|) a1_old`, the time-parallel transport from the tangent `u`
//! and director `a1_old` of the last accepted configuration (the history, advanced in
//! [`crate::Force::commit`]). So within a step the energy is an ordinary function of `q`, and the
//! force and Jacobian written here are its *exact* gradient and Hessian — including the twist
//! `g_k = −(u_k × t_k)/((1 + u_k·t_k)|e_k|)` that transported frames pick up when
//! `t_k ≠ u_k`, which the textbook DER gradient omits (it is exact only at `t_k = u_k`).
//! Newton therefore converges quadratically and the force equals `−∇E` to round-off.
//!
//! **Orientation.** `e0` must point into node `i` and `e1` out of it. A network edge stored
//! the other way round enters with sign `s = −1`: its tangent and twist angle are negated
//! (`t → −t`, `θ → −θ`, `a1` kept, hence `m1` kept and `m2 → −m2`), as in DisMech.
//!
//! **Rest alignment.** The averaged directors `m_j0 + m_j1` of `bend` vanish when the two
//! material frames differ by a half turn, and then `κ ≡ 0` (no bending stiffness). That
//! happens at a joint between rods whose reference frames are opposed (e.g. a rod listed in
//! the reverse direction, whose default director is then −ŷ instead of ŷ). Each element
//! therefore measures the twist angle of `e1` from the rest alignment, `θ1 → s θ1 − m_rest`
//! (`m_rest` the reference twist of the rest shape), so both frames coincide at rest and
//! `τ̄ = 0`. Inside a rod `m_rest = 0` (space-parallel frames), so this changes nothing
//! there. As in any DER, the twist across one element must stay well below π.
//!
//! **Hessian.** The gradient is coded once in closed form, generically over the scalar type;
//! evaluated on dual numbers seeded on the 8 local variables `(e0, e1, θ0, θ1)` it yields the
//! exact local Hessian, mapped to the 11 stencil DOFs by the constant map `e0 = x_i − x_{i−1}`,
//! `e1 = x_{i+1} − x_i`, `θ_loc = s θ`.

use super::bend::{curvature_gradients, curvatures};
use super::frames::{transport, RodFrames};
use super::scalar::{Dual, Real, G3};
use super::twist::{reference_twist, reference_twist_gradient};
use crate::element::{Element, Family};
use crate::force::{BlockMut, EvalInput, JacobianKind};
use crate::vec3::{node, V3};
use nalgebra::SMatrix;

/// One bend–twist element: two edges meeting at a node.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BendTwistElement {
    /// Nodes `[i−1, i, i+1]`: `e0 = x_i − x_{i−1}`, `e1 = x_{i+1} − x_i`.
    pub nodes: [usize; 3],
    /// Frame indices (edges of the family's frame list) of `e0` and `e1`.
    pub edges: [usize; 2],
    /// `+1` when the frame edge points like `e0` (resp. `e1`), `−1` when reversed.
    pub signs: [f64; 2],
    /// Bending stiffness about `d1 = m1`, paired with `κ2` (N·m²).
    pub ei1: f64,
    /// Bending stiffness about `d2 = m2`, paired with `κ1` (N·m²).
    pub ei2: f64,
    /// Torsional stiffness `GJ` (N·m²).
    pub gj: f64,
    /// Voronoi length `l̄` (m): half the sum of the two rest edge lengths.
    pub voronoi_len: f64,
}

/// Local geometry of one element, generic over the scalar (`f64` or dual numbers).
pub(crate) struct Local<T> {
    /// Edge lengths `|e_k|` (m).
    pub n: [T; 2],
    /// Unit tangents.
    pub t: [G3<T>; 2],
    /// Reference directors `a1_k`, time-parallel transported to `t_k`.
    pub r1: [G3<T>; 2],
    /// Material directors `m1_k`.
    pub m1: [G3<T>; 2],
    /// Material directors `m2_k`.
    pub m2: [G3<T>; 2],
    /// Curvature binormal `κb` (dimensionless).
    pub kb: G3<T>,
    /// `χ = 1 + t0·t1`.
    pub chi: T,
    /// Frame-transport twist rates `g_k = ∂ψ_k/∂e_k` (rad/m).
    pub g: [G3<T>; 2],
    /// Local twist angles `θ_k` (rad).
    pub th: [T; 2],
}

/// History of an element's two edges in local orientation: last tangents `u` and `a1`.
struct Hist {
    u: [V3; 2],
    a: [V3; 2],
}

impl<T: Real> Local<T> {
    fn new(e: [G3<T>; 2], th: [T; 2], h: &Hist) -> Self {
        let one = T::cst(1.0);
        let n = [e[0].norm(), e[1].norm()];
        let t = [e[0].scale(one / n[0]), e[1].scale(one / n[1])];
        let mut r1 = t;
        let mut m1 = t;
        let mut m2 = t;
        let mut g = t;
        for k in 0..2 {
            let u = G3::cst(&h.u[k]);
            r1[k] = transport(&G3::cst(&h.a[k]), &u, &t[k]);
            let r2 = t[k].cross(&r1[k]);
            let (s, c) = (th[k].sin(), th[k].cos());
            m1[k] = r1[k].scale(c) + r2.scale(s);
            m2[k] = r2.scale(c) - r1[k].scale(s);
            g[k] = -u.cross(&t[k]).scale(one / ((u.dot(&t[k]) + 1.0) * n[k]));
        }
        let chi = t[0].dot(&t[1]) + 1.0;
        let kb = t[0].cross(&t[1]).scale(T::cst(2.0) / chi);
        Self {
            n,
            t,
            r1,
            m1,
            m2,
            kb,
            chi,
            g,
            th,
        }
    }
}

/// Rest values and stiffness of one element, in the form the kernel needs.
struct Consts {
    ei: [f64; 2],
    gj: f64,
    inv_len: f64,
    kappa_bar: [f64; 2],
    tau_bar: f64,
    /// Rest alignment `c = −m_rest` added to the local twist of `e1` (rad).
    align: f64,
}

/// Energy (J) of one element.
fn energy_of(l: &Local<f64>, m: f64, c: &Consts) -> f64 {
    let k = curvatures(l);
    let tau = l.th[1] - l.th[0] + m;
    let d = [
        k[0] - c.kappa_bar[0],
        k[1] - c.kappa_bar[1],
        tau - c.tau_bar,
    ];
    0.5 * c.inv_len * (c.ei[0] * d[0] * d[0] + c.ei[1] * d[1] * d[1] + c.gj * d[2] * d[2])
}

/// Exact gradient `∂E/∂(e0, e1, θ0, θ1)` of one element (local variables).
fn gradient<T: Real>(l: &Local<T>, m: T, c: &Consts) -> [T; 8] {
    let kappa = curvatures(l);
    let cg = curvature_gradients(l, &kappa);
    let mg = reference_twist_gradient(l);
    let tau = l.th[1] - l.th[0] + m;
    let c1 = (kappa[0] + (-c.kappa_bar[0])) * (c.ei[0] * c.inv_len);
    let c2 = (kappa[1] + (-c.kappa_bar[1])) * (c.ei[1] * c.inv_len);
    let ct = (tau + (-c.tau_bar)) * (c.gj * c.inv_len);
    let mut out = [T::cst(0.0); 8];
    for k in 0..2 {
        let ge = cg.de[0][k].scale(c1) + cg.de[1][k].scale(c2) + mg[k].scale(ct);
        out[3 * k..3 * k + 3].copy_from_slice(&ge.0);
    }
    out[6] = cg.dth[0][0] * c1 + cg.dth[1][0] * c2 - ct;
    out[7] = cg.dth[0][1] * c1 + cg.dth[1][1] * c2 + ct;
    out
}

/// One element of the family: its description, rest values and reference twist.
pub struct BendTwistData {
    elem: BendTwistElement,
    consts: Consts,
    /// Reference twist at the last accepted configuration (rad): history.
    ref_twist: f64,
}

/// The bend–twist law: the reference frames of every edge (the history shared by the
/// elements).
pub struct BendTwistLaw {
    edge_nodes: Vec<[usize; 2]>,
    frames: RodFrames,
}

/// Bending and twisting of a set of rods (see the module docs).
pub type BendTwist = Family<BendTwistLaw>;

impl BendTwist {
    /// Elements `elems` over frame edges `edge_nodes` (node pairs, oriented), whose twist
    /// angles are the DOFs `twist_dofs` and whose first reference directors at the rest
    /// shape `q_rest` are `a1` (unit, ⟂ to the edges). Natural curvature and twist are those
    /// of `q_rest` with zero twist angles.
    pub fn new(
        name: &str,
        elems: Vec<BendTwistElement>,
        edge_nodes: Vec<[usize; 2]>,
        twist_dofs: &[usize],
        a1: Vec<V3>,
        q_rest: &[f64],
    ) -> Self {
        assert_eq!(edge_nodes.len(), twist_dofs.len());
        let tangent = edge_nodes
            .iter()
            .map(|&[a, b]| (node(q_rest, b) - node(q_rest, a)).normalize())
            .collect();
        let frames = RodFrames::new(tangent, a1);
        let mut stencils = Vec::with_capacity(11 * elems.len());
        for el in &elems {
            for nd in el.nodes {
                stencils.extend_from_slice(&[3 * nd, 3 * nd + 1, 3 * nd + 2]);
            }
            stencils.extend(el.edges.iter().map(|&e| twist_dofs[e]));
        }
        let data = elems
            .into_iter()
            .map(|elem| BendTwistData {
                consts: Consts {
                    ei: [elem.ei2, elem.ei1],
                    gj: elem.gj,
                    inv_len: 1.0 / elem.voronoi_len,
                    kappa_bar: [0.0; 2],
                    tau_bar: 0.0,
                    align: 0.0,
                },
                ref_twist: 0.0,
                elem,
            })
            .collect();
        let law = BendTwistLaw { edge_nodes, frames };
        let mut me = Family::from_elements(name, law, stencils, data);
        let mut q0 = q_rest.to_vec();
        for st in me.stencils.chunks(11) {
            q0[st[9]] = 0.0;
            q0[st[10]] = 0.0;
        }
        let Family {
            law,
            stencils,
            data,
            ..
        } = &mut me;
        for (el, st) in data.iter_mut().zip(stencils.chunks(11)) {
            let m = reference_twist(&law.local_f64(&q0, el, st), 0.0);
            el.ref_twist = m;
            el.consts.align = -m;
            let l = law.local_f64(&q0, el, st);
            el.consts.kappa_bar = curvatures(&l);
            el.consts.tau_bar = l.th[1] - l.th[0] + m;
        }
        me
    }

    /// The elements.
    pub fn elements(&self) -> impl ExactSizeIterator<Item = &BendTwistElement> {
        self.data.iter().map(|d| &d.elem)
    }
    /// Reference frames at the last accepted configuration.
    pub fn frames(&self) -> &RodFrames {
        &self.law.frames
    }
    /// Reference twist of each element at the last accepted configuration (rad).
    pub fn ref_twists(&self) -> Vec<f64> {
        self.data.iter().map(|d| d.ref_twist).collect()
    }
    /// Natural curvatures `[κ̄1, κ̄2]` of each element.
    pub fn natural_curvatures(&self) -> Vec<[f64; 2]> {
        self.data.iter().map(|d| d.consts.kappa_bar).collect()
    }
    /// Material curvatures `[κ1, κ2]` and twist `τ` of each element at `q`.
    pub fn strains(&self, q: &[f64]) -> Vec<([f64; 2], f64)> {
        self.data
            .iter()
            .zip(self.stencils.chunks(11))
            .map(|(el, st)| {
                let l = self.law.local_f64(q, el, st);
                let m = reference_twist(&l, el.ref_twist);
                (curvatures(&l), l.th[1] - l.th[0] + m)
            })
            .collect()
    }
}

impl BendTwistLaw {
    /// Edge vectors, local twists and local history of element `el` on stencil `st`.
    fn gather(&self, q: &[f64], el: &BendTwistData, st: &[usize]) -> ([V3; 2], [f64; 2], Hist) {
        let e = &el.elem;
        let x = e.nodes.map(|n| node(q, n));
        let s = e.signs;
        let hist = Hist {
            u: [
                self.frames.tangent[e.edges[0]] * s[0],
                self.frames.tangent[e.edges[1]] * s[1],
            ],
            a: [self.frames.a1[e.edges[0]], self.frames.a1[e.edges[1]]],
        };
        (
            [x[1] - x[0], x[2] - x[1]],
            [s[0] * q[st[9]], s[1] * q[st[10]] + el.consts.align],
            hist,
        )
    }

    fn local_f64(&self, q: &[f64], el: &BendTwistData, st: &[usize]) -> Local<f64> {
        let (e, th, h) = self.gather(q, el, st);
        Local::new([G3::cst(&e[0]), G3::cst(&e[1])], th, &h)
    }
}

impl Element for BendTwistLaw {
    const STENCIL: usize = 11;
    const KIND: JacobianKind = JacobianKind::ELASTIC;
    type Data = BendTwistData;

    /// Local force (11) and `∂f/∂q` (11×11, row-major) of one element.
    fn evaluate(&self, el: &BendTwistData, st: &[usize], input: &EvalInput<'_>, b: BlockMut<'_>) {
        let (q, f, dfdq) = (input.q, b.f, b.dfdq);
        let s = el.elem.signs;
        if dfdq.is_empty() {
            // Force only (modified-Newton trial residuals): the same closed-form gradient in
            // plain f64, ~8× cheaper than carrying 8 dual components through it.
            let l = self.local_f64(q, el, st);
            let m = reference_twist(&l, el.ref_twist);
            let g = gradient(&l, m, &el.consts);
            write_force(&g, s, f);
            return;
        }
        let (e, th, h) = self.gather(q, el, st);
        let mut ev = [G3([Dual::<8>::cst(0.0); 3]); 2];
        for k in 0..2 {
            for c in 0..3 {
                ev[k].0[c] = Dual::var(e[k][c], 3 * k + c);
            }
        }
        let thd = [Dual::var(th[0], 6), Dual::var(th[1], 7)];
        let l = Local::new(ev, thd, &h);
        let m = reference_twist(&l, el.ref_twist);
        let g = gradient(&l, m, &el.consts);
        write_force(&g, s, f);
        let hl = SMatrix::<f64, 8, 8>::from_fn(|r, c| 0.5 * (g[r].d[c] + g[c].d[r]));
        let mut bm = SMatrix::<f64, 8, 11>::zeros();
        for r in 0..6 {
            bm[(r, r)] = -1.0;
            bm[(r, r + 3)] = 1.0;
        }
        bm[(6, 9)] = s[0];
        bm[(7, 10)] = s[1];
        let k = bm.transpose() * hl * bm;
        for r in 0..11 {
            for c in 0..11 {
                dfdq[r * 11 + c] = -k[(r, c)];
            }
        }
    }

    fn add_energy(&self, el: &BendTwistData, st: &[usize], q: &[f64], acc: &mut f64) {
        let l = self.local_f64(q, el, st);
        let m = reference_twist(&l, el.ref_twist);
        *acc += energy_of(&l, m, &el.consts);
    }

    /// Advance the history: reference twists on their branch, then time-parallel transport
    /// of every edge's reference frame to its new tangent.
    fn commit(&mut self, els: &mut [BendTwistData], stencils: &[usize], q: &[f64], _v: &[f64]) {
        for (el, st) in els.iter_mut().zip(stencils.chunks(11)) {
            let l = self.local_f64(q, el, st);
            el.ref_twist = reference_twist(&l, el.ref_twist);
        }
        for (e, &[a, b]) in self.edge_nodes.iter().enumerate() {
            let t = (node(q, b) - node(q, a)).normalize();
            self.frames.time_transport(e, &t);
        }
    }

    fn history_len(&self, n_elements: usize) -> usize {
        n_elements + 6 * self.frames.tangent.len()
    }

    /// `[ref_twist…, (tangent, a1) per edge…]`: everything `commit` advances.
    fn history(&self, els: &[BendTwistData]) -> Vec<f64> {
        let mut h: Vec<f64> = els.iter().map(|d| d.ref_twist).collect();
        h.reserve(6 * self.frames.tangent.len());
        for (t, a) in self.frames.tangent.iter().zip(&self.frames.a1) {
            h.extend_from_slice(t.as_slice());
            h.extend_from_slice(a.as_slice());
        }
        h
    }

    fn restore_history(&mut self, els: &mut [BendTwistData], h: &[f64]) {
        let n_el = els.len();
        for (el, &m) in els.iter_mut().zip(&h[..n_el]) {
            el.ref_twist = m;
        }
        for (e, c) in h[n_el..].chunks_exact(6).enumerate() {
            self.frames.tangent[e] = V3::new(c[0], c[1], c[2]);
            self.frames.a1[e] = V3::new(c[3], c[4], c[5]);
        }
    }
}

/// Local force (11) from the gradient `g = ∂E/∂(e₀, e₁, θ₀, θ₁)` (J/m, J/rad): nodes get
/// `−∂E/∂x` through `e₀ = x₁ − x₀`, `e₁ = x₂ − x₁`; twists through the edge signs `s`.
fn write_force<T: Real>(g: &[T; 8], s: [f64; 2], f: &mut [f64]) {
    for c in 0..3 {
        f[c] = g[c].val();
        f[3 + c] = g[3 + c].val() - g[c].val();
        f[6 + c] = -g[3 + c].val();
    }
    f[9] = -s[0] * g[6].val();
    f[10] = -s[1] * g[7].val();
}

//! The kernel of one mid-edge face: its force and 21 × 21 Jacobian from the face's own
//! geometry and its interior edges' dihedral quantities (computed once per edge by
//! [`super::hinges`]).
//!
//! With `∇c_i = A_i ∇h_i + B_i ∇β_i` (`A = 2 sin β`, `B = 2h cos β`) the Hessian is
//! `U W Uᵀ + Σ_i (r_i A_i ∇²h_i + ½ r_i B_i ∇²θ_i)`, `U = [∇h₀, ∇β₀, ∇h₁, ∇β₁, ∇h₂, ∇β₂]`
//! and `W` the 6 × 6 of `K_ij ∇c_i ∇c_jᵀ` and the rank-one parts of `r_i ∇²c_i` (module docs
//! of [`super`]). It is accumulated by blocks, on the stencil's `v0, v1, v2` (9 DOFs, where
//! every term lives) and on each edge's wing `(o_i, ψ_i)` (4 DOFs, which only `∇β_i` and
//! `∇²θ_i` reach), then written once into the 21 × 21 block.

use super::hinges::EdgeAngle;
use super::{read, MidedgeData, NS};
use crate::force::BlockMut;
use crate::vec3::V3;

/// The face's `|N|` (`N = (v1 − v0) × (v2 − v0)`), unit normal, edges `e_k = v_{k+2} − v_{k+1}`
/// and `∇_k|N| = n̂ × e_k`.
struct Area {
    nn: f64,
    nh: V3,
    e: [V3; 3],
    gn: [V3; 3],
}

impl Area {
    fn new(x: &[V3; 6]) -> Self {
        let n = (x[1] - x[0]).cross(&(x[2] - x[0]));
        let nn = n.norm();
        let nh = n / nn;
        let e = [0, 1, 2].map(|k| x[(k + 2) % 3] - x[(k + 1) % 3]);
        Self {
            nn,
            nh,
            e,
            gn: e.map(|ek| nh.cross(&ek)),
        }
    }
}

/// Edge `i` of a face: its length, unit vector `ê` (from `v_{i+1}` to `v_{i+2}`), altitude
/// `h`, angle `β`, `∇h` (on `v0, v1, v2`) and `∇β` on `v0, v1, v2` and on the wing
/// `(o_i, ψ_i)`.
struct Edge {
    len: f64,
    e_hat: V3,
    h: f64,
    beta: f64,
    grad_h: [f64; 9],
    grad_beta: [f64; 9],
    grad_wing: [f64; 4],
}

/// `∂l_i/∂v_k = side · ê_i`: −1 at `v_{i+1}`, +1 at `v_{i+2}`, 0 at `v_i`.
#[inline]
pub(super) fn side(i: usize, k: usize) -> f64 {
    if k == (i + 1) % 3 {
        -1.0
    } else if k == (i + 2) % 3 {
        1.0
    } else {
        0.0
    }
}

/// Edge `i` of the face with angles `psi`; `theta` is its dihedral angle's view (`None` on
/// the boundary, where `β = ψ`).
fn edge(el: &MidedgeData, psi: &[f64; 3], i: usize, a: &Area, theta: Option<&EdgeAngle>) -> Edge {
    let len = a.e[i].norm();
    let inv = 1.0 / len;
    let e_hat = a.e[i] * inv;
    // ∇h = ∇|N|/l − |N| ∇l/l², ∇l = ∓ê at v_{i+1}, v_{i+2} (`side`).
    let mut grad_h = [0.0; 9];
    for k in 0..3 {
        for d in 0..3 {
            grad_h[3 * k + d] = a.gn[k][d] * inv;
        }
    }
    let w = a.nn * inv * inv;
    let (ka, kb) = ((i + 1) % 3, (i + 2) % 3);
    for d in 0..3 {
        grad_h[3 * ka + d] += w * e_hat[d];
        grad_h[3 * kb + d] -= w * e_hat[d];
    }
    let mut grad_beta = [0.0; 9];
    let (beta, grad_wing) = match theta {
        Some(t) => {
            for (r, k) in [ka, kb, i].into_iter().enumerate() {
                let g = t.grad(r);
                for d in 0..3 {
                    grad_beta[3 * k + d] = 0.5 * g[d];
                }
            }
            let g = t.grad(3);
            let wing = [0.5 * g[0], 0.5 * g[1], 0.5 * g[2], el.sign[i]];
            (0.5 * t.theta() + el.sign[i] * psi[i], wing)
        }
        None => (psi[i], [0.0, 0.0, 0.0, 1.0]),
    };
    Edge {
        len,
        e_hat,
        h: a.nn * inv,
        beta,
        grad_h,
        grad_beta,
        grad_wing,
    }
}

/// The Hessian of the face by blocks: `vv` on `v0, v1, v2`, `vw[i]` between them and edge
/// `i`'s wing `(o_i, ψ_i)`, `ww` between the wings (row and column `4i + t`).
struct Blocks {
    vv: [[f64; 9]; 9],
    vw: [[[f64; 4]; 9]; 3],
    ww: [[f64; 12]; 12],
}

impl Blocks {
    /// `U W Uᵀ`: `∇h_i` lives on `v` only, `∇β_i` on `v` and on wing `i`.
    fn low_rank(edges: &[Edge; 3], w: &[[f64; 6]; 6]) -> Self {
        let u: [&[f64; 9]; 6] = std::array::from_fn(|k| {
            let e = &edges[k / 2];
            if k % 2 == 0 {
                &e.grad_h
            } else {
                &e.grad_beta
            }
        });
        // V = W U on v (W is symmetric).
        let mut v = [[0.0; 9]; 6];
        for (k, vk) in v.iter_mut().enumerate() {
            for (l, ul) in u.iter().enumerate() {
                let wkl = w[k][l];
                for m in 0..9 {
                    vk[m] += wkl * ul[m];
                }
            }
        }
        let mut vv = [[0.0; 9]; 9];
        for (m, row) in vv.iter_mut().enumerate() {
            for (vk, uk) in v.iter().zip(&u) {
                let vkm = vk[m];
                for n in 0..9 {
                    row[n] += vkm * uk[n];
                }
            }
        }
        let g = edges.each_ref().map(|e| &e.grad_wing);
        let mut vw = [[[0.0; 4]; 9]; 3];
        for (i, vwi) in vw.iter_mut().enumerate() {
            for (row, vm) in vwi.iter_mut().zip(v[2 * i + 1]) {
                for (x, gt) in row.iter_mut().zip(g[i]) {
                    *x = vm * gt;
                }
            }
        }
        let mut ww = [[0.0; 12]; 12];
        for i in 0..3 {
            for j in 0..3 {
                let wij = w[2 * i + 1][2 * j + 1];
                for s in 0..4 {
                    for t in 0..4 {
                        ww[4 * i + s][4 * j + t] = wij * g[i][s] * g[j][t];
                    }
                }
            }
        }
        Self { vv, vw, ww }
    }

    /// `+= Σ_i α_i ∇²h_i` on `v`, with `h_i = |N|/l_i`: block `(k, m)` of `∇²h_i` is
    /// `∇²_{km}|N|/l − (s_m ∇_k|N| êᵀ + s_k ê ∇_m|N|ᵀ)/l² + s_k s_m (|N|/l³)(3êêᵀ − I)`
    /// (`s_k` = [`side`]), so the `|N|` Hessian enters once, weighted by `Σ α_i/l_i`; its
    /// block is `−(e_m e_kᵀ − (e_k·e_m) I + ∇_k|N| ∇_m|N|ᵀ)/|N| ± [n̂]×` (`+` for
    /// `m = k + 2`, `−` for `m = k + 1`, mod 3). With `g = ∇|N|` and `gl_i = ∇l_i` (on
    /// `v_{i+1}, v_{i+2}` only) the rank-one terms are `−(c g + Σ_i c1_i gl_i) gᵀ` and
    /// `−Σ_i (c1_i g − 3 c2_i gl_i) gl_iᵀ` (`c = Σ α_i/(l_i |N|)`, `c1 = α/l²`, `c2 = α|N|/l³`).
    fn add_altitudes(&mut self, edges: &[Edge; 3], alpha: &[f64; 3], a: &Area) {
        let wsum: f64 = (0..3).map(|i| alpha[i] / edges[i].len).sum();
        let (c, nh) = (wsum / a.nn, a.nh * wsum);
        let skew = [[0.0, -nh.z, nh.y], [nh.z, 0.0, -nh.x], [-nh.y, nh.x, 0.0]];
        for k in 0..3 {
            for m in 0..3 {
                let dot = c * a.e[k].dot(&a.e[m]);
                let sgn = [0.0, -1.0, 1.0][(m + 3 - k) % 3];
                for r in 0..3 {
                    let row = &mut self.vv[3 * k + r][3 * m..3 * m + 3];
                    for (d, x) in row.iter_mut().enumerate() {
                        *x += sgn * skew[r][d] - c * a.e[m][r] * a.e[k][d];
                    }
                    row[r] += dot;
                }
            }
        }
        let g: [f64; 9] = std::array::from_fn(|p| a.gn[p / 3][p % 3]);
        let mut left = g.map(|x| c * x);
        for (i, e) in edges.iter().enumerate() {
            let l = e.len;
            let (c1, c2) = (alpha[i] / (l * l), alpha[i] * a.nn / (l * l * l));
            // gl_i = −ê on v_{i+1} (node ka), +ê on v_{i+2} (node kb).
            let (ka, kb) = ((i + 1) % 3, (i + 2) % 3);
            for d in 0..3 {
                left[3 * ka + d] -= c1 * e.e_hat[d];
                left[3 * kb + d] += c1 * e.e_hat[d];
            }
            let gl: [f64; 9] = std::array::from_fn(|p| side(i, p / 3) * e.e_hat[p % 3]);
            for p in 0..9 {
                let a1 = c1 * g[p] - 3.0 * c2 * gl[p];
                let row = &mut self.vv[p];
                for d in 0..3 {
                    row[3 * ka + d] += a1 * e.e_hat[d];
                    row[3 * kb + d] -= a1 * e.e_hat[d];
                }
            }
            for (k, m) in [(ka, ka), (kb, kb), (ka, kb), (kb, ka)] {
                let s = side(i, k) * side(i, m) * c2;
                for d in 0..3 {
                    self.vv[3 * k + d][3 * m + d] -= s;
                }
            }
        }
        for (row, lp) in self.vv.iter_mut().zip(left) {
            for (x, gq) in row.iter_mut().zip(g) {
                *x -= lp * gq;
            }
        }
    }

    /// `+= ρ ∇²θ` of interior edge `i` (hinge `[v_{i+1}, v_{i+2}, v_i, o_i]`), using its
    /// symmetry to read the stored Hessian by contiguous columns.
    fn add_dihedral(&mut self, i: usize, rho: f64, t: &EdgeAngle) {
        let nodes = [(i + 1) % 3, (i + 2) % 3, i];
        for (c, &nc) in nodes.iter().enumerate() {
            for d in 0..3 {
                for (r, &nr) in nodes.iter().enumerate() {
                    let src = t.hess(r, c, d);
                    let dst = &mut self.vv[3 * nc + d][3 * nr..3 * nr + 3];
                    for e in 0..3 {
                        dst[e] += rho * src[e];
                    }
                }
                let src = t.hess(3, c, d);
                let dst = &mut self.vw[i][3 * nc + d];
                for e in 0..3 {
                    dst[e] += rho * src[e];
                }
            }
        }
        for d in 0..3 {
            let src = t.hess(3, 3, d);
            for e in 0..3 {
                self.ww[4 * i + d][4 * i + e] += rho * src[e];
            }
        }
    }

    /// Write `−H` (the Jacobian `∂f/∂q`) into the row-major 21 × 21 block.
    fn write(&self, out: &mut [f64; NS * NS]) {
        // Stencil slot of wing DOF `t` of edge `i`: `o_i` (t < 3) or `ψ_i`.
        let wing = |i: usize, t: usize| if t < 3 { 9 + 3 * i + t } else { 18 + i };
        for m in 0..9 {
            let row = &mut out[NS * m..NS * (m + 1)];
            for n in 0..9 {
                row[n] = -self.vv[m][n];
            }
            for i in 0..3 {
                for t in 0..4 {
                    row[wing(i, t)] = -self.vw[i][m][t];
                }
            }
        }
        for i in 0..3 {
            for s in 0..4 {
                let a = wing(i, s);
                let row = &mut out[NS * a..NS * (a + 1)];
                for n in 0..9 {
                    row[n] = -self.vw[i][n][s];
                }
                for j in 0..3 {
                    for t in 0..4 {
                        row[wing(j, t)] = -self.ww[4 * i + s][4 * j + t];
                    }
                }
            }
        }
    }
}

/// A face's curvature terms from its edges' altitudes `h_i` and angles `β_i`:
/// `c_i = 2 h_i sin β_i`, its partials `(A_i, B_i) = (2 sin β_i, 2 h_i cos β_i)` with respect
/// to `h_i` and `β_i`, and `r_i = Σ_j K_ij (c_j − c̄_j)` (the bending moment conjugate to
/// `c_i`).
pub(super) struct Curvature {
    /// `(A_i, B_i)`.
    pub coef: [(f64, f64); 3],
    /// `r_i` (N·m).
    pub r: [f64; 3],
    /// `(h_i, cos β_i)`, for the weights.
    h_cos: [(f64, f64); 3],
}

impl Curvature {
    /// The terms of the face `el` with edges `(h_i, β_i)`.
    pub(super) fn new(el: &MidedgeData, h_beta: [(f64, f64); 3]) -> Self {
        let sc = h_beta.map(|(_, beta)| beta.sin_cos());
        let coef = [0, 1, 2].map(|i| (2.0 * sc[i].0, 2.0 * h_beta[i].0 * sc[i].1));
        let k = &el.stiffness;
        let dc = [0, 1, 2].map(|i| h_beta[i].0 * coef[i].0 - el.rest[i]);
        let r = [0, 1, 2].map(|i| k[i][0] * dc[0] + k[i][1] * dc[1] + k[i][2] * dc[2]);
        let h_cos = [0, 1, 2].map(|i| (h_beta[i].0, sc[i].1));
        Self { coef, r, h_cos }
    }

    /// `W` of the Hessian's `U W Uᵀ`, `U = [∇h₀, ∇β₀, ∇h₁, ∇β₁, ∇h₂, ∇β₂]`, for the
    /// stiffness `k`: `K_ij (A_i, B_i) ⊗ (A_j, B_j)` plus each edge's second derivatives of
    /// `c_i` in `(h_i, β_i)` weighted by `r_i`.
    pub(super) fn weights(&self, k: &[[f64; 3]; 3]) -> [[f64; 6]; 6] {
        let (coef, r) = (&self.coef, &self.r);
        let mut w = [[0.0; 6]; 6];
        for i in 0..3 {
            let ci = [coef[i].0, coef[i].1];
            for j in 0..3 {
                let cj = [coef[j].0, coef[j].1];
                for (p, cp) in ci.iter().enumerate() {
                    for (q, cq) in cj.iter().enumerate() {
                        w[2 * i + p][2 * j + q] = k[i][j] * cp * cq;
                    }
                }
            }
            // r_i (2 cos β (∇h ∇βᵀ + ∇β ∇hᵀ) − 2 h sin β ∇β ∇βᵀ).
            let (h, cos) = self.h_cos[i];
            w[2 * i][2 * i + 1] += r[i] * 2.0 * cos;
            w[2 * i + 1][2 * i] += r[i] * 2.0 * cos;
            w[2 * i + 1][2 * i + 1] -= r[i] * h * coef[i].0;
        }
        w
    }
}

/// Force and (unless `b.dfdq` is empty) Jacobian of the face `el` on the DOFs `st` at `q`,
/// `theta[i]` the view of edge `i`'s dihedral quantities (`None` on the boundary).
pub(super) fn evaluate(
    el: &MidedgeData,
    st: &[usize],
    q: &[f64],
    theta: &[Option<EdgeAngle>; 3],
    b: BlockMut<'_>,
) {
    let (x, psi) = read(q, st);
    let area = Area::new(&x);
    // (An array literal, not `map`: `map` moves each 200-byte `Edge` through several copies.)
    let edge_i = |i: usize| edge(el, &psi, i, &area, theta[i].as_ref());
    let edges = [edge_i(0), edge_i(1), edge_i(2)];
    let c = Curvature::new(el, [0, 1, 2].map(|i| (edges[i].h, edges[i].beta)));
    let (coef, r) = (c.coef, c.r);
    let f: &mut [f64; NS] = b.f.try_into().expect("a 21-DOF stencil");
    f[..9].fill(0.0);
    for (i, e) in edges.iter().enumerate() {
        let (a, bb) = (r[i] * coef[i].0, r[i] * coef[i].1);
        for n in 0..9 {
            f[n] -= a * e.grad_h[n] + bb * e.grad_beta[n];
        }
        for t in 0..3 {
            f[9 + 3 * i + t] = -bb * e.grad_wing[t];
        }
        f[18 + i] = -bb * e.grad_wing[3];
    }
    if b.dfdq.is_empty() {
        return;
    }
    let w = c.weights(&el.stiffness);
    let mut h = Blocks::low_rank(&edges, &w);
    let alpha = [0, 1, 2].map(|i| r[i] * coef[i].0);
    h.add_altitudes(&edges, &alpha, &area);
    for (i, t) in theta.iter().enumerate() {
        if let Some(t) = t {
            h.add_dihedral(i, 0.5 * r[i] * coef[i].1, t);
        }
    }
    h.write(b.dfdq.try_into().expect("a 21 × 21 block"));
}

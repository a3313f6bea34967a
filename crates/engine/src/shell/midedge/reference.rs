//! The per-face kernel of mid-edge bending as it was before the per-edge pass (each
//! interior edge's dihedral angle, gradient and Hessian computed in both of its faces),
//! kept for the tests only: the force must reproduce it to round-off. It shares with the
//! force only the face's curvature terms ([`super::face::Curvature`]) and `side`; what it
//! checks is the per-edge pass and the block assembly.

use super::super::dihedral::{angle_grad, angle_grad_hess_into, Hess12};
use super::face::{side, Curvature};
use super::{hinge, read, MidedgeData, NS};
use crate::force::{BlockMut, EvalInput};
use crate::vec3::{outer, skew, M3, V3};

/// Twice the area `|N|` of the face, its gradient and (if `hess`) Hessian in `v0, v1, v2`.
fn twice_area_derivs(v: &[V3; 3], hess: bool) -> (f64, [V3; 3], [[M3; 3]; 3]) {
    let n = (v[1] - v[0]).cross(&(v[2] - v[0]));
    let nn = n.norm();
    let nh = n / nn;
    let e = [0, 1, 2].map(|k| v[(k + 2) % 3] - v[(k + 1) % 3]);
    let g = e.map(|ek| nh.cross(&ek));
    let mut h = [[M3::zeros(); 3]; 3];
    if hess {
        let p = (M3::identity() - outer(&nh, &nh)) / nn;
        let sn = skew(&nh);
        let se = e.map(|ek| skew(&ek));
        for k in 0..3 {
            for m in 0..3 {
                let mut b = -se[k] * p * se[m];
                if m == (k + 2) % 3 {
                    b += sn;
                } else if m == (k + 1) % 3 {
                    b -= sn;
                }
                h[k][m] = b;
            }
        }
    }
    (nn, g, h)
}

/// Edge `i` of a face: its length, unit vector `ê` (from `v_{i+1}` to `v_{i+2}`), altitude
/// `h`, angle `β` and their gradients on the stencil (`∇h` on `v0, v1, v2`, the first 9).
struct Edge {
    len: f64,
    e_hat: V3,
    h: f64,
    beta: f64,
    grad_h: [f64; 9],
    grad_beta: [f64; NS],
}

/// Edge `i` of the face at `x`, `psi`, with `|N|` and its gradient `gn`; on an interior
/// edge with `hess`, `∇²θ` (on its hinge `[v_{i+1}, v_{i+2}, v_i, o_i]`) into `theta_hess`.
fn edge(
    el: &MidedgeData,
    x: &[V3; 6],
    psi: &[f64; 3],
    i: usize,
    (nn, gn): (f64, &[V3; 3]),
    theta_hess: Option<&mut Hess12>,
) -> Edge {
    let (a, b) = ((i + 1) % 3, (i + 2) % 3);
    let e = x[b] - x[a];
    let len = e.norm();
    let e_hat = e / len;
    // ∇h = ∇|N|/l − |N| ∇l/l², ∇l = ∓ê at v_{i+1}, v_{i+2}.
    let mut grad_h = [0.0; 9];
    let w = nn / (len * len);
    for k in 0..3 {
        let s = side(i, k);
        for d in 0..3 {
            grad_h[3 * k + d] = gn[k][d] / len - s * w * e_hat[d];
        }
    }
    let mut grad_beta = [0.0; NS];
    let beta = if el.interior[i] {
        let hx = hinge(x, i);
        let (theta, gt) = match theta_hess {
            Some(ht) => angle_grad_hess_into(&hx, ht.as_mut_slice()),
            None => angle_grad(&hx),
        };
        for (r, node) in [a, b, i, 3 + i].into_iter().enumerate() {
            for d in 0..3 {
                grad_beta[3 * node + d] = 0.5 * gt[3 * r + d];
            }
        }
        grad_beta[18 + i] = el.sign[i];
        0.5 * theta + el.sign[i] * psi[i]
    } else {
        grad_beta[18 + i] = 1.0;
        psi[i]
    };
    Edge {
        len,
        e_hat,
        h: nn / len,
        beta,
        grad_h,
        grad_beta,
    }
}

/// `h −= U W Uᵀ` (row-major 21 × 21), `U = [∇h₀, ∇β₀, ∇h₁, ∇β₁, ∇h₂, ∇β₂]`: column `2i`
/// lives on `v0, v1, v2`, column `2i + 1` also on `o_i` and `ψ_i`.
fn sub_low_rank(h: &mut [f64; NS * NS], edges: &[Edge; 3], w: &[[f64; 6]; 6]) {
    let mut u = [[0.0; NS]; 6];
    for (i, e) in edges.iter().enumerate() {
        u[2 * i][..9].copy_from_slice(&e.grad_h);
        u[2 * i + 1] = e.grad_beta;
    }
    // V = U W, column by column.
    let mut v = [[0.0; NS]; 6];
    for (k, vk) in v.iter_mut().enumerate() {
        for (l, ul) in u.iter().enumerate() {
            let wlk = w[l][k];
            for m in 0..NS {
                vk[m] += wlk * ul[m];
            }
        }
    }
    for m in 0..NS {
        let row: &mut [f64; NS] = (&mut h[NS * m..NS * (m + 1)]).try_into().expect("a row");
        for k in 0..6 {
            let vkm = v[k][m];
            for n in 0..9 {
                row[n] -= vkm * u[k][n];
            }
        }
        for i in 0..3 {
            let (vkm, uk) = (v[2 * i + 1][m], &u[2 * i + 1]);
            for n in [9 + 3 * i, 10 + 3 * i, 11 + 3 * i, 18 + i] {
                row[n] -= vkm * uk[n];
            }
        }
    }
}

/// `h −= Σ_i α_i ∇²h_i` on the `v0, v1, v2` block, with `h_i = |N|/l_i`: block `(k, m)` of
/// `∇²h_i` is `∇²_{km}|N|/l − (s_m ∇_k|N| êᵀ + s_k ê ∇_m|N|ᵀ)/l² + s_k s_m (|N|/l³)(3êêᵀ − I)`
/// (`s_k` = [`side`]), so the `|N|` Hessian enters once, weighted by `Σ α_i/l_i`.
fn sub_altitude_hessians(
    h: &mut [f64; NS * NS],
    edges: &[Edge; 3],
    alpha: &[f64; 3],
    area: &AreaDerivs,
) {
    let (nn, gn, hn) = area;
    let mut hv = [[0.0; 9]; 9];
    let wsum: f64 = (0..3).map(|i| alpha[i] / edges[i].len).sum();
    for k in 0..3 {
        for m in 0..3 {
            for r in 0..3 {
                for c in 0..3 {
                    hv[3 * k + r][3 * m + c] = wsum * hn[k][m][(r, c)];
                }
            }
        }
    }
    let gn9: [f64; 9] = std::array::from_fn(|p| gn[p / 3][p % 3]);
    for (i, e) in edges.iter().enumerate() {
        let l = e.len;
        let (c1, c2) = (alpha[i] / (l * l), alpha[i] * nn / (l * l * l));
        let gl: [f64; 9] = std::array::from_fn(|p| side(i, p / 3) * e.e_hat[p % 3]);
        for p in 0..9 {
            let (a1, a2) = (c1 * gn9[p] - 3.0 * c2 * gl[p], c1 * gl[p]);
            for q in 0..9 {
                hv[p][q] -= a1 * gl[q] + a2 * gn9[q];
            }
        }
        let (a, b) = ((i + 1) % 3, (i + 2) % 3);
        for (k, m) in [(a, a), (b, b), (a, b), (b, a)] {
            let s = side(i, k) * side(i, m) * c2;
            for d in 0..3 {
                hv[3 * k + d][3 * m + d] -= s;
            }
        }
    }
    for p in 0..9 {
        for q in 0..9 {
            h[NS * p + q] -= hv[p][q];
        }
    }
}

/// `h −= ρ ∇²θ` of edge `i`'s hinge `[v_{i+1}, v_{i+2}, v_i, o_i]`.
fn sub_dihedral_hessian(h: &mut [f64; NS * NS], i: usize, rho: f64, ht: &Hess12) {
    let nodes = [(i + 1) % 3, (i + 2) % 3, i, 3 + i];
    // `∇²θ` is symmetric, so row `r` is its (contiguous, column-major) column `r`.
    let hs = ht.as_slice();
    for (rs, &nr) in nodes.iter().enumerate() {
        for d in 0..3 {
            let (row, col) = (NS * (3 * nr + d), 12 * (3 * rs + d));
            for (cs, &nc) in nodes.iter().enumerate() {
                let src = &hs[col + 3 * cs..col + 3 * cs + 3];
                let dst = &mut h[row + 3 * nc..row + 3 * nc + 3];
                for e in 0..3 {
                    dst[e] -= rho * src[e];
                }
            }
        }
    }
}

/// The face's `|N|`, its gradient and Hessian ([`twice_area_derivs`]), shared by its edges.
type AreaDerivs = (f64, [V3; 3], [[M3; 3]; 3]);

/// The force and (unless `b.dfdq` is empty) Jacobian of one face, the old way: `∇c_i =
/// A_i ∇h_i + B_i ∇β_i` (`A = 2 sin β`, `B = 2h cos β`), the Hessian `U W Uᵀ + Σ_i (r_i A_i
/// ∇²h_i + ½ r_i B_i ∇²θ_i)` written in place into the 21 × 21 block.
pub(super) fn evaluate(el: &MidedgeData, st: &[usize], input: &EvalInput<'_>, b: BlockMut<'_>) {
    let (x, psi) = read(input.q, st);
    let want_hess = !b.dfdq.is_empty();
    let area = twice_area_derivs(&[x[0], x[1], x[2]], want_hess);
    // (Every entry of an interior edge's is written; a boundary edge's is not read.)
    let mut ht = [Hess12::zeros(); 3];
    let mut hts = ht.iter_mut();
    let edges = [0, 1, 2].map(|i| {
        let slot = hts.next().filter(|_| want_hess);
        edge(el, &x, &psi, i, (area.0, &area.1), slot)
    });
    let c = Curvature::new(el, [0, 1, 2].map(|i| (edges[i].h, edges[i].beta)));
    let (coef, r) = (c.coef, c.r);
    b.f.iter_mut().for_each(|f| *f = 0.0);
    for (i, e) in edges.iter().enumerate() {
        let (a, bb) = (r[i] * coef[i].0, r[i] * coef[i].1);
        for n in 0..9 {
            b.f[n] -= a * e.grad_h[n];
        }
        for n in 0..NS {
            b.f[n] -= bb * e.grad_beta[n];
        }
    }
    if !want_hess {
        return;
    }
    let w = c.weights(&el.stiffness);
    let h: &mut [f64; NS * NS] = b.dfdq.try_into().expect("a 21 × 21 block");
    h.fill(0.0);
    sub_low_rank(h, &edges, &w);
    let alpha = [0, 1, 2].map(|i| r[i] * coef[i].0);
    sub_altitude_hessians(h, &edges, &alpha, &area);
    for i in (0..3).filter(|&i| el.interior[i]) {
        sub_dihedral_hessian(h, i, 0.5 * r[i] * coef[i].1, &ht[i]);
    }
}

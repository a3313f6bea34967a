//! Mid-edge bending of discrete shells: a discrete shape operator per triangle built from
//! one unit normal per edge (Grinspun, Gingold, Reisman & Zorin 2006, "Computing discrete
//! shape operators on general meshes", Eurographics), with the normal's angle about its edge
//! as one extra DOF per edge, in the `sin` form of Chen, Sastry, van Rees & Vouga 2018
//! ("Physical simulation of environmentally induced thin shell deformation", SIGGRAPH).
//! Unlike the hinge model it converges to Kirchhoff plate bending on general meshes and
//! honours the Poisson ratio. See docs/shells.md §Mid-edge bending for the derivation.
//!
//! **Geometry of one face** `(v0, v1, v2)` (counter-clockwise about its normal `n̂`). Edge `i`
//! is opposite vertex `i`, `e_i = v_{i+2} − v_{i+1}`, `h_i = 2A/|e_i|` the altitude from `v_i`.
//! The mid-edge normal `n_i` of edge `i` is a unit vector normal to the edge; `β_i` is its
//! angle from `n̂` about the edge, positive when it tilts away from the face across the edge.
//! Interpolating the normals linearly between the edge midpoints gives the second
//! fundamental form in the barycentric coordinates `(λ1, λ2)`
//!
//! `b = Σ_i c_i g_i g_iᵀ`,  `c_i = 2 h_i sin β_i`,  `g_0 = (−1, −1)`, `g_1 = (1, 0)`, `g_2 = (0, 1)`.
//!
//! **DOF.** `β_i = θ_i/2 + s_i ψ_i` on an interior edge (`θ_i` the signed dihedral angle of
//! [`super::dihedral`], so `ψ = 0` is the bisector of the two face normals; `s_i = +1` in the
//! edge's first face, `−1` in its second), `β_i = ψ_i` on a boundary edge. `ψ_e` (rad) is the
//! per-edge DOF; it is 0 in the rest state, and a free boundary `ψ` gives a moment-free edge.
//!
//! **Energy** (Koiter/Kirchhoff, isotropic): with `M = ā⁻¹(b − b̄)` on the rest metric `ā`,
//! `E = Ā (D/2) [ν (tr M)² + (1 − ν) tr M²]`, `D = E h³/(12(1 − ν²))`. As `b` is linear in
//! `c`, this is `E = ½ (c − c̄)ᵀ K (c − c̄)` with the constant 3×3 matrix
//! `K_ij = Ā D [ν |∇λ_i|²|∇λ_j|² + (1 − ν)(∇λ_i·∇λ_j)²]` (rest barycentric gradients).
//!
//! **Derivatives.** `∇E = Σ r_i ∇c_i`, `r = K (c − c̄)`, and the exact Hessian
//! `∇²E = Σ_ij K_ij ∇c_i ∇c_jᵀ + Σ_i r_i ∇²c_i`, with
//! `∇c = 2 sin β ∇h + 2 h cos β ∇β` and
//! `∇²c = 2 sin β ∇²h + 2 cos β (∇h ∇βᵀ + ∇β ∇hᵀ) + 2 h (cos β ∇²β − sin β ∇β ∇βᵀ)`,
//! `∇β = ½ ∇θ + s e_ψ`, `∇²β = ½ ∇²θ`; `θ` from [`super::dihedral`], `h = |N|/|e|` with
//! `N = (v1 − v0) × (v2 − v0)`, `∂|N|/∂v_k = n̂ × e_k`.
//!
//! **Stencil** (21 DOFs): the face's vertices `v0, v1, v2`, the vertices `o0, o1, o2` across
//! its edges (a boundary edge repeats `v_i` there; nothing depends on it), then `ψ0, ψ1, ψ2`.

use std::collections::HashMap;

use super::dihedral::{angle, angle_grad, angle_grad_hess_into, Hess12};
use super::mesh::TriMesh;
use crate::element::{Element, Family};
use crate::error::{EngineError, InvalidModel};
use crate::force::{BlockMut, EvalInput, JacobianKind};
use crate::model::{ForceId, Model};
use crate::vec3::{node, outer, skew, M3, V3};

/// DOFs per face stencil: 6 nodes and 3 edge angles.
const NS: usize = 21;

/// Name of the mid-edge bending family added by [`install`].
pub const NAME: &str = "shell-midedge";

/// Constants of one face.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MidedgeData {
    /// `K` (J·m²... per unit c²: N·m / m²): `E = ½ (c − c̄)ᵀ K (c − c̄)`.
    pub stiffness: [[f64; 3]; 3],
    /// Rest edge scalars `c̄_i = 2 h̄_i sin β̄_i` (m) with `ψ = 0`.
    pub rest: [f64; 3],
    /// Orientation `s_i = ±1` of the edge's `ψ` in this face.
    pub sign: [f64; 3],
    /// Whether edge `i` has a second face (else `β_i = ψ_i`).
    pub interior: [bool; 3],
}

/// The mid-edge bending law (stateless: everything is per face).
#[derive(Debug, Clone, Copy, Default)]
pub struct MidedgeLaw;

/// A family of mid-edge bending faces, stencil `[v0, v1, v2, o0, o1, o2, ψ0, ψ1, ψ2]`.
pub type MidedgeBending = Family<MidedgeLaw>;

/// Positions of the 6 node slots and the 3 edge angles.
#[inline]
fn read(q: &[f64], st: &[usize]) -> ([V3; 6], [f64; 3]) {
    let x = [0, 1, 2, 3, 4, 5].map(|k| node(q, st[3 * k] / 3));
    (x, [q[st[18]], q[st[19]], q[st[20]]])
}

/// The hinge `[v_{i+1}, v_{i+2}, v_i, o_i]` of edge `i` (face first, as `dihedral` wants).
#[inline]
fn hinge(x: &[V3; 6], i: usize) -> [V3; 4] {
    [x[(i + 1) % 3], x[(i + 2) % 3], x[i], x[3 + i]]
}

/// Edge scalars `c_i = 2 h_i sin β_i` (m) of the face at `x`, `psi`.
fn edge_scalars(el: &MidedgeData, x: &[V3; 6], psi: &[f64; 3]) -> [f64; 3] {
    let twice_area = (x[1] - x[0]).cross(&(x[2] - x[0])).norm();
    [0, 1, 2].map(|i| {
        let h = twice_area / (x[(i + 2) % 3] - x[(i + 1) % 3]).norm();
        2.0 * h * beta(el, x, psi, i).sin()
    })
}

/// `β_i` (rad).
#[inline]
fn beta(el: &MidedgeData, x: &[V3; 6], psi: &[f64; 3], i: usize) -> f64 {
    if el.interior[i] {
        0.5 * angle(&hinge(x, i)) + el.sign[i] * psi[i]
    } else {
        psi[i]
    }
}

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
            Some(ht) => angle_grad_hess_into(&hx, ht),
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

/// `∂l_i/∂v_k = side · ê_i`: −1 at `v_{i+1}`, +1 at `v_{i+2}`, 0 at `v_i`.
#[inline]
fn side(i: usize, k: usize) -> f64 {
    if k == (i + 1) % 3 {
        -1.0
    } else if k == (i + 2) % 3 {
        1.0
    } else {
        0.0
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

impl Element for MidedgeLaw {
    const STENCIL: usize = NS;
    const KIND: JacobianKind = JacobianKind::ELASTIC;
    const CONSERVATIVE: bool = true;
    type Data = MidedgeData;

    /// `∇c_i = A_i ∇h_i + B_i ∇β_i` (`A = 2 sin β`, `B = 2h cos β`), so the Hessian is
    /// `U W Uᵀ + Σ_i (r_i A_i ∇²h_i + ½ r_i B_i ∇²θ_i)` with the 6 × 6 `W` of
    /// `K_ij ∇c_i ∇c_jᵀ` and the rank-one parts of `r_i ∇²c_i` (module docs), written in
    /// place into the 21 × 21 block.
    fn evaluate(&self, el: &MidedgeData, st: &[usize], input: &EvalInput<'_>, b: BlockMut<'_>) {
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
        let sc = edges.each_ref().map(|e| e.beta.sin_cos());
        let coef = [0, 1, 2].map(|i| (2.0 * sc[i].0, 2.0 * edges[i].h * sc[i].1));
        let k = &el.stiffness;
        let dc = [0, 1, 2].map(|i| edges[i].h * coef[i].0 - el.rest[i]);
        let r = [0, 1, 2].map(|i| k[i][0] * dc[0] + k[i][1] * dc[1] + k[i][2] * dc[2]);
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
            w[2 * i][2 * i + 1] += r[i] * 2.0 * sc[i].1;
            w[2 * i + 1][2 * i] += r[i] * 2.0 * sc[i].1;
            w[2 * i + 1][2 * i + 1] -= r[i] * edges[i].h * coef[i].0;
        }
        let h: &mut [f64; NS * NS] = b.dfdq.try_into().expect("a 21 × 21 block");
        h.fill(0.0);
        sub_low_rank(h, &edges, &w);
        let alpha = [0, 1, 2].map(|i| r[i] * coef[i].0);
        sub_altitude_hessians(h, &edges, &alpha, &area);
        for i in (0..3).filter(|&i| el.interior[i]) {
            sub_dihedral_hessian(h, i, 0.5 * r[i] * coef[i].1, &ht[i]);
        }
    }

    fn add_energy(&self, el: &MidedgeData, st: &[usize], q: &[f64], acc: &mut f64) {
        let (x, psi) = read(q, st);
        let c = edge_scalars(el, &x, &psi);
        let dc = [0, 1, 2].map(|i| c[i] - el.rest[i]);
        let k = &el.stiffness;
        let mut e = 0.0;
        for i in 0..3 {
            for j in 0..3 {
                e += dc[i] * k[i][j] * dc[j];
            }
        }
        *acc += 0.5 * e;
    }
}

/// The isotropic bending constants of a mid-edge shell.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlateBending {
    /// Young's modulus `E` (Pa).
    pub youngs_modulus: f64,
    /// Poisson ratio `ν` (−1 < ν < 1; 1/2 for an incompressible sheet).
    pub poisson_ratio: f64,
    /// Thickness `h` (m).
    pub thickness: f64,
}

impl PlateBending {
    /// Plate bending stiffness `D = E h³/(12(1 − ν²))` (N·m).
    pub fn stiffness(&self) -> f64 {
        let nu = self.poisson_ratio;
        self.youngs_modulus * self.thickness.powi(3) / (12.0 * (1.0 - nu * nu))
    }
}

/// Where each face finds its edges: per face and edge `i`, the mesh edge index, the vertex
/// across it (`None` on the boundary) and the orientation `s_i`.
fn face_edges(mesh: &TriMesh) -> Vec<[(usize, Option<usize>, f64); 3]> {
    let index: HashMap<[usize; 2], usize> = mesh
        .edges
        .iter()
        .enumerate()
        .map(|(e, &k)| (k, e))
        .collect();
    // Undirected edge → (first face, its opposite; second face, its opposite).
    let mut across: HashMap<usize, ([usize; 2], [usize; 2])> = HashMap::new();
    for h in &mesh.hinges {
        let [a, b] = h.edge;
        across.insert(index[&[a.min(b), a.max(b)]], (h.faces, h.opposite));
    }
    mesh.faces
        .iter()
        .enumerate()
        .map(|(fi, f)| {
            [0, 1, 2].map(|i| {
                let (a, b) = (f[(i + 1) % 3], f[(i + 2) % 3]);
                let e = index[&[a.min(b), a.max(b)]];
                match across.get(&e) {
                    Some((faces, opp)) if faces[0] == fi => (e, Some(opp[1]), 1.0),
                    Some((_, opp)) => (e, Some(opp[0]), -1.0),
                    None => (e, None, 1.0),
                }
            })
        })
        .collect()
}

impl MidedgeBending {
    /// Mid-edge bending on every face of `mesh`, rest shape `q_rest` (node positions; the
    /// rest `ψ` is 0), with the angle `ψ_e` of mesh edge `e` (`mesh.edges[e]`) at DOF
    /// `first_dof + e`.
    pub fn new(
        name: &str,
        mesh: &TriMesh,
        q_rest: &[f64],
        plate: &PlateBending,
        first_dof: usize,
    ) -> Self {
        let d = plate.stiffness();
        let nu = plate.poisson_ratio;
        let mut stencils = Vec::with_capacity(NS * mesh.faces.len());
        let mut data = Vec::with_capacity(mesh.faces.len());
        for (f, edges) in mesh.faces.iter().zip(face_edges(mesh)) {
            let opp = [0, 1, 2].map(|i| edges[i].1.unwrap_or(f[i]));
            for &n in f.iter().chain(&opp) {
                stencils.extend([3 * n, 3 * n + 1, 3 * n + 2]);
            }
            stencils.extend(edges.map(|e| first_dof + e.0));
            let x = [f[0], f[1], f[2], opp[0], opp[1], opp[2]].map(|n| node(q_rest, n));
            // Rest barycentric gradients ∇λ_i = −(e_i × n̂)/(2A): only their dot products.
            let nvec = (x[1] - x[0]).cross(&(x[2] - x[0]));
            let area = 0.5 * nvec.norm();
            let nh = nvec.normalize();
            let t = [0, 1, 2].map(|i| (x[(i + 2) % 3] - x[(i + 1) % 3]).cross(&nh));
            let dot = |i: usize, j: usize| t[i].dot(&t[j]) / (4.0 * area * area);
            let mut stiffness = [[0.0; 3]; 3];
            for (i, row) in stiffness.iter_mut().enumerate() {
                for (j, kij) in row.iter_mut().enumerate() {
                    *kij = area * d * (nu * dot(i, i) * dot(j, j) + (1.0 - nu) * dot(i, j).powi(2));
                }
            }
            let mut el = MidedgeData {
                stiffness,
                rest: [0.0; 3],
                sign: edges.map(|e| e.2),
                interior: edges.map(|e| e.1.is_some()),
            };
            el.rest = edge_scalars(&el, &x, &[0.0; 3]);
            data.push(el);
        }
        Family::from_elements(name, MidedgeLaw, stencils, data)
    }

    /// Energy of face `i` (J) at `q`.
    pub fn face_energy(&self, q: &[f64], i: usize) -> f64 {
        let mut e = 0.0;
        MidedgeLaw.add_energy(&self.data[i], self.stencil(i), q, &mut e);
        e
    }
}

/// Add mid-edge bending on `mesh` to `model` ([`NAME`]), the angle of mesh edge `e` at DOF
/// `model.layout.twist(first_twist + e)`, each with the rotary inertia `ρ h³/12 · A_e`
/// (kg·m²; `A_e` a third of the adjacent faces' area, the Mindlin plate's rotary inertia)
/// so that a dynamic solve has a mass on every DOF. Rest shape: `q_rest` (ψ = 0).
///
/// Errors ([`InvalidModel::MeshTooLarge`], [`InvalidModel::TwistDofs`]) if the mesh or its
/// edge angles do not fit the model's layout; the model is then unchanged.
pub fn install(
    mesh: &TriMesh,
    plate: &PlateBending,
    density: f64,
    model: &mut Model,
    q_rest: &[f64],
    first_twist: usize,
) -> Result<ForceId, EngineError> {
    let lay = model.layout;
    if mesh.n_nodes > lay.n_nodes || q_rest.len() < 3 * mesh.n_nodes {
        return Err(InvalidModel::MeshTooLarge {
            mesh_nodes: mesh.n_nodes,
            model_nodes: lay.n_nodes,
            q_len: q_rest.len(),
        }
        .into());
    }
    if first_twist + mesh.edges.len() > lay.n_twists {
        return Err(InvalidModel::TwistDofs {
            start: first_twist,
            end: first_twist + mesh.edges.len(),
            available: lay.n_twists,
        }
        .into());
    }
    let first_dof = lay.twist(first_twist);
    let force = MidedgeBending::new(NAME, mesh, q_rest, plate, first_dof);
    let inertia = density * plate.thickness.powi(3) / 12.0;
    let index: HashMap<[usize; 2], usize> = mesh
        .edges
        .iter()
        .enumerate()
        .map(|(e, &k)| (k, e))
        .collect();
    for (f, &a) in mesh.faces.iter().zip(&mesh.face_areas) {
        for i in 0..3 {
            let (p, q) = (f[(i + 1) % 3], f[(i + 2) % 3]);
            model.mass[first_dof + index[&[p.min(q), p.max(q)]]] += inertia * a / 3.0;
        }
    }
    Ok(model.add_force(force))
}

//! Continuum membrane kinematics of a linear triangle, shared by the constant-strain
//! membranes ([`super::cst`], [`super::fabric`]): the rest frame, the deformation gradient,
//! the Green–Lagrange strain, and the element force and exact Hessian for any constitutive
//! law `ψ(ε)`. See `docs/shells.md` §Continuum membranes for the formulas quoted here.
//!
//! - **Rest frame**: an orthonormal basis `(t₁, t₂)` of the rest triangle's plane, `t₁` the
//!   given material axis projected onto that plane (the warp for a fabric, any edge for an
//!   isotropic law) and `t₂ = n̂ × t₁`. Node `a` has rest coordinates `X_a ∈ ℝ²` in it.
//! - **Deformation gradient** (3 × 2, constant on the triangle): `F = Σ_a x_a B_aᵀ`, with the
//!   shape-function gradients `B_a = ∂N_a/∂X` (rows of `D_m⁻¹`, `D_m = [X₁ − X₀, X₂ − X₀]`,
//!   and `B₀ = −B₁ − B₂`).
//! - **Green–Lagrange strain** `E = ½(FᵀF − I)`, in Voigt form `ε = (E₁₁, E₂₂, 2E₁₂)`
//!   (strain-like), work-conjugate to the second Piola–Kirchhoff membrane stress (force per
//!   rest length, N/m) `σ = (S₁₁, S₂₂, S₁₂) = ∂ψ/∂ε`.
//! - **Energy** `W = A ψ(ε)`, `A` the rest area, `ψ` per rest area (J/m²).
//! - **Gradient** `∂W/∂x_a = A F S B_a`; **Hessian** (3 × 3 block of nodes a, b)
//!   `K_ab = A [M_aᵀ D M_b + (B_aᵀ S B_b) I]` with `D = ∂²ψ/∂ε²` and `M_a = ∂ε/∂x_a`, whose
//!   rows are `B_a1 F₁ᵀ`, `B_a2 F₂ᵀ` and `B_a1 F₂ᵀ + B_a2 F₁ᵀ`.
//!
//! With `D ⪰ 0` the first term is positive semi-definite; the second (geometric) term is
//! indefinite exactly when `S` has a negative eigenvalue (compression), which is why
//! [`project_psd`] exists.

use crate::force::BlockMut;
use crate::vec3::{node, V3};
use nalgebra::{SMatrix, SymmetricEigen};

/// Voigt 3-vector: a strain `(E₁₁, E₂₂, 2E₁₂)` or a stress `(S₁₁, S₂₂, S₁₂)`.
pub type Voigt = [f64; 3];
/// Symmetric 3 × 3 Voigt matrix (a stiffness `∂σ/∂ε`, N/m).
pub type Voigt3 = [[f64; 3]; 3];

/// Why a membrane element cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MembraneError {
    /// A rest triangle of (nearly) zero area.
    #[error("triangle {face} is degenerate in the rest configuration")]
    DegenerateFace {
        /// Index of the face.
        face: usize,
    },
    /// The material axis is (nearly) normal to a rest triangle, so it has no direction in
    /// the triangle's plane.
    #[error("the material axis is normal to triangle {face} (its projection on the triangle is {projection:.1e} of its length)")]
    AxisNormalToFace {
        /// Index of the face.
        face: usize,
        /// Length of the axis's projection on the face, relative to the axis.
        projection: f64,
    },
    /// The constitutive constants do not give a positive-definite stiffness.
    #[error("{0}")]
    Material(String),
}

/// The rest geometry of one triangle: shape-function gradients in its rest frame and area.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RestTriangle {
    /// `B_a = ∂N_a/∂X` (1/m) for the three nodes, in the rest frame `(t₁, t₂)`.
    pub grad: [[f64; 2]; 3],
    /// Rest area `A` (m²).
    pub area: f64,
}

/// Projections below this fraction of the axis length count as "normal to the face".
const MIN_PROJECTION: f64 = 1e-3;

impl RestTriangle {
    /// The rest triangle with corners `x` and first frame axis `axis` projected onto its
    /// plane. `face` is only used in errors.
    pub fn new(x: [V3; 3], axis: V3, face: usize) -> Result<Self, MembraneError> {
        let (e1, e2) = (x[1] - x[0], x[2] - x[0]);
        let n = e1.cross(&e2);
        let twice_area = n.norm();
        let longest = e1
            .norm_squared()
            .max(e2.norm_squared())
            .max((x[2] - x[1]).norm_squared());
        // Also catches non-finite corners (NaN compares false).
        if twice_area.is_nan() || twice_area <= 2e-12 * longest {
            return Err(MembraneError::DegenerateFace { face });
        }
        let n = n / twice_area;
        let a = axis / axis.norm();
        let proj = a - n * n.dot(&a);
        let projection = proj.norm();
        if projection.is_nan() || projection <= MIN_PROJECTION {
            return Err(MembraneError::AxisNormalToFace { face, projection });
        }
        let t1 = proj / projection;
        let t2 = n.cross(&t1);
        // D_m = [X₁ − X₀, X₂ − X₀] in the frame; B₁, B₂ are the rows of D_m⁻¹.
        let (a11, a21, a12, a22) = (e1.dot(&t1), e1.dot(&t2), e2.dot(&t1), e2.dot(&t2));
        let det = a11 * a22 - a12 * a21;
        let b1 = [a22 / det, -a12 / det];
        let b2 = [-a21 / det, a11 / det];
        let b0 = [-b1[0] - b2[0], -b1[1] - b2[1]];
        Ok(Self {
            grad: [b0, b1, b2],
            area: 0.5 * twice_area,
        })
    }

    /// Rest triangles of `faces` (rest positions in `q_rest`), the frame axis of face `i`
    /// being `axis(i)`.
    pub fn all(
        faces: &[[usize; 3]],
        q_rest: &[f64],
        axis: impl Fn(usize, [V3; 3]) -> V3,
    ) -> Result<Vec<Self>, MembraneError> {
        faces
            .iter()
            .enumerate()
            .map(|(i, f)| {
                let x = f.map(|k| node(q_rest, k));
                Self::new(x, axis(i, x), i)
            })
            .collect()
    }
}

/// The deformation of one triangle: the columns of `F` and the Voigt Green strain.
#[derive(Debug, Clone, Copy)]
pub struct Strain {
    /// `F₁ = F t₁`-column and `F₂` of the 3 × 2 deformation gradient.
    pub f: [V3; 2],
    /// `ε = (E₁₁, E₂₂, 2E₁₂)`.
    pub eps: Voigt,
}

impl Strain {
    /// The strain of rest triangle `el` with current corners `x`.
    #[inline]
    pub fn new(el: &RestTriangle, x: &[V3; 3]) -> Self {
        let mut f = [V3::zeros(); 2];
        for (a, xa) in x.iter().enumerate() {
            f[0] += xa * el.grad[a][0];
            f[1] += xa * el.grad[a][1];
        }
        let eps = [
            0.5 * (f[0].norm_squared() - 1.0),
            0.5 * (f[1].norm_squared() - 1.0),
            f[0].dot(&f[1]),
        ];
        Self { f, eps }
    }
}

/// The three corner positions read from `q` through a 9-DOF stencil (each node's three
/// DOFs are consecutive).
#[inline]
pub fn corners(q: &[f64], st: &[usize]) -> [V3; 3] {
    let at = |k: usize| {
        let x = &q[st[3 * k]..st[3 * k] + 3];
        V3::new(x[0], x[1], x[2])
    };
    [at(0), at(1), at(2)]
}

/// Write the force `−∂W/∂x` of rest triangle `el` at strain `s` with stress `sigma` into
/// `b.f`, and, when `tangent` is given, `−∂²W/∂x²` into `b.dfdq` (projected to its positive
/// semi-definite part when `psd`).
pub fn write(
    el: &RestTriangle,
    s: &Strain,
    sigma: &Voigt,
    tangent: Option<&Voigt3>,
    psd: bool,
    b: BlockMut<'_>,
) {
    let [f1, f2] = s.f;
    let a = el.area;
    let g = &el.grad;
    for n in 0..3 {
        // A F S B_n: the first Piola–Kirchhoff stress P = F S applied to B_n.
        let sb1 = sigma[0] * g[n][0] + sigma[2] * g[n][1];
        let sb2 = sigma[2] * g[n][0] + sigma[1] * g[n][1];
        let grad = (f1 * sb1 + f2 * sb2) * a;
        for c in 0..3 {
            b.f[3 * n + c] = -grad[c];
        }
    }
    let Some(d) = tangent else { return };
    let k: &mut [f64; 81] = b.dfdq.try_into().expect("a 9 × 9 block");
    hessian(g, a, [f1, f2], sigma, d, k);
    if psd {
        project_psd(b.dfdq);
    }
}

/// `k = −∂²W/∂x²` (row-major 9 × 9). With `J_a = ∂ε/∂x_a` (3 × 3, the `M_a` above), block
/// (a, b) of the Hessian is `K_ab = A [J_aᵀ D J_b + (B_aᵀ S B_b) I]`. Translation invariance
/// (`B₀ = −B₁ − B₂`, so `J₀ = −J₁ − J₂`) gives the blocks of node 0 from those of nodes 1
/// and 2; the area enters negated, so the blocks are those of `−K` directly.
#[inline]
fn hessian(g: &[[f64; 2]; 3], area: f64, f: [V3; 2], sigma: &Voigt, d: &Voigt3, k: &mut [f64; 81]) {
    let (f1, f2) = (f[0], f[1]);
    // (Array `map` in this hot loop costs more than the arithmetic: plain loops.)
    let mut j = [[[0.0; 3]; 3]; 2];
    for (n, jn) in j.iter_mut().enumerate() {
        let [b1, b2] = g[n + 1];
        for i in 0..3 {
            jn[0][i] = b1 * f1[i];
            jn[1][i] = b2 * f2[i];
            jn[2][i] = b1 * f2[i] + b2 * f1[i];
        }
    }
    // (−A D) J_n.
    let mut dj = [[[0.0; 3]; 3]; 2];
    for n in 0..2 {
        for r in 0..3 {
            let (d0, d1, d2) = (-area * d[r][0], -area * d[r][1], -area * d[r][2]);
            for i in 0..3 {
                dj[n][r][i] = d0 * j[n][0][i] + d1 * j[n][1][i] + d2 * j[n][2][i];
            }
        }
    }
    let geo = |a: usize, b: usize| {
        let ([a1, a2], [b1, b2]) = (g[a], g[b]);
        -area * (a1 * (sigma[0] * b1 + sigma[2] * b2) + a2 * (sigma[2] * b1 + sigma[1] * b2))
    };
    let (g11, g12, g22) = (geo(1, 1), geo(1, 2), geo(2, 2));
    let mut k11 = [[0.0; 3]; 3];
    let mut k22 = [[0.0; 3]; 3];
    let mut k12 = [[0.0; 3]; 3];
    let (j1, j2, dj1, dj2) = (&j[0], &j[1], &dj[0], &dj[1]);
    for i in 0..3 {
        for c in i..3 {
            k11[i][c] = j1[0][i] * dj1[0][c] + j1[1][i] * dj1[1][c] + j1[2][i] * dj1[2][c];
            k11[c][i] = k11[i][c];
            k22[i][c] = j2[0][i] * dj2[0][c] + j2[1][i] * dj2[1][c] + j2[2][i] * dj2[2][c];
            k22[c][i] = k22[i][c];
        }
        for c in 0..3 {
            k12[i][c] = j1[0][i] * dj2[0][c] + j1[1][i] * dj2[1][c] + j1[2][i] * dj2[2][c];
        }
        k11[i][i] += g11;
        k22[i][i] += g22;
        k12[i][i] += g12;
    }
    for i in 0..3 {
        let r = [9 * i, 9 * (3 + i), 9 * (6 + i)];
        for c in 0..3 {
            let k01 = -(k11[i][c] + k12[c][i]);
            let k02 = -(k12[i][c] + k22[i][c]);
            // K₀₀ = −(K₀₁ᵀ + K₀₂ᵀ) = K₁₁ + K₁₂ + K₂₁ + K₂₂.
            k[r[0] + c] = k11[i][c] + k12[i][c] + k12[c][i] + k22[i][c];
            k[r[0] + 3 + c] = k01;
            k[r[0] + 6 + c] = k02;
            k[r[1] + 3 + c] = k11[i][c];
            k[r[1] + 6 + c] = k12[i][c];
            k[r[2] + 3 + c] = k12[c][i];
            k[r[2] + 6 + c] = k22[i][c];
            k[9 * (3 + c) + i] = k01;
            k[9 * (6 + c) + i] = k02;
        }
    }
}

/// Replace the 9 × 9 row-major Jacobian `−K` (K the element Hessian) by `−K₊`, `K₊` the
/// nearest positive semi-definite matrix in the Frobenius norm: `K = V Λ Vᵀ` (symmetric
/// eigen-decomposition, nalgebra, on the stack) and `K₊ = V max(Λ, 0) Vᵀ`. A Newton option,
/// not a derivative: the conformance checks apply to the exact Hessian.
pub fn project_psd(dfdq: &mut [f64]) {
    let k = SMatrix::<f64, 9, 9>::from_fn(|r, c| -dfdq[r * 9 + c]);
    let eig = SymmetricEigen::new(k);
    if eig.eigenvalues.iter().all(|&l| l >= 0.0) {
        return;
    }
    let lam = eig.eigenvalues.map(|l| l.max(0.0));
    let v = &eig.eigenvectors;
    let kp = v * SMatrix::<f64, 9, 9>::from_diagonal(&lam) * v.transpose();
    for r in 0..9 {
        for c in 0..9 {
            dfdq[r * 9 + c] = -0.5 * (kp[(r, c)] + kp[(c, r)]);
        }
    }
}

/// `½ εᵀ Q ε`.
#[inline]
pub fn quadratic_energy(q: &Voigt3, e: &Voigt) -> f64 {
    0.5 * dot(e, &mul(q, e))
}

/// `Q ε`.
#[inline]
pub fn mul(q: &Voigt3, e: &Voigt) -> Voigt {
    let row = |r: usize| q[r][0] * e[0] + q[r][1] * e[1] + q[r][2] * e[2];
    [row(0), row(1), row(2)]
}

/// `a · b`.
#[inline]
pub fn dot(a: &Voigt, b: &Voigt) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

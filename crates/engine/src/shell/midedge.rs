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
//!
//! **Evaluation** in two passes: `midedge/hinges.rs` computes every interior edge's `θ`, `∇θ` and
//! (for a Jacobian only) `∇²θ` once, into the force's scratch; `midedge/face.rs` then builds each
//! face's force and Jacobian from its own geometry and its three edges' results. (Each
//! interior edge is shared by two faces, so a per-face computation would do every dihedral
//! Hessian twice.)

use std::collections::HashMap;

use super::dihedral::angle;
use super::mesh::TriMesh;
use crate::error::{EngineError, InvalidModel};
use crate::force::{EvalInput, Force, JacobianKind, LocalBlocks};
use crate::model::{ForceId, Model};
use crate::vec3::{node, V3};

mod face;
mod hinges;
#[cfg(test)]
mod reference;
#[cfg(test)]
mod tests;

use hinges::{EdgeAngle, SLOT};

/// DOFs per face stencil: 6 nodes and 3 edge angles.
const NS: usize = 21;

/// Name of the mid-edge bending family added by [`install`].
pub const NAME: &str = "shell-midedge";

/// Marks a boundary edge in [`MidedgeBending`]'s per-face hinge indices.
const BOUNDARY: u32 = u32::MAX;

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

/// A family of mid-edge bending faces, stencil `[v0, v1, v2, o0, o1, o2, ψ0, ψ1, ψ2]`, with
/// the interior edges (hinges) whose dihedral quantities its faces share.
#[derive(Debug, Clone)]
pub struct MidedgeBending {
    name: String,
    stencils: Vec<usize>,
    data: Vec<MidedgeData>,
    /// Per face and edge `i`: the index of the edge in `hinges`, or [`BOUNDARY`].
    face_hinges: Vec<[u32; 3]>,
    /// Nodes `[x0, x1, x2, x3]` of every interior edge ([`super::Hinge::nodes`]).
    hinges: Vec<[usize; 4]>,
}

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

/// Energy `½ (c − c̄)ᵀ K (c − c̄)` (J) of the face `el` on the DOFs `st` at `q`.
fn face_energy(el: &MidedgeData, st: &[usize], q: &[f64]) -> f64 {
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
    0.5 * e
}

impl Force for MidedgeBending {
    fn name(&self) -> &str {
        &self.name
    }
    fn stencil_size(&self) -> usize {
        NS
    }
    fn stencils(&self) -> &[usize] {
        &self.stencils
    }
    fn jacobian_kind(&self) -> JacobianKind {
        JacobianKind::ELASTIC
    }
    /// The per-edge pass into `out.scratch` (sized by [`Force::new_blocks`]; resized here,
    /// once, for buffers made otherwise), then the faces in parallel.
    fn evaluate(&self, input: &EvalInput<'_>, out: &mut LocalBlocks) {
        let mut scratch = std::mem::take(&mut out.scratch);
        scratch.resize(SLOT * self.hinges.len(), 0.0);
        hinges::fill(
            &self.hinges,
            input.q,
            input.jacobian,
            out.serial,
            &mut scratch,
        );
        out.par_for_each(input.jacobian, |b| {
            let i = b.index;
            let el = &self.data[i];
            let theta = [0, 1, 2].map(|k| {
                let h = self.face_hinges[i][k];
                (h != BOUNDARY).then(|| EdgeAngle::new(&scratch, h as usize, el.sign[k] < 0.0))
            });
            face::evaluate(el, &self.stencils[NS * i..NS * (i + 1)], input.q, &theta, b);
        });
        out.scratch = scratch;
    }
    fn energy(&self, q: &[f64]) -> Option<f64> {
        Some((0..self.len()).map(|i| self.face_energy(q, i)).sum())
    }
    fn conservative(&self) -> bool {
        true
    }
    fn new_blocks(&self) -> LocalBlocks {
        let mut b = LocalBlocks::new(NS, self.len(), JacobianKind::ELASTIC);
        b.scratch = vec![0.0; SLOT * self.hinges.len()];
        b
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

/// How a face sees its edge `i`: the mesh edge index, the vertex across it and the edge's
/// hinge index (`None` on the boundary), and the orientation `s_i`.
type FaceEdge = (usize, Option<(usize, usize)>, f64);

/// Mesh edge index of each undirected edge `[min, max]`.
fn edge_index(mesh: &TriMesh) -> HashMap<[usize; 2], usize> {
    mesh.edges
        .iter()
        .enumerate()
        .map(|(e, &k)| (k, e))
        .collect()
}

/// Where each face finds its edges ([`FaceEdge`]).
fn face_edges(mesh: &TriMesh) -> Vec<[FaceEdge; 3]> {
    let index = edge_index(mesh);
    // Undirected edge → its hinge.
    let mut across: HashMap<usize, usize> = HashMap::new();
    for (hi, h) in mesh.hinges.iter().enumerate() {
        let [a, b] = h.edge;
        across.insert(index[&[a.min(b), a.max(b)]], hi);
    }
    mesh.faces
        .iter()
        .enumerate()
        .map(|(fi, f)| {
            [0, 1, 2].map(|i| {
                let (a, b) = (f[(i + 1) % 3], f[(i + 2) % 3]);
                let e = index[&[a.min(b), a.max(b)]];
                match across.get(&e).map(|&hi| (hi, &mesh.hinges[hi])) {
                    Some((hi, h)) if h.faces[0] == fi => (e, Some((h.opposite[1], hi)), 1.0),
                    Some((hi, h)) => (e, Some((h.opposite[0], hi)), -1.0),
                    None => (e, None, 1.0),
                }
            })
        })
        .collect()
}

/// The constants of the face at rest positions `x` (its nodes, then those across its
/// edges) with edges `edges`.
fn face_data(x: &[V3; 6], edges: &[FaceEdge; 3], plate: &PlateBending) -> MidedgeData {
    let (d, nu) = (plate.stiffness(), plate.poisson_ratio);
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
    el.rest = edge_scalars(&el, x, &[0.0; 3]);
    el
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
        let n = mesh.faces.len();
        let mut stencils = Vec::with_capacity(NS * n);
        let mut data = Vec::with_capacity(n);
        let mut face_hinges = Vec::with_capacity(n);
        for (f, edges) in mesh.faces.iter().zip(face_edges(mesh)) {
            let opp = [0, 1, 2].map(|i| edges[i].1.map_or(f[i], |(o, _)| o));
            for &n in f.iter().chain(&opp) {
                stencils.extend([3 * n, 3 * n + 1, 3 * n + 2]);
            }
            stencils.extend(edges.map(|e| first_dof + e.0));
            let x = [f[0], f[1], f[2], opp[0], opp[1], opp[2]].map(|n| node(q_rest, n));
            data.push(face_data(&x, &edges, plate));
            face_hinges.push(edges.map(|e| e.1.map_or(BOUNDARY, |(_, h)| h as u32)));
        }
        Self {
            name: name.to_string(),
            stencils,
            data,
            face_hinges,
            hinges: mesh.hinges.iter().map(|h| h.nodes()).collect(),
        }
    }

    /// Number of faces.
    pub fn len(&self) -> usize {
        self.data.len()
    }

    /// True when the family has no faces.
    pub fn is_empty(&self) -> bool {
        self.data.is_empty()
    }

    /// The constants of every face, in mesh order.
    pub fn data(&self) -> &[MidedgeData] {
        &self.data
    }

    /// Energy of face `i` (J) at `q`.
    pub fn face_energy(&self, q: &[f64], i: usize) -> f64 {
        face_energy(&self.data[i], &self.stencils[NS * i..NS * (i + 1)], q)
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
    let index = edge_index(mesh);
    for (f, &a) in mesh.faces.iter().zip(&mesh.face_areas) {
        for i in 0..3 {
            let (p, q) = (f[(i + 1) % 3], f[(i + 2) % 3]);
            model.mass[first_dof + index[&[p.min(q), p.max(q)]]] += inertia * a / 3.0;
        }
    }
    Ok(model.add_force(force))
}

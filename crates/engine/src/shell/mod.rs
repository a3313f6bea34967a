//! Discrete shells: membranes (edge springs, or constant-strain continuum triangles),
//! dihedral-angle hinges for bending, lumped masses. See `docs/shells.md` for the
//! derivations quoted here.
//!
//! - [`mesh`]: triangle-mesh topology ([`TriMesh`], [`Hinge`], [`MeshError`]);
//! - [`dihedral`]: signed dihedral angle, exact gradient and Hessian;
//! - [`hinge`]: the [`HingeBending`] force;
//! - [`midedge`]: the [`MidedgeBending`] force (mid-edge normals, one angle DOF per edge);
//! - stretching by edge springs reuses [`crate::rod::Stretch`] with `k_s = (√3/2) E h |ē|`;
//! - [`membrane`]: rest frame, deformation gradient and Green strain of a triangle, and
//!   the element force and Hessian for any membrane law;
//! - [`cst`]: the isotropic St Venant–Kirchhoff membrane [`CstMembrane`];
//! - [`fabric`]: the orthotropic fabric membrane [`FabricMembrane`], optionally without
//!   compression through [`tension_field`] (the barrier-regularised wrinkling relaxation).

pub mod cst;
pub mod dihedral;
pub mod fabric;
pub mod hinge;
pub mod membrane;
pub mod mesh;
pub mod midedge;
pub mod tension_field;

pub use cst::{CstLaw, CstMembrane};
pub use fabric::{FabricLaw, FabricMembrane, Orthotropic};
pub use hinge::{HingeBending, HingeData, HingeLaw};
pub use membrane::{MembraneError, RestTriangle};
pub use mesh::{Hinge, MeshError, TriMesh};
pub use midedge::{MidedgeBending, PlateBending};
pub use tension_field::{TensionField, Wrinkling};

use crate::error::{EngineError, InvalidModel};
use crate::model::Model;
use crate::rod::Stretch;
use crate::vec3::node;

/// Name of the shell stretching force family added by [`install`].
pub const STRETCH_NAME: &str = "shell-stretch";
/// Name of the shell bending force family added by [`install`].
pub const BEND_NAME: &str = "shell-bend";

/// Isotropic shell material.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShellMaterial {
    /// Young's modulus `E` (Pa).
    pub youngs_modulus: f64,
    /// Thickness `h` (m).
    pub thickness: f64,
    /// Density `ρ` (kg/m³).
    pub density: f64,
}

/// Regular mesh families for which the effective continuum stiffnesses are known in
/// closed form (leading order in edge length / curvature radius; see `docs/shells.md`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Lattice {
    /// Equilateral triangles (the hexagon and, approximately, circle generators).
    Equilateral,
    /// Square cells split by diagonals alternating like a union-jack (the rectangle
    /// generator): right isosceles triangles.
    UnionJack,
}

impl ShellMaterial {
    /// Edge spring stiffness `k_s = (√3/2) E h l̄` (N) for rest length `l̄` (m), so that
    /// the edge energy is `½ k_s ε² l̄`.
    pub fn stretch_stiffness(&self, rest_len: f64) -> f64 {
        0.5 * 3f64.sqrt() * self.youngs_modulus * self.thickness * rest_len
    }

    /// Hinge stiffness `k_b = (2/√3) E h³/12` (N·m), the DisMech convention.
    pub fn hinge_stiffness(&self) -> f64 {
        2.0 / 3f64.sqrt() * self.plate_stiffness()
    }

    /// Nominal plate stiffness `D = E h³/12` (N·m), without the `1/(1 − ν²)` factor (the
    /// hinge model has no independent Poisson ratio).
    pub fn plate_stiffness(&self) -> f64 {
        self.youngs_modulus * self.thickness.powi(3) / 12.0
    }

    /// Mass per area `ρ h` (kg/m²).
    pub fn areal_density(&self) -> f64 {
        self.density * self.thickness
    }

    /// Effective bending stiffness `D_eff` (N·m) and bending Poisson ratio `ν_b` of the
    /// hinge model on a regular `lattice`, for static (relaxed) deformations:
    /// - equilateral: `D_eff = (√3/2) k_b = E h³/12`, `ν_b = −1/3` (one node per lattice
    ///   cell, so nodes follow the smooth surface: no internal relaxation);
    /// - union-jack: `D_eff = ¾ k_b = (√3/2) E h³/12`, `ν_b = −1/3`. The lattice has two
    ///   node types (8 and 4 neighbours); their relative out-of-plane offset (a
    ///   checkerboard) couples to the mean curvature and relaxes the affine estimate
    ///   `D = k_b, ν_b = 0` (which is what a prescribed surface, e.g. nodes placed on a
    ///   cylinder, sees). See `docs/shells.md`.
    pub fn effective_bending(&self, lattice: Lattice) -> (f64, f64) {
        let kb = self.hinge_stiffness();
        match lattice {
            Lattice::Equilateral => (0.5 * 3f64.sqrt() * kb, -1.0 / 3.0),
            Lattice::UnionJack => (0.75 * kb, -1.0 / 3.0),
        }
    }

    /// Effective in-plane (membrane) Young's modulus times thickness `(E h)_eff` (N/m) and
    /// Poisson ratio of the edge springs on a regular `lattice` (affine deformation):
    /// - equilateral: `E h`, `ν = 1/3`;
    /// - union-jack: `(2/√3) E h`, `ν = 1/3` (every node is a centre of inversion, so a
    ///   uniform in-plane strain causes no internal relaxation).
    pub fn effective_membrane(&self, lattice: Lattice) -> (f64, f64) {
        let eh = self.youngs_modulus * self.thickness;
        match lattice {
            Lattice::Equilateral => (eh, 1.0 / 3.0),
            Lattice::UnionJack => (2.0 / 3f64.sqrt() * eh, 1.0 / 3.0),
        }
    }
}

/// Add a shell on `mesh` to `model`: edge springs ([`STRETCH_NAME`]) with
/// `k_s = (√3/2) E h |ē|`, hinges ([`BEND_NAME`]) with `k_b = (2/√3) E h³/12`, and lumped
/// masses `ρ h A/3` per vertex of every face. Rest lengths, rest angles and areas are
/// measured in `q_rest`. Empty families (no edges or no interior edges) are not added.
/// The same as [`ShellParts`]' three parts in turn (a model with another membrane or
/// bending law adds the parts it wants).
///
/// Errors ([`InvalidModel::MeshTooLarge`]) if the mesh has more nodes than the model or
/// `q_rest` is too short; the model is then unchanged.
pub fn install(
    mesh: &TriMesh,
    mat: &ShellMaterial,
    model: &mut Model,
    q_rest: &[f64],
) -> Result<(), EngineError> {
    let parts = ShellParts::try_new(mesh, mat, model, q_rest)?;
    parts.springs(model);
    parts.hinges(model);
    parts.masses(model);
    Ok(())
}

/// A shell's mesh, material and rest positions, checked to fit a model, whose parts
/// (edge springs, hinges, lumped masses) a builder adds one by one: a shell whose membrane
/// or bending is another law (e.g. [`midedge::install`]) leaves that part out.
#[derive(Clone, Copy)]
pub struct ShellParts<'a> {
    mesh: &'a TriMesh,
    mat: &'a ShellMaterial,
    q_rest: &'a [f64],
}

impl<'a> ShellParts<'a> {
    /// The parts of `mesh` with `mat`, rest shape `q_rest`, for `model`;
    /// [`InvalidModel::MeshTooLarge`] unless the mesh fits the model and `q_rest`.
    pub fn try_new(
        mesh: &'a TriMesh,
        mat: &'a ShellMaterial,
        model: &Model,
        q_rest: &'a [f64],
    ) -> Result<Self, EngineError> {
        if mesh.n_nodes > model.layout.n_nodes || q_rest.len() < 3 * mesh.n_nodes {
            return Err(InvalidModel::MeshTooLarge {
                mesh_nodes: mesh.n_nodes,
                model_nodes: model.layout.n_nodes,
                q_len: q_rest.len(),
            }
            .into());
        }
        Ok(Self { mesh, mat, q_rest })
    }

    /// Add the edge springs of [`install`] (none if the mesh has no edges).
    pub fn springs(&self, model: &mut Model) {
        let (mesh, q) = (self.mesh, self.q_rest);
        if mesh.edges.is_empty() {
            return;
        }
        let rest_len: Vec<f64> = mesh
            .edges
            .iter()
            .map(|&[a, b]| (node(q, b) - node(q, a)).norm())
            .collect();
        let ks = rest_len
            .iter()
            .map(|&l| self.mat.stretch_stiffness(l))
            .collect();
        model.add_force(Stretch::with_rest_lengths(
            STRETCH_NAME,
            &mesh.edges,
            rest_len,
            ks,
        ));
    }

    /// Add the bending hinges of [`install`] (none if the mesh has no interior edges).
    pub fn hinges(&self, model: &mut Model) {
        let hinges = &self.mesh.hinges;
        if !hinges.is_empty() {
            let kb = vec![self.mat.hinge_stiffness(); hinges.len()];
            model.add_force(HingeBending::new(BEND_NAME, hinges, self.q_rest, kb));
        }
    }

    /// Add the lumped masses `ρ h A/3` of [`install`] to every vertex of every face.
    pub fn masses(&self, model: &mut Model) {
        for f in &self.mesh.faces {
            let [a, b, c] = f.map(|i| node(self.q_rest, i));
            let area = 0.5 * (b - a).cross(&(c - a)).norm();
            for &i in f {
                model.add_node_mass(i, self.mat.areal_density() * area / 3.0);
            }
        }
    }
}

//! Constant-strain triangles (CST): an isotropic St Venant–Kirchhoff membrane on the rest
//! configuration.
//!
//! Energy of a triangle of rest area `A` (kinematics in [`super::membrane`]):
//! `W = A ψ(ε)`, `ψ = ½ εᵀ Q ε` with the plane-stress stiffness (N/m)
//!
//! ```text
//! Q = E h/(1 − ν²) [[1, ν, 0], [ν, 1, 0], [0, 0, (1 − ν)/2]]
//! ```
//!
//! acting on the Green strain `ε = (E₁₁, E₂₂, 2E₁₂)`. For small strains this is linear
//! plane-stress elasticity with the scenario's own `E` and `ν` on any triangulation (unlike
//! edge springs, whose ν is fixed by the mesh); for large rotations it is exactly
//! frame-invariant. Under compression SVK is not convex (nor is any membrane): the geometric
//! term of the Hessian is indefinite, and [`CstLaw::psd_projection`] offers the projected
//! Hessian as a Newton option.

use super::membrane::{self, corners, MembraneError, RestTriangle, Strain, Voigt3};
use crate::element::{node_stencils, Element, Family};
use crate::force::{BlockMut, EvalInput, JacobianKind};

/// The isotropic St Venant–Kirchhoff membrane law.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CstLaw {
    /// Plane-stress stiffness `Q` (N/m) on Voigt strains.
    pub stiffness: Voigt3,
    /// Write the element Hessian's positive semi-definite projection instead of the exact
    /// one (a Newton option; see [`membrane::project_psd`]).
    pub psd_projection: bool,
}

/// A family of constant-strain triangles, stencil `[x0, x1, x2]` (9 DOFs).
pub type CstMembrane = Family<CstLaw>;

/// Plane-stress stiffness `E h/(1 − ν²) [[1, ν, 0], [ν, 1, 0], [0, 0, (1 − ν)/2]]` (N/m) of
/// an isotropic sheet with Young's modulus `e` (Pa), Poisson ratio `nu` and thickness `h`
/// (m).
pub fn isotropic_stiffness(e: f64, nu: f64, h: f64) -> Voigt3 {
    let c = e * h / (1.0 - nu * nu);
    [
        [c, c * nu, 0.0],
        [c * nu, c, 0.0],
        [0.0, 0.0, 0.5 * c * (1.0 - nu)],
    ]
}

impl CstMembrane {
    /// Constant-strain triangles on `faces` with rest shape `q_rest`, Young's modulus `e`
    /// (Pa), Poisson ratio `nu` (−1 < ν < 1) and thickness `h` (m). Errors on a degenerate
    /// rest triangle or constants that do not make `Q` positive definite.
    pub fn new(
        name: &str,
        faces: &[[usize; 3]],
        q_rest: &[f64],
        e: f64,
        nu: f64,
        h: f64,
    ) -> Result<Self, MembraneError> {
        if !(e > 0.0 && h > 0.0 && nu > -1.0 && nu < 1.0) {
            return Err(MembraneError::Material(format!(
                "an isotropic membrane needs E > 0, h > 0 and −1 < ν < 1 (E = {e}, h = {h}, ν = {nu})"
            )));
        }
        let rest = RestTriangle::all(faces, q_rest, |_, x| x[1] - x[0])?;
        let law = CstLaw {
            stiffness: isotropic_stiffness(e, nu, h),
            psd_projection: false,
        };
        Ok(Family::from_elements(name, law, node_stencils(faces), rest))
    }

    /// The same family writing projected (positive semi-definite) element Hessians.
    pub fn with_psd_projection(mut self, on: bool) -> Self {
        self.law.psd_projection = on;
        self
    }

    /// Green strain `(E₁₁, E₂₂, 2E₁₂)` of triangle `i` at `q` (in its rest frame, whose
    /// first axis is the edge from its first to its second node).
    pub fn strain(&self, q: &[f64], i: usize) -> [f64; 3] {
        Strain::new(&self.data[i], &corners(q, self.stencil(i))).eps
    }

    /// Second Piola–Kirchhoff membrane stress `(S₁₁, S₂₂, S₁₂)` (N/m) of triangle `i` at `q`.
    pub fn stress(&self, q: &[f64], i: usize) -> [f64; 3] {
        membrane::mul(&self.law.stiffness, &self.strain(q, i))
    }
}

impl Element for CstLaw {
    const STENCIL: usize = 9;
    const KIND: JacobianKind = JacobianKind::ELASTIC;
    type Data = RestTriangle;

    fn evaluate(&self, el: &RestTriangle, st: &[usize], input: &EvalInput<'_>, b: BlockMut<'_>) {
        let s = Strain::new(el, &corners(input.q, st));
        let sigma = membrane::mul(&self.stiffness, &s.eps);
        let tangent = (!b.dfdq.is_empty()).then_some(&self.stiffness);
        membrane::write(el, &s, &sigma, tangent, self.psd_projection, b);
    }

    fn add_energy(&self, el: &RestTriangle, st: &[usize], q: &[f64], acc: &mut f64) {
        let s = Strain::new(el, &corners(q, st));
        *acc += el.area * membrane::quadratic_energy(&self.stiffness, &s.eps);
    }
}

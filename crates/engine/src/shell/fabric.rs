//! Woven fabric: an orthotropic St Venant–Kirchhoff membrane with warp and weft axes in the
//! rest plane, optionally unable to carry compression (a tension-field, wrinkling membrane).
//!
//! Energy of a triangle of rest area `A` (kinematics in [`super::membrane`], whose rest frame
//! here has its first axis along the warp): `W = A ψ(ε)`, `ψ = ½ εᵀ Q ε` with the
//! orthotropic plane-stress stiffness (N/m)
//!
//! ```text
//! Q = h [[E₁/Δ, ν₁₂E₂/Δ, 0], [ν₁₂E₂/Δ, E₂/Δ, 0], [0, 0, G₁₂]],   Δ = 1 − ν₁₂ν₂₁,  ν₂₁ = ν₁₂E₂/E₁
//! ```
//!
//! (1 = warp, 2 = weft; `ν₁₂` is the weft contraction under warp stress, `ε₂ = −ν₁₂ ε₁` in
//! uniaxial warp tension). `Q` is positive definite exactly when `E₁, E₂, G₁₂ > 0` and
//! `Δ > 0`, i.e. `ν₁₂² < E₁/E₂`.
//!
//! With no compression the stress is the tension-field relaxation of this law
//! ([`super::tension_field`]): smooth, never compressive, with a positive semi-definite
//! element Hessian. Without it, compression makes the geometric term of the Hessian
//! indefinite, and [`FabricLaw::psd_projection`] offers the projected Hessian as a Newton
//! option.

use super::membrane::{self, corners, MembraneError, RestTriangle, Strain, Voigt, Voigt3};
use super::tension_field::{TensionField, Wrinkling};
use crate::element::{node_stencils, Element, Family};
use crate::force::{BlockMut, EvalInput, JacobianKind};
use crate::vec3::V3;

/// Orthotropic constants of a woven fabric.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Orthotropic {
    /// Warp Young's modulus `E₁` (Pa).
    pub warp_modulus: f64,
    /// Weft Young's modulus `E₂` (Pa).
    pub weft_modulus: f64,
    /// In-plane shear modulus `G₁₂` (Pa).
    pub shear_modulus: f64,
    /// Poisson ratio `ν₁₂`: weft contraction under warp stress.
    pub poisson_ratio: f64,
    /// Thickness `h` (m).
    pub thickness: f64,
}

impl Orthotropic {
    /// Why these constants do not give a positive-definite law, if they do not.
    pub fn check(&self) -> Result<(), MembraneError> {
        let Self {
            warp_modulus: e1,
            weft_modulus: e2,
            shear_modulus: g,
            poisson_ratio: nu,
            thickness: h,
        } = *self;
        let positive = [e1, e2, g, h].iter().all(|&x| x > 0.0 && x.is_finite());
        if !positive {
            return Err(MembraneError::Material(format!(
                "fabric moduli and thickness must be positive (E₁ = {e1}, E₂ = {e2}, G₁₂ = {g}, h = {h})"
            )));
        }
        if nu.is_nan() || nu * nu >= e1 / e2 {
            return Err(MembraneError::Material(format!(
                "the fabric law is positive definite only for ν₁₂² < E₁/E₂ = {}: ν₁₂ = {nu}",
                e1 / e2
            )));
        }
        Ok(())
    }

    /// The stiffness `Q` (N/m) in the (warp, weft) frame.
    pub fn stiffness(&self) -> Voigt3 {
        let (e1, e2, nu) = (self.warp_modulus, self.weft_modulus, self.poisson_ratio);
        let h = self.thickness;
        let delta = 1.0 - nu * nu * e2 / e1;
        [
            [h * e1 / delta, h * nu * e2 / delta, 0.0],
            [h * nu * e2 / delta, h * e2 / delta, 0.0],
            [0.0, 0.0, h * self.shear_modulus],
        ]
    }
}

/// The fabric membrane law.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FabricLaw {
    /// Stiffness `Q` (N/m) in the (warp, weft) frame.
    pub stiffness: Voigt3,
    /// The no-compression relaxation, when the fabric cannot carry compression.
    pub tension_field: Option<TensionField>,
    /// Write the element Hessian's positive semi-definite projection instead of the exact
    /// one (a Newton option; see [`membrane::project_psd`]).
    pub psd_projection: bool,
}

/// A family of fabric triangles, stencil `[x0, x1, x2]` (9 DOFs).
pub type FabricMembrane = Family<FabricLaw>;

impl FabricLaw {
    /// Stress `(S₁₁, S₂₂, S₁₂)` (N/m) in the (warp, weft) frame at Green strain `eps`.
    pub fn stress(&self, eps: &Voigt) -> Voigt {
        match &self.tension_field {
            None => membrane::mul(&self.stiffness, eps),
            Some(tf) => tf.stress(eps),
        }
    }

    /// Energy per rest area `ψ(ε)` (J/m²).
    pub fn energy_density(&self, eps: &Voigt) -> f64 {
        match &self.tension_field {
            None => membrane::quadratic_energy(&self.stiffness, eps),
            Some(tf) => tf.relax(eps).energy,
        }
    }
}

impl FabricMembrane {
    /// Fabric triangles on `faces` with rest shape `q_rest`, constants `fabric`, the warp
    /// along `warp` (a 3-vector, projected onto each rest triangle's plane) and, with
    /// `no_compression = Some(ε_r)`, the tension-field relaxation with regularisation strain
    /// `ε_r` (> 0). Errors on constants that do not make `Q` positive definite, a degenerate
    /// rest triangle, or a warp normal to one.
    pub fn new(
        name: &str,
        faces: &[[usize; 3]],
        q_rest: &[f64],
        fabric: &Orthotropic,
        warp: [f64; 3],
        no_compression: Option<f64>,
    ) -> Result<Self, MembraneError> {
        fabric.check()?;
        if let Some(e) = no_compression.filter(|e| !(*e > 0.0 && e.is_finite())) {
            return Err(MembraneError::Material(format!(
                "the no-compression regularisation strain must be positive, got {e}"
            )));
        }
        let warp = V3::from(warp);
        let rest = RestTriangle::all(faces, q_rest, |_, _| warp)?;
        let stiffness = fabric.stiffness();
        let law = FabricLaw {
            stiffness,
            tension_field: no_compression.map(|e| TensionField::new(stiffness, e)),
            psd_projection: false,
        };
        Ok(Family::from_elements(name, law, node_stencils(faces), rest))
    }

    /// The same family writing projected (positive semi-definite) element Hessians.
    pub fn with_psd_projection(mut self, on: bool) -> Self {
        self.law.psd_projection = on;
        self
    }

    /// Green strain `(E₁₁, E₂₂, 2E₁₂)` of triangle `i` at `q`, in its (warp, weft) frame.
    pub fn strain(&self, q: &[f64], i: usize) -> Voigt {
        Strain::new(&self.data[i], &corners(q, self.stencil(i))).eps
    }

    /// The wrinkling state of triangle `i` at `q`; `None` for a fabric that carries
    /// compression (it never wrinkles in this model).
    pub fn wrinkling(&self, q: &[f64], i: usize) -> Option<Wrinkling> {
        let tf = self.law.tension_field.as_ref()?;
        Some(tf.wrinkling(&self.strain(q, i)))
    }

    /// Second Piola–Kirchhoff stress `(S₁₁, S₂₂, S₁₂)` (N/m) of triangle `i` at `q`, in its
    /// (warp, weft) frame.
    pub fn stress(&self, q: &[f64], i: usize) -> Voigt {
        self.law.stress(&self.strain(q, i))
    }
}

impl Element for FabricLaw {
    const STENCIL: usize = 9;
    const KIND: JacobianKind = JacobianKind::ELASTIC;
    type Data = RestTriangle;

    fn evaluate(&self, el: &RestTriangle, st: &[usize], input: &EvalInput<'_>, b: BlockMut<'_>) {
        let s = Strain::new(el, &corners(input.q, st));
        let jacobian = !b.dfdq.is_empty();
        match &self.tension_field {
            None => {
                let sigma = membrane::mul(&self.stiffness, &s.eps);
                let d = jacobian.then_some(&self.stiffness);
                membrane::write(el, &s, &sigma, d, self.psd_projection, b);
            }
            Some(tf) if jacobian => {
                let (sigma, d) = tf.stress_and_tangent(&s.eps);
                membrane::write(el, &s, &sigma, Some(&d), self.psd_projection, b);
            }
            Some(tf) => {
                let sigma = tf.stress(&s.eps);
                membrane::write(el, &s, &sigma, None, false, b);
            }
        }
    }

    fn add_energy(&self, el: &RestTriangle, st: &[usize], q: &[f64], acc: &mut f64) {
        let s = Strain::new(el, &corners(q, st));
        *acc += el.area * self.energy_density(&s.eps);
    }
}

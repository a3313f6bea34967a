//! Fixed-size elements and the one [`Force`] implementation they all share.
//!
//! Nearly every force is a family of identical elements, each acting on a stencil of the same
//! size: an edge spring on two nodes (6 DOFs), a hinge on four (12), drag on a triangle (9).
//! An [`Element`] says what *one* element does — its stencil size as a compile-time constant,
//! which Jacobians it has, its local force, Jacobians and energy — and [`Family`] holds the
//! stencils and per-element data of many and implements [`Force`] for all of them: the
//! parallel loop over stencils, the kind flags, the force-only path, energy summation and the
//! history hooks are written once here. (fenris bridges its fixed-size element trait to its
//! dynamic assembler the same way.)
//!
//! A new force is then one file with an `impl Element` and a constructor, plus one line of
//! [`force_conformance!`](crate::force_conformance) in the conformance tests; see
//! docs/architecture.md §The element trait.

use crate::error::HistoryError;
use crate::force::{BlockMut, EvalInput, Force, JacobianKind, LagCoupling, LocalBlocks};

/// The law of one element of a force family.
///
/// An implementor holds what all elements of the family share (a fluid's wind, a load
/// scale, the rods' reference frames); [`Element::Data`] is what each element has of its own
/// (a rest length, a stiffness, an area).
pub trait Element: Send + Sync + 'static {
    /// Number of DOFs in every stencil.
    const STENCIL: usize;
    /// Which Jacobians [`Element::evaluate`] writes (see also [`Element::kind`]).
    const KIND: JacobianKind;
    /// True when the force is `−∇E` of the energy added by [`Element::add_energy`] (see
    /// [`Force::conservative`]): by default every law whose [`Element::KIND`] has no
    /// velocity dependence and a symmetric `∂f/∂q` (elastic laws and constant loads), since
    /// such a field is a gradient; each of them implements `add_energy`.
    const CONSERVATIVE: bool = !Self::KIND.dv && Self::KIND.symmetric;
    /// Per-element constants.
    type Data: Send + Sync;

    /// Which Jacobians this family writes: [`Element::KIND`] unless the law's settings add
    /// dependencies (node drag in a fluid whose density varies with height gains `∂f/∂q`).
    fn kind(&self) -> JacobianKind {
        Self::KIND
    }

    /// Overwrite the local force `out.f` (length [`Element::STENCIL`]) of the element with
    /// data `el` on the global DOFs `st`, and, unless they are empty (the force-only path,
    /// `input.jacobian == false`), the local Jacobians `out.dfdq` / `out.dfdv` (row-major
    /// `STENCIL × STENCIL`) that [`Element::kind`] declares.
    fn evaluate(&self, el: &Self::Data, st: &[usize], input: &EvalInput<'_>, out: BlockMut<'_>);

    /// Add the element's potential energy (J) at `q` to `acc`; only called when
    /// [`Element::CONSERVATIVE`]. Accumulating rather than returning lets a load add its
    /// terms one at a time.
    fn add_energy(&self, _el: &Self::Data, _st: &[usize], _q: &[f64], _acc: &mut f64) {}

    /// Advance the history after an accepted step at `(q, v)` (see [`Force::commit`]).
    fn commit(&mut self, _els: &mut [Self::Data], _stencils: &[usize], _q: &[f64], _v: &[f64]) {}

    /// Read what the element holds over the step about to be solved from the state `(q, v)`
    /// that starts it (see [`Force::begin_step`]); its stencils stay.
    fn begin_step(&mut self, _stencils: &[usize], _q: &[f64], _v: &[f64]) {}

    /// Length of [`Element::history`] for a family of `n_elements`.
    fn history_len(&self, _n_elements: usize) -> usize {
        0
    }

    /// The history [`Element::commit`] advances, flattened (see [`Force::history`]).
    fn history(&self, _els: &[Self::Data]) -> Vec<f64> {
        Vec::new()
    }

    /// Restore a history of length [`Element::history_len`] (checked by the caller).
    fn restore_history(&mut self, _els: &mut [Self::Data], _h: &[f64]) {}

    /// The load scale of load-stepping solvers (see [`Force::set_load_scale`]).
    fn set_load_scale(&mut self, _scale: f64) {}

    /// The coupling through held quantities at `(q, v)` (see [`Force::lag_coupling`]).
    fn lag_coupling(
        &self,
        _els: &[Self::Data],
        _stencils: &[usize],
        _q: &[f64],
        _v: &[f64],
    ) -> Option<LagCoupling> {
        None
    }
}

/// A family of elements of one law: the stencils, the per-element data and the shared law.
/// Implements [`Force`].
pub struct Family<E: Element> {
    pub(crate) name: String,
    pub(crate) law: E,
    pub(crate) stencils: Vec<usize>,
    pub(crate) data: Vec<E::Data>,
}

// By hand: a derive would bound only `E: Clone`, not the per-element data.
impl<E: Element + Clone> Clone for Family<E>
where
    E::Data: Clone,
{
    fn clone(&self) -> Self {
        Self {
            name: self.name.clone(),
            law: self.law.clone(),
            stencils: self.stencils.clone(),
            data: self.data.clone(),
        }
    }
}

impl<E: Element> Family<E> {
    /// A family named `name` (diagnostics) of elements with law `law`: element `i` acts on
    /// the global DOFs `stencils[STENCIL i .. STENCIL (i + 1)]` with data `data[i]`.
    ///
    /// # Panics
    /// If `stencils` does not hold exactly [`Element::STENCIL`] DOFs per element.
    pub fn from_elements(
        name: impl Into<String>,
        law: E,
        stencils: Vec<usize>,
        data: Vec<E::Data>,
    ) -> Self {
        assert_eq!(
            stencils.len(),
            E::STENCIL * data.len(),
            "{} DOFs per stencil",
            E::STENCIL
        );
        Self {
            name: name.into(),
            law,
            stencils,
            data,
        }
    }

    /// Number of elements.
    pub fn len(&self) -> usize {
        self.data.len()
    }

    /// True when the family has no elements.
    pub fn is_empty(&self) -> bool {
        self.data.is_empty()
    }

    /// Global DOFs of element `i`.
    pub fn stencil(&self, i: usize) -> &[usize] {
        &self.stencils[E::STENCIL * i..E::STENCIL * (i + 1)]
    }

    /// The shared law.
    pub fn law(&self) -> &E {
        &self.law
    }

    /// Per-element data, in element order.
    pub fn data(&self) -> &[E::Data] {
        &self.data
    }
}

impl<E: Element> Force for Family<E> {
    fn name(&self) -> &str {
        &self.name
    }
    fn stencil_size(&self) -> usize {
        E::STENCIL
    }
    fn stencils(&self) -> &[usize] {
        &self.stencils
    }
    fn jacobian_kind(&self) -> JacobianKind {
        self.law.kind()
    }
    fn evaluate(&self, input: &EvalInput<'_>, out: &mut LocalBlocks) {
        let k = E::STENCIL;
        out.par_for_each(input.jacobian, |b| {
            let i = b.index;
            self.law
                .evaluate(&self.data[i], &self.stencils[k * i..k * i + k], input, b)
        });
    }
    fn energy(&self, q: &[f64]) -> Option<f64> {
        if !E::CONSERVATIVE {
            return None;
        }
        let mut e = 0.0;
        for (el, st) in self.data.iter().zip(self.stencils.chunks(E::STENCIL)) {
            self.law.add_energy(el, st, q, &mut e);
        }
        Some(e)
    }
    fn conservative(&self) -> bool {
        E::CONSERVATIVE
    }
    fn commit(&mut self, q: &[f64], v: &[f64]) {
        self.law.commit(&mut self.data, &self.stencils, q, v);
    }
    fn begin_step(&mut self, q: &[f64], v: &[f64], _dt: f64) -> bool {
        self.law.begin_step(&self.stencils, q, v);
        false
    }
    fn history(&self) -> Vec<f64> {
        self.law.history(&self.data)
    }
    fn restore_history(&mut self, h: &[f64]) -> Result<(), HistoryError> {
        let expected = self.law.history_len(self.data.len());
        if h.len() != expected {
            return Err(HistoryError {
                force: self.name.clone(),
                got: h.len(),
                expected,
            });
        }
        self.law.restore_history(&mut self.data, h);
        Ok(())
    }
    fn set_load_scale(&mut self, scale: f64) {
        self.law.set_load_scale(scale);
    }
    fn lag_coupling(&self, q: &[f64], v: &[f64]) -> Option<LagCoupling> {
        self.law.lag_coupling(&self.data, &self.stencils, q, v)
    }
}

/// Stencils `[3i, 3i+1, 3i+2, 3j, …]` of the nodes of each element, flattened: the usual
/// stencil of an element that acts on node positions only.
pub fn node_stencils<const N: usize>(elements: &[[usize; N]]) -> Vec<usize> {
    elements
        .iter()
        .flat_map(|e| e.iter().flat_map(|&i| [3 * i, 3 * i + 1, 3 * i + 2]))
        .collect()
}

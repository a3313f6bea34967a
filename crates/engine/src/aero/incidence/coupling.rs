//! The incidence law's dependence on the state through what it holds over a step, for the
//! linearisation of a steady state: `∂F/∂x ⊇ Σ_j (∂F/∂h_j)(∂h_j/∂x)` over the nine held
//! numbers `h` (axis, centroid, `K`).
//!
//! Both factors are central differences (step 1e-6 of each quantity's scale; error ~1e-12 of
//! the term): `h(q, v)` is a chain of normalisations, a maximum over the panels and a table
//! lookup, whose exact derivative would be long to write and to check, and the term is used
//! only by the eigen-analysis, never by the step solver.

use super::{Held, IncidencePressureLaw};
use crate::element::Element;
use crate::force::{BlockMut, EvalInput, LagCoupling};
use crate::vec3::V3;

/// Relative step of the differences.
const STEP: f64 = 1e-6;

/// The coupling of `law` (orientations `sigma`, triangles `stencils`) at `(q, v)`.
pub(super) fn of(
    law: &IncidencePressureLaw,
    sigma: &[f64],
    stencils: &[usize],
    q: &[f64],
    v: &[f64],
) -> LagCoupling {
    let mut dofs = stencils.to_vec();
    dofs.sort_unstable();
    dofs.dedup();
    let at = At {
        law,
        sigma,
        stencils,
        q,
        v,
        dofs: &dofs,
    };
    let held = law.held;
    let scales = held_scales(&held);
    let u = (0..9)
        .map(|j| {
            let shifted = |s: f64| {
                let mut l = law.clone();
                l.held = with(&held, j, get(&held, j) + s);
                at.force_of(&l)
            };
            let (p, m) = (shifted(scales[j]), shifted(-scales[j]));
            p.iter()
                .zip(&m)
                .map(|(a, b)| (a - b) / (2.0 * scales[j]))
                .collect()
        })
        .collect();
    let (wq, wv) = (at.held_derivatives(true), at.held_derivatives(false));
    LagCoupling { dofs, u, wq, wv }
}

/// Difference steps of the nine held numbers: 1e-6 of the unit axis, of the centroid's
/// distance from the origin (at least 1 m) and of `|K|` (at least 1e-3 /m).
fn held_scales(h: &Held) -> [f64; 9] {
    let c = STEP * (1.0 + h.centre.norm());
    let k = STEP * h.kvec.norm().max(1e-3);
    [STEP, STEP, STEP, c, c, c, k, k, k]
}

/// Held number `j` (axis, centroid, `K`, three each).
fn get(h: &Held, j: usize) -> f64 {
    [h.frame.axis, h.centre, h.kvec][j / 3][j % 3]
}

/// `h` with number `j` set to `x`.
fn with(h: &Held, j: usize, x: f64) -> Held {
    let mut out = *h;
    let target: &mut V3 = match j / 3 {
        0 => &mut out.frame.axis,
        1 => &mut out.centre,
        _ => &mut out.kvec,
    };
    target[j % 3] = x;
    out
}

/// The law (orientations `sigma`, triangles `stencils`) at one state `(q, v)`, seen on the
/// DOFs `dofs` its triangles touch (sorted).
struct At<'a> {
    law: &'a IncidencePressureLaw,
    sigma: &'a [f64],
    stencils: &'a [usize],
    q: &'a [f64],
    v: &'a [f64],
    dofs: &'a [usize],
}

impl At<'_> {
    /// The force on `dofs` of `law` (this law with other held numbers).
    fn force_of(&self, law: &IncidencePressureLaw) -> Vec<f64> {
        let (sigma, stencils, dofs) = (self.sigma, self.stencils, self.dofs);
        let input = EvalInput::outside_step(self.q, self.v, 0.0, false);
        let mut total = vec![0.0; dofs.len()];
        let mut f = [0.0; 9];
        for (i, (st, s)) in stencils.chunks_exact(9).zip(sigma).enumerate() {
            let b = BlockMut {
                index: i,
                f: &mut f,
                dfdq: &mut [],
                dfdv: &mut [],
            };
            law.evaluate(s, st, &input, b);
            for (d, fd) in st.iter().zip(&f) {
                let at = dofs.binary_search(d).expect("a stencil DOF");
                total[at] += fd;
            }
        }
        total
    }

    /// `∂h_j/∂q_d` (`positions`) or `∂h_j/∂v_d` for every DOF `d` of `dofs`: one row per `j`.
    fn held_derivatives(&self, positions: bool) -> Vec<Vec<f64>> {
        let (law, sigma, stencils, dofs) = (self.law, self.sigma, self.stencils, self.dofs);
        let fallback = law.held.frame.axis;
        let (mut q, mut v) = (self.q.to_vec(), self.v.to_vec());
        let mut rows = vec![vec![0.0; dofs.len()]; 9];
        for (col, &d) in dofs.iter().enumerate() {
            let x = if positions { q[d] } else { v[d] };
            let eps = STEP * (1.0 + x.abs());
            let mut at = |s: f64| {
                if positions {
                    q[d] = x + s;
                } else {
                    v[d] = x + s;
                }
                law.hold(stencils, sigma, &q, &v, fallback)
            };
            let (p, m) = (at(eps), at(-eps));
            if positions {
                q[d] = x;
            } else {
                v[d] = x;
            }
            for (j, row) in rows.iter_mut().enumerate() {
                row[col] = (get(&p, j) - get(&m, j)) / (2.0 * eps);
            }
        }
        rows
    }
}

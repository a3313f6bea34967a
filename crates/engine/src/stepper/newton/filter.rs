//! The local error estimate filtered through the step's held factors (RADAU5-style;
//! `stepper::error_control` module docs).

use std::time::Instant;

use super::NewtonCore;
use crate::model::Model;

impl NewtonCore {
    /// Filter the local error estimate `e` (every DOF) in place through the held factors `A`
    /// of the Newton matrix for `(c_m, c_v)`: `ê = A⁻¹ (c_m M e)` on the free DOFs
    /// (`stepper::error_control` module docs). `false`, with `e` unchanged, when no factors
    /// for that pair are held or the result is not finite (counted as a fallback).
    pub(crate) fn filter_estimate(
        &mut self,
        model: &Model,
        e: &mut [f64],
        c_m: f64,
        c_v: f64,
    ) -> bool {
        if !(self.solver.has_factors() && self.factored_for == (c_m, c_v)) {
            self.timings.error_filter_fallbacks += 1;
            return false;
        }
        for (r, &d) in self.assembler.dof_of.iter().enumerate() {
            self.delta[r] = c_m * model.mass[d] * e[d];
        }
        let t0 = Instant::now();
        self.solver.solve(&mut self.delta);
        self.timings.solve_s += t0.elapsed().as_secs_f64();
        if !self.delta.iter().all(|x| x.is_finite()) {
            self.timings.error_filter_fallbacks += 1;
            return false;
        }
        for (r, &d) in self.assembler.dof_of.iter().enumerate() {
            e[d] = self.delta[r];
        }
        self.timings.error_filters += 1;
        true
    }
}

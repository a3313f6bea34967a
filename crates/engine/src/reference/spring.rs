//! One undamped spring (a single [`Stretch`] edge with one node fixed): the oscillator whose
//! backward-Euler amplitude decays by exactly `1/√(1 + (ω dt)²)` per step.
use crate::rod::Stretch;
use crate::{DofLayout, Model, State};

/// A spring of axial stiffness `k_axial` (N; spring constant `k_axial/rest` N/m) and rest
/// length `rest` (m) along x from a fixed node 0 (mass 1 kg) to node 1 of mass `mass` (kg).
/// Its axial angular frequency is `ω = √(k_axial / (rest · mass))`.
pub fn spring_model(k_axial: f64, rest: f64, mass: f64) -> (Model, State) {
    let mut model = Model::new(DofLayout::new(2, 0));
    let q = vec![0.0, 0.0, 0.0, rest, 0.0, 0.0];
    model.add_force(Stretch::new("spring", &[[0, 1]], &q, vec![k_axial]));
    model.add_node_mass(0, 1.0);
    model.add_node_mass(1, mass);
    model.fix_node(0);
    (model, State::at_rest(q))
}

/// Backward Euler's exact amplitude ratio per step for a linear oscillator of angular
/// frequency `omega` (rad/s) stepped with `dt` (s): `1/√(1 + (ω dt)²)`.
pub fn backward_euler_decay(omega: f64, dt: f64) -> f64 {
    1.0 / (1.0 + (omega * dt).powi(2)).sqrt()
}

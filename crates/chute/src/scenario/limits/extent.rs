//! The model's size: its largest dimension, held far below where positions stop being
//! computable (a 1e40 m rod passed every other limit and failed at t = 0 with a non-finite
//! Newton update: the squares of its coordinates and lengths leave f64's exponent range in
//! the elements' derivatives).

use super::{input, Derived};
use crate::scenario::{CanopyShape, ModelKind, Scenario};

/// Largest dimension of a model (m): 100 km, far above any parachute and its lines.
pub const MAX_EXTENT_M: f64 = 1e5;

/// The model's largest dimension (m) from the keys that set it (an imported mesh's own extent
/// is its file's, not a key's).
pub(super) fn largest(s: &Scenario) -> Vec<Derived> {
    let c = &s.canopy;
    let mut inputs = Vec::new();
    if s.model.kind == ModelKind::Rod || c.shape == CanopyShape::Rectangle {
        inputs.push(input("canopy.span_m", c.span_m, 6.0));
        inputs.push(input("canopy.width_m", c.width_m, 3.0));
    }
    if s.model.kind == ModelKind::Shell
        && matches!(c.shape, CanopyShape::Hexagon | CanopyShape::Circle)
    {
        inputs.push(input("canopy.radius_m", c.radius_m, 1.0));
    }
    if s.site_count().is_some() {
        inputs.push(input("lines.length_m", s.lines.length_m, 3.0));
    }
    // A radius spans the canopy twice.
    let span = |i: &super::Input| match i.key {
        "canopy.radius_m" => 2.0 * i.value,
        _ => i.value,
    };
    let value = inputs.iter().map(span).fold(0.0, f64::max);
    match inputs.is_empty() {
        true => Vec::new(),
        false => vec![Derived {
            name: "model's largest dimension",
            unit: "m",
            value,
            inputs,
        }],
    }
}

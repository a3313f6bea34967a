//! Constructed round canopies (`canopy.shape = "circle"`): the apex vent and the gores'
//! profile, read once for the builder and checked for the validator.

use super::validate::Checker;
use super::CanopyProfile;
use super::{Canopy, CanopyShape, Scenario};
use crate::mesh::constructed::Profile;

/// The profile of the scenario's gores (flat unless `canopy.profile` says otherwise).
pub fn profile(c: &Canopy) -> Profile {
    match (c.profile, c.cone_angle_deg) {
        (Some(CanopyProfile::Conical), Some(a)) => Profile::Conical(a.to_radians()),
        (Some(CanopyProfile::Hemispherical), _) => Profile::Hemispherical,
        _ => Profile::Flat,
    }
}

/// The radius (m) within which the generated disc of `rings` rings is cut away for the vent
/// (between the ring nearest `canopy.vent_radius_m`, at least the first, and the one inside
/// it), or `None` without a vent.
pub fn vent_cut(c: &Canopy, rings: usize) -> Option<f64> {
    if c.vent_radius_m <= 0.0 || c.shape != CanopyShape::Circle {
        return None;
    }
    let spacing = c.radius_m / rings as f64;
    let hem = (c.vent_radius_m / spacing).round().max(1.0);
    Some((hem - 0.5) * spacing)
}

/// A vent leaves at least one ring of cloth: `vent_radius_m ≤ radius_m − edge_length_m`.
pub(super) fn check(c: &mut Checker, s: &Scenario) {
    let cn = &s.canopy;
    if cn.vent_radius_m > 0.0 && cn.vent_radius_m > cn.radius_m - cn.edge_length_m {
        c.fail(
            "canopy.vent_radius_m",
            cn.vent_radius_m,
            format!(
                "a vent as large as the canopy: at most canopy.radius_m − canopy.edge_length_m = {} m (one ring of cloth)",
                cn.radius_m - cn.edge_length_m
            ),
        );
    }
}

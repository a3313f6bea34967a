//! The rules of `[opening]` and `[contact]` between keys (docs/opening.md).

use super::validate::Checker;
use super::{CanopyProfile, CanopyShape, InflationSpeed, Packing, Scenario, ShellDrag};

/// A packed start needs a flat round canopy, a flat start's imperfection left out, and
/// contact; the packed radius and the contact distance are bounded by the canopy and its mesh;
/// a tilted one needs the inflation pressure at the canopy's speed.
pub(super) fn check(c: &mut Checker, s: &Scenario) {
    let cn = &s.canopy;
    if let Some(o) = &s.opening {
        let pack = format!("\"{}\"", o.pack.name());
        // A folded canopy read from a file may be any shell canopy.
        let folded = o.pack == Packing::Mesh;
        if cn.shape != CanopyShape::Circle && !folded {
            c.fail(
                "opening.pack",
                &pack,
                "packs a round canopy: set `canopy.shape = \"circle\"`, or give it folded (`pack = \"mesh\"`)",
            );
        } else if cn.profile.is_some_and(|p| p != CanopyProfile::Flat) && !folded {
            c.fail(
                "opening.pack",
                &pack,
                "packs a flat circular canopy (`canopy.profile = \"flat\"`)",
            );
        }
        if s.contact.is_none() {
            c.fail(
                "opening.pack",
                &pack,
                "needs `[contact]`: the packed cloth and the lines would pass through each other",
            );
        }
        if cn.imperfection_m != 0.0 {
            c.fail(
                "canopy.imperfection_m",
                cn.imperfection_m,
                "perturbs a flat start; a packed canopy (`[opening]`) starts folded",
            );
        }
        let held = s.fluid.shell_drag == ShellDrag::Inflation
            && s.fluid.inflation_speed == Some(InflationSpeed::Canopy);
        if o.attitude_deg != 0.0 && !held {
            c.fail(
                "opening.attitude_deg",
                o.attitude_deg,
                "needs `fluid.shell_drag = \"inflation\"` with `fluid.inflation_speed = \"canopy\"`: with each triangle's own speed a tilted canopy's folds are pushed harder the faster they fall, and the opening fails (docs/opening.md §Attitude)",
            );
        }
        if let Some(r) = o.packed_radius_m.filter(|&r| r >= 0.5 * cn.radius_m) {
            c.fail(
                "opening.packed_radius_m",
                r,
                format!(
                    "must be below canopy.radius_m / 2 = {} m (a packed canopy)",
                    0.5 * cn.radius_m
                ),
            );
        }
    }
    let distance = s.contact.as_ref().and_then(|k| k.distance_m);
    if let Some(d) = distance.filter(|&d| d >= 0.5 * cn.edge_length_m) {
        c.fail(
            "contact.distance_m",
            d,
            format!(
                "must be below canopy.edge_length_m / 2 = {} m: neighbouring nodes of the mesh would repel",
                0.5 * cn.edge_length_m
            ),
        );
    }
}

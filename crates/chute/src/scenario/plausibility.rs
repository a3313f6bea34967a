//! Plausibility warnings: values that are valid (a run can use them) but far outside any real
//! parachute fabric or line, so most likely a unit slip (MPa for Pa, g/cm³ for kg/m³, mm for
//! m), and a no-compression regularisation large enough to show in the canopy's shape
//! (`scenario/wrinkle.rs`). `chute check`, `run` and `resume` print them; nothing is refused.

use super::error::short;
use super::{ModelKind, Scenario};

/// A plausible band and what lies inside it, for one key.
struct Band {
    key: &'static str,
    unit: &'static str,
    lo: f64,
    hi: f64,
    examples: &'static str,
}

/// Young's modulus of real fabrics and fibres: from soft coated nylon (~10 MPa effective)
/// to UHMWPE fibre (~170 GPa); a band of an order of magnitude more on each side.
const MODULUS: (f64, f64) = (1e6, 1e12);
const MODULUS_EXAMPLES: &str = "nylon ~2 GPa, Kevlar 55–130 GPa, Dyneema ~170 GPa";
/// Densities of fibres: polypropylene and UHMWPE ~900–970, Kevlar 1440, glass 2550 kg/m³.
const DENSITY: (f64, f64) = (100.0, 3000.0);
const DENSITY_EXAMPLES: &str = "Dyneema ~970, nylon 1140, Kevlar 1440 kg/m³";

/// A warning for every value far outside real fabrics and lines, naming its key.
pub fn warnings(s: &Scenario) -> Vec<String> {
    let m = &s.material;
    let mut values = vec![
        (modulus("material.youngs_modulus_pa"), m.youngs_modulus_pa),
        (density("material.density_kg_m3"), m.density_kg_m3),
    ];
    // A rod canopy is a strip of any thickness; a shell is a fabric (0.02–2 mm typical).
    if s.model.kind == ModelKind::Shell {
        let band = Band {
            key: "canopy.thickness_m",
            unit: "m",
            lo: 1e-6,
            hi: 0.01,
            examples: "parachute fabrics 0.05–0.5 mm",
        };
        values.push((band, s.canopy.thickness_m));
    }
    if s.load.mode == super::LoadMode::Payload {
        values.push((
            modulus("lines.youngs_modulus_pa"),
            s.lines.youngs_modulus_pa,
        ));
        values.push((density("lines.density_kg_m3"), s.lines.density_kg_m3));
    }
    let regularisation = super::wrinkle::estimate(s)
        .filter(|r| r.strain_error > super::wrinkle::WARN)
        .map(|r| {
            format!(
                "material.wrinkle_strain = {}: {}",
                short(r.strain),
                r.explain(super::wrinkle::WARN)
            )
        });
    values
        .into_iter()
        .filter(|(b, x)| !(b.lo..=b.hi).contains(x))
        .map(|(b, x)| {
            let side = if x < b.lo { "below" } else { "above" };
            format!(
                "{} = {} {} is far {side} any real fabric ({}–{} {}; {}): is the unit right?",
                b.key,
                short(x),
                b.unit,
                short(b.lo),
                short(b.hi),
                b.unit,
                b.examples
            )
        })
        .chain(regularisation)
        .chain(super::limits::mach_warning(s))
        .chain(snapshot_collisions(&s.output.snapshots_s))
        .chain(large_circle(s))
        .chain(super::control::sensor_warnings(s))
        .collect()
}

/// Triangles above which a generated circle canopy is large enough to warn of: about
/// 25 000 nodes, 100 000 DOFs with mid-edge bending, whose model needs 0.6–1.3 GB
/// ([`super::limits::MAX_SHELL_TRIANGLES`]) and whose steps take seconds each on a laptop
/// (the bundled canopies: ≤ 11 000).
pub const LARGE_SHELL_TRIANGLES: f64 = 5.0e4;

/// A warning when a generated circle (refined so that its rim holds every load site) has
/// more than [`LARGE_SHELL_TRIANGLES`] triangles, saying what makes it so.
fn large_circle(s: &Scenario) -> Option<String> {
    let cn = &s.canopy;
    let rim = matches!(s.load.sites, super::Sites::Named(super::SiteSet::Rim));
    let generated = s.model.kind == ModelKind::Shell
        && cn.shape == super::CanopyShape::Circle
        && cn.radius_m > 0.0
        && cn.edge_length_m > 0.0;
    if !generated {
        return None;
    }
    let rings = |sites| crate::mesh::generate::circle_rings(cn.radius_m, cn.edge_length_m, sites);
    let n = rings(if rim { s.load.rim_site_count } else { 1 });
    let triangles = 6.0 * (n as f64).powi(2);
    if triangles <= LARGE_SHELL_TRIANGLES {
        return None;
    }
    let why = match (rim, n > rings(1)) {
        (true, true) => format!(
            "load.rim_site_count = {} refines it so that the rim holds a node at every site (a count that divides the rim's {} nodes keeps the mesh as canopy.edge_length_m makes it)",
            s.load.rim_site_count,
            6 * rings(1)
        ),
        _ => format!("canopy.edge_length_m = {} m makes it", short(cn.edge_length_m)),
    };
    Some(format!(
        "the circle canopy will have {n} rings, {} triangles: {why}; building the model and every step will take long (the bundled canopies have at most 11 000)",
        short(triangles)
    ))
}

/// Snapshot times whose files have one name (they are named to the millisecond): the later
/// snapshot overwrites the earlier.
fn snapshot_collisions(times: &[f64]) -> Vec<String> {
    let name = crate::output::plots::snapshot_file_name;
    let mut out = Vec::new();
    for (i, &a) in times.iter().enumerate() {
        if let Some(&b) = times[..i].iter().find(|&&b| name(b) == name(a)) {
            out.push(format!(
                "output.snapshots_s: {} s and {} s both write `{}` (names are to the millisecond): the later overwrites the earlier",
                short(b),
                short(a),
                name(a)
            ));
        }
    }
    out
}

fn modulus(key: &'static str) -> Band {
    Band {
        key,
        unit: "Pa",
        lo: MODULUS.0,
        hi: MODULUS.1,
        examples: MODULUS_EXAMPLES,
    }
}

fn density(key: &'static str) -> Band {
    Band {
        key,
        unit: "kg/m³",
        lo: DENSITY.0,
        hi: DENSITY.1,
        examples: DENSITY_EXAMPLES,
    }
}

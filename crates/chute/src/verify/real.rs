//! Real parachutes: the round canopy's drag at zero incidence against the recovery
//! handbook's bands (Knacke, *Parachute Recovery Systems Design Manual*, NWC TP 6575, 1991,
//! Table 5-1). Information rows: the model misses some bands, and docs/validation.md
//! §Real parachutes reports by how much; no coefficient is tuned to a row.
//!
//! Each canopy is `round-solid.toml`'s (3 m, 1.1 oz fabric, 12 lines, 100 N) with its gores
//! flat, conical (25°) or hemispherical, under the incidence law at zero incidence: the
//! inflation pressure `C_p = 1.75` and no tangential drag. Its steady descent (`chute
//! steady` after a symmetric 1.5 s transient) gives `C_D0 = 2W/(ρ v² S₀)`, `W` the total
//! weight and `S₀` the constructed surface, vent included. The transient flies a restoring
//! `C_N(α)` so that it stays near the symmetric state at any speed; at zero incidence the
//! table gives no force, so the equilibrium is the same under any table.
//!
//! `real-t10-descent`: a fielded troop canopy, the US Army T-10 (35 ft nominal, 30 gores and
//! lines of 25.5 ft, a 20 in vent, MIL-C-7020 Type I cloth of about 100 cfm, 360 lb at most
//! below it), flown as a flat circular canopy of its nominal diameter from the same start.

use super::Check;
use crate::build::build;

/// A restoring `C_N(α) = 0.5 sin α` (the sign of a porous canopy's), for the transient.
pub const RESTORING: [&str; 2] = [
    "fluid.incidence_alpha_deg=[-90,-60,-40,-20,-10,0,10,20,40,60,90]",
    "fluid.incidence_cn=[-0.5,-0.4330,-0.3214,-0.1710,-0.0868,0.0,0.0868,0.1710,0.3214,0.4330,0.5]",
];

/// The keys of a symmetric start flown for `duration_s` (s) at mesh `edge_m` (m) under
/// [`RESTORING`], before `chute steady` solves its equilibrium.
fn symmetric_start(duration_s: f64, edge_m: f64) -> Vec<String> {
    let mut sets: Vec<String> = RESTORING.iter().map(|k| k.to_string()).collect();
    sets.push("canopy.imperfection_m=0".into());
    sets.push(format!("time.duration_s={duration_s}"));
    sets.push(format!("canopy.edge_length_m={edge_m}"));
    sets
}

/// A canopy type: its keys and Knacke's C_D0 band.
struct Type {
    name: &'static str,
    keys: &'static [&'static str],
    band: (f64, f64),
}

const TYPES: [Type; 3] = [
    Type {
        name: "flat",
        keys: &[],
        band: (0.75, 0.80),
    },
    Type {
        name: "conical",
        keys: &["canopy.profile=\"conical\"", "canopy.cone_angle_deg=25"],
        band: (0.75, 0.90),
    },
    Type {
        name: "hemispherical",
        keys: &["canopy.profile=\"hemispherical\""],
        band: (0.62, 0.77),
    },
];

/// `real-cd0-{flat,conical,hemispherical}`: C_D0 at zero incidence (0.35 m mesh with
/// `--quick`, else 0.18 m, within 1 % of 0.125 m: docs/notes/real-parachutes-2026-12-07.md).
pub fn cd0(quick: bool) -> Result<Vec<Check>, String> {
    let edge = if quick { 0.35 } else { 0.18 };
    let mut out = Vec::new();
    for t in &TYPES {
        let mut sets = symmetric_start(1.5, edge);
        sets.extend(t.keys.iter().map(|k| k.to_string()));
        let sets: Vec<&str> = sets.iter().map(String::as_str).collect();
        let s = super::system::round_solid(&sets)?;
        let built = build(&s).map_err(|e| e.to_string())?;
        let r = crate::steady::steady(&s).map_err(|e| e.to_string())?;
        let v = r.terminal_velocity_mps;
        let cd0 =
            2.0 * built.total_weight_n / (s.fluid.density_kg_m3 * v * v * built.planform_area_m2);
        let (lo, hi) = t.band;
        let verdict = if (lo..=hi).contains(&cd0) {
            "inside"
        } else {
            "outside"
        };
        out.push(Check::info(
            &format!("real-cd0-{}", t.name),
            &format!(
                "C_D0 at zero incidence, {} canopy, {edge} m ({verdict} {lo}–{hi}; information)",
                t.name
            ),
            0.5 * (lo + hi),
            "Knacke NWC TP 6575 Table 5-1 (band midpoint)",
            cd0,
        ));
    }
    Ok(out)
}

/// The T-10's published descent: 19–23 ft/s "depending on jumper weight and air density"
/// (GlobalSecurity's T-10 page, after FM 57-220); the check takes the range's midpoint as
/// reference and its half-width as tolerance.
const T10_FT_S: (f64, f64) = (19.0, 23.0);
/// Feet to metres.
const FT: f64 = 0.3048;

/// `real-t10-descent`: the steady descent of the T-10 at its largest suspended weight (0.9 m
/// mesh with `--quick`, 7 % above the extrapolated speed, else 0.4 m, 1.3 % above it; the
/// ladder and its GCI: docs/validation.md §Real parachutes).
pub fn t10(quick: bool) -> Result<Vec<Check>, String> {
    let edge = if quick { 0.9 } else { 0.4 };
    let mut sets = symmetric_start(3.0, edge);
    sets.extend(
        [
            "canopy.radius_m=5.33",              // 35 ft nominal diameter
            "canopy.vent_radius_m=0.254",        // 20 in vent
            "load.rim_site_count=30",            // 30 gores and lines
            "lines.length_m=7.77",               // 25.5 ft
            "load.weight_n=1601",                // 360 lb, the largest suspended weight
            "material.air_permeability_cfm=100", // MIL-C-7020 Type I, nominal
        ]
        .map(String::from),
    );
    let sets: Vec<&str> = sets.iter().map(String::as_str).collect();
    let s = super::system::round_solid(&sets)?;
    let r = crate::steady::steady(&s).map_err(|e| e.to_string())?;
    let (lo, hi) = (T10_FT_S.0 * FT, T10_FT_S.1 * FT);
    let mid = 0.5 * (lo + hi);
    Ok(vec![Check::new(
        "real-t10-descent",
        &format!("T-10 descent speed at 360 lb, {edge} m (m/s)"),
        mid,
        "GlobalSecurity T-10 (FM 57-220): 19–23 ft/s, midpoint; tolerance the half-range",
        r.terminal_velocity_mps.abs(),
        (hi - mid) / mid,
    )])
}

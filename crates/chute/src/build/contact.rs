//! `[contact]`: the canopy's triangles and the suspension lines as one contact surface
//! (`engine::contact`), its barrier sized from the scenario (docs/opening.md §Contact).

use super::BuildError;
use engine::contact::barrier::Barrier;
use engine::contact::broad::{candidates, Surface};
use engine::contact::intersect::first_crossing;
use engine::contact::SelfContact;
use engine::Model;

/// The barrier's stiffness κ (J/m⁴) at which a node of mass `mass` (kg) arriving at `speed`
/// (m/s) is stopped at a tenth of the activation distance `distance` (m): the barrier's
/// energy there, `κ (d̂/100 − d̂)² ln 100`, equals the node's kinetic energy ½ m v².
pub fn stiffness(mass: f64, speed: f64, distance: f64) -> f64 {
    let d_hat = distance * distance;
    0.5 * mass * speed * speed / ((0.99 * d_hat).powi(2) * 100f64.ln())
}

/// Add self-contact of `triangles` and `lines` (node pairs) to `model` at positions `q`:
/// activation distance `distance` (m), κ from the mean mass of `canopy` nodes stopped from
/// `speed`. Errors (naming `contact.distance_m`) when two parts that do not share a node start
/// closer than the distance, and when the start passes through itself.
pub fn install(
    model: &mut Model,
    q: &[f64],
    (triangles, lines): (&[[usize; 3]], &[[usize; 2]]),
    canopy: &[usize],
    (distance, speed): (f64, f64),
) -> Result<Surface, BuildError> {
    let surface = Surface::from_mesh(triangles, lines);
    if let Some((e, t)) = first_crossing(&surface, q) {
        return Err(BuildError::key(
            "opening.pack",
            format!("the start passes through itself (edge {e} through triangle {t})"),
        ));
    }
    let closest = closest_pair(&surface, q, distance);
    if closest < distance {
        return Err(BuildError::key(
            "contact.distance_m",
            format!(
                "{distance} m is more than the {closest:.4} m between the closest parts of the \
                 start that share no node: set it below (or pack the canopy less tightly)"
            ),
        ));
    }
    let mass = canopy.iter().map(|&i| model.node_mass(i)).sum::<f64>() / canopy.len() as f64;
    let barrier = Barrier {
        d_hat: distance * distance,
        kappa: stiffness(mass, speed, distance),
    };
    let c = SelfContact::new("contact", surface.clone(), barrier, q, 0.0, true);
    model.add_force(c);
    Ok(surface)
}

/// The smallest distance (m) between two parts of `surface` that share no node, among the
/// pairs within `reach`; `reach` when none is closer.
fn closest_pair(surface: &Surface, q: &[f64], reach: f64) -> f64 {
    (candidates(surface, q, reach).iter())
        .map(|c| c.squared_distance(q))
        .fold(reach * reach, f64::min)
        .sqrt()
}

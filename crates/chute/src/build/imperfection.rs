//! `canopy.imperfection_m`: an initial out-of-plane perturbation of a shell canopy in one
//! fixed, asymmetric mode, so that a user can probe which branch of a bistable fold the
//! configuration prefers (docs/scenarios.md §`[canopy]`).
//!
//! With ξ, η ∈ [−1, 1] the canopy nodes' coordinates scaled to their bounding box, node z is
//! moved by `a φ(ξ, η)`, with
//!
//! φ(ξ, η) = ½ [cos(π ξ) + ξ η + ¼ sin(π η)]
//!
//! a cylindrical bend about y (even in ξ and η), a twist (odd in both) and an S-bend across y
//! (odd in η): no mirror line of the rectangle and not its 180° rotation maps φ to itself.
//! |φ| ≤ 1, with φ = −1 at the corners (−1, 1) and (1, −1) (the test checks it), so `a` is
//! the largest displacement of a rectangle. Only the initial positions move: the rest shape
//! (edge lengths, hinge angles, masses, drag areas) stays the flat canopy's, and the sheet
//! starts at rest.

use super::BuildError;

/// The mode shape φ(ξ, η) (dimensionless, |φ| ≤ 1 on [−1, 1]²).
pub fn mode(xi: f64, eta: f64) -> f64 {
    use std::f64::consts::PI;
    0.5 * ((PI * xi).cos() + xi * eta + 0.25 * (PI * eta).sin())
}

/// Move the z coordinate of each canopy node in `q` (3 DOFs per node first) by `a φ`.
pub fn apply(q: &mut [f64], canopy_nodes: &[usize], a: f64) -> Result<(), BuildError> {
    let key = "canopy.imperfection_m";
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for &i in canopy_nodes {
        for k in 0..2 {
            lo[k] = lo[k].min(q[3 * i + k]);
            hi[k] = hi[k].max(q[3 * i + k]);
        }
    }
    let half = [0.5 * (hi[0] - lo[0]), 0.5 * (hi[1] - lo[1])];
    // Imported meshes are only measured here (generated outlines are checked on load).
    let size = 2.0 * half[0].min(half[1]);
    if size.is_nan() || size <= 0.0 || a.abs() > 0.05 * size {
        return Err(BuildError::key(
            key,
            format!("{a} m: at most 5 % of the canopy size ({size} m) is allowed"),
        ));
    }
    for &i in canopy_nodes {
        let xi = (q[3 * i] - lo[0]) / half[0] - 1.0;
        let eta = (q[3 * i + 1] - lo[1]) / half[1] - 1.0;
        q[3 * i + 2] += a * mode(xi, eta);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mode_is_bounded_by_one_reached_at_two_corners() {
        let n = 400;
        let mut worst: f64 = 0.0;
        for i in 0..=n {
            for j in 0..=n {
                let (x, y) = (
                    2.0 * i as f64 / n as f64 - 1.0,
                    2.0 * j as f64 / n as f64 - 1.0,
                );
                worst = worst.max(mode(x, y).abs());
            }
        }
        assert!(worst <= 1.0 + 1e-15, "max |φ| = {worst}");
        assert!((mode(-1.0, 1.0) + 1.0).abs() < 1e-15);
        assert!((mode(1.0, -1.0) + 1.0).abs() < 1e-15);
    }

    #[test]
    fn mode_has_no_symmetry_of_the_rectangle() {
        let (x, y) = (0.3, 0.7);
        let f = mode(x, y);
        for (name, g) in [
            ("x mirror", mode(-x, y)),
            ("y mirror", mode(x, -y)),
            ("rotation", mode(-x, -y)),
        ] {
            assert!((f - g).abs() > 0.05, "{name}: {f} vs {g}");
        }
    }
}

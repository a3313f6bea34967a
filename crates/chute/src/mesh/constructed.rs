//! Constructed round canopies from the generated disc: an apex vent cut out of it, and its
//! gores shaped into a cone or a hemisphere (Knacke, *Parachute Recovery Systems Design
//! Manual*, NWC TP 6575, 1991, Table 5-1: flat circular, conical, hemispherical).
//!
//! The disc's radial coordinate `r` is the distance along a gore's centreline from the apex
//! (the cloth's meridian), kept by every profile, so a gore's length is the flat canopy's
//! radius `R` whatever its shape; the circumference at `r` is what the shape makes it:
//! - flat: `ρ = r`, `z = 0`;
//! - conical, cloth at the angle `β` to the skirt's plane: `ρ = r cos β`, `z = (R − r) sin β`;
//! - hemispherical: the meridian `r` is the arc `R_h φ` of a hemisphere of radius
//!   `R_h = 2R/π`: `ρ = R_h sin φ`, `z = R_h cos φ`.
//!
//! The surface area `S₀` is then `πR²`, `πR² cos β` and `2πR_h² = 8R²/π`: the nominal area
//! the handbook's `C_D0` is referred to.

use super::CanopyMesh;
use std::collections::BTreeMap;
use std::f64::consts::FRAC_PI_2;

/// The shape of a round canopy's gores.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Profile {
    /// A flat disc.
    Flat,
    /// A cone whose cloth makes this angle (rad) with the skirt's plane.
    Conical(f64),
    /// A hemisphere.
    Hemispherical,
}

/// The position of the disc point `(x, y)` on `profile` for a disc of radius `radius`.
pub fn place(profile: Profile, radius: f64, x: f64, y: f64) -> [f64; 3] {
    let r = x.hypot(y);
    let (c, s) = if r > 0.0 { (x / r, y / r) } else { (1.0, 0.0) };
    let (rho, z) = match profile {
        Profile::Flat => (r, 0.0),
        Profile::Conical(beta) => (r * beta.cos(), (radius - r) * beta.sin()),
        Profile::Hemispherical => {
            let rh = radius / FRAC_PI_2;
            let phi = FRAC_PI_2 * r / radius;
            (rh * phi.sin(), rh * phi.cos())
        }
    };
    [rho * c, rho * s, z]
}

/// The surface area (m²) of a canopy of gore length `radius` on `profile`, vent included:
/// `πR²`, `πR² cos β`, `8R²/π`.
pub fn nominal_area(profile: Profile, radius: f64) -> f64 {
    let disc = std::f64::consts::PI * radius * radius;
    match profile {
        Profile::Flat => disc,
        Profile::Conical(beta) => disc * beta.cos(),
        Profile::Hemispherical => 8.0 * radius * radius / std::f64::consts::PI,
    }
}

/// `mesh` (a generated disc of radius `radius` in the plane z = 0) on `profile`.
pub fn shaped(mut mesh: CanopyMesh, profile: Profile, radius: f64) -> CanopyMesh {
    for p in &mut mesh.positions {
        *p = place(profile, radius, p[0], p[1]);
    }
    mesh
}

/// `mesh` (a generated disc centred on the origin in z = 0, before [`shaped`]) without the
/// nodes nearer the centre than `hem` (m) and the triangles on them; the nodes left nearest the centre form
/// the node set "vent" (the vent's hem), and "center" is gone.
pub fn with_vent(mesh: CanopyMesh, hem: f64) -> CanopyMesh {
    let r = |p: &[f64; 3]| p[0].hypot(p[1]);
    let keep: Vec<bool> = mesh.positions.iter().map(|p| r(p) >= hem).collect();
    let mut new_index = vec![usize::MAX; keep.len()];
    let mut positions = Vec::new();
    for (i, p) in mesh.positions.iter().enumerate() {
        if keep[i] {
            new_index[i] = positions.len();
            positions.push(*p);
        }
    }
    let faces = mesh
        .faces
        .iter()
        .filter(|f| f.iter().all(|&i| keep[i]))
        .map(|f| f.map(|i| new_index[i]))
        .collect();
    let inner = positions.iter().map(r).fold(f64::INFINITY, f64::min);
    let vent: Vec<usize> = (0..positions.len())
        .filter(|&i| r(&positions[i]) <= inner * (1.0 + 1e-9))
        .collect();
    let mut node_sets: BTreeMap<String, Vec<usize>> = mesh
        .node_sets
        .into_iter()
        .filter(|(k, _)| k != "center")
        .map(|(k, v)| {
            (
                k,
                v.into_iter()
                    .filter(|&i| keep[i])
                    .map(|i| new_index[i])
                    .collect(),
            )
        })
        .collect();
    node_sets.insert("vent".into(), vent);
    CanopyMesh {
        positions,
        faces,
        rod_edges: Vec::new(),
        node_sets,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::generate::circle;

    fn area(m: &CanopyMesh) -> f64 {
        m.tri_mesh().unwrap().area()
    }

    #[test]
    fn profiles_keep_the_gores_length_and_make_the_handbooks_areas() {
        let r = 1.5;
        let disc = circle(r, 0.05);
        let flat = area(&disc);
        let pi_r2 = std::f64::consts::PI * r * r;
        // Inscribed polygons: the discrete areas sit below the smooth ones by O((ℓ/R)²).
        assert!((flat / pi_r2 - 1.0).abs() < 2e-3);
        let beta = 25f64.to_radians();
        let cone = area(&shaped(disc.clone(), Profile::Conical(beta), r));
        // Flat triangles between rings on the cone: O((ℓ/R)²) = 1e-3 off cos β (measured 3e-5).
        assert!(
            (cone / flat / beta.cos() - 1.0).abs() < 1e-3,
            "a cone's gores are cut narrower by cos β"
        );
        let hemi = shaped(disc.clone(), Profile::Hemispherical, r);
        let want = nominal_area(Profile::Hemispherical, r);
        // Chords of the sphere: O((ℓ/R)²) (measured 6e-4).
        assert!(
            (area(&hemi) / want - 1.0).abs() < 2e-3,
            "{} against {want}",
            area(&hemi)
        );
        // The rim lies in the plane z = 0 on the circle of radius R_h; the apex at R_h.
        let rh = r / FRAC_PI_2;
        for &i in disc.node_set("rim").unwrap() {
            let p = hemi.positions[i];
            assert!(p[2].abs() < 1e-12 && (p[0].hypot(p[1]) - rh).abs() < 1e-12);
        }
        assert!((hemi.positions[0][2] - rh).abs() < 1e-12);
    }

    #[test]
    fn a_vent_removes_the_centre_and_leaves_its_hem() {
        let disc = circle(1.5, 0.1);
        let vented = with_vent(disc.clone(), 0.29);
        let vent = vented.node_set("vent").unwrap();
        assert!(vented.node_set("center").is_none());
        let r: Vec<f64> = vent
            .iter()
            .map(|&i| vented.positions[i][0].hypot(vented.positions[i][1]))
            .collect();
        assert!(
            r.iter().all(|x| (x - 0.3).abs() < 1e-9),
            "the ring at 0.3 m: {r:?}"
        );
        assert_eq!(vent.len(), 18);
        assert_eq!(
            vented.node_set("rim").unwrap().len(),
            disc.node_set("rim").unwrap().len()
        );
        // The cut-out area is the hexagon-like ring's polygon: 6·3 nodes on radius 0.3.
        let hole = area(&disc) - area(&vented);
        let polygon = 0.5 * 18.0 * 0.3 * 0.3 * (2.0 * std::f64::consts::PI / 18.0).sin();
        assert!((hole - polygon).abs() < 1e-9, "{hole} against {polygon}");
        assert!(vented.tri_mesh().is_ok());
    }
}

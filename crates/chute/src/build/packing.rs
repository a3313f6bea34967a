//! `[opening]`: the round canopy packed at line stretch (docs/opening.md).
//!
//! The flat disc (apex at the centre, skirt at `R`) is mapped onto a narrow surface around
//! the vertical axis, apex up and mouth down: the node at radius `r` and angle `φ` goes to
//! radius `ρ(r, φ) = c r (1 + a cos(n (φ − φ₀)))` from the axis and `r √(1 − c²)` below the
//! apex, with `c = packed_radius / R`. `pulled` has `a = 0` (a cone: every gore keeps its
//! length along the radius and is gathered around it); `bundle` has `a = ½` and `n` lobes,
//! one per load site, the sites at their tips. Both are one-to-one (the depth grows with `r`,
//! and `ρ > 0` away from the apex), so the packed canopy is free of intersections by
//! construction; the cloth is gathered around the axis (its rest shape stays the flat disc:
//! a fabric without compression stiffness wrinkles there instead of pushing back). The
//! suspension lines run straight from the packed skirt to the payload at their full length.
//! `mesh` takes the folded canopy from a file instead (any shape, the flat mesh's nodes in
//! order), and hangs the payload below its sites as a flat start does. Any of them is then
//! tilted by `attitude` about the apex, lines and payload with it.

use crate::scenario::Packing;

/// The lobes' relative depth of `bundle`.
const LOBE_DEPTH: f64 = 0.5;

/// How the canopy is packed.
#[derive(Debug, Clone)]
pub struct Pack {
    /// The fold.
    pub packing: Packing,
    /// The canopy's flat radius R (m).
    pub radius_m: f64,
    /// The packed skirt's radius `c R` around the axis (m).
    pub packed_radius_m: f64,
    /// `pack = "mesh"`: the folded canopy's file.
    pub mesh_file: Option<std::path::PathBuf>,
    /// The packed system's tilt from the vertical about the y axis through the flat canopy's
    /// centre (the apex of `pulled` and `bundle`) (rad).
    pub attitude_rad: f64,
}

/// Pack the canopy nodes `canopy` of the flat positions `q` (every DOF; the disc centred at
/// `centre` in the plane z = 0) as the module docs say, and lay every line of `lines` (node
/// chains from a load site to the payload, the payload last) straight from its packed site
/// to the payload at the line's length. `sites` are the load sites (the lobes' tips).
/// `pack = "mesh"` takes the canopy from `start` instead (node `k` of `canopy` at
/// `start[k]`).
pub fn apply(
    q: &mut [f64],
    pack: &Pack,
    (canopy, sites): (&[usize], &[usize]),
    lines: &[Vec<usize>],
    start: Option<&[[f64; 3]]>,
) {
    let apex = centroid(q, canopy);
    pack_vertical(q, pack, (canopy, sites), lines, start);
    let mut moved: Vec<usize> = canopy
        .iter()
        .chain(lines.iter().flatten())
        .copied()
        .collect();
    moved.sort_unstable();
    moved.dedup();
    tilt(q, &moved, apex, pack.attitude_rad);
}

/// Turn `nodes` by `angle` about the y axis through `pivot` (the apex): the downward axis
/// (apex to payload, −e_z) goes to `(−sin θ, 0, −cos θ)`.
fn tilt(q: &mut [f64], nodes: &[usize], pivot: [f64; 3], angle: f64) {
    let (s, c) = angle.sin_cos();
    for &i in nodes {
        let (dx, dz) = (q[3 * i] - pivot[0], q[3 * i + 2] - pivot[2]);
        q[3 * i] = pivot[0] + c * dx + s * dz;
        q[3 * i + 2] = pivot[2] - s * dx + c * dz;
    }
}

/// [`apply`] with the axis vertical.
fn pack_vertical(
    q: &mut [f64],
    pack: &Pack,
    (canopy, sites): (&[usize], &[usize]),
    lines: &[Vec<usize>],
    start: Option<&[[f64; 3]]>,
) {
    let lengths: Vec<f64> = lines.iter().map(|l| chain_length(q, l)).collect();
    let (a, n) = match (pack.packing, start) {
        (Packing::Mesh, Some(start)) => {
            for (&i, p) in canopy.iter().zip(start) {
                q[3 * i..3 * i + 3].copy_from_slice(p);
            }
            return lay_lines(q, lines, sites, lengths.first().copied());
        }
        (Packing::Bundle, _) => (LOBE_DEPTH, sites.len() as f64),
        _ => (0.0, 0.0),
    };
    let c = pack.packed_radius_m / pack.radius_m;
    let depth = (1.0 - c * c).sqrt();
    let centre = centroid(q, canopy);
    let angle = |i: usize| (q[3 * i + 1] - centre[1]).atan2(q[3 * i] - centre[0]);
    let phi0 = sites.first().map_or(0.0, |&s| angle(s));
    for &i in canopy {
        let (x, y) = (q[3 * i] - centre[0], q[3 * i + 1] - centre[1]);
        let (r, phi) = (x.hypot(y), y.atan2(x));
        let rho = c * r * (1.0 + a * (n * (phi - phi0)).cos());
        q[3 * i] = centre[0] + rho * phi.cos();
        q[3 * i + 1] = centre[1] + rho * phi.sin();
        q[3 * i + 2] = centre[2] - r * depth;
    }
    let Some(payload) = lines.first().and_then(|l| l.last().copied()) else {
        return;
    };
    // The payload on the axis, every line at its full length (the sites are all at the same
    // radius and depth).
    let site = lines[0][0];
    let rho = (q[3 * site] - centre[0]).hypot(q[3 * site + 1] - centre[1]);
    let drop = (lengths[0] * lengths[0] - rho * rho).max(0.0).sqrt();
    let p = [centre[0], centre[1], q[3 * site + 2] - drop];
    q[3 * payload..3 * payload + 3].copy_from_slice(&p);
    straighten(q, lines, p);
}

/// A folded start's lines: the payload below the sites' centroid where the line of the site
/// farthest from it (horizontally) is `length` long from the highest site, as the flat
/// start places it; every line straight.
fn lay_lines(q: &mut [f64], lines: &[Vec<usize>], sites: &[usize], length: Option<f64>) {
    let (Some(payload), Some(len)) = (lines.first().and_then(|l| l.last().copied()), length) else {
        return;
    };
    let c = centroid(q, sites);
    let top = sites.iter().map(|&i| q[3 * i + 2]).fold(f64::MIN, f64::max);
    let r_max = (sites.iter())
        .map(|&i| (q[3 * i] - c[0]).hypot(q[3 * i + 1] - c[1]))
        .fold(0.0, f64::max);
    let p = [
        c[0],
        c[1],
        top - (len * len - r_max * r_max).max(0.0).sqrt(),
    ];
    q[3 * payload..3 * payload + 3].copy_from_slice(&p);
    straighten(q, lines, p);
}

/// Every line straight from its site to the payload at `p`, its nodes evenly spaced.
fn straighten(q: &mut [f64], lines: &[Vec<usize>], p: [f64; 3]) {
    for line in lines {
        let a: [f64; 3] = std::array::from_fn(|k| q[3 * line[0] + k]);
        let m = line.len() - 1;
        for (j, &node) in line.iter().enumerate().take(m).skip(1) {
            let t = j as f64 / m as f64;
            for k in 0..3 {
                q[3 * node + k] = a[k] + t * (p[k] - a[k]);
            }
        }
    }
}

fn centroid(q: &[f64], nodes: &[usize]) -> [f64; 3] {
    let n = nodes.len().max(1) as f64;
    std::array::from_fn(|k| nodes.iter().map(|&i| q[3 * i + k]).sum::<f64>() / n)
}

fn chain_length(q: &[f64], chain: &[usize]) -> f64 {
    (chain.windows(2))
        .map(|w| {
            (0..3)
                .map(|k| (q[3 * w[1] + k] - q[3 * w[0] + k]).powi(2))
                .sum::<f64>()
                .sqrt()
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A disc of 7 rings, packed either way: every node keeps its distance from the apex
    /// along the gore's radius within the lobes' stretch, the skirt lies at the packed
    /// radius (pulled) or between (1 ∓ a) of it (bundle), and lines keep their lengths.
    #[test]
    fn packing_keeps_the_gores_and_the_lines() {
        let mesh = crate::mesh::generate::circle_with_rim_sites(1.5, 0.25, 6);
        let mut q: Vec<f64> = mesh.positions.iter().flatten().copied().collect();
        let canopy: Vec<usize> = (0..mesh.positions.len()).collect();
        let rim: Vec<usize> = (canopy.iter().copied())
            .filter(|&i| (q[3 * i].hypot(q[3 * i + 1]) - 1.5).abs() < 1e-9)
            .collect();
        let sites: Vec<usize> = rim.iter().step_by(rim.len() / 6).copied().collect();
        // Three-segment lines from each site to a payload 3 m below.
        let payload = canopy.len() + 2 * sites.len();
        let mut lines = Vec::new();
        q.resize(3 * (payload + 1), 0.0);
        q[3 * payload + 2] = -(9.0f64 - 2.25).sqrt();
        for (k, &s) in sites.iter().enumerate() {
            let (a, b) = (canopy.len() + 2 * k, canopy.len() + 2 * k + 1);
            for (node, t) in [(a, 1.0 / 3.0), (b, 2.0 / 3.0)] {
                for c in 0..3 {
                    q[3 * node + c] = q[3 * s + c] + t * (q[3 * payload + c] - q[3 * s + c]);
                }
            }
            lines.push(vec![s, a, b, payload]);
        }
        for packing in [Packing::Pulled, Packing::Bundle] {
            let mut p = q.clone();
            let pack = Pack {
                packing,
                radius_m: 1.5,
                packed_radius_m: 0.15,
                mesh_file: None,
                attitude_rad: 0.0,
            };
            apply(&mut p, &pack, (&canopy, &sites), &lines, None);
            for &i in &rim {
                let rho = p[3 * i].hypot(p[3 * i + 1]);
                let (lo, hi) = match packing {
                    Packing::Pulled => (0.15 - 1e-12, 0.15 + 1e-12),
                    _ => (0.075 - 1e-12, 0.225 + 1e-12),
                };
                assert!(rho >= lo && rho <= hi, "{packing:?}: rim at {rho}");
            }
            for &s in &sites {
                let rho = p[3 * s].hypot(p[3 * s + 1]);
                let want = if packing == Packing::Pulled {
                    0.15
                } else {
                    0.225
                };
                assert!((rho - want).abs() < 1e-12, "{packing:?}: site at {rho}");
            }
            for l in &lines {
                let (flat, packed) = (chain_length(&q, l), chain_length(&p, l));
                assert!((flat - packed).abs() < 1e-12, "{flat} {packed}");
            }
        }
    }
}

//! Load sites: named node sets or `[x, y]` points resolved to the nearest canopy node.
use super::canopy::Geometry;
use super::BuildError;
use crate::resolve::ModelSpec;
use crate::scenario::{CanopyShape, ModelKind, SiteSet, Sites};

/// Resolve the scenario's load sites to canopy node indices (deduplicated, in order).
pub fn resolve(s: &ModelSpec, geo: &Geometry) -> Result<Vec<usize>, BuildError> {
    let pos = &geo.mesh.positions;
    let nearest = |x: f64, y: f64| -> usize {
        let d2 = |i: usize| (pos[i][0] - x).powi(2) + (pos[i][1] - y).powi(2);
        *geo.canopy_nodes
            .iter()
            .min_by(|&&a, &&b| d2(a).total_cmp(&d2(b)))
            .expect("canopy has nodes")
    };
    let named = |name: &str| -> Result<Vec<usize>, BuildError> {
        geo.mesh
            .node_set(name)
            .map(<[usize]>::to_vec)
            .filter(|v| !v.is_empty())
            .ok_or_else(|| {
                BuildError::key(
                    "load.sites",
                    format!("this canopy has no \"{name}\" node set"),
                )
            })
    };
    let mut out = match &s.load.sites {
        Sites::Points(pts) => {
            if s.canopy.shape == CanopyShape::Mesh {
                inside_mesh(geo, pts)?;
            }
            pts.iter().map(|p| nearest(p[0], p[1])).collect()
        }
        Sites::Named(set) => match (s.kind, set) {
            (ModelKind::Rod, SiteSet::Ends) => {
                let chain = geo.rod_chain.as_ref().expect("rod canopy");
                vec![chain[0], chain[chain.len() - 1]]
            }
            (_, SiteSet::Center) => vec![nearest(0.0, 0.0)],
            (ModelKind::Shell, SiteSet::Corners) => named("corners")?,
            (ModelKind::Shell, SiteSet::CornersAndMidspan) => {
                let mut v = named("corners")?;
                v.extend(named("long_edge_midpoints")?);
                v
            }
            (ModelKind::Shell, SiteSet::Rim) => rim_sites(s, geo)?,
            (kind, set) => {
                return Err(BuildError::key(
                    "load.sites",
                    format!("{set:?} sites are not defined for a {kind:?} canopy").to_lowercase(),
                ))
            }
        },
    };
    let mut seen = std::collections::HashSet::new();
    out.retain(|i| seen.insert(*i));
    if s.kind == ModelKind::Shell && s.canopy.shape == CanopyShape::Mesh && out.is_empty() {
        return Err(BuildError::key("load.sites", "no load site resolved"));
    }
    Ok(out)
}

/// Every `[x, y]` site must lie on the imported canopy seen from above (on the top view of
/// one of its triangles), as sites of a generated outline must lie inside it: a site off the
/// canopy is a mistake, not a request for the nearest node.
fn inside_mesh(geo: &Geometry, pts: &[[f64; 2]]) -> Result<(), BuildError> {
    let pos = &geo.mesh.positions;
    let (lo, hi) = super::canopy::extent(&geo.mesh, &geo.canopy_nodes);
    let eps = 1e-9 * (hi[0] - lo[0]).max(hi[1] - lo[1]).max(1.0);
    let on = |x: f64, y: f64, t: &[usize; 3]| {
        let [a, b, c] = t.map(|i| [pos[i][0], pos[i][1]]);
        let cross =
            |p: [f64; 2], q: [f64; 2]| (q[0] - p[0]) * (y - p[1]) - (q[1] - p[1]) * (x - p[0]);
        let area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        let scale = area.abs().sqrt().max(eps);
        let d = [cross(a, b), cross(b, c), cross(c, a)].map(|v| v * area.signum() / scale);
        d.iter().all(|&v| v >= -eps)
    };
    for (i, p) in pts.iter().enumerate() {
        if !geo.mesh.faces.iter().any(|t| on(p[0], p[1], t)) {
            return Err(BuildError::key(
                "load.sites",
                format!(
                    "site {} [{}, {}] m is not on the imported canopy seen from above (its nodes span x ∈ [{}, {}] m, y ∈ [{}, {}] m): give points on the canopy",
                    i + 1, p[0], p[1], lo[0], hi[0], lo[1], hi[1]
                ),
            ));
        }
    }
    Ok(())
}

/// `rim_site_count` rim nodes at equally spaced polar angles, the first on +x.
fn rim_sites(s: &ModelSpec, geo: &Geometry) -> Result<Vec<usize>, BuildError> {
    let rim = geo.mesh.node_set("rim").unwrap_or(&[]);
    if rim.is_empty() {
        return Err(BuildError::key("load.sites", "this canopy has no rim"));
    }
    let n = s.load.rim_site_count;
    let pos = &geo.mesh.positions;
    let angle = |i: usize| pos[i][1].atan2(pos[i][0]);
    Ok((0..n)
        .map(|k| {
            let target = 2.0 * std::f64::consts::PI * k as f64 / n as f64;
            let dist = |i: usize| {
                let d = (angle(i) - target).rem_euclid(2.0 * std::f64::consts::PI);
                d.min(2.0 * std::f64::consts::PI - d)
            };
            *rim.iter()
                .min_by(|&&a, &&b| dist(a).total_cmp(&dist(b)))
                .expect("rim not empty")
        })
        .collect())
}

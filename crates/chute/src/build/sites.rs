//! Load sites: named node sets or `[x, y]` points resolved to the nearest canopy node.
use super::canopy::Geometry;
use super::BuildError;
use crate::scenario::{CanopyShape, ModelKind, Scenario, SiteSet, Sites};

/// Resolve the scenario's load sites to canopy node indices (deduplicated, in order).
pub fn resolve(s: &Scenario, geo: &Geometry) -> Result<Vec<usize>, BuildError> {
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
        Sites::Points(pts) => pts.iter().map(|p| nearest(p[0], p[1])).collect(),
        Sites::Named(set) => match (s.model.kind, set) {
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
    if s.model.kind == ModelKind::Shell && s.canopy.shape == CanopyShape::Mesh && out.is_empty() {
        return Err(BuildError::key("load.sites", "no load site resolved"));
    }
    Ok(out)
}

/// `rim_site_count` rim nodes at equally spaced polar angles, the first on +x.
fn rim_sites(s: &Scenario, geo: &Geometry) -> Result<Vec<usize>, BuildError> {
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

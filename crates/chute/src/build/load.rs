//! The load: forces at the sites, masses at the sites, a payload on suspension lines, or a
//! scaled mesh node (the DisMech convention); and every rod of the model (the rod canopy,
//! suspension lines, rods of an imported mesh).
use super::canopy::Geometry;
use super::BuildError;
use crate::resolve::ModelSpec;
use crate::scenario::{LoadMode, ModelKind};
use engine::loads::PointForces;
use engine::rod::{RodHandles, RodNetwork, RodSpec, Section};
use engine::Model;

/// Nodes and rods of the whole model, and how the load is applied.
pub struct Plan {
    /// All node positions (m): canopy, then line nodes, then the payload.
    pub positions: Vec<[f64; 3]>,
    /// Every rod.
    pub rods: RodNetwork,
    /// Rod index of the rod canopy (rod model).
    pub canopy_rod: Option<usize>,
    /// Rod indices of suspension lines (payload mode and imported meshes).
    pub line_rods: Vec<usize>,
    /// Rod indices of the payload's suspension lines, in site order.
    pub payload_lines: Vec<usize>,
    /// The payload node (payload and node-mass-scale modes).
    pub payload_node: Option<usize>,
    /// Load sites (canopy nodes).
    pub sites: Vec<usize>,
    /// Load carried by constant forces rather than masses (N).
    pub applied_force_n: f64,
    /// Load mass added at canopy sites (kg), not part of the canopy's own weight.
    pub site_mass_kg: f64,
}

impl Plan {
    /// The payload's suspension lines once the rods are installed (`None` without them).
    pub fn lines(&self, s: &ModelSpec, handles: &RodHandles) -> Option<super::control::Lines> {
        if self.payload_lines.is_empty() {
            return None;
        }
        let rods: Vec<usize> = self
            .payload_lines
            .iter()
            .map(|&k| self.line_rods[k])
            .collect();
        let area = std::f64::consts::PI * s.lines.radius_m.powi(2);
        let mut lines = super::control::Lines::new(
            handles,
            &rods,
            &self.sites,
            s.lines.youngs_modulus_pa * area,
        )?;
        for (line, &r) in lines.lines.iter_mut().zip(&rods) {
            let spec = &self.rods.rods()[r];
            line.schedule = spec.rest_schedule.clone().zip(handles.rod_schedule[r]);
        }
        Some(lines)
    }

    /// Segments to draw: every rod edge.
    pub fn segments(&self, _geo: &Geometry) -> Vec<[usize; 2]> {
        self.rods.edges()
    }

    /// Add the load (after the structure's own masses are installed).
    pub fn add_masses_and_loads(&mut self, s: &ModelSpec, model: &mut Model) {
        let (w, g) = (s.load.weight_n, s.gravity_mps2);
        let n = self.sites.len().max(1) as f64;
        match s.load.mode {
            LoadMode::Force => {
                let f = vec![[0.0, 0.0, -w / n]; self.sites.len()];
                model.add_force(PointForces::new(&self.sites, &f));
                self.applied_force_n = w;
            }
            LoadMode::Mass => {
                for &i in &self.sites {
                    model.add_node_mass(i, w / (g * n));
                }
                self.site_mass_kg = w / g;
            }
            LoadMode::Payload => {
                let p = self.payload_node.expect("payload node planned");
                model.add_node_mass(p, w / g);
            }
            LoadMode::NodeMassScale => {
                let p = self.payload_node.expect("payload node planned");
                let m = model.node_mass(p);
                model.add_node_mass(p, (s.load.mass_scale - 1.0) * m);
            }
        }
    }
}

fn line_spec(s: &ModelSpec, nodes: Vec<usize>) -> RodSpec {
    let l = &s.lines;
    let g = l.youngs_modulus_pa / (2.0 * (1.0 + l.poisson_ratio));
    RodSpec::new(
        nodes,
        Section::Circle { radius: l.radius_m },
        l.youngs_modulus_pa,
        g,
        l.density_kg_m3,
    )
}

/// Plan nodes, rods and load application for `s`.
pub fn plan(s: &ModelSpec, geo: &Geometry, sites: &[usize]) -> Result<Plan, BuildError> {
    let mut p = Plan {
        positions: geo.mesh.positions.clone(),
        rods: RodNetwork::new(),
        canopy_rod: None,
        line_rods: Vec::new(),
        payload_lines: Vec::new(),
        payload_node: None,
        sites: sites.to_vec(),
        applied_force_n: 0.0,
        site_mass_kg: 0.0,
    };
    if let Some(chain) = &geo.rod_chain {
        let (m, c) = (&s.material, &s.canopy);
        let g = m.youngs_modulus_pa / (2.0 * (1.0 + m.poisson_ratio));
        let section = Section::Rectangle {
            width: c.width_m,
            height: c.thickness_m,
        };
        // Width along y: the strip bends easily out of its plane (about y).
        let spec = RodSpec::new(
            chain.clone(),
            section,
            m.youngs_modulus_pa,
            g,
            m.density_kg_m3,
        )
        .with_first_director([0.0, 1.0, 0.0]);
        p.canopy_rod = Some(p.rods.add_rod(spec));
    }
    for chain in &geo.mesh_lines {
        p.line_rods
            .push(p.rods.add_rod(line_spec(s, chain.clone())));
        p.rods.pin(chain[0]);
        p.rods.pin(chain[chain.len() - 1]);
    }
    match s.load.mode {
        LoadMode::Payload => add_payload_lines(s, &mut p)?,
        LoadMode::NodeMassScale => {
            let idx = s
                .load
                .node
                .checked_sub(1)
                .filter(|&i| i < p.positions.len());
            let idx = idx.ok_or_else(|| {
                BuildError::key(
                    "load.node",
                    format!(
                        "node {} is not in the mesh (1 … {})",
                        s.load.node,
                        p.positions.len()
                    ),
                )
            })?;
            p.payload_node = Some(idx);
        }
        LoadMode::Force | LoadMode::Mass => {}
    }
    if s.kind == ModelKind::Rod && p.canopy_rod.is_none() {
        return Err(BuildError::key(
            "model.kind",
            "rod model without a rod canopy",
        ));
    }
    Ok(p)
}

/// A payload node below the sites' centroid, at the depth where the line from the farthest
/// site has length `lines.length_m`; one line of `lines.segments` rod edges per site, pinned
/// at both ends. Every line starts straight and taut (rest length = initial length).
fn add_payload_lines(s: &ModelSpec, p: &mut Plan) -> Result<(), BuildError> {
    if p.sites.is_empty() {
        return Err(BuildError::key(
            "load.sites",
            "payload mode needs at least one site",
        ));
    }
    let n = p.sites.len() as f64;
    let (mut cx, mut cy, mut z_top) = (0.0, 0.0, f64::NEG_INFINITY);
    for &i in &p.sites {
        cx += p.positions[i][0] / n;
        cy += p.positions[i][1] / n;
        z_top = z_top.max(p.positions[i][2]);
    }
    let r_max = p
        .sites
        .iter()
        .map(|&i| (p.positions[i][0] - cx).hypot(p.positions[i][1] - cy))
        .fold(0.0, f64::max);
    let len = s.lines.length_m;
    if len <= r_max * 1.0001 {
        return Err(BuildError::key(
            "lines.length_m",
            format!("{len} m is not longer than the {r_max:.4} m horizontal distance from a load site to the payload"),
        ));
    }
    let payload = [cx, cy, z_top - (len * len - r_max * r_max).sqrt()];
    let pid = p.positions.len();
    p.positions.push(payload);
    p.payload_node = Some(pid);
    let segs = s.lines.segments;
    let lengths: Vec<f64> = p
        .sites
        .iter()
        .map(|&i| {
            (0..3)
                .map(|c| (p.positions[i][c] - payload[c]).powi(2))
                .sum::<f64>()
                .sqrt()
        })
        .collect();
    super::control::check(s, &lengths)?;
    for (k, &site) in p.sites.clone().iter().enumerate() {
        let a = p.positions[site];
        let mut nodes = vec![site];
        for k in 1..segs {
            let t = k as f64 / segs as f64;
            nodes.push(p.positions.len());
            p.positions
                .push([0, 1, 2].map(|c| a[c] + t * (payload[c] - a[c])));
        }
        nodes.push(pid);
        let mut spec = line_spec(s, nodes);
        if s.pulled() {
            spec = spec.with_rest_schedule(super::control::schedule(s, k));
        }
        p.line_rods.push(p.rods.add_rod(spec));
        p.payload_lines.push(p.line_rods.len() - 1);
        p.rods.pin(site);
    }
    p.rods.pin(pid);
    Ok(())
}

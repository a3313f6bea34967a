//! A builder for networks of Discrete Elastic Rods (knows nothing of parachutes).
//!
//! A rod is a chain of global nodes; its `j`-th edge joins `nodes[j] → nodes[j+1]`. Rods may
//! share nodes. Network edges are numbered rod by rod, and network edge `j` owns the twist
//! DOF `layout.twist(twist_offset + j)`.
//!
//! **Joint policy** (as DisMech): bend–twist elements couple every pair of consecutive edges
//! of a rod, and, at every node shared by several rods (or visited twice by one rod) that is
//! not [`RodNetwork::pin`]ned, every other pair of edges meeting there. A cross pair uses the
//! mean of the two rods' stiffnesses and the Voronoi length `(l̄_a + l̄_b)/2`; its natural
//! curvature and twist are those of the rest shape, so the joint is rigid (it keeps its rest
//! angles). A pinned node transmits forces but no moments between rods.

use super::bend_twist::{BendTwist, BendTwistElement};
use super::frames::first_director;
use super::section::Section;
use super::stretch::{RestSchedule, Scheduled, Stretch};
use crate::error::{EngineError, InvalidModel};
use crate::model::{ForceId, Model};
use crate::vec3::{node, V3};
use std::ops::Range;

/// One rod: its nodes, section and material.
#[derive(Debug, Clone, PartialEq)]
pub struct RodSpec {
    /// Global node indices along the rod (at least 2).
    pub nodes: Vec<usize>,
    /// Cross-section (uniform along the rod).
    pub section: Section,
    /// Young's modulus `E` (Pa).
    pub youngs_modulus: f64,
    /// Shear modulus `G` (Pa).
    pub shear_modulus: f64,
    /// Density `ρ` (kg/m³).
    pub density: f64,
    /// Direction of the first material director `d1` on the first edge (projected normal to
    /// it). `None`: `frames::perpendicular` (horizontal for a horizontal rod). For a
    /// rectangle `d1` is the width direction.
    pub first_director: Option<[f64; 3]>,
    /// A schedule of the rod's total rest length (a pulled line): see [`super::stretch`].
    pub rest_schedule: Option<RestSchedule>,
}

impl RodSpec {
    /// A rod with the default first director.
    pub fn new(nodes: Vec<usize>, section: Section, e: f64, g: f64, rho: f64) -> Self {
        Self {
            nodes,
            section,
            youngs_modulus: e,
            shear_modulus: g,
            density: rho,
            first_director: None,
            rest_schedule: None,
        }
    }
    /// The same rod with its rest length following `schedule`.
    pub fn with_rest_schedule(mut self, schedule: RestSchedule) -> Self {
        self.rest_schedule = Some(schedule);
        self
    }
    /// The same rod with first director `d1`.
    pub fn with_first_director(mut self, d1: [f64; 3]) -> Self {
        self.first_director = Some(d1);
        self
    }
}

/// What [`RodNetwork::install`] added, for the builders that come after it (drag, outputs).
#[derive(Debug, Clone, Default)]
pub struct RodHandles {
    /// Node pair of each network edge.
    pub edges: Vec<[usize; 2]>,
    /// Rod of each network edge.
    pub edge_rod: Vec<usize>,
    /// Global twist DOF of each network edge.
    pub twist_dofs: Vec<usize>,
    /// Rest length `l̄` of each network edge (m).
    pub rest_len: Vec<f64>,
    /// Network edges of each rod.
    pub rod_edges: Vec<Range<usize>>,
    /// Voronoi length of every global node (m): half the sum of the rest lengths of the
    /// network edges touching it (0 for nodes outside the network).
    pub voronoi_len: Vec<f64>,
    /// Voronoi length of each node of each rod, counting that rod's edges only (m).
    pub rod_voronoi_len: Vec<Vec<f64>>,
    /// Number of bend–twist elements.
    pub n_bend_twist: usize,
    /// The stretching family (`rod-stretch`), which holds the rest-length schedules.
    pub stretch: Option<ForceId>,
    /// Schedule index (in the stretching family) of each rod with a rest schedule.
    pub rod_schedule: Vec<Option<usize>>,
}

/// A set of rods, their joints and pins.
#[derive(Debug, Clone, Default)]
pub struct RodNetwork {
    rods: Vec<RodSpec>,
    pinned: Vec<usize>,
}

/// An edge end at a node: network edge, rod, position in the rod, and whether the edge
/// points into the node.
#[derive(Clone, Copy)]
struct Incidence {
    edge: usize,
    rod: usize,
    index: usize,
    into: bool,
}

impl RodNetwork {
    /// An empty network.
    pub fn new() -> Self {
        Self::default()
    }
    /// Add a rod; returns its index.
    pub fn add_rod(&mut self, spec: RodSpec) -> usize {
        self.rods.push(spec);
        self.rods.len() - 1
    }
    /// Make `node` a pin joint: no bending/twisting coupling across rods there.
    pub fn pin(&mut self, node: usize) {
        if !self.pinned.contains(&node) {
            self.pinned.push(node);
        }
    }
    /// The rods.
    pub fn rods(&self) -> &[RodSpec] {
        &self.rods
    }
    /// Number of edges (= twist DOFs needed).
    pub fn n_edges(&self) -> usize {
        self.rods
            .iter()
            .map(|r| r.nodes.len().saturating_sub(1))
            .sum()
    }
    /// Node pairs of all network edges, rod by rod.
    pub fn edges(&self) -> Vec<[usize; 2]> {
        self.rods
            .iter()
            .flat_map(|r| r.nodes.windows(2).map(|w| [w[0], w[1]]))
            .collect()
    }
    /// First network edge of each rod.
    fn rod_offsets(&self) -> Vec<usize> {
        let mut off = Vec::with_capacity(self.rods.len());
        let mut acc = 0;
        for r in &self.rods {
            off.push(acc);
            acc += r.nodes.len().saturating_sub(1);
        }
        off
    }

    fn validate(&self, model: &Model, q: &[f64], twist_offset: usize) -> Result<(), InvalidModel> {
        let lay = model.layout;
        if q.len() != lay.len() {
            return Err(InvalidModel::StateLength {
                got: q.len(),
                expected: lay.len(),
            });
        }
        if twist_offset + self.n_edges() > lay.n_twists {
            return Err(InvalidModel::TwistDofs {
                start: twist_offset,
                end: twist_offset + self.n_edges(),
                available: lay.n_twists,
            });
        }
        let pos = |x: f64| x.is_finite() && x > 0.0;
        for (rod, s) in self.rods.iter().enumerate() {
            if s.nodes.len() < 2 {
                return Err(InvalidModel::RodTooShort { rod });
            }
            if let Some(&node) = s.nodes.iter().find(|&&n| n >= lay.n_nodes) {
                return Err(InvalidModel::NodeOutOfRange {
                    rod,
                    node,
                    n_nodes: lay.n_nodes,
                });
            }
            if !(pos(s.youngs_modulus) && pos(s.shear_modulus) && s.density >= 0.0) {
                return Err(InvalidModel::Material { rod });
            }
            s.section
                .validate()
                .map_err(|reason| InvalidModel::Section { rod, reason })?;
            for w in s.nodes.windows(2) {
                if (node(q, w[1]) - node(q, w[0])).norm() <= 0.0 {
                    return Err(InvalidModel::ZeroLengthEdge {
                        rod,
                        a: w[0],
                        b: w[1],
                    });
                }
            }
        }
        Ok(())
    }

    /// First reference director of every edge: space-parallel transport along each rod.
    fn reference_directors(&self, q: &[f64]) -> Result<Vec<V3>, InvalidModel> {
        let mut out = Vec::with_capacity(self.n_edges());
        for (rod, s) in self.rods.iter().enumerate() {
            let t: Vec<V3> = s
                .nodes
                .windows(2)
                .map(|w| (node(q, w[1]) - node(q, w[0])).normalize())
                .collect();
            let d1 = first_director(&t[0], s.first_director)
                .ok_or(InvalidModel::DirectorParallel { rod })?;
            out.extend(super::frames::space_parallel_frames(&t, &d1));
        }
        Ok(out)
    }

    /// Bend–twist elements: consecutive edges of each rod, then joints.
    fn elements(&self, rest_len: &[f64], n_nodes: usize) -> Vec<BendTwistElement> {
        let off = self.rod_offsets();
        let mut inc: Vec<Vec<Incidence>> = vec![Vec::new(); n_nodes];
        for (r, s) in self.rods.iter().enumerate() {
            for (j, w) in s.nodes.windows(2).enumerate() {
                let edge = off[r] + j;
                inc[w[0]].push(Incidence {
                    edge,
                    rod: r,
                    index: j,
                    into: false,
                });
                inc[w[1]].push(Incidence {
                    edge,
                    rod: r,
                    index: j,
                    into: true,
                });
            }
        }
        let mut out = Vec::new();
        for (nd, list) in inc.iter().enumerate() {
            let pinned = self.pinned.contains(&nd);
            for (a, ia) in list.iter().enumerate() {
                for ib in &list[a + 1..] {
                    let consecutive = self.consecutive(ia, ib);
                    if consecutive || !pinned {
                        out.push(self.element(nd, ia, ib, consecutive, rest_len));
                    }
                }
            }
        }
        out
    }

    /// Whether two edge ends at a node are consecutive edges of one rod (incl. a closed
    /// rod's last and first edges).
    fn consecutive(&self, a: &Incidence, b: &Incidence) -> bool {
        if a.rod != b.rod || a.into == b.into {
            return false;
        }
        let n = self.rods[a.rod].nodes.len() - 1;
        let (i, o) = if a.into { (a, b) } else { (b, a) };
        o.index == i.index + 1 || (i.index + 1 == n && o.index == 0)
    }

    fn element(
        &self,
        nd: usize,
        a: &Incidence,
        b: &Incidence,
        consecutive: bool,
        rest_len: &[f64],
    ) -> BendTwistElement {
        // Order a consecutive pair along the rod; otherwise keep the incidence order.
        let (a, b) = if consecutive && !a.into {
            (b, a)
        } else {
            (a, b)
        };
        // The node at the other end of the edge.
        let far =
            |i: &Incidence| self.rods[i.rod].nodes[if i.into { i.index } else { i.index + 1 }];
        let (ra, rb) = (&self.rods[a.rod], &self.rods[b.rod]);
        let mean = |f: &dyn Fn(&RodSpec) -> f64| 0.5 * (f(ra) + f(rb));
        BendTwistElement {
            nodes: [far(a), nd, far(b)],
            edges: [a.edge, b.edge],
            signs: [
                if a.into { 1.0 } else { -1.0 },
                if b.into { -1.0 } else { 1.0 },
            ],
            ei1: mean(&|r| r.section.ei1(r.youngs_modulus)),
            ei2: mean(&|r| r.section.ei2(r.youngs_modulus)),
            gj: mean(&|r| r.section.gj(r.shear_modulus)),
            voronoi_len: 0.5 * (rest_len[a.edge] + rest_len[b.edge]),
        }
    }

    /// Add stretching (`k = E A`), bending and twisting forces and lumped masses (`ρ A l̄`
    /// split to the two nodes of each edge; `ρ (I1 + I2) l̄` to its twist DOF) to `model`.
    /// Network edge `j` uses twist DOF `model.layout.twist(twist_offset + j)`. `q` holds the
    /// rest shape; natural curvature and twist are taken from it with zero twist angles.
    /// Twist DOFs in no bend–twist element carry no energy and are fixed.
    pub fn install(
        &self,
        model: &mut Model,
        q: &[f64],
        twist_offset: usize,
    ) -> Result<RodHandles, EngineError> {
        self.validate(model, q, twist_offset)?;
        let edges = self.edges();
        let off = self.rod_offsets();
        let n_nodes = model.layout.n_nodes;
        let mut h = RodHandles {
            rest_len: edges
                .iter()
                .map(|&[a, b]| (node(q, b) - node(q, a)).norm())
                .collect(),
            twist_dofs: (0..edges.len())
                .map(|j| model.layout.twist(twist_offset + j))
                .collect(),
            voronoi_len: vec![0.0; n_nodes],
            ..Default::default()
        };
        let mut stiff = Vec::with_capacity(edges.len());
        for (r, s) in self.rods.iter().enumerate() {
            let range = off[r]..off[r] + s.nodes.len() - 1;
            let mut vor = vec![0.0; s.nodes.len()];
            let area = s.section.area();
            let rot = s.section.polar_inertia_density(s.density);
            for (j, e) in range.clone().enumerate() {
                let l = h.rest_len[e];
                let [a, b] = edges[e];
                model.add_node_mass(a, 0.5 * s.density * area * l);
                model.add_node_mass(b, 0.5 * s.density * area * l);
                model.mass[h.twist_dofs[e]] += rot * l;
                h.voronoi_len[a] += 0.5 * l;
                h.voronoi_len[b] += 0.5 * l;
                vor[j] += 0.5 * l;
                vor[j + 1] += 0.5 * l;
                stiff.push(s.youngs_modulus * area);
                h.edge_rod.push(r);
            }
            h.rod_edges.push(range);
            h.rod_voronoi_len.push(vor);
        }
        let (schedules, scheduled) = self.schedules(&h);
        h.rod_schedule = self.rod_schedule_index();
        h.stretch = Some(model.add_force(Stretch::with_schedules(
            "rod-stretch",
            &edges,
            h.rest_len.clone(),
            stiff,
            schedules,
            scheduled,
        )));
        let elems = self.elements(&h.rest_len, n_nodes);
        let mut used = vec![false; edges.len()];
        for el in &elems {
            used[el.edges[0]] = true;
            used[el.edges[1]] = true;
        }
        for (e, &u) in used.iter().enumerate() {
            if !u {
                model.fixed[h.twist_dofs[e]] = true;
            }
        }
        h.n_bend_twist = elems.len();
        let a1 = self.reference_directors(q)?;
        if !elems.is_empty() {
            let bt = BendTwist::new("rod-bend-twist", elems, edges.clone(), &h.twist_dofs, a1, q);
            model.add_force(bt);
        }
        h.edges = edges;
        Ok(h)
    }

    /// Schedule index of each rod that has a rest schedule, in rod order.
    fn rod_schedule_index(&self) -> Vec<Option<usize>> {
        let mut next = 0;
        self.rods
            .iter()
            .map(|r| {
                r.rest_schedule.as_ref().map(|_| {
                    next += 1;
                    next - 1
                })
            })
            .collect()
    }

    /// The schedules of the rods that have one, and each edge's part in its rod's schedule
    /// (the share `l̄₀/L₀`).
    fn schedules(&self, h: &RodHandles) -> (Vec<RestSchedule>, Vec<Option<Scheduled>>) {
        let mut scheduled = vec![None; h.rest_len.len()];
        let mut schedules = Vec::new();
        for (r, range) in h.rod_edges.iter().enumerate() {
            let Some(sch) = &self.rods[r].rest_schedule else {
                continue;
            };
            let total: f64 = h.rest_len[range.clone()].iter().sum();
            for e in range.clone() {
                scheduled[e] = Some(Scheduled {
                    schedule: schedules.len(),
                    share: h.rest_len[e] / total,
                });
            }
            schedules.push(sch.clone());
        }
        (schedules, scheduled)
    }

    /// Clamp an end of rod `rod` in position and orientation: its first (or last) two nodes
    /// and the end edge's twist DOF are fixed. The clamped section of a continuum cantilever
    /// is then the midpoint of the clamped edge (see `docs/rods.md`).
    pub fn clamp_end(&self, model: &mut Model, rod: usize, at_start: bool, twist_offset: usize) {
        let nodes = &self.rods[rod].nodes;
        let n = nodes.len();
        let (i, j, e) = if at_start {
            (nodes[0], nodes[1], 0)
        } else {
            (nodes[n - 2], nodes[n - 1], n - 2)
        };
        model.fix_node(i);
        model.fix_node(j);
        let edge = self.rod_offsets()[rod] + e;
        let d = model.layout.twist(twist_offset + edge);
        model.fixed[d] = true;
    }
}

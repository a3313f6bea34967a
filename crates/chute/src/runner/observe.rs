//! Observation of the state for the outputs: canopy means, total drag, per-triangle drag,
//! and the payload's line tension, acceleration and axis angle. Reads the state, never
//! changes it; buffers are reused (no allocation per step).

use crate::build::Built;
use crate::metrics::landing::BodyState;
use crate::output::timeseries::{canopy_means, Sample};

/// Reusable observation buffers.
pub(super) struct Observer {
    pub pos: Vec<[f64; 3]>,
    pub vel: Vec<[f64; 3]>,
    masses: Vec<f64>,
    drag_blocks: Vec<engine::LocalBlocks>,
    pub tri_drag: Vec<[f64; 3]>,
    /// The rod families acting on the payload node (the suspension lines), by index in
    /// `model.forces`, with their buffers.
    line_forces: Vec<(usize, engine::LocalBlocks)>,
    /// The payload's velocity at the previous sample (its acceleration over the step).
    payload_v: Option<[f64; 3]>,
}

/// The rod families (`RodNetwork::install` names them `rod-…`) with a stencil entry on the
/// payload node: the suspension lines.
fn line_forces(b: &Built) -> Vec<(usize, engine::LocalBlocks)> {
    let Some(p) = b.payload_node else {
        return Vec::new();
    };
    b.model
        .forces
        .iter()
        .enumerate()
        .filter(|(_, f)| f.name().starts_with("rod-"))
        .filter(|(_, f)| {
            f.stencils()
                .iter()
                .any(|&d| d / 3 == p && d < 3 * b.model.layout.n_nodes)
        })
        .map(|(i, f)| (i, f.new_blocks()))
        .collect()
}

impl Observer {
    pub fn new(b: &Built) -> Self {
        let n = b.model.layout.n_nodes;
        Self {
            pos: vec![[0.0; 3]; n],
            vel: vec![[0.0; 3]; n],
            masses: (0..n).map(|i| b.model.node_mass(i)).collect(),
            drag_blocks: b
                .drag_forces
                .iter()
                .map(|&id| b.model.force(id).new_blocks())
                .collect(),
            tri_drag: vec![[0.0; 3]; b.triangles.len()],
            line_forces: line_forces(b),
            payload_v: None,
        }
    }

    /// The canopy's mean height and vertical velocity at `(q, v)` (m, m/s), as a time-series
    /// row records them (`z_m`, `vz_mps`).
    pub fn canopy_height(&mut self, b: &Built, q: &[f64], v: &[f64]) -> Option<(f64, f64)> {
        self.load(q, v);
        let m = canopy_means(&self.pos, &self.vel, &self.masses, &b.canopy_nodes)?;
        Some((m.z_m, m.v_mps[2]))
    }

    /// Start the payload's acceleration from state `s` (a fresh or resumed run).
    pub fn start(&mut self, b: &Built, s: &engine::State) {
        self.payload_v = b
            .payload_node
            .map(|p| [s.v[3 * p], s.v[3 * p + 1], s.v[3 * p + 2]]);
    }

    /// The resultant force of the suspension lines on the payload at `(q, v)` (N).
    fn line_force(&mut self, b: &Built, q: &[f64], v: &[f64], t: f64) -> [f64; 3] {
        let mut total = [0.0; 3];
        let Some(p) = b.payload_node else {
            return total;
        };
        let input = engine::EvalInput::outside_step(q, v, t, false);
        for (i, blocks) in &mut self.line_forces {
            let force = &b.model.forces[*i];
            force.evaluate(&input, blocks);
            for (&d, f) in force.stencils().iter().zip(&blocks.f) {
                if d / 3 == p && d < 3 * b.model.layout.n_nodes {
                    total[d % 3] += f;
                }
            }
        }
        total
    }

    /// The body whose height ends the run at the ground: the payload, or without one the
    /// lowest canopy node (of the state last loaded).
    pub fn ground_body(&self, b: &Built, t: f64) -> BodyState {
        let i = b.payload_node.unwrap_or_else(|| {
            *b.canopy_nodes
                .iter()
                .min_by(|&&i, &&j| self.pos[i][2].total_cmp(&self.pos[j][2]))
                .expect("a canopy node")
        });
        BodyState {
            t_s: t,
            x_m: self.pos[i],
            v_mps: self.vel[i],
        }
    }

    pub fn load(&mut self, q: &[f64], v: &[f64]) {
        for i in 0..self.pos.len() {
            self.pos[i] = [q[3 * i], q[3 * i + 1], q[3 * i + 2]];
            self.vel[i] = [v[3 * i], v[3 * i + 1], v[3 * i + 2]];
        }
    }

    /// Total drag (N) and, for the triangle family, per-triangle drag.
    pub fn drag(&mut self, b: &Built, q: &[f64], v: &[f64], t: f64) -> [f64; 3] {
        let n_pos = 3 * b.model.layout.n_nodes;
        let input = engine::EvalInput::outside_step(q, v, t, false);
        let mut total = [0.0; 3];
        for (k, &id) in b.drag_forces.iter().enumerate() {
            let force = b.model.force(id);
            let blocks = &mut self.drag_blocks[k];
            force.evaluate(&input, blocks);
            let st = force.stencils();
            for (d, f) in st.iter().zip(&blocks.f) {
                if *d < n_pos {
                    total[d % 3] += f;
                }
            }
            if Some(id) == b.triangle_drag {
                for (t, f) in self.tri_drag.iter_mut().zip(blocks.f.chunks(9)) {
                    *t = [f[0] + f[3] + f[6], f[1] + f[4] + f[7], f[2] + f[5] + f[8]];
                }
            }
        }
        total
    }

    pub fn sample(&mut self, b: &Built, s: &engine::State, iters: u32, dt: f64) -> Sample {
        self.load(&s.q, &s.v);
        let drag = self.drag(b, &s.q, &s.v, s.t);
        let m = canopy_means(&self.pos, &self.vel, &self.masses, &b.canopy_nodes)
            .expect("canopy has mass");
        let (zp, vzp) = match b.payload_node {
            Some(p) => (self.pos[p][2], self.vel[p][2]),
            None => (m.z_m, m.v_mps[2]),
        };
        let lines = self.line_force(b, &s.q, &s.v, s.t);
        let (mut accel, mut angle) = (0.0, 0.0);
        if let Some(p) = b.payload_node {
            let vp = self.vel[p];
            if let Some(prev) = self.payload_v.replace(vp) {
                accel = norm([0, 1, 2].map(|k| vp[k] - prev[k])) / dt;
            }
            let axis = [0, 1, 2].map(|k| m.centre_m[k] - self.pos[p][k]);
            angle = (axis[2] / norm(axis)).clamp(-1.0, 1.0).acos().to_degrees();
        }
        Sample {
            t_s: s.t,
            z_m: m.z_m,
            vz_mps: m.v_mps[2],
            vx_mps: m.v_mps[0],
            vy_mps: m.v_mps[1],
            z_payload_m: zp,
            vz_payload_mps: vzp,
            extended_height_m: m.extended_height_m,
            drag_x_n: drag[0],
            drag_y_n: drag[1],
            drag_z_n: drag[2],
            newton_iterations: iters,
            dt_s: dt,
            line_tension_n: norm(lines),
            payload_acceleration_mps2: accel,
            axis_angle_deg: angle,
            canopy_diameter_m: m.diameter_m,
        }
    }
}

fn norm(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

//! Observation of the state for the outputs: canopy means, total drag, per-triangle drag.
//! Reads the state, never changes it; buffers are reused (no allocation per step).

use crate::build::Built;
use crate::output::timeseries::{canopy_means, Sample};

/// Reusable observation buffers.
pub(super) struct Observer {
    pub pos: Vec<[f64; 3]>,
    pub vel: Vec<[f64; 3]>,
    masses: Vec<f64>,
    drag_blocks: Vec<engine::LocalBlocks>,
    pub tri_drag: Vec<[f64; 3]>,
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
        let input = engine::EvalInput {
            q,
            v,
            t,
            jacobian: false,
        };
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
        }
    }
}

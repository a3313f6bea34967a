//! Flat rectangular triangulated sheets with stiff edge springs: rigid bodies for the drag
//! references and test meshes for the drag laws.
use crate::rod::Stretch;
use crate::shell::mesh::twice_area;

/// A flat rectangular sheet in the plane z = `z0`, normals +z.
pub struct Sheet {
    /// Node positions (m), 3 per node.
    pub q: Vec<f64>,
    /// Triangles, counter-clockwise seen from +z.
    pub tris: Vec<[usize; 3]>,
    /// Unique triangle edges.
    pub edges: Vec<[usize; 2]>,
    /// Number of nodes.
    pub n_nodes: usize,
}

/// `nx × ny` nodes over `lx × ly` metres, each cell split into two triangles.
pub fn sheet(nx: usize, ny: usize, lx: f64, ly: f64, z0: f64) -> Sheet {
    let id = |i: usize, j: usize| j * nx + i;
    let mut q = Vec::with_capacity(3 * nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            let x = lx * i as f64 / (nx - 1) as f64;
            let y = ly * j as f64 / (ny - 1) as f64;
            q.extend_from_slice(&[x, y, z0]);
        }
    }
    let mut tris = Vec::new();
    for j in 0..ny - 1 {
        for i in 0..nx - 1 {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            tris.push([a, b, c]);
            tris.push([a, c, d]);
        }
    }
    let mut edges: Vec<[usize; 2]> = tris
        .iter()
        .flat_map(|t| [[t[0], t[1]], [t[1], t[2]], [t[2], t[0]]])
        .map(|[a, b]| [a.min(b), a.max(b)])
        .collect();
    edges.sort_unstable();
    edges.dedup();
    Sheet {
        q,
        tris,
        edges,
        n_nodes: nx * ny,
    }
}

/// A flat disc in the plane z = `z0`, normals +z: a centre node (0) and `n_rim` nodes on the
/// circle of `radius` (m), joined in a fan of triangles (a regular polygon: its area is
/// `½ n r² sin(2π/n)`, short of `π r²` by a relative `(2π/n)²/6`).
pub fn disc(n_rim: usize, radius: f64, z0: f64) -> Sheet {
    let mut q = vec![0.0, 0.0, z0];
    for k in 0..n_rim {
        let a = std::f64::consts::TAU * k as f64 / n_rim as f64;
        q.extend_from_slice(&[radius * a.cos(), radius * a.sin(), z0]);
    }
    let tris: Vec<[usize; 3]> = (0..n_rim)
        .map(|k| [0, 1 + k, 1 + (k + 1) % n_rim])
        .collect();
    let mut edges: Vec<[usize; 2]> = (0..n_rim)
        .flat_map(|k| [[0, 1 + k], [1 + k, 1 + (k + 1) % n_rim]])
        .map(|[a, b]| [a.min(b), a.max(b)])
        .collect();
    edges.sort_unstable();
    Sheet {
        q,
        tris,
        edges,
        n_nodes: n_rim + 1,
    }
}

impl Sheet {
    /// Area of triangle `t` (m²).
    pub fn tri_area(&self, t: usize) -> f64 {
        let p = |i: usize| {
            let n = self.tris[t][i];
            [self.q[3 * n], self.q[3 * n + 1], self.q[3 * n + 2]]
        };
        0.5 * twice_area(p(0), p(1), p(2))
    }

    /// Lumped node masses for a total mass `m` spread in proportion to area (A/3 per
    /// triangle corner), so that a uniform drag per area gives a uniform acceleration.
    pub fn lumped_masses(&self, m: f64) -> Vec<f64> {
        let total: f64 = (0..self.tris.len()).map(|t| self.tri_area(t)).sum();
        let mut masses = vec![0.0; self.n_nodes];
        for (t, tri) in self.tris.iter().enumerate() {
            for &i in tri {
                masses[i] += m * self.tri_area(t) / (3.0 * total);
            }
        }
        masses
    }

    /// Stiff springs (axial stiffness `k`, N) on every edge.
    pub fn springs(&self, k: f64) -> Stretch {
        Stretch::new("edges", &self.edges, &self.q, vec![k; self.edges.len()])
    }
}

/// A 3 × 3-node sheet (8 triangles, 1 m², 1 kg), tilted (z = x/2) and crumpled by
/// `±0.2 m · noise()`, with stiff edge springs (1e4 N) at rest in that shape and gravity,
/// thrown at (3, 3, −10) m/s plus `±3 m/s · noise()` per DOF. Drag added by the caller
/// (≈ ½ρC A v² ≈ 100 N) then dominates the weight (≈ 10 N): the drag-dominated Newton step
/// of the solver tests. `noise` returns values in [−1, 1].
pub fn thrown_crumpled_sheet(
    noise: &mut dyn FnMut() -> f64,
) -> (crate::Model, crate::State, Sheet) {
    let s = sheet(3, 3, 1.0, 1.0, 0.0);
    let q: Vec<f64> =
        s.q.chunks(3)
            .flat_map(|p| [p[0], p[1], 0.5 * p[0] + 0.2 * noise()])
            .collect();
    let mut model = crate::Model::new(crate::DofLayout::new(s.n_nodes, 0));
    let masses = s.lumped_masses(1.0);
    for (i, &m) in masses.iter().enumerate() {
        model.add_node_mass(i, m);
    }
    let nodes: Vec<usize> = (0..s.n_nodes).collect();
    model.add_force(crate::loads::Gravity::new(
        &nodes,
        &masses,
        [0.0, 0.0, -9.81],
    ));
    // Rest lengths from the crumpled shape: the step starts stress-free.
    model.add_force(Stretch::new(
        "edges",
        &s.edges,
        &q,
        vec![1e4; s.edges.len()],
    ));
    let mut state = crate::State::at_rest(q);
    for (d, v) in state.v.iter_mut().enumerate() {
        *v = if d % 3 == 2 { -10.0 } else { 3.0 } + 3.0 * noise();
    }
    (model, state, s)
}

/// A Kevlar sheet (E = 55 GPa, 2 mm, 1,440 kg/m³; the course report's canopy) of `lx × ly` m
/// on an `nx × ny` grid (springs + hinges), flat at rest, under gravity, the DisMech pressure
/// drag and a downward point force `corner_n` (N) on each corner: the stiff-membrane,
/// drag-dominated start of the report's flight, on which modified Newton gives up at large dt.
pub fn kevlar_sheet(
    nx: usize,
    ny: usize,
    lx: f64,
    ly: f64,
    corner_n: f64,
) -> (crate::Model, crate::State) {
    kevlar_sheet_with(nx, ny, lx, ly, corner_n, |s| {
        Box::new(crate::aero::PressureDrag::new(
            &s.tris,
            &s.q,
            1.75,
            &crate::aero::Fluid::air(),
        ))
    })
}

/// [`kevlar_sheet`] with the drag force `drag` makes from the sheet (e.g. none: an empty
/// `DofForces`).
pub fn kevlar_sheet_with(
    nx: usize,
    ny: usize,
    lx: f64,
    ly: f64,
    corner_n: f64,
    drag: impl Fn(&Sheet) -> Box<dyn crate::force::Force>,
) -> (crate::Model, crate::State) {
    use crate::prelude::*;
    let s = sheet(nx, ny, lx, ly, 0.0);
    let mesh = TriMesh::from_q(s.tris.clone(), &s.q, s.n_nodes).expect("a valid grid");
    let mut model = Model::new(DofLayout::new(s.n_nodes, 0));
    let mat = ShellMaterial {
        youngs_modulus: 55e9,
        thickness: 2e-3,
        density: 1440.0,
    };
    crate::shell::install(&mesh, &mat, &mut model, &s.q).expect("a valid material");
    let nodes: Vec<usize> = (0..s.n_nodes).collect();
    let masses: Vec<f64> = nodes.iter().map(|&i| model.mass[3 * i]).collect();
    model.add_force(Gravity::new(&nodes, &masses, [0.0, 0.0, -9.81]));
    model.forces.push(drag(&s));
    let corners = [0, nx - 1, nx * (ny - 1), nx * ny - 1];
    model.add_force(PointForces::new(&corners, &[[0.0, 0.0, -corner_n]; 4]));
    (model, State::at_rest(s.q))
}

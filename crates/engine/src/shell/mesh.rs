//! Triangle-mesh topology for discrete shells: unique edges, hinges (interior edges with
//! their two opposite vertices), boundary, vertex→face adjacency, and lumped areas.
//!
//! Node indices are global (the same as in the model's [`crate::DofLayout`]); nodes that no
//! face references (e.g. rod nodes) are allowed and simply get no area.

use std::collections::HashMap;
use thiserror::Error;

/// Why a triangle list is not a usable shell mesh. Face indices are 0-based.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum MeshError {
    /// A face references a node that does not exist.
    #[error("face {face} references node {node}, but there are only {n_nodes} nodes")]
    IndexOutOfRange {
        /// The face.
        face: usize,
        /// The node it references.
        node: usize,
        /// Nodes there are.
        n_nodes: usize,
    },
    /// A face repeats a vertex or has (numerically) zero area.
    #[error("face {face} {nodes:?} is degenerate ({reason})")]
    DegenerateFace {
        /// The face.
        face: usize,
        /// Its nodes.
        nodes: [usize; 3],
        /// "repeated vertex" or "zero area".
        reason: &'static str,
    },
    /// More than two faces share an edge.
    #[error("edge {edge:?} is shared by {count} faces (faces {faces:?}); a shell edge may have at most 2")]
    NonManifoldEdge {
        /// The edge (node pair).
        edge: [usize; 2],
        /// Faces sharing it.
        count: usize,
        /// Those faces.
        faces: Vec<usize>,
    },
    /// Two faces traverse their shared edge in the same direction.
    #[error("faces {faces:?} traverse edge {edge:?} in the same direction: orient all faces consistently")]
    InconsistentOrientation {
        /// The shared edge (node pair).
        edge: [usize; 2],
        /// The two faces.
        faces: [usize; 2],
    },
    /// A position is NaN or infinite.
    #[error("node {node} has a non-finite coordinate")]
    NonFinite {
        /// The node.
        node: usize,
    },
}

/// An interior edge and its two wings, ordered so that the faces `(edge[0], edge[1],
/// opposite[0])` and `(edge[1], edge[0], opposite[1])` are the two faces with their mesh
/// orientation. The signed dihedral angle of [`crate::shell::dihedral`] is then well defined.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Hinge {
    /// The shared edge, in the direction face A traverses it.
    pub edge: [usize; 2],
    /// Vertex of face A, then vertex of face B, opposite the edge.
    pub opposite: [usize; 2],
    /// Face indices `[A, B]`.
    pub faces: [usize; 2],
}

impl Hinge {
    /// The four nodes in stencil order `[x0, x1, x2, x3]`.
    pub fn nodes(&self) -> [usize; 4] {
        [
            self.edge[0],
            self.edge[1],
            self.opposite[0],
            self.opposite[1],
        ]
    }
}

/// A consistently oriented, edge-manifold triangle mesh with its derived topology.
#[derive(Debug, Clone)]
pub struct TriMesh {
    /// Number of nodes the indices refer to.
    pub n_nodes: usize,
    /// Faces, counter-clockwise about their normal.
    pub faces: Vec<[usize; 3]>,
    /// Unique undirected edges `[a, b]` with `a < b`, in order of first appearance.
    pub edges: Vec<[usize; 2]>,
    /// One hinge per interior edge.
    pub hinges: Vec<Hinge>,
    /// Boundary edges, directed as their single face traverses them.
    pub boundary_edges: Vec<[usize; 2]>,
    /// Nodes on a boundary edge, sorted ascending.
    pub boundary_nodes: Vec<usize>,
    /// Faces incident to each node (empty for nodes no face uses).
    pub vertex_faces: Vec<Vec<usize>>,
    /// Face areas (m²) at the positions given to [`TriMesh::new`].
    pub face_areas: Vec<f64>,
    /// Lumped vertex area `Σ A_f / 3` over incident faces (m²).
    pub vertex_areas: Vec<f64>,
}

/// Relative area below which a face counts as degenerate: `A ≤ tol · (longest edge)²`.
const ZERO_AREA_TOL: f64 = 1e-12;

/// Twice the area vector `(b − a) × (c − a)` of the triangle `a, b, c` (m²).
pub(crate) fn twice_area_vector(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> [f64; 3] {
    let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
    [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ]
}

/// Twice the area `|(b − a) × (c − a)|` of the triangle `a, b, c` (m²).
pub(crate) fn twice_area(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    let n = twice_area_vector(a, b, c);
    (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt()
}

/// Squared length of the longest edge of the triangle `a, b, c` (m²).
fn longest_edge2(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    let d2 = |x: [f64; 3], y: [f64; 3]| (0..3).map(|k| (x[k] - y[k]).powi(2)).sum::<f64>();
    d2(a, b).max(d2(b, c)).max(d2(c, a))
}

impl TriMesh {
    /// Build and check the topology of `faces` over `positions` (m).
    ///
    /// Errors: indices out of range, degenerate faces (repeated vertex, or area
    /// `≤ 1e-12 ·` longest edge²), non-finite positions, edges with more than two faces,
    /// and interior edges traversed twice in the same direction.
    pub fn new(faces: Vec<[usize; 3]>, positions: &[[f64; 3]]) -> Result<Self, MeshError> {
        let n_nodes = positions.len();
        if let Some(node) = positions
            .iter()
            .position(|p| p.iter().any(|c| !c.is_finite()))
        {
            return Err(MeshError::NonFinite { node });
        }
        let mut face_areas = Vec::with_capacity(faces.len());
        for (fi, &f) in faces.iter().enumerate() {
            if let Some(&node) = f.iter().find(|&&i| i >= n_nodes) {
                return Err(MeshError::IndexOutOfRange {
                    face: fi,
                    node,
                    n_nodes,
                });
            }
            if f[0] == f[1] || f[1] == f[2] || f[0] == f[2] {
                return Err(MeshError::DegenerateFace {
                    face: fi,
                    nodes: f,
                    reason: "repeated vertex",
                });
            }
            let [a, b, c] = f.map(|i| positions[i]);
            let twice_area = twice_area(a, b, c);
            if twice_area <= 2.0 * ZERO_AREA_TOL * longest_edge2(a, b, c) {
                return Err(MeshError::DegenerateFace {
                    face: fi,
                    nodes: f,
                    reason: "zero area",
                });
            }
            face_areas.push(0.5 * twice_area);
        }
        let mut mesh = Self {
            n_nodes,
            faces,
            edges: Vec::new(),
            hinges: Vec::new(),
            boundary_edges: Vec::new(),
            boundary_nodes: Vec::new(),
            vertex_faces: vec![Vec::new(); n_nodes],
            face_areas,
            vertex_areas: vec![0.0; n_nodes],
        };
        mesh.build_topology()?;
        Ok(mesh)
    }

    /// Edges, hinges, boundary and adjacency from the (already range-checked) faces.
    fn build_topology(&mut self) -> Result<(), MeshError> {
        // Undirected edge → list of (face, directed edge, opposite vertex).
        let mut index: HashMap<[usize; 2], usize> = HashMap::new();
        let mut uses: Vec<Vec<(usize, [usize; 2], usize)>> = Vec::new();
        for (fi, f) in self.faces.iter().enumerate() {
            for k in 0..3 {
                let (a, b, c) = (f[k], f[(k + 1) % 3], f[(k + 2) % 3]);
                let key = [a.min(b), a.max(b)];
                let e = *index.entry(key).or_insert_with(|| {
                    self.edges.push(key);
                    uses.push(Vec::new());
                    uses.len() - 1
                });
                uses[e].push((fi, [a, b], c));
                self.vertex_faces[a].push(fi);
                self.vertex_areas[a] += self.face_areas[fi] / 3.0;
            }
        }
        let mut on_boundary = vec![false; self.n_nodes];
        for (e, u) in uses.iter().enumerate() {
            match u.as_slice() {
                [(_, dir, _)] => {
                    self.boundary_edges.push(*dir);
                    on_boundary[dir[0]] = true;
                    on_boundary[dir[1]] = true;
                }
                [(fa, da, oa), (fb, db, ob)] => {
                    if da == db {
                        return Err(MeshError::InconsistentOrientation {
                            edge: *da,
                            faces: [*fa, *fb],
                        });
                    }
                    self.hinges.push(Hinge {
                        edge: *da,
                        opposite: [*oa, *ob],
                        faces: [*fa, *fb],
                    });
                }
                _ => {
                    return Err(MeshError::NonManifoldEdge {
                        edge: self.edges[e],
                        count: u.len(),
                        faces: u.iter().map(|x| x.0).collect(),
                    })
                }
            }
        }
        self.boundary_nodes = (0..self.n_nodes).filter(|&i| on_boundary[i]).collect();
        Ok(())
    }

    /// Build from a flat coordinate vector `q` (its first `3 n_nodes` entries).
    pub fn from_q(faces: Vec<[usize; 3]>, q: &[f64], n_nodes: usize) -> Result<Self, MeshError> {
        let p: Vec<[f64; 3]> = (0..n_nodes)
            .map(|i| [q[3 * i], q[3 * i + 1], q[3 * i + 2]])
            .collect();
        Self::new(faces, &p)
    }

    /// Total area (m²).
    pub fn area(&self) -> f64 {
        self.face_areas.iter().sum()
    }

    /// Nodes used by at least one face, ascending.
    pub fn shell_nodes(&self) -> Vec<usize> {
        (0..self.n_nodes)
            .filter(|&i| !self.vertex_faces[i].is_empty())
            .collect()
    }
}

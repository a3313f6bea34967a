//! Canopy meshes: generators (rectangle, hexagon, circle), importers (DisMech text, Wavefront
//! OBJ) and the [`CanopyMesh`] they all produce.
//!
//! A canopy mesh holds node positions shared by the shell triangles and the rod edges
//! (suspension lines): a rod whose end node is a shell node is joined to the canopy there.
//! [`CanopyMesh::rod_chains`] splits the rod-edge graph into the individual rods.

pub mod constructed;
pub mod dismech;
pub mod generate;
pub mod obj;
pub mod unstructured;
mod validate;

pub use validate::MAX_COORDINATE_M;

use engine::shell::{MeshError, TriMesh};
use std::collections::BTreeMap;
use thiserror::Error;

/// Read an imported canopy mesh: Wavefront OBJ by its `.obj` extension, else the DisMech
/// text format.
pub fn read_file(path: &std::path::Path) -> Result<CanopyMesh, MeshFileError> {
    read_file_digested(path).map(|(mesh, _)| mesh)
}

/// [`read_file`], and the digest ([`crate::study::inputs::bytes_digest`]) of the very bytes
/// parsed: the run records that one, so that a file rewritten after it was read cannot be
/// recorded as the run's input.
pub fn read_file_digested(path: &std::path::Path) -> Result<(CanopyMesh, String), MeshFileError> {
    let is_obj = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("obj"));
    read_with(path, if is_obj { obj::parse } else { dismech::parse })
}

/// A canopy: positions (m), shell triangles, rod edges and named node sets.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct CanopyMesh {
    /// Node positions (m).
    pub positions: Vec<[f64; 3]>,
    /// Shell triangles (0-based node indices, counter-clockwise about the normal).
    pub faces: Vec<[usize; 3]>,
    /// Rod edges (0-based node pairs), e.g. suspension lines.
    pub rod_edges: Vec<[usize; 2]>,
    /// Named node sets: generators provide "center", "rim" (boundary loop, counter-
    /// clockwise seen from +z) and shape-specific sets ("corners", "long_edge_midpoints");
    /// importers derive "shell", "rim", "center", "corners" and "rod".
    pub node_sets: BTreeMap<String, Vec<usize>>,
}

/// Why a mesh file could not be read. `Display` is `path:line: message` when the problem
/// is on a line.
#[derive(Debug, Error)]
pub enum MeshFileError {
    /// The file could not be read.
    #[error("{path}: cannot read file: {source}")]
    Io {
        /// File path.
        path: String,
        /// Underlying error.
        #[source]
        source: std::io::Error,
    },
    /// A problem on one line (1-based).
    #[error("{path}:{line}: {message}")]
    Line {
        /// File path.
        path: String,
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// A problem with the file as a whole (e.g. no triangles).
    #[error("{path}: {message}")]
    File {
        /// File path.
        path: String,
        /// What is wrong.
        message: String,
    },
}

/// Largest mesh file read (bytes): a mesh within the model's limits
/// ([`crate::scenario::limits::MAX_SHELL_TRIANGLES`]) is a few tens of MB of text; a larger
/// file is refused before it is read into memory.
pub const MAX_MESH_BYTES: u64 = 1 << 28;

/// Why a mesh file of `len` bytes is not read ([`MAX_MESH_BYTES`]).
pub fn too_large(len: u64) -> Option<String> {
    (len > MAX_MESH_BYTES).then(|| {
        format!(
            "the file is {:.0} MiB; a mesh file is at most {} MiB (a canopy of the most triangles allowed is far less)",
            len as f64 / (1u64 << 20) as f64,
            MAX_MESH_BYTES >> 20
        )
    })
}

/// The bytes of a file of at most `max` bytes, counted as they are read (a file whose size
/// reads 0 but is unbounded, such as a link to `/proc/self/pagemap`, is stopped there too);
/// `Err(Some(len))` when it is longer (`len` as far as read or as the metadata say).
pub fn read_capped(path: &std::path::Path, max: u64) -> Result<Vec<u8>, ReadCapped> {
    use std::io::Read;
    if let Some(len) = std::fs::metadata(path)
        .ok()
        .map(|m| m.len())
        .filter(|&l| l > max)
    {
        return Err(ReadCapped::TooLong(len));
    }
    let mut bytes = Vec::new();
    std::fs::File::open(path)
        .and_then(|f| f.take(max + 1).read_to_end(&mut bytes))
        .map_err(ReadCapped::Io)?;
    if bytes.len() as u64 > max {
        return Err(ReadCapped::TooLong(bytes.len() as u64));
    }
    Ok(bytes)
}

/// Why [`read_capped`] read nothing.
#[derive(Debug)]
pub enum ReadCapped {
    /// Longer than the cap (bytes, at least).
    TooLong(u64),
    /// Reading failed.
    Io(std::io::Error),
}

/// Read `path` (lossy UTF-8, at most [`MAX_MESH_BYTES`]) and hand its text and display name
/// to `parse`; with the digest of the bytes read.
fn read_with(
    path: &std::path::Path,
    parse: fn(&str, &str) -> Result<CanopyMesh, MeshFileError>,
) -> Result<(CanopyMesh, String), MeshFileError> {
    let name = path.display().to_string();
    let bytes = read_capped(path, MAX_MESH_BYTES).map_err(|e| match e {
        ReadCapped::TooLong(len) => MeshFileError::File {
            path: name.clone(),
            message: too_large(len).unwrap_or_default(),
        },
        ReadCapped::Io(source) => MeshFileError::Io {
            path: name.clone(),
            source,
        },
    })?;
    let mesh = parse(&String::from_utf8_lossy(&bytes), &name)?;
    Ok((mesh, crate::study::inputs::bytes_digest(&bytes)))
}

impl CanopyMesh {
    /// The rod edges' total length (m) and each node's lumped share of it (half of every
    /// edge it ends), as the rods' masses are lumped.
    pub fn lumped_lengths(&self) -> (f64, Vec<f64>) {
        let mut share = vec![0.0; self.positions.len()];
        let mut total = 0.0;
        for &[a, b] in &self.rod_edges {
            let d = sub(self.positions[b], self.positions[a]);
            let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            total += l;
            share[a] += 0.5 * l;
            share[b] += 0.5 * l;
        }
        (total, share)
    }

    /// The triangles' total area (m²) and each node's lumped share of it (a third of every
    /// triangle it is a corner of), as the shell's masses are lumped.
    pub fn lumped_areas(&self) -> (f64, Vec<f64>) {
        let mut share = vec![0.0; self.positions.len()];
        let mut total = 0.0;
        for f in &self.faces {
            let [a, b, c] = f.map(|i| self.positions[i]);
            let (u, v) = (sub(b, a), sub(c, a));
            let n = [
                u[1] * v[2] - u[2] * v[1],
                u[2] * v[0] - u[0] * v[2],
                u[0] * v[1] - u[1] * v[0],
            ];
            let area = 0.5 * (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
            total += area;
            for &i in f {
                share[i] += area / 3.0;
            }
        }
        (total, share)
    }

    /// Number of nodes.
    pub fn n_nodes(&self) -> usize {
        self.positions.len()
    }

    /// Flat coordinate vector `[x0 y0 z0 x1 …]` (m).
    pub fn q(&self) -> Vec<f64> {
        self.positions.iter().flatten().copied().collect()
    }

    /// The engine's shell topology over all nodes (rod-only nodes get no area).
    pub fn tri_mesh(&self) -> Result<TriMesh, MeshError> {
        TriMesh::new(self.faces.clone(), &self.positions)
    }

    /// Nodes used by at least one triangle, ascending.
    pub fn shell_nodes(&self) -> Vec<usize> {
        let mask = self.shell_mask();
        (0..self.n_nodes()).filter(|&i| mask[i]).collect()
    }

    /// A named node set, if present.
    pub fn node_set(&self, name: &str) -> Option<&[usize]> {
        self.node_sets.get(name).map(Vec::as_slice)
    }

    fn shell_mask(&self) -> Vec<bool> {
        let mut m = vec![false; self.n_nodes()];
        for f in &self.faces {
            for &i in f {
                if let Some(x) = m.get_mut(i) {
                    *x = true;
                }
            }
        }
        m
    }

    /// Split the rod-edge graph into maximal chains (node lists) whose interior nodes have
    /// rod degree 2 and are not shell nodes; chains end at nodes of degree ≠ 2 (junctions,
    /// free ends) or at shell nodes (rod–shell joints). Closed loops without such a node
    /// come out as chains whose first and last node coincide. Chains start at their
    /// lowest-index end node, in edge input order, so the result is deterministic.
    pub fn rod_chains(&self) -> Vec<Vec<usize>> {
        let n = self.n_nodes();
        let mut adj: Vec<Vec<(usize, usize)>> = vec![Vec::new(); n];
        for (e, &[a, b]) in self.rod_edges.iter().enumerate() {
            if a < n && b < n {
                adj[a].push((e, b));
                adj[b].push((e, a));
            }
        }
        let shell = self.shell_mask();
        let is_end = |v: usize| adj[v].len() != 2 || shell[v];
        let mut used = vec![false; self.rod_edges.len()];
        let mut chains = Vec::new();
        let walk = |start: usize, e0: usize, next: usize, used: &mut Vec<bool>| {
            used[e0] = true;
            let (mut chain, mut cur, mut prev) = (vec![start, next], next, e0);
            while !is_end(cur) && cur != start {
                let Some(&(e, w)) = adj[cur].iter().find(|&&(e, _)| e != prev && !used[e]) else {
                    break;
                };
                used[e] = true;
                chain.push(w);
                (cur, prev) = (w, e);
            }
            chain
        };
        for v in (0..n).filter(|&v| is_end(v)) {
            for &(e, w) in &adj[v] {
                if !used[e] {
                    chains.push(walk(v, e, w, &mut used));
                }
            }
        }
        for (e, &[a, b]) in self.rod_edges.iter().enumerate() {
            if !used[e] && a < n && b < n {
                chains.push(walk(a, e, b, &mut used));
            }
        }
        chains
    }
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

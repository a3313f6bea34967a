//! Checks shared by the importers, with every error tied to its file line, and the node
//! sets derived for imported meshes.

use super::{CanopyMesh, MeshFileError};
use crate::scenario::limits::{MAX_LINE_NODES, MAX_SHELL_TRIANGLES};
use engine::shell::{MeshError, TriMesh};
use std::collections::{BTreeMap, HashMap};

/// Parsed records with the 1-based line each came from. Indices are 0-based but not yet
/// range-checked.
#[derive(Debug, Default)]
pub(crate) struct RawMesh {
    pub path: String,
    pub positions: Vec<[f64; 3]>,
    pub position_lines: Vec<usize>,
    pub faces: Vec<[usize; 3]>,
    pub face_lines: Vec<usize>,
    pub rods: Vec<[usize; 2]>,
    pub rod_lines: Vec<usize>,
}

/// Largest coordinate of a mesh node (m). Meshes are in metres and no parachute spans a
/// kilometre: a larger coordinate is a unit mistake or a stray node, refused at its line
/// instead of surfacing later as an implausible mass or terminal speed.
pub const MAX_COORDINATE_M: f64 = 1e3;

/// Most rod edges that may end at one node: the rods' joint there couples every pair of
/// them, so its work grows with the square of the count.
pub const MAX_ROD_DEGREE: usize = 1024;

/// Relative area below which a triangle is degenerate (as in the engine's `TriMesh`).
const ZERO_AREA_TOL: f64 = 1e-12;

impl RawMesh {
    pub fn new(path: &str) -> Self {
        Self {
            path: path.to_string(),
            ..Default::default()
        }
    }

    pub fn line_error(&self, line: usize, message: impl Into<String>) -> MeshFileError {
        MeshFileError::Line {
            path: self.path.clone(),
            line,
            message: message.into(),
        }
    }

    /// Parse `tok` as a finite coordinate (m).
    pub fn coordinate(&self, tok: &str, line: usize) -> Result<f64, MeshFileError> {
        let x: f64 = tok
            .parse()
            .map_err(|_| self.line_error(line, format!("bad number `{tok}`")))?;
        if !x.is_finite() {
            return Err(self.line_error(line, format!("non-finite coordinate `{tok}`")));
        }
        if x.abs() > MAX_COORDINATE_M {
            return Err(self.line_error(
                line,
                format!(
                    "coordinate `{tok}` m is beyond ±{MAX_COORDINATE_M} m: meshes are in metres \
                     (a unit mistake or a stray node?)"
                ),
            ));
        }
        Ok(x)
    }

    /// Refuse the record at `line` when the file already has `count` of `what`, the most
    /// the generators allow ([`MAX_SHELL_TRIANGLES`], [`MAX_LINE_NODES`]: memory and
    /// time): counted as the file is read, so that a long file stops there instead of
    /// filling memory first.
    fn room(&self, count: usize, what: &str, max: f64, line: usize) -> Result<(), MeshFileError> {
        match count as f64 >= max {
            true => Err(self.line_error(
                line,
                format!("more than {max:.0} {what}: a canopy may have at most {max:.0} (memory and time)"),
            )),
            false => Ok(()),
        }
    }

    /// Add node `p` from `line` (refused past the node limit).
    pub fn push_node(&mut self, p: [f64; 3], line: usize) -> Result<(), MeshFileError> {
        self.room(self.positions.len(), "nodes", MAX_SHELL_TRIANGLES, line)?;
        self.positions.push(p);
        self.position_lines.push(line);
        Ok(())
    }

    /// Add triangle `t` from `line` (refused past the triangle limit).
    pub fn push_face(&mut self, t: [usize; 3], line: usize) -> Result<(), MeshFileError> {
        self.room(self.faces.len(), "triangles", MAX_SHELL_TRIANGLES, line)?;
        self.faces.push(t);
        self.face_lines.push(line);
        Ok(())
    }

    /// Add rod edge `r` from `line` (refused past the line-node limit).
    pub fn push_rod(&mut self, r: [usize; 2], line: usize) -> Result<(), MeshFileError> {
        self.room(self.rods.len(), "rod edges", MAX_LINE_NODES, line)?;
        self.rods.push(r);
        self.rod_lines.push(line);
        Ok(())
    }

    /// Check everything and build the canopy mesh with derived node sets.
    pub fn finish(self) -> Result<CanopyMesh, MeshFileError> {
        self.check_duplicates()?;
        let n = self.positions.len();
        let range = |i: usize, line: usize| {
            if i < n {
                Ok(())
            } else {
                Err(self.line_error(
                    line,
                    format!("node index {} out of range (file has {n} nodes)", i + 1),
                ))
            }
        };
        let mut seen: BTreeMap<[usize; 3], usize> = BTreeMap::new();
        for (f, &line) in self.faces.iter().zip(&self.face_lines) {
            f.iter().try_for_each(|&i| range(i, line))?;
            self.check_triangle(*f, line)?;
            let mut key = *f;
            key.sort_unstable();
            if let Some(first) = seen.insert(key, line) {
                return Err(self.line_error(
                    line,
                    format!(
                        "duplicate triangle {} {} {}: line {first} has the same three nodes; remove one of them",
                        f[0] + 1,
                        f[1] + 1,
                        f[2] + 1
                    ),
                ));
            }
        }
        let mut rods: HashMap<[usize; 2], usize> = HashMap::new();
        let mut degree: HashMap<usize, usize> = HashMap::new();
        for (r, &line) in self.rods.iter().zip(&self.rod_lines) {
            r.iter().try_for_each(|&i| range(i, line))?;
            if r[0] == r[1] {
                return Err(
                    self.line_error(line, format!("rod edge joins node {} to itself", r[0] + 1))
                );
            }
            if let Some(first) = rods.insert([r[0].min(r[1]), r[0].max(r[1])], line) {
                return Err(self.line_error(
                    line,
                    format!(
                        "duplicate rod edge {} {}: line {first} joins the same two nodes; remove one of them",
                        r[0] + 1,
                        r[1] + 1
                    ),
                ));
            }
            for i in r {
                let d = degree.entry(*i).or_default();
                *d += 1;
                if *d > MAX_ROD_DEGREE {
                    return Err(self.line_error(line, format!(
                        "node {} is the end of more than {MAX_ROD_DEGREE} rod edges: a joint couples every pair of its rods (a confluence point of the most lines fielded has a few hundred)",
                        i + 1
                    )));
                }
            }
        }
        if self.faces.is_empty() {
            return Err(MeshFileError::File {
                path: self.path.clone(),
                message: "no triangles found".into(),
            });
        }
        self.check_all_used()?;
        let tri = TriMesh::new(self.faces.clone(), &self.positions)
            .map_err(|e| self.topology_error(e))?;
        let mut mesh = CanopyMesh {
            positions: self.positions,
            faces: self.faces,
            rod_edges: self.rods,
            node_sets: BTreeMap::new(),
        };
        mesh.node_sets = derived_node_sets(&mesh, &tri);
        Ok(mesh)
    }

    fn check_duplicates(&self) -> Result<(), MeshFileError> {
        // Exact coordinate match; −0.0 and 0.0 are the same point.
        let key = |p: &[f64; 3]| p.map(|x| (x + 0.0).to_bits());
        let mut seen: HashMap<[u64; 3], usize> = HashMap::new();
        for (i, p) in self.positions.iter().enumerate() {
            if let Some(&j) = seen.get(&key(p)) {
                return Err(self.line_error(
                    self.position_lines[i],
                    format!(
                        "node {} duplicates node {} (line {}) at ({}, {}, {})",
                        i + 1,
                        j + 1,
                        self.position_lines[j],
                        p[0],
                        p[1],
                        p[2]
                    ),
                ));
            }
            seen.insert(key(p), i);
        }
        Ok(())
    }

    /// Every node must be on a triangle or a rod edge: an unused one would have no mass (a
    /// file cut short before its `*Edges`, or a stray vertex).
    fn check_all_used(&self) -> Result<(), MeshFileError> {
        let mut used = vec![false; self.positions.len()];
        for &i in self
            .faces
            .iter()
            .flatten()
            .chain(self.rods.iter().flatten())
        {
            used[i] = true;
        }
        let Some(i) = used.iter().position(|u| !u) else {
            return Ok(());
        };
        let unused = used.iter().filter(|u| !**u).count();
        let others = match unused {
            1 => String::new(),
            n => format!(" ({} more unused nodes follow)", n - 1),
        };
        Err(self.line_error(
            self.position_lines[i],
            format!(
                "node {} is on no triangle and no rod edge, so it would have no mass{others}; \
                 remove it, or check that the file is complete (a DisMech file needs its *Edges)",
                i + 1
            ),
        ))
    }

    fn check_triangle(&self, f: [usize; 3], line: usize) -> Result<(), MeshFileError> {
        let [a, b, c] = f;
        if a == b || b == c || a == c {
            return Err(self.line_error(
                line,
                format!(
                    "degenerate triangle {} {} {}: repeated node",
                    a + 1,
                    b + 1,
                    c + 1
                ),
            ));
        }
        let [pa, pb, pc] = f.map(|i| self.positions[i]);
        let d = |p: [f64; 3], q: [f64; 3]| [q[0] - p[0], q[1] - p[1], q[2] - p[2]];
        let (u, v) = (d(pa, pb), d(pa, pc));
        let n = [
            u[1] * v[2] - u[2] * v[1],
            u[2] * v[0] - u[0] * v[2],
            u[0] * v[1] - u[1] * v[0],
        ];
        let sq = |w: [f64; 3]| w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
        let longest = sq(u).max(sq(v)).max(sq(d(pb, pc)));
        if sq(n).sqrt() <= 2.0 * ZERO_AREA_TOL * longest {
            return Err(self.line_error(
                line,
                format!(
                    "degenerate triangle {} {} {}: zero area",
                    a + 1,
                    b + 1,
                    c + 1
                ),
            ));
        }
        Ok(())
    }

    /// Attach the line of the offending face to a topology error.
    fn topology_error(&self, e: MeshError) -> MeshFileError {
        let face = match &e {
            MeshError::NonManifoldEdge { faces, .. } => faces.last().copied(),
            MeshError::InconsistentOrientation { faces, .. } => Some(faces[1]),
            MeshError::IndexOutOfRange { face, .. } | MeshError::DegenerateFace { face, .. } => {
                Some(*face)
            }
            MeshError::NonFinite { .. } => None,
        };
        // Engine messages use 0-based indices; restate the edge 1-based for the file.
        let message = match &e {
            MeshError::NonManifoldEdge { edge, count, .. } => format!(
                "non-manifold triangle: with it, edge {}–{} is shared by {count} triangles, and a surface has at most 2 on an edge",
                edge[0] + 1,
                edge[1] + 1
            ),
            MeshError::InconsistentOrientation { edge, .. } => format!(
                "triangle traverses edge {}→{} in the same direction as a neighbour: \
                 orient all triangles consistently",
                edge[0] + 1,
                edge[1] + 1
            ),
            other => other.to_string(),
        };
        match face {
            Some(f) => self.line_error(self.face_lines[f], message),
            None => MeshFileError::File {
                path: self.path.clone(),
                message,
            },
        }
    }
}

/// Boundary loops of a consistently oriented mesh, each following its faces' orientation.
/// Pinched boundaries (a node on several loops) are split greedily.
pub(crate) fn boundary_loops(tri: &TriMesh) -> Vec<Vec<usize>> {
    let mut next: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
    for &[a, b] in &tri.boundary_edges {
        next.entry(a).or_default().push(b);
    }
    let mut loops = Vec::new();
    while let Some((&start, _)) = next.iter().find(|(_, v)| !v.is_empty()) {
        let mut lp = vec![start];
        let mut cur = start;
        while let Some(nx) = next.get_mut(&cur).and_then(|v| v.pop()) {
            if nx == start {
                break;
            }
            lp.push(nx);
            cur = nx;
        }
        loops.push(lp);
    }
    loops
}

/// Rim nodes where the boundary turns by more than 30°.
pub(crate) fn corners(positions: &[[f64; 3]], rim: &[usize]) -> Vec<usize> {
    let m = rim.len();
    let sub = |a: [f64; 3], b: [f64; 3]| [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let norm = |v: [f64; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    (0..m)
        .filter(|&k| {
            let (p, c, n) = (rim[(k + m - 1) % m], rim[k], rim[(k + 1) % m]);
            let (u, v) = (
                sub(positions[p], positions[c]),
                sub(positions[c], positions[n]),
            );
            let cos = (u[0] * v[0] + u[1] * v[1] + u[2] * v[2]) / (norm(u) * norm(v));
            cos < 30f64.to_radians().cos()
        })
        .map(|k| rim[k])
        .collect()
}

/// "shell", "rim" (longest boundary loop), "center" (shell node nearest the shell nodes'
/// centroid), "corners" (rim turns > 30°) and "rod" (nodes only on rod edges).
fn derived_node_sets(mesh: &CanopyMesh, tri: &TriMesh) -> BTreeMap<String, Vec<usize>> {
    let shell = tri.shell_nodes();
    let rim = boundary_loops(tri)
        .into_iter()
        .max_by_key(Vec::len)
        .unwrap_or_default();
    let p = &mesh.positions;
    let mut c = [0.0; 3];
    for &i in &shell {
        for k in 0..3 {
            c[k] += p[i][k] / shell.len() as f64;
        }
    }
    let d2 = |i: usize| (0..3).map(|k| (p[i][k] - c[k]).powi(2)).sum::<f64>();
    let center = shell
        .iter()
        .copied()
        .min_by(|&a, &b| d2(a).total_cmp(&d2(b)));
    let mut rod: Vec<usize> = mesh
        .rod_edges
        .iter()
        .flatten()
        .copied()
        .filter(|&i| tri.vertex_faces[i].is_empty())
        .collect();
    rod.sort_unstable();
    rod.dedup();
    let mut sets = BTreeMap::new();
    sets.insert("corners".into(), corners(p, &rim));
    sets.insert("center".into(), center.into_iter().collect());
    sets.insert("rim".into(), rim);
    sets.insert("shell".into(), shell);
    sets.insert("rod".into(), rod);
    sets
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An imported mesh with more triangles, rod edges or nodes than the generators' limits
    /// allow is refused at the record past the limit, as the file is read.
    #[test]
    fn meshes_beyond_the_model_limits_are_refused_as_read() {
        let mut raw = RawMesh::new("m.txt");
        let full = |n: f64| n as usize;
        (raw.faces, raw.face_lines) = (vec![[0, 1, 2]; full(MAX_SHELL_TRIANGLES)], vec![4; 1]);
        (raw.rods, raw.rod_lines) = (vec![[0, 1]; full(MAX_LINE_NODES)], vec![4; 1]);
        raw.positions = vec![[0.0; 3]; full(MAX_SHELL_TRIANGLES)];
        let refused = |e: MeshFileError, what: &str, max: f64| {
            let want = format!("m.txt:7: more than {max:.0} {what}: a canopy may have at most");
            assert!(e.to_string().contains(&want), "{e}");
        };
        refused(
            raw.push_face([0, 1, 2], 7).unwrap_err(),
            "triangles",
            MAX_SHELL_TRIANGLES,
        );
        refused(
            raw.push_rod([0, 1], 7).unwrap_err(),
            "rod edges",
            MAX_LINE_NODES,
        );
        refused(
            raw.push_node([0.0; 3], 7).unwrap_err(),
            "nodes",
            MAX_SHELL_TRIANGLES,
        );
        // One fewer is taken.
        raw.faces.pop();
        raw.push_face([0, 1, 2], 7).unwrap();
    }

    /// A rod edge given twice (either way round), or more rods at one node than a joint
    /// takes, is refused at its line.
    #[test]
    fn duplicate_rod_edges_and_overloaded_joints_are_refused() {
        let refused = |rods: Vec<[usize; 2]>, want: &str| {
            let mut raw = RawMesh::new("m.txt");
            let n = rods.iter().flatten().max().unwrap() + 1;
            raw.positions = (0..n.max(3))
                .map(|i| [i as f64, (i * i) as f64, 0.0])
                .collect();
            raw.position_lines = (1..=n.max(3)).collect();
            (raw.faces, raw.face_lines) = (vec![[0, 1, 2]], vec![n + 2]);
            raw.rod_lines = (0..rods.len()).map(|k| n + 4 + k).collect();
            raw.rods = rods;
            let e = raw.finish().unwrap_err().to_string();
            assert!(e.contains(want), "want `{want}` in: {e}");
        };
        refused(vec![[0, 3], [3, 4], [3, 0]], "duplicate rod edge 4 1: line");
        let star: Vec<[usize; 2]> = (3..3 + MAX_ROD_DEGREE + 1).map(|i| [0, i]).collect();
        refused(star, "node 1 is the end of more than 1024 rod edges");
    }
}

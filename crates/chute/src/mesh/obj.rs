//! Wavefront OBJ meshes: `v x y z [w]` vertices (m; `w` ignored) and `f a b c …` faces.
//!
//! Face entries may be `a`, `a/t`, `a//n` or `a/t/n` (only the vertex index `a` is used);
//! indices are 1-based, or negative to count back from the last vertex defined so far.
//! Polygons are fan-triangulated from their first vertex. All other records (`vt`, `vn`,
//! `o`, `g`, `s`, `usemtl`, `mtllib`, `l`, …) are ignored, and so are `#` comments. OBJ
//! files carry no rod edges.

use super::validate::RawMesh;
use super::{CanopyMesh, MeshFileError};
use std::path::Path;

/// Read an OBJ file. Errors name the file and line.
pub fn read(path: impl AsRef<Path>) -> Result<CanopyMesh, MeshFileError> {
    super::read_with(path.as_ref(), parse).map(|(mesh, _)| mesh)
}

/// Parse OBJ text; `path` is only used in error messages.
pub fn parse(text: &str, path: &str) -> Result<CanopyMesh, MeshFileError> {
    let mut raw = RawMesh::new(path);
    for (k, full) in text.lines().enumerate() {
        let line = k + 1;
        let content = full.split('#').next().unwrap_or("");
        let mut tokens = content.split_whitespace();
        match tokens.next() {
            Some("v") => {
                let c: Vec<&str> = tokens.collect();
                if !(c.len() == 3 || c.len() == 4) {
                    return Err(raw.line_error(
                        line,
                        format!("expected 3 vertex coordinates, found {}", c.len()),
                    ));
                }
                let mut p = [0.0; 3];
                for (d, s) in p.iter_mut().zip(&c) {
                    *d = raw.coordinate(s, line)?;
                }
                raw.push_node(p, line)?;
            }
            Some("f") => {
                let mut poly = Vec::new();
                for tok in tokens {
                    poly.push(vertex_index(&raw, tok, line)?);
                }
                if poly.len() < 3 {
                    return Err(raw.line_error(
                        line,
                        format!("a face needs at least 3 vertices, found {}", poly.len()),
                    ));
                }
                for i in 1..poly.len() - 1 {
                    raw.push_face([poly[0], poly[i], poly[i + 1]], line)?;
                }
            }
            _ => {}
        }
    }
    raw.finish()
}

/// The 0-based vertex index of a face entry `a[/t[/n]]`.
fn vertex_index(raw: &RawMesh, tok: &str, line: usize) -> Result<usize, MeshFileError> {
    let v = tok.split('/').next().unwrap_or("");
    let i: i64 = v
        .parse()
        .map_err(|_| raw.line_error(line, format!("bad vertex index `{tok}`")))?;
    let count = raw.positions.len() as i64;
    let resolved = match i {
        0 => return Err(raw.line_error(line, "vertex index 0: indices are 1-based")),
        i if i > 0 => i - 1,
        i => count + i,
    };
    if resolved < 0 {
        return Err(raw.line_error(
            line,
            format!(
                "relative vertex index {i} points before the first vertex ({count} defined so far)"
            ),
        ));
    }
    usize::try_from(resolved).map_err(|_| raw.line_error(line, format!("bad vertex index `{tok}`")))
}

//! DisMech text meshes (StructuresComp DisMech, e.g. `hexparachute_n6_python.txt`).
//!
//! Format: sections introduced by case-insensitive headers `*Nodes` (one node per line:
//! `x, y, z` in m), `*Triangles` (three 1-based node indices: shell faces) and `*Edges`
//! (two 1-based node indices: rod edges). Fields are separated by commas and/or spaces.
//! `#` starts a comment (whole line or trailing). Shell edges and hinges derive from the
//! triangles. Any other `*` header is an error.

use super::validate::RawMesh;
use super::{CanopyMesh, MeshFileError};
use std::path::Path;

#[derive(Clone, Copy, PartialEq)]
enum Section {
    None,
    Nodes,
    Triangles,
    Edges,
}

/// Read a DisMech mesh file. Errors name the file and line.
pub fn read(path: impl AsRef<Path>) -> Result<CanopyMesh, MeshFileError> {
    super::read_with(path.as_ref(), parse).map(|(mesh, _)| mesh)
}

/// Parse DisMech text; `path` is only used in error messages.
pub fn parse(text: &str, path: &str) -> Result<CanopyMesh, MeshFileError> {
    let mut raw = RawMesh::new(path);
    let mut section = Section::None;
    for (k, full) in text.lines().enumerate() {
        let line = k + 1;
        let content = full.split('#').next().unwrap_or("").trim();
        if content.is_empty() {
            continue;
        }
        if let Some(header) = content.strip_prefix('*') {
            section = match header.trim().to_ascii_lowercase().as_str() {
                "nodes" => Section::Nodes,
                "triangles" => Section::Triangles,
                "edges" => Section::Edges,
                _ => {
                    return Err(raw.line_error(
                        line,
                        format!(
                            "unknown section `{content}` (expected *Nodes, *Triangles or *Edges)"
                        ),
                    ))
                }
            };
            continue;
        }
        let fields: Vec<&str> = content
            .split(|c: char| c == ',' || c.is_whitespace())
            .filter(|s| !s.is_empty())
            .collect();
        match section {
            Section::None => {
                return Err(raw.line_error(
                    line,
                    "data before any section header (*Nodes, *Triangles, *Edges)",
                ))
            }
            Section::Nodes => {
                let [x, y, z] = expect_n::<3>(&raw, &fields, line, "coordinates")?;
                let p = [
                    raw.coordinate(x, line)?,
                    raw.coordinate(y, line)?,
                    raw.coordinate(z, line)?,
                ];
                raw.push_node(p, line)?;
            }
            Section::Triangles => {
                let f = expect_n::<3>(&raw, &fields, line, "node indices")?;
                let mut t = [0; 3];
                for (d, s) in t.iter_mut().zip(f) {
                    *d = index(&raw, s, line)?;
                }
                raw.push_face(t, line)?;
            }
            Section::Edges => {
                let [a, b] = expect_n::<2>(&raw, &fields, line, "node indices")?;
                let r = [index(&raw, a, line)?, index(&raw, b, line)?];
                raw.push_rod(r, line)?;
            }
        }
    }
    raw.finish()
}

fn expect_n<'a, const N: usize>(
    raw: &RawMesh,
    fields: &[&'a str],
    line: usize,
    what: &str,
) -> Result<[&'a str; N], MeshFileError> {
    <[&str; N]>::try_from(fields).map_err(|_| {
        raw.line_error(
            line,
            format!("expected {N} {what}, found {} fields", fields.len()),
        )
    })
}

/// A 1-based index token as a 0-based index.
fn index(raw: &RawMesh, tok: &str, line: usize) -> Result<usize, MeshFileError> {
    match tok.parse::<usize>() {
        Ok(0) => Err(raw.line_error(line, "node index 0: indices are 1-based")),
        Ok(i) => Ok(i - 1),
        Err(_) => Err(raw.line_error(line, format!("bad node index `{tok}`"))),
    }
}

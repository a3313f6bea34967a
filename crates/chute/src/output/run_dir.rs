//! Reading a run directory back, as chute writes it: the frames (`canopy.pvd` and the ASCII
//! `frames/*.vtu` of [`super::vtk`]), `timeseries.csv`, `summary.json` and
//! `scenario.resolved.toml`. The viewer is built from these alone, so it can be made for any
//! run directory after the fact.

use std::path::{Path, PathBuf};

use super::vtk::{PVD_NAME, VTK_LINE, VTK_TRIANGLE};

/// A run directory that cannot be read.
#[derive(Debug, thiserror::Error)]
pub enum RunDirError {
    /// A file could not be read.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// A file is not what chute writes.
    #[error("{}: {message}", path.display())]
    Format {
        /// The file.
        path: PathBuf,
        /// What is wrong with it.
        message: String,
    },
}

fn format_err(path: &Path, message: impl Into<String>) -> RunDirError {
    RunDirError::Format {
        path: path.to_path_buf(),
        message: message.into(),
    }
}

fn read(path: &Path) -> Result<String, RunDirError> {
    super::atomic::read_own_string(path).map_err(|source| match source.kind() {
        // Read, but not text: a file that is not what chute writes (bad input), not an I/O
        // failure.
        std::io::ErrorKind::InvalidData => format_err(path, "not UTF-8 text"),
        _ => RunDirError::Io {
            path: path.to_path_buf(),
            source,
        },
    })
}

/// The frame list of `canopy.pvd`: (time in s, path of the frame).
pub fn read_pvd(dir: &Path) -> Result<Vec<(f64, PathBuf)>, RunDirError> {
    let path = dir.join(PVD_NAME);
    let text = read(&path)?;
    let attr = |tag: &str, name: &str| -> Option<String> {
        let key = format!("{name}=\"");
        let start = tag.find(&key)? + key.len();
        let len = tag[start..].find('"')?;
        Some(tag[start..start + len].to_string())
    };
    let mut out = Vec::new();
    for (k, tag) in text.split("<DataSet").skip(1).enumerate() {
        let tag = &tag[..tag.find('>').unwrap_or(tag.len())];
        let t = attr(tag, "timestep").and_then(|s| s.parse::<f64>().ok());
        let file = attr(tag, "file");
        match (t, file) {
            (Some(t), Some(f)) if t.is_finite() => out.push((t, dir.join(f))),
            _ => {
                return Err(format_err(
                    &path,
                    format!("DataSet {k} lacks timestep or file"),
                ))
            }
        }
    }
    if out.windows(2).any(|w| w[1].0 < w[0].0) {
        return Err(format_err(&path, "frame times decrease"));
    }
    if !text.contains("<Collection") {
        return Err(format_err(
            &path,
            "not a ParaView collection (no <Collection>)",
        ));
    }
    // (Frames on disk beyond those listed are normal: a run killed between writing a frame
    // and listing it.)
    Ok(out)
}

/// The mesh of a frame: what does not change from frame to frame.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct FrameMesh {
    /// Number of nodes.
    pub n_nodes: usize,
    /// Triangles (VTK_TRIANGLE cells).
    pub triangles: Vec<[u32; 3]>,
    /// Segments (VTK_LINE cells).
    pub segments: Vec<[u32; 2]>,
    /// Point data `role` ([`super::vtk::point_roles`]); `None` in frames without it.
    pub roles: Option<Vec<u8>>,
}

/// The state of one frame.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct FrameState {
    /// Node positions (m).
    pub positions: Vec<[f64; 3]>,
    /// Node velocities (m/s).
    pub velocities: Vec<[f64; 3]>,
}

/// The text of the `DataArray` named `name` in an ASCII VTU document.
fn data_array<'a>(xml: &'a str, name: &str) -> Option<&'a str> {
    let at = xml.find(&format!("Name=\"{name}\""))?;
    let open = at + xml[at..].find('>')? + 1;
    let close = open + xml[open..].find("</DataArray>")?;
    Some(&xml[open..close])
}

fn numbers<T: std::str::FromStr>(
    path: &Path,
    text: &str,
    name: &str,
) -> Result<Vec<T>, RunDirError> {
    text.split_ascii_whitespace()
        .map(|w| w.parse::<T>())
        .collect::<Result<_, _>>()
        .map_err(|_| format_err(path, format!("DataArray {name}: not a list of numbers")))
}

fn array<T: std::str::FromStr>(path: &Path, xml: &str, name: &str) -> Result<Vec<T>, RunDirError> {
    let text = data_array(xml, name)
        .ok_or_else(|| format_err(path, format!("no DataArray named {name}")))?;
    numbers(path, text, name)
}

fn triples(path: &Path, v: Vec<f64>, n: usize, name: &str) -> Result<Vec<[f64; 3]>, RunDirError> {
    if v.len() != 3 * n {
        return Err(format_err(
            path,
            format!("{name}: {} values for {n} points", v.len()),
        ));
    }
    Ok(v.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect())
}

/// Read one frame: its mesh and its state.
pub fn read_frame(path: &Path) -> Result<(FrameMesh, FrameState), RunDirError> {
    let xml = read(path)?;
    let positions = array::<f64>(path, &xml, "Points")?;
    let n = positions.len() / 3;
    let positions = triples(path, positions, n, "Points")?;
    let velocities = triples(path, array(path, &xml, "velocity")?, n, "velocity")?;
    let conn: Vec<u32> = array(path, &xml, "connectivity")?;
    let offsets: Vec<usize> = array(path, &xml, "offsets")?;
    let types: Vec<u8> = array(path, &xml, "types")?;
    if offsets.len() != types.len() || offsets.last().copied().unwrap_or(0) != conn.len() {
        return Err(format_err(path, "offsets, types and connectivity disagree"));
    }
    let mut mesh = FrameMesh {
        n_nodes: n,
        ..FrameMesh::default()
    };
    let mut start = 0;
    for (&end, &ty) in offsets.iter().zip(&types) {
        let cell = conn
            .get(start..end)
            .ok_or_else(|| format_err(path, "offsets decrease"))?;
        if cell.iter().any(|&i| i as usize >= n) {
            return Err(format_err(path, "cell node index out of range"));
        }
        match (ty, cell) {
            (VTK_TRIANGLE, &[a, b, c]) => mesh.triangles.push([a, b, c]),
            (VTK_LINE, &[a, b]) => mesh.segments.push([a, b]),
            _ => return Err(format_err(path, format!("unexpected cell of type {ty}"))),
        }
        start = end;
    }
    if let Some(text) = data_array(&xml, "role") {
        let roles: Vec<u8> = numbers(path, text, "role")?;
        if roles.len() != n {
            return Err(format_err(
                path,
                format!("{} roles for {n} points", roles.len()),
            ));
        }
        mesh.roles = Some(roles);
    }
    let state = FrameState {
        positions,
        velocities,
    };
    Ok((mesh, state))
}

/// Columns of `timeseries.csv` the viewer charts, decimated.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Series {
    /// Time (s).
    pub t_s: Vec<f64>,
    /// Canopy vertical velocity (m/s).
    pub vz_mps: Vec<f64>,
    /// Extended height (m).
    pub extended_height_m: Vec<f64>,
    /// Rows in the file (before decimation).
    pub rows: usize,
}

/// Read `timeseries.csv` of `dir` keeping at most `max_points` rows: every k-th row with the
/// smallest k that fits, and always the last. Columns are found by name, so columns added
/// later do not matter. `None` when there is no such file.
pub fn read_series(dir: &Path, max_points: usize) -> Result<Option<Series>, RunDirError> {
    let path = dir.join("timeseries.csv");
    if !path.exists() {
        return Ok(None);
    }
    let bad = |m: String| format_err(&path, m);
    let text = super::atomic::read_own(&path).map_err(|source| RunDirError::Io {
        path: path.clone(),
        source,
    })?;
    // A row is written when its newline is: a run still writing (or one that was killed)
    // may show part of its next row, which is not data yet.
    let whole = &text[..text.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1)];
    let mut reader = csv::Reader::from_reader(whole);
    let headers = reader.headers().map_err(|e| bad(e.to_string()))?.clone();
    let col = |name: &str| {
        headers
            .iter()
            .position(|h| h == name)
            .ok_or_else(|| bad(format!("no column {name}")))
    };
    let (ct, cv, ch) = (col("t_s")?, col("vz_mps")?, col("extended_height_m")?);
    let mut rows: Vec<[f64; 3]> = Vec::new();
    for (i, rec) in reader.records().enumerate() {
        let rec = rec.map_err(|e| bad(e.to_string()))?;
        let get = |c: usize| {
            rec.get(c)
                .and_then(|s| s.parse::<f64>().ok())
                .ok_or_else(|| bad(format!("row {}: column {c} is not a number", i + 2)))
        };
        rows.push([get(ct)?, get(cv)?, get(ch)?]);
    }
    let stride = rows.len().div_ceil(max_points.max(2) - 1).max(1);
    let mut s = Series {
        rows: rows.len(),
        ..Series::default()
    };
    let last = rows.len().saturating_sub(1);
    for (i, r) in rows.iter().enumerate() {
        if i % stride == 0 || i == last {
            s.t_s.push(r[0]);
            s.vz_mps.push(r[1]);
            s.extended_height_m.push(r[2]);
        }
    }
    Ok(Some(s))
}

/// The contents of `dir/name` when it exists.
pub fn read_optional(dir: &Path, name: &str) -> Result<Option<String>, RunDirError> {
    let path = dir.join(name);
    if path.exists() {
        read(&path).map(Some)
    } else {
        Ok(None)
    }
}

/// Indices of the frames to keep out of `total` when each takes `bytes_per_frame` and all
/// may take `cap_bytes`: every k-th with the smallest k that fits, always the first and last.
pub fn frame_selection(total: usize, bytes_per_frame: usize, cap_bytes: usize) -> Vec<usize> {
    if total == 0 {
        return Vec::new();
    }
    let fit = (cap_bytes / bytes_per_frame.max(1)).max(2);
    let stride = if total <= fit {
        1
    } else {
        (total - 1).div_ceil(fit - 1)
    };
    let mut keep: Vec<usize> = (0..total).step_by(stride).collect();
    if keep.last() != Some(&(total - 1)) {
        keep.push(total - 1);
    }
    keep
}

//! `viewer.html`: one self-contained page (plain WebGL, no library, no network) that plays a
//! run in 3-D beside its vz(t) and h(t) charts. Everything comes from the run directory
//! ([`super::run_dir`]), so `chute view DIR` can build it for any run afterwards.
//!
//! The page is the template `assets/viewer/viewer.html` with the stylesheet, the script and
//! the data (one JSON block) put in. Frames are embedded as base64 little-endian Float32:
//! positions (3 per node, offsets from the frame's centre, which is given in full) and speeds
//! |v| (1 per node); above [`MAX_FRAME_BYTES`] of frame
//! data only every k-th frame is kept (the first and the last always). docs/outputs.md
//! §viewer.html describes the page and its test hooks.

use std::path::{Path, PathBuf};

use serde_json::{json, Value};

use super::console;
use super::run_dir::{self, RunDirError};
use super::summary::Summary;

/// Name of the viewer in the run directory.
pub const VIEWER_HTML: &str = "viewer.html";
/// Frame data (before base64) embedded at most: 16 MiB, e.g. 1000 frames of 1000 nodes.
pub const MAX_FRAME_BYTES: usize = 16 * 1024 * 1024;
/// Time-series rows embedded at most (every k-th row, and the last).
pub const MAX_SERIES_POINTS: usize = 4000;

const TEMPLATE: &str = include_str!("../../assets/viewer/viewer.html");
const SCRIPT: &str = include_str!("../../assets/viewer/viewer.js");
const STYLE: &str = include_str!("../../assets/viewer/viewer.css");

/// What was written.
#[derive(Debug, Clone, PartialEq)]
pub struct ViewerReport {
    /// The file.
    pub path: PathBuf,
    /// Its size (bytes).
    pub bytes: usize,
    /// Frames in the run directory.
    pub frames_total: usize,
    /// Frames embedded.
    pub frames_embedded: usize,
    /// Canopy triangles of the mesh.
    pub triangles: usize,
}

/// Write `dir/viewer.html` (atomically) with at most [`MAX_FRAME_BYTES`] of frames.
pub fn write_viewer(dir: &Path) -> Result<ViewerReport, RunDirError> {
    write_viewer_capped(dir, MAX_FRAME_BYTES)
}

/// [`write_viewer`] with another cap on the embedded frame data (bytes).
pub fn write_viewer_capped(dir: &Path, cap_bytes: usize) -> Result<ViewerReport, RunDirError> {
    let (html, mut report) = viewer_html(dir, cap_bytes)?;
    let path = dir.join(VIEWER_HTML);
    super::write_atomic(&path, html.as_bytes()).map_err(|source| RunDirError::Io {
        path: path.clone(),
        source,
    })?;
    report.path = path;
    report.bytes = html.len();
    Ok(report)
}

/// Standard base64 (RFC 4648, with padding).
pub fn base64(bytes: &[u8]) -> String {
    const ABC: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            *chunk.get(1).unwrap_or(&0),
            *chunk.get(2).unwrap_or(&0),
        ];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(ABC[((n >> (18 - 6 * k)) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

pub(super) fn f32_base64(values: impl Iterator<Item = f64>) -> String {
    let bytes: Vec<u8> = values.flat_map(|v| (v as f32).to_le_bytes()).collect();
    base64(&bytes)
}

pub(super) fn u32_base64(values: impl Iterator<Item = u32>) -> String {
    let bytes: Vec<u8> = values.flat_map(u32::to_le_bytes).collect();
    base64(&bytes)
}

/// The embedded frames: mesh, times, positions and speeds, and notes on what is missing.
fn frames_json(
    dir: &Path,
    cap: usize,
    notes: &mut Vec<String>,
) -> Result<(Value, usize, usize, usize), RunDirError> {
    let list = if dir.join(super::vtk::PVD_NAME).exists() {
        run_dir::read_pvd(dir)?
    } else {
        Vec::new()
    };
    if list.is_empty() {
        notes.push("no frames in this run directory: only the charts are shown".into());
        return Ok((Value::Null, 0, 0, 0));
    }
    let (mesh, _) = run_dir::read_frame(&list[0].1)?;
    let n = mesh.n_nodes;
    let keep = run_dir::frame_selection(list.len(), 16 * n, cap);
    if keep.len() < list.len() {
        notes.push(format!(
            "{} of {} frames embedded (every {}th): the frames exceed the viewer's {} MiB cap",
            keep.len(),
            list.len(),
            keep.get(1).copied().unwrap_or(1),
            cap >> 20
        ));
    }
    if mesh.roles.is_none() {
        notes.push("the frames carry no node roles (an older chute wrote them): load sites and payload are not marked".into());
    }
    let (mut offsets, mut origins, mut speed, mut times) = (vec![], vec![], vec![], vec![]);
    for &i in &keep {
        let (t, path) = &list[i];
        let (m, state) = run_dir::read_frame(path)?;
        if m != mesh {
            return Err(RunDirError::Format {
                path: path.clone(),
                message: format!(
                    "its mesh differs from the first frame's ({})",
                    list[0].1.display()
                ),
            });
        }
        times.push(*t);
        // Float32 offsets from the frame's centre keep ~1e-7 of the canopy size however far
        // it has fallen; the centre itself is exact in the JSON.
        let origin = centre(&state.positions);
        origins.push(origin);
        offsets.extend(
            state
                .positions
                .iter()
                .flat_map(|p| [0, 1, 2].map(|c| p[c] - origin[c])),
        );
        speed.extend(
            state
                .velocities
                .iter()
                .map(|v| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()),
        );
    }
    let roles = mesh.roles.as_ref().map(|r| base64(r));
    let value = json!({
        "nodes": n,
        "triangles": u32_base64(mesh.triangles.iter().flatten().copied()),
        "triangle_count": mesh.triangles.len(),
        "segments": u32_base64(mesh.segments.iter().flatten().copied()),
        "segment_count": mesh.segments.len(),
        "roles": roles,
        "times": times,
        "total": list.len(),
        "origins": origins,
        "positions": f32_base64(offsets.into_iter()),
        "speeds": f32_base64(speed.into_iter()),
    });
    Ok((value, list.len(), keep.len(), mesh.triangles.len()))
}

/// Centre of the bounding box of `points`.
pub(super) fn centre(points: &[[f64; 3]]) -> [f64; 3] {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in points {
        for c in 0..3 {
            lo[c] = lo[c].min(p[c]);
            hi[c] = hi[c].max(p[c]);
        }
    }
    [0, 1, 2].map(|c| {
        if lo[c] <= hi[c] {
            0.5 * (lo[c] + hi[c])
        } else {
            0.0
        }
    })
}

/// The page for run directory `dir` and what it holds (`path` and `bytes` left empty).
pub fn viewer_html(dir: &Path, cap_bytes: usize) -> Result<(String, ViewerReport), RunDirError> {
    let mut notes = Vec::new();
    let summary_text = run_dir::read_optional(dir, "summary.json")?;
    let summary: Option<Value> = match &summary_text {
        Some(text) => Some(serde_json::from_str(text).map_err(|e| RunDirError::Format {
            path: dir.join("summary.json"),
            message: format!("not JSON: {e}"),
        })?),
        None => None,
    };
    let typed: Option<Summary> = summary.clone().and_then(|v| serde_json::from_value(v).ok());
    let series = run_dir::read_series(dir, MAX_SERIES_POINTS)?;
    let toml = run_dir::read_optional(dir, "scenario.resolved.toml")?;
    let (frames, total, embedded, triangles) = frames_json(dir, cap_bytes, &mut notes)?;
    if total == 0 && summary.is_none() && series.is_none() {
        return Err(RunDirError::Format {
            path: dir.to_path_buf(),
            message: "not a run directory: no canopy.pvd, timeseries.csv or summary.json".into(),
        });
    }
    let name = summary
        .as_ref()
        .and_then(|s| s["scenario_name"].as_str().map(str::to_string))
        .or_else(|| dir.file_name().map(|n| n.to_string_lossy().into_owned()))
        .unwrap_or_else(|| "run".into());
    let results: Vec<Value> = typed
        .as_ref()
        .map(|s| {
            console::key_results(s)
                .into_iter()
                .map(|(k, v)| json!([k, v]))
                .collect()
        })
        .unwrap_or_default();
    let series = series.map(|s| {
        json!({
            "rows": s.rows,
            "t": f32_base64(s.t_s.into_iter()),
            "vz": f32_base64(s.vz_mps.into_iter()),
            "h": f32_base64(s.extended_height_m.into_iter()),
        })
    });
    // Only what the page shows: the page must be a function of the run's results alone (the
    // wall time in summary.json would make two identical runs' viewers differ).
    let terminal = typed
        .as_ref()
        .filter(|s| s.reached_terminal)
        .map(|s| s.terminal_velocity_mps);
    let data = json!({
        "format": 1,
        "name": name,
        "results": results,
        "terminal_velocity_mps": terminal,
        "scenario_toml": toml,
        "frames": frames,
        "series": series,
        "notes": notes,
    });
    let html = page(&name, &data);
    let report = ViewerReport {
        path: PathBuf::new(),
        bytes: 0,
        frames_total: total,
        frames_embedded: embedded,
        triangles,
    };
    Ok((html, report))
}

/// The page: the template with the stylesheet, the script, the title `name` and `data`.
pub(super) fn page(name: &str, data: &Value) -> String {
    // `<` only occurs inside JSON strings; escaping it keeps `</script>` and `<!--` in a
    // scenario name or file from ending the data block early.
    let data = data.to_string().replace('<', "\\u003c");
    let title = html_escape(name);
    fill(
        TEMPLATE,
        &[
            ("/*CHUTE_STYLE*/", STYLE),
            ("/*CHUTE_SCRIPT*/", SCRIPT),
            ("CHUTE_TITLE", &title),
            ("/*CHUTE_DATA*/", &data),
        ],
    )
}

/// `template` with each slot marker replaced by its text, in one pass over the template (so
/// text put in is never searched for markers).
fn fill(template: &str, slots: &[(&str, &str)]) -> String {
    let mut out =
        String::with_capacity(template.len() + slots.iter().map(|s| s.1.len()).sum::<usize>());
    let mut rest = template;
    loop {
        let next = slots
            .iter()
            .filter_map(|&(marker, text)| rest.find(marker).map(|i| (i, marker, text)))
            .min_by_key(|&(i, _, _)| i);
        let Some((i, marker, text)) = next else {
            out.push_str(rest);
            return out;
        };
        out.push_str(&rest[..i]);
        out.push_str(text);
        rest = &rest[i + marker.len()..];
    }
}

/// `s` safe as HTML text and attribute values.
pub(crate) fn html_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

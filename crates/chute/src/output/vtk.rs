//! ParaView output: one ASCII VTU (XML UnstructuredGrid) per frame in `frames/`, and a
//! `canopy.pvd` collection that indexes them by time.
//!
//! Each frame is written atomically and the PVD is rewritten atomically after each frame, so
//! ParaView can open the output at any time during a run and always sees complete files.

use std::fmt::Write as _;
use std::io;
use std::path::{Path, PathBuf};

use super::atomic::{at, FileError};
use super::write_atomic;

/// VTK cell type of a 3-node triangle.
pub const VTK_TRIANGLE: u8 = 5;
/// VTK cell type of a 2-node line segment.
pub const VTK_LINE: u8 = 3;
/// Sub-directory of the output directory holding the frames.
pub const FRAMES_DIR: &str = "frames";
/// Name of the collection file in the output directory.
pub const PVD_NAME: &str = "canopy.pvd";

/// Point data `role` (UInt8) of a canopy node.
pub const ROLE_CANOPY: u8 = 0;
/// `role` of a node of a suspension line or other non-canopy rod.
pub const ROLE_LINE: u8 = 1;
/// `role` of the payload node.
pub const ROLE_PAYLOAD: u8 = 2;
/// `role` of a canopy node that is a load site (carries the load or a line attachment).
pub const ROLE_LOAD_SITE: u8 = 3;

/// The `role` of each of `n_nodes` nodes: canopy, load site (a canopy node), payload, or line
/// (every node that is none of these). The payload wins over the others, load sites over
/// canopy.
pub fn point_roles(
    n_nodes: usize,
    canopy: &[usize],
    load_sites: &[usize],
    payload: Option<usize>,
) -> Vec<u8> {
    let mut roles = vec![ROLE_LINE; n_nodes];
    let mut set = |nodes: &mut dyn Iterator<Item = usize>, role: u8| {
        for i in nodes.filter(|&i| i < n_nodes) {
            roles[i] = role;
        }
    };
    set(&mut canopy.iter().copied(), ROLE_CANOPY);
    set(&mut load_sites.iter().copied(), ROLE_LOAD_SITE);
    set(&mut payload.into_iter(), ROLE_PAYLOAD);
    roles
}

/// Cell data of a membrane that cannot carry compression, one value per triangle
/// (docs/outputs.md §Frames): where the fabric wrinkles, and how much.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Wrinkles {
    /// `wrinkle_strain`: the largest principal wrinkling strain (dimensionless; the strain
    /// taken up by wrinkles); segments get 0.
    pub strain: Vec<f64>,
    /// `membrane_state`: 0 taut, 1 wrinkled (one slack direction), 2 slack (both); segments
    /// get 0.
    pub state: Vec<u8>,
}

/// One mesh state to write. Cells are the triangles followed by the segments.
#[derive(Debug, Clone, Copy)]
pub struct Frame<'a> {
    /// Simulated time (s).
    pub t_s: f64,
    /// Node positions (m).
    pub positions: &'a [[f64; 3]],
    /// Node velocities (m/s), point data `velocity`.
    pub velocities: &'a [[f64; 3]],
    /// Triangles (node indices), VTK_TRIANGLE cells.
    pub triangles: &'a [[usize; 3]],
    /// Line segments (node indices), e.g. suspension lines, VTK_LINE cells.
    pub segments: &'a [[usize; 2]],
    /// Aerodynamic drag force on each triangle (N), cell data `drag`; segments get zeros.
    pub triangle_drag: &'a [[f64; 3]],
    /// What each node is ([`point_roles`]), point data `role`; empty to leave it out.
    pub roles: &'a [u8],
    /// The wrinkling cell data, for a membrane that cannot carry compression.
    pub wrinkles: Option<&'a Wrinkles>,
}

/// Writer of a frame series into one output directory.
#[derive(Debug)]
pub struct VtkSeries {
    out_dir: PathBuf,
    /// (time, file name relative to `out_dir`) of every frame written so far.
    entries: Vec<(f64, String)>,
    /// Point data `role` written with every frame (empty: none).
    roles: Vec<u8>,
    /// Cell data of the next frame only ([`VtkSeries::set_wrinkles`]).
    wrinkles: Option<Wrinkles>,
}

/// The path of frame `i` inside a run directory (`frames/frame_NNNNNN.vtu`).
pub fn frame_name(i: usize) -> String {
    format!("{FRAMES_DIR}/frame_{i:06}.vtu")
}

/// The frame files of `out_dir/frames/` numbered `kept` or later: left by a run stopped after
/// its checkpoint, which a resumed run removes.
pub fn later_frames(out_dir: &Path, kept: usize) -> io::Result<Vec<PathBuf>> {
    let mut later = Vec::new();
    for entry in std::fs::read_dir(out_dir.join(FRAMES_DIR))? {
        let name = entry?.file_name();
        let index = name
            .to_str()
            .and_then(|n| n.strip_prefix("frame_"))
            .and_then(|n| n.strip_suffix(".vtu"))
            .and_then(|n| n.parse::<usize>().ok());
        if index.is_some_and(|i| i >= kept) {
            later.push(out_dir.join(FRAMES_DIR).join(name));
        }
    }
    Ok(later)
}

impl VtkSeries {
    /// Prepare `out_dir/frames/` (created if missing). Nothing else is written yet.
    pub fn new(out_dir: &Path) -> Result<Self, FileError> {
        let frames = out_dir.join(FRAMES_DIR);
        std::fs::create_dir_all(&frames).map_err(at(&frames))?;
        Ok(Self {
            out_dir: out_dir.to_path_buf(),
            entries: Vec::new(),
            roles: Vec::new(),
            wrinkles: None,
        })
    }

    /// Continue a series whose first frames, at `times` (s), are already in
    /// `out_dir/frames/` (resume from a checkpoint). Frame files numbered from `times.len()`
    /// on are left from an interrupted run; they are removed so the directory only ever holds
    /// frames the PVD lists (later frames are rewritten with the same names).
    pub fn resume(out_dir: &Path, times: &[f64]) -> Result<Self, FileError> {
        let mut me = Self::new(out_dir)?;
        me.entries = times
            .iter()
            .enumerate()
            .map(|(i, &t)| (t, frame_name(i)))
            .collect();
        let frames = out_dir.join(FRAMES_DIR);
        for path in later_frames(out_dir, times.len()).map_err(at(&frames))? {
            std::fs::remove_file(&path).map_err(at(&path))?;
        }
        let pvd = out_dir.join(PVD_NAME);
        write_atomic(&pvd, me.pvd_string().as_bytes()).map_err(at(&pvd))?;
        Ok(me)
    }

    /// Write `roles` ([`point_roles`]) as point data `role` with every later frame, so a
    /// reader (the viewer, ParaView) knows the canopy, lines, payload and load sites.
    pub fn set_roles(&mut self, roles: Vec<u8>) {
        self.roles = roles;
    }

    /// Write `wrinkles` as cell data with the next frame (only), taken by
    /// [`write_frame`](Self::write_frame).
    pub fn set_wrinkles(&mut self, wrinkles: Option<Wrinkles>) {
        self.wrinkles = wrinkles;
    }

    /// Times (s) of the frames written so far, in order.
    pub fn times(&self) -> Vec<f64> {
        self.entries.iter().map(|(t, _)| *t).collect()
    }

    /// Number of frames written.
    pub fn frames(&self) -> usize {
        self.entries.len()
    }

    /// Write `frames/frame_<NNNNNN>.vtu` (numbered from 0) and rewrite `canopy.pvd`.
    /// Returns the path of the frame. Fails with `InvalidInput` on inconsistent lengths or
    /// out-of-range node indices, before writing anything.
    pub fn write_frame(
        &mut self,
        t: f64,
        positions: &[[f64; 3]],
        velocities: &[[f64; 3]],
        triangles: &[[usize; 3]],
        segments: &[[usize; 2]],
        triangle_drag: &[[f64; 3]],
    ) -> Result<PathBuf, FileError> {
        // Moved out for the call: `write` borrows `self` mutably.
        let roles = std::mem::take(&mut self.roles);
        let wrinkles = self.wrinkles.take();
        let frame = Frame {
            t_s: t,
            positions,
            velocities,
            triangles,
            segments,
            triangle_drag,
            roles: &roles,
            wrinkles: wrinkles.as_ref(),
        };
        let written = self.write(&frame);
        self.roles = roles;
        written
    }

    /// Same as [`write_frame`](Self::write_frame), taking a [`Frame`].
    pub fn write(&mut self, f: &Frame<'_>) -> Result<PathBuf, FileError> {
        let name = frame_name(self.entries.len());
        let path = self.out_dir.join(&name);
        validate(f).map_err(at(&path))?;
        write_atomic(&path, vtu_string(f).as_bytes()).map_err(at(&path))?;
        self.entries.push((f.t_s, name));
        let pvd = self.out_dir.join(PVD_NAME);
        write_atomic(&pvd, self.pvd_string().as_bytes()).map_err(at(&pvd))?;
        Ok(path)
    }

    /// The collection file listing every frame written so far.
    pub fn pvd_string(&self) -> String {
        let mut s = String::from(
            "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" \
             byte_order=\"LittleEndian\">\n  <Collection>\n",
        );
        for (t, file) in &self.entries {
            let _ = writeln!(
                s,
                "    <DataSet timestep=\"{t}\" group=\"\" part=\"0\" file=\"{file}\"/>"
            );
        }
        s.push_str("  </Collection>\n</VTKFile>\n");
        s
    }
}

fn invalid(msg: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, msg)
}

fn validate(f: &Frame<'_>) -> io::Result<()> {
    let n = f.positions.len();
    if f.velocities.len() != n {
        return Err(invalid(format!(
            "{} velocities for {n} points",
            f.velocities.len()
        )));
    }
    if !f.roles.is_empty() && f.roles.len() != n {
        return Err(invalid(format!("{} roles for {n} points", f.roles.len())));
    }
    if let Some(w) = f
        .wrinkles
        .filter(|w| w.strain.len() != f.triangles.len() || w.state.len() != f.triangles.len())
    {
        return Err(invalid(format!(
            "{} wrinkle strains and {} membrane states for {} triangles",
            w.strain.len(),
            w.state.len(),
            f.triangles.len()
        )));
    }
    if f.triangle_drag.len() != f.triangles.len() {
        return Err(invalid(format!(
            "{} drag vectors for {} triangles",
            f.triangle_drag.len(),
            f.triangles.len()
        )));
    }
    let bad = f
        .triangles
        .iter()
        .flatten()
        .chain(f.segments.iter().flatten())
        .find(|&&i| i >= n);
    if let Some(i) = bad {
        return Err(invalid(format!(
            "cell node index {i} out of range ({n} points)"
        )));
    }
    Ok(())
}

/// Append a DataArray of 3-vectors, one vector per line.
fn vec3_array(s: &mut String, name: &str, indent: &str, data: impl Iterator<Item = [f64; 3]>) {
    let _ = writeln!(
        s,
        "{indent}<DataArray type=\"Float64\" Name=\"{name}\" NumberOfComponents=\"3\" \
         format=\"ascii\">"
    );
    for [a, b, c] in data {
        let _ = writeln!(s, "{indent}  {a} {b} {c}");
    }
    let _ = writeln!(s, "{indent}</DataArray>");
}

/// The VTU document of one frame (ASCII; `{}` prints f64 losslessly).
pub fn vtu_string(f: &Frame<'_>) -> String {
    let (n_pts, n_tri, n_seg) = (f.positions.len(), f.triangles.len(), f.segments.len());
    let mut s = String::with_capacity(64 * (n_pts * 2 + n_tri * 3 + n_seg * 2) + 1024);
    let _ = write!(
        s,
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" \
         byte_order=\"LittleEndian\" header_type=\"UInt64\">\n  <UnstructuredGrid>\n    \
         <FieldData>\n      <DataArray type=\"Float64\" Name=\"TimeValue\" \
         NumberOfTuples=\"1\" format=\"ascii\">{}</DataArray>\n    </FieldData>\n    \
         <Piece NumberOfPoints=\"{n_pts}\" NumberOfCells=\"{}\">\n      <PointData \
         Vectors=\"velocity\">\n",
        f.t_s,
        n_tri + n_seg
    );
    vec3_array(&mut s, "velocity", "        ", f.velocities.iter().copied());
    if !f.roles.is_empty() {
        s.push_str("        <DataArray type=\"UInt8\" Name=\"role\" format=\"ascii\">\n          ");
        for r in f.roles {
            let _ = write!(s, "{r} ");
        }
        s.push_str("\n        </DataArray>\n");
    }
    s.push_str("      </PointData>\n      <CellData Vectors=\"drag\">\n");
    let zeros = std::iter::repeat_n([0.0; 3], n_seg);
    vec3_array(
        &mut s,
        "drag",
        "        ",
        f.triangle_drag.iter().copied().chain(zeros),
    );
    if let Some(w) = f.wrinkles {
        wrinkle_arrays(&mut s, w, n_seg);
    }
    s.push_str("      </CellData>\n      <Points>\n");
    vec3_array(&mut s, "Points", "        ", f.positions.iter().copied());
    s.push_str("      </Points>\n      <Cells>\n");
    cells(&mut s, f);
    s.push_str("      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n");
    s
}

/// The `wrinkle_strain` and `membrane_state` cell arrays (segments get zeros).
fn wrinkle_arrays(s: &mut String, w: &Wrinkles, n_seg: usize) {
    let indent = "        ";
    let _ = writeln!(
        s,
        "{indent}<DataArray type=\"Float64\" Name=\"wrinkle_strain\" format=\"ascii\">"
    );
    for x in w.strain.iter().chain(std::iter::repeat_n(&0.0, n_seg)) {
        let _ = writeln!(s, "{indent}  {x}");
    }
    let _ = writeln!(s, "{indent}</DataArray>");
    let _ = write!(
        s,
        "{indent}<DataArray type=\"UInt8\" Name=\"membrane_state\" format=\"ascii\">\n{indent}  "
    );
    for x in w.state.iter().chain(std::iter::repeat_n(&0, n_seg)) {
        let _ = write!(s, "{x} ");
    }
    let _ = writeln!(s, "\n{indent}</DataArray>");
}

/// Connectivity, offsets (end index of each cell in the connectivity) and types.
fn cells(s: &mut String, f: &Frame<'_>) {
    let open = |s: &mut String, ty: &str, name: &str| {
        let _ = writeln!(
            s,
            "        <DataArray type=\"{ty}\" Name=\"{name}\" format=\"ascii\">"
        );
    };
    let close = "        </DataArray>\n";
    open(s, "Int64", "connectivity");
    for [a, b, c] in f.triangles {
        let _ = writeln!(s, "          {a} {b} {c}");
    }
    for [a, b] in f.segments {
        let _ = writeln!(s, "          {a} {b}");
    }
    s.push_str(close);
    open(s, "Int64", "offsets");
    let tri_offsets = (1..=f.triangles.len()).map(|i| 3 * i);
    let end_tri = 3 * f.triangles.len();
    let seg_offsets = (1..=f.segments.len()).map(|i| end_tri + 2 * i);
    for o in tri_offsets.chain(seg_offsets) {
        let _ = writeln!(s, "          {o}");
    }
    s.push_str(close);
    open(s, "UInt8", "types");
    let types = std::iter::repeat_n(VTK_TRIANGLE, f.triangles.len())
        .chain(std::iter::repeat_n(VTK_LINE, f.segments.len()));
    for ty in types {
        let _ = writeln!(s, "          {ty}");
    }
    s.push_str(close);
}

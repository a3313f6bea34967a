//! The per-step time series: streamed to `timeseries.csv`, with a bounded in-memory copy.
//!
//! The CSV is written row by row but only whole rows ever reach the file, so after every
//! [`TimeSeriesWriter::flush`] (and after a crash) the file is a valid CSV prefix of the run.
//! [`DecimatedSeries`] keeps at most `capacity + 1` samples in memory whatever the simulated
//! time, for the metrics and the plots.

use std::fs::File;
use std::io::{self, Write};
use std::path::Path;

/// CSV header of `timeseries.csv`, in column order (units in the names).
pub const HEADER: &str = "t_s,z_m,vz_mps,vx_mps,vy_mps,z_payload_m,vz_payload_mps,\
extended_height_m,drag_x_n,drag_y_n,drag_z_n,newton_iterations,dt_s,line_tension_n,\
payload_acceleration_mps2,axis_angle_deg,canopy_diameter_m";

/// Buffered rows are written to the file once they exceed this many bytes (~500 rows).
const FLUSH_THRESHOLD_BYTES: usize = 64 * 1024;

/// One row of `timeseries.csv`: the state at the end of an accepted step.
///
/// Canopy quantities (`z_m`, `v*_mps`) are mass-weighted means over canopy nodes (see
/// [`canopy_means`]). When the scenario has no payload, `z_payload_m`/`vz_payload_mps` repeat
/// the canopy values so the columns never hold NaN.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct Sample {
    /// Simulated time at the end of the step (s).
    pub t_s: f64,
    /// Mass-weighted mean canopy height (m).
    pub z_m: f64,
    /// Mass-weighted mean canopy vertical velocity (m/s; negative = descending).
    pub vz_mps: f64,
    /// Mass-weighted mean canopy velocity along x (m/s).
    pub vx_mps: f64,
    /// Mass-weighted mean canopy velocity along y (m/s).
    pub vy_mps: f64,
    /// Payload height (m); the canopy value when there is no payload.
    pub z_payload_m: f64,
    /// Payload vertical velocity (m/s); the canopy value when there is no payload.
    pub vz_payload_mps: f64,
    /// Extended height: max z − min z over canopy nodes (m).
    pub extended_height_m: f64,
    /// Total aerodynamic drag on the system along x (N).
    pub drag_x_n: f64,
    /// Total aerodynamic drag on the system along y (N).
    pub drag_y_n: f64,
    /// Total aerodynamic drag on the system along z (N; positive = upward, opposing descent).
    pub drag_z_n: f64,
    /// Newton iterations taken by this step.
    pub newton_iterations: u32,
    /// Size of this step (s).
    pub dt_s: f64,
    /// Magnitude of the resultant force of the suspension lines on the payload (N); 0 without
    /// a payload. (Absent in files written before the column existed: read as 0.)
    #[serde(default)]
    pub line_tension_n: f64,
    /// Magnitude of the payload's acceleration over this step, |v(t) − v(t − dt)|/dt (m/s²);
    /// 0 on the initial row and without a payload.
    #[serde(default)]
    pub payload_acceleration_mps2: f64,
    /// Angle between the vertical and the axis from the payload to the canopy's mass centre
    /// (degrees, 0 = canopy straight above); 0 without a payload.
    #[serde(default)]
    pub axis_angle_deg: f64,
    /// Projected diameter of the canopy: twice the largest horizontal distance of a canopy
    /// node from the canopy's mass centre (m). (Absent in files written before the column
    /// existed: read as 0.)
    #[serde(default)]
    pub canopy_diameter_m: f64,
}

impl Sample {
    /// Append this sample as one CSV row (with newline). `{}` on f64 prints the shortest
    /// string that parses back to the same value, so the CSV loses no precision.
    fn write_row(&self, out: &mut Vec<u8>) {
        // Writing into a Vec cannot fail.
        let _ = writeln!(
            out,
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
            self.t_s,
            self.z_m,
            self.vz_mps,
            self.vx_mps,
            self.vy_mps,
            self.z_payload_m,
            self.vz_payload_mps,
            self.extended_height_m,
            self.drag_x_n,
            self.drag_y_n,
            self.drag_z_n,
            self.newton_iterations,
            self.dt_s,
            self.line_tension_n,
            self.payload_acceleration_mps2,
            self.axis_angle_deg,
            self.canopy_diameter_m
        );
    }
}

/// Mass-weighted canopy kinematics of one state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CanopyMeans {
    /// Σ mᵢ zᵢ / Σ mᵢ over canopy nodes (m).
    pub z_m: f64,
    /// Σ mᵢ vᵢ / Σ mᵢ over canopy nodes (m/s), [vx, vy, vz].
    pub v_mps: [f64; 3],
    /// max zᵢ − min zᵢ over canopy nodes (m).
    pub extended_height_m: f64,
    /// Σ mᵢ xᵢ / Σ mᵢ over canopy nodes (m): the canopy's mass centre.
    pub centre_m: [f64; 3],
    /// Twice the largest horizontal distance of a canopy node from the mass centre (m).
    pub diameter_m: f64,
}

/// Mass-weighted mean height and velocity, and extended height, over the nodes `nodes`.
///
/// `positions`, `velocities` and `masses` are indexed by node. Returns `None` when `nodes` is
/// empty or the total mass is not positive (the means would be undefined).
pub fn canopy_means(
    positions: &[[f64; 3]],
    velocities: &[[f64; 3]],
    masses: &[f64],
    nodes: &[usize],
) -> Option<CanopyMeans> {
    let (mut m_sum, mut mz, mut mv, mut mx) = (0.0, 0.0, [0.0; 3], [0.0; 3]);
    let (mut z_min, mut z_max) = (f64::INFINITY, f64::NEG_INFINITY);
    for &i in nodes {
        let (x, v, m) = (positions[i], velocities[i], masses[i]);
        m_sum += m;
        mz += m * x[2];
        for c in 0..3 {
            mv[c] += m * v[c];
            mx[c] += m * x[c];
        }
        z_min = z_min.min(x[2]);
        z_max = z_max.max(x[2]);
    }
    if m_sum <= 0.0 {
        return None;
    }
    let centre_m = mx.map(|s| s / m_sum);
    let radius = (nodes.iter())
        .map(|&i| (positions[i][0] - centre_m[0]).hypot(positions[i][1] - centre_m[1]))
        .fold(0.0, f64::max);
    Some(CanopyMeans {
        z_m: mz / m_sum,
        v_mps: mv.map(|s| s / m_sum),
        extended_height_m: z_max - z_min,
        centre_m,
        diameter_m: 2.0 * radius,
    })
}

/// Streams [`Sample`]s to a CSV file.
///
/// Rows are buffered in memory and written to the file only as whole rows, so the file is
/// always a valid CSV prefix. [`flush`](Self::flush) hands buffered rows to the OS (enough to
/// survive a crash of the process); [`finish`](Self::finish) also fsyncs. Dropping the writer
/// flushes on a best-effort basis.
pub struct TimeSeriesWriter {
    file: File,
    /// Bytes of whole rows in the file.
    len: u64,
    buf: Vec<u8>,
    rows: u64,
}

impl TimeSeriesWriter {
    /// Create `path` anew (a new file renamed over an old one, which may be a hard link to
    /// another directory's) and write the header line immediately.
    pub fn create(path: &Path) -> io::Result<Self> {
        super::write_atomic(path, format!("{HEADER}\n").as_bytes())?;
        Self::append_to(path, 0)
    }

    /// Continue an existing file that already holds the header and `rows` data rows (and
    /// nothing after them: see `checkpoint::truncate_timeseries`), appending from its end.
    pub fn append_to(path: &Path, rows: u64) -> io::Result<Self> {
        let (file, len) = super::atomic::open_rows(path)?;
        Ok(Self {
            file,
            len,
            buf: Vec::with_capacity(FLUSH_THRESHOLD_BYTES + 1024),
            rows,
        })
    }

    /// Append one row; it reaches the file at the latest on the next [`flush`](Self::flush).
    pub fn push(&mut self, s: &Sample) -> io::Result<()> {
        s.write_row(&mut self.buf);
        self.rows += 1;
        if self.buf.len() >= FLUSH_THRESHOLD_BYTES {
            self.flush()?;
        }
        Ok(())
    }

    /// Write all buffered rows to the file (one write of whole rows; one that fails is
    /// taken back, so the file still ends in a whole row: [`super::atomic::append_whole`]).
    pub fn flush(&mut self) -> io::Result<()> {
        if !self.buf.is_empty() {
            super::atomic::append_whole(&mut self.file, &mut self.len, &self.buf)?;
            self.buf.clear();
        }
        Ok(())
    }

    /// Flush and fsync; call once at the end of a run.
    pub fn finish(mut self) -> io::Result<()> {
        self.flush()?;
        self.file.sync_all()
    }

    /// Number of rows pushed so far (excluding the header).
    pub fn rows(&self) -> u64 {
        self.rows
    }
}

impl Drop for TimeSeriesWriter {
    fn drop(&mut self) {
        let _ = self.flush();
    }
}

/// Bounded in-memory copy of the series for metrics and plots (structure of arrays).
///
/// Decimation: sample number k (0-based, in push order) is retained when k is a multiple of
/// the current `stride` (initially 1). When `capacity` samples are retained, every other one is
/// dropped and `stride` doubles, so the retained samples are always those with k a multiple of
/// `stride`: uniformly spaced in step count, between `capacity/2` and `capacity` of them. The
/// most recent sample is always kept as well (as a provisional last entry), so the series ends
/// at the current time. Memory is bounded by `capacity + 1` samples whatever the run length.
/// The maximum extended height, the peak line tension (with its time) and the peak payload
/// acceleration are tracked exactly over all samples, not only retained ones.
#[derive(Debug, Clone)]
pub struct DecimatedSeries {
    capacity: usize,
    stride: u64,
    pushed: u64,
    /// Whether the last entry of the columns is the provisional latest sample.
    tail_is_provisional: bool,
    max_extended_height_m: f64,
    peak_line_tension: (f64, f64),
    peak_payload_acceleration_mps2: f64,
    /// Simulated time (s), per retained sample.
    pub t_s: Vec<f64>,
    /// Canopy mean vertical velocity (m/s).
    pub vz_mps: Vec<f64>,
    /// Canopy mean x velocity (m/s).
    pub vx_mps: Vec<f64>,
    /// Canopy mean y velocity (m/s).
    pub vy_mps: Vec<f64>,
    /// Extended height (m).
    pub extended_height_m: Vec<f64>,
    /// Total drag along z (N).
    pub drag_z_n: Vec<f64>,
    /// Canopy mean height (m).
    pub z_m: Vec<f64>,
    /// Payload height (m; the canopy's without a payload).
    pub z_payload_m: Vec<f64>,
    /// Line tension on the payload (N).
    pub line_tension_n: Vec<f64>,
    /// Angle of the payload–canopy axis from the vertical (degrees).
    pub axis_angle_deg: Vec<f64>,
    /// Projected canopy diameter (m).
    pub canopy_diameter_m: Vec<f64>,
}

/// Number of columns of [`DecimatedSeries`].
const COLUMNS: usize = 11;

/// Default bound on retained samples.
pub const DEFAULT_CAPACITY: usize = 20_000;

impl Default for DecimatedSeries {
    fn default() -> Self {
        Self::new(DEFAULT_CAPACITY)
    }
}

impl DecimatedSeries {
    /// Empty series retaining at most `capacity` (≥ 2, clamped) samples plus the latest one.
    pub fn new(capacity: usize) -> Self {
        let capacity = capacity.max(2);
        let col = || Vec::with_capacity(capacity + 1);
        Self {
            capacity,
            stride: 1,
            pushed: 0,
            tail_is_provisional: false,
            max_extended_height_m: f64::NEG_INFINITY,
            peak_line_tension: (f64::NAN, f64::NEG_INFINITY),
            peak_payload_acceleration_mps2: f64::NEG_INFINITY,
            t_s: col(),
            vz_mps: col(),
            vx_mps: col(),
            vy_mps: col(),
            extended_height_m: col(),
            drag_z_n: col(),
            z_m: col(),
            z_payload_m: col(),
            line_tension_n: col(),
            axis_angle_deg: col(),
            canopy_diameter_m: col(),
        }
    }

    fn columns_mut(&mut self) -> [&mut Vec<f64>; COLUMNS] {
        [
            &mut self.t_s,
            &mut self.vz_mps,
            &mut self.vx_mps,
            &mut self.vy_mps,
            &mut self.extended_height_m,
            &mut self.drag_z_n,
            &mut self.z_m,
            &mut self.z_payload_m,
            &mut self.line_tension_n,
            &mut self.axis_angle_deg,
            &mut self.canopy_diameter_m,
        ]
    }

    /// Record one sample (see the type docs for the decimation rule).
    pub fn push(&mut self, s: &Sample) {
        if self.tail_is_provisional {
            self.pop();
        }
        let k = self.pushed;
        self.pushed += 1;
        self.max_extended_height_m = self.max_extended_height_m.max(s.extended_height_m);
        if s.line_tension_n > self.peak_line_tension.1 {
            self.peak_line_tension = (s.t_s, s.line_tension_n);
        }
        self.peak_payload_acceleration_mps2 = self
            .peak_payload_acceleration_mps2
            .max(s.payload_acceleration_mps2);
        self.push_raw([
            s.t_s,
            s.vz_mps,
            s.vx_mps,
            s.vy_mps,
            s.extended_height_m,
            s.drag_z_n,
            s.z_m,
            s.z_payload_m,
            s.line_tension_n,
            s.axis_angle_deg,
            s.canopy_diameter_m,
        ]);
        self.tail_is_provisional = !k.is_multiple_of(self.stride);
        if !self.tail_is_provisional && self.t_s.len() >= self.capacity {
            self.halve();
        }
    }

    fn pop(&mut self) {
        for c in self.columns_mut() {
            c.pop();
        }
    }

    /// Keep retained entries 0, 2, 4, … (push index a multiple of 2·stride) and double stride.
    fn halve(&mut self) {
        fn keep_even(v: &mut Vec<f64>) {
            let mut i = 0;
            v.retain(|_| {
                i += 1;
                (i - 1) % 2 == 0
            });
        }
        let last = self.sample_at(self.t_s.len() - 1);
        let last_was_dropped = (self.t_s.len() - 1) % 2 == 1;
        for v in self.columns_mut() {
            keep_even(v);
        }
        self.stride *= 2;
        // The newest sample must stay visible: re-add it as the provisional tail if dropped.
        if last_was_dropped {
            self.push_raw(last);
            self.tail_is_provisional = true;
        }
    }

    fn sample_at(&mut self, i: usize) -> [f64; COLUMNS] {
        self.columns_mut().map(|c| c[i])
    }

    fn push_raw(&mut self, r: [f64; COLUMNS]) {
        for (c, x) in self.columns_mut().into_iter().zip(r) {
            c.push(x);
        }
    }

    /// Number of samples currently held (≤ capacity + 1).
    pub fn len(&self) -> usize {
        self.t_s.len()
    }

    /// True before the first push.
    pub fn is_empty(&self) -> bool {
        self.t_s.is_empty()
    }

    /// Total number of samples pushed.
    pub fn pushed(&self) -> u64 {
        self.pushed
    }

    /// Current decimation stride (1 until the first halving).
    pub fn stride(&self) -> u64 {
        self.stride
    }

    /// Exact maximum extended height over every pushed sample (m); −∞ when empty.
    pub fn max_extended_height_m(&self) -> f64 {
        self.max_extended_height_m
    }

    /// Exact peak line tension over every pushed sample: (time (s), tension (N)), the
    /// earliest if repeated; (NaN, −∞) when empty.
    pub fn peak_line_tension(&self) -> (f64, f64) {
        self.peak_line_tension
    }

    /// Exact peak payload acceleration over every pushed sample (m/s²); −∞ when empty.
    pub fn peak_payload_acceleration_mps2(&self) -> f64 {
        self.peak_payload_acceleration_mps2
    }

    /// Borrow the columns in the form [`crate::metrics::compute`] takes.
    pub fn series(&self) -> crate::metrics::Series<'_> {
        crate::metrics::Series {
            t_s: &self.t_s,
            vz_mps: &self.vz_mps,
            vx_mps: &self.vx_mps,
            vy_mps: &self.vy_mps,
            extended_height_m: &self.extended_height_m,
            drag_z_n: &self.drag_z_n,
            exact_max_extended_height_m: (!self.is_empty()).then_some(self.max_extended_height_m),
        }
    }

    /// Borrow the columns and peaks the recovery metrics take
    /// ([`crate::metrics::descent::compute`]).
    pub fn recovery_series(&self) -> crate::metrics::descent::RecoverySeries<'_> {
        crate::metrics::descent::RecoverySeries {
            t_s: &self.t_s,
            vz_mps: &self.vz_mps,
            drag_z_n: &self.drag_z_n,
            z_m: &self.z_m,
            z_payload_m: &self.z_payload_m,
            line_tension_n: &self.line_tension_n,
            axis_angle_deg: &self.axis_angle_deg,
            canopy_diameter_m: &self.canopy_diameter_m,
            peak_line_tension: self.peak_line_tension,
            peak_payload_acceleration_mps2: self.peak_payload_acceleration_mps2,
        }
    }
}

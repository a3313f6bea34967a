//! Checkpoints: everything a run needs to continue bit-for-bit from a saved point.
//!
//! A checkpoint (`checkpoint.bin` in the run directory) holds the engine state (q, v, t), the
//! history of every force ([`engine::Force::history`]: DER reference frames and reference
//! twists), the run loop's counters and schedules (the step-size policy's state — the next
//! step size or adaptive proposal, success streak, cap after a Newton failure, rejection
//! counts —, step and iteration counts, next frame, snapshot and sync indices, warnings) and
//! the number of rows of `timeseries.csv` at that state. The in-memory decimated series and
//! the step-size statistics are not stored: on resume they are rebuilt by re-reading those
//! rows, which `{}` formatting wrote with exact round-trip precision, so they are
//! bit-identical to the ones the uninterrupted run holds.
//!
//! File format (little-endian): the magic `CHUTECKP`, a format version (u32), the fields in
//! the order of [`Checkpoint::encode`] (u64 lengths before vectors and UTF-8 strings, f64 as
//! IEEE-754 bits), and an FNV-1a-64 checksum of all preceding bytes. Files are written
//! atomically, so a checkpoint is either the previous one or the new one, never a mix; a
//! truncated or corrupted file is rejected with a clear error.
//!
//! Versions: 2 (adaptive time steps) appends the cap and the two rejection counters after the
//! warnings; 3 (`chute resume DIR`) appends the run's checkpoint interval (0 for none), so a
//! resumed run keeps checkpointing as the original did. Version 1 files (fixed steps only)
//! are still read: no cap, no error rejections, and the Newton rejections counted from the
//! "step rejected" warnings (exact up to the 20 warnings kept, a lower bound beyond);
//! versions 1 and 2 record no checkpoint interval. 4 (solver counters in `summary.json`)
//! appends the Newton solves' counters accumulated so far
//! ([`crate::output::summary::SolverCounters`]): a u64 flag (1 when they are known for the
//! whole run so far, 0 when the run was resumed from a checkpoint without them), then the 18
//! counts (u64) and the 4 times (f64, s) in the order of `SolverCounters::counts` and
//! `SolverCounters::seconds` (zeros when unknown). Versions 1 to 3 record no counters: a run
//! resumed from one reports `"solver": null` with a warning, and so do its later checkpoints.
//! 5 (the exact retry's step homotopy) has 20 counts: `homotopies` and
//! `homotopies_converged` after `continuations_converged`; a version-4 file reads them as 0,
//! which is exact (the build that wrote it had no homotopy stage). 6 (the exact retry's
//! ledger) has 21 counts: `exact_retries_skipped` last; versions 4 and 5 read it as 0, which
//! is exact (their builds never skipped a retry). 7 (the step solver's ladder of stages, with
//! other counters) stores the flag and then the counters ([`engine::Counters`]) as one JSON
//! string, which names every field; the counters of versions 4 to 6 belong to the earlier
//! solver and are read as unknown.

use std::io::{self, BufRead};
use std::path::{Path, PathBuf};

use crate::output::summary::SolverCounters;
use crate::output::timeseries::Sample;
use crate::output::write_atomic;

/// File name of the checkpoint inside a run directory.
pub const FILE_NAME: &str = "checkpoint.bin";
const MAGIC: &[u8; 8] = b"CHUTECKP";
/// Version of the binary layout; bump on any change.
pub const FORMAT_VERSION: u32 = 7;
/// Counts and times of the earlier solver's counters in versions 4, 5 and 6 (skipped).
const OLD_COUNTS: [usize; 3] = [18, 20, 21];
const OLD_TIMES: usize = 4;
/// The first version written only beside a `run.json` (the run's record of its inputs): a
/// directory holding such a checkpoint and no record had its record deleted.
pub const FIRST_WITH_RECORD: u32 = 7;
/// The oldest version this build reads.
const OLDEST_READABLE: u32 = 1;

/// A saved point of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct Checkpoint {
    /// The resolved scenario TOML the run was started with (resume checks it matches).
    pub scenario_toml: String,
    /// Whether the point is a sync point (factorisation refreshed there in every run), so
    /// that resuming from it reproduces the uninterrupted run bit for bit.
    pub synced: bool,
    /// Simulated time (s).
    pub t: f64,
    /// Generalised coordinates (m, rad).
    pub q: Vec<f64>,
    /// Generalised velocities (m/s, rad/s).
    pub v: Vec<f64>,
    /// [`engine::Force::history`] of every force of the model, in model order.
    pub histories: Vec<Vec<f64>>,
    /// Size the next step tries (s): fixed, the current step, possibly reduced after
    /// failures; adaptive, the controller's proposal (before shortening to an event).
    pub dt: f64,
    /// Consecutive accepted steps since the last failure or regrowth.
    pub streak: u32,
    /// Adaptive: ceiling on the step after a failed Newton solve (s; +∞ when none).
    pub dt_cap: f64,
    /// Steps rejected for their local error so far.
    pub rejected_error: u64,
    /// Steps rejected because Newton failed so far.
    pub rejected_newton: u64,
    /// Accepted steps so far.
    pub steps: u64,
    /// Newton iterations so far.
    pub newton_iterations: u64,
    /// Wall-clock time spent so far (s).
    pub wall_time_s: f64,
    /// Data rows of `timeseries.csv` at this state (the header not counted).
    pub ts_rows: u64,
    /// Times of the VTK frames written so far (s).
    pub frame_times: Vec<f64>,
    /// Time of the next VTK frame (s).
    pub next_frame: f64,
    /// Index of the next snapshot to draw (into the sorted snapshot times).
    pub snap_idx: u64,
    /// Index `k` of the next sync point, at simulated time `k · sync interval`.
    pub next_sync: u64,
    /// Run-loop warnings so far.
    pub warnings: Vec<String>,
    /// The run's `--checkpoint-every` interval (s), which `chute resume` keeps using.
    pub checkpoint_every_s: Option<f64>,
    /// The Newton solves' counters and times so far; `None` when they are not known for
    /// the whole run so far (it was resumed from a checkpoint older than version 4).
    pub solver: Option<SolverCounters>,
}

/// Why a checkpoint could not be used.
#[derive(Debug, thiserror::Error)]
pub enum CheckpointError {
    /// Reading or writing failed.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: io::Error,
    },
    /// The file is not a valid checkpoint.
    #[error("{}: not a valid chute checkpoint: {reason}", path.display())]
    Invalid {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        reason: String,
    },
    /// A file of the run (`timeseries.csv`) does not hold what the checkpoint says it does.
    #[error("{}: does not match the run's checkpoint: {reason}", path.display())]
    Mismatch {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        reason: String,
    },
}

/// 64-bit FNV-1a: a cheap checksum that catches truncation and bit rot (not tampering).
fn fnv1a(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

struct Enc(Vec<u8>);

impl Enc {
    fn u64(&mut self, x: u64) {
        self.0.extend_from_slice(&x.to_le_bytes());
    }
    fn f64(&mut self, x: f64) {
        self.u64(x.to_bits());
    }
    fn f64s(&mut self, v: &[f64]) {
        self.u64(v.len() as u64);
        v.iter().for_each(|&x| self.f64(x));
    }
    fn str(&mut self, s: &str) {
        self.u64(s.len() as u64);
        self.0.extend_from_slice(s.as_bytes());
    }
}

struct Dec<'a> {
    b: &'a [u8],
    at: usize,
}

impl Dec<'_> {
    fn take(&mut self, n: usize) -> Result<&[u8], String> {
        let end = self.at.checked_add(n).filter(|&e| e <= self.b.len());
        let end = end.ok_or_else(|| format!("truncated at byte {}", self.at))?;
        let s = &self.b[self.at..end];
        self.at = end;
        Ok(s)
    }
    fn u64(&mut self) -> Result<u64, String> {
        let mut a = [0u8; 8];
        a.copy_from_slice(self.take(8)?);
        Ok(u64::from_le_bytes(a))
    }
    fn f64(&mut self) -> Result<f64, String> {
        Ok(f64::from_bits(self.u64()?))
    }
    /// A length, checked against the bytes left so a corrupted length cannot allocate.
    fn len(&mut self, item_bytes: usize) -> Result<usize, String> {
        let n = self.u64()?;
        let left = (self.b.len() - self.at) as u64;
        if n.saturating_mul(item_bytes as u64) > left {
            return Err(format!("length {n} at byte {} exceeds the file", self.at));
        }
        Ok(n as usize)
    }
    fn f64s(&mut self) -> Result<Vec<f64>, String> {
        let n = self.len(8)?;
        (0..n).map(|_| self.f64()).collect()
    }
    fn str(&mut self) -> Result<String, String> {
        let n = self.len(1)?;
        String::from_utf8(self.take(n)?.to_vec()).map_err(|e| e.to_string())
    }
    /// The solver counters: the known flag, then (version 7) their JSON, or (versions 4 to
    /// 6, the earlier solver's) counts and times that are skipped.
    fn solver(&mut self, version: u32) -> Result<Option<SolverCounters>, String> {
        let known = match self.u64()? {
            0 => false,
            1 => true,
            k => return Err(format!("solver-counters flag {k}, not 0 or 1")),
        };
        if version < 7 {
            for _ in 0..OLD_COUNTS[version as usize - 4] + OLD_TIMES {
                self.u64()?;
            }
            return Ok(None);
        }
        let json = self.str()?;
        let counters = serde_json::from_str(&json).map_err(|e| format!("solver counters: {e}"))?;
        Ok(known.then_some(counters))
    }
}

impl Checkpoint {
    /// The binary form (see the module docs).
    pub fn encode(&self) -> Vec<u8> {
        let mut e = Enc(Vec::with_capacity(64 + 8 * (self.q.len() + self.v.len())));
        e.0.extend_from_slice(MAGIC);
        e.0.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
        e.str(&self.scenario_toml);
        e.u64(u64::from(self.synced));
        e.f64(self.t);
        e.f64s(&self.q);
        e.f64s(&self.v);
        e.u64(self.histories.len() as u64);
        self.histories.iter().for_each(|h| e.f64s(h));
        e.f64(self.dt);
        e.u64(u64::from(self.streak));
        e.u64(self.steps);
        e.u64(self.newton_iterations);
        e.f64(self.wall_time_s);
        e.u64(self.ts_rows);
        e.f64s(&self.frame_times);
        e.f64(self.next_frame);
        e.u64(self.snap_idx);
        e.u64(self.next_sync);
        e.u64(self.warnings.len() as u64);
        self.warnings.iter().for_each(|w| e.str(w));
        e.f64(self.dt_cap);
        e.u64(self.rejected_error);
        e.u64(self.rejected_newton);
        e.f64(self.checkpoint_every_s.unwrap_or(0.0));
        e.u64(u64::from(self.solver.is_some()));
        let solver = self.solver.unwrap_or_default();
        e.str(&serde_json::to_string(&solver).expect("counters serialise"));
        let sum = fnv1a(&e.0);
        e.u64(sum);
        e.0
    }

    /// Parse the binary form; the error says what is wrong.
    pub fn decode(bytes: &[u8]) -> Result<Self, String> {
        if bytes.len() < 20 || &bytes[..8] != MAGIC {
            return Err("missing the CHUTECKP header".into());
        }
        let (body, sum) = bytes.split_at(bytes.len() - 8);
        let mut s = [0u8; 8];
        s.copy_from_slice(sum);
        if fnv1a(body) != u64::from_le_bytes(s) {
            return Err("checksum mismatch (truncated or corrupted file)".into());
        }
        let mut v = [0u8; 4];
        v.copy_from_slice(&body[8..12]);
        let version = u32::from_le_bytes(v);
        if !(OLDEST_READABLE..=FORMAT_VERSION).contains(&version) {
            return Err(format!(
                "format version {version}, this chute reads versions {OLDEST_READABLE} to {FORMAT_VERSION}"
            ));
        }
        let mut d = Dec { b: body, at: 12 };
        let scenario_toml = d.str()?;
        let synced = d.u64()? != 0;
        let t = d.f64()?;
        let (q, v) = (d.f64s()?, d.f64s()?);
        let n_hist = d.len(8)?;
        let histories = (0..n_hist).map(|_| d.f64s()).collect::<Result<_, _>>()?;
        let dt = d.f64()?;
        let streak = u32::try_from(d.u64()?).map_err(|e| e.to_string())?;
        let (steps, newton_iterations) = (d.u64()?, d.u64()?);
        let wall_time_s = d.f64()?;
        let ts_rows = d.u64()?;
        let frame_times = d.f64s()?;
        let next_frame = d.f64()?;
        let (snap_idx, next_sync) = (d.u64()?, d.u64()?);
        let n_warn = d.len(8)?;
        let warnings: Vec<String> = (0..n_warn).map(|_| d.str()).collect::<Result<_, _>>()?;
        let (dt_cap, rejected_error, rejected_newton) = if version >= 2 {
            (d.f64()?, d.u64()?, d.u64()?)
        } else {
            let newton = warnings
                .iter()
                .filter(|w| w.starts_with("step rejected at"))
                .count();
            (f64::INFINITY, 0, newton as u64)
        };
        let every = if version >= 3 { d.f64()? } else { 0.0 };
        let checkpoint_every_s = (every > 0.0 && every.is_finite()).then_some(every);
        let solver = if version >= 4 {
            d.solver(version)?
        } else {
            None
        };
        if d.at != body.len() {
            return Err(format!("{} unexpected trailing bytes", body.len() - d.at));
        }
        Ok(Self {
            scenario_toml,
            synced,
            t,
            q,
            v,
            histories,
            dt,
            streak,
            dt_cap,
            rejected_error,
            rejected_newton,
            steps,
            newton_iterations,
            wall_time_s,
            ts_rows,
            frame_times,
            next_frame,
            snap_idx,
            next_sync,
            warnings,
            checkpoint_every_s,
            solver,
        })
    }

    /// Write `dir/checkpoint.bin` atomically.
    pub fn write(&self, dir: &Path) -> Result<(), CheckpointError> {
        let path = dir.join(FILE_NAME);
        write_atomic(&path, &self.encode()).map_err(|source| CheckpointError::Io { path, source })
    }

    /// Read `dir/checkpoint.bin`.
    pub fn read(dir: &Path) -> Result<Self, CheckpointError> {
        Self::read_versioned(dir).map(|(c, _)| c)
    }

    /// [`Checkpoint::read`], with the file's format version.
    pub fn read_versioned(dir: &Path) -> Result<(Self, u32), CheckpointError> {
        let path = dir.join(FILE_NAME);
        let bytes =
            crate::output::atomic::read_own(&path).map_err(|source| CheckpointError::Io {
                path: path.clone(),
                source,
            })?;
        let c = Self::decode(&bytes).map_err(|reason| CheckpointError::Invalid { path, reason })?;
        // `decode` checked the header: the version is bytes 8..12.
        let version = u32::from_le_bytes([bytes[8], bytes[9], bytes[10], bytes[11]]);
        Ok((c, version))
    }

    /// Check that this checkpoint fits a model of `n_dofs` DOFs and `n_forces` forces.
    pub fn check_shape(&self, n_dofs: usize, n_forces: usize) -> Result<(), String> {
        if self.q.len() != n_dofs || self.v.len() != n_dofs {
            return Err(format!(
                "the checkpoint has {} DOFs, the model {n_dofs}",
                self.q.len()
            ));
        }
        if self.histories.len() != n_forces {
            return Err(format!(
                "the checkpoint has {} force families, the model {n_forces}",
                self.histories.len()
            ));
        }
        if self.q.iter().chain(&self.v).any(|x| !x.is_finite()) || !self.t.is_finite() {
            return Err("the checkpoint state is not finite".into());
        }
        if !(self.dt > 0.0 && self.dt.is_finite() && self.dt_cap > 0.0) {
            return Err(format!(
                "the checkpoint's step size {} s (cap {} s) is not positive",
                self.dt, self.dt_cap
            ));
        }
        Ok(())
    }
}

/// Cut `timeseries.csv` back to its header and first `rows` data rows (a run interrupted
/// after its checkpoint wrote more), and return those rows' samples so the in-memory series
/// can be rebuilt. Errors if the file has fewer rows or a malformed one.
pub fn truncate_timeseries(path: &Path, rows: u64) -> Result<Vec<Sample>, CheckpointError> {
    let (samples, keep) = timeseries_prefix(path, rows)?;
    let io_err = |source| CheckpointError::Io {
        path: path.to_path_buf(),
        source,
    };
    // A new file renamed over the old one, not the old one cut in place: a directory copied
    // with hard links (`cp -al`) shares its files with the original, which must not change.
    let bytes = crate::output::atomic::read_own(path).map_err(io_err)?;
    let keep = (keep as usize).min(bytes.len());
    crate::output::atomic::write_atomic(path, &bytes[..keep]).map_err(io_err)?;
    Ok(samples)
}

/// The samples of the first `rows` data rows of `timeseries.csv` and the bytes they take
/// with the header, without changing the file: errors as [`truncate_timeseries`].
pub fn timeseries_prefix(path: &Path, rows: u64) -> Result<(Vec<Sample>, u64), CheckpointError> {
    let invalid = |reason: String| CheckpointError::Mismatch {
        path: path.to_path_buf(),
        reason,
    };
    let io_err = |source| CheckpointError::Io {
        path: path.to_path_buf(),
        source,
    };
    let file = crate::output::atomic::open_own(path).map_err(io_err)?;
    let mut reader = io::BufReader::new(file);
    let mut line = String::new();
    let mut keep: u64 = 0;
    let mut text = String::new();
    for i in 0..=rows {
        line.clear();
        let n = reader.read_line(&mut line).map_err(io_err)?;
        if n == 0 || !line.ends_with('\n') {
            return Err(invalid(format!(
                "has {} complete rows, the checkpoint needs {rows}",
                i.saturating_sub(1)
            )));
        }
        keep += n as u64;
        text.push_str(&line);
    }
    let mut rdr = csv::Reader::from_reader(text.as_bytes());
    let samples = rdr
        .deserialize::<Sample>()
        .enumerate()
        .map(|(i, r)| r.map_err(|e| invalid(format!("row {}: {e}", i + 1))))
        .collect::<Result<Vec<_>, _>>()?;
    Ok((samples, keep))
}

#[cfg(test)]
mod tests;

//! The run loop's persistence: checkpoints of its state, resuming from one, and clearing an
//! earlier run's outputs (docs/reliability.md §2).

use std::path::Path;
use std::time::Instant;

use super::dt_policy::DtStats;
use super::{io_err, Run, RunConfig, RunControl, RunError};
use crate::build::Built;
use crate::checkpoint::{self, Checkpoint};
use crate::output::timeseries::TimeSeriesWriter;
use crate::output::vtk::VtkSeries;

impl Run {
    /// The run state of checkpoint `c`, with `timeseries.csv` cut back to its rows and the
    /// frames after it removed; the model's force histories are restored.
    pub(super) fn resume(
        built: &mut Built,
        cfg: &RunConfig,
        out_dir: &Path,
        c: &Checkpoint,
    ) -> Result<Self, RunError> {
        let bad = |reason: String| RunError::Checkpoint(reason);
        check_resumable(built, out_dir, c)?;
        for (f, h) in built.model.forces.iter_mut().zip(&c.histories) {
            f.restore_history(h).map_err(|e| bad(e.to_string()))?;
        }
        // All or nothing: the frames after the checkpoint are moved aside (put back if one
        // cannot be), then the time series is cut back by a new file renamed over the old
        // one (the frames put back if that fails, a full disk), and only then are the moved
        // frames removed: a resume that fails here leaves the stopped run as it was.
        let later = crate::output::vtk::later_frames(out_dir, c.frame_times.len())
            .map_err(io_err(out_dir))?;
        let moved =
            crate::output::trash::Trash::take_all(out_dir, &later).map_err(|e| RunError::Io {
                path: out_dir.join(crate::output::vtk::FRAMES_DIR),
                source: e,
            })?;
        let ts_path = out_dir.join("timeseries.csv");
        let rows = match checkpoint::truncate_timeseries(&ts_path, c.ts_rows) {
            Ok(rows) => rows,
            Err(e) => {
                moved.restore();
                return Err(match e {
                    checkpoint::CheckpointError::Io { path, source } => {
                        RunError::Io { path, source }
                    }
                    e => bad(e.to_string()),
                });
            }
        };
        moved.empty();
        let ts = TimeSeriesWriter::append_to(&ts_path, c.ts_rows).map_err(io_err(&ts_path))?;
        let vtk = VtkSeries::resume(out_dir, &c.frame_times)?;
        let mut run = Self::blank(built, cfg, out_dir, ts, vtk, Some(c.t))?;
        built.state = engine::State {
            q: c.q.clone(),
            v: c.v.clone(),
            t: c.t,
        };
        let f = &mut run.flight;
        rows.iter().for_each(|s| f.dec.push(s));
        f.dt.sizes.state = engine::stepper::SizeState {
            h: c.dt,
            cap: c.dt_cap,
            streak: c.streak,
            rejected_error: c.rejected_error,
            rejected_newton: c.rejected_newton,
        };
        f.dt.used = DtStats::from_rows(&rows);
        f.steps = c.steps;
        f.newton_total = c.newton_iterations;
        f.warnings = c.warnings.clone();
        f.next_frame = c.next_frame;
        f.snap_idx = (c.snap_idx as usize).min(f.snaps.len());
        f.next_sync = c.next_sync;
        f.solver_before = c.solver;
        run.wall_before_s = c.wall_time_s;
        Ok(run)
    }

    /// The checkpoint of the current state; `counters` are the stepper's since the start or
    /// resume.
    pub(super) fn checkpoint(
        &self,
        built: &Built,
        ctl: &RunControl<'_>,
        wall: &Instant,
        counters: &engine::Counters,
        synced: bool,
    ) -> Checkpoint {
        let f = &self.flight;
        Checkpoint {
            scenario_toml: ctl.scenario_toml.clone(),
            synced,
            t: built.state.t,
            q: built.state.q.clone(),
            v: built.state.v.clone(),
            histories: built.model.forces.iter().map(|f| f.history()).collect(),
            dt: f.dt.sizes.state.h,
            streak: f.dt.sizes.state.streak,
            dt_cap: f.dt.sizes.state.cap,
            rejected_error: f.dt.sizes.state.rejected_error,
            rejected_newton: f.dt.sizes.state.rejected_newton,
            steps: f.steps,
            newton_iterations: f.newton_total,
            wall_time_s: self.wall_before_s + wall.elapsed().as_secs_f64(),
            ts_rows: self.ts.rows(),
            frame_times: self.vtk.times(),
            next_frame: f.next_frame,
            snap_idx: f.snap_idx as u64,
            next_sync: f.next_sync,
            warnings: f.warnings.clone(),
            checkpoint_every_s: ctl.checkpoint_every_s,
            solver: f.solver(counters),
        }
    }

    /// Write `c` after making every time-series row it counts durable.
    pub(super) fn save(&mut self, c: &Checkpoint, out_dir: &Path) -> Result<(), RunError> {
        self.ts.flush().map_err(io_err(&self.ts_path))?;
        c.write(out_dir)
            .map_err(|e| RunError::Checkpoint(e.to_string()))
    }
}

/// Whether `out_dir` can be resumed from `c` with the model of `built`, judged without
/// changing anything: the checkpoint's shape fits the model, and the time series and the
/// frames it counts are all there. A resume refused for any of these leaves the directory as
/// it was.
pub fn check_resumable(built: &Built, out_dir: &Path, c: &Checkpoint) -> Result<(), RunError> {
    let bad = |reason: String| RunError::Checkpoint(reason);
    c.check_shape(built.model.n_dofs(), built.model.forces.len())
        .map_err(bad)?;
    // A resumed run appends to and rewrites its files in place: never through a link.
    for entry in std::fs::read_dir(out_dir).map_err(super::io_err(out_dir))? {
        let entry = entry.map_err(super::io_err(out_dir))?;
        let name = entry.file_name();
        let linked = entry.file_type().is_ok_and(|t| t.is_symlink());
        if linked && crate::output::run_files::is_run_file(&name.to_string_lossy()) {
            return Err(bad(format!(
                "`{}` is a symbolic link: a resumed run writes its files in place, never through a link; run the scenario again",
                entry.path().display()
            )));
        }
    }
    let ts_path = out_dir.join("timeseries.csv");
    let (rows, _) =
        checkpoint::timeseries_prefix(&ts_path, c.ts_rows).map_err(|e| bad(e.to_string()))?;
    // The time series must end where the checkpoint is: a row of every accepted step, the
    // last at the checkpoint's time and state (a checkpoint of another run copied in with its
    // scenario would continue that run over this one's rows).
    let mut obs = super::observe::Observer::new(built);
    let here = obs.canopy_height(built, &c.q, &c.v);
    if let (Some(last), Some((z, vz))) = (rows.last(), here) {
        if (last.t_s, last.z_m, last.vz_mps) != (c.t, z, vz) {
            return Err(bad(format!(
                "`{}` ends at t = {} s, z = {} m, but the checkpoint is at t = {} s, z = {} m: they are not of one run; run the scenario again",
                ts_path.display(),
                last.t_s,
                last.z_m,
                c.t,
                z
            )));
        }
    }
    // Pulled lines: `lines.csv` and `track.csv` hold a row at every frame, so each must reach
    // the checkpoint's last frame (a file lost or cut back would lose those rows for good).
    let lines = built.lines.as_ref().map(|l| &l.lines);
    if let Some(lines) = lines.filter(|l| l.iter().any(|x| x.schedule.is_some())) {
        let last = c.frame_times.last().copied();
        crate::output::control_files::check_resumable(out_dir, last, lines.len()).map_err(bad)?;
    }
    // A resumed run lists the frames the checkpoint counts in `canopy.pvd`: a directory
    // missing one is not the run that was stopped.
    for i in 0..c.frame_times.len() {
        let f = out_dir.join(crate::output::vtk::frame_name(i));
        let meta = std::fs::symlink_metadata(&f);
        if meta.as_ref().is_ok_and(|m| m.file_type().is_symlink()) {
            return Err(bad(format!(
                "`{}` is a symbolic link: a run's frames are its own files; run the scenario again",
                f.display()
            )));
        }
        if !meta.is_ok_and(|m| m.is_file()) {
            return Err(bad(format!(
                "`{}` of the stopped run is missing: the run directory changed since; run the scenario again",
                f.display()
            )));
        }
    }
    // The frames after the checkpoint are removed: each must be a file (a directory named
    // like one would stop the resume half-way).
    let later = crate::output::vtk::later_frames(out_dir, c.frame_times.len())
        .map_err(super::io_err(out_dir))?;
    if let Some(d) = later
        .iter()
        .find(|p| p.symlink_metadata().is_ok_and(|m| m.is_dir()))
    {
        return Err(bad(format!(
            "`{}` is a directory where the stopped run's later frame was: a resumed run removes that frame and cannot; remove it, or run the scenario again",
            d.display()
        )));
    }
    Ok(())
}

/// Remove whatever an earlier run left in `out_dir` besides what this run has started
/// (its record, resolved scenario, time series, frames and their collection), so that
/// nothing in the directory can be mistaken for this run's output (the registry:
/// [`crate::output::run_files`]).
pub(super) fn remove_stale_outputs(out_dir: &Path) -> Result<(), RunError> {
    use crate::output::run_files::{self, RESOLVED_SCENARIO, RUN_RECORD, TIMESERIES};
    use crate::output::vtk::PVD_NAME;
    let started = [RESOLVED_SCENARIO, RUN_RECORD, TIMESERIES, PVD_NAME];
    run_files::clear_top_except(out_dir, &started).map_err(io_err(out_dir))
}

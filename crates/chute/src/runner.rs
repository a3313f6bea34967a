//! The run loop: step the model, observe it, stream outputs, recover from failed steps.
//!
//! Failure policy (docs/reliability.md): a step whose Newton solve fails or produces a
//! non-finite value is rejected (state unchanged), `dt` is halved and the step retried;
//! after [`GROW_AFTER`] consecutive successes `dt` doubles back towards the scenario's `dt`.
//! Below `min_dt` the run stops: the summary is marked incomplete with the reason, and the
//! time series and frames written so far stay valid, and `checkpoint.bin` holds the last good
//! state.
//!
//! Checkpoints and determinism: every [`SYNC_STEPS`] nominal steps of simulated time the loop
//! drops the stepper's reused factorisation (a *sync point*, in every run, checkpointing or
//! not). Checkpoints are taken only at sync points (except the last-good-state one of a failed
//! run), and a resumed stepper starts without a factorisation too, so a resumed run is
//! bit-identical to an uninterrupted one. A stop request (Ctrl-C / SIGTERM via [`STOP`])
//! writes the last sync point's checkpoint and ends with valid partial outputs.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use engine::{ImplicitEuler, NewtonOptions, StepError};

use crate::build::Built;
use crate::checkpoint::{self, Checkpoint};
use crate::metrics;
use crate::output::plots;
use crate::output::summary::{RunInfo, Summary};
use crate::output::timeseries::{DecimatedSeries, TimeSeriesWriter};
use crate::output::vtk::VtkSeries;

mod observe;
use observe::Observer;

/// Consecutive accepted steps before a reduced `dt` is doubled again.
pub const GROW_AFTER: u32 = 8;

/// Everything the loop needs besides the model.
#[derive(Debug, Clone)]
pub struct RunConfig {
    /// Scenario name (for the summary).
    pub name: String,
    /// Nominal time step (s).
    pub dt_s: f64,
    /// Smallest time step before giving up (s).
    pub min_dt_s: f64,
    /// Simulated duration (s).
    pub duration_s: f64,
    /// Interval between VTK frames (s); 0 disables frames.
    pub frame_interval_s: f64,
    /// Times at which snapshot PNGs are drawn (s).
    pub snapshots_s: Vec<f64>,
    /// Newton settings.
    pub newton: NewtonOptions,
    /// Air density (kg/m³) and viscosity (Pa·s) for the metrics.
    pub air_density: f64,
    /// Dynamic viscosity (Pa·s).
    pub air_viscosity: f64,
    /// Whether drag is quadratic (regime warning).
    pub quadratic_drag: bool,
    /// Show a progress bar.
    pub progress: bool,
}

/// How a run ended.
#[derive(Debug)]
pub struct RunResult {
    /// The summary as written to `summary.json`.
    pub summary: Summary,
    /// Whether the requested duration was simulated.
    pub complete: bool,
    /// Why it stopped early.
    pub stop_reason: Option<String>,
}

/// Errors that prevent a run from producing its outputs at all.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// The engine rejected the model.
    #[error("model: {0}")]
    Engine(#[from] engine::EngineError),
    /// The checkpoint to resume from does not fit, or one could not be written.
    #[error("checkpoint: {0}")]
    Checkpoint(String),
    /// An output file could not be written.
    #[error("writing {path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
}

fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> RunError + '_ {
    move |source| RunError::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// Human-readable location of a DOF.
pub fn describe_dof(b: &Built, dof: usize) -> String {
    let n = b.model.layout.n_nodes;
    if dof < 3 * n {
        format!("node {} {}", dof / 3, ["x", "y", "z"][dof % 3])
    } else {
        format!("twist of rod edge {}", dof - 3 * n)
    }
}

/// Accepted steps' worth of nominal `dt` between *sync points*. At every sync point the run
/// loop drops the stepper's reused factorisation (modified Newton), so the next step starts
/// with a fresh Jacobian exactly as a resumed run does: checkpoints are only taken at sync
/// points, which makes a resumed run bit-identical to an uninterrupted one. One extra
/// factorisation every 64 steps costs ~1 % at most.
pub const SYNC_STEPS: f64 = 64.0;

/// Set by the Ctrl-C / SIGTERM handler of the binary: every run loop in the process stops
/// gracefully at its next step (with a checkpoint and valid partial outputs).
pub static STOP: AtomicBool = AtomicBool::new(false);

/// How a run is driven besides its configuration: stop flag, checkpoints, resume.
#[derive(Debug)]
pub struct RunControl<'a> {
    /// Graceful stop request (checked before every step).
    pub stop: &'a AtomicBool,
    /// Write `checkpoint.bin` at the first sync point after every multiple of this many
    /// simulated seconds.
    pub checkpoint_every_s: Option<f64>,
    /// Continue from this checkpoint (its outputs must be in `out_dir`).
    pub resume: Option<Checkpoint>,
    /// The resolved scenario, stored in checkpoints so a resume can check it.
    pub scenario_toml: String,
}

/// Run `built` for `cfg.duration_s`, writing every output into `out_dir` (which must exist).
/// `stop` requests a graceful early stop (Ctrl-C / SIGTERM).
pub fn simulate(
    built: &mut Built,
    cfg: &RunConfig,
    out_dir: &Path,
    stop: &AtomicBool,
) -> Result<RunResult, RunError> {
    let ctl = RunControl {
        stop,
        checkpoint_every_s: None,
        resume: None,
        scenario_toml: String::new(),
    };
    simulate_with(built, cfg, out_dir, &ctl)
}

/// [`simulate`] with checkpoints and resume (see [`RunControl`] and `docs/reliability.md`).
///
/// A checkpoint is written at the first sync point after every `checkpoint_every_s`; on a
/// stop request the last sync point's checkpoint is written (so resuming from it is
/// bit-identical; at most [`SYNC_STEPS`] steps are redone); when a step fails below
/// `min_dt` the last good state is checkpointed (marked not synced) for inspection.
pub fn simulate_with(
    built: &mut Built,
    cfg: &RunConfig,
    out_dir: &Path,
    ctl: &RunControl<'_>,
) -> Result<RunResult, RunError> {
    let wall = Instant::now();
    let mut stepper = ImplicitEuler::new(&built.model, cfg.newton)?;
    let mut run = match &ctl.resume {
        None => Run::fresh(built, cfg, out_dir)?,
        Some(c) => Run::resume(built, cfg, out_dir, c)?,
    };
    let bar = progress_bar(cfg);
    let sync_dt = SYNC_STEPS * cfg.dt_s;
    let eps_t = 1e-9 * cfg.dt_s;
    let next_multiple = |every: f64, t: f64| ((t + eps_t) / every).floor() as u64 + 1;
    let mut next_ckpt = ctl
        .checkpoint_every_s
        .map(|s| next_multiple(s, run.state.t));
    // The start (fresh or resumed) is a sync point: the stepper holds no factorisation.
    let mut last_sync = run.checkpoint(built, ctl, &wall, true);
    let mut stop_reason = None;
    while run.state.t < cfg.duration_s - eps_t {
        if ctl.stop.load(Ordering::Relaxed) {
            stop_reason = Some(format!(
                "interrupted at t = {:.6} s; checkpoint at t = {:.6} s",
                run.state.t, last_sync.t
            ));
            run.save(&last_sync, out_dir)?;
            break;
        }
        let h = run.dt.min(cfg.duration_s - run.state.t);
        match stepper.step(&mut built.model, &mut run.state, h) {
            Ok(rep) => {
                run.accept(built, cfg, out_dir, rep.iterations, h)?;
                if let Some(bar) = &bar {
                    bar.set_position((run.state.t / cfg.duration_s * 1000.0) as u64);
                    let rate = run.steps as f64 / wall.elapsed().as_secs_f64().max(1e-9);
                    bar.set_message(format!(
                        "t = {:.3} s, {rate:.0} steps/s, {} Newton it/step",
                        run.state.t, rep.iterations
                    ));
                }
                if run.state.t < run.next_sync as f64 * sync_dt - eps_t {
                    continue;
                }
                stepper.invalidate_factorization();
                run.next_sync = next_multiple(sync_dt, run.state.t);
                last_sync = run.checkpoint(built, ctl, &wall, true);
                if let (Some(k), Some(every)) = (next_ckpt, ctl.checkpoint_every_s) {
                    if run.state.t >= k as f64 * every - eps_t {
                        run.save(&last_sync, out_dir)?;
                        next_ckpt = Some(next_multiple(every, run.state.t));
                    }
                }
            }
            Err(e) => {
                if let Some(reason) = run.reject(built, cfg, &e) {
                    stop_reason = Some(reason);
                    let good = run.checkpoint(built, ctl, &wall, false);
                    run.save(&good, out_dir)?;
                    break;
                }
            }
        }
    }
    if let Some(bar) = &bar {
        bar.finish_and_clear();
    }
    run.finish(built, cfg, out_dir, stop_reason, &wall)
}

/// The run loop's mutable state and open outputs: what a checkpoint saves and restores.
struct Run {
    state: engine::State,
    dt: f64,
    streak: u32,
    steps: u64,
    newton_total: u64,
    warnings: Vec<String>,
    next_frame: f64,
    snaps: Vec<f64>,
    snap_idx: usize,
    next_sync: u64,
    wall_before_s: f64,
    ts_path: PathBuf,
    ts: TimeSeriesWriter,
    dec: DecimatedSeries,
    vtk: VtkSeries,
    obs: Observer,
}

impl Run {
    fn blank(
        built: &Built,
        cfg: &RunConfig,
        out_dir: &Path,
        ts: TimeSeriesWriter,
        vtk: VtkSeries,
    ) -> Self {
        let mut snaps = cfg.snapshots_s.clone();
        snaps.sort_by(f64::total_cmp);
        Self {
            state: built.state.clone(),
            dt: cfg.dt_s,
            streak: 0,
            steps: 0,
            newton_total: 0,
            warnings: Vec::new(),
            next_frame: 0.0,
            snaps,
            snap_idx: 0,
            next_sync: 1,
            wall_before_s: 0.0,
            ts_path: out_dir.join("timeseries.csv"),
            ts,
            dec: DecimatedSeries::default(),
            vtk,
            obs: Observer::new(built),
        }
    }

    fn fresh(built: &Built, cfg: &RunConfig, out_dir: &Path) -> Result<Self, RunError> {
        let ts_path = out_dir.join("timeseries.csv");
        let ts = TimeSeriesWriter::create(&ts_path).map_err(io_err(&ts_path))?;
        // With --force over an earlier run: its frames and checkpoint must not be mistaken for
        // this run's (resuming needs matching rows and frames).
        let vtk = VtkSeries::resume(out_dir, &[]).map_err(io_err(out_dir))?;
        remove_stale_outputs(out_dir)?;
        let mut run = Self::blank(built, cfg, out_dir, ts, vtk);
        let s0 = run.obs.sample(built, &run.state, 0, cfg.dt_s);
        run.ts.push(&s0).map_err(io_err(&ts_path))?;
        run.dec.push(&s0);
        run.write_due_outputs(built, cfg, out_dir)?;
        Ok(run)
    }

    fn resume(
        built: &mut Built,
        cfg: &RunConfig,
        out_dir: &Path,
        c: &Checkpoint,
    ) -> Result<Self, RunError> {
        let bad = |reason: String| RunError::Checkpoint(reason);
        c.check_shape(built.model.n_dofs(), built.model.forces.len())
            .map_err(bad)?;
        for (f, h) in built.model.forces.iter_mut().zip(&c.histories) {
            f.restore_history(h).map_err(bad)?;
        }
        let ts_path = out_dir.join("timeseries.csv");
        let rows =
            checkpoint::truncate_timeseries(&ts_path, c.ts_rows).map_err(|e| bad(e.to_string()))?;
        let ts = TimeSeriesWriter::append_to(&ts_path, c.ts_rows).map_err(io_err(&ts_path))?;
        let vtk = VtkSeries::resume(out_dir, &c.frame_times).map_err(io_err(out_dir))?;
        let mut run = Self::blank(built, cfg, out_dir, ts, vtk);
        rows.iter().for_each(|s| run.dec.push(s));
        run.state = engine::State {
            q: c.q.clone(),
            v: c.v.clone(),
            t: c.t,
        };
        run.dt = c.dt;
        run.streak = c.streak;
        run.steps = c.steps;
        run.newton_total = c.newton_iterations;
        run.warnings = c.warnings.clone();
        run.next_frame = c.next_frame;
        run.snap_idx = (c.snap_idx as usize).min(run.snaps.len());
        run.next_sync = c.next_sync;
        run.wall_before_s = c.wall_time_s;
        Ok(run)
    }

    /// The checkpoint of the current state.
    fn checkpoint(
        &self,
        built: &Built,
        ctl: &RunControl<'_>,
        wall: &Instant,
        synced: bool,
    ) -> Checkpoint {
        Checkpoint {
            scenario_toml: ctl.scenario_toml.clone(),
            synced,
            t: self.state.t,
            q: self.state.q.clone(),
            v: self.state.v.clone(),
            histories: built.model.forces.iter().map(|f| f.history()).collect(),
            dt: self.dt,
            streak: self.streak,
            steps: self.steps,
            newton_iterations: self.newton_total,
            wall_time_s: self.wall_before_s + wall.elapsed().as_secs_f64(),
            ts_rows: self.ts.rows(),
            frame_times: self.vtk.times(),
            next_frame: self.next_frame,
            snap_idx: self.snap_idx as u64,
            next_sync: self.next_sync,
            warnings: self.warnings.clone(),
        }
    }

    /// Write `c` after making every time-series row it counts durable.
    fn save(&mut self, c: &Checkpoint, out_dir: &Path) -> Result<(), RunError> {
        self.ts.flush().map_err(io_err(&self.ts_path))?;
        c.write(out_dir)
            .map_err(|e| RunError::Checkpoint(e.to_string()))
    }

    fn accept(
        &mut self,
        built: &Built,
        cfg: &RunConfig,
        out_dir: &Path,
        iterations: usize,
        h: f64,
    ) -> Result<(), RunError> {
        self.steps += 1;
        self.newton_total += iterations as u64;
        self.streak += 1;
        if self.dt < cfg.dt_s && self.streak >= GROW_AFTER {
            self.dt = (2.0 * self.dt).min(cfg.dt_s);
            self.streak = 0;
        }
        let s = self.obs.sample(built, &self.state, iterations as u32, h);
        self.ts.push(&s).map_err(io_err(&self.ts_path))?;
        self.dec.push(&s);
        self.write_due_outputs(built, cfg, out_dir)
    }

    /// Halve `dt` after a failed step; the stop reason when it falls below `min_dt`.
    fn reject(&mut self, built: &Built, cfg: &RunConfig, e: &StepError) -> Option<String> {
        self.streak = 0;
        self.dt *= 0.5;
        if self.dt < cfg.min_dt_s {
            return Some(failure_message(built, e, self.state.t, self.dt));
        }
        if self.warnings.len() < 20 {
            self.warnings.push(format!(
                "step rejected at t = {:.6} s ({e}); dt halved to {:.3e} s",
                self.state.t, self.dt
            ));
        }
        None
    }

    /// Write the VTK frame and snapshot PNGs that are due at the current time.
    fn write_due_outputs(
        &mut self,
        b: &Built,
        cfg: &RunConfig,
        out_dir: &Path,
    ) -> Result<(), RunError> {
        let s = &self.state;
        let half = 0.5 * cfg.dt_s;
        let frame_due = cfg.frame_interval_s > 0.0 && s.t >= self.next_frame - half;
        let snaps = &self.snaps;
        let snap_due = self.snap_idx < snaps.len() && s.t >= snaps[self.snap_idx] - half;
        if !(frame_due || snap_due) {
            return Ok(());
        }
        self.obs.load(&s.q, &s.v);
        if frame_due {
            self.obs.drag(b, &s.q, &s.v, s.t);
            let o = &self.obs;
            self.vtk
                .write_frame(s.t, &o.pos, &o.vel, &b.triangles, &b.segments, &o.tri_drag)
                .map_err(io_err(out_dir))?;
            while self.next_frame <= s.t + half {
                self.next_frame += cfg.frame_interval_s;
            }
        }
        while self.snap_idx < snaps.len() && s.t >= snaps[self.snap_idx] - half {
            let _ = plots::snapshot_plot(
                out_dir,
                snaps[self.snap_idx],
                &self.obs.pos,
                &b.triangles,
                &b.segments,
            );
            self.snap_idx += 1;
        }
        Ok(())
    }

    /// Close the outputs: time series, final plots and `summary.json` (always written, marked
    /// incomplete with the reason when the run stopped early).
    fn finish(
        mut self,
        built: &mut Built,
        cfg: &RunConfig,
        out_dir: &Path,
        stop_reason: Option<String>,
        wall: &Instant,
    ) -> Result<RunResult, RunError> {
        let mut warnings = std::mem::take(&mut self.warnings);
        for t in &self.snaps[self.snap_idx..] {
            warnings.push(format!(
                "snapshot at {t} s not drawn: the run ended at {:.6} s",
                self.state.t
            ));
        }
        self.ts.finish().map_err(io_err(&self.ts_path))?;
        let complete = stop_reason.is_none();
        // The final state is always drawn, whether or not the run completed.
        self.obs.load(&self.state.q, &self.state.v);
        let _ = plots::final_shape_plot(
            out_dir,
            self.state.t,
            &self.obs.pos,
            &built.triangles,
            &built.segments,
        );
        built.state = self.state;
        let params = metrics::Params {
            total_weight_n: built.total_weight_n,
            air_density_kg_m3: cfg.air_density,
            air_viscosity_pa_s: cfg.air_viscosity,
            reference_length_m: built.reference_length_m,
            quadratic_drag: cfg.quadratic_drag,
        };
        let dec = &self.dec;
        let info = RunInfo {
            scenario_name: cfg.name.clone(),
            complete,
            stop_reason: stop_reason.clone(),
            simulated_time_s: built.state.t,
            steps: self.steps,
            newton_iterations: self.newton_total,
            wall_time_s: self.wall_before_s + wall.elapsed().as_secs_f64(),
            dofs: built.model.n_dofs(),
            warnings,
        };
        let summary = match metrics::compute(&dec.series(), &params) {
            Ok(m) => {
                let _ = plots::velocity_plot(
                    &out_dir.join("velocity.png"),
                    &dec.t_s,
                    &dec.vz_mps,
                    Some(m.terminal_velocity_mps),
                    m.time_to_terminal_s,
                );
                let _ = plots::height_plot(
                    &out_dir.join("height.png"),
                    &dec.t_s,
                    &dec.extended_height_m,
                );
                Summary::new(info, &m)
            }
            Err(e) => {
                let mut info = info;
                info.warnings.push(format!("metrics unavailable: {e}"));
                Summary::new(info, &metrics::Metrics::undefined(built.total_weight_n))
            }
        };
        let sp = out_dir.join("summary.json");
        summary.write(&sp).map_err(io_err(&sp))?;
        Ok(RunResult {
            summary,
            complete,
            stop_reason,
        })
    }
}

fn failure_message(b: &Built, e: &StepError, t: f64, dt: f64) -> String {
    let at = match e {
        StepError::NotConverged {
            worst_dof,
            residual,
            ..
        } => {
            format!(
                "; residual {residual:.3e} N, worst at {}",
                describe_dof(b, *worst_dof)
            )
        }
        StepError::Diverged { worst_dof, .. } => {
            format!("; worst at {}", describe_dof(b, *worst_dof))
        }
        StepError::NonFinite { dof, .. } => format!("; at {}", describe_dof(b, *dof)),
        StepError::Linear(_) => String::new(),
    };
    format!(
        "step failed at t = {t:.6} s even with dt = {:.3e} s: {e}{at}",
        2.0 * dt
    )
}

fn progress_bar(cfg: &RunConfig) -> Option<indicatif::ProgressBar> {
    use std::io::IsTerminal;
    if !cfg.progress || !std::io::stderr().is_terminal() {
        return None;
    }
    let bar = indicatif::ProgressBar::new(1000);
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{bar:40} {percent:>3}% [{elapsed_precise} < {eta}] {msg}",
        )
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    Some(bar)
}

/// Remove an earlier run's checkpoint, plots and summary (with `--force`), so that nothing in
/// the directory can be mistaken for this run's output.
fn remove_stale_outputs(out_dir: &Path) -> Result<(), RunError> {
    let fixed = [
        checkpoint::FILE_NAME,
        "summary.json",
        "velocity.png",
        "height.png",
        "shape.png",
    ];
    let snapshots = std::fs::read_dir(out_dir)
        .map_err(io_err(out_dir))?
        .filter_map(|e| e.ok().map(|e| e.file_name().to_string_lossy().into_owned()))
        .filter(|n| n.starts_with("snapshot_") && n.ends_with(".png"));
    for name in fixed.iter().map(|s| s.to_string()).chain(snapshots) {
        let stale = out_dir.join(&name);
        match std::fs::remove_file(&stale) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => return Err(io_err(&stale)(e)),
            _ => {}
        }
    }
    Ok(())
}

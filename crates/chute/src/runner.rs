//! The run loop: step the model, observe it, stream outputs, recover from failed steps.
//!
//! Step sizes (fixed, or adaptive with local-error control) are chosen by
//! [`dt_policy`]: a step whose Newton solve fails or produces a non-finite
//! value is rejected (state unchanged) and retried with half the step; an adaptive step whose
//! local error exceeds the tolerance is rejected and retried with the controller's smaller
//! step. Below the smallest step the run stops: the summary is marked incomplete with the
//! reason, the time series and frames written so far stay valid, and `checkpoint.bin` holds
//! the last good state.
//!
//! Checkpoints and determinism: at *sync points*, fixed simulated times that do not depend on
//! the run's history (every [`SYNC_STEPS`] nominal steps; adaptive steps end on them), the
//! loop drops the stepper's reused factorisation, in every run, checkpointing or not.
//! Checkpoints are taken only at sync points (except the last-good-state one of a failed
//! run), and a resumed stepper starts without a factorisation too, so a resumed run is
//! bit-identical to an uninterrupted one. A stop request (Ctrl-C / SIGTERM via [`STOP`])
//! writes the last sync point's checkpoint and ends with valid partial outputs.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::Instant;

use engine::{ImplicitEuler, NewtonOptions, StepError};

use crate::build::Built;
use crate::checkpoint::Checkpoint;
use crate::metrics;
use crate::output::plots;
use crate::output::summary::{RunInfo, Summary};
use crate::output::timeseries::{DecimatedSeries, TimeSeriesWriter};
use crate::output::vtk::VtkSeries;

mod advance;
pub mod dt_policy;
mod observe;
mod persist;
mod session;
pub use advance::Driver;
use advance::Outcome;
use dt_policy::{DtPolicy, Plan};
pub use dt_policy::{GROW_AFTER, SYNC_STEPS};
use observe::Observer;
pub use session::{Session, StepInfo, Stopped};

/// Everything the loop needs besides the model.
#[derive(Debug, Clone)]
pub struct RunConfig {
    /// Scenario name (for the summary).
    pub name: String,
    /// Nominal time step (s); with `adaptive`, the first step.
    pub dt_s: f64,
    /// Smallest time step before giving up (s).
    pub min_dt_s: f64,
    /// Local-error control of the step size (`time.adaptive`); `None` for a fixed step.
    pub adaptive: Option<crate::scenario::AdaptiveSettings>,
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
    /// Where to publish the simulated time after every accepted step (`f64::to_bits`), for
    /// a progress display in another thread.
    pub sim_time: Option<&'a AtomicU64>,
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
        sim_time: None,
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
    let (sync_dt, tol) = (run.dt.sync_dt, run.dt.time_tol);
    let next_multiple = |every: f64, t: f64| ((t + tol) / every).floor() as u64 + 1;
    let mut next_ckpt = ctl
        .checkpoint_every_s
        .map(|s| next_multiple(s, run.state.t));
    // The start (fresh or resumed) is a sync point: the stepper holds no factorisation.
    let mut last_sync = run.checkpoint(built, ctl, &wall, true);
    let mut stop_reason = None;
    while run.state.t < cfg.duration_s - tol {
        if ctl.stop.load(Ordering::Relaxed) {
            stop_reason = Some(format!(
                "interrupted at t = {:.6} s; checkpoint at t = {:.6} s",
                run.state.t, last_sync.t
            ));
            run.save(&last_sync, out_dir)?;
            break;
        }
        let plan = run.dt.plan(run.state.t, run.next_event(cfg));
        let iterations = match run.attempt(&mut stepper, built, cfg, out_dir, &plan)? {
            Attempt::Accepted(iterations) => iterations,
            Attempt::Rejected => continue,
            Attempt::Failed(e) => {
                if let Some(reason) = run.reject(built, &e, plan.h) {
                    stop_reason = Some(reason);
                    let good = run.checkpoint(built, ctl, &wall, false);
                    run.save(&good, out_dir)?;
                    break;
                }
                continue;
            }
        };
        if let Some(t) = ctl.sim_time {
            t.store(run.state.t.to_bits(), Ordering::Relaxed);
        }
        if let Some(bar) = &bar {
            bar.set_position((run.state.t / cfg.duration_s * 1000.0) as u64);
            let rate = run.steps as f64 / wall.elapsed().as_secs_f64().max(1e-9);
            bar.set_message(format!(
                "t = {:.3} s, {rate:.0} steps/s, {iterations} Newton it/step",
                run.state.t
            ));
        }
        if run.state.t < run.next_sync as f64 * sync_dt - tol {
            continue;
        }
        stepper.invalidate_factorization();
        run.next_sync = next_multiple(sync_dt, run.state.t);
        last_sync = run.checkpoint(built, ctl, &wall, true);
        if let (Some(k), Some(every)) = (next_ckpt, ctl.checkpoint_every_s) {
            if run.state.t >= k as f64 * every - tol {
                run.save(&last_sync, out_dir)?;
                next_ckpt = Some(next_multiple(every, run.state.t));
            }
        }
    }
    if let Some(bar) = &bar {
        bar.finish_and_clear();
    }
    run.finish(built, cfg, out_dir, stop_reason, &wall)
}

/// What one attempt at a step did.
enum Attempt {
    /// Accepted and recorded, with this many Newton iterations.
    Accepted(usize),
    /// Rejected for its local error; retry with the policy's smaller step.
    Rejected,
    /// Newton failed (state unchanged).
    Failed(StepError),
}

/// The run loop's mutable state and open outputs: what a checkpoint saves and restores.
struct Run {
    state: engine::State,
    dt: DtPolicy,
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
    ) -> Result<Self, RunError> {
        let mut snaps = cfg.snapshots_s.clone();
        snaps.sort_by(f64::total_cmp);
        let mut vtk = vtk;
        vtk.set_roles(node_roles(built));
        Ok(Self {
            state: built.state.clone(),
            dt: DtPolicy::new(cfg)?,
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
        })
    }

    fn fresh(built: &Built, cfg: &RunConfig, out_dir: &Path) -> Result<Self, RunError> {
        let ts_path = out_dir.join("timeseries.csv");
        let ts = TimeSeriesWriter::create(&ts_path).map_err(io_err(&ts_path))?;
        // With --force over an earlier run: its frames and checkpoint must not be mistaken for
        // this run's (resuming needs matching rows and frames).
        let vtk = VtkSeries::resume(out_dir, &[]).map_err(io_err(out_dir))?;
        persist::remove_stale_outputs(out_dir)?;
        let mut run = Self::blank(built, cfg, out_dir, ts, vtk)?;
        let s0 = run.obs.sample(built, &run.state, 0, cfg.dt_s);
        run.ts.push(&s0).map_err(io_err(&ts_path))?;
        run.dec.push(&s0);
        run.write_due_outputs(built, cfg, out_dir)?;
        Ok(run)
    }

    /// The first event after the current time, where an adaptive step must end: the end of
    /// the run, the next frame, snapshot and sync point. A fixed step only ends on the end.
    fn next_event(&self, cfg: &RunConfig) -> f64 {
        if !self.dt.adaptive() {
            return cfg.duration_s;
        }
        let after = self.state.t + self.dt.time_tol;
        let frame = if cfg.frame_interval_s > 0.0 {
            self.next_frame
        } else {
            f64::INFINITY
        };
        let snap = self
            .snaps
            .get(self.snap_idx)
            .copied()
            .unwrap_or(f64::INFINITY);
        let sync = self.next_sync as f64 * self.dt.sync_dt;
        [frame, snap, sync]
            .into_iter()
            .filter(|&e| e > after)
            .fold(cfg.duration_s, f64::min)
    }

    /// Solve the step `plan`, judge its local error, and commit and record it or drop it.
    fn attempt(
        &mut self,
        stepper: &mut ImplicitEuler,
        built: &mut Built,
        cfg: &RunConfig,
        out_dir: &Path,
        plan: &Plan,
    ) -> Result<Attempt, RunError> {
        let state = &mut self.state;
        let (iterations, err) =
            match advance::attempt(&mut self.dt, stepper, &mut built.model, state, plan) {
                Outcome::Accepted { iterations, err } => (iterations, err),
                Outcome::Rejected => return Ok(Attempt::Rejected),
                Outcome::Failed(e) => return Ok(Attempt::Failed(e)),
            };
        if err > 1.0 && self.warnings.len() < 20 {
            // Accepted only because the step is already the smallest allowed.
            self.warnings.push(format!(
                "local error {:.3} × the tolerance accepted at t = {:.6} s: dt = {:.3e} s is the smallest step allowed",
                err, self.state.t, plan.h
            ));
        }
        self.steps += 1;
        self.newton_total += iterations as u64;
        let s = self
            .obs
            .sample(built, &self.state, iterations as u32, plan.h);
        self.ts.push(&s).map_err(io_err(&self.ts_path))?;
        self.dec.push(&s);
        self.write_due_outputs(built, cfg, out_dir)?;
        Ok(Attempt::Accepted(iterations))
    }

    /// Halve the step after a failed Newton solve of a step of size `h`; the stop reason when
    /// it falls below the smallest step.
    fn reject(&mut self, built: &Built, e: &StepError, h: f64) -> Option<String> {
        if !self.dt.newton_failed(h) {
            return Some(failure_message(built, e, self.state.t, self.dt.h));
        }
        if self.warnings.len() < 20 {
            self.warnings.push(format!(
                "step rejected at t = {:.6} s ({e}); dt halved to {:.3e} s",
                self.state.t, self.dt.h
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
        let half = self.dt.due_tol;
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
                self.next_frame = self
                    .dt
                    .next_frame_after(self.next_frame, cfg.frame_interval_s);
            }
        }
        while self.snap_idx < snaps.len() && s.t >= snaps[self.snap_idx] - half {
            let roles = node_roles(b);
            let scene = shape_scene(b, &self.obs.pos, &roles);
            let _ = plots::snapshot_plot(out_dir, snaps[self.snap_idx], &scene);
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
        let missed = &self.snaps[self.snap_idx..];
        if !missed.is_empty() {
            // One warning for all of them: a short run with the default snapshot times would
            // otherwise repeat the same sentence.
            let times: Vec<String> = missed.iter().map(|t| format!("{t} s")).collect();
            warnings.push(format!(
                "snapshot{} at {} not drawn: the run ended at {:.6} s",
                if missed.len() > 1 { "s" } else { "" },
                times.join(", "),
                self.state.t
            ));
        }
        self.ts.finish().map_err(io_err(&self.ts_path))?;
        let complete = stop_reason.is_none();
        // The final state is always drawn, whether or not the run completed.
        self.obs.load(&self.state.q, &self.state.v);
        let roles = node_roles(built);
        let scene = shape_scene(built, &self.obs.pos, &roles);
        let _ = plots::final_shape_plot(out_dir, self.state.t, &scene);
        let stepping = self.dt.stepping(cfg);
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
            stepping,
            warnings,
        };
        let summary = match metrics::compute(&dec.series(), &params) {
            Ok(m) => {
                let summary = Summary::new(info, &m);
                let reason = crate::output::console::not_reached_reason(&summary);
                let mark = match &reason {
                    None => plots::TerminalMark::Reached {
                        v_mps: m.terminal_velocity_mps,
                        time_to_terminal_s: m.time_to_terminal_s,
                    },
                    Some(r) => plots::TerminalMark::NotReached { reason: r },
                };
                let _ = plots::velocity_plot(
                    &out_dir.join("velocity.png"),
                    &dec.t_s,
                    &dec.vz_mps,
                    &mark,
                );
                let _ = plots::height_plot(
                    &out_dir.join("height.png"),
                    &dec.t_s,
                    &dec.extended_height_m,
                );
                summary
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

/// What each node is (point data `role` of the frames, markers of the pictures).
fn node_roles(b: &Built) -> Vec<u8> {
    crate::output::vtk::point_roles(
        b.model.layout.n_nodes,
        &b.canopy_nodes,
        &b.load_sites,
        b.payload_node,
    )
}

/// The picture of positions `pos` of model `b`, coloured by height.
fn shape_scene<'a>(b: &'a Built, pos: &'a [[f64; 3]], roles: &'a [u8]) -> plots::ShapeScene<'a> {
    plots::ShapeScene {
        roles,
        ..plots::ShapeScene::new(pos, &b.triangles, &b.segments)
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

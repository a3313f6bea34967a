//! The run loop: step the model, observe it, stream outputs, recover from failed steps.
//!
//! Step sizes (fixed, or adaptive with local-error control) are chosen by
//! [`dt_policy`]: a step whose Newton solve fails or produces a non-finite
//! value is rejected (state unchanged) and retried with half the step; an adaptive step whose
//! local error exceeds the tolerance is rejected and retried with the controller's smaller
//! step. Below the smallest step the run stops: the summary is marked incomplete with the
//! reason, the time series and frames written so far stay valid, and `checkpoint.bin` holds
//! the last good state. With a ground (`atmosphere.ground_altitude_m`) the run ends, complete,
//! at the first step on which the payload (or the lowest canopy node) reaches it
//! (`stop_reason = "ground"`).
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

use engine::{NewtonOptions, StepError};

use crate::build::Built;
use crate::checkpoint::Checkpoint;
use crate::output::plots;
use crate::output::summary::Summary;
use crate::output::timeseries::{Sample, TimeSeriesWriter};
use crate::output::vtk::VtkSeries;

mod advance;
mod control_out;
pub mod dt_policy;
mod flight;
mod observe;
mod persist;
mod progress;
mod recovery;
mod session;
pub use advance::{new_stepper, Driver};
pub use dt_policy::SYNC_STEPS;
pub use engine::stepper::step_size::GROW_AFTER;
pub use flight::WASTED_WORK_WARN;
use flight::{Attempt, End, Flight};
pub use persist::check_resumable;
pub use session::{Session, StepInfo, Stopped};

/// Everything the loop needs besides the model.
#[derive(Debug, Clone)]
pub struct RunConfig {
    /// Scenario name (for the summary).
    pub name: String,
    /// Time steps and duration.
    pub stepping: Stepping,
    /// What is written while the run goes.
    pub outputs: Outputs,
    /// Newton settings.
    pub newton: NewtonOptions,
    /// Whether drag is quadratic (regime warning).
    pub quadratic_drag: bool,
    /// The air at every height (the metrics take ρ and μ from it).
    pub air: engine::aero::Fluid,
    /// Geometric altitude of the model's z = 0 (m).
    pub altitude_m: f64,
    /// Model height of the ground (m), when the run ends there.
    pub ground_z_m: Option<f64>,
    /// Gravitational acceleration (m/s²).
    pub gravity_mps2: f64,
    /// The guidance law (`[guidance]`), which pulls lines between steps.
    pub guidance: Option<crate::control::Controller>,
    /// The sensor-started pulls (`[[control]]` with `sensor`), fired between steps.
    pub triggers: Option<crate::control::Triggers>,
    /// Warnings about the scenario itself, first in the summary.
    pub scenario_warnings: Vec<String>,
    /// Show a progress bar.
    pub progress: bool,
}

/// A run's time steps (`[time]`, resolved).
#[derive(Debug, Clone)]
pub struct Stepping {
    /// Nominal time step (s); with `adaptive`, the first step.
    pub dt_s: f64,
    /// Smallest time step before giving up (s).
    pub min_dt_s: f64,
    /// Local-error control of the step size (`time.adaptive`); `None` for a fixed step.
    pub adaptive: Option<crate::scenario::AdaptiveSettings>,
    /// Simulated duration (s).
    pub duration_s: f64,
}

/// What a run writes as it goes (`[output]`).
#[derive(Debug, Clone)]
pub struct Outputs {
    /// Interval between VTK frames (s); 0 disables frames.
    pub frame_interval_s: f64,
    /// Times at which snapshot PNGs are drawn (s).
    pub snapshots_s: Vec<f64>,
}

/// How a run ended.
#[derive(Debug)]
pub struct RunResult {
    /// The summary as written to `summary.json`.
    pub summary: Summary,
    /// Whether the requested duration was simulated, or the run reached the ground.
    pub complete: bool,
    /// Why it stopped before the duration ([`GROUND`] when it landed).
    pub stop_reason: Option<String>,
}

/// The stop reason of a run that reached the ground (complete).
pub const GROUND: &str = "ground";

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

impl From<crate::output::atomic::FileError> for RunError {
    fn from(e: crate::output::atomic::FileError) -> Self {
        RunError::Io {
            path: e.path,
            source: e.source,
        }
    }
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
    } else if dof - 3 * n < b.rod_twists {
        format!("twist of rod edge {}", dof - 3 * n)
    } else {
        format!(
            "mid-edge angle of shell edge {}",
            dof - 3 * n - b.rod_twists
        )
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

/// Run `built` for `cfg.stepping.duration_s`, writing every output into `out_dir` (which must exist).
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
    let mut stepper = advance::new_stepper(&built.model, cfg)?;
    let mut run = match &ctl.resume {
        None => Run::fresh(built, cfg, out_dir)?,
        Some(c) => Run::resume(built, cfg, out_dir, c)?,
    };
    let bar = progress::bar(cfg);
    let tol = run.flight.dt.time_tol;
    let next_multiple = |every: f64, t: f64| ((t + tol) / every).floor() as u64 + 1;
    let mut next_ckpt = ctl
        .checkpoint_every_s
        .map(|s| next_multiple(s, built.state.t));
    run.flight.start_watches(built);
    if ctl.checkpoint_every_s.is_some() && cfg.stepping.duration_s < run.flight.dt.sync_dt - tol {
        // Checkpoints are written at sync points only (bit-identical resume).
        run.flight.warnings.push(format!(
            "no checkpoint was written: the run ends at t = {} s, before its first sync point at t = {} s, where --checkpoint-every writes the first one",
            cfg.stepping.duration_s, run.flight.dt.sync_dt
        ));
    }
    // The start (fresh or resumed) is a sync point: the stepper holds no factorisation.
    let mut last_sync = run.checkpoint(built, ctl, &wall, stepper.counters(), true);
    let mut stop_reason = None;
    while built.state.t < cfg.stepping.duration_s - tol {
        if ctl.stop.load(Ordering::Relaxed) {
            stop_reason = Some(format!(
                "interrupted at t = {:.6} s; checkpoint at t = {:.6} s",
                built.state.t, last_sync.t
            ));
            run.save(&last_sync, out_dir)?;
            break;
        }
        let iterations = match run.flight.attempt(&mut stepper, built, cfg) {
            Attempt::Accepted(iterations, sample) => {
                if let Err(e) = run.record(built, cfg, out_dir, &sample) {
                    // The rows taken so far are kept where they fit (a frame that did not
                    // fit on a full disk may leave room for them); whole rows only.
                    let _ = run.ts.flush();
                    return Err(e);
                }
                if run.flight.landing.is_some() {
                    stop_reason = Some(GROUND.to_string());
                    break;
                }
                iterations
            }
            Attempt::Rejected => continue,
            Attempt::Failed(reason) => {
                stop_reason = Some(reason);
                let good = run.checkpoint(built, ctl, &wall, stepper.counters(), false);
                run.save(&good, out_dir)?;
                break;
            }
        };
        if let Some(t) = ctl.sim_time {
            t.store(built.state.t.to_bits(), Ordering::Relaxed);
        }
        if let Some(bar) = &bar {
            progress::show(bar, built.state.t, cfg, run.flight.steps, &wall, iterations);
        }
        if !run.flight.passed_sync(built.state.t) {
            continue;
        }
        stepper.invalidate_factorization();
        last_sync = run.checkpoint(built, ctl, &wall, stepper.counters(), true);
        if let (Some(k), Some(every)) = (next_ckpt, ctl.checkpoint_every_s) {
            if built.state.t >= k as f64 * every - tol {
                run.save(&last_sync, out_dir)?;
                next_ckpt = Some(next_multiple(every, built.state.t));
            }
        }
    }
    if let Some(bar) = &bar {
        bar.finish_and_clear();
    }
    let end = run.end(stop_reason, &wall, stepper.counters());
    run.finish(built, cfg, out_dir, end)
}

/// A flight and the outputs it streams into its run directory: what a checkpoint saves and
/// restores (with `built.state`).
struct Run {
    flight: Flight,
    wall_before_s: f64,
    ts_path: PathBuf,
    ts: TimeSeriesWriter,
    vtk: VtkSeries,
    /// `lines.csv` and `track.csv`, with line pulls or guidance.
    control: Option<control_out::Recorder>,
}

impl Run {
    fn blank(
        built: &Built,
        cfg: &RunConfig,
        out_dir: &Path,
        ts: TimeSeriesWriter,
        vtk: VtkSeries,
        t_resume: Option<f64>,
    ) -> Result<Self, RunError> {
        let mut vtk = vtk;
        vtk.set_roles(node_roles(built));
        Ok(Self {
            flight: Flight::new(built, cfg)?,
            wall_before_s: 0.0,
            ts_path: out_dir.join("timeseries.csv"),
            ts,
            vtk,
            control: control_out::Recorder::open(built, out_dir, t_resume)?,
        })
    }

    fn fresh(built: &Built, cfg: &RunConfig, out_dir: &Path) -> Result<Self, RunError> {
        let ts_path = out_dir.join("timeseries.csv");
        let ts = TimeSeriesWriter::create(&ts_path).map_err(io_err(&ts_path))?;
        // With --force over an earlier run: its frames and checkpoint must not be mistaken for
        // this run's (resuming needs matching rows and frames).
        let vtk = VtkSeries::resume(out_dir, &[])?;
        persist::remove_stale_outputs(out_dir)?;
        let mut run = Self::blank(built, cfg, out_dir, ts, vtk, None)?;
        let s0 = run
            .flight
            .obs
            .sample(built, &built.state, 0, cfg.stepping.dt_s);
        run.flight.dec.push(&s0);
        run.record(built, cfg, out_dir, &s0)?;
        Ok(run)
    }

    /// Stream an accepted step's sample and the frame and snapshots due now.
    fn record(
        &mut self,
        b: &Built,
        cfg: &RunConfig,
        out_dir: &Path,
        sample: &Sample,
    ) -> Result<(), RunError> {
        self.ts.push(sample).map_err(io_err(&self.ts_path))?;
        let s = &b.state;
        let due = self.flight.take_due(s.t, cfg);
        if !due.frame && due.snaps.is_empty() {
            return Ok(());
        }
        let obs = &mut self.flight.obs;
        obs.load(&s.q, &s.v);
        if due.frame {
            // The rows first: a frame that does not fit (a full disk) then fails after the
            // time series up to it is on disk, not with the rows still in memory.
            self.ts.flush().map_err(io_err(&self.ts_path))?;
            if let Some(c) = &mut self.control {
                c.push(b, out_dir)?;
            }
            obs.drag(b, &s.q, &s.v, s.t);
            self.vtk.set_wrinkles(b.wrinkles(&s.q));
            self.vtk.write_frame(
                s.t,
                &obs.pos,
                &obs.vel,
                &b.triangles,
                &b.segments,
                &obs.tri_drag,
            )?;
        }
        for t in due.snaps {
            let roles = node_roles(b);
            let scene = shape_scene(b, &obs.pos, &roles);
            let r = plots::snapshot_plot(out_dir, t, &scene);
            plotted(
                &mut self.flight.warnings,
                &format!("the snapshot at t = {t} s"),
                r,
            );
        }
        Ok(())
    }

    /// How the run ended: stopped early for `stop_reason` (or not), after `wall` and, in the
    /// stepper, `counters` since the start or resume.
    fn end(&self, stop_reason: Option<String>, wall: &Instant, counters: &engine::Counters) -> End {
        End {
            ended: true,
            complete: stop_reason.is_none() || self.flight.landing.is_some(),
            stop_reason,
            wall_time_s: self.wall_before_s + wall.elapsed().as_secs_f64(),
            counters: *counters,
        }
    }

    /// Close the outputs: time series, final plots and `summary.json` (always written, marked
    /// incomplete with the reason when the run stopped early, as `end` says).
    fn finish(
        mut self,
        built: &mut Built,
        cfg: &RunConfig,
        out_dir: &Path,
        end: End,
    ) -> Result<RunResult, RunError> {
        self.ts.finish().map_err(io_err(&self.ts_path))?;
        let (complete, stop_reason) = (end.complete, end.stop_reason.clone());
        if let Some(c) = &mut self.control {
            c.push(built, out_dir)?;
            let target = cfg.guidance.as_ref().map(|g| g.target());
            c.plot(out_dir, target, self.flight.landing.map(|l| l.point_m));
        }
        // The final state is always drawn, whether or not the run completed.
        let obs = &mut self.flight.obs;
        obs.load(&built.state.q, &built.state.v);
        let roles = node_roles(built);
        let scene = shape_scene(built, &obs.pos, &roles);
        let mut failed = Vec::new();
        let r = plots::final_shape_plot(out_dir, built.state.t, &scene);
        plotted(&mut failed, "shape.png", r);
        if let Some(w) = built.wrinkles(&built.state.q) {
            // One state per canopy triangle (the probe is the canopy's membrane).
            let by_state = plots::ShapeScene {
                cell_state: &w.state,
                ..scene
            };
            let r = plots::wrinkle_plot(out_dir, built.state.t, &by_state);
            plotted(&mut failed, "wrinkles.png", r);
        }
        // The time-series plots need the metrics; their failures are added after them.
        self.flight.warnings.extend(failed);
        let info = self.flight.info(built, cfg, end);
        let (mut summary, metrics) = self.flight.summary(built, cfg, info);
        if let Some(m) = metrics {
            let reason = crate::output::console::not_reached_reason(&summary);
            let mark = match &reason {
                None => plots::TerminalMark::Reached {
                    v_mps: m.terminal_velocity_mps,
                    time_to_terminal_s: m.time_to_terminal_s,
                },
                Some(r) => plots::TerminalMark::NotReached { reason: r },
            };
            let dec = &self.flight.dec;
            let r =
                plots::velocity_plot(&out_dir.join("velocity.png"), &dec.t_s, &dec.vz_mps, &mark);
            plotted(&mut summary.warnings, "velocity.png", r);
            let r = plots::height_plot(
                &out_dir.join("height.png"),
                &dec.t_s,
                &dec.extended_height_m,
            );
            plotted(&mut summary.warnings, "height.png", r);
        }
        let sp = out_dir.join("summary.json");
        summary.write(&sp).map_err(io_err(&sp))?;
        Ok(RunResult {
            summary,
            complete,
            stop_reason,
        })
    }
}

/// A picture that could not be drawn or written (a full disk) is missing from the run
/// directory: a warning says which and why, instead of the file silently not being there.
fn plotted<T>(warnings: &mut Vec<String>, what: &str, r: Result<T, plots::PlotError>) {
    match r {
        Ok(_) | Err(plots::PlotError::NoData(_)) => {}
        Err(e) => warnings.push(format!("{what} was not written: {e}")),
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
        StepError::NonFinite { dof, .. } => format!("; at {}", describe_dof(b, *dof)),
        // Diverged, Homotopy (its last failed sub-solve's DOF), Linear (none).
        _ => e.dof().map_or_else(String::new, |d| {
            format!("; worst at {}", describe_dof(b, d))
        }),
    };
    format!(
        "step failed at t = {t:.6} s even with dt = {:.3e} s: {e}{at}",
        2.0 * dt
    )
}

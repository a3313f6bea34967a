//! The run loop: step the model, observe it, stream outputs, recover from failed steps.
//!
//! Failure policy (docs/reliability.md): a step whose Newton solve fails or produces a
//! non-finite value is rejected (state unchanged), `dt` is halved and the step retried;
//! after [`GROW_AFTER`] consecutive successes `dt` doubles back towards the scenario's `dt`.
//! Below `min_dt` the run stops: the summary is marked incomplete with the reason, and the
//! time series and frames written so far stay valid.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use engine::{ImplicitEuler, NewtonOptions, StepError};

use crate::build::Built;
use crate::metrics;
use crate::output::plots;
use crate::output::summary::{RunInfo, Summary};
use crate::output::timeseries::{canopy_means, DecimatedSeries, Sample, TimeSeriesWriter};
use crate::output::vtk::VtkSeries;

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

/// Reusable observation buffers (no allocation per step).
struct Observer {
    pos: Vec<[f64; 3]>,
    vel: Vec<[f64; 3]>,
    masses: Vec<f64>,
    drag_blocks: Vec<engine::LocalBlocks>,
    tri_drag: Vec<[f64; 3]>,
}

impl Observer {
    fn new(b: &Built) -> Self {
        let n = b.model.layout.n_nodes;
        Self {
            pos: vec![[0.0; 3]; n],
            vel: vec![[0.0; 3]; n],
            masses: (0..n).map(|i| b.model.node_mass(i)).collect(),
            drag_blocks: b
                .drag_forces
                .iter()
                .map(|&i| b.model.forces[i].new_blocks())
                .collect(),
            tri_drag: vec![[0.0; 3]; b.triangles.len()],
        }
    }

    fn load(&mut self, b: &Built, q: &[f64], v: &[f64]) {
        for i in 0..self.pos.len() {
            self.pos[i] = [q[3 * i], q[3 * i + 1], q[3 * i + 2]];
            self.vel[i] = [v[3 * i], v[3 * i + 1], v[3 * i + 2]];
        }
        let _ = b;
    }

    /// Total drag (N) and, for the triangle family, per-triangle drag.
    fn drag(&mut self, b: &Built, q: &[f64], v: &[f64], t: f64) -> [f64; 3] {
        let n_pos = 3 * b.model.layout.n_nodes;
        let input = engine::EvalInput {
            q,
            v,
            t,
            jacobian: false,
        };
        let mut total = [0.0; 3];
        for (k, &fi) in b.drag_forces.iter().enumerate() {
            let force = &b.model.forces[fi];
            let blocks = &mut self.drag_blocks[k];
            force.evaluate(&input, blocks);
            let st = force.stencils();
            for (d, f) in st.iter().zip(&blocks.f) {
                if *d < n_pos {
                    total[d % 3] += f;
                }
            }
            if Some(fi) == b.triangle_drag {
                for (t, f) in self.tri_drag.iter_mut().zip(blocks.f.chunks(9)) {
                    *t = [f[0] + f[3] + f[6], f[1] + f[4] + f[7], f[2] + f[5] + f[8]];
                }
            }
        }
        total
    }

    fn sample(&mut self, b: &Built, s: &engine::State, iters: u32, dt: f64) -> Sample {
        self.load(b, &s.q, &s.v);
        let drag = self.drag(b, &s.q, &s.v, s.t);
        let m = canopy_means(&self.pos, &self.vel, &self.masses, &b.canopy_nodes)
            .expect("canopy has mass");
        let (zp, vzp) = match b.payload_node {
            Some(p) => (self.pos[p][2], self.vel[p][2]),
            None => (m.z_m, m.v_mps[2]),
        };
        Sample {
            t_s: s.t,
            z_m: m.z_m,
            vz_mps: m.v_mps[2],
            vx_mps: m.v_mps[0],
            vy_mps: m.v_mps[1],
            z_payload_m: zp,
            vz_payload_mps: vzp,
            extended_height_m: m.extended_height_m,
            drag_x_n: drag[0],
            drag_y_n: drag[1],
            drag_z_n: drag[2],
            newton_iterations: iters,
            dt_s: dt,
        }
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

/// Run `built` for `cfg.duration_s`, writing every output into `out_dir` (which must exist).
/// `stop` requests a graceful early stop (Ctrl-C / SIGTERM).
pub fn simulate(
    built: &mut Built,
    cfg: &RunConfig,
    out_dir: &Path,
    stop: &AtomicBool,
) -> Result<RunResult, RunError> {
    let wall = Instant::now();
    let mut stepper = ImplicitEuler::new(&built.model, cfg.newton)?;
    let ts_path = out_dir.join("timeseries.csv");
    let mut ts = TimeSeriesWriter::create(&ts_path).map_err(io_err(&ts_path))?;
    let mut dec = DecimatedSeries::default();
    let mut vtk = VtkSeries::new(out_dir).map_err(io_err(out_dir))?;
    let mut obs = Observer::new(built);
    let mut state = built.state.clone();
    let bar = progress_bar(cfg);

    let s0 = obs.sample(built, &state, 0, cfg.dt_s);
    ts.push(&s0).map_err(io_err(&ts_path))?;
    dec.push(&s0);
    let mut next_frame = 0.0;
    let mut snaps: Vec<f64> = cfg.snapshots_s.clone();
    snaps.sort_by(f64::total_cmp);
    let mut snap_idx = 0;
    write_due_outputs(
        built,
        cfg,
        out_dir,
        &mut obs,
        &state,
        &mut vtk,
        &mut next_frame,
        &snaps,
        &mut snap_idx,
    )?;

    let (mut dt, mut streak) = (cfg.dt_s, 0u32);
    let (mut steps, mut newton_total) = (0u64, 0u64);
    let mut warnings = Vec::new();
    let mut stop_reason = None;
    let eps_t = 1e-9 * cfg.dt_s;
    while state.t < cfg.duration_s - eps_t {
        if stop.load(Ordering::Relaxed) {
            stop_reason = Some(format!("interrupted at t = {:.6} s", state.t));
            break;
        }
        let h = dt.min(cfg.duration_s - state.t);
        match stepper.step(&mut built.model, &mut state, h) {
            Ok(rep) => {
                steps += 1;
                newton_total += rep.iterations as u64;
                streak += 1;
                if dt < cfg.dt_s && streak >= GROW_AFTER {
                    dt = (2.0 * dt).min(cfg.dt_s);
                    streak = 0;
                }
                let s = obs.sample(built, &state, rep.iterations as u32, h);
                ts.push(&s).map_err(io_err(&ts_path))?;
                dec.push(&s);
                write_due_outputs(
                    built,
                    cfg,
                    out_dir,
                    &mut obs,
                    &state,
                    &mut vtk,
                    &mut next_frame,
                    &snaps,
                    &mut snap_idx,
                )?;
                if let Some(bar) = &bar {
                    bar.set_position((state.t / cfg.duration_s * 1000.0) as u64);
                    let rate = steps as f64 / wall.elapsed().as_secs_f64().max(1e-9);
                    bar.set_message(format!(
                        "t = {:.3} s, {rate:.0} steps/s, {} Newton it/step",
                        state.t, rep.iterations
                    ));
                }
            }
            Err(e) => {
                streak = 0;
                dt *= 0.5;
                if dt < cfg.min_dt_s {
                    stop_reason = Some(failure_message(built, &e, state.t, dt));
                    break;
                }
                if warnings.len() < 20 {
                    warnings.push(format!(
                        "step rejected at t = {:.6} s ({e}); dt halved to {dt:.3e} s",
                        state.t
                    ));
                }
            }
        }
    }
    if let Some(bar) = &bar {
        bar.finish_and_clear();
    }
    for t in &snaps[snap_idx..] {
        warnings.push(format!(
            "snapshot at {t} s not drawn: the run ended at {:.6} s",
            state.t
        ));
    }
    ts.finish().map_err(io_err(&ts_path))?;
    let complete = stop_reason.is_none();
    // The final state is always drawn and written, whether or not the run completed.
    obs.load(built, &state.q, &state.v);
    let _ = plots::final_shape_plot(
        out_dir,
        state.t,
        &obs.pos,
        &built.triangles,
        &built.segments,
    );
    built.state = state;
    let params = metrics::Params {
        total_weight_n: built.total_weight_n,
        air_density_kg_m3: cfg.air_density,
        air_viscosity_pa_s: cfg.air_viscosity,
        reference_length_m: built.reference_length_m,
        quadratic_drag: cfg.quadratic_drag,
    };
    let m = metrics::compute(&dec.series(), &params);
    let info = RunInfo {
        scenario_name: cfg.name.clone(),
        complete,
        stop_reason: stop_reason.clone(),
        simulated_time_s: built.state.t,
        steps,
        newton_iterations: newton_total,
        wall_time_s: wall.elapsed().as_secs_f64(),
        dofs: built.model.n_dofs(),
        warnings,
    };
    let summary = match m {
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
        StepError::Linear(_) => String::new(),
    };
    format!(
        "step failed at t = {t:.6} s even with dt = {:.3e} s: {e}{at}",
        2.0 * dt
    )
}

#[allow(clippy::too_many_arguments)]
fn write_due_outputs(
    b: &Built,
    cfg: &RunConfig,
    out_dir: &Path,
    obs: &mut Observer,
    s: &engine::State,
    vtk: &mut VtkSeries,
    next_frame: &mut f64,
    snaps: &[f64],
    snap_idx: &mut usize,
) -> Result<(), RunError> {
    let half = 0.5 * cfg.dt_s;
    let frame_due = cfg.frame_interval_s > 0.0 && s.t >= *next_frame - half;
    let snap_due = *snap_idx < snaps.len() && s.t >= snaps[*snap_idx] - half;
    if !(frame_due || snap_due) {
        return Ok(());
    }
    obs.load(b, &s.q, &s.v);
    if frame_due {
        obs.drag(b, &s.q, &s.v, s.t);
        vtk.write_frame(
            s.t,
            &obs.pos,
            &obs.vel,
            &b.triangles,
            &b.segments,
            &obs.tri_drag,
        )
        .map_err(io_err(out_dir))?;
        while *next_frame <= s.t + half {
            *next_frame += cfg.frame_interval_s;
        }
    }
    while snap_due && *snap_idx < snaps.len() && s.t >= snaps[*snap_idx] - half {
        let _ = plots::snapshot_plot(
            out_dir,
            snaps[*snap_idx],
            &obs.pos,
            &b.triangles,
            &b.segments,
        );
        *snap_idx += 1;
    }
    Ok(())
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

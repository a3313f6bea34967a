//! The interface between the command line and the simulation: `check` and `run` a scenario.
//! The other commands live in their own modules: [`crate::verify`] (`chute validate`), [`crate::bench`],
//! [`crate::study`].

pub(crate) mod out_dir;
pub(crate) mod resume;
pub use resume::Resumable;
pub mod view;

use std::path::{Path, PathBuf};

use crate::output::record::{InputFile, RunRecord, Status};
use crate::scenario::{Scenario, ScenarioError};
pub use out_dir::{check_fresh_dir, ensure_dir, not_a_run_dir, prepare_out_dir, Prepared};
pub use resume::{resolved_value, scenario_difference, unresumable, Difference, DURATION_KEY};

/// How to run one scenario.
#[derive(Debug, Clone, PartialEq)]
pub struct RunOptions {
    /// Output directory (created; must be writable).
    pub out_dir: PathBuf,
    /// Overwrite an existing, non-empty output directory.
    pub force: bool,
    /// Show a progress bar on stderr.
    pub progress: bool,
    /// Write a checkpoint every this many simulated seconds.
    pub checkpoint_every_s: Option<f64>,
    /// Resume from the checkpoint in this run directory.
    pub resume: Option<PathBuf>,
    /// Whether the command writes `viewer.html` after the run; recorded in `run.json` so
    /// that `chute resume` does as the run did.
    pub viewer: bool,
    /// The study case the run is made for (`study/case`), recorded in `run.json` so that a
    /// study knows a run of its case whose marker it lost from a run someone else put there.
    pub case_of: Option<String>,
}

/// What a run produced.
#[derive(Debug, Clone, PartialEq)]
pub struct RunOutcome {
    /// The contents of `summary.json` (docs/outputs.md).
    pub summary: serde_json::Value,
    /// Whether the run reached `time.duration_s`.
    pub complete: bool,
    /// Why the run stopped early, or a warning worth showing.
    pub message: Option<String>,
}

/// Everything that can stop a command; [`AppError::exit_code`] maps it to the process status.
#[derive(Debug, thiserror::Error)]
pub enum AppError {
    /// A bad scenario (exit 2). Boxed: it is the largest variant.
    #[error(transparent)]
    Scenario(Box<ScenarioError>),
    /// A scenario the builders cannot turn into a model, e.g. a bad mesh file (exit 2).
    #[error(transparent)]
    Build(#[from] crate::build::BuildError),
    /// Any other bad input: output directory, study file, shard spec (exit 2).
    #[error("{0}")]
    Input(String),
    /// The simulation failed (exit 3).
    #[error("run failed: {0}")]
    RunFailed(String),
    /// Reading or writing a file failed (exit 1).
    #[error("{}: {source}", path.display())]
    Io {
        /// The file or directory.
        path: PathBuf,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// Some verification cases failed (exit 1).
    #[error("{failed} verification case(s) failed")]
    ValidationFailed {
        /// Number of failed cases.
        failed: usize,
    },
}

impl From<ScenarioError> for AppError {
    fn from(e: ScenarioError) -> Self {
        AppError::Scenario(Box::new(e))
    }
}

impl AppError {
    /// Process exit status: 2 for input errors, 3 for a failed run, 1 for anything else.
    pub fn exit_code(&self) -> i32 {
        match self {
            AppError::Scenario(_) | AppError::Build(_) | AppError::Input(_) => 2,
            AppError::RunFailed(_) => 3,
            AppError::Io { .. } | AppError::ValidationFailed { .. } => 1,
        }
    }

    /// Wrap an I/O error with the path it concerns.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        AppError::Io {
            path: path.into(),
            source,
        }
    }
}

/// Derived quantities of a scenario (name, value with units), for `chute check`: the
/// model is built (meshes generated or read, masses lumped) so every number is the one a run
/// would use.
pub fn check(s: &Scenario) -> Result<Vec<(String, String)>, AppError> {
    let built = crate::build::build(s)?;
    check_ground(s, &built)?;
    let mut out = built.derived.clone();
    out.extend(atmosphere_lines(s, &built));
    out.extend(fabric_lines(s, &built));
    out.extend(s.notes.0.iter().map(|w| ("warning".to_string(), w.clone())));
    let t = &s.time;
    match s.adaptive_settings() {
        None => out.push((
            "time steps".into(),
            format!(
                "{:.0} (dt = {} s, {} s)",
                (t.duration_s / t.dt_s).ceil(),
                t.dt_s,
                t.duration_s
            ),
        )),
        Some(a) => {
            out.push((
                "time steps".into(),
                format!(
                    "adaptive, local error ≤ {:e} m per step; first dt = {} s, dt in [{:.4e}, {}] s, {} s",
                    a.error_tolerance_m, t.dt_s, a.dt_min_s, a.dt_max_s, t.duration_s
                ),
            ));
            // The step the tolerance allows at the start of a fall (a = g): h = √(2 tol/g).
            let h = (2.0 * a.error_tolerance_m / s.fluid.gravity_mps2).sqrt();
            out.push((
                "adaptive dt at a = g".into(),
                format!(
                    "{h:.3e} s (√(2 tol/g)); at least {:.0} steps",
                    (t.duration_s / a.dt_max_s).ceil()
                ),
            ));
        }
    }
    Ok(out)
}

pub use crate::resolve::run_config;

/// Build the model, simulate, and write the output directory (which must exist).
///
/// The directory is held for the run ([`crate::output::lock`]) unless this process holds it
/// already. With `opts.resume` the run continues from `checkpoint.bin` in that directory
/// (which must be `opts.out_dir`); the scenario must resolve to the one the checkpoint was
/// written with, except for `time.duration_s`, which may only grow (a run may be extended),
/// and every input file must have the bytes recorded in `run.json`. A fresh run needs an
/// empty directory, or `opts.force` over an earlier run, whose files are cleared
/// ([`crate::output::run_files::clear`]) once the model is known to be valid, so a run that
/// cannot start leaves the earlier one intact and one that starts never mixes with it. The
/// run's record (`run.json`) says `running` until the run ends, then how it ended, also
/// after an I/O failure. With `opts.checkpoint_every_s` a checkpoint is written
/// periodically. The process-wide [`crate::runner::STOP`] flag (set by the Ctrl-C / SIGTERM
/// handler of the binary) stops the run gracefully.
pub fn run(s: &Scenario, opts: &RunOptions) -> Result<RunOutcome, AppError> {
    let watch = Watch {
        stop: &crate::runner::STOP,
        sim_time: None,
    };
    run_watched(s, opts, watch)
}

/// How a run is watched from another thread (the Python bindings): the flag that stops it
/// gracefully, and where it publishes its simulated time ([`crate::runner::RunControl`]).
#[derive(Debug, Clone, Copy)]
pub struct Watch<'a> {
    /// Graceful stop request, checked before every step.
    pub stop: &'a std::sync::atomic::AtomicBool,
    /// Receives the simulated time after every accepted step (`f64::to_bits`).
    pub sim_time: Option<&'a std::sync::atomic::AtomicU64>,
}

/// [`run`] with its own stop flag and progress instead of the process-wide
/// [`crate::runner::STOP`].
pub fn run_watched(
    s: &Scenario,
    opts: &RunOptions,
    watch: Watch<'_>,
) -> Result<RunOutcome, AppError> {
    let dir = &opts.out_dir;
    let _held = out_dir::hold(dir)?;
    if opts.resume.is_some() {
        resume::check_inputs(dir, s)?;
    }
    let mut built = crate::build::build(s)?;
    if opts.resume.is_some() {
        // Again with the bytes the model was just built from (the file may have changed
        // since the check above read it).
        resume::check_built_inputs(dir, &built)?;
    }
    check_ground(s, &built)?;
    let scenario_toml = s.to_toml();
    let (resume, record, cleared) = match &opts.resume {
        Some(from) => {
            out_dir::refuse_directory_named_like_a_run_file(dir)?;
            out_dir::refuse_users_trash(dir)?;
            let c = resume::load_checkpoint(from, dir, &scenario_toml)?;
            // Judged before anything in the directory changes: a refused resume leaves it
            // as it was.
            crate::runner::check_resumable(&built, dir, &c).map_err(|e| match e {
                crate::runner::RunError::Checkpoint(m) => {
                    AppError::Input(format!("checkpoint: {m}"))
                }
                e => AppError::RunFailed(e.to_string()),
            })?;
            crate::output::run_files::remove_temporaries(dir).map_err(|e| AppError::io(dir, e))?;
            // A run of a chute before run.json gets one now (its inputs as they are).
            let record = match RunRecord::read(dir).map_err(AppError::Input)? {
                // What this resume was told (`--no-viewer`), for the next one.
                Some(r) => RunRecord {
                    viewer: opts.viewer,
                    ..r
                },
                None => fresh_record(s, opts, &built)?,
            };
            (Some(c), record, None)
        }
        None => {
            check_fresh_dir(dir, opts.force)?;
            let record = fresh_record(s, opts, &built)?;
            let cleared = crate::output::run_files::clear(dir).map_err(|e| AppError::io(dir, e))?;
            (None, record, Some(cleared))
        }
    };
    begin(dir, &record, &scenario_toml, cleared)?;
    let cfg = run_config(s, opts.progress);
    let ctl = crate::runner::RunControl {
        stop: watch.stop,
        checkpoint_every_s: opts.checkpoint_every_s,
        resume,
        scenario_toml,
        sim_time: watch.sim_time,
    };
    let result = crate::runner::simulate_with(&mut built, &cfg, dir, &ctl);
    // Room for the record (and a study's marker) even when the file system filled up.
    crate::output::lock::free_reserve(dir);
    let ended = match &result {
        Ok(r) if r.complete => record.with_status(Status::Complete, None),
        Ok(r) => record.with_status(Status::Incomplete, r.stop_reason.clone()),
        Err(e) => record.with_status(Status::Failed, Some(e.to_string())),
    };
    let path = dir.join(crate::output::run_files::RUN_RECORD);
    let recorded = ended.write(dir).map_err(|e| AppError::io(&path, e));
    let r = result.map_err(|e| match e {
        crate::runner::RunError::Io { path, source } => AppError::Io { path, source },
        crate::runner::RunError::Checkpoint(m) => AppError::Input(format!("checkpoint: {m}")),
        e => AppError::RunFailed(e.to_string()),
    })?;
    recorded?;
    let summary = serde_json::from_str(&r.summary.to_json())
        .map_err(|e| AppError::RunFailed(format!("summary: {e}")))?;
    // Landing is how a run with a ground ends: complete, nothing to warn about.
    let message = r.stop_reason.filter(|m| m != crate::runner::GROUND);
    Ok(RunOutcome {
        summary,
        complete: r.complete,
        message,
    })
}

/// Write the record of a run starting (`running`) and its resolved scenario. When either
/// cannot be written (a full disk), an earlier run moved aside (`cleared`) is put back as it
/// was; a resumed run's record says why it never went on.
fn begin(
    dir: &Path,
    record: &RunRecord,
    scenario_toml: &str,
    cleared: Option<crate::output::run_files::Cleared>,
) -> Result<(), AppError> {
    use crate::output::run_files::{RESOLVED_SCENARIO, RUN_RECORD};
    let (path, resolved) = (dir.join(RUN_RECORD), dir.join(RESOLVED_SCENARIO));
    let written = record
        .with_status(Status::Running, None)
        .write(dir)
        .map_err(|e| (&path, e))
        .and_then(|()| {
            crate::output::atomic::write_atomic(&resolved, scenario_toml.as_bytes())
                .map_err(|e| (&resolved, e))
        });
    let Err((file, e)) = written else {
        if let Some(earlier) = cleared {
            earlier.commit();
        }
        return Ok(());
    };
    crate::output::lock::free_reserve(dir);
    match cleared {
        Some(earlier) => {
            let _ = std::fs::remove_file(&path);
            earlier.restore();
        }
        None => {
            let why = format!("{}: {e}", file.display());
            let _ = record.with_status(Status::Failed, Some(why)).write(dir);
        }
    }
    Err(AppError::io(file, e))
}

/// The record of a run starting now: every input file by digest, and its options.
fn fresh_record(
    s: &Scenario,
    opts: &RunOptions,
    built: &crate::build::Built,
) -> Result<RunRecord, AppError> {
    let inputs = s
        .input_files()
        .into_iter()
        .map(|(key, path)| {
            // The bytes the model was built from, not the file as it is now.
            let parsed = built.input_digests.iter().find(|(k, _)| *k == key);
            let digest = match parsed {
                Some((_, d)) => d.clone(),
                None => crate::study::inputs::file_digest(&path).map_err(|e| {
                    AppError::Input(format!("{key}: cannot read `{}`: {e}", path.display()))
                })?,
            };
            Ok(InputFile {
                key: key.to_string(),
                path,
                digest,
            })
        })
        .collect::<Result<Vec<_>, AppError>>()?;
    Ok(RunRecord {
        status: Status::Running,
        reason: None,
        inputs,
        viewer: opts.viewer,
        case_of: opts.case_of.clone(),
    })
}

/// `chute check`'s lines on a `[wind]` profile: the wind at the start and 10 m above the
/// ground (altitude 0 without one).
fn wind_lines(s: &Scenario, fluid: &engine::aero::Fluid) -> Vec<(String, String)> {
    use crate::scenario::derived::sig4;
    if s.wind.is_none() {
        return Vec::new();
    }
    let a = &s.atmosphere;
    let low = a.ground_altitude_m.unwrap_or(0.0) + 10.0;
    [a.altitude_m, low]
        .into_iter()
        .map(|h| {
            let u = fluid.wind_at(h - a.altitude_m).velocity;
            (
                format!("wind at {} m", sig4(h)),
                format!("[{}, {}] m/s", sig4(u[0]), sig4(u[1])),
            )
        })
        .collect()
}

/// `chute check`'s lines on the air: the model, the air at the start and at the ground, and
/// the time to fall from one to the other at the flat-canopy speed √(2W/(ρ(h) C_D A)).
fn atmosphere_lines(s: &Scenario, b: &crate::build::Built) -> Vec<(String, String)> {
    use crate::scenario::derived::sig4;
    use crate::scenario::AtmosphereModel;
    let a = &s.atmosphere;
    let fluid = crate::resolve::air(s);
    let describe = |h: f64| -> String {
        let air = fluid.at(h - a.altitude_m);
        match a.model {
            AtmosphereModel::Constant => format!(
                "ρ = {} kg/m³, μ = {} Pa·s (constant)",
                sig4(air.density),
                sig4(air.viscosity)
            ),
            AtmosphereModel::Isa1976 => {
                let st = engine::aero::atmosphere::isa1976(h);
                format!(
                    "T = {} K, p = {} Pa, ρ = {} kg/m³, μ = {} Pa·s",
                    sig4(st.temperature_k),
                    sig4(st.pressure_pa),
                    sig4(st.density_kg_m3),
                    sig4(st.viscosity_pa_s)
                )
            }
        }
    };
    let model = match a.model {
        AtmosphereModel::Constant => "constant (fluid.density_kg_m3, fluid.viscosity_pa_s)",
        AtmosphereModel::Isa1976 => "isa1976 (U.S. Standard Atmosphere 1976)",
    };
    let mut out = vec![
        ("atmosphere".to_string(), model.to_string()),
        (
            format!("air at the start ({} m)", sig4(a.altitude_m)),
            describe(a.altitude_m),
        ),
    ];
    out.extend(wind_lines(s, &fluid));
    let Some(g) = a.ground_altitude_m else {
        return out;
    };
    out.push((format!("air at the ground ({} m)", sig4(g)), describe(g)));
    // ∫ dh / v_flat(h) by the composite midpoint rule on 2000 intervals (ρ is smooth inside
    // each layer; the error is far below the flat-canopy estimate's own).
    let n = 2000;
    let dh = (a.altitude_m - g) / n as f64;
    let w = b.total_weight_n;
    let time: f64 = (0..n)
        .map(|i| {
            let h = g + (i as f64 + 0.5) * dh;
            let rho = fluid.at(h - a.altitude_m).density;
            dh / (2.0 * w / (rho * b.flat_drag_area_m2)).sqrt()
        })
        .sum();
    out.push((
        "time to fall to the ground at the flat-canopy speed".into(),
        format!("{} s ({} m)", sig4(time), sig4(a.altitude_m - g)),
    ));
    out
}

/// `chute check`'s lines on a permeable fabric: k (and where it came from) and the leakage
/// speed at the canopy loading W/S₀ in the air at the start.
fn fabric_lines(s: &Scenario, b: &crate::build::Built) -> Vec<(String, String)> {
    use crate::scenario::derived::sig4;
    let Some(f) = crate::build::drag::fabric(&s.material, s.canopy.thickness_m) else {
        return Vec::new();
    };
    let air = crate::resolve::air(s).at(0.0);
    let loading = b.total_weight_n / b.planform_area_m2;
    let source = match s.material.air_permeability_cfm {
        Some(q) => format!(" (from {} ft³/(ft²·min), ASTM D737, Darcy term)", sig4(q)),
        None => String::new(),
    };
    vec![
        (
            "fabric permeability k".into(),
            format!(
                "{} m²{source}, C_F = {}, h = {} m",
                sig4(f.permeability),
                sig4(f.forchheimer),
                sig4(f.thickness)
            ),
        ),
        (
            "leakage through the fabric at W/S₀".into(),
            format!(
                "{} m/s at {} Pa",
                sig4(f.leakage_at(loading, air.density, air.viscosity)),
                sig4(loading)
            ),
        ),
    ]
}

/// The ground must lie below where the landing body (the payload, or the lowest canopy node)
/// starts; only the builder knows that height.
fn check_ground(s: &Scenario, b: &crate::build::Built) -> Result<(), AppError> {
    use crate::scenario::derived::sig4;
    let Some(g) = s.atmosphere.ground_altitude_m else {
        return Ok(());
    };
    let n = b.model.layout.n_nodes;
    let z = |i: usize| b.state.q[3 * i + 2];
    let (what, z0) = match b.payload_node {
        Some(p) => ("the payload", z(p)),
        None => (
            "the lowest canopy node",
            b.canopy_nodes
                .iter()
                .map(|&i| z(i))
                .fold(f64::INFINITY, f64::min),
        ),
    };
    debug_assert!(b.canopy_nodes.iter().all(|&i| i < n));
    let start = s.atmosphere.altitude_m + z0;
    if g >= start {
        return Err(crate::build::BuildError::key(
            "atmosphere.ground_altitude_m",
            format!(
                "the ground at {} m is not below {what}, which starts at {} m ({} m below atmosphere.altitude_m = {} m); set the ground below {} m, or raise atmosphere.altitude_m",
                sig4(g),
                sig4(start),
                sig4(-z0),
                sig4(s.atmosphere.altitude_m),
                sig4(start)
            ),
        )
        .into());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A run records the digest of the mesh bytes it built its model from, not of the file as
    /// it is when the record is written (a mesh rewritten meanwhile), and a resume refuses a
    /// model built from bytes other than the record's.
    #[test]
    fn a_run_records_the_mesh_bytes_it_was_built_from() {
        let tmp = tempfile::tempdir().unwrap();
        let repo = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
        let mesh = tmp.path().join("mesh.txt");
        std::fs::copy(
            repo.join("crates/chute/data/meshes/hexparachute_n6_python.txt"),
            &mesh,
        )
        .unwrap();
        let set = [format!("canopy.mesh_file={}", mesh.display())];
        let s = Scenario::load(&repo.join("scenarios/dismech-hex-n6.toml"), &set).unwrap();
        let built = crate::build::build(&s).unwrap();
        let original = crate::study::inputs::file_digest(&mesh).unwrap();
        // The file changes after the model was built from it.
        let mut text = std::fs::read_to_string(&mesh).unwrap();
        text.push('\n');
        std::fs::write(&mesh, text).unwrap();
        assert_ne!(crate::study::inputs::file_digest(&mesh).unwrap(), original);
        let opts = RunOptions {
            out_dir: tmp.path().join("out"),
            force: false,
            progress: false,
            checkpoint_every_s: None,
            resume: None,
            viewer: false,
            case_of: None,
        };
        let record = fresh_record(&s, &opts, &built).unwrap();
        assert_eq!(record.inputs.len(), 1);
        assert_eq!(record.inputs[0].digest, original);
        // A resume whose model was built from the changed bytes is refused, naming the key.
        let dir = tmp.path().join("run");
        std::fs::create_dir(&dir).unwrap();
        record.write(&dir).unwrap();
        let rebuilt = crate::build::build(&s).unwrap();
        let err = resume::check_built_inputs(&dir, &rebuilt)
            .unwrap_err()
            .to_string();
        assert!(err.contains("canopy.mesh_file"), "{err}");
        resume::check_built_inputs(&dir, &built).unwrap();
    }
}

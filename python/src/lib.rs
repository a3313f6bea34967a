//! `chute._native`: the Rust half of the Python package `chute` (docs/python.md). The
//! Python half (`python/chute/`) holds the public API, its docstrings and the `Result`
//! class; this module runs scenarios, studies and the verification suite through the
//! `chute` crate exactly as the command line does, and steps a `Simulation`.
//!
//! Long calls run with the GIL released and poll Python's signal handlers between steps (a
//! whole run: on a worker thread, polled from the calling thread; a `Simulation`: between its
//! steps), so Ctrl-C stops a run gracefully with its partial outputs.

mod convert;
mod simulation;
mod watch;

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};

use pyo3::prelude::*;

use chute::api::Scenario;
use chute::api::{self, RunOptions, Watch};
use chute::api::{CaseStatus, Shard, StudyOptions};
pub use convert::{RunError, ScenarioError};

/// Run scenario `path` with overrides `set` (`KEY=VALUE` texts) into the existing or new
/// directory `out` as `chute run` does; `progress(t_s, duration_s)` is called about ten
/// times a second while it runs. Returns `(complete, message)`: whether the run reached
/// `time.duration_s` and why not (or a warning). Raises `ScenarioError` for bad input,
/// `RunError` when the run cannot produce its outputs, and re-raises the exception of a
/// signal handler (KeyboardInterrupt) or of `progress` after the run has stopped at its next
/// step with valid partial outputs.
#[pyfunction]
#[pyo3(signature = (path, set, out, force, viewer, progress=None))]
fn run(
    py: Python<'_>,
    path: PathBuf,
    set: Vec<String>,
    out: PathBuf,
    force: bool,
    viewer: bool,
    progress: Option<Bound<'_, PyAny>>,
) -> PyResult<(bool, Option<String>)> {
    let s = api::load(&path, &set).map_err(convert::app_err)?;
    // Held until the viewer is written: one process writes a run directory at a time.
    let prepared = api::prepare_out_dir(&out, force).map_err(convert::app_err)?;
    let opts = RunOptions {
        out_dir: out.clone(),
        force,
        progress: false,
        checkpoint_every_s: None,
        resume: None,
        viewer,
        case_of: None,
    };
    let stop = AtomicBool::new(false);
    let sim_time = AtomicU64::new(0f64.to_bits());
    let watch = Watch {
        stop: &stop,
        sim_time: Some(&sim_time),
    };
    let duration = s.time.duration_s;
    let tick = || match &progress {
        Some(p) => p
            .call1((f64::from_bits(sim_time.load(Ordering::Relaxed)), duration))
            .map(drop),
        None => Ok(()),
    };
    let outcome = watch::watched(py, &stop, || api::run(&s, &opts, watch), tick)?;
    if viewer && outcome.is_ok() {
        // As `chute run`: a viewer that cannot be written is a warning, not a failure.
        if let Err(e) = api::write_viewer(&out) {
            let msg = format!("viewer.html not written: {e}");
            PyErr::warn(
                py,
                &py.get_type::<pyo3::exceptions::PyUserWarning>(),
                &std::ffi::CString::new(msg).unwrap_or_default(),
                1,
            )?;
        }
    }
    prepared.release();
    let o = outcome.map_err(convert::app_err)?;
    Ok((o.complete, o.message))
}

/// Run study file `path` (every case validated first, then `jobs` in parallel, each into
/// `out/<case>/`) as `chute study` does. Returns `(case, status, message)` per selected case
/// in case order, status one of `complete`, `incomplete`, `failed`, `skipped` (complete
/// from an earlier invocation). `progress(finished, to_run)` is called about ten times a
/// second with the number of cases that have ended and of those to run (not skipped).
/// Signals stop every running case gracefully (see `run`). `shard = (i, n)` runs only the cases
/// whose index is `i` modulo `n`, as `chute study --shard i/n`.
#[pyfunction]
#[pyo3(signature = (path, out, jobs=None, set=Vec::new(), force=false, progress=None, shard=None))]
#[allow(clippy::too_many_arguments)]
fn study(
    py: Python<'_>,
    path: PathBuf,
    out: PathBuf,
    jobs: Option<usize>,
    set: Vec<String>,
    force: bool,
    progress: Option<Bound<'_, PyAny>>,
    shard: Option<(usize, usize)>,
) -> PyResult<Vec<(String, String, Option<String>)>> {
    let st = api::load_study(&path).map_err(convert::app_err)?;
    if jobs == Some(0) {
        return Err(ScenarioError::new_err("jobs must be at least 1"));
    }
    let shard = match shard {
        Some((index, count)) if index < count => Some(Shard { index, count }),
        Some((i, n)) => {
            return Err(ScenarioError::new_err(format!(
                "shard ({i}, {n}): give 0 ≤ i < n"
            )))
        }
        None => None,
    };
    let mine = |c: &api::Case| shard.is_none_or(|s| c.index % s.count == s.index);
    let to_run = (st.cases.iter())
        .filter(|c| mine(c) && (force || !api::case_is_current(&st, c, &set, &out)))
        .count();
    let opts = StudyOptions {
        out_dir: out,
        jobs,
        set,
        shard,
        force,
        verbose: false,
    };
    let stop = AtomicBool::new(false);
    let finished = AtomicUsize::new(0);
    let runner = |s: &Scenario, o: &RunOptions| {
        let watch = Watch {
            stop: &stop,
            sim_time: None,
        };
        let r = api::run(s, o, watch);
        finished.fetch_add(1, Ordering::Relaxed);
        r
    };
    let tick = || match &progress {
        Some(p) => p
            .call1((finished.load(Ordering::Relaxed), to_run))
            .map(drop),
        None => Ok(()),
    };
    let report = watch::watched(py, &stop, || api::study(&st, &opts, &runner), tick)?
        .map_err(convert::app_err)?;
    Ok(report
        .cases
        .into_iter()
        .map(|(name, status)| {
            let (word, message) = match status {
                CaseStatus::Complete => ("complete", None),
                CaseStatus::Skipped => ("skipped", None),
                CaseStatus::Incomplete(m) => ("incomplete", Some(m)),
                CaseStatus::Failed(m) => ("failed", Some(m)),
            };
            (name, word.to_string(), message)
        })
        .collect())
}

/// The case names of study file `path`, in order, every case validated with the study-wide
/// overrides `set` first (as `study` does before it runs any).
#[pyfunction]
#[pyo3(signature = (path, set=Vec::new()))]
fn study_cases(path: PathBuf, set: Vec<String>) -> PyResult<Vec<String>> {
    let st = api::load_study(&path).map_err(convert::app_err)?;
    for c in &st.cases {
        st.scenario(c, &set).map_err(convert::app_err)?;
    }
    Ok(st.cases.into_iter().map(|c| c.name).collect())
}

/// `chute collect DIRS --out OUT`: the study table (and a dispersion's files) of the cases
/// found in `dirs`. Returns the warnings of cases that are not complete (empty when every case
/// of the study is complete).
#[pyfunction]
fn collect(py: Python<'_>, dirs: Vec<PathBuf>, out: PathBuf) -> PyResult<Vec<String>> {
    let table = py
        .detach(|| api::collect(&dirs, &out))
        .map_err(convert::app_err)?;
    Ok(table.unfinished())
}

/// Run the verification suite (`chute validate`; `quick` for the short versions, `case` to
/// select cases by name) and return its checks as JSON text. A signal raises at once; the
/// case that is running finishes in the background (the cases take no stop request).
#[pyfunction]
#[pyo3(signature = (quick=true, case=None))]
fn validate(py: Python<'_>, quick: bool, case: Option<String>) -> PyResult<String> {
    let args = api::ValidateArgs {
        quick,
        case,
        ..Default::default()
    };
    let checks = watch::watched_detached(py, move || api::validate(&args))?;
    serde_json::to_string(&checks).map_err(|e| RunError::new_err(format!("JSON: {e}")))
}

/// `chute steady`: the report as JSON text, the equilibrium's node positions `(n, 3)` and the
/// modes' shapes `(modes, n, 3)` (complex); `out` also gets `stability.json`.
#[pyfunction]
#[pyo3(signature = (path, set, out=None))]
fn steady<'py>(
    py: Python<'py>,
    path: PathBuf,
    set: Vec<String>,
    out: Option<PathBuf>,
) -> PyResult<Bound<'py, pyo3::types::PyTuple>> {
    let s = api::load(&path, &set).map_err(convert::app_err)?;
    if let Some(dir) = &out {
        api::check_stability_out(dir).map_err(convert::app_err)?;
    }
    let r = watch::watched_detached(py, move || api::steady(&s))?.map_err(convert::app_err)?;
    if let Some(dir) = &out {
        api::write_stability(&r, dir).map_err(convert::app_err)?;
    }
    convert::steady(py, &r)
}

/// The frames of run directory `dir` (`canopy.pvd`): `(times, positions, velocities,
/// triangles, segments)` with shapes (F,), (F, n, 3), (F, n, 3), (m, 3), (k, 2).
#[pyfunction]
fn read_frames(py: Python<'_>, dir: PathBuf) -> PyResult<Bound<'_, pyo3::types::PyTuple>> {
    convert::frames(py, &dir)
}

/// The `chute._native` module.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("ScenarioError", py.get_type::<ScenarioError>())?;
    m.add("RunError", py.get_type::<RunError>())?;
    m.add_class::<simulation::Simulation>()?;
    m.add_function(wrap_pyfunction!(run, m)?)?;
    m.add_function(wrap_pyfunction!(steady, m)?)?;
    m.add_function(wrap_pyfunction!(study, m)?)?;
    m.add_function(wrap_pyfunction!(study_cases, m)?)?;
    m.add_function(wrap_pyfunction!(collect, m)?)?;
    m.add_function(wrap_pyfunction!(validate, m)?)?;
    m.add_function(wrap_pyfunction!(read_frames, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}

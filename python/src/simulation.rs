//! `chute._native.Simulation`: a run stepped from Python (`chute::api::Session`).

use std::path::{Path, PathBuf};

use pyo3::prelude::*;

use chute::api::{AppError, Session};

use crate::convert::{self, app_err, RunError};

/// A scenario's run stepped by the caller, with the physics of `chute.run` (the Python
/// class `chute.Simulation` wraps it; its docstrings are the reference).
#[pyclass(module = "chute._native")]
pub struct Simulation {
    session: Session,
}

fn session(path: &Path, set: &[String]) -> Result<Session, AppError> {
    chute::api::session(&chute::api::load(path, set)?)
}

#[pymethods]
impl Simulation {
    #[new]
    #[pyo3(signature = (path, set=Vec::new()))]
    fn new(path: PathBuf, set: Vec<String>) -> PyResult<Self> {
        Ok(Self {
            session: session(&path, &set).map_err(app_err)?,
        })
    }

    /// Take up to `n` steps (fewer at the end); the number taken. The GIL is released during
    /// each step and the signal handlers run between steps: KeyboardInterrupt leaves the
    /// state after the last whole step.
    #[pyo3(signature = (n=1))]
    fn step(&mut self, py: Python<'_>, n: u64) -> PyResult<u64> {
        let mut taken = 0;
        while taken < n {
            let session = &mut self.session;
            match py.detach(|| session.step()) {
                Ok(Some(_)) => taken += 1,
                Ok(None) => break,
                Err(stopped) => return Err(RunError::new_err(stopped.to_string())),
            }
            py.check_signals()?;
        }
        Ok(taken)
    }

    /// Step until the time reaches `t` (s) or the end; the number of steps taken.
    fn advance_to(&mut self, py: Python<'_>, t: f64) -> PyResult<u64> {
        let mut taken = 0;
        while !self.session.reached(t) && !self.session.finished() {
            taken += self.step(py, 1)?;
        }
        Ok(taken)
    }

    #[getter]
    fn time(&self) -> f64 {
        self.session.time()
    }

    #[getter]
    fn duration(&self) -> f64 {
        self.session.config().stepping.duration_s
    }

    #[getter]
    fn steps(&self) -> u64 {
        self.session.steps()
    }

    #[getter]
    fn finished(&self) -> bool {
        self.session.finished()
    }

    #[getter]
    fn stop_reason(&self) -> Option<String> {
        self.session.stop_reason().map(str::to_string)
    }

    #[getter]
    fn positions<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        let b = self.session.built();
        convert::nodes3(py, &b.state.q, b.model.layout.n_nodes)
    }

    #[getter]
    fn velocities<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        let b = self.session.built();
        convert::nodes3(py, &b.state.v, b.model.layout.n_nodes)
    }

    #[getter]
    fn triangles<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        let t: Vec<[u64; 3]> = (self.session.built().triangles.iter())
            .map(|t| t.map(|i| i as u64))
            .collect();
        convert::index_rows(py, &t)
    }

    #[getter]
    fn rod_edges<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        let e: Vec<[u64; 2]> = (self.session.built().segments.iter())
            .map(|s| s.map(|i| i as u64))
            .collect();
        convert::index_rows(py, &e)
    }

    #[getter]
    fn canopy_nodes(&self) -> Vec<usize> {
        self.session.built().canopy_nodes.clone()
    }

    #[getter]
    fn load_sites(&self) -> Vec<usize> {
        self.session.built().load_sites.clone()
    }

    #[getter]
    fn payload_node(&self) -> Option<usize> {
        self.session.built().payload_node
    }

    /// The summary so far (a dict like `summary.json`).
    fn summary<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        convert::json(py, &self.session.summary().to_json())
    }
}

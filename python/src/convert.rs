//! Conversions between the `chute` crate and Python: errors to exceptions, JSON to Python
//! objects, frames and states to numpy arrays.

use std::path::Path;

use numpy::ndarray::{Array1, Array2, Array3};
use numpy::IntoPyArray;
use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyTuple;

use chute::api::{self, AppError, RunDirError};

pyo3::create_exception!(
    chute,
    ScenarioError,
    PyValueError,
    "Bad input: a scenario, an override, a study file or an output directory. The message is \
     the one `chute` prints after `error: `, an override named as the entry of `set` it came \
     from; it names the key and where its value came from."
);
pyo3::create_exception!(
    chute,
    RunError,
    pyo3::exceptions::PyRuntimeError,
    "A run that failed or stopped before `time.duration_s`. `result` holds its partial \
     `Result` when it wrote outputs (None otherwise)."
);

/// The exception for an application error: bad input (exit status 2 of the command line) is
/// `ScenarioError`, a failed run (status 3) `RunError`, a file that could not be read or
/// written `OSError`; the message is the command line's.
pub fn app_err(e: AppError) -> PyErr {
    let msg = python_words(&e.to_string());
    match e {
        AppError::Scenario(_) | AppError::Build(_) | AppError::Input(_) => {
            ScenarioError::new_err(msg)
        }
        AppError::RunFailed(_) | AppError::ValidationFailed { .. } => RunError::new_err(msg),
        AppError::Io { .. } => PyOSError::new_err(msg),
    }
}

/// The command line's message in the words of the Python call: an override is an entry of
/// `set` (`set["load.weight_n"] = -5`, not `--set load.weight_n=-5`), `--force` is
/// `force=True` and `--out DIR` the argument `out`.
pub fn python_words(msg: &str) -> String {
    let mut out = String::with_capacity(msg.len());
    let mut rest = msg;
    while let Some(i) = rest.find("`--set ") {
        out.push_str(&rest[..i]);
        let arg = &rest[i + "`--set ".len()..];
        let Some(end) = arg.find('`') else {
            out.push_str(&rest[i..]);
            rest = "";
            break;
        };
        match arg[..end].split_once('=') {
            Some((key, value)) => out.push_str(&format!("`set[\"{key}\"] = {value}`")),
            None => out.push_str(&format!("`set` entry `{}`", &arg[..end])),
        }
        rest = &arg[end + 1..];
    }
    out.push_str(rest);
    out.replace("--force", "force=True")
        .replace("--out DIR", "`out`")
        .replace("--out", "`out`")
}

fn run_dir_err(e: RunDirError) -> PyErr {
    PyOSError::new_err(e.to_string())
}

/// JSON text as Python objects (`json.loads`).
pub fn json<'py>(py: Python<'py>, text: &str) -> PyResult<Bound<'py, PyAny>> {
    py.import("json")?.call_method1("loads", (text,))
}

/// Node coordinates of `q` (3 per node, then rod twists) as an (n, 3) float64 array.
pub fn nodes3<'py>(py: Python<'py>, q: &[f64], n: usize) -> Bound<'py, PyAny> {
    let a = Array2::from_shape_vec((n, 3), q[..3 * n].to_vec()).expect("3 coordinates per node");
    a.into_pyarray(py).into_any()
}

/// Index tuples as an (m, K) int64 array.
pub fn index_rows<'py, const K: usize, T: Copy + Into<u64>>(
    py: Python<'py>,
    rows: &[[T; K]],
) -> Bound<'py, PyAny> {
    let flat: Vec<i64> = rows.iter().flatten().map(|&i| i.into() as i64).collect();
    let a = Array2::from_shape_vec((rows.len(), K), flat).expect("K indices per row");
    a.into_pyarray(py).into_any()
}

/// The frames of a run directory (see `read_frames` in lib.rs).
pub fn frames<'py>(py: Python<'py>, dir: &Path) -> PyResult<Bound<'py, PyTuple>> {
    let list = api::frame_list(dir).map_err(run_dir_err)?;
    let mut times = Vec::with_capacity(list.len());
    let (mut pos, mut vel) = (Vec::new(), Vec::new());
    let mut mesh = api::FrameMesh::default();
    for (k, (t, path)) in list.iter().enumerate() {
        let (m, st) = api::read_frame(path).map_err(run_dir_err)?;
        if k == 0 {
            mesh = m;
        } else if m.n_nodes != mesh.n_nodes {
            let msg = format!(
                "{}: {} nodes, the first frame has {}",
                path.display(),
                m.n_nodes,
                mesh.n_nodes
            );
            return Err(PyOSError::new_err(msg));
        }
        times.push(*t);
        pos.extend(st.positions.iter().flatten());
        vel.extend(st.velocities.iter().flatten());
    }
    let shape = (list.len(), mesh.n_nodes, 3);
    let cube = |v: Vec<f64>| Array3::from_shape_vec(shape, v).expect("n nodes per frame");
    let items = [
        Array1::from_vec(times).into_pyarray(py).into_any(),
        cube(pos).into_pyarray(py).into_any(),
        cube(vel).into_pyarray(py).into_any(),
        index_rows(py, &mesh.triangles),
        index_rows(py, &mesh.segments),
    ];
    PyTuple::new(py, items)
}

/// A `chute steady` report for Python: `(json, positions (n, 3), shapes (modes, n, 3))`.
pub fn steady<'py>(py: Python<'py>, r: &api::SteadyReport) -> PyResult<Bound<'py, PyTuple>> {
    let json = serde_json::to_string(r).map_err(|e| PyValueError::new_err(e.to_string()))?;
    let n = r.positions_m.len();
    let pos: Vec<f64> = r.positions_m.iter().flatten().copied().collect();
    let shapes: Vec<numpy::Complex64> = r
        .modes
        .iter()
        .flat_map(|m| m.shape.iter().flatten())
        .map(|z| numpy::Complex64::new(z.re, z.im))
        .collect();
    let items = [
        json.into_pyobject(py)?.into_any(),
        Array2::from_shape_vec((n, 3), pos)
            .expect("3 per node")
            .into_pyarray(py)
            .into_any(),
        Array3::from_shape_vec((r.modes.len(), n, 3), shapes)
            .expect("3 per node and mode")
            .into_pyarray(py)
            .into_any(),
    ];
    PyTuple::new(py, items)
}

//! Long calls with the GIL released and Python's signal handlers polled: the work runs on a
//! worker thread while the calling thread waits for it without the GIL, waking every
//! [`POLL`] to run the handlers (`Python::check_signals`) and a progress callback.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, RecvTimeoutError};
use std::time::Duration;

use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;

/// How often the waiting thread runs the signal handlers and the progress callback.
const POLL: Duration = Duration::from_millis(100);

fn internal_error() -> PyErr {
    PyRuntimeError::new_err("internal error (a bug in chute; please report it with the input)")
}

/// Wait without the GIL until `rx`'s sender is dropped (the worker ended) or [`POLL`] passed;
/// whether it ended.
fn wait(py: Python<'_>, rx: mpsc::Receiver<()>) -> (bool, mpsc::Receiver<()>) {
    py.detach(move || {
        let ended = matches!(rx.recv_timeout(POLL), Err(RecvTimeoutError::Disconnected));
        (ended, rx)
    })
}

/// Run `work` on a worker thread with the GIL released. Meanwhile the signal handlers and
/// `tick` run every [`POLL`] (and `tick` once more at the end); when one raises, `stop` is set (the work must then end soon and
/// gracefully) and, once the work has ended, that exception is returned instead of its
/// result. A panic in the work is an internal error.
pub fn watched<T: Send>(
    py: Python<'_>,
    stop: &AtomicBool,
    work: impl FnOnce() -> T + Send,
    mut tick: impl FnMut() -> PyResult<()>,
) -> PyResult<T> {
    std::thread::scope(|scope| {
        let (tx, mut rx) = mpsc::channel::<()>();
        let handle = scope.spawn(move || {
            // Dropped when the work returns or unwinds: either wakes the waiting thread.
            let _done = tx;
            work()
        });
        let mut raised: Option<PyErr> = None;
        loop {
            let (ended, back) = wait(py, rx);
            rx = back;
            if ended {
                break;
            }
            if raised.is_none() {
                if let Err(e) = py.check_signals().and_then(|()| tick()) {
                    stop.store(true, Ordering::SeqCst);
                    raised = Some(e);
                }
            }
        }
        let result = handle.join().map_err(|_| internal_error())?;
        match raised {
            Some(e) => Err(e),
            // Once more at the end, so a progress display shows where the work ended.
            None => tick().map(|()| result),
        }
    })
}

/// Run `work`, which cannot be stopped, on a worker thread with the GIL released, polling
/// the signal handlers; when one raises, its exception is returned at once and the work goes
/// on to its end in the background, its result dropped.
pub fn watched_detached<T: Send + 'static>(
    py: Python<'_>,
    work: impl FnOnce() -> T + Send + 'static,
) -> PyResult<T> {
    let (tx, mut rx) = mpsc::channel::<()>();
    let handle = std::thread::spawn(move || {
        let _done = tx;
        work()
    });
    loop {
        let (ended, back) = wait(py, rx);
        rx = back;
        if ended {
            return handle.join().map_err(|_| internal_error());
        }
        py.check_signals()?;
    }
}

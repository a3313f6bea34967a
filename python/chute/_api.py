"""chute.run, chute.study and chute.validate, and the Result of a run."""

from __future__ import annotations

import csv
import functools
import json
import os
import pathlib
import tempfile
from typing import Any, NamedTuple

import numpy as np

from . import _native
from ._native import RunError, ScenarioError
from ._overrides import Overrides, PathLike, existing, overrides
from ._progress import ProgressBar, cases_label

__all__ = ["Frames", "Result", "run", "study", "validate"]

# timeseries.csv columns that hold counts, not measurements.
_INTEGER_COLUMNS = {"newton_iterations"}


class Frames(NamedTuple):
    """The frames of a run (``canopy.pvd``, every ``output.frame_interval_s``)."""

    times: np.ndarray
    """Frame times (s), shape (F,)."""
    positions: np.ndarray
    """Node positions (m), shape (F, n, 3)."""
    velocities: np.ndarray
    """Node velocities (m/s), shape (F, n, 3)."""
    triangles: np.ndarray
    """Canopy triangles (node indices), shape (m, 3), int64; empty for a rod canopy."""
    rod_edges: np.ndarray
    """Rod edges: canopy strip and suspension lines (node indices), shape (k, 2), int64."""


class Result:
    """The outputs of one run, read from its output directory on first use.

    ``out_dir`` holds every file ``chute run`` writes (docs/outputs.md). A run made with
    ``out=None`` lives in a temporary directory that is removed when the Result is garbage
    collected (or on :meth:`cleanup`); copy what you need, or pass ``out``.
    """

    def __init__(self, out_dir: PathLike, tmp: tempfile.TemporaryDirectory | None = None):
        self.out_dir = pathlib.Path(out_dir)
        self._tmp = tmp  # keeps the temporary directory alive as long as the Result

    @functools.cached_property
    def summary(self) -> dict[str, Any]:
        """``summary.json`` as a dict (keys documented in docs/outputs.md)."""
        with open(self.out_dir / "summary.json", encoding="utf-8") as f:
            return json.load(f)

    @functools.cached_property
    def timeseries(self) -> dict[str, np.ndarray]:
        """``timeseries.csv`` as a dict of 1-D numpy arrays keyed by column name (one entry
        per accepted step, plus the initial state); float64, ``newton_iterations`` int64.
        The values are those of the file exactly (it prints every digit)."""
        path = self.out_dir / "timeseries.csv"
        with open(path, newline="", encoding="utf-8") as f:
            header = next(csv.reader(f))
        data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2, dtype=np.float64)
        columns = {}
        for k, name in enumerate(header):
            col = data[:, k].copy() if data.size else np.empty(0)
            columns[name] = col.astype(np.int64) if name in _INTEGER_COLUMNS else col
        return columns

    @functools.cached_property
    def frames(self) -> Frames:
        """The frames as a :class:`Frames` (times and an array of positions per frame)."""
        return Frames(*_native.read_frames(str(self.out_dir)))

    @property
    def complete(self) -> bool:
        """Whether the run reached ``time.duration_s``."""
        return bool(self.summary["complete"])

    def cleanup(self) -> None:
        """Remove the temporary output directory now (runs with ``out=None`` only)."""
        if self._tmp is not None:
            self._tmp.cleanup()
            self._tmp = None

    def __repr__(self) -> str:
        try:
            s = self.summary
        except OSError:
            return f"<chute.Result {str(self.out_dir)!r} (no summary.json)>"
        v = s.get("terminal_velocity_mps")
        v = "n/a" if v is None else f"{v:.4g} m/s"
        state = "complete" if s.get("complete") else "INCOMPLETE"
        return (
            f"<chute.Result {s.get('scenario_name')!r}: {state}, "
            f"t = {s.get('simulated_time_s')} s, terminal velocity {v}, "
            f"reached: {s.get('reached_terminal')}; {str(self.out_dir)!r}>"
        )


def _output_dir(out, force):
    """The output directory and the temporary directory object (None when `out` is given)."""
    if out is None:
        tmp = tempfile.TemporaryDirectory(prefix="chute-run-")
        return tmp.name, tmp
    out = os.fspath(out)
    if os.path.isdir(out) and os.listdir(out) and not force:
        raise ScenarioError(
            f"output directory `{out}` already exists and is not empty; pass force=True to "
            "overwrite it, or out=DIR to choose another"
        )
    return out, None


def run(
    path: PathLike,
    set: Overrides = None,
    out: PathLike | None = None,
    progress: bool = False,
    force: bool = False,
    viewer: bool = True,
) -> Result:
    """Run a scenario as ``chute run`` does and return its :class:`Result`.

    Parameters
    ----------
    path : str or os.PathLike
        The scenario file (TOML, docs/scenarios.md).
    set : dict or list of str, optional
        Overrides, like ``--set``: ``{"load.weight_n": 500, "time.adaptive": True}`` or
        ``["load.weight_n=500"]``. Values go through the same checks as the file's.
    out : str or os.PathLike, optional
        Output directory. None: a temporary directory kept alive by the Result.
    progress : bool
        Draw a text progress bar on ``sys.stderr``.
    force : bool
        Replace an earlier chute run in a non-empty output directory (``--force``); a
        non-empty directory that is not a chute run directory is refused.
    viewer : bool
        Write ``viewer.html`` (as ``chute run`` does unless ``--no-viewer``).

    Raises
    ------
    ScenarioError
        Bad input, with the message ``chute`` prints (it names the key).
    RunError
        The run failed or stopped before ``time.duration_s``; ``.result`` holds the
        partial Result (summary marked incomplete, time series and frames up to the stop).
    KeyboardInterrupt
        Ctrl-C: the run stops at its next step and writes valid partial outputs first; the
        exception's ``.result`` holds them.
    """
    out_dir, tmp = _output_dir(out, force)
    bar = ProgressBar() if progress else None
    try:
        complete, message = _native.run(
            existing(path), overrides(set), out_dir, force, viewer, bar
        )
    except (ScenarioError, OSError):
        raise
    except BaseException as e:
        # A failed run, a signal handler's exception (KeyboardInterrupt) or the progress
        # bar's: the run has stopped gracefully and its partial outputs are complete files.
        has_outputs = os.path.exists(os.path.join(out_dir, "summary.json"))
        e.result = Result(out_dir, tmp) if has_outputs else None
        raise
    finally:
        if bar is not None:
            bar.close()
    result = Result(out_dir, tmp)
    if not complete:
        err = RunError(
            f"stopped before time.duration_s: {message or 'no reason given'}; partial "
            f"outputs are in `{out_dir}`"
        )
        err.result = result
        raise err
    return result


def _value(text):
    """A study override's value text as a Python value (a number when it is one)."""
    try:
        return json.loads(text)
    except ValueError:
        return text


def _case_row(study_dir, name, status, message):
    row = {"case": name}
    case_dir = pathlib.Path(study_dir) / name
    try:
        with open(case_dir / "done.json", encoding="utf-8") as f:
            done = json.load(f)
        for key, value in done.get("overrides", []):
            row[key] = _value(value)
    except OSError:
        pass
    row["status"] = status
    row["message"] = message
    try:
        with open(case_dir / "summary.json", encoding="utf-8") as f:
            row.update(json.load(f))
    except OSError:
        pass
    row["out_dir"] = str(case_dir)
    return row


def study(
    path: PathLike,
    jobs: int | None = None,
    out: PathLike | None = None,
    set: Overrides = None,
    force: bool = False,
    as_frame: bool = False,
    progress: bool = False,
) -> Any:
    """Run a study file as ``chute study`` does and return one row per case.

    Every case is validated before any runs; then ``jobs`` cases run in parallel (default
    one per core), each into ``out/<case>/``, and ``study.csv`` and ``study.md`` are written
    into ``out`` (docs/cli.md §chute study). With ``out=None`` the study runs in a temporary
    directory that is removed before this returns (the rows keep the numbers).

    Returns a list of dicts in case order: ``case``, the case's overridden keys
    (``"load.weight_n": 20``), ``status`` (``complete``, ``incomplete``, ``failed`` or
    ``skipped`` when complete from an earlier call with the same ``out``), ``message``, then
    every ``summary.json`` field and ``out_dir``. With ``as_frame=True``, a pandas
    DataFrame of the same rows (ImportError when pandas is not installed).

    ``set`` overrides keys in every case, before the cases' own; ``force`` re-runs complete
    cases; ``progress`` draws a text progress bar of the cases on ``sys.stderr``. Raises
    ScenarioError for a bad study file or case (nothing has run then); a case that fails
    does not raise (its row says so). Ctrl-C stops every running case at its next step
    (their partial outputs stay in ``out``) and raises KeyboardInterrupt.
    """
    if as_frame:
        try:
            import pandas
        except ImportError as e:
            raise ImportError(
                "chute.study(..., as_frame=True) needs pandas: pip install pandas "
                "(or call it without as_frame for a list of dicts)"
            ) from e
    tmp = tempfile.TemporaryDirectory(prefix="chute-study-") if out is None else None
    study_dir = tmp.name if tmp is not None else os.fspath(out)
    bar = ProgressBar(label=cases_label) if progress else None
    try:
        cases = _native.study(
            existing(path, "study file"), study_dir, jobs, overrides(set), force, bar
        )
        rows = [_case_row(study_dir, *c) for c in cases]
    finally:
        if bar is not None:
            bar.close()
        if tmp is not None:
            tmp.cleanup()
    if tmp is not None:
        for row in rows:
            row["out_dir"] = None
    if as_frame:
        return pandas.DataFrame(rows)
    return rows


def validate(quick: bool = True, case: str | None = None) -> list[dict[str, Any]]:
    """Run the verification suite (``chute validate``) and return its checks.

    ``quick`` runs the short versions (under a minute on 2 cores); ``case`` selects the
    cases whose name contains it. Returns a list of dicts: ``name``, ``quantity``,
    ``reference``, ``source``, ``simulated``, ``rel_error``, ``tolerance``, ``pass``,
    ``wall_s`` (docs/validation.md). It does not raise when a check fails: test
    ``all(c["pass"] for c in checks)``.
    """
    return json.loads(_native.validate(quick, case))

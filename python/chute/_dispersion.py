"""chute.dispersion: a study's ``[dispersion]`` run here or on a Dask cluster, and its footprint."""

from __future__ import annotations

import csv
import json
import os
import pathlib
import tempfile
from typing import Any

from . import _native
from ._native import ScenarioError
from ._overrides import Overrides, PathLike, existing, overrides

__all__ = ["Dispersion", "dispersion"]


def _number(text: str) -> float | None:
    return float(text) if text != "" else None


class Dispersion:
    """The outputs of a dispersion study, read from its output directory.

    ``samples`` holds ``dispersion.csv``: one dict per sample (``sample``, each drawn key,
    ``landing_x_m``, ``landing_y_m``, ``flight_time_s``, ``landing_velocity_mps``,
    ``peak_line_tension_n``; None where a sample has not landed). ``footprint`` and
    ``sensitivity`` are those of ``footprint.json`` (docs/dispersion.md), None until every
    sample has landed. ``unfinished`` holds a line per sample that did not run to its end
    (failed, stopped, missing), saying why, and ``not_landed`` the names of the samples
    without a landing.
    """

    def __init__(self, out_dir: PathLike | None, rows, footprint, unfinished):
        self.out_dir = None if out_dir is None else pathlib.Path(out_dir)
        self.samples: list[dict[str, Any]] = rows
        self.footprint: dict[str, Any] | None = footprint and footprint["footprint"]
        self.sensitivity: list[dict[str, Any]] | None = footprint and footprint["sensitivity"]
        self.unfinished: list[str] = unfinished

    @property
    def not_landed(self) -> list[str]:
        """The samples that have no landing (not run, failed, or still aloft at the end)."""
        return [s["sample"] for s in self.samples if s["landing_x_m"] is None]

    def frame(self):
        """``samples`` as a pandas DataFrame (ImportError without pandas)."""
        import pandas

        return pandas.DataFrame(self.samples)

    def __repr__(self) -> str:
        n = len(self.samples)
        if self.footprint is None:
            return f"<chute.Dispersion: {n} samples, {len(self.unfinished)} not landed>"
        f = self.footprint
        return (
            f"<chute.Dispersion: {n} samples, mean landing ({f['mean_m'][0]:.1f}, "
            f"{f['mean_m'][1]:.1f}) m, CEP50 {f['cep50_m']:.1f} m>"
        )


def _read(out_dir: str, unfinished: list[str]) -> Dispersion:
    with open(os.path.join(out_dir, "dispersion.csv"), newline="", encoding="utf-8") as f:
        reader = csv.DictReader(f)
        rows = [
            {k: (v if k == "sample" else _number(v)) for k, v in r.items()} for r in reader
        ]
    try:
        with open(os.path.join(out_dir, "footprint.json"), encoding="utf-8") as f:
            footprint = json.load(f)
    except FileNotFoundError:
        footprint = None
    return Dispersion(out_dir, rows, footprint, unfinished)


def _run_shard(index: int, path: str, out: str, count: int, set: list[str], force: bool):
    """One Dask task: shard ``index`` of ``count``, as ``chute study --shard index/count``."""
    return _native.study(path, out, 1, set, force, None, (index, count))


def dispersion(
    path: PathLike,
    out: PathLike | None = None,
    client: Any = None,
    jobs: int | None = None,
    set: Overrides = None,
    force: bool = False,
) -> Dispersion:
    """Run a study file's ``[dispersion]`` and return its :class:`Dispersion`.

    Without ``client`` the samples run here, ``jobs`` at a time (default one per core), as
    ``chute study`` runs them. With a ``dask.distributed.Client`` the samples are split into
    shards, up to four per worker thread, each one task on its cluster (``chute study --shard
    i/N``), then collected (``chute collect``). The workers must see ``out`` and the study's
    files at the same paths (one machine, or a shared file system). Each sample's inputs come
    from (seed, its index) alone, so every way gives the same files, byte for byte.

    ``out=None`` runs in a temporary directory removed before this returns (``out_dir`` is
    then None; the samples and footprint are kept). ``set`` overrides keys in every sample;
    ``force`` re-runs finished samples. Raises ScenarioError for a bad study file or sample
    before anything runs; a sample that fails does not raise (``unfinished`` names it).
    """
    study_file = existing(path, "study file")
    sets = overrides(set)
    names = _native.study_cases(study_file, sets)  # validates every sample first
    tmp = tempfile.TemporaryDirectory(prefix="chute-dispersion-") if out is None else None
    out_dir = tmp.name if tmp is not None else os.path.abspath(os.fspath(out))
    try:
        if client is None:
            _native.study(study_file, out_dir, jobs, sets, force)
        else:
            if jobs is not None:
                raise ScenarioError("jobs is for a run here: a Dask cluster has its own workers")
            os.makedirs(out_dir, exist_ok=True)
            # Every shard reads and checks the whole study, so not one per sample: four per
            # worker thread balance the load without that cost growing as N².
            threads = sum(client.nthreads().values()) or 1
            n = min(len(names), 4 * threads)
            futures = client.map(
                _run_shard,
                range(n),
                path=os.path.abspath(study_file),
                out=out_dir,
                count=n,
                set=sets,
                force=force,
                pure=False,
            )
            client.gather(futures)
        unfinished = _native.collect([out_dir], out_dir)
        result = _read(out_dir, unfinished)
    finally:
        if tmp is not None:
            tmp.cleanup()
    if tmp is not None:
        result.out_dir = None
    return result

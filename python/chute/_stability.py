"""chute.steady and chute.modes: the steady descent as an equilibrium and its modes
(``chute steady``, docs/cli.md)."""

from __future__ import annotations

import json
from typing import Any

import numpy as np

from . import _native
from ._overrides import Overrides, PathLike, existing, overrides

__all__ = ["modes", "steady"]


def steady(path: PathLike, set: Overrides = None, out: PathLike | None = None) -> dict[str, Any]:
    """Fly scenario ``path`` for ``time.duration_s``, then solve its steady descent and the
    modes of the motion about it (``chute steady``).

    Returns the fields of ``stability.json`` (docs/cli.md §chute steady), with
    ``velocity_mps`` as an array of shape (3,), ``positions_m`` the equilibrium's node
    positions (n, 3), and in each of ``modes`` a ``shape`` (n, 3), complex. ``out`` also
    writes ``out/stability.json`` (a directory that holds anything else is refused).
    """
    text, positions, shapes = _native.steady(
        existing(path), overrides(set), None if out is None else str(out)
    )
    report = json.loads(text)
    report["velocity_mps"] = np.asarray(report["velocity_mps"], dtype=float)
    report["positions_m"] = positions
    for mode, shape in zip(report["modes"], shapes):
        mode["shape"] = shape
    return report


def modes(source: PathLike | dict[str, Any], set: Overrides = None) -> dict[str, Any]:
    """The modes of a :func:`steady` result (or of scenario ``source``, solved now) as
    arrays: ``eigenvalues`` (complex, 1/s), ``growth_rate_per_s``, ``frequency_hz``,
    ``damping_ratio`` (NaN for a neutral mode), each of shape (k,); ``shapes`` (k, n, 3)
    complex; ``descriptions``, a list of k texts. Largest growth rate first.
    """
    report = source if isinstance(source, dict) else steady(source, set)
    ms = report["modes"]
    n = len(report["positions_m"])

    def column(key: str) -> np.ndarray:
        return np.array([np.nan if m[key] is None else m[key] for m in ms], dtype=float)

    return {
        "eigenvalues": np.array([complex(*m["eigenvalue"]) for m in ms], dtype=complex),
        "growth_rate_per_s": column("growth_rate_per_s"),
        "frequency_hz": column("frequency_hz"),
        "damping_ratio": column("damping_ratio"),
        "shapes": np.array([m["shape"] for m in ms], dtype=complex).reshape(len(ms), n, 3),
        "descriptions": [m["description"] for m in ms],
    }

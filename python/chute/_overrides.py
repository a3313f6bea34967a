"""Scenario overrides: Python values to the `KEY=VALUE` texts of `chute run --set`."""

from __future__ import annotations

import errno
import math
import os
from collections.abc import Mapping, Sequence
from typing import Any, Union

__all__ = ["Overrides", "PathLike", "existing", "overrides"]

#: A file or directory path, as ``open`` takes it.
PathLike = Union[str, "os.PathLike[str]"]
#: Scenario overrides: ``{"load.weight_n": 500}`` or ``["load.weight_n=500"]``, or None.
Overrides = Union[Mapping[str, Any], Sequence[str], None]


def existing(path: PathLike, what: str = "scenario file") -> str:
    """``os.fspath(path)``, or :class:`FileNotFoundError` (Python's own error for a missing
    file, with the path) when nothing is there."""
    text = os.fspath(path)
    if not os.path.exists(text):
        raise FileNotFoundError(errno.ENOENT, f"{what} not found", text)
    return text


def _toml(value, nested=False):
    """`value` as TOML text. Strings are taken as they are at the top level (as on the
    command line: `--set load.mode=force`) and quoted inside arrays and tables."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        if not nested:
            return value
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if hasattr(value, "__fspath__"):
        return _toml(str(value.__fspath__()), nested)
    if hasattr(value, "tolist") and not isinstance(value, (list, tuple)):
        return _toml(value.tolist(), nested)  # numpy scalars and arrays
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, Mapping):
        items = ", ".join(f"{k} = {_toml(v, True)}" for k, v in value.items())
        return "{" + items + "}"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_toml(v, True) for v in value) + "]"
    raise TypeError(
        f"cannot use a {type(value).__name__} as a scenario value: give a number, "
        "bool, string, list or dict"
    )


def overrides(set: Overrides) -> list[str]:
    """The `--set` texts of `set`: a mapping of dotted keys to values
    (``{"load.weight_n": 500}``), or an iterable of ``"KEY=VALUE"`` texts, or None."""
    if set is None:
        return []
    if isinstance(set, str):
        raise TypeError('set must be a dict of keys to values, e.g. {"load.weight_n": 500}')
    if isinstance(set, Mapping):
        return [f"{key}={_toml(value)}" for key, value in set.items()]
    return [str(s) for s in set]

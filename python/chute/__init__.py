"""chute: parachute flight simulator for flexible canopies, from Python.

The same simulations as the ``chute`` command line, with numpy arrays in and out
(docs/python.md):

- :func:`run` — run a scenario file (with ``set`` overrides) into an output directory and
  get a :class:`Result` (``summary``, ``timeseries``, ``frames``, ``out_dir``);
- :class:`Simulation` — step a scenario from Python (``step``, ``positions``, ...);
- :func:`study` — a study file's cases in parallel (rows, or a pandas DataFrame);
- :func:`dispersion` — a study's ``[dispersion]`` here or on a Dask cluster, and its footprint;
- :func:`validate` — the verification suite;
- :func:`steady`, :func:`modes` — the steady descent as an equilibrium and its modes.

Bad input raises :class:`ScenarioError` with the command line's message; a run that fails
or stops early raises :class:`RunError` with its partial result.
"""

from ._native import RunError, ScenarioError, __version__
from ._api import Frames, Result, run, study, validate
from ._dispersion import Dispersion, dispersion
from ._simulation import Simulation
from ._stability import modes, steady

__all__ = [
    "Dispersion",
    "Frames",
    "Result",
    "RunError",
    "ScenarioError",
    "Simulation",
    "__version__",
    "dispersion",
    "modes",
    "run",
    "steady",
    "study",
    "validate",
]

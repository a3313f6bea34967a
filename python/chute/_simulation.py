"""chute.Simulation: a run stepped from Python."""

from __future__ import annotations

from typing import Any

import numpy as np

from . import _native
from ._native import RunError
from ._overrides import Overrides, PathLike, existing, overrides

__all__ = ["Simulation"]


class Simulation:
    """A scenario's run, stepped by the caller, with the physics of :func:`chute.run`.

    ``Simulation(path, set={...})`` loads and checks the scenario exactly as ``run`` does
    (:class:`chute.ScenarioError` on bad input) and builds the model at rest at t = 0. It
    takes the same steps as ``run`` (fixed or adaptive, ending on the same frame, snapshot
    and sync times), so stepping to the end gives the run's final state bit for bit and
    :meth:`summary` its ``summary.json`` (but for the wall time). It writes no files.

    Arrays are copies: changing them does not change the simulation.
    """

    def __init__(self, path: PathLike, set: Overrides = None):
        self._sim = _native.Simulation(existing(path), overrides(set))

    def step(self, n: int = 1) -> int:
        """Take up to ``n`` steps (fewer at the end of the run) and return how many were
        taken. Each step is one accepted step of the run's policy (failed or rejected
        attempts are retried inside it). The GIL is released while stepping; Ctrl-C raises
        KeyboardInterrupt between two steps. Raises :class:`chute.RunError` when a step
        fails even at the smallest step allowed (the state stays the last good one)."""
        try:
            return self._sim.step(int(n))
        except RunError as e:
            e.result = None  # a Simulation writes no outputs
            raise

    def advance_to(self, t: float) -> int:
        """Step until the time reaches ``t`` (s) or the end; steps are not shortened to land
        on ``t``. Returns the number of steps taken."""
        try:
            return self._sim.advance_to(float(t))
        except RunError as e:
            e.result = None  # a Simulation writes no outputs
            raise

    def run(self) -> int:
        """Step to the end; returns the number of steps taken."""
        return self.advance_to(self.duration)

    @property
    def time(self) -> float:
        """Simulated time (s)."""
        return self._sim.time

    @property
    def duration(self) -> float:
        """The run's end time ``time.duration_s`` (s)."""
        return self._sim.duration

    @property
    def steps(self) -> int:
        """Accepted steps so far."""
        return self._sim.steps

    @property
    def finished(self) -> bool:
        """Whether the end time or the ground is reached, or a step failed (see ``stop_reason``)."""
        return self._sim.finished

    @property
    def stop_reason(self) -> str | None:
        """Why the simulation stopped before the end time: ``"ground"`` once it landed
        (``atmosphere.ground_altitude_m``, complete), a step failure's reason, or None."""
        return self._sim.stop_reason

    @property
    def positions(self) -> np.ndarray:
        """Node positions (m): (n, 3) float64, a copy."""
        return self._sim.positions

    @property
    def velocities(self) -> np.ndarray:
        """Node velocities (m/s): (n, 3) float64, a copy."""
        return self._sim.velocities

    @property
    def triangles(self) -> np.ndarray:
        """Canopy triangles as node indices: (m, 3) int64; empty (0, 3) for a rod canopy."""
        return self._sim.triangles

    @property
    def rod_edges(self) -> np.ndarray:
        """Rod edges (canopy strip, suspension lines) as node indices: (k, 2) int64."""
        return self._sim.rod_edges

    @property
    def canopy_nodes(self) -> list[int]:
        """Indices of the canopy's nodes (the metrics average over them)."""
        return self._sim.canopy_nodes

    @property
    def load_sites(self) -> list[int]:
        """Indices of the canopy nodes that carry the load."""
        return self._sim.load_sites

    @property
    def payload_node(self) -> int | None:
        """Index of the payload node (None unless the load hangs on lines)."""
        return self._sim.payload_node

    def summary(self) -> dict[str, Any]:
        """The summary so far, a dict with the keys of ``summary.json``: what the run would
        write had it ended now (``complete`` is False before the end time)."""
        return self._sim.summary()

    def __repr__(self) -> str:
        return (
            f"<chute.Simulation t = {self.time:.6g} / {self.duration:g} s, "
            f"{self.steps} steps, {len(self.positions)} nodes>"
        )

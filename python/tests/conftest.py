"""Shared fixtures: the repository's scenarios, short variants of them, and the `chute`
command line built from the same sources (for the CLI comparisons)."""

import json
import os
import pathlib
import subprocess

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]
SCENARIOS = REPO / "scenarios"

# The report's rod strip, coarse and short: 300 fixed steps (4 sync points), frames every
# 0.05 s, one snapshot inside the run and one after it. About a second of wall time.
ROD = SCENARIOS / "report-rod-200n.toml"
ROD_SET = {
    "canopy.nodes": 21,
    "time.duration_s": 0.3,
    "output.snapshots_s": [0.1, 0.5],
}
# The report's shell canopy as bundled (cst + midedge, dt 4 ms) on a coarse mesh.
SHELL = SCENARIOS / "report-shell-4-sites.toml"
SHELL_SET = {
    "canopy.edge_length_m": 1.0,
    "time.duration_s": 0.1,
    "output.frame_interval_s": 0.02,  # a multiple of the scenario's dt (4 ms)
    "output.snapshots_s": [],
}


def cli_args(set):
    """`--set` arguments for a dict of overrides (the same texts the package passes)."""
    from chute._overrides import overrides

    args = []
    for s in overrides(set):
        args += ["--set", s]
    return args


@pytest.fixture(scope="session")
def chute_bin():
    """The `chute` binary: $CHUTE_BIN (scripts/test-python sets it), else the release build
    under $CARGO_TARGET_DIR or the repository's target/."""
    env = os.environ.get("CHUTE_BIN")
    target = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", REPO / "target"))
    path = pathlib.Path(env) if env else target / "release" / "chute"
    if not path.is_file():
        pytest.fail(
            f"no chute binary at {path}: run `cargo build --release -p chute` or set "
            "CHUTE_BIN (scripts/test-python does both)"
        )
    return path


@pytest.fixture(scope="session")
def run_cli(chute_bin):
    """Run `chute ARGS...`; returns the CompletedProcess (text output)."""

    def go(*args, cwd=None):
        return subprocess.run(
            [str(chute_bin), *map(str, args)], capture_output=True, text=True, cwd=cwd
        )

    return go


SOLVER_TIMES = ("assembly_s", "factor_s", "solve_s")


def summary_without_wall_time(path_or_dict, snapshots=True):
    """summary.json as a dict without its wall times (`wall_time_s` and the four times of
    `solver`), the only values that may differ; the solver counts stay. ``snapshots=False``:
    as a Simulation's, which draws no snapshots and so never warns of one not drawn."""
    if isinstance(path_or_dict, dict):
        s = dict(path_or_dict)
    else:
        s = json.loads(pathlib.Path(path_or_dict).read_text())
    if not snapshots:
        s["warnings"] = [w for w in s["warnings"] if "not drawn" not in w]
    s.pop("wall_time_s")
    if s.get("solver") is not None:
        s["solver"] = {k: v for k, v in s["solver"].items() if k not in SOLVER_TIMES}
    return s

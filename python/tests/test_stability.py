"""chute.steady and chute.modes against the command line's own numbers."""

import json
import subprocess

import numpy as np
import pytest

import chute

from conftest import ROD


def test_steady_matches_the_command_line_and_gives_arrays(tmp_path, chute_bin):
    report = chute.steady(ROD, {"time.duration_s": 2}, out=tmp_path / "st")
    written = json.loads((tmp_path / "st" / "stability.json").read_text())
    assert report["terminal_velocity_mps"] == written["terminal_velocity_mps"]
    assert report["velocity_mps"].shape == (3,)
    assert report["terminal_velocity_mps"] == pytest.approx(
        report["transient_terminal_velocity_mps"], rel=2e-3
    )
    cli = subprocess.run(
        [str(chute_bin), "steady", str(ROD), "--set", "time.duration_s=2", "--json"],
        capture_output=True, text=True, check=True,
    )
    assert json.loads(cli.stdout)["terminal_velocity_mps"] == report["terminal_velocity_mps"]
    m = chute.modes(report)
    k = len(report["modes"])
    n = report["positions_m"].shape[0]
    assert m["eigenvalues"].shape == (k,) and m["shapes"].shape == (k, n, 3)
    assert np.all(np.diff(m["growth_rate_per_s"]) <= 0)
    # Every shape is scaled to a largest component of 1.
    assert np.allclose(np.abs(m["shapes"]).reshape(k, -1).max(axis=1), 1.0)
    assert len(m["descriptions"]) == k


def test_a_run_directory_is_refused_before_any_work(tmp_path):
    (tmp_path / "r").mkdir()
    (tmp_path / "r" / "summary.json").write_text("{}")
    with pytest.raises(chute.ScenarioError, match="not a `chute steady` directory"):
        chute.steady(ROD, out=tmp_path / "r")

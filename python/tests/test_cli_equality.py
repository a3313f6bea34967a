"""chute.run against the `chute run` command line on the same scenario: the same numbers to
the last digit (summary.json, every time-series row, every frame), fixed and adaptive steps,
rod and shell canopies."""

import filecmp

import numpy as np
import pytest

import chute
from conftest import ROD, ROD_SET, SHELL, SHELL_SET, cli_args, summary_without_wall_time

CASES = {
    "rod-fixed": (ROD, ROD_SET),
    "rod-adaptive": (ROD, {**ROD_SET, "time.adaptive": True}),
    "shell-fixed": (SHELL, SHELL_SET),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_run_equals_the_command_line(case, tmp_path, run_cli):
    path, set = CASES[case]
    cli_dir = tmp_path / "cli"
    p = run_cli("run", path, "--out", cli_dir, "--quiet", *cli_args(set))
    assert p.returncode == 0, p.stderr
    r = chute.run(path, set=set, out=tmp_path / "py")
    assert r.out_dir == tmp_path / "py"
    assert summary_without_wall_time(r.summary) == summary_without_wall_time(
        cli_dir / "summary.json"
    )
    # Byte for byte: the files print every digit.
    for name in ["timeseries.csv", "canopy.pvd", "scenario.resolved.toml"]:
        assert filecmp.cmp(r.out_dir / name, cli_dir / name, shallow=False), name
    frames = sorted(p.name for p in (cli_dir / "frames").iterdir())
    assert frames == sorted(p.name for p in (r.out_dir / "frames").iterdir())
    match, mismatch, errors = filecmp.cmpfiles(
        cli_dir / "frames", r.out_dir / "frames", frames, shallow=False
    )
    assert mismatch == [] and errors == [], (mismatch, errors)
    # The arrays hold exactly the file's values.
    cli_rows = np.loadtxt(cli_dir / "timeseries.csv", delimiter=",", skiprows=1)
    assert np.array_equal(r.timeseries["t_s"], cli_rows[:, 0])
    assert np.array_equal(r.timeseries["drag_z_n"], cli_rows[:, 10])


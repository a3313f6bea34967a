"""python/examples/table1.py runs (quick variant), prints Table I and draws its plot."""

import importlib.util
import pathlib
import subprocess
import sys

EXAMPLE = pathlib.Path(__file__).resolve().parents[1] / "examples" / "table1.py"


def test_table1_example_quick(tmp_path):
    out = tmp_path / "table1"
    p = subprocess.run(
        [sys.executable, str(EXAMPLE), "--quick", "--out", str(out), "--jobs", "2"],
        capture_output=True,
        text=True,
    )
    assert p.returncode == 0, p.stderr
    lines = [l for l in p.stdout.splitlines() if l.startswith("| ")]
    assert len(lines) == 4  # header + 3 cases
    assert [l.split("|")[1].strip() for l in lines[1:]] == ["20N", "200N", "2000N"]
    assert (out / "study.csv").exists()
    has_mpl = importlib.util.find_spec("matplotlib") is not None
    assert (out / "table1.png").exists() == has_mpl
    assert ("plot:" in p.stdout) == has_mpl

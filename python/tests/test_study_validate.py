"""chute.study (rows, a pandas DataFrame, a clear ImportError without pandas) and
chute.validate."""

import builtins
import sys

import pytest

import chute
from conftest import ROD, summary_without_wall_time

STUDY = f"""
name = "mini"
base = "{ROD.as_posix()}"

[[case]]
name = "20N"
set = ["load.weight_n=20"]

[[case]]
name = "2000N"
set = ["load.weight_n=2000"]
"""
SHORT = {"canopy.nodes": 11, "time.duration_s": 0.05, "output.snapshots_s": []}


@pytest.fixture
def study_file(tmp_path):
    p = tmp_path / "mini.toml"
    p.write_text(STUDY)
    return p


def test_study_rows_equal_single_runs(study_file, tmp_path, capsys):
    out = tmp_path / "out"
    rows = chute.study(study_file, jobs=2, out=out, set=SHORT, progress=True)
    bar = capsys.readouterr().err
    assert bar.startswith("\r[") and bar.endswith("\n")
    assert "100%  2 / 2 cases" in bar.rsplit("\r", 1)[-1]
    assert [r["case"] for r in rows] == ["20N", "2000N"]
    assert [r["load.weight_n"] for r in rows] == [20, 2000]
    assert all(r["status"] == "complete" and r["complete"] for r in rows)
    assert (out / "study.csv").exists() and (out / "study.md").exists()
    # A case is the base scenario with the study-wide, then the case's overrides and its name.
    single = chute.run(ROD, set={**SHORT, "load.weight_n": 2000, "name": "mini-2000N"})
    row = {k: v for k, v in rows[1].items() if k not in ("case", "load.weight_n", "status", "message", "out_dir")}
    assert summary_without_wall_time(row) == summary_without_wall_time(single.summary)
    assert rows[0]["terminal_velocity_mps"] > rows[1]["terminal_velocity_mps"]  # heavier falls faster
    # Complete cases are skipped on a second call into the same directory.
    again = chute.study(study_file, out=out, set=SHORT, progress=True)
    assert [r["status"] for r in again] == ["skipped", "skipped"]
    assert "100%  0 / 0 cases" in capsys.readouterr().err


def test_study_as_frame(study_file):
    pandas = pytest.importorskip("pandas")
    df = chute.study(study_file, set=SHORT, as_frame=True)
    assert isinstance(df, pandas.DataFrame)
    assert list(df["case"]) == ["20N", "2000N"] and list(df["load.weight_n"]) == [20, 2000]
    assert df["out_dir"].isna().all()  # the temporary directory is gone


def test_study_as_frame_without_pandas(study_file, monkeypatch):
    real_import = builtins.__import__

    def no_pandas(name, *args, **kwargs):
        if name == "pandas" or name.startswith("pandas."):
            raise ImportError("No module named 'pandas'")
        return real_import(name, *args, **kwargs)

    monkeypatch.delitem(sys.modules, "pandas", raising=False)
    monkeypatch.setattr(builtins, "__import__", no_pandas)
    with pytest.raises(ImportError, match="pip install pandas"):
        chute.study(study_file, set=SHORT, as_frame=True)


def test_study_errors_name_the_case_and_run_nothing(study_file, tmp_path):
    out = tmp_path / "out"
    with pytest.raises(chute.ScenarioError, match="case `20N`.*time.dt_s"):
        chute.study(study_file, out=out, set={**SHORT, "time.dt_s": -1})
    assert not (out / "20N").exists()
    with pytest.raises(FileNotFoundError):
        chute.study(tmp_path / "none.toml")


def test_validate_returns_the_checks():
    checks = chute.validate(quick=True, case="be-spring-damping")
    assert [c["name"] for c in checks] == ["be-spring-damping"]
    c = checks[0]
    assert c["pass"] is True and c["rel_error"] <= c["tolerance"]
    assert set(c) >= {"quantity", "reference", "simulated", "source", "wall_s"}

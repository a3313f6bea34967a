"""Errors: bad input raises chute.ScenarioError with the command line's message (naming the
key); a run that cannot finish raises chute.RunError carrying its partial result."""

import re

import pytest

import chute
from conftest import ROD, ROD_SET, cli_args

BAD_OVERRIDES = [
    ({"load.weigth_n": 20}, "load.weigth_n"),  # unknown key, "did you mean"
    ({"load.weight_n": -5}, "load.weight_n"),  # out of range
    ({"time.dt_s": "fast"}, "time.dt_s"),  # wrong type
    (["load.weight_n"], "load.weight_n"),  # not KEY=VALUE
    ({"load.mode": "rope"}, "load.mode"),  # not one of the choices
]


def python_words(cli_message):
    """The command line's message as the Python call words it: `--set K=V` is `set["K"] = V`."""
    cli_message = re.sub(r"`--set ([^`=]*)=([^`]*)`", r'`set["\1"] = \2`', cli_message)
    return re.sub(r"`--set ([^`]*)`", r"`set` entry `\1`", cli_message)


@pytest.mark.parametrize("set,key", BAD_OVERRIDES, ids=[k for _, k in BAD_OVERRIDES])
def test_bad_override_has_the_cli_message_in_pythons_words(set, key, run_cli, tmp_path):
    with pytest.raises(chute.ScenarioError) as e:
        chute.run(ROD, set=set)
    msg = str(e.value)
    assert key in msg and "--set" not in msg, msg
    args = cli_args(set) if isinstance(set, dict) else ["--set", set[0]]
    p = run_cli("check", ROD, *args)
    assert p.returncode == 2
    assert "--set" in p.stderr
    assert python_words(p.stderr.strip()) == f"error: {msg}"
    assert isinstance(e.value, ValueError)


def test_bad_file_has_the_cli_message(run_cli, tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text((ROD.read_text()).replace("nodes = 61", "nodes = 61\nnodez = 3"))
    with pytest.raises(chute.ScenarioError) as e:
        chute.run(bad)
    assert "canopy.nodez" in str(e.value) and "bad.toml:" in str(e.value)
    assert run_cli("check", bad).stderr.strip() == f"error: {e.value}"
    # A missing file is Python's FileNotFoundError, with its path.
    missing = tmp_path / "missing.toml"
    for call in (chute.run, chute.Simulation, chute.study):
        with pytest.raises(FileNotFoundError) as e:
            call(missing)
        assert e.value.filename == str(missing)
    syntax = tmp_path / "syntax.toml"
    syntax.write_text("[canopy\n")
    with pytest.raises(chute.ScenarioError) as e:
        chute.Simulation(syntax)
    assert run_cli("check", syntax).stderr.strip() == f"error: {e.value}"


def test_a_non_empty_output_directory_needs_force(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / "keep.txt").write_text("mine")
    set = {**ROD_SET, "time.duration_s": 0.01}
    with pytest.raises(chute.ScenarioError, match="force=True") as e:
        chute.run(ROD, set=set, out=out)
    assert "--" not in str(e.value), e.value  # the call's words, not the command line's
    # --force replaces only an earlier chute run, never a directory chute did not write.
    with pytest.raises(chute.ScenarioError, match="not a chute run directory"):
        chute.run(ROD, set=set, out=out, force=True)
    run_dir = tmp_path / "run"
    chute.run(ROD, set=set, out=run_dir)
    (run_dir / "keep.txt").write_text("mine")
    with pytest.raises(chute.ScenarioError, match="force=True"):
        chute.run(ROD, set=set, out=run_dir)
    r = chute.run(ROD, set=set, out=run_dir, force=True)
    assert r.complete and (run_dir / "keep.txt").read_text() == "mine"


def test_a_failed_run_raises_run_error_with_the_partial_result():
    # One Newton iteration cannot meet the strict tolerance from rest with a 50 ms step, nor
    # with any of its halvings down to dt/1024: the run stops at t = 0. (The default
    # accuracy-based tolerance would take these steps, so the failure path is reached with it
    # off.)
    set = {
        **ROD_SET,
        "time.dt_s": 0.05,
        "time.newton_max_iterations": 1,
        "time.newton_strict": True,
    }
    with pytest.raises(chute.RunError) as e:
        chute.run(ROD, set=set)
    r = e.value.result
    assert isinstance(r, chute.Result)
    assert r.summary["complete"] is False
    assert r.summary["stop_reason"].startswith("step failed at t = 0.000000 s")
    assert r.summary["stop_reason"] in str(e.value)
    assert len(r.timeseries["t_s"]) == r.summary["steps"] + 1
    assert (r.out_dir / "checkpoint.bin").exists()
    # The Simulation stops the same way.
    sim = chute.Simulation(ROD, set=set)
    with pytest.raises(chute.RunError) as e2:
        sim.run()
    assert sim.finished and sim.stop_reason == r.summary["stop_reason"]
    assert str(e2.value) == r.summary["stop_reason"] and e2.value.result is None


def test_the_package_is_typed():
    """The installed package says it is typed (PEP 561: ``py.typed``, a stub for the compiled
    part), and the public functions carry their types."""
    import importlib.resources
    import inspect

    files = importlib.resources.files("chute")
    assert files.joinpath("py.typed").is_file()
    assert files.joinpath("_native.pyi").is_file()
    for f in (chute.run, chute.study, chute.validate, chute.Simulation.__init__):
        sig = inspect.signature(f)
        assert sig.return_annotation is not inspect.Signature.empty or f is chute.Simulation.__init__
        assert all(
            p.annotation is not inspect.Parameter.empty
            for name, p in sig.parameters.items()
            if name != "self"
        ), f

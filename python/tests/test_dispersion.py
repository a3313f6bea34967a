"""chute.dispersion: here, on a real Dask cluster (a LocalCluster of worker processes) and as
the command line runs it, the same files byte for byte; the footprint as footprint.json has it."""

import json

import pytest
from dask.distributed import Client, LocalCluster

import chute
from conftest import REPO, SCENARIOS

# The bundled quick dispersion (4 samples of the rod strip dropped 8 m, a second each), as
# scripts/test-slurm runs it as a job array: the three ways give the same files.
QUICK = REPO / "studies" / "dispersion-quick.toml"
# The same samples without their time limit (the base scenario's 20 s) and ground height.
STUDY = f"""
name = "d"
base = "{(SCENARIOS / "report-rod-20n.toml").as_posix()}"

[dispersion]
samples = 4
seed = 3
set = ["atmosphere.altitude_m=8"]

[[dispersion.vary]]
key = "fluid.wind_mps[0]"
uniform = {{ lo = 1.0, hi = 3.0 }}

[[dispersion.vary]]
key = "load.weight_n"
normal = {{ mean = 20.0, std_dev = 2.0, lo = 15.0, hi = 25.0 }}
"""
FILES = ("dispersion.csv", "footprint.json")


@pytest.fixture
def study_file(tmp_path):
    p = tmp_path / "d.toml"
    p.write_text(STUDY)
    return p


def test_dask_local_and_command_line_give_the_same_files(tmp_path, run_cli):
    cli = run_cli("study", QUICK, "--out", tmp_path / "cli", "--jobs", "2")
    assert cli.returncode == 0, cli.stderr
    local = chute.dispersion(QUICK, out=tmp_path / "local", jobs=2)
    with LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster, Client(cluster) as client:
        on_dask = chute.dispersion(QUICK, out=tmp_path / "dask", client=client)
        # Each sample ran in a worker process, not here.
        assert len(client.scheduler_info()["workers"]) == 2
    for name in FILES:
        want = (tmp_path / "cli" / name).read_bytes()
        assert (tmp_path / "local" / name).read_bytes() == want, name
        assert (tmp_path / "dask" / name).read_bytes() == want, name
    # The result holds the files' numbers.
    fp = json.loads((tmp_path / "dask" / "footprint.json").read_text())
    assert on_dask.footprint == fp["footprint"] and on_dask.sensitivity == fp["sensitivity"]
    assert [s["sample"] for s in on_dask.samples] == [f"sample-0000{i}" for i in range(4)]
    xs = [s["landing_x_m"] for s in on_dask.samples]
    assert on_dask.footprint["mean_m"][0] == pytest.approx(sum(xs) / 4, rel=1e-12)
    assert all(15.0 <= s["load.weight_n"] <= 25.0 for s in local.samples)
    assert on_dask.unfinished == [] and on_dask.not_landed == []


def test_samples_that_do_not_land_leave_no_footprint(study_file):
    d = chute.dispersion(study_file, set={"time.duration_s": 0.05})  # no ground either
    assert d.out_dir is None and d.footprint is None and d.sensitivity is None
    assert d.not_landed == [f"sample-0000{i}" for i in range(4)]
    assert all(s["landing_x_m"] is None for s in d.samples)


def test_a_bad_dispersion_is_refused_before_anything_runs(study_file, tmp_path):
    out = tmp_path / "out"
    with pytest.raises(chute.ScenarioError, match="time.dt_s"):
        chute.dispersion(study_file, out=out, set={"time.dt_s": -1})
    assert not out.exists()
    bad = tmp_path / "bad.toml"
    bad.write_text(STUDY.replace("load.weight_n\"", "load.weight_nn\""))
    with pytest.raises(chute.ScenarioError, match="load.weight_nn"):
        chute.dispersion(bad, out=out)

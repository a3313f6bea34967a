"""chute.Simulation: stepping to the end equals chute.run bit for bit; shapes, dtypes and
copies of its arrays; the step count and the end."""

import numpy as np
import pytest

import chute
from conftest import ROD, ROD_SET, SHELL, SHELL_SET, summary_without_wall_time


@pytest.mark.parametrize(
    "path,set",
    [
        (ROD, ROD_SET),
        (ROD, {**ROD_SET, "time.adaptive": True}),
        (SHELL, SHELL_SET),
    ],
    ids=["rod-fixed", "rod-adaptive", "shell-fixed"],
)
def test_stepping_to_the_end_equals_run(path, set):
    r = chute.run(path, set=set)
    sim = chute.Simulation(path, set=set)
    taken = 0
    while sim.step(7):  # uneven batches: a batch boundary changes nothing
        taken += 1
    assert sim.finished and sim.step() == 0
    assert sim.steps == r.summary["steps"]
    assert sim.time == r.summary["simulated_time_s"]
    # The last frame is at the end time; frames print positions losslessly.
    f = r.frames
    assert f.times[-1] == sim.time
    assert np.array_equal(sim.positions, f.positions[-1])
    assert np.array_equal(sim.velocities, f.velocities[-1])
    assert summary_without_wall_time(sim.summary()) == summary_without_wall_time(
        r.summary, snapshots=False
    )


def test_arrays_are_float64_and_int64_copies_of_the_right_shape():
    sim = chute.Simulation(SHELL, set=SHELL_SET)
    n = sim.positions.shape[0]
    for a in (sim.positions, sim.velocities):
        assert a.shape == (n, 3) and a.dtype == np.float64
    tri = sim.triangles
    assert tri.ndim == 2 and tri.shape[1] == 3 and tri.shape[0] > 0
    assert tri.dtype == np.int64 and tri.min() >= 0 and tri.max() < n
    assert sim.rod_edges.shape == (0, 2) and sim.rod_edges.dtype == np.int64
    # Flat at rest at t = 0; changing a copy changes nothing.
    assert sim.time == 0.0 and np.all(sim.positions[:, 2] == 0.0)
    assert np.all(sim.velocities == 0.0)
    p = sim.positions
    p[:] = 99.0
    assert np.all(sim.positions[:, 2] == 0.0)
    sim.step()
    assert sim.time > 0 and np.all(sim.velocities[:, 2] < 0.0)  # falling

    rod = chute.Simulation(ROD, set=ROD_SET)
    edges = rod.rod_edges
    assert edges.shape == (ROD_SET["canopy.nodes"] - 1, 2) and edges.dtype == np.int64
    assert rod.triangles.shape == (0, 3)
    assert len(rod.load_sites) == 2 and rod.payload_node is None


def test_step_counts_advance_to_and_a_partial_summary():
    sim = chute.Simulation(ROD, set=ROD_SET)
    assert sim.step(10) == 10 and sim.steps == 10
    assert sim.time == pytest.approx(0.01, abs=1e-15)
    assert sim.advance_to(0.1) == 90
    s = sim.summary()
    assert s["complete"] is False and s["steps"] == 100
    assert any("run incomplete" in w for w in s["warnings"])
    assert not sim.finished
    rest = sim.run()
    assert rest == 200 and sim.finished and sim.summary()["complete"] is True
    assert "t = 0.3" in repr(sim)


def test_bad_input_raises_like_run():
    with pytest.raises(chute.ScenarioError, match="load.weight_n"):
        chute.Simulation(ROD, set={"load.weight_n": -1})


def test_a_simulation_lands_like_run():
    # 0.5 m of ground clearance below a rod canopy at 1,000 m: it lands in under 2 s.
    ground = {
        **ROD_SET,
        "time.duration_s": 2.0,
        "atmosphere.model": "isa1976",
        "atmosphere.altitude_m": 1000.0,
        "atmosphere.ground_altitude_m": 999.5,
    }
    r = chute.run(ROD, set=ground)
    sim = chute.Simulation(ROD, set=ground)
    while sim.step(50):
        pass
    assert sim.finished and sim.step() == 0
    assert sim.stop_reason == "ground" == r.summary["stop_reason"]
    assert sim.time == r.summary["simulated_time_s"] < 2.0
    assert summary_without_wall_time(sim.summary()) == summary_without_wall_time(
        r.summary, snapshots=False
    )
    assert sim.summary()["complete"] and "landing_velocity_mps" in sim.summary()
